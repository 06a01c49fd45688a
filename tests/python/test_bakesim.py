"""The Python module against the command line and itself (ctest: python_module).

Run by ctest with PYTHONPATH=build/python and BAKESIM_EXE=build/app/bakesim;
by hand: PYTHONPATH=build/python /usr/bin/python3 -m unittest tests/python/test_bakesim.py
"""
import json
import filecmp
import os
import shutil
import subprocess
import tempfile
import threading
import unittest

import numpy as np

import bakesim

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
COOKIE = os.path.join(ROOT, "scenes", "cookie-on-a-tray.json")
COOKIE_SPH = os.path.join(ROOT, "scenes", "cookie-on-a-tray-sph.json")
EXE = os.environ.get("BAKESIM_EXE", os.path.join(ROOT, "build", "app", "bakesim"))


def small_cookie(end=0.4, overrides=None, path=COOKIE):
    return bakesim.Scene.load(path, overrides=overrides, preview=True).with_end_time(end)


def without_wall_time(stats_csv):
    """stats.csv's lines without the wall_time column (the only one that depends on the clock)."""
    with open(stats_csv) as f:
        lines = f.read().splitlines()
    k = lines[0].split(",").index("wall_time")
    return [",".join(c for i, c in enumerate(line.split(",")) if i != k) for line in lines]


def png_size(path):
    """(width, height) from a PNG's IHDR chunk."""
    with open(path, "rb") as f:
        head = f.read(24)
    return int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big")


class Base(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="bakesim-py-")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)


class SetupWarnings(Base):
    def test_a_body_sampled_short_of_its_shape_is_warned_about_as_on_the_command_line(self):
        tin = os.path.join(ROOT, "scenes", "tin-loaf-sph.json")
        coarse = bakesim.Simulation(bakesim.Scene.load(tin, overrides={"solver.sph.spacing": 0.003}), threads=1)
        self.assertEqual(len(coarse.warnings), 1)
        self.assertIn("body 'loaf' is sampled as 94.2% of its volume", coarse.warnings[0])
        cli = subprocess.run([EXE, "validate", tin, "--set", "solver.sph.spacing=0.003"], capture_output=True, text=True)
        self.assertIn(coarse.warnings[0], cli.stderr)
        self.assertEqual(bakesim.Simulation(bakesim.Scene.load(tin), threads=1).warnings, [])


class SceneErrors(Base):
    def test_an_override_of_the_wrong_type_names_the_file_and_key_path(self):
        with self.assertRaises(bakesim.InputError) as c:
            bakesim.Scene.load(COOKIE, overrides={"environment.air_temperature": "hot"})
        self.assertEqual(c.exception.where, COOKIE + ": environment.air_temperature")
        self.assertIn("expected a number", c.exception.detail)
        self.assertIsInstance(c.exception, ValueError)

    def test_an_out_of_range_value_and_an_unknown_key(self):
        with self.assertRaises(bakesim.InputError) as c:
            bakesim.Scene.load(COOKIE, overrides={"bodies[0].shape.radius": -1})
        self.assertEqual(c.exception.where, COOKIE + ": bodies[0].shape.radius")
        with self.assertRaises(bakesim.InputError) as c:
            bakesim.Scene.load(COOKIE, overrides={"environment.air_temperatur": 1})
        self.assertIn("environment.air_temperatur", c.exception.where)
        self.assertIn("did you mean 'air_temperature'", c.exception.detail)

    def test_a_dict_scene_is_checked_like_a_file(self):
        with self.assertRaises(bakesim.InputError) as c:
            bakesim.Scene.load({"name": "x", "solver": {"type": "mpm"}, "bodies": 3})
        self.assertEqual(c.exception.where, "<dict>: bodies")

    def test_the_same_messages_as_the_command_line(self):
        r = subprocess.run([EXE, "validate", COOKIE, "--set", "bodies[0].shape.radius=-1"], capture_output=True,
                           text=True)
        self.assertEqual(r.returncode, 2)
        with self.assertRaises(bakesim.InputError) as c:
            bakesim.Scene.load(COOKIE, overrides={"bodies[0].shape.radius": -1})
        self.assertIn(str(c.exception), r.stderr)

    def test_a_missing_file(self):
        with self.assertRaises(bakesim.InputError):
            bakesim.Scene.load(os.path.join(self.tmp, "none.json"))


class SameAsTheCommandLine(Base):
    def check(self, path, threads):
        cli, py = os.path.join(self.tmp, "cli"), os.path.join(self.tmp, "py")
        subprocess.run([EXE, "run", path, "--preview", "--end-time", "0.4", "--threads", str(threads), "--out", cli,
                        "--quiet"], check=True)
        sim = bakesim.Simulation(small_cookie(0.4, path=path), threads=threads, out=py)
        sim.run()
        frames = sorted(os.listdir(os.path.join(cli, "frames")))
        self.assertGreaterEqual(len(frames), 4)
        self.assertEqual(frames, sorted(os.listdir(os.path.join(py, "frames"))))
        for f in frames:
            self.assertTrue(filecmp.cmp(os.path.join(cli, "frames", f), os.path.join(py, "frames", f), shallow=False),
                            f)
        for f in ("scene.json", "stats.units.csv", "particles.pvd"):
            self.assertTrue(filecmp.cmp(os.path.join(cli, f), os.path.join(py, f), shallow=False), f)
        self.assertEqual(without_wall_time(os.path.join(cli, "stats.csv")),
                         without_wall_time(os.path.join(py, "stats.csv")))
        # And the in-memory stats are stats.csv's numbers.
        stats = bakesim.read_stats(py)
        for column in ("time", "core_temperature:cookie", "volume:cookie"):
            np.testing.assert_allclose(sim.stats[column], stats[column], rtol=1e-8)  # stats.csv: 9 digits

    def test_mpm_byte_for_byte(self):
        self.check(COOKIE, 2)

    def test_sph_byte_for_byte(self):
        self.check(COOKIE_SPH, 2)


class Views(Base):
    def test_views_are_the_solvers_values_and_writes_reach_it(self):
        out = os.path.join(self.tmp, "run")
        sim = bakesim.Simulation(small_cookie(0.2), threads=2, out=out)
        sim.run()
        # The last frame's file and the arrays hold the same numbers (PLY stores float32).
        last = bakesim.read_frame(bakesim.frames(out)[-1][1])
        order = np.argsort(sim.particles["id"])
        file_order = np.argsort(last["id"])
        np.testing.assert_allclose(sim.particles["temperature"][order], last["temperature"][file_order], rtol=1e-6)
        np.testing.assert_allclose(sim.particles["position"][order], last["position"][file_order], rtol=1e-6)
        self.assertEqual(sim.particles.units["temperature"], "degC")
        self.assertEqual(sim.particles["velocity"].shape, (len(sim.particles), 3))
        # No copy: the same memory twice.
        self.assertTrue(np.shares_memory(sim.particles["temperature"], sim.particles["temperature"]))
        # Read-only where a write would break the solver.
        with self.assertRaises(ValueError):
            sim.particles["J"][:] = 1.0
        with self.assertRaises(ValueError):
            sim.particles["id"] = 0
        # Writes reach the solver: the whole cookie at 90 degC is what it steps from (below the boiling
        # point: the moist dough's boiling cap would take a hotter one back to 100 degC in the step).
        sim.particles["temperature"][:] = 90.0
        sim.particles["velocity"] = np.zeros((len(sim.particles), 3))
        before = sim.time
        sim.step()
        self.assertGreater(sim.time, before)
        t = sim.particles["temperature"]
        self.assertTrue(np.all(np.abs(t - 90.0) < 5.0), (t.min(), t.max()))
        self.assertAlmostEqual(sim.sample(sim.particles["position"][0], ["temperature"])[0], t[0], delta=5.0)


class Independent(Base):
    def stats_of(self, sim):
        return {k: v for k, v in sim.stats.items() if k != "wall_time"}

    def test_two_simulations_in_one_process_do_not_interfere(self):
        def mpm():
            return bakesim.Simulation(small_cookie(0.2), threads=2)

        def sph():
            return bakesim.Simulation(small_cookie(0.2, {"environment.air_temperature": 220}, COOKIE_SPH), threads=1)

        alone, hot_alone = mpm(), sph()
        alone.run()
        hot_alone.run()
        # Interleaved in one thread, then side by side in two threads (the steps release the GIL),
        # against the same steps taken alone.
        a, b, a_alone, b_alone = mpm(), sph(), mpm(), sph()
        for _ in range(10):
            a.advance(0.01)
            b.advance(0.01)
        ta = threading.Thread(target=a.run)
        tb = threading.Thread(target=b.run)
        ta.start(), tb.start()
        ta.join(), tb.join()
        for sim, ref in ((a, a_alone), (b, b_alone)):
            for _ in range(10):
                ref.advance(0.01)
            ref.run()
            self.assertEqual(sim.steps, ref.steps)
            self.assertEqual(sim.time, ref.time)
            for name in ("position", "temperature"):
                np.testing.assert_array_equal(sim.particles[name], ref.particles[name], name)
        c = bakesim.Simulation(small_cookie(0.2), threads=2)
        d = bakesim.Simulation(small_cookie(0.2, {"environment.air_temperature": 220}, COOKIE_SPH), threads=1)
        tc = threading.Thread(target=c.run)
        td = threading.Thread(target=d.run)
        tc.start(), td.start()
        tc.join(), td.join()
        self.assertEqual(self.stats_of(c).keys(), self.stats_of(alone).keys())
        for k in self.stats_of(alone):
            np.testing.assert_array_equal(self.stats_of(c)[k], self.stats_of(alone)[k], k)
            if k in self.stats_of(hot_alone):
                np.testing.assert_array_equal(self.stats_of(d)[k], self.stats_of(hot_alone)[k], k)
        for sim, ref in ((c, alone), (d, hot_alone)):
            for name in ("position", "temperature", "velocity"):
                np.testing.assert_array_equal(sim.particles[name], ref.particles[name], name)


class Checkpoints(Base):
    def test_a_checkpoint_file_goes_on_where_it_was(self):
        scene = small_cookie(0.4)
        whole = bakesim.Simulation(scene, threads=2)
        whole.run()
        half = bakesim.Simulation(scene, threads=2)
        half.run(until=0.2)
        ckpt = os.path.join(self.tmp, "half.ckpt")
        half.checkpoint(ckpt)
        with self.assertRaises(bakesim.InputError) as c:
            bakesim.Simulation.resume(ckpt)  # a file alone does not say its scene
        self.assertEqual(c.exception.where, ckpt)
        self.assertIn("needs the scene", c.exception.detail)
        with self.assertRaises(bakesim.InputError):
            bakesim.Simulation.resume(ckpt, scene=small_cookie(0.4, {"environment.air_temperature": 200}))
        resumed = bakesim.Simulation.resume(ckpt, scene=scene, threads=2)
        self.assertEqual(resumed.frame, half.frame)
        resumed.run()
        self.assertEqual(resumed.steps, whole.steps)
        for name in ("position", "temperature", "velocity"):
            np.testing.assert_array_equal(resumed.particles[name], whole.particles[name], name)
        np.testing.assert_array_equal(resumed.stats["core_temperature:cookie"],
                                      whole.stats["core_temperature:cookie"][half.frame + 1:])

    def test_a_stopped_run_directory_resumes_into_the_same_files(self):
        full, part = os.path.join(self.tmp, "full"), os.path.join(self.tmp, "part")
        bakesim.Simulation(small_cookie(0.4), threads=2, out=full).run()
        sim = bakesim.Simulation(small_cookie(0.4), threads=2, out=part)
        summary = sim.run(on_frame=lambda s: s.frame < 1)
        self.assertTrue(summary["stopped"])
        self.assertTrue(os.listdir(os.path.join(part, "checkpoints")))
        del sim  # lets go of the run directory's lock
        again = bakesim.Simulation.resume(part, threads=2)
        self.assertEqual(again.frame, 1)
        again.run()
        self.assertEqual(without_wall_time(os.path.join(full, "stats.csv")),
                         without_wall_time(os.path.join(part, "stats.csv")))
        self.assertEqual(len(again.stats["time"]), len(bakesim.read_stats(full)["time"]))

    def test_an_exception_in_the_callback_stops_with_a_checkpoint_and_is_raised(self):
        out = os.path.join(self.tmp, "run")
        sim = bakesim.Simulation(small_cookie(0.4), threads=2, out=out)

        def boom(s):
            if s.frame == 1:
                raise RuntimeError("stop here")

        with self.assertRaises(RuntimeError):
            sim.run(on_frame=boom)
        self.assertEqual(sim.frame, 1)
        self.assertTrue(os.path.exists(os.path.join(out, "checkpoints", "00001.ckpt")))


class RunDirectories(Base):
    def test_mesh_render_plot_report(self):
        out = os.path.join(self.tmp, "run")
        bakesim.Simulation(small_cookie(0.2), threads=2, out=out).run()
        meshed = bakesim.mesh(out, frames=[0])
        self.assertEqual(meshed, [0])
        self.assertTrue(os.path.exists(os.path.join(out, "meshes", "00000.ply")))
        self.assertFalse(os.path.exists(os.path.join(out, "meshes", "00000.vdb")))
        plain = open(os.path.join(out, "meshes", "00000.ply"), "rb").read()
        # The command line's --range, --vdb and --voxel: another colouring, a VDB beside the mesh.
        self.assertEqual(bakesim.mesh(out, frames=[0], colour="temperature", range=(20, 30), vdb=True), [0])
        self.assertTrue(os.path.getsize(os.path.join(out, "meshes", "00000.vdb")) > 0)
        self.assertNotEqual(open(os.path.join(out, "meshes", "00000.ply"), "rb").read(), plain)
        for bad in ({"range": (30, 20)}, {"voxel_ratio": 5}, {"voxel_ratio": 0.01}):
            with self.assertRaises(bakesim.InputError, msg=str(bad)):
                bakesim.mesh(out, frames=[0], **bad)
        # Small pictures (the size is the caller's, as with --width and --height).
        small = {"width": 160, "height": 90}
        pictures = bakesim.render(out, frames=[0], **small)
        self.assertTrue(pictures and all(os.path.exists(p) for p in pictures))
        self.assertEqual(png_size(pictures[0]), (160, 90))
        cut = bakesim.render(out, frames=[0], cut="z", **small)
        self.assertEqual([os.path.basename(p) for p in cut], ["mesh-browning-cut-z-00000.png"])
        ranged = bakesim.render(out, frames=[0], colour="temperature", range=(20, 40), method="wyvill", **small)
        self.assertEqual([os.path.basename(p) for p in ranged], ["mesh-temperature-00000.png"])
        self.assertNotEqual(open(ranged[0], "rb").read(), open(pictures[0], "rb").read())
        for bad in ({"width": 8}, {"height": 10000}, {"range": (40, 20)}, {"method": "marching"}):
            with self.assertRaises(bakesim.InputError, msg=str(bad)):
                bakesim.render(out, frames=[0], **{**small, **bad})
        turns = bakesim.render(out, frames=[0], turntable=2, camera=(0.1, 0.1, 0.2), field_of_view=30, **small)
        self.assertEqual([os.path.basename(p) for p in turns],
                         ["mesh-browning-00000-turn-000.png", "mesh-browning-00000-turn-001.png"])
        plots = bakesim.plot(out)
        self.assertTrue(plots and all(os.path.exists(p) for p in plots))
        page = bakesim.report(out)
        self.assertTrue(os.path.getsize(page) > 1000)
        results = bakesim.run_results(out)
        self.assertIn("cookie", results["bodies"])
        self.assertEqual(results["done_C"], 95.0)  # a sea-level scene: done at 95 degC


class Sweeps(Base):
    def test_a_2x2_sweep_on_a_two_worker_local_cluster_equals_four_single_runs(self):
        import dask.distributed as dd
        grid = {"environment.air_temperature": [160, 200], "environment.heat_transfer_coefficient": [20, 40]}
        with dd.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
                dd.Client(cluster) as client:
            table = bakesim.sweep(COOKIE, grid, client=client, out=os.path.join(self.tmp, "sweep"), end_time=0.2,
                                  preview=True)
        self.assertEqual(len(table), 4)
        self.assertTrue(os.path.exists(table.csv))
        for row in table:
            self.assertEqual(row["status"], "done")
            single = os.path.join(self.tmp, f"single-{row['air_temperature']}-{row['heat_transfer_coefficient']}")
            sim = bakesim.Simulation(small_cookie(0.2, {"environment.air_temperature": row["air_temperature"],
                                                        "environment.heat_transfer_coefficient":
                                                            row["heat_transfer_coefficient"]}), threads=1, out=single)
            sim.run()
            self.assertEqual(without_wall_time(os.path.join(single, "stats.csv")),
                             without_wall_time(os.path.join(row["dir"], "stats.csv")))
            self.assertEqual(row["core_end_C:cookie"], bakesim.run_results(single)["bodies"]["cookie"]["core_end_C"])
        # Hotter air, hotter core; more air movement, more water gone. (Not a hotter core: the fan oven's walls
        # radiate, so at h 20 the wet surface sits warmer than at 40, where it evaporates twice as fast: at
        # 200 degC, 4.8 min, core 73.4 against 71.7 degC.)
        cores = {(r["air_temperature"], r["heat_transfer_coefficient"]): r["core_end_C:cookie"] for r in table}
        losses = {(r["air_temperature"], r["heat_transfer_coefficient"]): r["moisture_loss_percent:cookie"]
                  for r in table}
        self.assertGreater(cores[(200, 40)], cores[(160, 40)])
        self.assertGreater(losses[(200, 40)], losses[(200, 20)])

    def test_a_point_keeps_its_finished_run_only_while_the_scene_is_the_same(self):
        # A sweep run again into the same directory keeps the runs it finished, but not one baked from a scene
        # that has changed since (an edited scene or preset): that one is baked again, as `bakesim sweep` does.
        from bakesim.sweep import run_point
        run_dir = os.path.join(self.tmp, "point")
        first = run_point(COOKIE, ["environment.air_temperature=160"], run_dir, end_time=0.05, preview=True)
        self.assertEqual(first["status"], "done")
        stats = os.path.join(run_dir, "stats.csv")
        written = os.stat(stats).st_mtime_ns
        again = run_point(COOKIE, ["environment.air_temperature=160"], run_dir, end_time=0.05, preview=True)
        self.assertEqual(again["status"], "done")
        self.assertEqual(os.stat(stats).st_mtime_ns, written)  # kept, not baked again
        changed = run_point(COOKIE, ["environment.air_temperature=200"], run_dir, end_time=0.05, preview=True)
        self.assertEqual(changed["status"], "done")
        with open(os.path.join(run_dir, "scene.json")) as f:
            self.assertEqual(json.load(f)["environment"]["air_temperature"], 200)
        self.assertTrue(os.path.isdir(os.path.join(run_dir, "previous")))  # the stale run moved aside, not deleted


if __name__ == "__main__":
    unittest.main()
