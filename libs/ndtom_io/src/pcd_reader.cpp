#include "ndtom_io/pcd_reader.h"

#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "lzf.h"
#include "ndtom/atomic_file.h"

namespace ndtom::io {
namespace {

struct Field {
  std::string name;
  int size = 4;       // bytes per element
  char type = 'F';    // F (float), I (signed), U (unsigned)
  int count = 1;      // elements
  size_t offset = 0;  // bytes from the start of a point (binary layout)
};

struct Header {
  std::vector<Field> fields;
  size_t width = 0, height = 1, points = 0;
  bool points_given = false;
  std::string data;
  Eigen::Isometry3d viewpoint = Eigen::Isometry3d::Identity();
  size_t point_bytes = 0;
};

[[noreturn]] void fail(const std::string& name, const std::string& why) {
  throw PcdError("PCD " + name + ": " + why);
}

size_t parseCount(const std::string& token, const std::string& name, const char* what) {
  try {
    size_t used = 0;
    const long long v = std::stoll(token, &used);
    if (used != token.size() || v < 0) throw std::invalid_argument(token);
    return size_t(v);
  } catch (const std::exception&) {
    fail(name, std::string("bad ") + what + " '" + token + "'");
  }
}

Header parseHeader(std::istream& in, const std::string& name) {
  Header h;
  std::vector<std::string> names, types;
  std::vector<size_t> sizes, counts;
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
      for (const auto& v : values) sizes.push_back(parseCount(v, name, "SIZE"));
    } else if (key == "TYPE") {
      types = values;
    } else if (key == "COUNT") {
      for (const auto& v : values) counts.push_back(parseCount(v, name, "COUNT"));
    } else if (key == "WIDTH" && values.size() == 1) {
      h.width = parseCount(values[0], name, "WIDTH");
    } else if (key == "HEIGHT" && values.size() == 1) {
      h.height = parseCount(values[0], name, "HEIGHT");
    } else if (key == "POINTS" && values.size() == 1) {
      h.points = parseCount(values[0], name, "POINTS");
      h.points_given = true;
    } else if (key == "VIEWPOINT" && values.size() == 7) {
      double v[7];
      for (int i = 0; i < 7; ++i) {
        try {
          v[i] = std::stod(values[i]);
        } catch (const std::exception&) {
          fail(name, "bad VIEWPOINT");
        }
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
  if (sizes.size() != names.size() || types.size() != names.size())
    fail(name, "FIELDS, SIZE and TYPE have different lengths");
  if (counts.empty()) counts.assign(names.size(), 1);
  if (counts.size() != names.size()) fail(name, "COUNT and FIELDS have different lengths");
  if (!h.points_given) h.points = h.width * h.height;
  if (h.width * h.height != h.points) fail(name, "WIDTH x HEIGHT differs from POINTS");
  size_t offset = 0;
  for (size_t i = 0; i < names.size(); ++i) {
    Field f{names[i], int(sizes[i]), types[i].empty() ? '?' : types[i][0], int(counts[i]), offset};
    const bool ok =
        types[i].size() == 1 && ((f.type == 'F' && (f.size == 4 || f.size == 8)) ||
                                 ((f.type == 'I' || f.type == 'U') &&
                                  (f.size == 1 || f.size == 2 || f.size == 4 || f.size == 8)));
    if (!ok) fail(name, "unsupported type " + types[i] + " of size " + std::to_string(f.size));
    if (f.count < 1 || f.count > 1 << 20) fail(name, "bad COUNT of field " + f.name);
    offset += size_t(f.size) * size_t(f.count);
    h.fields.push_back(f);
  }
  h.point_bytes = offset;
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

PointCloud parsePcd(const std::string& bytes, const std::string& name) {
  std::istringstream in(bytes);
  const Header h = parseHeader(in, name);
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
    if (h.point_bytes != 0 && available / h.point_bytes < h.points)
      fail(name, "truncated: data holds " + std::to_string(available / h.point_bytes) + " of " +
                     std::to_string(h.points) + " points");
    cloud.points.resize(h.points);
    for (size_t i = 0; i < h.points; ++i) {
      const char* point = data + i * h.point_bytes;
      for (int a = 0; a < 3; ++a) cloud.points[i][a] = decodeValue(point + xyz[a]->offset, *xyz[a]);
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
    if (uint64_t(uncompressed) != uint64_t(h.point_bytes) * h.points)
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

PointCloud readPcd(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) fail(path, "cannot open the file");
  std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (file.bad()) fail(path, "cannot read the file");
  return parsePcd(bytes, path);
}

void writePcdBinary(const std::string& path, const std::vector<Eigen::Vector3d>& points) {
  std::ostringstream out;
  out << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
      << "TYPE F F F\nCOUNT 1 1 1\nWIDTH " << points.size() << "\nHEIGHT 1\n"
      << "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << points.size() << "\nDATA binary\n";
  for (const auto& p : points) {
    const float v[3] = {float(p.x()), float(p.y()), float(p.z())};
    out.write(reinterpret_cast<const char*>(v), sizeof(v));
  }
  const std::string bytes = out.str();
  writeFileAtomically(path, bytes.data(), bytes.size());
}

}  // namespace ndtom::io
