#include "io/checkpoint.hpp"

#include <fmt/format.h>

#include <cmath>

#include <algorithm>
#include <cstring>

#include "core/errors.hpp"
#include "io/binary.hpp"
#include "io/files.hpp"

namespace bakesim {

namespace fs = std::filesystem;

namespace {

constexpr char kMagic[] = "BAKESIM-CKPT";  // 12 bytes, no terminator written
constexpr std::size_t kMagicSize = 12;
constexpr std::size_t kHeaderSize = kMagicSize + 4 + 8 + 8;

std::uint64_t fnv1a(const char* data, std::size_t n) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < n; ++i) {
    h ^= static_cast<unsigned char>(data[i]);
    h *= 1099511628211ull;
  }
  return h;
}

void put_string(std::string& out, const std::string& s) {
  put_bytes(out, std::uint64_t(s.size()));
  out += s;
}

template <class T>
void put_array(std::string& out, const std::vector<T>& v) {
  put_bytes(out, std::uint64_t(v.size()));
  out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

class Reader {
 public:
  Reader(const std::string& b, std::size_t pos, const std::string& where) : b_(b), pos_(pos), where_(where) {}
  template <class T>
  T get() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, b_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string string() {
    const std::uint64_t n = get<std::uint64_t>();
    need(n);
    std::string s = b_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  template <class T>
  void array(std::vector<T>& v, std::size_t expected) {
    const std::uint64_t n = get<std::uint64_t>();
    if (n != expected) fail(fmt::format("an attribute has {} values for {} particles", n, expected));
    read_values(v, n);
  }
  template <class T>
  void array(std::vector<T>& v) {
    const std::uint64_t n = get<std::uint64_t>();
    if (n > (b_.size() - pos_) / sizeof(T)) fail("an array runs past the end");
    read_values(v, n);
  }
  bool at_end() const { return pos_ == b_.size(); }
  [[noreturn]] void fail(const std::string& what) const { throw InputError(where_, "corrupt checkpoint: " + what); }

 private:
  template <class T>
  void read_values(std::vector<T>& v, std::uint64_t n) {
    // A crafted count must not wrap n·sizeof(T) around, and an empty list has
    // no data pointer to copy to (memcpy with null is undefined even for 0 bytes).
    if (n > (b_.size() - pos_) / sizeof(T)) fail("it ends early");
    v.resize(n);
    if (n > 0) std::memcpy(static_cast<void*>(v.data()), b_.data() + pos_, n * sizeof(T));
    pos_ += n * sizeof(T);
  }
  void need(std::uint64_t n) const {
    if (n > b_.size() - pos_) fail("it ends early");
  }
  const std::string& b_;
  std::size_t pos_;
  const std::string& where_;
};

}  // namespace

std::string scene_fingerprint(const nlohmann::json& resolved) {
  nlohmann::json j = resolved;
  if (j.contains("time")) j["time"].erase("end");
  j.erase("output");
  j.erase("render");
  j.erase("name");
  j.erase("description");
  const std::string text = j.dump();
  return fmt::format("{:016x}", fnv1a(text.data(), text.size()));
}

std::string encode_checkpoint(const Checkpoint& c) {
  std::string p;
  put_string(p, c.solver);
  put_string(p, c.scene_fingerprint);
  put_string(p, c.scene_dir);
  put_bytes(p, std::int32_t(c.frame));
  put_bytes(p, std::int64_t(c.steps));
  put_bytes(p, c.last_dt);
  put_bytes(p, std::uint64_t(c.solver_state.size()));
  for (const auto& [name, value] : c.solver_state) put_string(p, name), put_bytes(p, value);
  const ParticleSet& ps = c.particles;
  put_bytes(p, std::uint64_t(ps.size()));
  put_bytes(p, std::uint64_t(ps.scalars().size() + ps.vectors().size() + ps.integers().size()));
  for (const auto& a : ps.scalars()) put_bytes(p, std::uint8_t(0)), put_string(p, a.info.name), put_array(p, a.data);
  for (const auto& a : ps.vectors()) put_bytes(p, std::uint8_t(1)), put_string(p, a.info.name), put_array(p, a.data);
  for (const auto& a : ps.integers()) put_bytes(p, std::uint8_t(2)), put_string(p, a.info.name), put_array(p, a.data);
  put_array(p, c.follow_ids);
  return seal_checkpoint_payload(p);
}

std::string seal_checkpoint_payload(std::string_view payload) {
  std::string out(kMagic, kMagicSize);
  put_bytes(out, kCheckpointVersion);
  put_bytes(out, std::uint64_t(payload.size()));
  put_bytes(out, fnv1a(payload.data(), payload.size()));
  out.append(payload);
  return out;
}

Checkpoint decode_checkpoint(const std::string& b, const std::string& where) {
  if (b.size() < kHeaderSize || b.compare(0, kMagicSize, kMagic, kMagicSize) != 0)
    throw InputError(where, "not a bakesim checkpoint");
  Reader head(b, kMagicSize, where);
  const auto version = head.get<std::uint32_t>();
  if (version != kCheckpointVersion)
    throw InputError(where, fmt::format("checkpoint format version {} (this bakesim reads version {})", version,
                                        kCheckpointVersion));
  const auto size = head.get<std::uint64_t>();
  const auto sum = head.get<std::uint64_t>();
  if (size != b.size() - kHeaderSize)
    head.fail(fmt::format("{} payload bytes, the header says {}", b.size() - kHeaderSize, size));
  if (fnv1a(b.data() + kHeaderSize, size) != sum) head.fail("checksum mismatch");
  Reader r(b, kHeaderSize, where);
  Checkpoint c;
  c.solver = r.string();
  c.scene_fingerprint = r.string();
  c.scene_dir = r.string();
  c.frame = r.get<std::int32_t>();
  c.steps = r.get<std::int64_t>();
  c.last_dt = r.get<double>();
  const auto n_state = r.get<std::uint64_t>();
  if (n_state > 1000) r.fail("too many solver values");
  for (std::uint64_t i = 0; i < n_state; ++i) {
    std::string name = r.string();
    c.solver_state.emplace_back(std::move(name), r.get<double>());
  }
  const auto n = r.get<std::uint64_t>();
  const auto attributes = r.get<std::uint64_t>();
  if (attributes > 10000 || n > (b.size() / 4)) r.fail("implausible particle or attribute count");
  c.particles.resize(n);
  for (std::uint64_t k = 0; k < attributes; ++k) {
    const auto kind = r.get<std::uint8_t>();
    const std::string name = r.string();
    if (kind == 0)
      r.array(c.particles.add_scalar(name, ""), n);
    else if (kind == 1)
      r.array(c.particles.add_vector(name, ""), n);
    else if (kind == 2)
      r.array(c.particles.add_int(name), n);
    else
      r.fail("unknown attribute kind");
  }
  r.array(c.follow_ids);
  if (!r.at_end()) r.fail("bytes after the end of the data");
  return c;
}

Checkpoint capture_checkpoint(const Solver& solver) {
  Checkpoint c;
  c.solver = solver.name();
  c.solver_state = solver.checkpoint_state();
  const ParticleSet& ps = solver.particles();
  c.particles.resize(ps.size());
  for (const auto& a : ps.scalars()) c.particles.add_scalar(a.info.name, a.info.unit, a.info.exported) = a.data;
  for (const auto& a : ps.vectors()) c.particles.add_vector(a.info.name, a.info.unit, a.info.exported) = a.data;
  for (const auto& a : ps.integers()) c.particles.add_int(a.info.name, a.info.exported) = a.data;
  return c;
}

// A checkpoint whose checksum was recomputed after editing is still refused
// unless it could have come from a run of this scene (issue 21): the counters
// are in range, the particles are the scene's (the ids a permutation, each
// with the body and material it started with), and the state is finite.
void validate_checkpoint(const ParticleSet& fresh, const Checkpoint& c, const std::string& where) {
  auto refuse = [&](const std::string& why) { throw InputError(where, "checkpoint refused: " + why); };
  if (c.frame < 0 || c.frame > 1000000) refuse(fmt::format("frame {} out of range", c.frame));
  if (c.steps < 0 || c.steps > 1e15) refuse(fmt::format("step count {} out of range", c.steps));
  if (!std::isfinite(c.last_dt) || c.last_dt < 0) refuse("time step not a finite non-negative number");
  for (const auto& [name, value] : c.solver_state)  // heat totals may be negative (a cooling body)
    if (!std::isfinite(value) || ((name == "time" || name == "steps") && !(value >= 0 && value <= 1e15)))
      refuse(fmt::format("solver state '{}' = {} out of range", name, value));
  const ParticleSet& p = c.particles;
  if (p.size() != fresh.size()) refuse(fmt::format("{} particles, the scene makes {}", p.size(), fresh.size()));
  if (fresh.has("id") && p.has("id")) {
    const auto& fid = fresh.integer("id");
    const auto& id = p.integer("id");
    std::vector<std::size_t> fresh_at(fid.size());
    for (std::size_t i = 0; i < fid.size(); ++i) fresh_at[std::size_t(fid[i])] = i;
    std::vector<char> seen(id.size(), 0);
    for (std::size_t i = 0; i < id.size(); ++i) {
      if (id[i] < 0 || std::size_t(id[i]) >= id.size() || seen[std::size_t(id[i])]++)
        refuse(fmt::format("particle ids are not a permutation of the scene's (entry {})", i));
      for (const char* owner : {"body_id", "material_id"})
        if (fresh.has(owner) && p.has(owner) &&
            p.integer(owner)[i] != fresh.integer(owner)[fresh_at[std::size_t(id[i])]])
          refuse(fmt::format("particle {} has {} {}, the scene gives it {}", id[i], owner, p.integer(owner)[i],
                             fresh.integer(owner)[fresh_at[std::size_t(id[i])]]));
    }
  }
  for (const auto& a : p.scalars())
    for (std::size_t i = 0; i < a.data.size(); ++i)
      if (!std::isfinite(a.data[i])) refuse(fmt::format("{} of particle entry {} is not finite", a.info.name, i));
  for (const auto& a : p.vectors())
    for (std::size_t i = 0; i < a.data.size(); ++i)
      if (!a.data[i].allFinite()) refuse(fmt::format("{} of particle entry {} is not finite", a.info.name, i));
}

void restore_checkpoint(Solver& solver, const Checkpoint& c, const std::string& where) {
  if (c.solver != solver.name())
    throw InputError(where, fmt::format("checkpoint of a {} run, the scene runs {}", c.solver, solver.name()));
  validate_checkpoint(solver.particles(), c, where);
  ParticleSet& ps = solver.particles_for_restore();
  // Every attribute the solver has must be in the checkpoint, with the same kind.
  auto missing = [&](const std::string& name) {
    return InputError(where, "checkpoint lacks the particle attribute '" + name + "'");
  };
  for (const auto& a : ps.scalars())
    if (!c.particles.has(a.info.name)) throw missing(a.info.name);
  for (const auto& a : ps.vectors())
    if (!c.particles.has(a.info.name)) throw missing(a.info.name);
  for (const auto& a : ps.integers())
    if (!c.particles.has(a.info.name)) throw missing(a.info.name);
  ps.resize(c.particles.size());
  try {
    for (const auto& a : ps.scalars()) ps.scalar(a.info.name) = c.particles.scalar(a.info.name);
    for (const auto& a : ps.vectors()) ps.vector(a.info.name) = c.particles.vector(a.info.name);
    for (const auto& a : ps.integers()) ps.integer(a.info.name) = c.particles.integer(a.info.name);
  } catch (const std::exception& e) {
    throw InputError(where, std::string("checkpoint attributes do not match the solver's: ") + e.what());
  }
  solver.restore_state(c.solver_state);
  if (const std::string problem = solver.restored_state_problem(); !problem.empty())
    throw InputError(where, "checkpoint refused: " + problem);
}

fs::path write_checkpoint(const fs::path& run_dir, const Checkpoint& c, int keep) {
  const fs::path dir = run_dir / "checkpoints";
  ensure_directory(dir);
  const fs::path file = dir / (frame_stem(c.frame) + ".ckpt");
  write_file_atomic(file, encode_checkpoint(c));
  // The one just written and the newest `keep` - 1 before it stay. Files numbered past it are
  // not this run's (a run directory starts clean) and are left alone.
  std::size_t kept = 0;
  std::error_code ec;
  for (const fs::path& old : list_checkpoints(run_dir)) {
    const auto number = frame_number(old.stem().string());
    if (!number || *number > c.frame) continue;
    if (++kept > std::size_t(std::max(keep, 1)) && fs::is_regular_file(fs::symlink_status(old, ec)))
      fs::remove(old, ec);
  }
  return file;
}

std::vector<fs::path> list_checkpoints(const fs::path& run_dir) {
  std::vector<fs::path> out;
  const fs::path dir = run_dir / "checkpoints";
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return out;
  std::vector<std::pair<int, fs::path>> numbered;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (const auto number = frame_number(e.path().stem().string()); number && e.path().extension() == ".ckpt")
      numbered.emplace_back(*number, e.path());
  // By frame number, not by name: "100000" sorts before "99999".
  std::sort(numbered.begin(), numbered.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (auto& [number, path] : numbered) out.push_back(std::move(path));
  return out;
}

}  // namespace bakesim
