"""Parameter sweeps on a Dask cluster.

    table = bakesim.sweep("scenes/cookie-on-a-tray.json",
                          grid={"environment.air_temperature": [150, 180, 210]})

Each point of the grid (the Cartesian product of the lists, the first key
varying slowest, as `bakesim sweep --set`) is one bake in OUT/runs/NN-LABEL/,
run by a Dask worker through this module; the results come back as a table
(one row per run: the values, the status and the bake's key numbers) and as
OUT/sweep.csv, sweep.md and plots/ as `bakesim sweep` writes them. A run that
finished is kept, one that stopped with a checkpoint is resumed, when the
same sweep is run again. Workers on other machines need the scene files and
OUT on a file system they share (docs/python.md, "Sweeps on a cluster").
"""

import json as _json
import os as _os

import numpy as _np

from . import _bakesim
from . import _input_error  # bakesim defines it before it imports this module


def _value_text(value):
    """A grid value as `--set` reads it: JSON, or a plain word as it is."""
    return value if isinstance(value, str) else _json.dumps(value)


def _axis(path, values):
    if isinstance(values, (str, bytes)) or not hasattr(values, "__iter__"):
        values = [values]
    texts = [_value_text(v) for v in values]
    if not texts:
        raise _input_error(f"sweep grid: {path}", "has no values")
    return path + "=" + ",".join(texts)


def _same_scene(run_dir, loaded):
    """Whether the run in run_dir baked this very scene (its resolved scene.json, as the command line's sweep
    compares fingerprints): a run of an edited scene or preset is baked again, not kept or resumed."""
    try:
        with open(_os.path.join(run_dir, "scene.json")) as f:
            return _json.load(f) == loaded.resolved
    except (OSError, ValueError):
        return False


def _finished(run_dir, loaded):
    try:
        results = _bakesim.run_results(run_dir)
    except Exception:
        return False
    end_time = loaded.end_time
    return (results["frames"] > 0 and abs(results["time_end_s"] - end_time) <= 1e-9 * max(1.0, end_time)
            and _same_scene(run_dir, loaded))


def run_point(scene, sets, run_dir, threads=1, end_time=None, preview=False):
    """One point of a sweep, in the process that calls it (a Dask worker):
    keeps a finished run of this very scene, resumes a stopped one, else bakes
    it anew (a run of an edited scene or preset too). Returns
    {"directory", "status", "results"}; a failed bake is a status, not an
    exception, so the table is complete."""
    from . import Scene, Simulation  # on the worker
    name = _os.path.basename(run_dir)
    try:
        loaded = Scene.load(scene, list(sets), preview)
        if end_time is not None:
            loaded = loaded.with_end_time(end_time)
        if _finished(run_dir, loaded):
            status = "done"
        else:
            sim = None
            checkpoints = _os.path.join(run_dir, "checkpoints")
            if _os.path.isdir(checkpoints) and any(f.endswith(".ckpt") for f in _os.listdir(checkpoints)) \
                    and _same_scene(run_dir, loaded):
                try:
                    sim = Simulation.resume(run_dir, threads=threads)
                except _bakesim.InputError:
                    sim = None  # another scene's checkpoints (the grid changed): start over
            if sim is None:
                sim = Simulation(loaded, threads=threads, out=run_dir)
            summary = sim.run(until=loaded.end_time)
            status = "stopped" if summary["stopped"] else "done"
    except _bakesim.SimulationError as e:
        status = f"failed: {e}"
    except _bakesim.InputError as e:
        status = f"bad input: {e}"
    results = None
    try:
        results = _bakesim.run_results(run_dir)
    except Exception:
        pass
    return {"directory": name, "status": status, "results": results}


class SweepTable:
    """The sweep's results: `rows` (one dict per run), `columns`, column(name) as a numpy array,
    and the files written (csv, markdown, plots)."""

    def __init__(self, rows, columns, csv, markdown, plots, text):
        self.rows, self.columns, self.csv, self.markdown, self.plots, self.text = rows, columns, csv, markdown, plots, text

    def column(self, name):
        values = [row.get(name) for row in self.rows]
        try:
            return _np.array(values, dtype=float)
        except (TypeError, ValueError):
            return _np.array(values, dtype=object)

    def __len__(self):
        return len(self.rows)

    def __iter__(self):
        return iter(self.rows)

    def __repr__(self):
        return self.text


def _row(point, axis_names, outcome, run_dir):
    label, directory, sets, values = point
    row = {"run": directory}
    for name, value in zip(axis_names, values):
        try:
            row[name] = _json.loads(value)
        except ValueError:
            row[name] = value
    row["status"] = outcome["status"]
    row["dir"] = run_dir
    results = outcome["results"]
    if results:
        row["bake_minutes"] = results["bake_minutes"]
        row["heat_in_kJ"] = results["heat_in_kJ"]
        row["wall_s"] = results["wall_s"]
        for body, k in results["bodies"].items():
            for key in ("minutes_to_done", "core_end_C", "crust_end_C", "volume_ratio", "height_end_m",
                        "moisture_loss_percent"):
                row[f"{key}:{body}"] = k[key]
    return row


def sweep(scene, grid, client=None, out=None, threads=1, end_time=None, preview=False, sets=()):
    """Runs `scene` (a path, or a dict) once per point of `grid` ({key path:
    [values]}) on a dask.distributed `client` (default: a LocalCluster of one
    single-threaded worker per core, closed afterwards; or a scheduler
    address such as "tcp://host:8786"). `sets`: more "KEY=VALUE" for every
    run. `threads`: threads per run. Returns a SweepTable."""
    import dask.distributed as dd

    axes = [_axis(path, values) for path, values in grid.items()] + [str(s) for s in sets]
    if not axes:
        raise _input_error("sweep", "the grid is empty")
    points, axis_names = _bakesim._sweep_points(axes)
    if isinstance(scene, dict):
        source, name = scene, scene.get("name", "scene")
    else:
        source = _os.path.abspath(_os.fspath(scene))
        name = None
    # Every point is checked here before any runs: a bad value fails the sweep at once, naming it.
    first = None
    for point in points:
        loaded = _bakesim.Scene.load(source, list(point[2]), preview)
        first = first or loaded
    if name is None:
        name = first.name
    out = _os.path.abspath(_os.fspath(out) if out is not None else _os.path.join("out", f"{name}-sweep"))
    _os.makedirs(_os.path.join(out, "runs"), exist_ok=True)

    own = None
    if client is None or isinstance(client, str):
        if client is None:
            own = dd.LocalCluster(n_workers=max(1, (_os.cpu_count() or 1) // max(1, threads)),
                                  threads_per_worker=1, processes=True, dashboard_address=None)
            client = dd.Client(own)
        else:
            client = dd.Client(client)
        close = True
    else:
        close = False
    try:
        futures = [client.submit(run_point, source, list(p[2]), _os.path.join(out, "runs", p[1]), threads, end_time,
                                 preview, key=f"bakesim-{name}-{p[1]}", pure=False) for p in points]
        outcomes = client.gather(futures)
    finally:
        if close:
            client.close()
        if own is not None:
            own.close()
    csv, markdown, plots, text = _bakesim._write_sweep_outputs(out, axes, [(o["directory"], o["status"])
                                                                            for o in outcomes])
    rows = [_row(p, axis_names, o, _os.path.join(out, "runs", p[1])) for p, o in zip(points, outcomes)]
    columns = []
    for row in rows:
        for c in row:
            if c not in columns:
                columns.append(c)
    return SweepTable(rows, columns, csv, markdown, plots, text)


def main(argv=None):
    """`python3 -m bakesim sweep SCENE --set KEY=V1,V2 ... [--scheduler local|ADDRESS]`
    (bakesim.sweep from a shell; `bakesim sweep` hands its runs to bakesim.dask_runs). Exit status 0 when every run is done, 1 otherwise."""
    import argparse
    parser = argparse.ArgumentParser(prog="python3 -m bakesim sweep", description=main.__doc__)
    parser.add_argument("scene")
    parser.add_argument("--set", action="append", default=[], dest="sets", metavar="KEY=V1,V2,...")
    parser.add_argument("--scheduler", default="local", help="'local' (a LocalCluster) or a scheduler's address")
    parser.add_argument("--out")
    parser.add_argument("--threads", type=int, default=1, help="threads per run")
    parser.add_argument("--end-time", type=float)
    parser.add_argument("--preview", action="store_true")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    try:
        table = sweep(args.scene, {}, client=None if args.scheduler == "local" else args.scheduler, out=args.out,
                      threads=args.threads, end_time=args.end_time, preview=args.preview, sets=args.sets)
    except _bakesim.InputError as e:
        print(f"bakesim: error: {e}", file=__import__("sys").stderr)
        return 2
    if not args.quiet:
        print(table.text)
        print(f"sweep: {table.csv}")
    return 0 if all(row["status"] == "done" for row in table) else 1
