#include "io/particle_files.hpp"

#include <fmt/format.h>

#include "io/binary.hpp"

#include <bit>
#include <cstring>

namespace bakesim {
namespace {

static_assert(std::endian::native == std::endian::little, "frame writers assume a little-endian host");

}  // namespace

std::string encode_ply(const ParticleSet& ps) {
  const auto& pos = ps.vector("position");
  std::string header = "ply\nformat binary_little_endian 1.0\ncomment bakesim particle frame\n";
  header += fmt::format("element vertex {}\n", ps.size());
  header += "property float x\nproperty float y\nproperty float z\n";
  for (const auto& a : ps.vectors())
    if (a.info.exported && a.info.name != "position")
      for (const char* c : {"_x", "_y", "_z"}) header += fmt::format("property float {}{}\n", a.info.name, c);
  for (const auto& a : ps.scalars())
    if (a.info.exported) header += fmt::format("property float {}\n", a.info.name);
  for (const auto& a : ps.integers())
    if (a.info.exported) header += fmt::format("property int {}\n", a.info.name);
  header += "end_header\n";
  std::string out = header;
  out.reserve(header.size() + ps.size() * 4 * 32);
  for (std::size_t i = 0; i < ps.size(); ++i) {
    for (int k = 0; k < 3; ++k) put_bytes(out, static_cast<float>(pos[i][k]));
    for (const auto& a : ps.vectors())
      if (a.info.exported && a.info.name != "position")
        for (int k = 0; k < 3; ++k) put_bytes(out, static_cast<float>(a.data[i][k]));
    for (const auto& a : ps.scalars())
      if (a.info.exported) put_bytes(out, static_cast<float>(a.data[i]));
    for (const auto& a : ps.integers())
      if (a.info.exported) put_bytes(out, static_cast<std::int32_t>(a.data[i]));
  }
  return out;
}

std::string encode_vtu(const ParticleSet& ps) {
  const std::size_t n = ps.size();
  std::string xml, data;
  std::uint64_t offset = 0;
  // Each appended block: UInt64 byte count, then the values.
  auto block = [&](const std::string& attrs, auto&& fill, std::uint64_t bytes) {
    xml += fmt::format("        <DataArray {} format=\"appended\" offset=\"{}\"/>\n", attrs, offset);
    put_bytes(data, bytes);
    fill();
    offset += 8 + bytes;
  };
  xml += "<?xml version=\"1.0\"?>\n";
  xml += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  xml += "  <UnstructuredGrid>\n";
  xml += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", n, n);
  xml += "      <PointData>\n";
  for (const auto& a : ps.vectors())
    if (a.info.exported && a.info.name != "position")
      block(
          fmt::format("type=\"Float32\" Name=\"{}\" NumberOfComponents=\"3\"", a.info.name),
          [&] {
            for (std::size_t i = 0; i < n; ++i)
              for (int k = 0; k < 3; ++k) put_bytes(data, float(a.data[i][k]));
          },
          n * 12);
  for (const auto& a : ps.scalars())
    if (a.info.exported)
      block(
          fmt::format("type=\"Float32\" Name=\"{}\"", a.info.name),
          [&] {
            for (std::size_t i = 0; i < n; ++i) put_bytes(data, float(a.data[i]));
          },
          n * 4);
  for (const auto& a : ps.integers())
    if (a.info.exported)
      block(
          fmt::format("type=\"Int32\" Name=\"{}\"", a.info.name),
          [&] {
            for (std::size_t i = 0; i < n; ++i) put_bytes(data, std::int32_t(a.data[i]));
          },
          n * 4);
  xml += "      </PointData>\n      <Points>\n";
  const auto& pos = ps.vector("position");
  block(
      "type=\"Float32\" Name=\"Points\" NumberOfComponents=\"3\"",
      [&] {
        for (std::size_t i = 0; i < n; ++i)
          for (int k = 0; k < 3; ++k) put_bytes(data, float(pos[i][k]));
      },
      n * 12);
  xml += "      </Points>\n      <Cells>\n";
  block(
      "type=\"Int64\" Name=\"connectivity\"",
      [&] {
        for (std::size_t i = 0; i < n; ++i) put_bytes(data, std::int64_t(i));
      },
      n * 8);
  block(
      "type=\"Int64\" Name=\"offsets\"",
      [&] {
        for (std::size_t i = 0; i < n; ++i) put_bytes(data, std::int64_t(i + 1));
      },
      n * 8);
  block(
      "type=\"UInt8\" Name=\"types\"",
      [&] {
        for (std::size_t i = 0; i < n; ++i) put_bytes(data, std::uint8_t(1));
      },
      n);
  xml += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n";
  xml += "  <AppendedData encoding=\"raw\">\n   _";
  std::string out = xml;
  out += data;
  out += "\n  </AppendedData>\n</VTKFile>\n";
  return out;
}

std::string encode_pvd(const std::vector<PvdEntry>& entries) {
  std::string out =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  "
      "<Collection>\n";
  for (const auto& e : entries)
    out += fmt::format("    <DataSet timestep=\"{:.9g}\" group=\"\" part=\"0\" file=\"{}\"/>\n", e.time, e.file);
  out += "  </Collection>\n</VTKFile>\n";
  return out;
}

}  // namespace bakesim

namespace bakesim {

const std::vector<ParticleFormat>& particle_formats() {
  static const std::vector<ParticleFormat> formats = {
      {"ply", ".ply", &encode_ply, false},
      {"vtu", ".vtu", &encode_vtu, true},
  };
  return formats;
}

}  // namespace bakesim
