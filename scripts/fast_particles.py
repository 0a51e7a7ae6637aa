#!/usr/bin/python3
"""Where a DFSPH run's fastest particles are, frame by frame (what sets the step count).

The CFL step of "dfsph" follows the largest speed of the fluid; this reads a cache (written with a
high output.fps to see between steps) and prints per frame the speed percentiles, and for the
fastest particles where they are (distance to each of a box tank's walls), how many fluid
neighbours and boundary particles lie within the kernel support, and their density.

The same for the peer (SPlisHSPlasH): a directory of its VTK export (`"enableVTKExport": true`,
`"particleAttributes": "velocity;id"`), whose frame K is at (K - 1) / FPS s; it has no boundary
particles or density to show.

    scripts/fast_particles.py CACHE.h5 --tank -2 0 -0.75 2 3 0.75 --support 0.04 [--top 5]
    scripts/fast_particles.py --peer-vtk OUT/vtk --fps 100 --tank ... --support 0.04

With --summary FROM TO, one line for the frames in [FROM, TO] s instead, how still water is: the
fastest particle, how many particles were ever over --over m/s, the largest mean vertical speed
(the whole fluid heaving) and the height of the top 5% of particles at the first and last frame.
Read the same way from both programs' frames, so a still tank can be compared with the peer's:

    scripts/fast_particles.py CACHE.h5 --summary 5 10
    scripts/fast_particles.py --peer-vtk OUT/vtk --fps 50 --summary 5 10

With --tank and --spacing too, a second line says where those particles were at their fastest: in
the floor's layer, beside a side wall or elsewhere (the still tank's creep is its floor layer's):

    scripts/fast_particles.py CACHE.h5 --summary 5 10 --over 0.005 --tank 0 0 0 0.12 0.4 0.12 --spacing 0.01
"""
import argparse
import glob
import os
import re
import sys

import h5py
import numpy as np


def frames(f):
    names = sorted((k for k in f if k.startswith("Step#")), key=lambda k: int(k.split("#")[1]))
    for k in names:
        yield f[k]


def cache_frames(path):
    """Per frame: time, step, positions, velocities, ids, densities; and the boundary particles."""
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        fail(f"{path}: not a readable HDF5 cache ({e})")
    with f:
        if "Boundary" not in f:
            fail(f"{path}: no 'Boundary' group: not a sphsplat cache")
        b = f["Boundary"]
        boundary = np.stack([b["x"][:], b["y"][:], b["z"][:]], axis=1)
        for g in frames(f):
            x = np.stack([g["x"][:], g["y"][:], g["z"][:]], axis=1)
            v = np.stack([g["vx"][:], g["vy"][:], g["vz"][:]], axis=1)
            yield (g.attrs["TimeValue"], int(g.attrs["step"]), x, v, g["id"][:], g["rho"][:],
                   boundary)


def fail(message):
    """Bad input: one line, exit 2."""
    print(f"fast_particles.py: {message}", file=sys.stderr)
    sys.exit(2)


def vtk_array(data, header, width, kind):
    """The array after `header` (a regular expression naming its count) in a legacy binary VTK
    file: big-endian, `width` values a point."""
    m = re.search(header, data)
    if not m:
        return None
    n = int(m.group(1))
    if len(data) < m.end() + width * n * 4:
        return None  # cut short
    return np.frombuffer(data, dtype=">" + kind, count=width * n, offset=m.end()).reshape(n, width)


def peer_frames(directory, fps):
    """The peer's VTK export, frame by frame, in the shape of cache_frames (no step, density or
    boundary)."""
    def number(path):
        return int(re.findall(r"_(\d+)\.vtk$", path)[0])
    paths = sorted(glob.glob(os.path.join(directory, "ParticleData_Fluid_*.vtk")), key=number)
    if not paths:
        fail(f"{directory}: no ParticleData_Fluid_*.vtk files")
    for path in paths:
        data = open(path, "rb").read()
        x = vtk_array(data, rb"POINTS (\d+) float\n", 3, "f4")
        v = vtk_array(data, rb"velocity 3 (\d+) float\n", 3, "f4")
        if x is None or v is None:
            fail(f"{path}: expected whole POINTS and 'velocity' arrays (particleAttributes)")
        m = re.search(rb"SCALARS id unsigned_int 1\nLOOKUP_TABLE \w+\n", data)
        whole = m and len(data) >= m.end() + 4 * len(x)
        ids = (np.frombuffer(data, dtype=">u4", count=len(x), offset=m.end()) if whole
               else np.arange(len(x)))  # without "id" in particleAttributes: the file's order
        yield (number(path) - 1) / fps, None, x.astype(float), v.astype(float), ids, None, None


def within(points, centre, radius):
    """How many of `points` lie within `radius` of `centre` (a few particles a frame: a plain
    scan, no spatial index to build)."""
    return int((np.sum((points - centre) ** 2, axis=1) <= radius * radius).sum())


def region(x, lo, hi, spacing):
    """Where a particle of a box tank is: in the floor's layer (within one spacing of the floor),
    beside a side wall (within one spacing of one), or elsewhere."""
    if x[1] - lo[1] < spacing:
        return "floor layer"
    side = min(x[0] - lo[0], hi[0] - x[0], x[2] - lo[2], hi[2] - x[2])
    return "beside a side wall" if side < spacing else "elsewhere"


def summary(source, t0, t1, over, tank=None, spacing=None):
    """One line: how still the frames in [t0, t1] are (the module's docstring); with a tank and
    its spacing a second: where the particles over `over` were at their fastest."""
    count, fastest, heave, ever, heights = 0, 0.0, 0.0, {}, []
    for t, _, x, v, ids, _, _ in source:
        if t < t0 - 1e-6 or t > t1 + 1e-6:
            continue
        s = np.linalg.norm(v, axis=1)
        count += 1
        fastest = max(fastest, float(s.max()))
        heave = max(heave, abs(float(v[:, 1].mean())))
        for i in np.nonzero(s > over)[0]:
            if ids[i] not in ever or s[i] > ever[ids[i]][0]:
                ever[ids[i]] = (float(s[i]), x[i].copy())
        heights.append(float(np.sort(x[:, 1])[-max(1, len(x) // 20):].mean()))
    if count == 0:
        fail(f"no frame between {t0} and {t1} s")
    print(f"{count} frames, {t0:g}-{t1:g} s: fastest particle {100 * fastest:.2f} cm/s, "
          f"{len(ever)} particles ever over {100 * over:g} cm/s, largest mean vertical speed "
          f"{1000 * heave:.2f} mm/s, top 5% of the particles at {heights[0]:.4f} -> "
          f"{heights[-1]:.4f} m")
    if tank is None or not ever:
        return
    lo, hi = np.array(tank[:3]), np.array(tank[3:])
    places = [region(at, lo, hi, spacing) for _, at in ever.values()]
    counts = ", ".join(f"{places.count(r)} {r}" for r in
                       ("floor layer", "beside a side wall", "elsewhere"))
    print(f"  where they were at their fastest (one spacing, {spacing:g} m): {counts}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("cache", nargs="?", help="a sphsplat cache (or --peer-vtk)")
    ap.add_argument("--peer-vtk", metavar="DIR", help="the peer's VTK export directory instead")
    ap.add_argument("--fps", type=float, help="the peer's dataExportFPS (with --peer-vtk)")
    ap.add_argument("--tank", type=float, nargs=6, metavar="LO/HI",
                    help="the tank's inner box: xlo ylo zlo xhi yhi zhi (m)")
    ap.add_argument("--support", type=float, help="kernel support h (m)")
    ap.add_argument("--summary", type=float, nargs=2, metavar=("FROM", "TO"),
                    help="one line on how still the frames in [FROM, TO] s are")
    ap.add_argument("--over", type=float, default=0.01,
                    help="the speed --summary counts particles over (m/s, default 0.01)")
    ap.add_argument("--spacing", type=float,
                    help="with --summary and --tank: the particle spacing (m), the thickness of "
                         "the floor's layer and of the water beside the side walls")
    ap.add_argument("--top", type=int, default=5, help="fastest particles described per frame")
    ap.add_argument("--from-time", type=float, default=0.0)
    a = ap.parse_args()
    if sys.stdout is None:  # started with standard output closed: what it prints would be lost
        fail("standard output is closed: nowhere to print the frames")
    if (a.cache is None) == (a.peer_vtk is None):
        ap.error("give either a cache or --peer-vtk DIR")
    if a.peer_vtk and not a.fps:
        ap.error("--peer-vtk needs --fps (the peer's dataExportFPS)")
    source = peer_frames(a.peer_vtk, a.fps) if a.peer_vtk else cache_frames(a.cache)
    if a.summary:
        if (a.tank is None) != (a.spacing is None):
            ap.error("--summary places the fast particles with both --tank and --spacing")
        if a.spacing is not None and not a.spacing > 0:
            ap.error(f"--spacing must be a length > 0 m, not {a.spacing:g}")
        summary(source, a.summary[0], a.summary[1], a.over, a.tank, a.spacing)
        return
    if a.tank is None or a.support is None:
        ap.error("--tank and --support are needed (or --summary FROM TO)")
    lo, hi = np.array(a.tank[:3]), np.array(a.tank[3:])
    last_step = None
    for t, step, x, v, ids, rho, boundary in source:
        steps = "" if last_step is None or step is None else f" (+{step - last_step:3d})"
        last_step = step
        if t < a.from_time - 1e-9:
            continue
        s = np.linalg.norm(v, axis=1)
        q = np.percentile(s, [50, 99, 99.9])
        at = f" step {step:5d}{steps}" if step is not None else ""
        # Three figures, not two decimals: a still tank's speeds are mm/s
        print(f"t {t:.3f}{at} speed median {q[0]:.3g} p99 {q[1]:.3g} "
              f"p99.9 {q[2]:.3g} max {s.max():.3g} m/s; >4.4 m/s: {(s > 4.4).sum()}")
        for i in np.argsort(s)[::-1][: a.top]:
            d = np.concatenate([x[i] - lo, hi - x[i]])  # to the walls x-, y-, z-, x+, y+, z+
            near = [n for n, di in zip(["x-", "y-", "z-", "x+", "y+", "z+"], d) if di < a.support]
            nf = within(x, x[i], a.support) - 1
            walls = (f"{within(boundary, x[i], a.support)} boundary neighbours; "
                     f"rho {rho[i]:.0f}" if boundary is not None else "the peer's walls are a map")
            print(f"   id {ids[i]:7d} at ({x[i][0]:+.3f}, {x[i][1]:.3f}, {x[i][2]:+.3f}) "
                  f"v ({v[i][0]:+.3g}, {v[i][1]:+.3g}, {v[i][2]:+.3g}) |v| {s[i]:.3g}; walls "
                  f"within h: {','.join(near) or '-'}; {nf} fluid, {walls}")


if __name__ == "__main__":
    try:
        main()
        sys.stdout.flush()
    except BrokenPipeError:  # the reader stopped early (| head): nothing more is wanted
        sys.stderr.close()  # Python's flush at exit would print a traceback otherwise
        sys.exit(0)
    except OSError as e:  # writing the lines failed (a full disk)
        fail(f"cannot write the output: {e.strerror}")
