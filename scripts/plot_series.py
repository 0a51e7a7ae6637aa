#!/usr/bin/python3
"""Plot the energy series a `sphsplat bench` energy metric writes (variant-N-energy.csv).

    plot_series.py variant-0-energy.csv OUT.png [--settle 2.0] [--title TEXT]

Three panels over simulated time: total energy relative to its value at the settle time, the
kinetic energy (log scale), and the mean density. The settle time is marked: the initial lattice
is not in equilibrium, so drift is measured from there on.
"""
import argparse
import csv

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("csv")
    p.add_argument("png")
    p.add_argument("--settle", type=float, default=0.0, help="s; drift reference time")
    p.add_argument("--title", default="")
    a = p.parse_args()
    with open(a.csv, newline="") as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    t = [r["time"] for r in rows]
    ref = next((r for r in rows if r["time"] >= a.settle and r["step"] > 0), rows[-1])
    drift = [100 * (r["total"] - ref["total"]) / abs(ref["total"]) for r in rows]
    moving = [r for r in rows if r["kinetic"] > 0]  # the start is at rest: nothing to put on a log axis
    rho = [r["mean_rho"] for r in rows]

    fig, axes = plt.subplots(3, 1, figsize=(8, 7.5), sharex=True)
    axes[0].plot(t, drift, linewidth=0.9)
    axes[0].set_ylabel("total energy\nchange (%)")
    axes[1].semilogy([r["time"] for r in moving], [r["kinetic"] for r in moving], linewidth=0.9, color="darkorange")
    axes[1].set_ylabel("kinetic energy (J)")
    axes[2].plot(t, rho, linewidth=0.9, color="seagreen")
    axes[2].set_ylabel("mean density\n(kg/m^3)")
    axes[2].set_xlabel("simulated time (s); %d steps" % int(rows[-1]["step"]))
    for ax in axes:
        ax.grid(True, alpha=0.3)
        if a.settle > 0:
            ax.axvline(a.settle, color="grey", linestyle="--", linewidth=0.8)
    axes[0].set_title(a.title or a.csv)
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)


if __name__ == "__main__":
    main()
