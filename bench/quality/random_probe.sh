#!/usr/bin/env bash
# The random-shape probe of BENCHMARKS.md: SEEDS x COUNT random limbed shapes
# (make_test_meshes --random), each mapped by `spheremap map` at fast, standard and high;
# counts the maps that are not certified (exit code) or that left the stretch-optimized
# path, and summarizes stretch, area distortion, smallest spherical triangle and time.
#
#   bench/quality/random_probe.sh [count per seed] [seeds...]   (default: 25 1 2 3 4)
set -euo pipefail
cd "$(dirname "$0")/../.."
count=${1:-25}
if [ $# -gt 1 ]; then
  shift
  seeds=("$@")
else
  seeds=(1 2 3 4)
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
scripts/build.sh > /dev/null
for seed in "${seeds[@]}"; do build/tests/make_test_meshes "$work" --random "$count" "$seed"; done
for mesh in "$work"/random_*.obj; do
  for quality in fast standard high; do
    code=0
    build/cli/spheremap map "$mesh" -o "$work/out.obj" --quiet --quality "$quality" \
      --metrics "$work/m.json" 2> "$work/err.txt" || code=$?
    python3 - "$mesh" "$quality" "$code" "$work/m.json" << 'PY'
import json, os, sys
mesh, quality, code, path = sys.argv[1:]
d = json.load(open(path)) if os.path.exists(path) else {}
print(json.dumps({"mesh": os.path.basename(mesh), "quality": quality, "exit": int(code),
                  "faces": d.get("faces"), "optimized": d.get("optimized"),
                  "attempts": d.get("attempts"), "stretch": d.get("stretch", {}).get("l2"),
                  "area": d.get("area_distortion", {}).get("mean_abs_log"),
                  "min_area": d.get("min_spherical_area"),
                  "seconds": sum(d.get("seconds", {}).values())}))
PY
    rm -f "$work/m.json"
  done
done > "$work/rows.jsonl"
python3 - "$work/rows.jsonl" << 'PY'
import json, statistics, sys
rows = [json.loads(line) for line in open(sys.argv[1])]
print("| quality | maps | not certified | off the optimized path | faces | stretch L2 median / max | mean abs log area median / max | smallest triangle | seconds median / max |")
print("|---|---|---|---|---|---|---|---|---|")
for q in ("fast", "standard", "high"):
    r = [x for x in rows if x["quality"] == q]
    ok = [x for x in r if x["stretch"] is not None]
    s = [x["stretch"] for x in ok]; a = [x["area"] for x in ok]; t = [x["seconds"] for x in ok]
    f = [x["faces"] for x in ok]
    print(f"| {q} | {len(r)} | {sum(x['exit'] != 0 for x in r)} | "
          f"{sum(not x['optimized'] or x['attempts'] != 1 for x in ok)} | {min(f)}-{max(f)} | "
          f"{statistics.median(s):.2f} / {max(s):.2f} | {statistics.median(a):.2f} / {max(a):.2f} | "
          f"{min(x['min_area'] for x in ok):.1e} | {statistics.median(t):.2f} / {max(t):.2f} |")
PY
