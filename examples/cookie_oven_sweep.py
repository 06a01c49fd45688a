#!/usr/bin/env python3
"""The cookie of scenes/cookie-on-a-tray.json baked at three oven temperatures
on a Dask cluster, and what each bake did.

    PYTHONPATH=build/python /usr/bin/python3 examples/cookie_oven_sweep.py
        on a LocalCluster (one worker per core) into out/cookie-oven-sweep/
    ... --scheduler tcp://HOST:8786
        on a running cluster (docs/python.md, "Sweeps on a cluster")
    ... --quick
        the CI check: previews (2x coarser), two workers; a hotter oven must
        give a hotter core, and each run's stats.csv must exist
"""
import argparse
import os
import sys

import bakesim

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "scenes", "cookie-on-a-tray.json")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--scheduler", help="a Dask scheduler's address (default: a LocalCluster)")
    parser.add_argument("--out", default="out/cookie-oven-sweep")
    args = parser.parse_args()
    client = args.scheduler
    cluster = None
    if client is None and args.quick:
        import dask.distributed as dd
        cluster = dd.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
        client = dd.Client(cluster)
    try:
        table = bakesim.sweep(SCENE, grid={"environment.air_temperature": [150, 180, 210]}, client=client,
                              out=args.out, preview=args.quick)
    finally:
        if cluster is not None:
            client.close()
            cluster.close()
    print(table.text)
    for row in table:
        print(f"{row['air_temperature']:>4} degC oven: core {row['core_end_C:cookie']:.1f} degC, "
              f"95 degC after {row['minutes_to_done:cookie']:.1f} min, rise x{row['volume_ratio:cookie']:.2f}, "
              f"{row['moisture_loss_percent:cookie']:.1f} % of its water gone ({row['status']})")
    print(f"table: {table.csv}")
    cores = table.column("core_end_C:cookie")
    ok = all(r["status"] == "done" for r in table) and all(a < b for a, b in zip(cores, cores[1:]))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
