#!/usr/bin/env bash
# The page at GET / in headless Chromium (Debian chromium + npm playwright-core) against
# the real server on a loopback port: a GLB (a corpus model, or a generated one without
# the corpus), a generated textured GLB (its sphere must show its texture) and a .gltf
# chosen with its .bin and textures must end `succeeded` with a drawn canvas and no
# console error, and so must an OBJ; every view must frame its object (framing_test.mjs) and the "Try an
# example" button must map the built-in example; a file chosen while the previous one is
# being submitted wins (resubmit_test.mjs); a wrapped torus shows beside its envelope
# (compare_test.mjs). Exit 77 (skipped) without chromium or npm.
set -uo pipefail
spheremap=$1 make_meshes=$2 corpus=$3
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../start_server.sh"
. "$here/../npm_packages.sh"
fail() { echo "FAIL: $*"; [ -f "$work/server.log" ] && tail -5 "$work/server.log"; exit 1; }
chromium=${CHROMIUM:-/usr/bin/chromium}
[ -x "$chromium" ] || { echo "chromium not found: skipped (apt-get install chromium)"; exit 77; }
need_npm_packages "$here" playwright-core
work=$(mktemp -d)
trap 'kill $server 2> /dev/null; wait $server 2> /dev/null; rm -rf "$work"' EXIT
start_server "$work/server.log" --workers 1
url=$url/
"$make_meshes" "$work" > /dev/null || fail "make_test_meshes"
mesh=$corpus/spot.glb
[ -f "$mesh" ] || mesh=$work/icosphere4.glb
CHROMIUM=$chromium node "$here/page_test.mjs" "$url" "$mesh" || fail "page test on $(basename "$mesh")"
# A textured input keeps its texture on the sphere it comes back as.
EXPECT_TEXTURE=1 CHROMIUM=$chromium node "$here/page_test.mjs" "$url" "$work/textured_horseshoe.glb" ||
  fail "page test on a textured mesh"
box=$corpus/gltf-samples/BoxWithSpaces-glTF
if [ -d "$box" ]; then
  CHROMIUM=$chromium node "$here/page_test.mjs" "$url" "$box/Box With Spaces.gltf" "$box/Box With Spaces.bin" \
    "$box/glTF Logo With Spaces.png" "$box/Normal Map.png" "$box/Roughness Metallic.png" ||
    fail "page test on a .gltf with its .bin and textures"
fi
# An OBJ goes in as a glTF does (the service reads it; the page shows it once mapped).
obj=$(cd "$here/../.." && pwd)/examples/spot.obj
CHROMIUM=$chromium node "$here/page_test.mjs" "$url" "$obj" || fail "page test on an OBJ"
# Every view fits its object, on an elongated mesh and on a unit sphere; the example button.
CHROMIUM=$chromium node "$here/framing_test.mjs" "$url" "$work/ellipsoid.glb" "$work/icosphere4.glb" ||
  fail "framing test"
# A wrapped torus: the original beside its envelope, coloured by distance, the legend's
# max as metrics.json states it.
CHROMIUM=$chromium node "$here/compare_test.mjs" "$url" "$work/torus.glb" || fail "side-by-side test"
# A second file chosen before the first submission is answered: the page shows the second.
CHROMIUM=$chromium node "$here/resubmit_test.mjs" "$url" "$work/icosphere4.glb" "$work/ellipsoid.glb" ||
  fail "resubmit test"
echo "page: ok"
