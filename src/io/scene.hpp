#pragma once
// Scenes: read a JSON file, validate it against the schema (filling every
// default), check what the schema cannot (names that refer to each other,
// boxes with min < max, mesh files), and build the solver's setup.
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/solver.hpp"
#include "physics/curves.hpp"
#include "mpm/solver.hpp"
#include "sph/solver.hpp"

namespace bakesim {

struct ProbeSpec {
  std::string name;
  Vec3 position;
  std::vector<std::string> quantities;
  bool follow = false;  // track the particle that starts nearest the position
};

struct OutputSpec {
  std::vector<std::string> particle_formats = {"ply", "vtu"};  // rows of io/particle_files.hpp's table
  int every_frames = 1;
};

struct Scene {
  std::string file;  // as given by the user
  std::string name;
  std::string description;
  std::string solver_type;  // "sph" or "mpm"
  nlohmann::json resolved;  // the document with every default filled in
  Real end_time = 1.0;
  Real fps = 30.0;
  Oven oven;  // air, bake clock, browning (both solvers)
  Vec3 gravity = Vec3(0, -9.81, 0);
  struct BodyInfo {
    std::string name;
    bool hold_temperature = false;  // a heater or cooler: no bake statistics
    Real boiling_point = 100;       // its material's moisture.boiling_point, °C: where its crust starts
  };
  std::vector<BodyInfo> bodies;
  std::vector<ProbeSpec> probes;
  OutputSpec output;
  // What the loader did that a user should see in the log (the presets it expanded).
  std::vector<std::string> notes;
  // The files this scene extends ("extends"), nearest first; the resolved scene has them merged in.
  std::vector<std::string> extends;
  // Values that are allowed but look like a unit mistake (an oven at 493 °C
  // typed in kelvin, a body 50 m across typed in millimetres); `validate`
  // and `run` print them.
  std::vector<std::string> warnings;
  // The chosen solver's setup (the other stays empty).
  sph::Setup sph;
  mpm::Setup mpm;
};

// A change to a scene from the command line: `--set key.path=value`, e.g.
// `environment.air_temperature=200`, `bodies[0].temperature=5`,
// `materials.dough.density=650`. The value is read as JSON (a number, true,
// [0, 1, 0], {"curve": ...}, "text") and as a plain string when it is not JSON.
struct SceneOverride {
  std::string path;               // as typed, for messages
  std::vector<std::string> keys;  // object keys, or array indices as "[N]"
  nlohmann::json value;
};
// Throws InputError("--set", ...) for text without "=" or with a malformed path.
SceneOverride parse_override(const std::string& text);

// Reads and validates a scene file. Throws InputError (file:line:column for
// syntax errors, "file: key.path" for content errors). Overrides are applied
// to the document before it is validated, so they obey the same schema and
// limits and appear in the resolved scene.
Scene load_scene(const std::string& path, const std::vector<SceneOverride>& overrides = {});
// Same, from text; `file` names it in messages, `base_dir` resolves mesh paths.
Scene parse_scene(const std::string& text, const std::string& file, const std::string& base_dir,
                  const std::vector<SceneOverride>& overrides = {});

// `--preview`: the changes that make a quick look at a scene (docs/scenes.md,
// "Previews"): the particle spacing (SPH) or cell size (MPM) times
// kPreviewCoarsening, so 8x fewer particles taking about 2x longer steps; at
// most kPreviewFrames frames; the name NAME-preview (so out/NAME-preview).
// MPM containers and cups keep their walls two cells thick, which may limit the coarsening.
// Where the doubled spacing samples a body more than 5% off its shape's volume
// (a thin cookie loses a layer), the nearest finer spacing that fills the
// bodies within 5% (geometry/shapes.hpp, fitting_spacing).
// The physics, the bake clock and the bake's length stay as they are.
inline constexpr double kPreviewCoarsening = 2.0;
inline constexpr int kPreviewFrames = 10;
std::vector<SceneOverride> preview_overrides(const Scene& scene);
// load_scene, and with `preview` once more with preview_overrides after `overrides` (run, validate, sweep).
Scene load_scene(const std::string& path, std::vector<SceneOverride> overrides, bool preview);
// --end-time: `end_time` instead of time.end, within the limits scene files obey (at most 1e6 s and a
// million frames); recorded in the resolved scene. InputError("--end-time", ...) otherwise.
void set_end_time(Scene& scene, double end_time);

// The air pressure a scene's `environment` names, Pa: its `altitude` through
// the ICAO standard atmosphere, or its `air_pressure`; none (sea level) when
// it names neither. (Both at once is refused when the scene is loaded.)
struct NamedAirPressure {
  double pascal = 0;
  std::optional<double> altitude;  // m, when the scene gave the altitude
};
std::optional<NamedAirPressure> named_air_pressure(const nlohmann::json& environment);

std::unique_ptr<Solver> make_solver(const Scene& scene);

// Human-readable summary of what the scene will simulate (for `validate`):
// the scene's frame, the solver's own summary, and the time step.
std::string describe(const Scene& scene, Solver& solver);

}  // namespace bakesim
