#!/usr/bin/env bash
# The same input and options give byte-identical outputs, for any thread count: every
# output of every command, written with 1 and with 2 threads, compared byte for byte.
set -uo pipefail
spheremap=$1 make_meshes=$2 corpus=$3
fail() { echo "FAIL: $*"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mesh=$corpus/hand.glb
if [ ! -f "$mesh" ]; then
  "$make_meshes" "$work" > /dev/null || fail "make_test_meshes"
  mesh=$work/horseshoe.glb
fi
for threads in 1 2; do
  out=$work/t$threads
  mkdir -p "$out"
  "$spheremap" map "$mesh" -o "$out/sphere.glb" --threads $threads --quiet || fail "map"
  "$spheremap" map "$mesh" -o "$out/sphere_draco.glb" --draco --draco-position-bits 16 \
    --threads $threads --quiet || fail "map --draco"
  "$spheremap" map "$mesh" -o "$out/sphere.obj" --threads $threads --quiet || fail "map .obj"
  "$spheremap" remesh "$mesh" -o "$out/remesh.glb" --resolution 64 \
    --geometry-image "$out/geometry.png" --threads $threads --quiet || fail "remesh"
  "$spheremap" uv "$mesh" -o "$out/uv.glb" --threads $threads --quiet || fail "uv"
  "$spheremap" morph "$mesh" -o "$out/morph.glb" --threads $threads --quiet || fail "morph"
done
for file in sphere.glb sphere_draco.glb sphere.obj remesh.glb geometry.png uv.glb morph.glb; do
  cmp -s "$work/t1/$file" "$work/t2/$file" || fail "$file differs between 1 and 2 threads"
done
echo "deterministic: 7 outputs of $(basename "$mesh") byte-identical for 1 and 2 threads"
