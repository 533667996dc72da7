// The scene's parallel gzip: what zlib's own reader and MRPT's scene loader get back is what
// went in, for any thread count, in one member or many.
#include <gtest/gtest.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <mrpt/io/CStream.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfTriangles.h>
#include <mrpt/serialization/CArchive.h>
#include <random>
#include <unistd.h>

#include "ndtom_apps/gzip_members.h"

namespace ndtom::mapper {
namespace {

namespace fs = std::filesystem;

fs::path scratchFile(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("ndtom_gzip_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

std::string gzipped(const std::string& data, int threads, size_t piece) {
  std::string out;
  const ndtom::FileSink sink = [&](const void* d, size_t n) {
    out.append(static_cast<const char*>(d), n);
  };
  GzipMemberWriter gzip(sink, 1, threads);
  for (size_t at = 0; at < data.size(); at += piece)
    gzip.write(data.data() + at, std::min(piece, data.size() - at));
  gzip.finish();
  return out;
}

// What zlib's gzread (MRPT's CFileGZInputStream reads through it) gets from `bytes`.
std::string gunzipped(const std::string& bytes) {
  const fs::path file = scratchFile("data.gz");
  std::ofstream(file, std::ios::binary) << bytes;
  gzFile in = gzopen(file.c_str(), "rb");
  EXPECT_NE(in, nullptr);
  std::string out;
  char buffer[1 << 16];
  int n;
  while ((n = gzread(in, buffer, sizeof buffer)) > 0) out.append(buffer, size_t(n));
  EXPECT_EQ(n, 0) << "gzread failed";
  gzclose(in);
  return out;
}

size_t gzipHeaders(const std::string& bytes) {  // 1f 8b 08: a member's start (or a lucky run)
  size_t count = 0;
  for (size_t i = 0; i + 2 < bytes.size(); ++i)
    count += uint8_t(bytes[i]) == 0x1f && uint8_t(bytes[i + 1]) == 0x8b && bytes[i + 2] == 8;
  return count;
}

TEST(GzipMembers, RoundTripsForAnyThreadCountAndPieceSize) {
  std::mt19937 rng(3);
  std::string data(GzipMemberWriter::kPartBytes * 2 + 12345, '\0');
  for (size_t i = 0; i < data.size(); ++i)  // compressible, like a mesh: runs and noise
    data[i] = char((i / 64) % 7 == 0 ? rng() : i % 251);
  for (const int threads : {1, 2, 3})
    for (const size_t piece : {size_t(1), size_t(4096), data.size()}) {
      if (piece == 1 && threads != 2) continue;  // byte by byte is slow; once is enough
      const std::string z = gzipped(data, threads, piece);
      EXPECT_LT(z.size(), data.size() / 2) << threads;
      EXPECT_GE(gzipHeaders(z), 3u) << "one member per 4 MB part";
      EXPECT_EQ(gunzipped(z), data) << threads << " threads, pieces of " << piece;
    }
  // The members do not depend on the thread count.
  EXPECT_EQ(gzipped(data, 1, 4096), gzipped(data, 2, 4096));
}

TEST(GzipMembers, EmptyAndSmallInputsAreOneMember) {
  EXPECT_EQ(gunzipped(gzipped("", 2, 1)), "");
  const std::string z = gzipped("hello", 2, 1);
  EXPECT_EQ(gzipHeaders(z), 1u);
  EXPECT_EQ(gunzipped(z), "hello");
}

TEST(GzipMembers, SinkErrorsReachTheCaller) {
  const ndtom::FileSink failing = [](const void*, size_t) {
    throw std::runtime_error("cannot write x: No space left on device");
  };
  const std::string data(GzipMemberWriter::kPartBytes * 3, 'a');
  GzipMemberWriter gzip(failing, 1, 2);
  EXPECT_THROW(
      {
        gzip.write(data.data(), data.size());
        gzip.finish();
      },
      std::runtime_error);
}

TEST(GzipMembers, MrptLoadsASceneWrittenInManyMembers) {
  mrpt::opengl::COpenGLScene scene;
  auto mesh = mrpt::opengl::CSetOfTriangles::Create();
  mesh->setName("mesh");
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-10, 10);
  for (int i = 0; i < 150000; ++i) {  // ~13 MB archived: several members
    mrpt::opengl::TTriangle t;
    for (auto& v : t.vertices) v.xyzrgba.pt = {u(rng), u(rng), u(rng)};
    mesh->insertTriangle(t);
  }
  scene.insert(mesh);
  std::string bytes;
  const ndtom::FileSink sink = [&](const void* d, size_t n) {
    bytes.append(static_cast<const char*>(d), n);
  };
  struct Stream : mrpt::io::CStream {
    GzipMemberWriter& gzip;
    explicit Stream(GzipMemberWriter& g) : gzip(g) {}
    size_t Write(const void* d, size_t n) override {
      gzip.write(d, n);
      return n;
    }
    size_t Read(void*, size_t) override { return 0; }
    uint64_t Seek(int64_t, TSeekOrigin) override { return 0; }
    uint64_t getTotalBytesCount() const override { return 0; }
    uint64_t getPosition() const override { return 0; }
  };
  {
    GzipMemberWriter gzip(sink, 1, 2);
    Stream stream(gzip);
    mrpt::serialization::archiveFrom(stream) << scene;
    gzip.finish();
  }
  ASSERT_GE(gzipHeaders(bytes), 3u);
  const fs::path file = scratchFile("scene.3Dscene");
  std::ofstream(file, std::ios::binary) << bytes;
  mrpt::opengl::COpenGLScene loaded;
  ASSERT_TRUE(loaded.loadFromFile(file.string()));
  const auto back = loaded.getByClass<mrpt::opengl::CSetOfTriangles>();
  ASSERT_TRUE(back);
  ASSERT_EQ(back->getTrianglesCount(), mesh->getTrianglesCount());
  for (size_t i = 0; i < mesh->getTrianglesCount(); i += 997) {
    mrpt::opengl::TTriangle a, b;
    back->getTriangle(i, a);
    mesh->getTriangle(i, b);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(a.vertices[k].xyzrgba.pt, b.vertices[k].xyzrgba.pt);
  }
  fs::remove_all(file.parent_path());
}

}  // namespace
}  // namespace ndtom::mapper
