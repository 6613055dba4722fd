#!/usr/bin/env bash
# Runs the corpus benchmark on every valid corpus mesh (OBJ; igea_loop1 from its Draco GLB)
# and prints the table that
# BENCHMARKS.md quotes, after a line describing the machine.
# Usage: bench/run.sh [corpus dir] [paper iteration cap]
set -euo pipefail
cd "$(dirname "$0")/.."
corpus=$(realpath "${1:-../shared/meshes}")
cap=${2:-5000}
scripts/build.sh > /dev/null
echo "Machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(free -g | awk '/Mem/{print $2}') GiB; $(date -u +%Y-%m-%d)"
echo "Command: bench/run.sh $corpus $cap"
echo
meshes=()
for m in box spot_control cylinder knight horse_quad spot_quad duck spot cheburashka hand beast \
         armadillo horse scorpion igea; do
  [ -f "$corpus/$m.obj" ] && meshes+=("$corpus/$m.obj")
done
# igea_loop1 ships as Draco only: read it as such.
[ -f "$corpus/igea_loop1.draco.glb" ] && meshes+=("$corpus/igea_loop1.draco.glb")
build/bench/corpus_bench --paper-cap "$cap" --paper-seconds 60 "${meshes[@]}"
