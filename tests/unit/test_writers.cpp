// Frame writers: PLY header and payload, VTU layout, atomic writes.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/errors.hpp"
#include "io/files.hpp"
#include "io/particle_files.hpp"

using namespace bakesim;
namespace fs = std::filesystem;

namespace {
ParticleSet small_set() {
  ParticleSet ps;
  auto& x = ps.add_vector("position", "m");
  auto& v = ps.add_vector("velocity", "m/s");
  auto& t = ps.add_scalar("temperature", "degC");
  ps.add_scalar("hidden", "", false);
  auto& id = ps.add_int("id");
  ps.resize(3);
  for (int i = 0; i < 3; ++i) {
    x[i] = Vec3(i, 2 * i, 3 * i);
    v[i] = Vec3(-i, 0, 1);
    t[i] = 20 + i;
    id[i] = 100 + i;
  }
  return ps;
}
}  // namespace

TEST(Writers, PlyHeaderListsEveryExportedAttributeAndPayloadMatches) {
  const std::string ply = encode_ply(small_set());
  const auto end = ply.find("end_header\n");
  ASSERT_NE(end, std::string::npos);
  const std::string header = ply.substr(0, end);
  EXPECT_NE(header.find("format binary_little_endian 1.0"), std::string::npos);
  EXPECT_NE(header.find("element vertex 3"), std::string::npos);
  EXPECT_NE(header.find("property float velocity_x"), std::string::npos);
  EXPECT_NE(header.find("property float temperature"), std::string::npos);
  EXPECT_NE(header.find("property int id"), std::string::npos);
  EXPECT_EQ(header.find("hidden"), std::string::npos);
  // x y z vx vy vz temperature id = 8 values of 4 bytes per vertex.
  const std::string body = ply.substr(end + 11);
  ASSERT_EQ(body.size(), 3u * 8u * 4u);
  float f;
  std::memcpy(&f, body.data() + 32 + 4, 4);  // second vertex, y
  EXPECT_EQ(f, 2.0f);
  std::int32_t id;
  std::memcpy(&id, body.data() + 2 * 32 + 28, 4);
  EXPECT_EQ(id, 102);
}

TEST(Writers, VtuDeclaresArraysWithConsistentOffsets) {
  const std::string vtu = encode_vtu(small_set());
  EXPECT_NE(vtu.find("NumberOfPoints=\"3\""), std::string::npos);
  EXPECT_NE(vtu.find("Name=\"temperature\""), std::string::npos);
  EXPECT_NE(vtu.find("Name=\"velocity\" NumberOfComponents=\"3\""), std::string::npos);
  // The last block (types, 3 bytes) ends where the appended data ends.
  const auto marker = vtu.find("_", vtu.find("<AppendedData"));
  const auto close = vtu.rfind("\n  </AppendedData>");
  const auto last_offset_pos = vtu.rfind("offset=\"");
  const std::uint64_t last_offset = std::stoull(vtu.substr(last_offset_pos + 8));
  EXPECT_EQ(close - (marker + 1), last_offset + 8 + 3);
}

TEST(Writers, AtomicWriteReplacesWholeFilesAndReportsUnwritableDirectories) {
  const fs::path dir = fs::temp_directory_path() / "bakesim_atomic";
  fs::create_directories(dir);
  write_file_atomic(dir / "a.txt", "first");
  write_file_atomic(dir / "a.txt", "second");
  std::ifstream in(dir / "a.txt");
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_EQ(ss.str(), "second");
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos);
  EXPECT_THROW(write_file_atomic("/no/such/dir/a.txt", "x"), IoError);
}

TEST(Writers, PvdListsFramesInOrder) {
  const std::string pvd = encode_pvd({{0.0, "frames/00000.vtu"}, {0.5, "frames/00001.vtu"}});
  EXPECT_LT(pvd.find("00000.vtu"), pvd.find("00001.vtu"));
  EXPECT_NE(pvd.find("timestep=\"0.5\""), std::string::npos);
}
