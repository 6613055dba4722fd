#!/usr/bin/env bash
# The JavaScript client's tests against a real server on a loopback port, then `npm pack`
# and an install of the packed tarball in an empty project that imports it.
# Exit 77 (skipped) without npm.
set -uo pipefail
spheremap=$1 make_meshes=$2
here=$(cd "$(dirname "$0")/.." && pwd)
. "$here/../../tests/start_server.sh"
. "$here/../../tests/npm_packages.sh"
fail() { echo "FAIL: $*"; exit 1; }
need_npm_packages --ci "$here" @gltf-transform/functions
work=$(mktemp -d)
trap 'kill $server 2> /dev/null; wait $server 2> /dev/null; rm -rf "$work"' EXIT
"$make_meshes" "$work" > /dev/null || fail "make_test_meshes"
start_server "$work/server.log" --workers 2
# The types are made from api/openapi.yaml: the committed ones must be up to date.
(cd "$here" && npx --no-install openapi-typescript ../../api/openapi.yaml -o "$work/openapi.d.ts" > /dev/null 2>&1) ||
  fail "openapi-typescript"
cmp -s "$work/openapi.d.ts" "$here/src/openapi.d.ts" || fail "src/openapi.d.ts is stale: npm run types"
(cd "$here" && npx --no-install tsc --noEmit --strict --module nodenext --moduleResolution nodenext \
  src/index.d.ts src/gltf-transform.d.ts) || fail "the type declarations do not check"
(cd "$here" && SPHEREMAP_URL=$url SPHEREMAP_MESH=$work/icosphere4.glb \
  SPHEREMAP_SLOW_MESH=$work/horseshoe.glb node --test test/) || fail "client tests"

# npm pack gives a package that installs and imports elsewhere.
(cd "$here" && npm pack --pack-destination "$work" --loglevel=error > /dev/null) || fail "npm pack"
mkdir -p "$work/consumer" && cd "$work/consumer" && echo '{"type":"module","private":true}' > package.json
npm install --no-audit --no-fund --loglevel=error "$work"/spheremap-client-*.tgz > /dev/null || fail "install the tarball"
SPHEREMAP_URL=$url node --input-type=module -e "
  import { readFileSync } from 'node:fs';
  const { SpheremapClient } = await import('spheremap-client');
  const job = await new SpheremapClient({ endpoint: process.env.SPHEREMAP_URL }).submit(readFileSync('$work/icosphere2.glb'));
  if (!/^[0-9a-f]{32}$/.test(job.id)) process.exit(1);
  console.log('installed package submits: ' + job.id);
" || fail "the installed package does not work"
echo "js client: ok"
