#!/usr/bin/python3
"""Torn crust of the bread loaf (scenes/bread-loaf*.json): the lattice neighbours
among the particles of its top crust at the start (within 7 mm of the surface of
the loaf's 4 cm cylinder, axis along z through y = 5 cm, top half, away from the
ends), and for each FRAME how many of those pairs are now more than twice the
particle spacing apart, and the largest stretch of a pair. The count of the
regression test MpmBakes.BreadLoafRisesItsCoreBakesThroughAndItsCrustTears.
  tools/crust_tears.py RUN_DIR FRAME [FRAME...]
The particle spacing is half the run's MPM cell. Uses Debian's /usr/bin/python3
with python3-numpy and python3-scipy."""
import argparse
import json
import os

import numpy as np
from scipy.spatial import cKDTree

from top_profile import read_ply


def positions(frame):
    return np.stack([frame['x'], frame['y'], frame['z']], axis=1).astype(float)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('run_dir')
    ap.add_argument('frames', nargs='+', type=int)
    args = ap.parse_args()
    with open(os.path.join(args.run_dir, 'scene.json')) as f:
        spacing = 0.5 * json.load(f)['solver']['mpm']['cell_size']
    first = read_ply(os.path.join(args.run_dir, 'frames', '00000.ply'))
    x = positions(first)
    crust = (np.hypot(x[:, 0], x[:, 1] - 0.05) > 0.033) & (x[:, 1] > 0.06) & (np.abs(x[:, 2]) < 0.07)
    pairs = cKDTree(x[crust]).query_pairs(1.05 * spacing, output_type='ndarray')
    rest = np.linalg.norm(x[crust][pairs[:, 0]] - x[crust][pairs[:, 1]], axis=1)
    ids = first['id'][crust][pairs]
    print(f'{len(pairs)} top-crust pairs, spacing {spacing * 1e3:g} mm')
    for k in args.frames:
        frame = read_ply(os.path.join(args.run_dir, 'frames', f'{k:05d}.ply'))
        index = np.full(frame['id'].max() + 1, -1)
        index[frame['id']] = np.arange(len(frame))
        y = positions(frame)
        d = np.linalg.norm(y[index[ids[:, 0]]] - y[index[ids[:, 1]]], axis=1)
        torn = int((d > 2 * spacing).sum())
        print(f'frame {k}: {torn} torn ({100 * torn / len(pairs):.1f}%), largest stretch x{(d / rest).max():.2f}')


if __name__ == '__main__':
    main()
