#!/usr/bin/env bash
# --time-limit as a process sees it: a limit that has passed before the map starts (it
# counts from the start of reading) stops the map in its first stage, the hierarchy; the
# command still writes a complete map and its metrics, exits 3, and names the verdict and
# the stage on stderr and in the metrics. (No wall-clock assertion: the overruns measured
# on large meshes are in BENCHMARKS.md.)
set -uo pipefail
spheremap=$1 make_test_meshes=$2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$make_test_meshes" "$out" || exit 1
err=$("$spheremap" map "$out/icosphere4.glb" -o "$out/sphere.obj" --metrics "$out/m.json" \
  --time-limit 0.000001 --quiet 2>&1 >/dev/null)
code=$?
echo "$err"
[ "$code" -eq 3 ] || { echo "expected exit code 3, got $code"; exit 1; }
[[ "$err" == *"time_limit: the map stopped at the time limit during its hierarchy stage"* ]] ||
  { echo "expected the time_limit verdict naming the hierarchy stage"; exit 1; }
grep -q '"stop_reason": "time_limit"' "$out/m.json" || { echo "expected stop_reason time_limit"; exit 1; }
grep -q '"stopped_in": "hierarchy"' "$out/m.json" || { echo "expected stopped_in hierarchy"; exit 1; }
[ "$(grep -c '^v ' "$out/sphere.obj")" -eq 2562 ] || { echo "expected all 2562 vertices written"; exit 1; }

# The limit stops an envelope too (it has no partial map to write): a torus wrapped at
# 512 voxels across takes tens of seconds; with a limit of 0.5 s the command ends with
# exit 3 and the time_limit verdict naming the envelope, long before the envelope would.
start=$(date +%s)
err=$("$spheremap" map "$out/torus.glb" -o "$out/wrapped.obj" --prepare wrap \
  --wrap-resolution 512 --time-limit 0.5 --quiet 2>&1 >/dev/null)
code=$?
elapsed=$(($(date +%s) - start))
echo "$err (after ${elapsed} s)"
[ "$code" -eq 3 ] || { echo "expected exit code 3 for the envelope, got $code"; exit 1; }
[[ "$err" == *"time_limit: the time limit (0.5 s) passed while an envelope was being built"* ]] ||
  { echo "expected the time_limit verdict naming the envelope"; exit 1; }
[ "$elapsed" -lt 20 ] || { echo "the envelope was not stopped (${elapsed} s)"; exit 1; }
[ ! -e "$out/wrapped.obj" ] || { echo "expected nothing written"; exit 1; }

# The rest of the preparation is stopped too (no partial result either), once the limit has
# passed by as much again or by a second: 256 GPU instances of an open sphere (1.3M
# triangles, 256 parts) take seconds to prepare (`info`: 3.8 s here); with a limit of 0.2 s
# the command ends at about 1.2 s with exit 3, naming the preparation and the mesh to map
# once.
"$make_test_meshes" "$out" --instanced 256 || exit 1
start=$(date +%s)
err=$("$spheremap" map "$out/instanced_256.glb" -o "$out/instanced.obj" --time-limit 0.2 \
  --quiet 2>&1 >/dev/null)
code=$?
elapsed=$(($(date +%s) - start))
echo "$err (after ${elapsed} s)"
[ "$code" -eq 3 ] || { echo "expected exit code 3 for the preparation, got $code"; exit 1; }
[[ "$err" == *"passed while the input was being prepared (stopped at 1.2 s); nothing was mapped"* ]] ||
  { echo "expected the time_limit verdict naming the preparation"; exit 1; }
[[ "$err" == *"the scene draws mesh 0 256 times: --mesh 0 maps it once"* ]] ||
  { echo "expected the mesh to map once"; exit 1; }
[ "$elapsed" -lt 20 ] || { echo "the preparation was not stopped (${elapsed} s)"; exit 1; }
[ ! -e "$out/instanced.obj" ] || { echo "expected nothing written"; exit 1; }
echo "ok"
