#!/usr/bin/env bash
# Renders the README's images from real outputs: MESH (default spot) mapped, remeshed,
# texture-mapped and morphed by the tool, each GLB drawn by three.js in headless Chromium
# (Debian's chromium, software WebGL). Writes docs/images/*.png.
# Usage: docs/render/render.sh [MESH]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
mesh=${1:-$repo/../shared/meshes/spot.obj}
spheremap=$repo/build/cli/spheremap
command -v chromium > /dev/null || { echo "needs Debian's chromium (apt-get install chromium)"; exit 1; }
[ -d "$here/node_modules/three" ] || (cd "$here" && npm install --no-audit --no-fund --loglevel=error)
work=$here/work
rm -rf "$work" && mkdir -p "$work"
trap 'kill $server 2>/dev/null || true; rm -rf "$work"' EXIT
"$spheremap" map "$mesh" -o "$work/sphere.glb" --quiet
"$spheremap" remesh "$mesh" -o "$work/remesh.glb" --resolution 32 --quiet
"$spheremap" uv "$mesh" -o "$work/uv.glb" --quiet
"$spheremap" morph "$mesh" -o "$work/morph.glb" --quiet
cp "$mesh" "$work/" 2>/dev/null || true
port=18765
node "$here/serve.mjs" $port "$here" &
server=$!
sleep 0.5
shot() {  # NAME QUERY
  chromium --headless=new --no-sandbox --disable-gpu --use-angle=swiftshader \
    --enable-unsafe-swiftshader --disable-background-networking --disable-component-update \
    --disable-sync --no-first-run --disable-quic --user-data-dir="$work/profile" \
    --hide-scrollbars --window-size=640,480 --virtual-time-budget=20000 \
    --screenshot="$repo/docs/images/$1.png" "http://127.0.0.1:$port/view.html?$2" 2> /dev/null
  echo "wrote docs/images/$1.png"
}
shot sphere "model=work/sphere.glb&mode=sphere"
shot remesh "model=work/remesh.glb&mode=remesh"
shot uv "model=work/uv.glb&mode=uv"
shot morph "model=work/morph.glb&mode=morph&weight=0.5"
