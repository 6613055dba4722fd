#!/usr/bin/env bash
# Maps corpus meshes (OBJ, GLB, Draco GLB) to GLB with the tool and runs the Khronos glTF
# validator on every file written. Installs the validator from npm on first use.
# Exit 77 (skipped) without the corpus or without node/npm.
set -uo pipefail
spheremap=$1 corpus=$2
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../npm_packages.sh"
[ -d "$corpus" ] || { echo "corpus not found: skipped"; exit 77; }
need_npm_packages "$here" gltf-validator @gltf-transform/core
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
files=()
for input in box.glb duck.glb spot_control.obj cylinder.obj spot.draco.glb horse_quad.glb knight.obj; do
  [ -f "$corpus/$input" ] || continue
  name=${input%%.*}.${input#*.}
  "$spheremap" map "$corpus/$input" -o "$out/${name//./_}.glb" --quiet || { echo "map $input failed"; exit 1; }
  files+=("$out/${name//./_}.glb")
done
# A Draco-compressed output too (the validator checks its structure; it does not decode Draco).
if [ -f "$corpus/spot.obj" ]; then
  "$spheremap" map "$corpus/spot.obj" -o "$out/spot_draco.glb" --draco --quiet || { echo "map --draco failed"; exit 1; }
  files+=("$out/spot_draco.glb")
fi
node "$here/validate.mjs" "${files[@]}"
