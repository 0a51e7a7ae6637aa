#!/usr/bin/python3
"""Measure what each skip of a scene saves (docs/benchmarks.md, "What a scene skips").

    scripts/bench_skips.py [--build build/release] [--out results/skips] [--threads 1]

DESIGN.md: "no camera or render section -> no GL context; no collision section -> no collision
pass; splats only for surface particles inside the frustum; boundary samples computed once;
output frames only at the output rate". For each skip this runs the same scene with and without
the skipped work where an option can switch it on (collision section, cache fields, frame rate)
and otherwise measures the skipped work directly (bench/bench_skips: a GL context, boundary
sampling). Every number comes from the runs made here; the markdown goes to OUT/skips.md.

Timings: wall time and the child processes' CPU time (user + sys). On a shared machine the CPU
time of a 1-thread run is the steadier figure; the ratios within one table come from one session.
"""
import argparse
import csv
import json
import os
import re
import resource
import shlex
import subprocess
import sys
import time

SCENE = "scenes/dam_break.json"
SPACING = "solver.spacing=0.0073"  # a / dx = 20: 6400 fluid particles


def run(cmd, cwd):
    """Runs cmd; returns (stdout+stderr, wall s, child CPU s)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if p.returncode != 0:
        sys.exit("bench_skips.py: %s failed (exit %d):\n%s" % (" ".join(map(shlex.quote, cmd)), p.returncode, p.stdout))
    return p.stdout, wall, cpu


def quoted(cmd):
    return " ".join(shlex.quote(c) for c in cmd)


def parse_run(output):
    """The figures `sphsplat run` prints: ms per step, steps, and the cache summary if any."""
    r = {}
    m = re.search(r"simulated [\d.e+-]+ s in (\d+) steps", output)
    r["steps"] = int(m.group(1)) if m else 0
    m = re.search(r"([\d.]+) ms per step", output)
    r["ms_per_step"] = float(m.group(1)) if m else float("nan")
    # "cache: PATH (+ SIDECAR for ParaView): 16 frames, 3.21 MB; frame datasets 23.3 bytes per
    # particle per frame; writing took 100.2 ms = 0.57% of the run" (io/cache/CacheSession.cpp)
    m = re.search(r"cache: .*: (\d+) frames, ([\d.e+]+) MB.*?writing took ([\d.]+) (us|ms|s) ", output)
    if m:
        r["frames"] = int(m.group(1))
        r["cache_mb"] = float(m.group(2))
        r["write_s"] = float(m.group(3)) * {"us": 1e-6, "ms": 1e-3, "s": 1.0}[m.group(4)]
    m = re.search(r"frame datasets ([\d.e+]+) bytes per particle per frame", output)
    r["bytes_per_particle"] = float(m.group(1)) if m else float("nan")
    r["skipped"] = [line.strip() for line in output.splitlines() if line.strip().startswith("skipped:")]
    return r


def fmt(v, spec=".3g"):
    return "-" if v is None or v != v else format(v, spec)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default="build/release", help="build folder with app/sphsplat and bench/bench_skips")
    p.add_argument("--out", default="results/skips")
    p.add_argument("--threads", default="1")
    a = p.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    build = os.path.abspath(a.build)
    sphsplat = os.path.join(build, "app", "sphsplat")
    bench_skips = os.path.join(build, "bench", "bench_skips")
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    env_note = "OMP_WAIT_POLICY=PASSIVE"
    os.environ["OMP_WAIT_POLICY"] = "PASSIVE"  # no spinning threads on a shared machine
    md = []

    # 1. What --verbose says is skipped, for a plain run.
    cmd = [sphsplat, "run", SCENE, "--set", SPACING, "--end", "0.02", "--threads", a.threads, "-v"]
    text, _, _ = run(cmd, root)
    md.append("`sphsplat run %s --set %s --end 0.02 -v` reports:\n" % (SCENE, SPACING))
    md.append("```\n" + "\n".join(parse_run(text)["skipped"]) + "\n```\n")

    # 2. Collision pass: a sweep with the section off and each method on.
    sweep_out = os.path.join(out, "skip_collision")
    cmd = [sphsplat, "bench", "bench/sweeps/skip_collision.json", "--output", sweep_out, "--no-plot", "--quiet"]
    run(cmd, root)
    with open(os.path.join(sweep_out, "skip_collision.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    base = rows[0]
    base_cpu = float(base["cpu_s"]) / int(base["steps"])
    md.append("**Collision pass** (`%s`; 1 thread, best of 2 runs):\n" % quoted(["sphsplat"] + cmd[1:]))
    md.append("| collision | ms/step (wall) | CPU ms/step | collide pass ms/step | setup s | vs skipped (CPU) |")
    md.append("| --- | --- | --- | --- | --- | --- |")
    for r in rows:
        steps = int(r["steps"]) or 1
        cpu = float(r["cpu_s"]) / steps
        status = "" if r["status"] == "stable" else " (%s)" % r["status"]
        md.append("| %s%s | %s | %s | %s | %s | %s |" % (r["case"], status, fmt(float(r["ms_per_step"])), fmt(1e3 * cpu),
                                                         fmt(1e3 * float(r["pass_collide_s"]) / steps),
                                                         fmt(float(r["setup_s"])), "1" if r is base else "%.2fx" % (cpu / base_cpu)))
    md.append("")

    # 3. Cache: only the requested fields, and frames only at the output rate.
    h5 = os.path.join(out, "skips.h5")
    common = [sphsplat, "run", SCENE, "--set", SPACING, "--end", "0.25", "--threads", a.threads, "-v"]
    cases = [
        ("no cache (no output path)", []),
        ("x y z only, no resume record", ["--set", "output.fields=[\"x\",\"y\",\"z\"]", "--set", "output.restart=false"]),
        ("default fields (x y z vx vy vz rho p id + resume)", []),
        ("all 13 fields + resume", ["--set", "output.fields=[\"x\",\"y\",\"z\",\"vx\",\"vy\",\"vz\",\"ax\",\"ay\",\"az\",\"rho\",\"p\",\"collide_time\",\"id\"]"]),
        ("default fields, a frame every step (fps 5000)", ["--set", "output.fps=5000"]),
    ]
    md.append("**Cache output** (`%s --output skips.h5 --overwrite --set ...`, 0.25 s simulated, 60 fps unless said):\n"
              % quoted(["sphsplat"] + common[1:]))
    md.append("| output | frames | cache MB | bytes / particle / frame | writing s | writing ms/frame | run wall s | run CPU s |")
    md.append("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for label, extra in cases:
        cmd = common + ([] if label.startswith("no cache") else ["--output", h5, "--overwrite"]) + extra
        text, wall, cpu = run(cmd, root)
        r = parse_run(text)
        frames = r.get("frames")
        md.append("| %s | %s | %s | %s | %s | %s | %s | %s |" % (
            label, frames if frames else "-", fmt(r.get("cache_mb")), fmt(r.get("bytes_per_particle")), fmt(r.get("write_s")),
            fmt(1e3 * r["write_s"] / frames) if frames else "-", fmt(wall), fmt(cpu)))
    for f in (h5, h5.replace(".h5", ".xdmf")):
        if os.path.exists(f):
            os.remove(f)
    md.append("")

    # 4. Work measured directly: a GL context, boundary sampling.
    json_path = os.path.join(out, "bench_skips.json")
    cmd = [bench_skips, "--benchmark_format=json", "--benchmark_out=" + json_path, "--benchmark_out_format=json"]
    os.environ["OMP_NUM_THREADS"] = a.threads
    run(cmd, root)
    with open(json_path) as f:
        # Google Benchmark appends the arguments and options to the name: key by the name we gave.
        results = {"/".join(b["name"].split("/")[:2]): b for b in json.load(f)["benchmarks"]}

    def ms(name):
        b = results.get(name)
        if not b or b.get("error_occurred"):
            return float("nan")
        scale = {"ms": 1.0, "us": 1e-3, "ns": 1e-6, "s": 1e3}[b["time_unit"]]
        return b["real_time"] * scale

    step = ms("Simulation/step")
    gl = results.get("GlContext/headless", {})
    md.append("**Work measured directly** (`bench/bench_skips --benchmark_format=json`, OMP_NUM_THREADS=%s; "
              "dam break at a / dx = 20):\n" % a.threads)
    md.append("| skipped work | cost | compared with |")
    md.append("| --- | --- | --- |")
    if gl.get("error_occurred"):
        md.append("| GL context (headless EGL) | unavailable here: %s | |" % gl.get("error_message", ""))
    else:
        md.append("| GL context (headless EGL, %s) | %s ms to create + destroy, %s MB resident | once per run; a step is %s ms |"
                  % ("llvmpipe", fmt(ms("GlContext/headless")), fmt(gl.get("rss_mb")), fmt(step)))
    bs = results.get("Boundary/sample", {})
    md.append("| boundary sampling (%d boundary particles) | %s ms | done once; per step it would add %.0f%% to the %s ms step |"
              % (int(bs.get("boundary_particles", 0)), fmt(ms("Boundary/sample")), 100 * ms("Boundary/sample") / step, fmt(step)))
    md.append("| whole setup (constants, boundary, static boundary density, lattice) | %s ms | %.1f steps |"
              % (fmt(ms("Simulation/setup")), ms("Simulation/setup") / step))
    surface, every, narrow = (results.get("Splats/" + k, {}) for k in ("surface", "every_particle", "surface_narrow_view"))
    if surface and every and not surface.get("error_occurred"):
        md.append("| splats for interior particles (quad splats, t = 0.2 s, CPU build) | %s ms for all %d particles | "
                  "%s ms for the %d surface particles the default builds (%.1fx less) |"
                  % (fmt(ms("Splats/every_particle")), int(every["splats"]), fmt(ms("Splats/surface")),
                     int(surface["splats"]), ms("Splats/every_particle") / ms("Splats/surface")))
    if narrow and not narrow.get("error_occurred"):
        md.append("| splats for off-screen particles (12 deg view instead of 60) | %d surface particles culled | "
                  "%s ms for the %d splats in view, %s ms for the full view's %d |"
                  % (int(narrow["culled"]), fmt(ms("Splats/surface_narrow_view")), int(narrow["splats"]),
                     fmt(ms("Splats/surface")), int(surface["splats"])))
    md.append("")
    md.append("Environment: %s, %s thread(s)." % (env_note, a.threads))

    with open(os.path.join(out, "skips.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))


if __name__ == "__main__":
    main()
