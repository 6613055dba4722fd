#!/usr/bin/env bash
# The command-line contract: help, exit codes for usage errors and missing files, info.
set -uo pipefail
spheremap=$1
fail() { echo "FAIL: $*"; exit 1; }
"$spheremap" --help | grep -q "spheremap map INPUT" || fail "--help"
"$spheremap" map --help | grep -q -- "--method" || fail "map --help lists options"
"$spheremap" map --help | grep -q "default 0.25" || fail "map --help shows defaults"
"$spheremap" map x.obj -o y.obj --bogus 2>/dev/null; [ $? -eq 1 ] || fail "unknown option exit 1"
"$spheremap" map x.obj 2>/dev/null; [ $? -eq 1 ] || fail "missing -o exit 1"
"$spheremap" map /nonexistent.obj -o /tmp/y.obj 2>/dev/null; [ $? -eq 2 ] || fail "missing file exit 2"
msg=$("$spheremap" map x.obj -o y.obj --alpha 3 2>&1); [ $? -eq 1 ] || fail "range exit 1"
[[ "$msg" == *"--alpha must be a number in [0, 1]"* ]] || fail "range check names option: $msg"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
printf 'v 1 1 1\nv 1 -1 -1\nv -1 1 -1\nv -1 -1 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n' > "$tmp/tet.obj"
"$spheremap" info "$tmp/tet.obj" > "$tmp/info.json" || fail "info exit 0"
grep -q '"genus": 0' "$tmp/info.json" || fail "info genus"
"$spheremap" map "$tmp/tet.obj" -o "$tmp/s.obj" --metrics "$tmp/m.json" || fail "map tetrahedron"
grep -q '"bijective": true' "$tmp/m.json" || fail "tetrahedron bijective"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$tmp/tri.obj"
"$spheremap" info "$tmp/tri.obj" > /dev/null; [ $? -eq 2 ] || fail "info on open mesh exit 2"
echo "cli usage: ok"
