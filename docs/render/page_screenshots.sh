#!/usr/bin/env bash
# Screenshots of the page at GET / in each view (docs/images/page-{input,sphere,remesh,
# morph}.png): the framing test (tests/web/framing_test.mjs) run against a local server,
# which maps the built-in example with its "Try an example" button and saves each view.
# Needs a build (build/cli/spheremap, build/tests/make_test_meshes), Debian's chromium
# and npm (for tests/web's playwright-core). Usage: docs/render/page_screenshots.sh
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
spheremap=$repo/build/cli/spheremap
make_meshes=$repo/build/tests/make_test_meshes
. "$repo/tests/start_server.sh"
. "$repo/tests/npm_packages.sh"
command -v chromium > /dev/null || { echo "needs Debian's chromium (apt-get install chromium)"; exit 1; }
need_npm_packages "$repo/tests/web" playwright-core
work=$(mktemp -d)
trap 'kill $server 2> /dev/null; wait $server 2> /dev/null; rm -rf "$work"' EXIT
start_server "$work/server.log" --workers 1
"$make_meshes" "$work" > /dev/null
SCREENSHOTS=$repo/docs/images CHROMIUM=$(command -v chromium) \
  node "$repo/tests/web/framing_test.mjs" "$url/" "$work/ellipsoid.glb" "$work/icosphere4.glb"
echo "wrote docs/images/page-{input,sphere,remesh,morph}.png"
