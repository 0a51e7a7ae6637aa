#!/usr/bin/python3
"""The pressure through the still tank's column, both solvers (docs/benchmarks.md, "Bottom
pressure of DFSPH"): the p of each cache's frames from --from on, by layers one spacing thick,
in the centre columns (x and z in the middle half of the tank) and near the side walls apart.

    sphsplat run scenes/still_tank.json --set 'fluids[0].max=[0.12,0.3,0.12]' \\
        --set 'boundaries[0].max=[0.12,0.4,0.12]' --set output.fps=20 --end 1.5 -o wcsph.h5
    (the same with --set solver.pressure=dfsph --end 1.0 -o dfsph.h5)
    plot_still_tank_pressure.py wcsph.h5 dfsph.h5 --from 0.5 --width 0.12 --out DIR

The reference at a particle is the weight of the water above it over the tank's cross-section
(what holds it up), rho0 g d for the water at rest density: it does not depend on how densely the
particles pack. Writes DIR/profile.csv and DIR/profile.png; needs h5py, numpy, matplotlib.
"""
import argparse
import csv
import os

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402

G = 9.81


def profile(path, start, width):
    """Per layer and region: mean depth (m), mean p (Pa), mean weight above / area (Pa)."""
    with h5py.File(path, "r") as f:
        steps = sorted((k for k in f if k.startswith("Step#")), key=lambda k: int(k[5:]))
        spacing = float(f.attrs["solver.spacing"])
        mass = float(f.attrs["solver.particle_mass"])
        sums = {}
        for name in steps:
            s = f[name]
            if s.attrs["TimeValue"] < start - 1e-9:
                continue
            x, y, z, p = (s[k][:] for k in ("x", "y", "z", "p"))
            above = np.empty(len(y))
            above[np.argsort(-y)] = np.arange(len(y)) + 0.5  # particles above, half of itself
            weight = above * mass * G / (width * width)
            top = len(y) * spacing**3 / (width * width)  # the surface at rest density
            lo, hi = 0.25 * width, 0.75 * width
            centre = (x > lo) & (x < hi) & (z > lo) & (z < hi)
            layer = np.floor(y / spacing).astype(int)
            for k in range(layer.max() + 1):
                for region, pick in (("centre", centre), ("walls", ~centre)):
                    m = (layer == k) & pick
                    if not m.any():
                        continue
                    acc = sums.setdefault((k, region), np.zeros(4))
                    acc += [(top - y[m]).mean(), p[m].mean(), weight[m].mean(), 1]
    return {key: v[:3] / v[3] for key, v in sums.items()}


def main():
    a = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    a.add_argument("wcsph")
    a.add_argument("dfsph")
    a.add_argument("--from", dest="start", type=float, default=0.5, help="first frame time (s)")
    a.add_argument("--width", type=float, default=0.12, help="the tank's side (m)")
    a.add_argument("--out", required=True)
    args = a.parse_args()
    os.makedirs(args.out, exist_ok=True)
    runs = {"wcsph": profile(args.wcsph, args.start, args.width), "dfsph": profile(args.dfsph, args.start, args.width)}
    with open(os.path.join(args.out, "profile.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["solver", "layer", "region", "depth_m", "p_Pa", "weight_above_Pa", "ratio"])
        for solver, rows in runs.items():
            for (layer, region), (depth, p, weight) in sorted(rows.items()):
                w.writerow([solver, layer, region, f"{depth:.4f}", f"{p:.1f}", f"{weight:.1f}", f"{p / weight:.4f}"])
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.6))
    style = {"wcsph": ("tab:blue", "WCSPH"), "dfsph": ("tab:red", "DFSPH")}
    for solver, rows in runs.items():
        colour, label = style[solver]
        for region, marker, fill in (("centre", "o", colour), ("walls", "^", "none")):
            keys = sorted(k for k in rows if k[1] == region)
            depth = [rows[k][0] for k in keys]
            p = [rows[k][1] for k in keys]
            ratio = [rows[k][1] / rows[k][2] for k in keys]
            name = f"{label}, {'centre columns' if region == 'centre' else 'near the side walls'}"
            left.plot(depth, p, marker, color=colour, mfc=fill, ms=4, label=name)
            right.plot(depth, ratio, marker + "-", color=colour, mfc=fill, ms=4, lw=0.8, label=name)
    d = np.linspace(0, 0.3, 2)
    left.plot(d, 1000 * G * d, "k--", lw=1, label=r"$\rho_0 g d$")
    left.set_xlabel("depth below the surface at rest density d (m)")
    left.set_ylabel("mean p of the layer (Pa)")
    left.legend(fontsize=8)
    right.axhspan(0.99, 1.01, color="0.85", label="within 1%")
    right.set_xlabel("depth below the surface at rest density d (m)")
    right.set_ylabel("p / (weight of the water above / area)")
    right.set_ylim(0.6, 2.1)
    right.legend(fontsize=8)
    fig.suptitle("Still tank 0.12 x 0.3 x 0.12 m, spacing 1 cm: the layers' p at rest")
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "profile.png"), dpi=110)


if __name__ == "__main__":
    main()
