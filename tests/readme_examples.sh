#!/usr/bin/env bash
# The README's commands run as written: each block between `<!-- readme-test: NAME -->`
# and `<!-- /readme-test -->` is run by bash (-euo pipefail) from the repository root,
# against a real `spheremap serve` on a free loopback port (127.0.0.1:8080 in the text
# becomes that port) and with build/cli/spheremap as the binary under test; then what
# it wrote is checked. Usage: readme_examples.sh SPHEREMAP
set -euo pipefail
spheremap=$1
cd "$(dirname "$0")/.."
root=$PWD
work=$(mktemp -d)
server=
trap 'kill $server 2> /dev/null || true; rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
source tests/start_server.sh
start_server "$work/server.log" --workers 1
hostport=${url#http://}
# Untracked files only: what the examples could write (edits to tracked files are not theirs).
untracked() { git status --porcelain --untracked-files=all 2> /dev/null | grep '^??' || true; }
before=$(untracked)

# block NAME: the text of one marked block, with the test's port and binary.
block() {
  sed -n "/^<!-- readme-test: $1 -->/,/^<!-- \/readme-test -->/p" README.md |
    sed -e '/^<!--/d' -e '/^```/d' -e "s|127\.0\.0\.1:8080|$hostport|g" \
        -e "s|build/cli/spheremap|$spheremap|g"
}
for name in curl-session cli; do
  [ -n "$(block $name)" ] || fail "README has no block marked readme-test: $name"
done

# The curl session: it cds into a temporary folder of its own; the check runs there.
{ block curl-session
  echo '[ "$(head -c 4 sphere.glb)" = glTF ] || { echo "sphere.glb is not a GLB"; exit 1; }'
  echo 'grep -q "\"bijective\": *true" metrics.json || { echo "metrics: not bijective"; exit 1; }'
  echo 'echo "curl session wrote: $(ls | tr "\n" " ")"'
} > "$work/curl-session.sh"
(cd "$root" && timeout 120 bash -euo pipefail "$work/curl-session.sh") ||
  fail "the README's curl session (see the output above)"

# The CLI block: every output it names must exist and be a GLB.
{ block cli
  echo 'for f in sphere remesh uv morph; do [ "$(head -c 4 "$out/$f.glb")" = glTF ] || { echo "$f.glb missing"; exit 1; }; done'
  echo 'grep -q "\"bijective\": *true" "$out/metrics.json" || { echo "cli metrics: not bijective"; exit 1; }'
  echo 'rm -rf "$out"'
} > "$work/cli.sh"
(cd "$root" && timeout 300 bash -euo pipefail "$work/cli.sh" > "$work/cli.out") ||
  fail "the README's CLI block: $(tail -5 "$work/cli.out")"
# Nothing written into the checkout (the examples work in temporary folders).
[ "$(untracked)" = "$before" ] ||
  fail "the README's examples left files in the checkout: $(untracked | head -5)"
echo "readme examples: ok"
