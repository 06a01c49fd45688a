#!/usr/bin/python3
"""Top-surface profile of a run's particle frames across X (or Z), for seeing
slits open and crusts crack: for each 4 mm bin, the highest particle (mm) among
those within --band metres of the middle of the other horizontal axis.
  tools/top_profile.py RUN_DIR FRAME [FRAME...] [--across z] [--band 0.04]
Uses Debian's /usr/bin/python3 with python3-numpy."""
import argparse
import numpy as np


def read_ply(path):
    """The vertex element of a binary little-endian PLY frame as a structured array."""
    types = {'float': '<f4', 'double': '<f8', 'int': '<i4', 'uint': '<u4', 'uchar': 'u1', 'char': 'i1',
             'short': '<i2', 'ushort': '<u2'}
    with open(path, 'rb') as f:
        if f.readline().strip() != b'ply':
            raise SystemExit(f'{path}: not a PLY file')
        props, count = [], 0
        while True:
            words = f.readline().decode('ascii').split()
            if not words:
                continue
            if words[0] == 'format' and words[1] != 'binary_little_endian':
                raise SystemExit(f'{path}: only binary little-endian PLY is read')
            if words[:2] == ['element', 'vertex']:
                count = int(words[2])
            elif words[0] == 'property':
                props.append((words[2], types[words[1]]))
            elif words[0] == 'end_header':
                break
        dtype = np.dtype(props)
        return np.frombuffer(f.read(count * dtype.itemsize), dtype=dtype, count=count)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('run_dir')
    ap.add_argument('frames', nargs='+', type=int)
    ap.add_argument('--across', choices=['x', 'z'], default='x', help='axis of the profile (default x)')
    ap.add_argument('--band', type=float, default=0.04, help='half-width of the band along the other axis (m)')
    ap.add_argument('--bin', type=float, default=0.004, help='bin width (m); keep it wider than the particle spacing')
    a = ap.parse_args()
    other = 'z' if a.across == 'x' else 'x'
    for frame in a.frames:
        d = read_ply(f'{a.run_dir}/frames/{frame:05d}.ply')
        centre = 0.5 * (d[other].min() + d[other].max())
        sel = np.abs(d[other] - centre) < a.band
        u, y = d[a.across][sel], d['y'][sel]
        edges = np.arange(u.min(), u.max() + a.bin, a.bin)
        idx = np.digitize(u, edges)
        tops = [f'{1000 * y[idx == i].max():6.1f}' if np.any(idx == i) else '     -' for i in range(1, len(edges))]
        print(f'frame {frame} ({a.across} from {1000 * edges[0]:.0f} mm in {1000 * a.bin:.0f} mm bins):')
        print(' '.join(tops))


if __name__ == '__main__':
    main()
