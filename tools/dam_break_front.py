#!/usr/bin/python3
"""Compares a dam-break run's surge front with the experiments.

Usage: tools/dam_break_front.py RUN_DIR [VALIDATION_DIR]

Reads RUN_DIR/stats.csv (front = max_x, the column's back wall at x = 0,
a = 0.146 m) and prints Z = x/a against Martin & Moyce (1952) and
Koshizuka & Oka (1996) at the experiments' times T = t sqrt(2g/a).
"""
import csv
import math
import os
import sys

A = 0.146
G = 9.81


def experiment(path):
    rows = []
    with open(path) as f:
        lines = [l for l in f if not l.startswith("#")]
    for r in csv.DictReader(lines):
        rows.append((float(r["T"]), float(r["Z"])))
    return sorted(rows)


def main():
    run = sys.argv[1]
    data_dir = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "validation-data")
    with open(os.path.join(run, "stats.csv")) as f:
        stats = list(csv.DictReader(f))
    scale = math.sqrt(2 * G / A)
    ts = [float(r["time"]) * scale for r in stats]
    zs = [float(r["max_x"]) / A for r in stats]

    def simulated(T):
        for i in range(1, len(ts)):
            if ts[i] >= T:
                return zs[i - 1] + (zs[i] - zs[i - 1]) * (T - ts[i - 1]) / (ts[i] - ts[i - 1])
        return None

    print("| experiment | T | Z measured | Z simulated | difference |")
    print("|---|---|---|---|---|")
    worst = 0.0
    for name, fname in (("Martin & Moyce 1952", "dambreak_martin_moyce1952.csv"),
                        ("Koshizuka & Oka 1996", "dambreak_koshizuka_oka1996.csv")):
        for T, Z in experiment(os.path.join(data_dir, fname)):
            if T < 0.5 or T > 2.5:
                continue
            z = simulated(T)
            if z is None:
                continue
            err = (z - Z) / Z
            if name.startswith("Martin"):
                worst = max(worst, abs(err))
            print("| %s | %.3f | %.3f | %.3f | %+.1f%% |" % (name, T, Z, z, 100 * err))
    print("\nlargest difference from Martin & Moyce for T in [0.5, 2.5]: %.1f%%" % (100 * worst))


if __name__ == "__main__":
    main()
