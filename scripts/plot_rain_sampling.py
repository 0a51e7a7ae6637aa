#!/usr/bin/python3
"""Plot what build/release/bench/rain_sampling prints (rain.sampling: ours against eq. (7)).

    build/release/bench/rain_sampling > rain_sampling.csv
    plot_rain_sampling.py rain_sampling.csv OUT.png

Left: the density of the radius of points drawn in the sphere of eq. (5), against 3 r^2, the
uniform ball's. Right: the density of the depth of the drops spawned in the rain space (the
sphere cut by the frustum's side planes) of a still camera at fov 45 degrees, 16:9.
"""
import argparse
import csv

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402

LABEL = {"uniform": 'ours, "uniform": points of the cube in the ball', "paper": '"paper": eq. (7), a radius per axis'}
COLOUR = {"uniform": "tab:blue", "paper": "tab:red"}


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("csv")
    p.add_argument("png")
    a = p.parse_args()
    with open(a.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    for sampling in ("uniform", "paper"):
        mine = [r for r in rows if r["sampling"] == sampling]
        lo = [float(r["bin_lo"]) for r in mine] + [float(mine[-1]["bin_hi"])]
        for axis, key in ((left, "radius_density"), (right, "depth_density")):
            values = [float(r[key]) for r in mine]
            axis.stairs(values, lo, color=COLOUR[sampling], label=LABEL[sampling], linewidth=1.6)
    r = [i / 200 for i in range(201)]
    left.plot(r, [3 * x * x for x in r], "k--", linewidth=1, label="uniform ball: 3 r$^2$")
    left.set_xlabel("distance from the sphere's centre / its radius")
    left.set_ylabel("density")
    left.set_title("points drawn in the sphere of eq. (5), 10$^6$")
    right.set_xlabel("depth along the view axis / far")
    right.set_title("drops spawned in the rain space (fov 45$^\\circ$, 16:9), 10$^6$")
    for axis in (left, right):
        axis.set_xlim(0, 1)
        axis.set_ylim(bottom=0)
        axis.grid(alpha=0.3)
        axis.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)


if __name__ == "__main__":
    main()
