#!/usr/bin/python3
"""The house rules a file-by-file review misses, checked on the whole tree (docs/architecture.md):

- every #include of a project header goes down the layers: a folder includes only the folders the
  table below allows it (its library links only those, so the table and the CMake files agree);
- tests, benches and fuzzers do not include app/ (what they need lives in a library; the
  fuzzers run the command line itself);
- no C++ file over 500 lines; sim/'s root holds at most 11 files;
- no "issue N" in product code or build files: history belongs in git.

Usage: check_layout.py SOURCE_DIR. Prints one line per breach and exits 1 if there is any.
"""
import os
import re
import subprocess
import sys

# folder -> the folders its files may include (besides its own). Product folders only.
SIM = {'sim'}
ALLOWED = {
    'sim': set(),
    'sim/scene': SIM,
    'sim/grid': SIM,
    'sim/ranks': SIM | {'sim/grid'},
    'sim/solver': SIM | {'sim/scene', 'sim/grid', 'sim/ranks'},
    'sim/collision': SIM | {'sim/scene', 'sim/grid'},
    'sim/cdt': SIM | {'sim/scene', 'sim/grid', 'sim/solver', 'sim/collision'},
    'sim/rain': SIM | {'sim/scene', 'sim/solver'},
    'sim/lights': SIM | {'sim/scene', 'sim/solver'},
    'sim/run': SIM | {'sim/scene', 'sim/grid', 'sim/ranks', 'sim/solver', 'sim/rain'},
}
ALL_SIM = set(ALLOWED)
ALLOWED.update({
    'io': SIM,
    'io/cache': ALL_SIM | {'io'},
    'io/scene': ALL_SIM | {'io', 'io/cache'},
    'io/exports': ALL_SIM | {'io', 'io/cache'},
    'render/gl': set(),
    'render/frame': ALL_SIM | {'render/gl'},
    'render/splat': ALL_SIM | {'render/gl', 'render/frame'},
    'render/mesh': ALL_SIM | {'render/frame', 'render/splat'},
    'render/solids': ALL_SIM | {'render/gl', 'render/frame'},
    'render/cdt': ALL_SIM | {'render/gl'},
    'render/rain': ALL_SIM | {'render/gl', 'render/frame'},
    'render/lights': ALL_SIM | {'render/gl', 'render/frame', 'render/solids'},
    'render/compose': ALL_SIM | {'render/gl', 'render/frame', 'render/splat', 'render/solids',
                                 'render/rain', 'render/lights'},
})
ALL_IO = {'io', 'io/cache', 'io/scene', 'io/exports'}
ALL_RENDER = {f for f in ALLOWED if f.startswith('render/')}
ALLOWED.update({
    'job/distributed/mpi': SIM | {'sim/ranks'},
    'job/distributed': ALL_SIM | ALL_IO | {'job/distributed/mpi'},
    'job': ALL_SIM | ALL_IO | ALL_RENDER | {'job/distributed'},
    'bench/sweep': None,  # a library of the benches and of `sphsplat bench`: anything but app/
    'app': None,          # the top: anything
})
PRODUCT = ('sim', 'io', 'render', 'job', 'app', 'shaders')
MAX_LINES = 500
MAX_SIM_ROOT = 11


def main(root):
    os.chdir(root)
    try:
        files = subprocess.check_output(['git', 'ls-files', '--cached', '--others', '--exclude-standard'],
                                        text=True, stderr=subprocess.DEVNULL).split('\n')
    except (OSError, subprocess.CalledProcessError):  # a source tree without git: every file
        files = [os.path.relpath(os.path.join(d, f)) for d, dirs, names in os.walk('.')
                 for f in names if not d.startswith(('./build', './.git'))]
    files = sorted({f for f in files if f and os.path.isfile(f)})  # (a merge lists some twice)
    breaches = []
    include = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
    for f in files:
        if not f.endswith(('.cpp', '.h')):
            continue
        text = open(f, encoding='utf-8', errors='replace').read()
        lines = text.count('\n')
        if lines > MAX_LINES:
            breaches.append(f'{f}: {lines} lines (at most {MAX_LINES})')
        here = os.path.dirname(f)
        top = here.split('/')[0]
        for m in include.finditer(text):
            inc = m.group(1)
            there = os.path.dirname(inc)
            if not there or there == here or not os.path.isfile(inc):
                continue  # same folder, or not ours (a system or generated header)
            if top in ('tests', 'bench', 'fuzz'):
                # The fuzzers run the command line itself, in-process (app/CommandLine.h).
                if there.split('/')[0] == 'app' and inc != 'app/CommandLine.h':
                    breaches.append(f'{f}: includes {inc} (tests, benches and fuzzers use libraries, not app/)')
                continue
            if here not in ALLOWED:
                breaches.append(f'{f}: folder {here} is not in the layer table (tests/layout/check_layout.py)')
                continue
            allowed = ALLOWED[here]
            if allowed is None:
                if here != 'app' and there.split('/')[0] == 'app':
                    breaches.append(f'{f}: includes {inc} (only app/ includes app/)')
                continue
            if there not in allowed:
                breaches.append(f'{f}: includes {inc} ({here} may include only '
                                f'{", ".join(sorted(allowed)) or "its own folder"})')
    sim_root = [f for f in files if os.path.dirname(f) == 'sim']
    if len(sim_root) > MAX_SIM_ROOT:
        breaches.append(f'sim/: {len(sim_root)} files at its root (at most {MAX_SIM_ROOT})')
    issue = re.compile(r'\bissues? #?[0-9]', re.I)
    for f in files:
        name = os.path.basename(f)
        if not (f.startswith(PRODUCT) or name == 'CMakeLists.txt'):
            continue
        for n, line in enumerate(open(f, encoding='utf-8', errors='replace'), 1):
            if issue.search(line):
                breaches.append(f'{f}:{n}: names an issue (history belongs in git): {line.strip()[:80]}')
    for b in breaches:
        print(b)
    if breaches:
        print(f'check_layout: {len(breaches)} breaches of the house rules (docs/architecture.md)')
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else '.'))
