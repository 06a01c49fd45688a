// Fuzz target: `run --resume` of crafted checkpoints. Any input must be
// refused with an InputError or restore a state the solver then steps (a
// SimulationError from the health checks is a refusal too); nothing else.
// The first byte chooses the solver (bit 0: SPH or MPM, each a tiny baking
// scene built once) and how the rest is read (byte / 2 mod 3):
//   0  a whole checkpoint file, as read from disk;
//   1  a payload, sealed with its correct checksum (to get past it);
//   2  edits of a real checkpoint's payload, five bytes each (a little-endian
//      offset, modulo the payload size, and the byte to put there), sealed:
//      the checks after the checksum (counts, ids, finite state) see input
//      that is nearly valid.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>

#include "core/errors.hpp"
#include "io/checkpoint.hpp"
#include "io/scene.hpp"

namespace {

using namespace bakesim;

const char* const kSphScene = R"({
  "solver": {"type": "sph", "sph": {"spacing": 0.01}},
  "time": {"end": 0.1, "fps": 50},
  "domain": {"min": [0, 0, 0], "max": [0.12, 0.12, 0.12]},
  "environment": {"air_temperature": 180, "bake_time_scale": 100},
  "materials": {"dough": {"preset": "dough"}},
  "bodies": [{"name": "ball", "material": "dough", "temperature": 25,
    "shape": {"type": "sphere", "center": [0.06, 0.04, 0.06], "radius": 0.025}}],
  "probes": [{"name": "core", "position": [0.06, 0.04, 0.06], "quantities": ["temperature"], "follow": true}]
})";

const char* const kMpmScene = R"({
  "solver": {"type": "mpm", "mpm": {"cell_size": 0.01, "heat": "explicit"}, "max_dt": 5e-4},
  "time": {"end": 0.1, "fps": 50},
  "domain": {"min": [-0.06, 0, -0.06], "max": [0.06, 0.08, 0.06]},
  "environment": {"air_temperature": 180, "bake_time_scale": 200},
  "materials": {"dough": {"density": 800, "youngs_modulus": 5e4, "poisson_ratio": 0.3,
    "plasticity": {"model": "cam_clay", "yield_stress": 200, "viscosity": 10, "initial_porosity": 0.2},
    "water": {"saturation": 0.6},
    "leavening": {"rate": 2e-5, "peak_temperature": 60, "width": 20}}},
  "bodies": [{"name": "dough", "material": "dough", "temperature": 25,
    "shape": {"type": "box", "min": [-0.03, 0.002, -0.03], "max": [0.03, 0.03, 0.03]}}],
  "colliders": [{"name": "tray", "shape": {"type": "plane", "point": [0, 0.001, 0], "normal": [0, 1, 0]},
    "temperature": 200}]
})";

struct Case {
  Scene scene;
  std::string payload;  // of a checkpoint after a few steps
};

Case make_case(const char* text) {
  Case c{parse_scene(text, "fuzz-checkpoint.json", "."), {}};
  auto solver = make_solver(c.scene);
  for (int i = 0; i < 3; ++i) solver->step(solver->max_stable_dt());
  Checkpoint ck = capture_checkpoint(*solver);
  ck.frame = 1;
  ck.steps = 3;
  ck.last_dt = solver->max_stable_dt();
  c.payload = encode_checkpoint(ck).substr(kCheckpointHeaderBytes);
  return c;
}

const Case& the_case(bool mpm) {
  static const Case sph = make_case(kSphScene), mpm_case = make_case(kMpmScene);
  return mpm ? mpm_case : sph;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const Case& c = the_case(data[0] & 1);
  const std::string rest(reinterpret_cast<const char*>(data + 1), size - 1);
  std::string file;
  switch ((data[0] >> 1) % 3) {
    case 0: file = rest; break;
    case 1: file = seal_checkpoint_payload(rest); break;
    default: {
      std::string payload = c.payload;
      for (std::size_t at = 0; at + 5 <= rest.size(); at += 5) {
        std::uint32_t offset;
        std::memcpy(&offset, rest.data() + at, 4);
        payload[offset % payload.size()] = rest[at + 4];
      }
      file = seal_checkpoint_payload(payload);
    }
  }
  try {
    const Checkpoint ck = decode_checkpoint(file, "fuzz.ckpt");
    auto solver = make_solver(c.scene);
    restore_checkpoint(*solver, ck, "fuzz.ckpt");
    for (int i = 0; i < 3; ++i) {
      const Real dt = solver->max_stable_dt();
      if (!(dt >= 1e-10)) break;
      solver->step(std::min<Real>(dt, 1e-3));
    }
  } catch (const InputError&) {
  } catch (const SimulationError&) {
  }
  return 0;
}
