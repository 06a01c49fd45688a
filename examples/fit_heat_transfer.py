#!/usr/bin/env python3
"""Fits the oven's heat-transfer coefficient h of the Zhang et al. (2005) loaf
(scenes/zhang-loaf-unrisen-mpm.json) to a centre-temperature curve with scipy.optimize.

    PYTHONPATH=build/python /usr/bin/python3 examples/fit_heat_transfer.py
        fits h to the measured centre temperature (validation-data/zhang2005_centre_temperature.csv)
        at the preview resolution (6 mm cells); --cell-size 0.003 for the scene's own
    ... --quick
        the check CI runs (9 mm cells): a target curve baked with h = 14 W/(m^2 K) is fitted
        from the range 5-30 and must give h back within 2 % and the curve within 0.3 degC RMS

Each evaluation is one bake in memory (no files): bakesim.Simulation on the scene with
environment.heat_transfer_coefficient overridden, the centre probe's temperature
against bake minutes, interpolated at the target's times.
"""
import argparse
import os
import sys

import numpy as np
from scipy.optimize import minimize_scalar

import bakesim

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "scenes", "zhang-loaf-unrisen-mpm.json")
MEASURED = os.path.join(ROOT, "validation-data", "zhang2005_centre_temperature.csv")


def centre_curve(h, cell_size, threads):
    """Bake minutes and centre temperature (degC) of the loaf baked with coefficient h."""
    scene = bakesim.Scene.load(SCENE, overrides={"environment.heat_transfer_coefficient": h,
                                                 "solver.mpm.cell_size": cell_size})
    sim = bakesim.Simulation(scene, threads=threads)
    sim.run()
    return sim.stats["bake_time"] / 60.0, sim.probes["centre"]["temperature"]


def read_measured(path):
    rows = [line.split(",") for line in open(path) if line.strip() and not line.startswith("#")]
    data = np.array([[float(a), float(b)] for a, b in rows[1:]])
    return data[:, 0], data[:, 1]


def fit(t_target, T_target, cell_size, threads, bounds=(5.0, 30.0)):
    evaluations = []

    def rms(h):
        minutes, centre = centre_curve(h, cell_size, threads)
        inside = t_target <= minutes[-1]
        err = float(np.sqrt(np.mean((np.interp(t_target[inside], minutes, centre) - T_target[inside]) ** 2)))
        evaluations.append((h, err))
        print(f"  h = {h:7.3f} W/(m^2 K): centre RMS {err:6.3f} degC", flush=True)
        return err

    best = minimize_scalar(rms, bounds=bounds, method="bounded", options={"xatol": 0.02})
    return best.x, best.fun, len(evaluations)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="fit a synthetic curve of known h (the CI check)")
    parser.add_argument("--cell-size", type=float, default=None,
                        help="MPM cell size, m (default 0.006; --quick 0.009; the scene's: 0.003)")
    parser.add_argument("--threads", type=int, default=0)
    args = parser.parse_args()
    if args.cell_size is None:
        # The synthetic check recovers h at any resolution: CI runs it on the coarsest grid that holds the loaf.
        args.cell_size = 0.009 if args.quick else 0.006
    if args.quick:
        true_h = 14.0
        t_target, T_target = centre_curve(true_h, args.cell_size, args.threads)
        print(f"target: the loaf baked with h = {true_h} W/(m^2 K), {len(t_target)} frames")
    else:
        t_target, T_target = read_measured(MEASURED)
        print(f"target: {os.path.relpath(MEASURED, ROOT)}, {len(t_target)} points")
    h, err, n = fit(t_target, T_target, args.cell_size, args.threads)
    print(f"fitted h = {h:.3f} W/(m^2 K) after {n} bakes; centre RMS {err:.3f} degC")
    if args.quick:
        ok = abs(h - true_h) <= 0.02 * true_h and err <= 0.3
        print("recovered" if ok else "NOT recovered")
        return 0 if ok else 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
