// bakesim._bakesim: the library for Python (pybind11). A thin front end like
// the command line: scenes load with the same validation, a Simulation owns
// its solver (no global state, so several live in one process), runs into a
// run directory through the same code as `bakesim run` (io/bake_run.hpp), and
// shows particle attributes as numpy arrays over the solver's own storage.
// The Python package bakesim/ (python/bakesim/__init__.py) wraps this.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

#include "core/errors.hpp"
#include "io/bake_run.hpp"
#include "io/checkpoint.hpp"
#include "io/files.hpp"
#include "io/run_meshes.hpp"
#include "io/scene.hpp"
#include "io/sweep.hpp"
#include "render/plot.hpp"
#include "render/report.hpp"
#include "render/run_pictures.hpp"
#include "render/run_results.hpp"
#include "render/sweep_outputs.hpp"

namespace py = pybind11;
namespace fs = std::filesystem;
using namespace bakesim;

namespace {

// Python's json module turns values into text and back: the scene loader reads JSON.
std::string to_json_text(const py::handle& value) {
  return py::module_::import("json").attr("dumps")(value).cast<std::string>();
}
py::object from_json(const nlohmann::json& value) { return py::module_::import("json").attr("loads")(value.dump()); }

// {"environment.air_temperature": 200, ...} or ["KEY=VALUE", ...] (as typed on the command line).
std::vector<SceneOverride> overrides_of(const py::object& overrides) {
  std::vector<SceneOverride> out;
  if (overrides.is_none()) return out;
  if (py::isinstance<py::dict>(overrides)) {
    for (const auto& [key, value] : overrides.cast<py::dict>())
      out.push_back(parse_override(py::str(key).cast<std::string>() + "=" + to_json_text(value)));
    return out;
  }
  for (const auto& item : overrides) out.push_back(parse_override(py::str(item).cast<std::string>()));
  return out;
}

struct PyScene {
  std::shared_ptr<Scene> scene;
  std::string scene_dir;  // where relative mesh paths resolve
};

PyScene load(const py::object& source, const py::object& overrides, bool preview, const std::string& base_dir) {
  PyScene s;
  std::vector<SceneOverride> sets = overrides_of(overrides);
  if (py::isinstance<py::dict>(source)) {
    const std::string text = to_json_text(source);
    s.scene_dir = fs::absolute(base_dir.empty() ? fs::current_path() : fs::path(base_dir)).string();
    Scene scene = parse_scene(text, "<dict>", s.scene_dir, sets);
    if (preview) {
      for (auto& o : preview_overrides(scene)) sets.push_back(std::move(o));
      scene = parse_scene(text, "<dict>", s.scene_dir, sets);
    }
    s.scene = std::make_shared<Scene>(std::move(scene));
  } else {
    const std::string path = py::str(source).cast<std::string>();
    s.scene = std::make_shared<Scene>(load_scene(path, std::move(sets), preview));
    s.scene_dir = fs::absolute(fs::path(path)).parent_path().string();
  }
  return s;
}

// A numpy array over an attribute's storage, kept alive by `owner`.
template <class T>
py::array view_of(std::vector<T>& data, int columns, bool writable, const py::object& owner) {
  using Scalar = std::conditional_t<std::is_same_v<T, Vec3>, Real, T>;
  py::array out;
  if (columns == 1)
    out = py::array_t<Scalar>({py::ssize_t(data.size())}, {py::ssize_t(sizeof(T))},
                              reinterpret_cast<Scalar*>(data.data()), owner);
  else
    out = py::array_t<Scalar>({py::ssize_t(data.size()), py::ssize_t(columns)},
                              {py::ssize_t(sizeof(T)), py::ssize_t(sizeof(Scalar))},
                              reinterpret_cast<Scalar*>(data.data()), owner);
  if (!writable) out.attr("setflags")(py::arg("write") = false);
  return out;
}

// Attributes a user may set between steps: the state the solver advances
// from. Everything else is derived (density, pressure, surface flags, ...)
// or bookkeeping (ids, bodies), where a write would break the solver's invariants.
bool settable(const std::string& name) { return name == "temperature" || name == "velocity" || name == "water_mass"; }

// A whole frame (a PLY read back, a registry) as {name: array}, copied.
py::dict arrays_of(const ParticleSet& ps) {
  py::dict out;
  for (const auto& a : ps.scalars()) out[py::str(a.info.name)] = py::array_t<Real>(a.data.size(), a.data.data());
  for (const auto& a : ps.vectors()) {
    py::array_t<Real> v({py::ssize_t(a.data.size()), py::ssize_t(3)});
    auto w = v.mutable_unchecked<2>();
    for (std::size_t i = 0; i < a.data.size(); ++i)
      for (int k = 0; k < 3; ++k) w(py::ssize_t(i), k) = a.data[i][k];
    out[py::str(a.info.name)] = v;
  }
  for (const auto& a : ps.integers())
    out[py::str(a.info.name)] = py::array_t<std::int32_t>(a.data.size(), a.data.data());
  return out;
}

// An observer that keeps the stats rows in memory (a Simulation without a run directory).
class MemoryOutput final : public FrameObserver {
 public:
  MemoryOutput(const Scene& scene, const Solver& solver) : recorder_(scene, solver) {}
  void on_frame(const FrameInfo& info, const Solver& solver) override { recorder_.record(info, solver); }
  FrameRecorder& recorder() { return recorder_; }

 private:
  FrameRecorder recorder_;
};

class Simulation {
 public:
  // A new simulation of `scene`; with `out`, a run directory claimed as `bakesim run --out` does.
  Simulation(const PyScene& scene, int threads, const std::optional<fs::path>& out, bool force, bool quiet)
      : Simulation(scene, threads, quiet) {
    if (out) {
      RunDirectoryClaim claim = claim_new_run(*out, scene_.name, force);
      lock_ = std::move(claim.lock);
      log_->logger().info("bakesim {} run from Python ({} threads)", BAKESIM_VERSION, threads_);
      for (const auto& w : scene_.warnings) log_->logger().warn("{}", w);
      for (const auto& w : solver_->warnings()) log_->logger().warn("{}", w);
      log_->logger().info("{} particles; output in {}", solver_->particles().size(), out->string());
      output_ = std::make_unique<RunOutput>(*out, scene_, *solver_, *log_);
    } else {
      memory_ = std::make_unique<MemoryOutput>(scene_, *solver_);
    }
  }

  // Resumes the run in a run directory (as `bakesim run --resume DIR`).
  static std::unique_ptr<Simulation> resume_run(const fs::path& dir, int threads, bool quiet) {
    ResumePoint r = open_resume(dir);
    PyScene scene{std::make_shared<Scene>(std::move(r.scene)), r.scene_dir};
    auto sim = std::unique_ptr<Simulation>(new Simulation(scene, threads, quiet));
    sim->lock_ = std::move(r.lock);
    sim->output_ = std::make_unique<RunOutput>(dir, sim->scene_, *sim->solver_, *sim->log_);
    FrameLoopConfig cfg;
    for (const auto& why : r.refused) sim->log_->logger().warn("refused checkpoint: {}", why);
    sim->arena_.execute(
        [&] { resume_from(*sim->solver_, *sim->output_, cfg, r.checkpoint, r.checkpoint_file.string()); });
    sim->set_position(r.checkpoint);
    return sim;
  }

  // Resumes a checkpoint file written by checkpoint(), of `scene`, in memory.
  static std::unique_ptr<Simulation> resume_file(const fs::path& file, const PyScene& scene, int threads, bool quiet) {
    const Checkpoint c = decode_checkpoint(read_file(file), file.string());
    if (c.scene_fingerprint != scene_fingerprint(scene.scene->resolved))
      throw InputError(file.string(), "checkpoint of a different scene than " + scene.scene->file);
    PyScene at{scene.scene, c.scene_dir};
    auto sim = std::unique_ptr<Simulation>(new Simulation(at, threads, quiet));
    sim->memory_ = std::make_unique<MemoryOutput>(sim->scene_, *sim->solver_);
    sim->arena_.execute([&] { restore_checkpoint(*sim->solver_, c, file.string()); });
    sim->memory_->recorder().resume(c.follow_ids, {});
    sim->set_position(c);
    return sim;
  }

  const Scene& scene() const { return scene_; }
  Solver& solver() { return *solver_; }
  int threads() const { return threads_; }
  int frame() const { return info_.frame; }
  long steps() const { return info_.steps; }
  Real time() const { return solver_->time(); }
  Real bake_time() const { return scene_.oven.bake_time(solver_->time()); }
  std::optional<fs::path> directory() const {
    return output_ ? std::optional<fs::path>(output_->directory()) : std::nullopt;
  }

  // One step of the largest stable size; returns it.
  Real step() {
    Real dt = 0;
    arena_.execute([&] {
      dt = checked_stable_dt(*solver_, min_dt_, info_.steps);
      solver_->step(dt);
      solver_->synchronize();  // what Python reads next is at time()
    });
    info_.last_dt = dt;
    ++info_.steps;
    return dt;
  }

  // Steps until `duration` more seconds have passed, landing on the end exactly (as the frame loop does).
  long advance(Real duration) {
    if (!(duration >= 0) || !std::isfinite(duration))
      throw InputError("Simulation.advance", "expects a duration >= 0 s");
    const Real target = solver_->time() + duration;
    long steps = 0;
    arena_.execute([&] {
      while (solver_->time() < target - 1e-12) {
        const Real dt = landing_step(checked_stable_dt(*solver_, min_dt_, info_.steps), target - solver_->time());
        solver_->step(dt);
        info_.last_dt = dt;
        ++info_.steps;
        ++steps;
      }
      solver_->synchronize();
    });
    return steps;
  }

  // The frame loop up to `until` (the scene's end when NaN); `after_frame`
  // returning false stops it after that frame (with a checkpoint in a run directory).
  RunSummary run(Real until, const std::function<bool(const FrameInfo&)>& after_frame) {
    FrameLoopConfig cfg = frame_loop_config(scene_, *solver_);
    if (!std::isnan(until)) {
      if (!(until > 0) || !std::isfinite(until)) throw InputError("Simulation.run", "until must be a time > 0 s");
      cfg.end_time = until;
    }
    if (recorded()) {
      cfg.start_frame = info_.frame;
      cfg.start_steps = info_.steps;
      cfg.start_last_dt = info_.last_dt;
      cfg.start_frame_written = true;
    }
    auto keep_going = [&](const FrameInfo& info, const Solver&) {
      info_ = info;
      return after_frame ? after_frame(info) : true;
    };
    ProgressBar quiet_bar(stderr, false);
    RunSummary summary;
    arena_.execute([&] {
      if (output_) {
        BakeIntoOptions options;
        options.scene_dir = scene_dir_;
        options.cadence = checkpoint_cadence(scene_);
        options.after_frame = keep_going;
        summary = bake_into(*solver_, scene_, *output_, cfg, options, quiet_bar, log_->logger());
        if (!summary.stopped && info_.frame >= int(std::ceil(scene_.end_time * scene_.fps - 1e-9))) {
          for (const auto& line : output_->bake_summary()) log_->logger().info("bake: {}", line);
          output_->flush_log();
        }
      } else {
        cfg.after_frame = keep_going;
        summary = run_frames(*solver_, cfg, *memory_, quiet_bar, log_->logger());
      }
    });
    return summary;
  }

  // Writes a checkpoint of the current state to `file` (atomically).
  void checkpoint(const fs::path& file) const {
    const Checkpoint c =
        make_checkpoint(*solver_, scene_fingerprint(scene_.resolved), scene_dir_, info_, recorder().follow_ids());
    write_file_atomic(file, encode_checkpoint(c));
  }

  const FrameRecorder& recorder() const { return output_ ? output_->recorder() : memory_->recorder(); }
  bool recorded() const { return recorder().recorded() || info_.frame > 0; }
  const std::string& scene_dir() const { return scene_dir_; }
  std::vector<std::string> bake_summary() const { return recorder().bake_summary(); }

 private:
  // For the resumes: the solver only; the caller adds the output.
  Simulation(const PyScene& scene, int threads, bool quiet)
      : scene_(*scene.scene),
        scene_dir_(scene.scene_dir),
        min_dt_(scene_.resolved["solver"]["min_dt"].get<double>()),
        threads_(threads_of(threads)),
        arena_(threads_) {
    log_ = std::make_unique<RunLog>(!quiet);
    arena_.execute([&] { solver_ = make_solver(scene_); });
  }
  static int threads_of(int threads) {
    if (threads < 0) throw InputError("Simulation(threads)", "must be >= 0 (0: every core)");
    return threads > 0 ? threads : int(tbb::info::default_concurrency());
  }
  void set_position(const Checkpoint& c) {
    info_.frame = c.frame;
    info_.steps = c.steps;
    info_.last_dt = c.last_dt;
    info_.time = solver_->time();
  }

  Scene scene_;
  std::string scene_dir_;
  Real min_dt_;  // the scene's step floor (solver.min_dt)
  int threads_;
  tbb::task_arena arena_;  // this simulation's threads: two in one process do not share a limit
  std::unique_ptr<RunLog> log_;
  std::unique_ptr<Solver> solver_;
  RunDirectoryLock lock_;
  std::unique_ptr<RunOutput> output_;
  std::unique_ptr<MemoryOutput> memory_;
  FrameInfo info_;
};

py::dict results_of(const render::RunResults& r) {
  py::dict d;
  d["dir"] = r.dir.string();
  d["scene"] = r.scene_name;
  d["frames"] = r.frames;
  d["time_end_s"] = r.time_end;
  d["bake_minutes"] = r.bake_minutes;
  d["air_end_C"] = r.air_end;
  d["heat_in_kJ"] = r.heat_in_kilojoules;
  d["wall_s"] = r.wall_seconds;
  d["done_C"] = r.done_degc;
  py::dict bodies;
  for (const auto& b : r.bodies) {
    py::dict k;
    k["heated"] = b.heated;
    k["core_end_C"] = b.core_end;
    k["crust_end_C"] = b.crust_end;
    k["minutes_to_done"] = b.minutes_to_done;
    k["volume_ratio"] = b.volume_ratio;
    k["height_start_m"] = b.height_start;
    k["height_end_m"] = b.height_end;
    k["moisture_loss_percent"] = b.moisture_loss_percent;
    bodies[py::str(b.name)] = k;
  }
  d["bodies"] = bodies;
  return d;
}

// An exception type of the module whose instances carry `where` (file and key path) and `detail`.
void translate(const InputError& e, const py::object& type) {
  py::object exc = type(e.what());
  exc.attr("where") = e.where();
  exc.attr("detail") = e.detail();
  PyErr_SetObject(type.ptr(), exc.ptr());
}

}  // namespace

PYBIND11_MODULE(_bakesim, m) {
  m.doc() = "bakesim's library (the package bakesim wraps it; see docs/python.md)";
  m.attr("__version__") = BAKESIM_VERSION;

  static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<SimulationError> simulation_error(m, "SimulationError", error.ptr());
  static py::exception<IoError> io_error(m, "IoError", PyExc_OSError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      translate(e, input_error);
    } catch (const SimulationError& e) {
      PyErr_SetString(simulation_error.ptr(), e.what());
    } catch (const IoError& e) {
      PyErr_SetString(io_error.ptr(), e.what());
    } catch (const Error& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });

  py::class_<PyScene>(m, "Scene")
      .def_static(
          "load",
          [](const py::object& source, const py::object& overrides, bool preview, const std::string& base_dir) {
            return load(source, overrides, preview, base_dir);
          },
          py::arg("source"), py::arg("overrides") = py::none(), py::arg("preview") = false, py::arg("base_dir") = "")
      .def_property_readonly("name", [](const PyScene& s) { return s.scene->name; })
      .def_property_readonly("file", [](const PyScene& s) { return s.scene->file; })
      .def_property_readonly("solver", [](const PyScene& s) { return s.scene->solver_type; })
      .def_property_readonly("scene_dir", [](const PyScene& s) { return s.scene_dir; })
      .def_property_readonly("end_time", [](const PyScene& s) { return s.scene->end_time; })
      .def_property_readonly("fps", [](const PyScene& s) { return s.scene->fps; })
      .def_property_readonly("warnings", [](const PyScene& s) { return s.scene->warnings; })
      .def_property_readonly("notes", [](const PyScene& s) { return s.scene->notes; })
      .def_property_readonly("bodies",
                             [](const PyScene& s) {
                               std::vector<std::string> names;
                               for (const auto& b : s.scene->bodies) names.push_back(b.name);
                               return names;
                             })
      .def_property_readonly("probes",
                             [](const PyScene& s) {
                               std::vector<std::string> names;
                               for (const auto& p : s.scene->probes) names.push_back(p.name);
                               return names;
                             })
      .def_property_readonly("resolved", [](const PyScene& s) { return from_json(s.scene->resolved); })
      .def("bake_time", [](const PyScene& s, Real t) { return s.scene->oven.bake_time(t); })
      .def(
          "with_end_time",
          [](const PyScene& s, double end) {
            PyScene copy{std::make_shared<Scene>(*s.scene), s.scene_dir};
            set_end_time(*copy.scene, end);
            return copy;
          },
          py::arg("end_time"))
      .def("describe",
           [](const PyScene& s) {
             auto solver = make_solver(*s.scene);
             return describe(*s.scene, *solver);
           })
      .def("__repr__", [](const PyScene& s) {
        return fmt::format("<bakesim.Scene '{}' ({}, {:g} s)>", s.scene->name, s.scene->solver_type, s.scene->end_time);
      });

  py::class_<Simulation>(m, "Simulation")
      .def(py::init([](const PyScene& scene, int threads, const std::optional<fs::path>& out, bool force, bool quiet) {
             return std::make_unique<Simulation>(scene, threads, out, force, quiet);
           }),
           py::arg("scene"), py::arg("threads") = 0, py::arg("out") = py::none(), py::arg("force") = false,
           py::arg("quiet") = true)
      .def_static("_resume_run", &Simulation::resume_run, py::arg("dir"), py::arg("threads") = 0,
                  py::arg("quiet") = true)
      .def_static("_resume_file", &Simulation::resume_file, py::arg("file"), py::arg("scene"), py::arg("threads") = 0,
                  py::arg("quiet") = true)
      .def("step", &Simulation::step, py::call_guard<py::gil_scoped_release>())
      .def("advance", &Simulation::advance, py::arg("duration"), py::call_guard<py::gil_scoped_release>())
      .def(
          "_run",
          [](Simulation& sim, Real until, const py::object& on_frame) {
            // The callback and Ctrl-C (KeyboardInterrupt) need the interpreter: each
            // frame takes the GIL back briefly. An exception there stops the run
            // after that frame (a run directory gets its checkpoint) and is raised.
            std::optional<py::error_already_set> raised;
            std::function<bool(const FrameInfo&)> after = [&](const FrameInfo&) {
              py::gil_scoped_acquire gil;
              try {
                if (PyErr_CheckSignals() != 0) throw py::error_already_set();
                if (!on_frame.is_none()) {
                  const py::object r = on_frame();
                  if (!r.is_none() && !r.cast<bool>()) return false;
                }
                return true;
              } catch (py::error_already_set& e) {
                raised = std::move(e);
                return false;
              }
            };
            RunSummary s;
            {
              py::gil_scoped_release release;
              s = sim.run(until, after);
            }
            if (raised) throw std::move(*raised);
            py::dict d;
            d["steps"] = s.steps;
            d["frames"] = s.last_frame;
            d["wall_seconds"] = s.wall_seconds;
            d["particle_steps_per_second"] = s.particle_steps_per_second;
            d["stopped"] = s.stopped;
            return d;
          },
          py::arg("until"), py::arg("on_frame"))
      .def("checkpoint", &Simulation::checkpoint, py::arg("path"), py::call_guard<py::gil_scoped_release>())
      .def_property_readonly("time", &Simulation::time)
      .def_property_readonly("bake_time", &Simulation::bake_time)
      .def_property_readonly("frame", &Simulation::frame)
      .def_property_readonly("steps", &Simulation::steps)
      .def_property_readonly("threads", &Simulation::threads)
      .def_property_readonly("directory", &Simulation::directory)
      .def_property_readonly("solver", [](Simulation& s) { return s.solver().name(); })
      .def_property_readonly("dt_bound", [](Simulation& s) { return std::string(s.solver().active_dt_bound()); })
      .def_property_readonly("scene",
                             [](Simulation& s) {
                               return PyScene{std::make_shared<Scene>(s.scene()), s.scene_dir()};
                             })
      .def("max_stable_dt", [](Simulation& s) { return s.solver().max_stable_dt(); })
      .def_property_readonly("warnings", [](Simulation& s) { return s.solver().warnings(); })
      .def("bake_summary", &Simulation::bake_summary)
      .def("timers", [](Simulation& s) { return s.solver().timers().report(std::max(1L, s.steps())); })
      .def("frame_quantities", [](Simulation& s) { return s.solver().frame_quantities(); })
      .def(
          "sample",
          [](Simulation& s, const std::array<Real, 3>& x, const std::vector<std::string>& quantities) {
            return s.solver().sample(Vec3(x[0], x[1], x[2]), quantities);
          },
          py::arg("position"), py::arg("quantities"))
      // Particle attributes: the registry's names, units and kinds; arrays over its storage.
      .def("_attributes",
           [](Simulation& s) {
             std::vector<std::tuple<std::string, std::string, std::string, bool, bool>> out;
             const ParticleSet& ps = s.solver().particles();
             for (const auto& a : ps.scalars())
               out.emplace_back(a.info.name, a.info.unit, "scalar", a.info.exported, settable(a.info.name));
             for (const auto& a : ps.vectors())
               out.emplace_back(a.info.name, a.info.unit, "vector", a.info.exported, settable(a.info.name));
             for (const auto& a : ps.integers())
               out.emplace_back(a.info.name, a.info.unit, "integer", a.info.exported, false);
             return out;
           })
      .def("_view",
           [](py::object self, const std::string& name) -> py::array {
             Simulation& s = self.cast<Simulation&>();
             // particles_for_restore: the registry, mutable; only settable attributes come back writable.
             ParticleSet& ps = s.solver().particles_for_restore();
             for (auto& a : const_cast<std::deque<Attribute<Real>>&>(ps.scalars()))
               if (a.info.name == name) return view_of(a.data, 1, settable(name), self);
             for (auto& a : const_cast<std::deque<Attribute<Vec3>>&>(ps.vectors()))
               if (a.info.name == name) return view_of(a.data, 3, settable(name), self);
             for (auto& a : const_cast<std::deque<Attribute<std::int32_t>>&>(ps.integers()))
               if (a.info.name == name) return view_of(a.data, 1, false, self);
             throw py::key_error("no particle attribute '" + name + "'");
           })
      .def("_particle_count", [](Simulation& s) { return s.solver().particles().size(); })
      .def("_stats_columns", [](Simulation& s) { return s.recorder().columns(); })
      .def("_stats_row", [](Simulation& s) { return s.recorder().last_row(); })
      .def("_stats_units", [](Simulation& s) {
        std::vector<std::string> units;
        for (const auto& c : s.recorder().columns()) units.push_back(stats_column_unit(c, s.solver().particles()));
        return units;
      });

  m.def(
      "read_frame", [](const fs::path& ply) { return arrays_of(read_particle_frame(ply)); }, py::arg("path"),
      "A particle frame (frames/NNNNN.ply) as {attribute: numpy array}.");
  m.def(
      "read_stats",
      [](const fs::path& dir) {
        const render::Table t = render::read_csv(dir / "stats.csv");
        py::dict out;
        for (std::size_t k = 0; k < t.names.size(); ++k)
          out[py::str(t.names[k])] = py::array_t<double>(t.columns[k].size(), t.columns[k].data());
        return out;
      },
      py::arg("run_dir"), "A run directory's stats.csv as {column: numpy array}.");
  m.def(
      "run_results", [](const fs::path& dir) { return results_of(render::read_run_results(dir)); }, py::arg("run_dir"),
      "What a bake did, from its run directory's stats.csv (the numbers of sweep.csv).");
  m.def(
      "_mesh",
      [](const fs::path& dir, const std::string& method, const std::string& colour, std::optional<double> voxel_ratio,
         std::vector<int> frames, std::optional<std::pair<Real, Real>> range, bool vdb) {
        MeshSettings settings;
        settings.surface.method = surface::parse_surface_method(method);
        if (voxel_ratio) settings.surface.voxel_ratio = *voxel_ratio;  // mesh_run checks it and the range
        settings.colour = colour;
        settings.range = range;
        settings.vdb = vdb;
        const MeshRunResult r = mesh_run(dir, settings, std::move(frames));
        return std::make_tuple(r.frames, r.triangles, r.warnings);
      },
      py::arg("run_dir"), py::arg("method"), py::arg("colour"), py::arg("voxel_ratio"), py::arg("frames"),
      py::arg("range"), py::arg("vdb"), py::call_guard<py::gil_scoped_release>());
  m.def(
      "_render",
      [](const fs::path& dir, std::vector<int> frames, bool all_frames, const std::string& mode,
         const std::string& colour, bool movie, bool strip, const std::string& cut,
         std::optional<std::array<double, 3>> camera, std::optional<std::array<double, 3>> look_at,
         std::optional<Real> field_of_view, int turntable, std::optional<std::pair<Real, Real>> range,
         const std::string& method, std::optional<int> width, std::optional<int> height) {
        render::RenderRunOptions o;  // render_run checks the size and the range
        o.range = range;
        o.method = surface::parse_surface_method(method);
        o.width = width;
        o.height = height;
        if (camera) o.camera_position = Vec3((*camera)[0], (*camera)[1], (*camera)[2]);
        if (look_at) o.look_at = Vec3((*look_at)[0], (*look_at)[1], (*look_at)[2]);
        o.field_of_view = field_of_view;
        o.turntable = turntable;
        o.frames = std::move(frames);
        o.all_frames = all_frames;
        o.mode = mode;
        o.colour = colour;
        o.movie = movie;
        o.strip = strip;
        o.cut = cut;
        const auto r = render::render_run(dir, o);
        std::vector<fs::path> files = r.images;
        if (r.movie) files.push_back(*r.movie);
        if (r.strip) files.push_back(*r.strip);
        return std::make_pair(files, r.note);
      },
      py::arg("run_dir"), py::arg("frames"), py::arg("all_frames"), py::arg("mode"), py::arg("colour"),
      py::arg("movie"), py::arg("strip"), py::arg("cut"), py::arg("camera"), py::arg("look_at"),
      py::arg("field_of_view"), py::arg("turntable"), py::arg("range"), py::arg("method"), py::arg("width"),
      py::arg("height"), py::call_guard<py::gil_scoped_release>());
  m.def(
      "plot", [](const fs::path& dir) { return render::plot_run(dir); }, py::arg("run_dir"),
      py::call_guard<py::gil_scoped_release>(), "Plots of stats.csv into RUN_DIR/plots/; returns the files.");
  m.def(
      "_report",
      [](const fs::path& dir, std::vector<std::string> compare, const std::optional<fs::path>& output) {
        render::ReportOptions o;
        o.compare = std::move(compare);
        if (output) o.output = *output;
        o.generator = "bakesim (Python)";
        const auto r = render::write_report(dir, o);
        return std::make_pair(r.file, r.notes);
      },
      py::arg("run_dir"), py::arg("compare"), py::arg("output"), py::call_guard<py::gil_scoped_release>());

  // Sweeps: the grid and the table, as `bakesim sweep` makes them.
  m.def(
      "_sweep_points",
      [](const std::vector<std::string>& sets) {
        std::vector<SweepAxis> axes;
        for (const auto& s : sets) axes.push_back(parse_sweep_axis(s));
        std::vector<std::tuple<std::string, std::string, std::vector<std::string>, std::vector<std::string>>> out;
        for (const auto& p : sweep_points(axes)) out.emplace_back(p.label, p.directory, p.sets, p.values);
        return std::make_pair(out, axis_names(axes));
      },
      py::arg("sets"));
  m.def(
      "_write_sweep_outputs",
      [](const fs::path& dir, const std::vector<std::string>& sets,
         const std::vector<std::pair<std::string, std::string>>& runs) {
        std::vector<SweepAxis> axes;
        for (const auto& s : sets) axes.push_back(parse_sweep_axis(s));
        const std::vector<SweepPoint> points = sweep_points(axes);
        std::vector<render::SweepRun> table;
        for (const auto& p : points) {
          render::SweepRun r{p, "not run", std::nullopt};
          for (const auto& [directory, status] : runs)
            if (directory == p.directory) r.status = status;
          std::error_code ec;
          if (fs::is_regular_file(dir / "runs" / p.directory / "stats.csv", ec)) try {
              r.results = render::read_run_results(dir / "runs" / p.directory);
            } catch (const InputError&) {
            }
          table.push_back(std::move(r));
        }
        const auto o = render::write_sweep_outputs(dir, axes, table);
        return std::make_tuple(o.csv, o.markdown, o.plots, o.table);
      },
      py::arg("dir"), py::arg("sets"), py::arg("runs"));
}
