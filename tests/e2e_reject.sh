#!/usr/bin/env bash
# A bad corpus mesh must be refused with exit code 2 and the named check on stderr (one
# line, and a second "  fix:" line when an option would map it).
set -uo pipefail
spheremap=$1 mesh=$2 check=$3
[ -f "$mesh" ] || { echo "corpus mesh $mesh not found: skipped"; exit 77; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# Several parts that each map are mapped by default (--prepare parts); one part at a time
# (--prepare repair) refuses them and names parts as the fix.
one_part=()
[ "$check" != components ] || one_part=(--prepare repair)
err=$("$spheremap" map "$mesh" -o "$out/sphere.obj" --quiet "${one_part[@]}" 2>&1 >/dev/null)
code=$?
echo "$err"
[ "$code" -eq 2 ] || { echo "expected exit code 2, got $code"; exit 1; }
[[ "$err" == *"[$check]"* ]] || { echo "expected check [$check]"; exit 1; }
lines=$(printf '%s\n' "$err" | wc -l)
[ "$lines" -eq 1 ] || { [ "$lines" -eq 2 ] && [[ "$(printf '%s\n' "$err" | tail -1)" == "  fix: --"* ]]; } ||
  { echo "expected one line on stderr, or two with a fix"; exit 1; }
[ "$check" != components ] || [[ "$err" == *"fix: --prepare parts"* ]] || { echo "expected the fix"; exit 1; }
if [ "$check" = components ]; then
  "$spheremap" map "$mesh" -o "$out/sphere.obj" --metrics "$out/metrics.json" --quiet ||
    { echo "expected every part mapped by default"; exit 1; }
  python3 -c 'import json,sys; m=json.load(open(sys.argv[1])); assert m["parts_left_out"] == 0 and m["parts_mapped"] >= 2, m["parts"]' \
    "$out/metrics.json" || exit 1
fi
