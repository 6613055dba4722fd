#!/usr/bin/env bash
# The quality table of BENCHMARKS.md: every valid corpus mesh and the generated stress set,
# and three random limbed shapes (make_test_meshes --random 3 1), mapped at --quality
# fast, standard and high, judged beside Praun & Hoppe's SphereParam
# (fastest and default effort) by the same code (bench/quality_bench.cpp): time, cost in
# CSR sweeps, stretch L2, mean |log area|, dilatation K, float32 bijectivity, remesh
# Hausdorff at 131,072 triangles.
#
#   bench/quality/run.sh [corpus dir] [out dir]
#
# Praun & Hoppe runs only when ../shared/tools/praun-hoppe is there (one thread, as its
# README measures it); it is a benchmark anchor, never part of the product. Its outputs
# are cached in OUT/ph (delete them to re-measure). Prints JSON lines, then the table.
set -euo pipefail
cd "$(dirname "$0")/../.."
corpus=$(realpath "${1:-../shared/meshes}")
out=$(realpath -m "${2:-build/quality-bench}")
ph_tool=$(realpath -m ../shared/tools/praun-hoppe/sphere_param.sh)
scripts/build.sh > /dev/null
mkdir -p "$out/meshes" "$out/ph"
build/tests/make_test_meshes "$out/meshes" --stress
rm -f "$out"/meshes/random_*.obj
build/tests/make_test_meshes "$out/meshes" --random 3 1  # shapes no one tuned for
meshes=()
for m in box spot_control cylinder knight horse_quad spot_quad duck spot cheburashka hand beast \
         armadillo horse scorpion igea; do
  [ -f "$corpus/$m.obj" ] && meshes+=("$corpus/$m.obj")
done
for m in "$out"/meshes/stress_*.obj "$out"/meshes/random_*.obj; do meshes+=("$m"); done
echo "Machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); $(date -u +%Y-%m-%d)" >&2
: > "$out/results.jsonl"
for mesh in "${meshes[@]}"; do
  name=$(basename "$mesh" .obj)
  args=()
  if [ -x "$ph_tool" ]; then
    for effort in 0 2; do
      ph="$out/ph/$name.e$effort.obj"
      if [ ! -f "$ph" ]; then
        # SphereParam stops on beast's polygons: give it a fan triangulation with the same
        # vertices in the same order (bench/quality/triangulate_obj.py).
        input=$mesh
        if grep -qE '^f( +[^ ]+){4,}' "$mesh"; then
          input="$out/ph/$name.tri.obj"
          python3 bench/quality/triangulate_obj.py "$mesh" "$input"
        fi
        OMP_NUM_THREADS=1 "$ph_tool" "$input" "$ph" "$effort" > "$out/ph/$name.e$effort.json" ||
          echo '{"failed": true}' > "$out/ph/$name.e$effort.json"
      fi
      [ -f "$ph" ] && args+=(--sphere "$ph" --label "praun-hoppe-e$effort")
    done
  fi
  build/bench/quality_bench --quality fast --quality standard --quality high "${args[@]}" "$mesh" |
    tee -a "$out/results.jsonl"
done
python3 bench/quality/table.py "$out/results.jsonl" "$out/ph"
