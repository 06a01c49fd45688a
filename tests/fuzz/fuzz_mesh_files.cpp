// Fuzz target: the OBJ and PLY mesh readers (colliders, bodies) and the PLY
// reader of frames and surface meshes must turn any bytes into a mesh or an
// InputError, never read out of bounds or crash.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "core/errors.hpp"
#include "geometry/mesh_io.hpp"
#include "io/ply_reader.hpp"

namespace {
std::string scratch(const char* ext) { return "/tmp/bakesim-fuzz-" + std::to_string(getpid()) + ext; }

void load_through_file(const std::string& bytes, const char* ext) {
  const std::string path = scratch(ext);
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(bytes.data(), 1, bytes.size(), f);
    std::fclose(f);
  }
  try {
    bakesim::TriangleMesh m = bakesim::load_mesh(path);
    (void)m;
  } catch (const bakesim::InputError&) {
  }
  std::remove(path.c_str());
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  load_through_file(bytes, ".obj");
  load_through_file(bytes, ".ply");
  try {
    const bakesim::PlyData ply = bakesim::parse_ply(bytes, "fuzz.ply");
    try {
      (void)bakesim::particles_from_ply(ply, "fuzz.ply");
    } catch (const bakesim::InputError&) {
    }
    try {
      (void)bakesim::mesh_from_ply(ply, "fuzz.ply");
    } catch (const bakesim::InputError&) {
    }
  } catch (const bakesim::InputError&) {
  }
  return 0;
}
