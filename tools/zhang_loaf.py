#!/usr/bin/python3
"""Compares a run of scenes/zhang-loaf-{mpm,sph}.json with the measured loaf of
Zhang, Datta & Mukherjee (2005) (validation-data/zhang2005_*.csv).

    tools/zhang_loaf.py RUN_DIR [--json]

Prints the figures the validation targets name (docs/validation.md): the centre
temperature's RMS error over 3-13 min, the bake minute it reaches 95 degC, the
hottest centre while its moisture is above 0.3 kg/kg, the side probe's RMS error
(2 mm under the surface, 1-13 min), and the weight loss at 15 min against the
measured moisture curve (dry basis converted to a share of the dough mass).
"""
import csv
import json
import math
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def read_measured(name):
    with open(os.path.join(ROOT, "validation-data", name)) as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
    return [(float(a), float(b)) for a, b in rows[1:]]


def read_run(run):
    with open(os.path.join(run, "stats.csv")) as f:
        rows = list(csv.DictReader(f))
    return rows


def interp(xs, ys, x):
    if x <= xs[0]:
        return ys[0]
    for i in range(1, len(xs)):
        if x <= xs[i]:
            f = (x - xs[i - 1]) / (xs[i] - xs[i - 1])
            return ys[i - 1] + f * (ys[i] - ys[i - 1])
    return ys[-1]


def rms(model_t, model_v, measured, lo, hi):
    errors = [interp(model_t, model_v, t) - v for t, v in measured if lo <= t <= hi and t <= model_t[-1]]
    return math.sqrt(sum(e * e for e in errors) / len(errors)) if errors else float("nan")


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    rows = read_run(sys.argv[1])
    minutes = [float(r["bake_time"]) / 60 for r in rows]
    centre = [float(r["probe:centre:temperature"]) for r in rows]
    side = [float(r["probe:side:temperature"]) for r in rows]
    moist = [float(r["probe:centre:moisture"]) for r in rows] if "probe:centre:moisture" in rows[0] else None
    loss_key = next((k for k in rows[0] if k.startswith("weight_loss_percent:")), None)
    loss = [float(r[loss_key]) for r in rows] if loss_key else None
    measured_centre = read_measured("zhang2005_centre_temperature.csv")
    measured_side = read_measured("zhang2005_surface_temperature.csv")
    measured_moisture = read_measured("zhang2005_total_moisture.csv")
    x0 = measured_moisture[0][1]
    measured_loss = [(t, 100 * (x0 - x) / (1 + x0)) for t, x in measured_moisture]
    t95 = next((t for t, v in zip(minutes, centre) if v >= 95), float("nan"))
    hottest_moist = max((v for v, x in zip(centre, moist) if x > 0.3), default=float("nan")) if moist else float("nan")
    out = {
        "centre_rms_3_13_min": rms(minutes, centre, measured_centre, 3, 13),
        "centre_95C_minute": t95,
        "centre_hottest_while_moist": hottest_moist,
        "side_rms_1_13_min": rms(minutes, side, measured_side, 1, 13),
        "weight_loss_15_min_percent": interp(minutes, loss, 15) if loss else float("nan"),
        "measured_weight_loss_15_min_percent": interp([t for t, _ in measured_loss], [v for _, v in measured_loss], 15),
        "bake_minutes": minutes[-1],
    }
    if "--json" in sys.argv:
        print(json.dumps(out))
        return
    print(f"centre RMS error 3-13 min   {out['centre_rms_3_13_min']:.1f} degC   (target <= 5)")
    print(f"centre reaches 95 degC at   {out['centre_95C_minute']:.1f} min      (measured 9.8, target 9.8 +- 1.5)")
    print(f"hottest centre while moist  {out['centre_hottest_while_moist']:.1f} degC   (target <= 100.5 while X > 0.3)")
    print(f"side RMS error 1-13 min     {out['side_rms_1_13_min']:.1f} degC   (target <= 10)")
    print(f"weight loss at 15 min       {out['weight_loss_15_min_percent']:.1f} %      "
          f"(measured {out['measured_weight_loss_15_min_percent']:.1f}, target 9 +- 2)")
    for t in range(0, int(minutes[-1]) + 1):
        print(f"  {t:2d} min  centre {interp(minutes, centre, t):6.1f} (measured {interp(*zip(*measured_centre), t):6.1f})"
              f"  side {interp(minutes, side, t):6.1f} (measured {interp(*zip(*measured_side), t):6.1f})"
              + (f"  loss {interp(minutes, loss, t):5.1f} % (measured {interp(*zip(*measured_loss), t):4.1f})" if loss else ""))


if __name__ == "__main__":
    main()
