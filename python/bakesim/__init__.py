"""bakesim from Python: scenes, simulations with numpy views of their particles,
run directories (frames, meshes, pictures, plots, reports) and sweeps on Dask.

    import bakesim
    scene = bakesim.Scene.load("scenes/cookie-on-a-tray.json",
                               overrides={"environment.air_temperature": 200})
    sim = bakesim.Simulation(scene, threads=2, out="out/cookie-200")
    sim.run(on_frame=lambda s: print(s.bake_time / 60, s.bodies["cookie"]["core_temperature"][-1]))

The API is described in docs/python.md. The library underneath is the same
as the command line's (bakesim._bakesim): the same validation, messages and
files; a run with `out=` writes what `bakesim run` writes.
"""

import math as _math
import os as _os

import numpy as _np

from . import _bakesim
from ._bakesim import Error, InputError, IoError, Scene, SimulationError, read_frame, read_stats, run_results

__version__ = _bakesim.__version__

__all__ = [
    "Scene", "Simulation", "Particles", "Error", "InputError", "SimulationError", "IoError",
    "read_frame", "read_stats", "frames", "run_results", "mesh", "render", "plot", "report", "sweep",
]


def _input_error(where, detail):
    """An InputError as the library raises it: "where: detail", with .where and .detail."""
    error = InputError(f"{where}: {detail}")
    error.where, error.detail = where, detail
    return error


def _as_scene(scene, overrides=None, preview=False):
    if isinstance(scene, Scene):
        if overrides or preview:
            raise ValueError("overrides and preview apply when a scene is loaded: Scene.load(path, overrides=...)")
        return scene
    if isinstance(scene, dict):
        return Scene.load(scene, overrides, preview)
    return Scene.load(_os.fspath(scene), overrides, preview)


class Particles:
    """The particle attributes of a simulation by name, as numpy arrays over
    the solver's own storage (no copy). temperature, velocity and water_mass
    are writable (the state the solver goes on from); every other attribute
    is read-only. A step may reorder the particles (both solvers sort them
    for locality): take the arrays again after stepping, and follow a
    particle by its "id"."""

    def __init__(self, sim):
        self._sim = sim

    def _table(self):
        return {name: (unit, kind, exported, writable)
                for name, unit, kind, exported, writable in self._sim._attributes()}

    def keys(self):
        return list(self._table())

    def __iter__(self):
        return iter(self.keys())

    def __contains__(self, name):
        return name in self._table()

    def __len__(self):
        return self._sim._particle_count()

    def __getitem__(self, name):
        return self._sim._view(name)

    def __setitem__(self, name, values):
        view = self._sim._view(name)
        if not view.flags.writeable:
            raise ValueError(f"particle attribute '{name}' is read-only (writable: {', '.join(self.writable)})")
        _np.copyto(view, values)

    @property
    def units(self):
        """{name: SI unit} ("degC" for temperatures, "" for ratios and integers)."""
        return {name: info[0] for name, info in self._table().items()}

    @property
    def writable(self):
        return [name for name, info in self._table().items() if info[3]]

    def __repr__(self):
        return f"<bakesim.Particles: {len(self)} particles, {', '.join(self.keys())}>"


def _split_columns(columns, history):
    """stats columns into {"probes": {probe: {quantity: array}}, "bodies": {body: {column: array}}}."""
    stats = {c: _np.array([row[k] for row in history], dtype=float) for k, c in enumerate(columns)}
    probes, bodies = {}, {}
    for c, values in stats.items():
        if c.startswith("probe:"):
            _, probe, quantity = c.split(":", 2)
            probes.setdefault(probe, {})[quantity] = values
        elif ":" in c:
            column, body = c.split(":", 1)
            bodies.setdefault(body, {})[column] = values
    return stats, probes, bodies


class Simulation:
    """One simulation: its scene, its solver and (with out=) its run directory.

    Simulation(scene, threads=0, out=None, force=False, quiet=True)
        scene   a Scene, a scene file's path or a scene as a dict
        threads how many threads its steps use (0: every core); each
                simulation has its own, so several can run side by side
        out     a run directory: run() writes frames, stats.csv,
                checkpoints and log.txt there exactly as `bakesim run --out`
        force   as `bakesim run --force`
        quiet   False: the scene's warnings go to stderr too
    """

    def __init__(self, scene, threads=0, out=None, force=False, quiet=True, *, _native=None):
        if _native is None:
            scene = _as_scene(scene)
            _native = _bakesim.Simulation(scene, threads, None if out is None else _os.fspath(out), force, quiet)
        self._sim = _native
        self._history = []
        self.particles = Particles(self._sim)

    @classmethod
    def resume(cls, path, scene=None, threads=0, quiet=True):
        """Goes on from a checkpoint. `path` a run directory (its newest valid
        checkpoint; the run continues into it as `bakesim run --resume`), or a
        file written by checkpoint(), with the scene it was made from."""
        path = _os.fspath(path)
        if _os.path.isdir(path):
            sim = cls(None, _native=_bakesim.Simulation._resume_run(path, threads, quiet))
            stats = read_stats(path)
            columns = list(stats)
            sim._history = [[stats[c][i] for c in columns] for i in range(len(stats[columns[0]]))] if columns else []
            return sim
        if scene is None:
            raise _input_error(path, "a checkpoint file needs the scene it was made from: "
                                     "Simulation.resume(path, scene=...)")
        return cls(None, _native=_bakesim.Simulation._resume_file(path, _as_scene(scene), threads, quiet))

    # --- stepping -----------------------------------------------------------
    def step(self):
        """One step of the largest stable size (no frame is written); returns the step, s."""
        return self._sim.step()

    def advance(self, duration):
        """Steps for `duration` seconds, landing on the end exactly; returns the number of steps."""
        return self._sim.advance(duration)

    def run(self, until=None, on_frame=None):
        """The frame loop from where the simulation is to `until` seconds (the
        scene's end by default): frames at the scene's fps, each recorded in
        stats (and written, with out=). on_frame(sim) is called after each
        frame; returning False stops the run there (a run directory gets a
        checkpoint). Ctrl-C stops after the frame, then raises. Steps run
        without the GIL. Returns {"steps", "frames", "wall_seconds", ...}."""

        def after_frame():
            self._history.append(self._sim._stats_row())
            if on_frame is not None:
                return on_frame(self)
            return None

        return self._sim._run(_math.nan if until is None else float(until), after_frame)

    def checkpoint(self, path):
        """Writes the whole state to `path`; Simulation.resume(path, scene) goes on from it."""
        self._sim.checkpoint(_os.fspath(path))

    # --- what it is and did --------------------------------------------------
    time = property(lambda self: self._sim.time, doc="simulated time, s")
    bake_time = property(lambda self: self._sim.bake_time, doc="time in the oven (the bake clock), s")
    frame = property(lambda self: self._sim.frame, doc="the last frame recorded")
    steps = property(lambda self: self._sim.steps)
    threads = property(lambda self: self._sim.threads)
    solver = property(lambda self: self._sim.solver)
    scene = property(lambda self: self._sim.scene)
    directory = property(lambda self: self._sim.directory, doc="the run directory (None without out=)")
    warnings = property(lambda self: self._sim.warnings,
                        doc="what the solver's set-up found doubtful (a body its particle lattice fills short)")

    @property
    def stats(self):
        """stats.csv's columns as {column: numpy array}, one value per frame recorded."""
        return _split_columns(self._sim._stats_columns(), self._history)[0]

    @property
    def probes(self):
        """{probe: {quantity: numpy array per frame}}."""
        return _split_columns(self._sim._stats_columns(), self._history)[1]

    @property
    def bodies(self):
        """{body: {"core_temperature": ..., "crust_temperature": ..., "volume": ..., ...}} per frame."""
        return _split_columns(self._sim._stats_columns(), self._history)[2]

    @property
    def units(self):
        """The unit of each stats column (as stats.units.csv)."""
        return dict(zip(self._sim._stats_columns(), self._sim._stats_units()))

    def sample(self, position, quantities):
        """Interpolated quantities at a point (NaN where no particle is near)."""
        return self._sim.sample(tuple(position), list(quantities))

    def bake_summary(self):
        return self._sim.bake_summary()

    def timers(self):
        """Time per step by phase, as the run log prints it."""
        return self._sim.timers()

    def __repr__(self):
        return (f"<bakesim.Simulation {self.scene.name!r} ({self.solver}, {len(self.particles)} particles, "
                f"t = {self.time:.6g} s, frame {self.frame})>")


# --- run directories ----------------------------------------------------------
def frames(run_dir):
    """[(frame number, path of frames/NNNNN.ply)], in order."""
    directory = _os.path.join(_os.fspath(run_dir), "frames")
    out = []
    for name in sorted(_os.listdir(directory)):
        stem, ext = _os.path.splitext(name)
        if ext == ".ply" and stem.isdigit():
            out.append((int(stem), _os.path.join(directory, name)))
    return out


def mesh(run_dir, method="levelset", colour="browning", frames=None, voxel_ratio=None, range=None, vdb=False):
    """Surface meshes of a run's frames into RUN_DIR/meshes/ (as `bakesim mesh`); returns the frames meshed.

    range: (low, high) of the colour quantity (--range); voxel_ratio: voxel size in particle spacings, 0.1-2
    (--voxel); vdb: also NNNNN.vdb per frame (--vdb)."""
    done, triangles, warnings = _bakesim._mesh(_os.fspath(run_dir), method, colour, voxel_ratio, list(frames or []),
                                               None if range is None else (float(range[0]), float(range[1])),
                                               bool(vdb))
    for w in warnings:
        import warnings as _warnings
        _warnings.warn(w)
    return done


def render(run_dir, frames=None, all_frames=False, mode="mesh", colour=None, movie=False, strip=False, cut="",
           camera=None, look_at=None, field_of_view=None, turntable=0, range=None, method="levelset", width=None,
           height=None):
    """Pictures into RUN_DIR/render/ as `bakesim render` draws them; returns the files written.

    colour: None for the scene's render.colour (else browning); range: (low, high) of the colour quantity
    (--range; None: the scene's render.range, else the quantity's own); cut: "z" or "x=0.01" (--cut);
    method: "levelset" or "wyvill" (--method); width, height: pixels (None: the scene's render size, 1280 x 720);
    camera, look_at: (x, y, z) in metres; field_of_view: degrees;
    turntable: N views of each frame around the vertical axis."""
    files, note = _bakesim._render(_os.fspath(run_dir), list(frames or []), all_frames, mode, colour or "", movie, strip,
                                   cut, camera, look_at, field_of_view, int(turntable),
                                   None if range is None else (float(range[0]), float(range[1])), method,
                                   None if width is None else int(width), None if height is None else int(height))
    return files


plot = _bakesim.plot


def report(run_dir, compare=(), output=None):
    """The HTML bake report (as `bakesim report`); returns its path."""
    path, notes = _bakesim._report(_os.fspath(run_dir), [_os.fspath(c) for c in compare],
                                   None if output is None else _os.fspath(output))
    return path


from .sweep import sweep  # noqa: E402  (uses the names above)
