#!/usr/bin/env python3
"""A run's particle frames read into numpy: the coldest particle of each frame
(the core) against stats.csv, and the temperature across the last frame by
distance from the centre.

    PYTHONPATH=build/python /usr/bin/python3 examples/read_frames.py [RUN_DIR]
        without RUN_DIR: bakes a preview of scenes/bread-roll.json for it first
    ... --quick     the CI check: a short bake, and the frames must agree with stats.csv
"""
import argparse
import os
import sys

import numpy as np

import bakesim

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run_dir", nargs="?")
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    run_dir = args.run_dir
    if run_dir is None:
        run_dir = "out/bread-roll-frames"
        scene = bakesim.Scene.load(os.path.join(ROOT, "scenes", "bread-roll.json"), preview=True)
        if args.quick:
            scene = scene.with_end_time(scene.end_time / 12)  # a few frames are enough to compare
        print(f"baking {scene.name} into {run_dir}")
        bakesim.Simulation(scene, out=run_dir, force=True).run()
    stats = bakesim.read_stats(run_dir)
    body = next(c.split(":", 1)[1] for c in stats if c.startswith("core_temperature:"))
    worst = 0.0
    print(f"{'frame':>5} {'bake min':>8} {'coldest':>8} {'stats core':>10} {'hottest':>8}")
    for number, path in bakesim.frames(run_dir):
        frame = bakesim.read_frame(path)  # {attribute: numpy array}
        mine = frame["body_id"] == 0
        coldest = frame["temperature"][mine].min()
        row = number  # stats.csv has one row per frame, frame 0 first
        worst = max(worst, abs(coldest - stats[f"core_temperature:{body}"][row]))
        print(f"{number:5d} {stats['bake_time'][row] / 60:8.2f} {coldest:8.2f} "
              f"{stats[f'core_temperature:{body}'][row]:10.2f} {frame['temperature'][mine].max():8.2f}")
    last = bakesim.read_frame(bakesim.frames(run_dir)[-1][1])
    x, t = last["position"], last["temperature"]
    r = np.linalg.norm(x - x.mean(axis=0), axis=1)
    edges = np.linspace(0, r.max(), 7)
    print("temperature by distance from the centre, last frame:")
    for lo, hi in zip(edges, edges[1:]):
        inside = (r >= lo) & (r <= hi)
        if inside.any():
            print(f"  {lo * 1000:5.1f}-{hi * 1000:5.1f} mm: {t[inside].mean():6.1f} degC ({inside.sum()} particles)")
    print(f"largest difference between a frame's coldest particle and stats.csv: {worst:.2e} degC")
    return 0 if worst < 1e-3 else 1  # PLY holds float32


if __name__ == "__main__":
    sys.exit(main())
