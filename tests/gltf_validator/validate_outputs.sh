#!/usr/bin/env bash
# Maps corpus meshes (OBJ, GLB, Draco GLB) to GLB with the tool and runs the Khronos glTF
# validator on every file written. Installs the validator from npm on first use.
# Exit 77 (skipped) without the corpus or without node/npm.
set -uo pipefail
spheremap=$1 corpus=$2
here=$(cd "$(dirname "$0")" && pwd)
[ -d "$corpus" ] || { echo "corpus not found: skipped"; exit 77; }
command -v npm > /dev/null || { echo "npm not found: skipped"; exit 77; }
if [ ! -d "$here/node_modules/gltf-validator" ] || [ ! -d "$here/node_modules/@gltf-transform/core" ]; then
  (cd "$here" && npm install --no-audit --no-fund --loglevel=error) || { echo "npm install failed"; exit 1; }
fi
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
