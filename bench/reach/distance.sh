#!/usr/bin/env bash
# Reach II's fidelity bench: per file, the remesh at N=128 under the default options
# (`spheremap remesh FILE -o OUT.glb --resolution 128 --time-limit 30 --threads 1`) and
# its two-sided distance to the ORIGINAL file (bench/remesh_distance), relative to the
# original's diagonal. Files: the ones the auto run wrapped (decided wrap or parts+wrap in
# RESULTS), sorted by path, every STEP-th (default 3, from the first). One at a time.
# DECIDED=exact,repair,parts (comma-separated) takes the files auto decided so instead;
# a --prepare method (DECIDED=auto) takes every file the run prepared with it (a metrics file).
# Prints one TSV line per file, then: certified share, share within 2% (certified and
# Hausdorff <= 0.02), median/p90/max Hausdorff, median/max seconds. KEEP=DIR keeps each
# file's metrics JSON and distances in DIR.
# Usage: [STEP=3] [DECIDED=wrap,parts+wrap] [KEEP=DIR] [TIME_LIMIT=30] bench/reach/distance.sh SPHEREMAP REMESH_DISTANCE SETDIR RESULTS
set -euo pipefail
spheremap=$(realpath "$1")
distance=$(realpath "$2")
setdir=$(realpath "$3")
results=$(realpath "$4")
python3 - "$spheremap" "$distance" "$setdir" "$results" << 'EOF'
import json, os, subprocess, sys, tempfile, time
spheremap, distance, setdir, results = sys.argv[1:5]
step = int(os.environ.get("STEP", "3"))
limit = os.environ.get("TIME_LIMIT", "30")  # seconds; a loaded machine needs more
keep = os.environ.get("KEEP", "")  # a folder: each file's metrics and distances kept there
decided = os.environ.get("DECIDED", "wrap,parts+wrap").split(",")
files = []
# Columns by the header's names: run.sh added `method` before `decided`, and a fixed index
# (12) then read `method`, so DECIDED=wrap selected nothing.
lines = open(results).read().splitlines()
column = {name: i for i, name in enumerate(lines[0].split("\t"))}
for line in lines[1:]:
    f = line.split("\t")
    method = f[column["method"]] if "method" in column else ""
    if f[column["decided"]] in decided or method in decided:
        files.append(os.path.join(setdir, f[0], f[1], f[2]))
files = sorted(files)[::step]
print("exit\tseconds\thausdorff\torig->out\tout->orig\trms\tfile")
rows = []
for path in files:
    with tempfile.TemporaryDirectory() as tmp:
        start = time.monotonic()
        p = subprocess.run(["timeout", "120", spheremap, "remesh", path, "-o", f"{tmp}/r.glb",
                            "--resolution", "128", "--time-limit", limit, "--quiet",
                            "--threads", "1", "--metrics", f"{tmp}/m.json"], capture_output=True, text=True, errors="replace")
        seconds = time.monotonic() - start
        d = {}
        if os.path.exists(f"{tmp}/r.glb"):
            q = subprocess.run([distance, path, f"{tmp}/r.glb"], capture_output=True, text=True)
            if q.returncode == 0:
                d = json.loads(q.stdout)
        if keep:  # the run's metrics and distances, for the causes
            name = os.path.relpath(path, setdir).replace("/", "+")
            if os.path.exists(f"{tmp}/m.json"):
                os.replace(f"{tmp}/m.json", f"{keep}/{name}.metrics.json")
            json.dump(d, open(f"{keep}/{name}.distance.json", "w"))
    h = d.get("hausdorff", float("nan"))
    rows.append((p.returncode, seconds, h))
    print(f"{p.returncode}\t{seconds:.2f}\t{h:.4f}\t{d.get('original_to_output', float('nan')):.4f}"
          f"\t{d.get('output_to_original', float('nan')):.4f}\t{d.get('rms', float('nan')):.4f}"
          f"\t{os.path.relpath(path, setdir)}", flush=True)
def pct(xs, q):
    xs = sorted(xs)
    return xs[min(len(xs) - 1, int(q * len(xs)))] if xs else float("nan")
n = len(rows)
certified = sum(1 for r in rows if r[0] == 0)
within = sum(1 for r in rows if r[0] == 0 and r[2] <= 0.02)
hs = [r[2] for r in rows if r[2] == r[2]]
ts = [r[1] for r in rows]
print(f"# files {n}  certified {certified}  within 2% {within} ({100 * within / max(n, 1):.0f}%)"
      f"  hausdorff median {pct(hs, 0.5):.4f} p90 {pct(hs, 0.9):.4f} max {max(hs, default=0):.4f}"
      f"  seconds median {pct(ts, 0.5):.2f} max {max(ts, default=0):.2f}")
EOF
