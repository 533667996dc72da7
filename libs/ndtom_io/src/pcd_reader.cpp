#include "ndtom_io/pcd_reader.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "lzf.h"
#include "ndtom_internal/atomic_file.h"
#include "ndtom_internal/checked_size.h"
#include "ndtom_internal/input_file.h"

namespace ndtom::io {
namespace {

// What a header may claim. PCL's widest fields are histograms of a few hundred elements.
constexpr uint64_t kMaxFields = 1024;
constexpr uint64_t kMaxFieldCount = uint64_t(1) << 20;  // elements of one field
constexpr uint64_t kMaxPointBytes = uint64_t(1) << 24;
constexpr uint64_t kMaxPcdFileBytes = uint64_t(1) << 30;

struct Field {
  std::string name;
  int size = 4;       // bytes per element: 1, 2, 4 or 8
  char type = 'F';    // F (float), I (signed), U (unsigned)
  int count = 1;      // elements, at most kMaxFieldCount
  size_t offset = 0;  // bytes from the start of a point (binary layout)
};

struct Header {
  std::vector<Field> fields;
  uint64_t width = 0, height = 1, points = 0;
  bool points_given = false;
  std::string data;
  Eigen::Isometry3d viewpoint = Eigen::Isometry3d::Identity();
  size_t point_bytes = 0;
};

[[noreturn]] void fail(const std::string& name, const std::string& why) {
  throw PcdError("PCD " + name + ": " + why);
}

uint64_t parseNumber(const std::string& token, uint64_t max, const std::string& name,
                     const char* what) {
  const auto v = parseCount(token, max);
  if (!v && max != UINT64_MAX)
    fail(name,
         std::string("bad ") + what + " '" + token + "' (at most " + std::to_string(max) + ")");
  if (!v) fail(name, std::string("bad ") + what + " '" + token + "'");
  return *v;
}

Header parseHeader(std::istream& in, const std::string& name, uint64_t max_points) {
  Header h;
  std::vector<std::string> names, types;
  std::vector<uint64_t> sizes, counts;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string key, token;
    s >> key;
    std::vector<std::string> values;
    while (s >> token) values.push_back(token);
    if (key == "VERSION") {
    } else if (key == "FIELDS") {
      names = values;
    } else if (key == "SIZE") {
      for (const auto& v : values) sizes.push_back(parseNumber(v, 8, name, "SIZE"));
    } else if (key == "TYPE") {
      types = values;
    } else if (key == "COUNT") {
      for (const auto& v : values) counts.push_back(parseNumber(v, kMaxFieldCount, name, "COUNT"));
    } else if (key == "WIDTH" && values.size() == 1) {
      h.width = parseNumber(values[0], UINT64_MAX, name, "WIDTH");
    } else if (key == "HEIGHT" && values.size() == 1) {
      h.height = parseNumber(values[0], UINT64_MAX, name, "HEIGHT");
    } else if (key == "POINTS" && values.size() == 1) {
      h.points = parseNumber(values[0], UINT64_MAX, name, "POINTS");
      h.points_given = true;
    } else if (key == "VIEWPOINT" && values.size() == 7) {
      double v[7];
      for (int i = 0; i < 7; ++i) {
        char* end = nullptr;
        v[i] = std::strtod(values[i].c_str(), &end);
        if (end == values[i].c_str() || *end != '\0' || !std::isfinite(v[i]))
          fail(name, "bad VIEWPOINT '" + values[i] + "'");
      }
      h.viewpoint.setIdentity();
      h.viewpoint.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
      const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
      if (!(q.norm() > 0.5 && q.norm() < 2)) fail(name, "bad VIEWPOINT quaternion");
      h.viewpoint.linear() = q.normalized().toRotationMatrix();
    } else if (key == "DATA" && values.size() == 1) {
      h.data = values[0];
      break;
    } else {
      fail(name, "unexpected header line '" + line + "'");
    }
  }
  if (h.data.empty()) fail(name, "no DATA line: not a PCD file or truncated header");
  if (names.empty()) fail(name, "no FIELDS");
  if (names.size() > kMaxFields)
    fail(name, std::to_string(names.size()) + " FIELDS, more than " + std::to_string(kMaxFields));
  if (sizes.size() != names.size() || types.size() != names.size())
    fail(name, "FIELDS, SIZE and TYPE have different lengths");
  if (counts.empty()) counts.assign(names.size(), 1);
  if (counts.size() != names.size()) fail(name, "COUNT and FIELDS have different lengths");
  const auto width_x_height = checkedMul(h.width, h.height);
  if (!h.points_given && width_x_height) h.points = *width_x_height;
  if (!width_x_height || *width_x_height != h.points)
    fail(name, "WIDTH x HEIGHT differs from POINTS");
  if (h.points > max_points)
    fail(name, std::to_string(h.points) + " points, more than the " + std::to_string(max_points) +
                   " a scan may have here");
  uint64_t offset = 0;
  for (size_t i = 0; i < names.size(); ++i) {
    // sizes[i] <= 8 and counts[i] <= kMaxFieldCount: both fit an int.
    Field f{names[i], int(sizes[i]), types[i].empty() ? '?' : types[i][0], int(counts[i]),
            size_t(offset)};
    const bool ok =
        types[i].size() == 1 && ((f.type == 'F' && (f.size == 4 || f.size == 8)) ||
                                 ((f.type == 'I' || f.type == 'U') &&
                                  (f.size == 1 || f.size == 2 || f.size == 4 || f.size == 8)));
    if (!ok) fail(name, "unsupported type " + types[i] + " of size " + std::to_string(f.size));
    if (f.count < 1) fail(name, "bad COUNT of field " + f.name);
    offset += uint64_t(f.size) * uint64_t(f.count);  // at most 1024 * 8 * 2^20: no overflow
    if (offset > kMaxPointBytes)
      fail(name, "a point of more than " + std::to_string(kMaxPointBytes) + " bytes");
    h.fields.push_back(f);
  }
  h.point_bytes = size_t(offset);
  return h;
}

double decodeValue(const char* p, const Field& f) {
  switch (f.type) {
    case 'F':
      if (f.size == 4) {
        float v;
        std::memcpy(&v, p, 4);
        return v;
      } else {
        double v;
        std::memcpy(&v, p, 8);
        return v;
      }
    case 'I': {
      int64_t v = 0;
      std::memcpy(&v, p, size_t(f.size));  // little-endian hosts only, as PCL itself
      const int shift = 64 - 8 * f.size;
      return double((v << shift) >> shift);  // sign-extend
    }
    default: {
      uint64_t v = 0;
      std::memcpy(&v, p, size_t(f.size));
      return double(v);
    }
  }
}

const Field& requireField(const Header& h, const char* wanted, const std::string& name) {
  for (const Field& f : h.fields)
    if (f.name == wanted) return f;
  fail(name, std::string("missing field '") + wanted + "' (fields: x y z are required)");
}

}  // namespace

PointCloud parsePcd(const std::string& bytes, const std::string& name, uint64_t max_points) {
  std::istringstream in(bytes);
  const Header h = parseHeader(in, name, max_points);
  const Field* xyz[3] = {&requireField(h, "x", name), &requireField(h, "y", name),
                         &requireField(h, "z", name)};
  PointCloud cloud;
  cloud.viewpoint = h.viewpoint;
  // tellg() is -1 when the header ran to the end of the bytes (no data at all).
  const std::streamoff header_end = in.tellg();
  const size_t data_start = header_end < 0 ? bytes.size() : size_t(header_end);
  const size_t available = bytes.size() - data_start;
  const char* data = bytes.data() + data_start;

  if (h.data == "ascii") {
    // One point per line, values in field order, COUNT values per field.
    size_t values_per_point = 0;
    for (const Field& f : h.fields) values_per_point += size_t(f.count);
    std::vector<size_t> column(3);
    for (int a = 0; a < 3; ++a) {
      size_t col = 0;
      for (const Field& f : h.fields) {
        if (&f == xyz[a]) break;
        col += size_t(f.count);
      }
      column[a] = col;
    }
    std::string line;
    std::vector<std::string> tokens;
    while (cloud.points.size() < h.points && std::getline(in, line)) {
      std::istringstream s(line);
      tokens.clear();
      for (std::string t; s >> t;) tokens.push_back(t);
      if (tokens.empty()) continue;
      if (tokens.size() != values_per_point)
        fail(name, "point " + std::to_string(cloud.points.size()) + " has " +
                       std::to_string(tokens.size()) + " values, expected " +
                       std::to_string(values_per_point));
      Eigen::Vector3d p;
      for (int a = 0; a < 3; ++a) {
        const std::string& t = tokens[column[a]];
        char* end = nullptr;
        p[a] = std::strtod(t.c_str(), &end);
        if (end == t.c_str() || *end != '\0') fail(name, "bad number '" + t + "'");
      }
      cloud.points.push_back(p);
    }
    if (cloud.points.size() != h.points)
      fail(name, "truncated: " + std::to_string(cloud.points.size()) + " of " +
                     std::to_string(h.points) + " points");
  } else if (h.data == "binary") {
    if (!fitsIn(h.points, h.point_bytes, available))
      fail(name, "truncated: data holds " + std::to_string(available / h.point_bytes) + " of " +
                     std::to_string(h.points) + " points");
    cloud.points.resize(h.points);
    const auto isFloat = [](const Field* f) { return f->type == 'F' && f->size == 4; };
    if (isFloat(xyz[0]) && isFloat(xyz[1]) && isFloat(xyz[2])) {
      // The usual layout, read without decodeValue's switch per value (same values).
      const size_t ox = xyz[0]->offset, oy = xyz[1]->offset, oz = xyz[2]->offset;
      for (size_t i = 0; i < h.points; ++i) {
        const char* point = data + i * h.point_bytes;
        float x, y, z;
        std::memcpy(&x, point + ox, 4);
        std::memcpy(&y, point + oy, 4);
        std::memcpy(&z, point + oz, 4);
        cloud.points[i] = Eigen::Vector3d(x, y, z);
      }
    } else {
      for (size_t i = 0; i < h.points; ++i) {
        const char* point = data + i * h.point_bytes;
        for (int a = 0; a < 3; ++a)
          cloud.points[i][a] = decodeValue(point + xyz[a]->offset, *xyz[a]);
      }
    }
  } else if (h.data == "binary_compressed") {
    // u32 compressed size, u32 uncompressed size, LZF data; fields stored one after another.
    if (available < 8) fail(name, "truncated compressed header");
    uint32_t compressed = 0, uncompressed = 0;
    std::memcpy(&compressed, data, 4);
    std::memcpy(&uncompressed, data + 4, 4);
    if (compressed > available - 8) fail(name, "truncated compressed data");
    // A back-reference of 3 bytes expands to at most 264: bound the allocation by that.
    if (uint64_t(uncompressed) > uint64_t(compressed) * 88 + 64)
      fail(name, "implausible uncompressed size");
    const auto expected = checkedMul(h.point_bytes, h.points);
    if (!expected || *expected != uint64_t(uncompressed))
      fail(name, "compressed data size does not match the fields and POINTS");
    std::string raw(uncompressed, '\0');
    if (!lzfDecompress(data + 8, compressed, raw.data(), raw.size()))
      fail(name, "corrupt compressed data");
    cloud.points.resize(h.points);
    for (int a = 0; a < 3; ++a) {
      const Field& f = *xyz[a];
      const size_t base = f.offset * h.points;  // fields are laid out as whole columns
      const size_t stride = size_t(f.size) * size_t(f.count);
      for (size_t i = 0; i < h.points; ++i)
        cloud.points[i][a] = decodeValue(raw.data() + base + i * stride, f);
    }
  } else {
    fail(name, "unknown DATA type '" + h.data + "'");
  }
  return cloud;
}

PointCloud readPcd(const std::string& path, uint64_t max_points) {
  std::string bytes;
  try {
    bytes = readInputFile(path, kMaxPcdFileBytes, "PCD");
  } catch (const InputFileError& e) {
    throw PcdError(e.what());
  }
  return parsePcd(bytes, path, max_points);
}

void writePcdBinary(const std::string& path, const std::vector<Eigen::Vector3d>& points) {
  std::ostringstream header;
  header << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
         << "TYPE F F F\nCOUNT 1 1 1\nWIDTH " << points.size() << "\nHEIGHT 1\n"
         << "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << points.size() << "\nDATA binary\n";
  // The points in pieces of 4096 (48 kB): no copy of the whole file in memory.
  writeFileAtomically(path, [&](const FileSink& write) {
    const std::string text = header.str();
    write(text.data(), text.size());
    std::vector<float> piece;
    for (size_t first = 0; first < points.size(); first += 4096) {
      const size_t n = std::min<size_t>(4096, points.size() - first);
      piece.resize(3 * n);
      for (size_t k = 0; k < n; ++k)
        for (int a = 0; a < 3; ++a) piece[3 * k + size_t(a)] = float(points[first + k][a]);
      write(piece.data(), piece.size() * sizeof(float));
    }
  });
}

}  // namespace ndtom::io
