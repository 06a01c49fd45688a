#!/usr/bin/python3
"""Compares a run of scenes/tin-loaf-mpm.json with the tin loaf the
breadBakingFoam authors baked and measured
(validation-data/breadbakingfoam_own_experiment_1min.csv).

    tools/tin_loaf.py RUN_DIR [--json]

Prints, per thermocouple (point1 r 13 mm, 41 mm above the tin floor; point2
r 35 mm, 0.1 mm; point4 r 28 mm, 21 mm), the RMS error over the measured
minutes the run covers, the minute it reaches 90 degC against the measured
one, and its plateau (the mean over the last three measured minutes, which the
issue asks to lie between 97 and 100 degC); then the mean moisture loss
against the measured mean moisture (dry basis).
"""
import csv
import json
import math
import os
import sys

from zhang_loaf import interp  # tools/ is the script's directory

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
POINTS = ("point1", "point2", "point4")


def read_measured():
    with open(os.path.join(ROOT, "validation-data", "breadbakingfoam_own_experiment_1min.csv")) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return [r for r in rows if r["T_point1_avg_C"] != "nan"]


def first_reaching(ts, vs, level):
    return next((t for t, v in zip(ts, vs) if v >= level), float("nan"))


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    with open(os.path.join(sys.argv[1], "stats.csv")) as f:
        rows = list(csv.DictReader(f))
    minutes = [float(r["bake_time"]) / 60 for r in rows]
    measured = read_measured()
    m_t = [float(r["t_min"]) for r in measured]
    out = {"bake_minutes": minutes[-1]}
    covered = [t for t in m_t if t <= minutes[-1] + 1e-9]
    last3 = covered[-3:]
    for p in POINTS:
        key = "T_" + p + "_avg_C"
        m_v = [float(r[key]) for r in measured]
        model = [float(r[f"probe:{p}:temperature"]) for r in rows]
        errors = [interp(minutes, model, t) - v for t, v in zip(m_t, m_v) if t in covered]
        out[p] = {
            "rms": math.sqrt(sum(e * e for e in errors) / len(errors)),
            "minute_90C": first_reaching(minutes, model, 90.0),
            "measured_minute_90C": first_reaching(m_t, m_v, 90.0),
            "plateau": sum(interp(minutes, model, t) for t in last3) / len(last3),
            "measured_plateau": sum(v for t, v in zip(m_t, m_v) if t in last3) / len(last3),
            "hottest": max(model),
        }
    x0 = float(measured[0]["moisture_db_avg"])
    x_end = interp(m_t, [float(r["moisture_db_avg"]) for r in measured], minutes[-1])
    loss_key = next((k for k in rows[0] if k.startswith("moisture_loss_percent:")), None)
    out["moisture_loss_percent"] = float(rows[-1][loss_key]) if loss_key else float("nan")
    out["measured_moisture_loss_percent"] = 100 * (x0 - x_end) / x0
    if "--json" in sys.argv:
        print(json.dumps(out))
        return
    print(f"bake of {minutes[-1]:.1f} min; measured minutes compared: {covered[0]:.0f}-{covered[-1]:.0f}")
    for p in POINTS:
        o = out[p]
        print(f"{p}: RMS {o['rms']:5.1f} degC, 90 degC at {o['minute_90C']:5.1f} min (measured "
              f"{o['measured_minute_90C']:4.1f}), plateau {o['plateau']:5.1f} degC (measured {o['measured_plateau']:5.1f}; "
              f"target 97-100), hottest {o['hottest']:5.1f}")
    print(f"moisture loss {out['moisture_loss_percent']:.1f} % of the water (measured {out['measured_moisture_loss_percent']:.1f} %)")
    for t, r in zip(m_t, measured):
        if t > minutes[-1] + 1e-9:
            break
        cells = "  ".join(f"{p} {interp(minutes, [float(x[f'probe:{p}:temperature']) for x in rows], t):6.1f} "
                          f"({float(r['T_' + p + '_avg_C']):6.1f})" for p in POINTS)
        print(f"  {t:4.0f} min  {cells}")


if __name__ == "__main__":
    main()
