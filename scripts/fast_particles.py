#!/usr/bin/env python3
"""Where a DFSPH run's fastest particles are, frame by frame (issue 15, the step count).

The CFL step of "dfsph" follows the largest speed of the fluid; this reads a cache (written with a
high output.fps to see between steps) and prints per frame the speed percentiles, and for the
fastest particles where they are (distance to each of a box tank's walls), how many fluid
neighbours and boundary particles lie within the kernel support, and their density.

    scripts/fast_particles.py CACHE.h5 --tank -2 0 -0.75 2 3 0.75 --support 0.04 [--top 5]
"""
import argparse

import h5py
import numpy as np
from scipy.spatial import cKDTree


def frames(f):
    names = sorted((k for k in f if k.startswith("Step#")), key=lambda k: int(k.split("#")[1]))
    for k in names:
        yield f[k]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("cache")
    ap.add_argument("--tank", type=float, nargs=6, required=True, metavar="LO/HI",
                    help="the tank's inner box: xlo ylo zlo xhi yhi zhi (m)")
    ap.add_argument("--support", type=float, required=True, help="kernel support h (m)")
    ap.add_argument("--top", type=int, default=5, help="fastest particles described per frame")
    ap.add_argument("--from-time", type=float, default=0.0)
    a = ap.parse_args()
    lo, hi = np.array(a.tank[:3]), np.array(a.tank[3:])
    with h5py.File(a.cache, "r") as f:
        b = f["Boundary"]
        btree = cKDTree(np.stack([b["x"][:], b["y"][:], b["z"][:]], axis=1))
        last_step = None
        for g in frames(f):
            t, step = g.attrs["TimeValue"], int(g.attrs["step"])
            steps = "" if last_step is None else f"{step - last_step:3d}"
            last_step = step
            if t < a.from_time:
                continue
            x = np.stack([g["x"][:], g["y"][:], g["z"][:]], axis=1)
            v = np.stack([g["vx"][:], g["vy"][:], g["vz"][:]], axis=1)
            s = np.linalg.norm(v, axis=1)
            q = np.percentile(s, [50, 99, 99.9])
            print(f"t {t:.3f} step {step:5d} (+{steps}) speed median {q[0]:.2f} p99 {q[1]:.2f} "
                  f"p99.9 {q[2]:.2f} max {s.max():.2f} m/s; >4.4 m/s: {(s > 4.4).sum()}")
            tree = cKDTree(x)
            for i in np.argsort(s)[::-1][: a.top]:
                d = np.concatenate([x[i] - lo, hi - x[i]])  # to the walls x-, y-, z-, x+, y+, z+
                near = [n for n, di in zip(["x-", "y-", "z-", "x+", "y+", "z+"], d) if di < a.support]
                nf = len(tree.query_ball_point(x[i], a.support)) - 1
                nb = len(btree.query_ball_point(x[i], a.support))
                print(f"   id {g['id'][i]:7d} at ({x[i][0]:+.3f}, {x[i][1]:.3f}, {x[i][2]:+.3f}) "
                      f"v ({v[i][0]:+.2f}, {v[i][1]:+.2f}, {v[i][2]:+.2f}) |v| {s[i]:.2f}; walls "
                      f"within h: {','.join(near) or '-'}; {nf} fluid, {nb} boundary neighbours; "
                      f"rho {g['rho'][i]:.0f}")


if __name__ == "__main__":
    main()
