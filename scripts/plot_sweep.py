#!/usr/bin/python3
"""Plot a `sphsplat bench` sweep: wall time against error, Pareto front marked.

    plot_sweep.py SWEEP.csv OUT.png --x wall_s --y front_rms_pct [--log-y] [--axis dx --axis cfl ...]

Colour follows the first axis, marker shape the second, the fill the third (filled, hollow, pale;
if the sweep has them). The Pareto front of the two plotted columns is joined by a line.
Variants the guard stopped (or that timed out) have no error: they are drawn as red crosses along
the top edge at the wall time they ran for. Needs matplotlib (Debian's python3-matplotlib, which
scripts/setup installs for /usr/bin/python3, the interpreter named above).
"""
import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

MARKERS = ["o", "s", "^", "D", "v", "P", "*", "X", "<", ">"]


def number(text):
    try:
        v = float(text)
    except (TypeError, ValueError):
        return math.nan
    return v


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("csv")
    p.add_argument("png")
    p.add_argument("--x", default="wall_s")
    p.add_argument("--y", required=True)
    p.add_argument("--title", default="")
    p.add_argument("--log-y", action="store_true")
    p.add_argument("--axis", action="append", default=[], help="sweep axis column, in the sweep's order")
    a = p.parse_args()

    with open(a.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit("plot_sweep.py: %s has no rows" % a.csv)
    for column in [a.x, a.y] + a.axis:
        if column not in rows[0]:
            sys.exit("plot_sweep.py: %s has no column %r" % (a.csv, column))

    def values(axis):  # distinct values in first-seen order
        seen = []
        for r in rows:
            if r[axis] not in seen:
                seen.append(r[axis])
        return seen

    axes = a.axis[:3]
    colour_values = values(axes[0]) if axes else [""]
    marker_values = values(axes[1]) if len(axes) > 1 else [""]
    fill_values = values(axes[2]) if len(axes) > 2 else [""]
    cmap = plt.get_cmap("viridis")

    def colour(r):
        k = colour_values.index(r[axes[0]]) if axes else 0
        return cmap(0.9 * k / max(1, len(colour_values) - 1))

    def marker(r):
        return MARKERS[marker_values.index(r[axes[1]]) % len(MARKERS)] if len(axes) > 1 else "o"

    def face(c, k):  # third axis: filled, hollow, pale, then hollow again
        return c if k == 0 else (c[0], c[1], c[2], 0.3) if k == 2 else "none"

    def fill_index(r):
        return fill_values.index(r[axes[2]]) if len(axes) > 2 else 0

    fig, ax = plt.subplots(figsize=(8.5, 5.5))
    good = [r for r in rows if r["status"] == "stable" and math.isfinite(number(r[a.x])) and math.isfinite(number(r[a.y]))]
    bad = [r for r in rows if r not in good]
    for r in good:
        c = colour(r)
        ax.scatter(number(r[a.x]), number(r[a.y]), s=46, marker=marker(r), facecolors=[face(c, fill_index(r))],
                   edgecolors=[c], linewidths=1.4, zorder=3)
    # The Pareto front of (x, y), both minimised, computed here (as sphsplat does for the table) so
    # any column of the CSV can be plotted.
    front = sorted((r for r in good if not any(
        number(o[a.x]) <= number(r[a.x]) and number(o[a.y]) <= number(r[a.y]) and
        (number(o[a.x]) < number(r[a.x]) or number(o[a.y]) < number(r[a.y])) for o in good)), key=lambda r: number(r[a.x]))
    if front:
        xs = [number(r[a.x]) for r in front]
        ys = [number(r[a.y]) for r in front]
        ax.step(xs, ys, where="post", color="crimson", linewidth=1.2, zorder=2)
        ax.scatter(xs, ys, s=150, facecolors="none", edgecolors="crimson", linewidths=1.2, zorder=4)
        for r in front:
            ax.annotate(r["variant"], (number(r[a.x]), number(r[a.y])), textcoords="offset points", xytext=(6, 5),
                        fontsize=7, color="crimson")
    ax.set_xscale("log")
    if a.log_y and all(number(r[a.y]) > 0 for r in good) and good:
        ax.set_yscale("log")
    # Plain numbers on log axes (not 6x10^0); on an axis spanning decades only the minor ticks 2
    # and 5 are labelled, or the labels overlap.
    for axis, (lo, hi) in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        wide = lo > 0 and hi / lo > 20
        axis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        axis.set_minor_formatter(matplotlib.ticker.FuncFormatter(
            lambda v, _, wide=wide: "" if wide and round(v / 10 ** math.floor(math.log10(v))) not in (2, 5) else "%g" % v))
    if bad:
        top = ax.get_ylim()[1] if good else 1.0
        for r in bad:
            x = number(r[a.x])
            if math.isfinite(x) and x > 0:
                ax.scatter(x, top, marker="x", color="red", s=50, zorder=5, clip_on=False)
    threads = rows[0].get("threads", "")
    ax.set_xlabel("%s (%s thread%s)" % (a.x, threads, "" if threads == "1" else "s"))
    ax.set_ylabel(a.y)
    ax.set_title(a.title + "  (%d variants, %d stable)" % (len(rows), len(good)))
    ax.grid(True, which="both", alpha=0.25)

    handles = []
    if axes:
        for v in colour_values:
            k = colour_values.index(v)
            handles.append(Line2D([], [], marker="o", linestyle="", color=cmap(0.9 * k / max(1, len(colour_values) - 1)),
                                  label="%s = %s" % (axes[0], v)))
    if len(axes) > 1:
        for v in marker_values:
            handles.append(Line2D([], [], marker=MARKERS[marker_values.index(v) % len(MARKERS)], linestyle="",
                                  color="grey", label="%s = %s" % (axes[1], v)))
    if len(axes) > 2:
        for k, v in enumerate(fill_values):
            handles.append(Line2D([], [], marker="o", linestyle="", markerfacecolor=face((0.5, 0.5, 0.5, 1.0), k),
                                  markeredgecolor="grey", label="%s = %s" % (axes[2], v)))
    if front:
        handles.append(Line2D([], [], color="crimson", marker="o", markerfacecolor="none", label="Pareto front (variant #)"))
    if bad:
        handles.append(Line2D([], [], marker="x", linestyle="", color="red", label="guard stopped / timeout"))
    ax.legend(handles=handles, fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5), frameon=False)
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)


if __name__ == "__main__":
    main()
