#!/usr/bin/env bash
# The three assets built on the map (remesh, uv, morph) for every valid corpus mesh up
# to 100K faces (generated meshes without the corpus): each written by the tool, checked
# by the Khronos glTF validator (0 errors) and decoded by gltf-transform; the remesh read
# back by `spheremap info` (our own validator: closed, manifold, genus 0); the UV map has
# no flipped triangle; a wrapped torus's morph (with _DISTANCE) too.
# Usage: validate_assets.sh SPHEREMAP MAKE_TEST_MESHES CORPUS
set -uo pipefail
spheremap=$1 make_meshes=$2 corpus=$3
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../npm_packages.sh"
need_npm_packages "$here" gltf-validator @gltf-transform/core
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
inputs=()
if [ -d "$corpus" ]; then
  for m in box spot_control cylinder knight horse_quad spot_quad duck spot cheburashka hand \
           beast armadillo horse scorpion; do
    [ -f "$corpus/$m.obj" ] && inputs+=("$corpus/$m.obj")
  done
else
  echo "corpus not found: generated meshes only"
fi
"$make_meshes" "$out"
inputs+=("$out/icosphere4.glb" "$out/horseshoe.glb")
failed=0
files=()
for input in "${inputs[@]}"; do
  name=$(basename "${input%.*}")
  for kind in remesh uv morph; do
    # --quality fast: what is checked here is the files (every map is certified at every
    # quality); 48 maps at the default quality were the sanitizer pass's longest test.
    extra=(--quality fast)
    [ "$kind" = remesh ] && extra+=(--resolution 128)
    if ! "$spheremap" "$kind" "$input" -o "$out/$name.$kind.glb" --metrics "$out/$name.$kind.json" \
        "${extra[@]}" --quiet; then
      echo "FAIL: $kind $name"; failed=1; continue
    fi
    files+=("$out/$name.$kind.glb")
  done
  info=$("$spheremap" info "$out/$name.remesh.glb")
  if ! grep -q '"mappable": true' <<< "$info" || ! grep -q '"genus": 0' <<< "$info"; then
    echo "FAIL: $name remesh is not closed genus 0: $info"; failed=1
  fi
  if ! grep -q '"flipped_triangles": 0' "$out/$name.uv.json"; then
    echo "FAIL: $name has flipped UV triangles"; failed=1
  fi
done
# The morph of an envelope carries the application-specific _DISTANCE attribute: still clean.
if "$spheremap" morph "$out/torus.glb" --prepare wrap -o "$out/torus.wrap.morph.glb" \
    --metrics "$out/torus.wrap.morph.json" --quiet; then
  grep -q '"_DISTANCE"' "$out/torus.wrap.morph.json" || { echo "FAIL: wrapped morph without _DISTANCE"; failed=1; }
  files+=("$out/torus.wrap.morph.glb")
else
  echo "FAIL: morph torus --prepare wrap"; failed=1
fi
node "$here/validate.mjs" "${files[@]}" || failed=1
exit $failed
