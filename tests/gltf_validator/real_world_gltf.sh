#!/usr/bin/env bash
# glTF as pipelines make it: corpus meshes run through gltfpack (default output:
# KHR_mesh_quantization; -cc: EXT_meshopt_compression too) and gltf-transform (quantize,
# meshopt) at test time must map certified, with stretch within 3% of the original's;
# the Khronos samples as shipped (.gltf + .bin) map or are refused with the fix; `info`
# answers JSON even for a file it cannot read. Exit 77 (skipped) without the corpus or npm.
set -uo pipefail
spheremap=$1 corpus=$2
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../npm_packages.sh"
fail() { echo "FAIL: $*"; exit 1; }
[ -d "$corpus" ] || { echo "corpus not found: skipped"; exit 77; }
need_npm_packages "$here" .bin/gltfpack .bin/gltf-transform
bin=$here/node_modules/.bin
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
stretch() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['stretch']['l2'])" "$1"; }

for mesh in spot hand; do
  [ -f "$corpus/$mesh.glb" ] || continue
  "$spheremap" map "$corpus/$mesh.glb" -o "$out/$mesh.glb" --metrics "$out/$mesh.json" --quiet ||
    fail "$mesh.glb"
  reference=$(stretch "$out/$mesh.json")
  "$bin/gltfpack" -i "$corpus/$mesh.glb" -o "$out/${mesh}_pack.glb" > /dev/null || fail "gltfpack"
  "$bin/gltfpack" -i "$corpus/$mesh.glb" -o "$out/${mesh}_pack_cc.glb" -cc > /dev/null || fail "gltfpack -cc"
  "$bin/gltf-transform" quantize "$corpus/$mesh.glb" "$out/${mesh}_quantize.glb" > /dev/null 2>&1 ||
    fail "gltf-transform quantize"
  "$bin/gltf-transform" meshopt "$corpus/$mesh.glb" "$out/${mesh}_meshopt.glb" > /dev/null 2>&1 ||
    fail "gltf-transform meshopt"
  # A quantized .gltf with its .bin beside it, as gltf-transform writes a .gltf.
  mkdir -p "$out/split"
  "$bin/gltf-transform" quantize "$corpus/$mesh.glb" "$out/split/${mesh}_quantize.gltf" > /dev/null 2>&1 ||
    fail "gltf-transform quantize to .gltf"
  ls "$out/split/"*.bin > /dev/null 2>&1 || fail "gltf-transform wrote no .bin"
  "$spheremap" map "$out/split/${mesh}_quantize.gltf" -o "$out/s.glb" --quiet || fail "$mesh quantized .gltf + .bin"
  grep -q KHR_mesh_quantization "$out/${mesh}_pack.glb" || fail "gltfpack did not quantize"
  grep -q EXT_meshopt_compression "$out/${mesh}_pack_cc.glb" || fail "gltfpack -cc did not use meshopt"
  for variant in pack pack_cc quantize meshopt; do
    file=$out/${mesh}_$variant.glb
    "$spheremap" map "$file" -o "$out/s.glb" --metrics "$out/m.json" --quiet ||
      fail "$mesh $variant: exit $?"
    s=$(stretch "$out/m.json")
    python3 -c "import sys; a,b=map(float,sys.argv[1:]); sys.exit(0 if abs(a-b) <= 0.03*b else 1)" \
      "$s" "$reference" || fail "$mesh $variant: stretch $s vs $reference"
    echo "$mesh $variant: certified, stretch $s (original $reference)"
  done
done

samples=$corpus/gltf-samples
if [ -d "$samples" ]; then
  "$spheremap" map "$samples/BoxWithSpaces-glTF/Box With Spaces.gltf" -o "$out/box.glb" --quiet ||
    fail "Box With Spaces.gltf"
  "$spheremap" map "$samples/CesiumMan-glTF-Draco/CesiumMan.gltf" -o "$out/man.glb" --quiet ||
    fail "CesiumMan Draco .gltf"
  # The fish's body and two eyes: every part maps by default; one part at a time refuses
  # it and names parts as the fix.
  "$spheremap" map "$samples/BarramundiFish-glTF/BarramundiFish.gltf" -o "$out/f.glb" \
    --metrics "$out/f.json" --quiet || fail "fish parts"
  grep -q '"parts_mapped": 3' "$out/f.json" || fail "fish: 3 parts mapped"
  err=$("$spheremap" map "$samples/BarramundiFish-glTF/BarramundiFish.gltf" -o "$out/f.glb" \
    --prepare repair 2>&1)
  [ $? -eq 2 ] && [[ "$err" == *"fix: --prepare parts"* ]] || fail "fish hint: $err"
  "$spheremap" map "$samples/BarramundiFish-glTF/BarramundiFish.gltf" -o "$out/f.glb" \
    --largest-component --quiet || fail "fish body"
  # A copy whose buffer URI climbs out of its folder is refused; nothing is read.
  mkdir -p "$out/escape/inner"
  sed 's|"uri" *: *"BarramundiFish.bin"|"uri": "../../BarramundiFish.bin"|' \
    "$samples/BarramundiFish-glTF/BarramundiFish.gltf" > "$out/escape/inner/fish.gltf"
  cp "$samples/BarramundiFish-glTF/BarramundiFish.bin" "$out/"
  "$spheremap" info "$out/escape/inner/fish.gltf" > "$out/info.json" 2> /dev/null
  [ $? -eq 2 ] || fail "escape exit code"
  python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert d['mappable'] is False and \"'..' segment\" in d['error']['message'], d" \
    "$out/info.json" || fail "escape refused in JSON"
fi
# A GLB 1.0 (KHR_binary_glTF's container) of a tetrahedron, ids for indices, its buffer a
# data: URI: read through its glTF 2.0 upgrade, it maps certified, with a warning saying so.
v1_json='{"asset":{"version":"1.0"},"buffers":{"b":{"byteLength":72,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAACAAEAAAABAAMAAQACAAMAAAADAAIA"}},"bufferViews":{"v":{"buffer":"b","byteOffset":0,"byteLength":48},"i":{"buffer":"b","byteOffset":48,"byteLength":24}},"accessors":{"p":{"bufferView":"v","byteOffset":0,"byteStride":12,"componentType":5126,"count":4,"type":"VEC3"},"x":{"bufferView":"i","byteOffset":0,"componentType":5123,"count":12,"type":"SCALAR"}},"meshes":{"m":{"primitives":[{"attributes":{"POSITION":"p"},"indices":"x"}]}},"nodes":{"n":{"meshes":["m"]}},"scenes":{"s":{"nodes":["n"]}},"scene":"s"}'
le32() { printf "\\$(printf %03o $(($1 & 255)))\\$(printf %03o $(($1 >> 8 & 255)))\\$(printf %03o $(($1 >> 16 & 255)))\\$(printf %03o $(($1 >> 24 & 255)))"; }
{ printf 'glTF'; le32 1; le32 $((20 + ${#v1_json})); le32 ${#v1_json}; le32 0; printf '%s' "$v1_json"; } > "$out/v1.glb"
"$spheremap" map "$out/v1.glb" -o "$out/v1_sphere.glb" --metrics "$out/v1.json" --quiet ||
  fail "glTF 1.0 map: exit $?"
grep -q '"bijective": true' "$out/v1.json" || fail "glTF 1.0 map not certified"
grep -q 'read as glTF 1.0' "$out/v1.json" || fail "glTF 1.0 not said in the metrics' input_warnings"
echo "real-world glTF: ok"
