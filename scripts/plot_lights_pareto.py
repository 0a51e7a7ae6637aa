#!/usr/bin/python3
"""Time against error of the particle-light volume's settings, with the Pareto front.

    LIBGL_ALWAYS_SOFTWARE=1 build/release/bench/bench_lights filters --repeat 2 > filters.txt
    plot_lights_pareto.py filters.txt OUT.png

Reads the table `bench_lights filters` prints (voxel size, filter, ms, PSNR and the diffuse and
specular figures) and plots the probe's time against the lit image's PSNR to the exact sum: one
point per setting, coloured by filter, shaped by voxel size; the settings no other beats on both
time and PSNR are joined (the Pareto front) and named.
"""
import argparse
import re

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402

ROW = re.compile(r"^([0-9.]+)\s+(.+?)\s+([0-9.]+) \|\s+([0-9.]+)\s+([0-9.]+) \|\s+([0-9.]+)\s+([0-9.]+) \|\s+([0-9.]+)")
COLOUR = {"nearest": "tab:orange", "trilinear": "tab:blue", "tricubic": "tab:green"}
MARKER = {0.25: "o", 0.125: "s", 0.0625: "^"}


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("table")
    p.add_argument("png")
    a = p.parse_args()
    rows = []
    with open(a.table) as f:
        for line in f:
            m = ROW.match(line)
            if m:
                rows.append({"voxel": float(m[1]), "filter": m[2].strip(), "ms": float(m[3]),
                             "psnr": float(m[4]), "spec": float(m[8])})
    if not rows:
        raise SystemExit(f"{a.table}: no rows of `bench_lights filters` found")
    front = [r for r in rows
             if not any(o["ms"] <= r["ms"] and o["psnr"] >= r["psnr"] and o is not r
                        and (o["ms"] < r["ms"] or o["psnr"] > r["psnr"]) for o in rows)]
    front.sort(key=lambda r: r["ms"])
    fig, ax = plt.subplots(figsize=(8, 5))
    for r in rows:
        kind = r["filter"].split()[0]
        ax.scatter(r["ms"], r["psnr"], color=COLOUR[kind], marker=MARKER.get(r["voxel"], "x"),
                   s=46, alpha=0.85, edgecolors="none")
    ax.plot([r["ms"] for r in front], [r["psnr"] for r in front], "k-", linewidth=1, zorder=0)
    for r in front:
        ax.annotate(f'{r["voxel"]:g} m {r["filter"]}', (r["ms"], r["psnr"]), textcoords="offset points",
                    xytext=(6, -10), fontsize=8)
    for kind, colour in COLOUR.items():
        ax.scatter([], [], color=colour, label=kind)
    for voxel, marker in MARKER.items():
        ax.scatter([], [], color="grey", marker=marker, label=f"voxel {voxel:g} m")
    ax.plot([], [], "k-", linewidth=1, label="Pareto front")
    ax.set_xscale("log")
    ax.set_xlabel("ms per probe of 65,536 points (llvmpipe, 2 cores)")
    ax.set_ylabel("PSNR of the lit image to the exact sum (dB)")
    ax.set_title("particle lights: volume settings, time against error (x8 = oversampling 2)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)


if __name__ == "__main__":
    main()
