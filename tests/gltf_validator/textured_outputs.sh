#!/usr/bin/env bash
# Textured glTF in, textured glTF out: sphere (.glb and .gltf), morph and remesh of a
# generated textured mesh (always) and of the duck, its Draco copy, Box With Spaces and
# CesiumMan (corpus), written by the CLI and by the service (a .gltf download), each
# checked by the Khronos validator (0 errors) and by check_look.mjs (materials, textures,
# images and TEXCOORD_0 of the input kept; the remesh has a base colour texture). Of a
# wrapped input: the remesh's normal map (with TANGENT), the sphere's (Draco too), UV
# mesh's and morph's COLOR_0.
# Usage: textured_outputs.sh SPHEREMAP MAKE_TEST_MESHES CORPUS. Exit 77 without npm.
set -uo pipefail
spheremap=$1 make_meshes=$2 corpus=$3
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../start_server.sh"
. "$here/../npm_packages.sh"
fail() { echo "FAIL: $*"; exit 1; }
need_npm_packages "$here" gltf-validator @gltf-transform/core
out=$(mktemp -d)
server=
trap '[ -n "$server" ] && kill $server 2> /dev/null; wait 2> /dev/null; rm -rf "$out"' EXIT
"$make_meshes" "$out" > /dev/null || fail "make_test_meshes"
inputs=("$out/textured_horseshoe.glb")
if [ -d "$corpus" ]; then
  for f in duck.glb duck.draco.glb "gltf-samples/BoxWithSpaces-glTF/Box With Spaces.gltf" \
           gltf-samples/CesiumMan-glTF-Draco/CesiumMan.gltf; do
    [ -f "$corpus/$f" ] && inputs+=("$corpus/$f")
  done
else
  echo "corpus not found: the generated textured mesh only"
fi
checks=()
for input in "${inputs[@]}"; do
  name=$(basename "${input%.*}" | tr ' .' '__')
  "$spheremap" map "$input" -o "$out/$name.sphere.glb" --quiet || fail "map $input"
  "$spheremap" map "$input" -o "$out/$name.sphere.gltf" --quiet || fail "map $input to .gltf"
  "$spheremap" morph "$input" -o "$out/$name.morph.glb" --quiet || fail "morph $input"
  "$spheremap" remesh "$input" -o "$out/$name.remesh.glb" --resolution 64 --quiet ||
    fail "remesh $input"
  checks+=("$input" "$out/$name.sphere.glb" "$out/$name.sphere.gltf" "$out/$name.morph.glb"
           "$out/$name.remesh.glb")
done

# The service: the same through a job, sphere downloaded as .gltf.
start_server "$out/server.log" --workers 1
curl -sf -D "$out/headers" -o "$out/service.sphere.glb" -H 'Prefer: wait=120' \
  -H 'Content-Type: model/gltf-binary' --data-binary "@$out/textured_horseshoe.glb" \
  "$url/v1/map?outputs=sphere,morph,remesh&resolution=32" || fail "POST /v1/map"
id=$(grep -i '^spheremap-job:' "$out/headers" | tr -d '\r' | cut -d' ' -f2)
grep -q '^HTTP/1.1 200' "$out/headers" || fail "the job did not succeed: $(cat "$out/headers")"
for a in sphere.gltf morph.glb remesh.glb; do
  curl -sf -o "$out/service.$a" "$url/v1/jobs/$id/artifacts/$a" || fail "download $a"
done
checks+=("$out/textured_horseshoe.glb" "$out/service.sphere.gltf" "$out/service.sphere.gltf"
         "$out/service.morph.glb" "$out/service.remesh.glb")

# A wrapped input (prepare=wrap): the envelope's remesh carries the input's base colour
# baked by closest point (CLI, and a service job whose original crosses the worker pipe).
"$spheremap" remesh "$out/textured_horseshoe.glb" -o "$out/wrapped.remesh.glb" --prepare wrap \
  --wrap-resolution 64 --resolution 32 --quiet || fail "remesh --prepare wrap"
curl -sf -D "$out/wrapped.headers" -o "$out/wrapped.sphere.glb" -H 'Prefer: wait=120' \
  -H 'Content-Type: model/gltf-binary' --data-binary "@$out/textured_horseshoe.glb" \
  "$url/v1/map?outputs=sphere,remesh&resolution=32&prepare=wrap&wrap_resolution=64" ||
  fail "POST /v1/map prepare=wrap"
grep -q '^HTTP/1.1 200' "$out/wrapped.headers" || fail "the wrap job did not succeed"
id=$(grep -i '^spheremap-job:' "$out/wrapped.headers" | tr -d '\r' | cut -d' ' -f2)
curl -sf -o "$out/service.wrapped.remesh.glb" "$url/v1/jobs/$id/artifacts/remesh.glb" ||
  fail "download the wrapped remesh"
for f in "$out/wrapped.remesh.glb" "$out/service.wrapped.remesh.glb"; do
  grep -aq baseColorTexture "$f" || fail "$f has no baked base colour"
  grep -aq distance_to_original "$f" || fail "$f has no distance_to_original"
  grep -aq normalTexture "$f" || fail "$f has no baked normal map"
  grep -aq '"TANGENT"' "$f" || fail "$f has no TANGENT for its normal map"
done
# normal_map=false (the service) and --no-normal-map (the CLI) leave the normal map out.
curl -sf -D "$out/plain.headers" -o /dev/null -H 'Prefer: wait=120' \
  -H 'Content-Type: model/gltf-binary' --data-binary "@$out/textured_horseshoe.glb" \
  "$url/v1/map?outputs=remesh&resolution=16&prepare=wrap&wrap_resolution=64&normal_map=false" ||
  fail "POST /v1/map normal_map=false"
grep -q '^HTTP/1.1 200' "$out/plain.headers" || fail "the normal_map=false job did not succeed"
id=$(grep -i '^spheremap-job:' "$out/plain.headers" | tr -d '\r' | cut -d' ' -f2)
curl -sf -o "$out/service.plain.remesh.glb" "$url/v1/jobs/$id/artifacts/remesh.glb" ||
  fail "download the remesh without normal map"
"$spheremap" remesh "$out/textured_horseshoe.glb" -o "$out/plain.remesh.glb" --prepare wrap \
  --wrap-resolution 64 --resolution 16 --no-normal-map --quiet || fail "remesh --no-normal-map"
for f in "$out/service.plain.remesh.glb" "$out/plain.remesh.glb"; do
  grep -aq baseColorTexture "$f" || fail "$f has no baked base colour"
  grep -aq normalTexture "$f" && fail "$f has a normal map though it was turned off"
done
# The sphere and UV mesh of an envelope carry the original's colour per vertex (COLOR_0).
"$spheremap" map "$out/textured_horseshoe.glb" -o "$out/wrapped.sphere.cli.glb" --prepare wrap \
  --wrap-resolution 64 --quiet || fail "map --prepare wrap"
"$spheremap" map "$out/textured_horseshoe.glb" -o "$out/wrapped.sphere.draco.glb" --prepare wrap \
  --wrap-resolution 64 --draco --quiet || fail "map --prepare wrap --draco"
"$spheremap" uv "$out/textured_horseshoe.glb" -o "$out/wrapped.uv.glb" --prepare wrap \
  --wrap-resolution 64 --quiet || fail "uv --prepare wrap"
"$spheremap" morph "$out/textured_horseshoe.glb" -o "$out/wrapped.morph.glb" --prepare wrap \
  --wrap-resolution 64 --quiet || fail "morph --prepare wrap"
for f in "$out/wrapped.sphere.cli.glb" "$out/wrapped.sphere.draco.glb" "$out/wrapped.uv.glb" \
         "$out/wrapped.morph.glb" "$out/wrapped.sphere.glb"; do
  grep -aq '"COLOR_0"' "$f" || fail "$f has no COLOR_0"
done

files=("$out/wrapped.remesh.glb" "$out/service.wrapped.remesh.glb" "$out/wrapped.sphere.cli.glb"
       "$out/wrapped.sphere.draco.glb" "$out/wrapped.uv.glb" "$out/wrapped.morph.glb"
       "$out/wrapped.sphere.glb")
for ((i = 0; i < ${#checks[@]}; i += 5)); do files+=("${checks[@]:i+1:4}"); done
node "$here/validate.mjs" "${files[@]}" || fail "the validator found errors"
node "$here/check_look.mjs" "${checks[@]}" || fail "an output lost the input's look"
