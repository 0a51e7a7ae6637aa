#!/usr/bin/python3
"""The dam-break front study (docs/benchmarks.md, "The dam-break front: convergence,
gate, walls and viscosity"): reads the output folders of the sweeps
bench/sweeps/dam_break_{convergence,walls_viscosity,gate}.json (each NAME.csv and the
variant-N-front.csv series the surge_front metric's `series` option writes) and writes

    OUT/study.csv        one row per run: model, a / dx, the front's RMS and bias at the release
                         time, its RMS with the one gate delay fitted to all low-dissipation runs
                         (GATE below), with its own best delay, and against Koshizuka & Oka's
                         experiment on the same geometry (at its t = 0 and its best delay)
    OUT/convergence.png  front RMS against a / dx per model, at the release time and with GATE
    OUT/fronts.png       the front Z(T) of the finest runs against both experiments

    plot_dam_break_study.py DIR [DIR ...] --out docs/bench/dam_break_study

The front between steps is linear (steps are 0.2-4 ms; the front moves 2-3 mm a ms). Needs numpy
and matplotlib (Debian's, which scripts/setup installs for /usr/bin/python3).
"""
import argparse
import csv
import glob
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

A = 0.146  # m, the scene's column width
DEPTH = 0.0584  # m, the shipped tank's depth: a lattice that does not divide it leaves a gap
G = 9.81
# Martin & Moyce (1952), Fig. 3, a = 2.25 in, T <= 3 (tests/data/martin_moyce_1952.csv).
MM = np.array([[0.832, 1.217], [1.219, 1.474], [1.997, 2.292], [2.547, 2.995]])
HERE = os.path.dirname(os.path.abspath(__file__))
KO_FILE = os.path.join(HERE, "..", "docs", "bench", "dam_break_study", "koshizuka_oka_1996.csv")


def read_reference(path):
    rows = [line.split(",") for line in open(path) if line[0].isdigit()]
    return np.array([[float(t), float(z)] for t, z in rows])


def model_of(row):
    """The run's model: solver and the dissipation it has (automatic viscosity, walls)."""
    label = row["label"]
    solver = "dfsph" if ("dfsph" in label or "accurate" in label) else "wcsph"
    if "nu 0" in label:
        return solver + " nu=0"
    if "2e-4" in label:
        return solver + " nu=2e-4"
    if "slip" in label and "no-slip" not in label:
        return solver + " auto slip-walls"
    return solver + " auto (default)"


def front_at(series, t):
    """Z at simulated time t (the column at rest before 0); NaN past the run."""
    ts, zs = series
    if t > ts[-1] + 1e-12:
        return math.nan
    return float(np.interp(max(t, 0.0), ts, zs))


def errors(series, ref, a, delay):
    """Signed relative deviations (%) at the reference points with the experiment's clock started
    `delay` seconds before the release."""
    scale = math.sqrt(2 * G / a)
    return np.array([100 * (front_at(series, T / scale - delay) - Z) / Z for T, Z in ref])


def rms(e):
    return float(np.sqrt(np.mean(e**2)))


def load(dirs):
    runs = []
    for d in dirs:
        for path in glob.glob(os.path.join(d, "*.csv")):
            if os.path.basename(path).startswith("variant-"):
                continue
            for row in csv.DictReader(open(path)):
                if row["status"] != "stable":
                    continue
                data = np.loadtxt(os.path.join(d, "variant-%s-front.csv" % row["variant"]),
                                  delimiter=",", skiprows=1, ndmin=2)
                dx = float(row["dx"])
                n = max(1, round(A / dx))
                layers = DEPTH / dx
                runs.append({"model": model_of(row), "dx": dx, "n": n, "a": n * dx,
                             "exact": abs(layers - round(layers)) < 1e-3,
                             "series": (data[:, 0], data[:, 2]), "cpu_s": float(row["cpu_s"]),
                             "sweep": os.path.basename(path)[:-4]})
    # The same model and resolution run by two sweeps: keep one (they are the same run).
    seen, unique = set(), []
    for r in sorted(runs, key=lambda r: (r["model"], r["n"], r["sweep"])):
        if (r["model"], r["n"]) not in seen:
            seen.add((r["model"], r["n"]))
            unique.append(r)
    return unique


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("dirs", nargs="+")
    p.add_argument("--out", required=True)
    args = p.parse_args()
    os.makedirs(args.out, exist_ok=True)
    ko = read_reference(KO_FILE)
    ko = ko[(ko[:, 0] > 0) & (ko[:, 0] <= 3)]
    runs = load(args.dirs)
    delays = np.arange(-0.05, 0.1 + 1e-9, 0.00025)

    # GATE: the one delay that fits every low-dissipation run at a / dx >= 20 best (least mean
    # RMS): the experiment's release time if the simulated flow were right.
    low = [r for r in runs if "auto (default)" not in r["model"] and "2e-4" not in r["model"]
           and r["n"] >= 20 and r["exact"]]
    gate = math.nan
    if low:
        cost = [np.mean([rms(errors(r["series"], MM, r["a"], d)) for r in low]) for d in delays]
        gate = float(delays[int(np.nanargmin(cost))])

    rows = []
    for r in runs:
        e0 = errors(r["series"], MM, r["a"], 0.0)
        fits = [rms(errors(r["series"], MM, r["a"], d)) for d in delays]
        k = int(np.nanargmin(fits))
        eg = errors(r["series"], MM, r["a"], gate)
        ko_fits = [rms(errors(r["series"], ko, r["a"], d)) for d in delays]
        kk = int(np.nanargmin(ko_fits))
        rows.append({"model": r["model"], "a_dx": r["n"], "depth_layers": DEPTH / r["dx"],
                     "cpu_s": r["cpu_s"],
                     "rms_pct": rms(e0), "bias_pct": float(e0.mean()),
                     **{"e%d_pct" % (i + 1): float(v) for i, v in enumerate(e0)},
                     "gate_ms": 1e3 * gate, "rms_gate_pct": rms(eg),
                     "bias_gate_pct": float(eg.mean()),
                     "best_delay_ms": 1e3 * delays[k], "rms_best_pct": fits[k],
                     "rms_vs_ko_pct": rms(errors(r["series"], ko, r["a"], 0.0)),
                     "ko_best_delay_ms": 1e3 * delays[kk], "rms_vs_ko_best_pct": ko_fits[kk]})
    rows.sort(key=lambda x: (x["model"], x["a_dx"]))
    with open(os.path.join(args.out, "study.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        for row in rows:
            w.writerow({k: ("%.4g" % v if isinstance(v, float) else v) for k, v in row.items()})

    models = sorted({x["model"] for x in rows})
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.4))
    panels = [("bias_pct", "mean signed deviation at the release (%)"),
              ("rms_pct", "RMS deviation at the release (%)"),
              ("rms_gate_pct", "RMS deviation, gate held %.1f ms (%%)" % (1e3 * gate))]
    for i, m in enumerate(models):
        exact = [x for x in rows if x["model"] == m and abs(x["depth_layers"] - round(
            x["depth_layers"])) < 1e-3]
        gap = [x for x in rows if x["model"] == m and x not in exact]
        for a, (key, _) in zip(ax, panels):
            a.plot([x["a_dx"] for x in exact], [x[key] for x in exact], marker="osD^v<>"[i % 7],
                   color="C%d" % i, label=m)
            a.plot([x["a_dx"] for x in gap], [x[key] for x in gap], ls="none",
                   marker="osD^v<>"[i % 7], mfc="none", color="C%d" % i)
    for a, (_, title) in zip(ax, panels):
        a.set_title(title, fontsize=10)
        if "RMS" in title:
            a.axhline(5, color="k", lw=0.8, ls="--")
        else:
            a.axhline(0, color="k", lw=0.8)
        a.set_xlabel("a / dx (hollow: the lattice leaves a gap at the back wall)")
        a.set_xscale("log")
        a.set_xticks([10, 15, 20, 25, 30, 40])
        a.get_xaxis().set_major_formatter(matplotlib.ticker.ScalarFormatter())
        a.grid(alpha=0.3)
    ax[0].set_ylabel("surge front against Martin & Moyce, T <= 3 (%)")
    ax[2].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "convergence.png"), dpi=100)

    fig, ax = plt.subplots(figsize=(7, 4.6))
    # The default and inviscid models at their finest lattice that fills the tank, and the
    # accurate preset at a / dx = 15 (the resolution where it is nearest at the release).
    shown = []
    for m in ("dfsph auto (default)", "wcsph auto (default)", "dfsph nu=0"):
        fine = [r for r in runs if r["model"] == m and r["exact"]]
        if fine:
            shown.append((max(fine, key=lambda r: r["n"]), "-"))
    shown += [(r, ":") for r in runs
              if r["model"] == "dfsph auto (default)" and r["n"] == 15 and r["exact"]]
    for i, (r, ls) in enumerate(shown):
        ts, zs = r["series"]
        k = math.sqrt(2 * G / r["a"])
        ax.plot(ts * k, zs, color="C%d" % i, ls=ls, label="%s, a/dx = %d" % (r["model"], r["n"]))
        if r["model"] == "dfsph nu=0":
            ax.plot((ts + gate) * k, zs, color="C%d" % i, ls="--",
                    label="%s, a/dx = %d, gate %.1f ms" % (r["model"], r["n"], 1e3 * gate))
    ax.plot(MM[:, 0], MM[:, 1], "ko", label="Martin & Moyce 1952 (a = 2.25 in)")
    ax.plot(ko[:, 0], ko[:, 1], "k^", mfc="none", label="Koshizuka & Oka 1996 (a = 0.146 m)")
    ax.set_xlim(0, 3.1)
    ax.set_ylim(0.9, 3.6)
    ax.set_xlabel("T = t sqrt(2 g / a)")
    ax.set_ylabel("Z = front / a")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "fronts.png"), dpi=110)
    print("gate delay fitted to the low-dissipation runs at a/dx >= 20: %.2f ms" % (1e3 * gate))


if __name__ == "__main__":
    main()
