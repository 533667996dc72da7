// Class 1 of issue #17: sizes in PCD headers that overflow, wrap or lie about the data.
#include <array>
#include <filesystem>

#include "cases.h"
#include "hostile_files.h"
#include "support/pcd_bytes.h"

namespace redteam {
namespace {

const std::vector<Eigen::Vector3d> kTwoPoints = {{1, 2, 3}, {4, 5, 6}};

// The data of kTwoPoints in one encoding, after `header`.
std::string withData(const std::string& header, const std::string& data) {
  const std::string raw = pcdBinaryPoints(kTwoPoints);
  if (data == "ascii") return header + "1 2 3\n4 5 6\n";
  if (data == "binary") return header + raw;
  // binary_compressed stores fields as columns: x x y y z z.
  std::string columns;
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < 2; ++i) columns.append(raw, size_t(12 * i + 4 * a), 4);
  const std::string packed = ndtom::testing::lzfLiterals(columns);
  std::string out = header;
  const uint32_t sizes[2] = {uint32_t(packed.size()), uint32_t(columns.size())};
  out.append(reinterpret_cast<const char*>(sizes), 8);
  return out + packed;
}

std::string header(const std::string& size, const std::string& count, const std::string& width,
                   const std::string& height, const std::string& points, const std::string& data) {
  return "VERSION 0.7\nFIELDS x y z\nSIZE " + size + " 4 4\nTYPE F F F\nCOUNT " + count +
         " 1 1\nWIDTH " + width + "\nHEIGHT " + height + "\nPOINTS " + points + "\nDATA " + data +
         "\n";
}

}  // namespace

std::vector<Case> pcdHeaderCases(const Context& c) {
  std::vector<std::string> names, files;
  std::vector<Expect> expects;
  auto add = [&](const std::string& name, const std::string& bytes,
                 Expect expect = Expect::Refuse) {
    names.push_back(name);
    files.push_back(bytes);
    expects.push_back(expect);
  };
  add("131072 fields x 2^20 x 2^24 points (wraps to 0)", ndtom::testing::wrappingCompressedPcd());
  for (const std::string data : {"ascii", "binary", "binary_compressed"}) {
    for (const std::string size : {"0", "3", "4294967300", "18446744073709551620", "-4", "4.0"})
      add("SIZE " + size + " " + data, withData(header(size, "1", "2", "1", "2", data), data));
    for (const std::string count :
         {"0", "2", "4294967297", "4294967296", "18446744073709551617", "-1", "1e0"})
      add("COUNT " + count + " " + data, withData(header("4", count, "2", "1", "2", data), data));
    const std::vector<std::array<std::string, 3>> whp = {
        {"4294967296", "4294967296", "0"},
        {"8589934592", "2147483648", "0"},
        {"18446744073709551615", "1", "18446744073709551615"},
        {"3", "1", "3"},
        {"1", "4294967296", "4294967296"},
        {"2", "9223372036854775808", "0"},
        {"65536", "65536", "4294967296"}};
    for (const auto& [w, h, p] : whp)
      add("WIDTH " + w + " HEIGHT " + h + " POINTS " + p + " " + data,
          withData(header("4", "1", w, h, p, data), data));
  }
  // Compressed sizes that lie.
  const std::string h2 = header("4", "1", "2", "1", "2", "binary_compressed");
  for (const auto& [compressed, uncompressed] : std::vector<std::pair<uint32_t, uint32_t>>{
           {0xFFFFFFFF, 24}, {30, 0xFFFFFFFF}, {30, 2640}, {1, 24}, {0, 0}, {26, 4000000}}) {
    std::string bytes = h2;
    const uint32_t sizes[2] = {compressed, uncompressed};
    bytes.append(reinterpret_cast<const char*>(sizes), 8);
    bytes += ndtom::testing::lzfLiterals(std::string(24, '\1'));
    add("compressed " + std::to_string(compressed) + " / " + std::to_string(uncompressed), bytes);
  }
  // Points of 2^24 bytes, 2^40 of them: the product wraps to 0.
  add("2^40 points of 2^24 bytes", ndtom::testing::wideWrappingCompressedPcd());
  for (const int fields : {1025, 4096, 131072}) {
    std::string f = "x y z", s = "4 4 4", t = "F F F";
    for (int i = 3; i < fields; ++i) f += " f" + std::to_string(i), s += " 4", t += " F";
    add(std::to_string(fields) + " fields",
        "FIELDS " + f + "\nSIZE " + s + "\nTYPE " + t + "\nWIDTH 2\nHEIGHT 1\nPOINTS 2\n" +
            "DATA binary\n" + std::string(8 * size_t(fields), '\0'),
        Expect::Either);  // valid, if wide: a reader may take it or refuse it
  }
  add("VIEWPOINT nan",
      "VIEWPOINT nan 0 0 1 0 0 0\n" + withData(header("4", "1", "2", "1", "2", "ascii"), "ascii"));

  CaseSet set(c, "1 PCD header arithmetic", "pcd");
  for (size_t i = 0; i < files.size(); ++i) {
    const std::string path = set.path(".pcd");
    Case& k = set.add();
    k.name = "parse " + names[i];
    k.expect = expects[i];
    k.argv = {c.probe, "parse-pcd", path};
    k.limits.timeout_s = 30;
    k.setup = [path, bytes = files[i]] {
      writeFile(path, bytes);
      return sizeOf(path);
    };
  }
  // The same files as one scan of ndtom-map's PCD folder input, after two good scans.
  for (size_t i = 0; i < files.size(); i += 3) {
    Case& k = set.add();
    k.name = "ndtom-map, scan 2 is: " + names[i];
    k.expect = expects[i];
    const std::string folder = c.work + "/pcd-map" + std::to_string(i);
    k.argv = c.mapper_args(folder, c.work + "/pcd-map-out/out", {});
    k.setup = [&c, folder, i, bytes = files[i]] {
      c.lidarFolder("pcd-map" + std::to_string(i), 3);
      writeFile(folder + "/full2.pcd", bytes);
      return sizeOf(folder);
    };
  }
  return set.cases;
}

}  // namespace redteam
