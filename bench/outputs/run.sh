#!/usr/bin/env bash
# The assets built on the map, per valid corpus mesh up to 100K faces: remesh distance
# to the original (RMS and Hausdorff, relative to the bounding-box diagonal) at N = 128
# and 256, and the time of each output (the map's own time excluded; 2 threads).
# Prints the table BENCHMARKS.md quotes. Usage: bench/outputs/run.sh [corpus dir]
set -euo pipefail
cd "$(dirname "$0")/../.."
corpus=$(realpath "${1:-../shared/meshes}")
scripts/build.sh > /dev/null
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "Machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); $(date -u +%Y-%m-%d)"
echo "Command: bench/outputs/run.sh $corpus"
echo
echo "| mesh | faces | map s | N=128 RMS | N=128 Hausdorff | N=128 s | N=256 RMS | N=256 Hausdorff | N=256 s | closed genus 0 | uv s | split tris | flipped | stretch L2 | morph s |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
field() { node -e "const m=require('$1'); console.log(($2))"; }
for m in box spot_control cylinder knight horse_quad spot_quad duck spot cheburashka hand beast \
         armadillo horse scorpion; do
  [ -f "$corpus/$m.obj" ] || continue
  for n in 128 256; do
    build/cli/spheremap remesh "$corpus/$m.obj" -o "$out/r$n.glb" --resolution $n \
      --metrics "$out/r$n.json" --quiet
  done
  build/cli/spheremap uv "$corpus/$m.obj" -o "$out/uv.glb" --metrics "$out/uv.json" --quiet
  build/cli/spheremap morph "$corpus/$m.obj" -o "$out/morph.glb" --metrics "$out/morph.json" --quiet
  r1=$out/r128.json r2=$out/r256.json
  printf '| %s | %s | %.2f | %.5f | %.4f | %.2f | %.5f | %.4f | %.2f | %s | %.3f | %s | %s | %.2f | %.3f |\n' \
    "$m" "$(field $r1 'm.map.faces')" "$(field $r1 'm.map.seconds.mapping')" \
    "$(field $r1 'm.remesh.distance.rms')" "$(field $r1 'm.remesh.distance.hausdorff')" \
    "$(field $r1 'm.remesh.seconds.total')" \
    "$(field $r2 'm.remesh.distance.rms')" "$(field $r2 'm.remesh.distance.hausdorff')" \
    "$(field $r2 'm.remesh.seconds.total')" \
    "$(field $r2 'm.remesh.closed_genus0 && m.remesh.unlocated_samples === 0 ? "yes" : "NO"')" \
    "$(field $out/uv.json 'm.uv.seconds')" "$(field $out/uv.json 'm.uv.split_triangles')" \
    "$(field $out/uv.json 'm.uv.flipped_triangles')" "$(field $out/uv.json 'm.uv.stretch.l2')" \
    "$(field $out/morph.json 'm.morph.seconds')"
done
