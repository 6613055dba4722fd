#!/usr/bin/env bash
# A bad corpus mesh must be refused with exit code 2 and the named check on stderr (one
# line, and a second "  fix:" line when an option would map it).
set -uo pipefail
spheremap=$1 mesh=$2 check=$3
[ -f "$mesh" ] || { echo "corpus mesh $mesh not found: skipped"; exit 77; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# A mesh the default (--prepare auto) maps as it is or repaired (holes filled, or left for
# its back: the bunny's five are wide) is refused under the method given:
# "repair" (one part at a time: several parts refused, parts named as the fix) or
# "repair-no-fill" (holes left open: --max-hole-fill 0) or "no-handles" (handles left:
# --max-handle-cycle 0) or "exact" (--prepare exact: non-manifold vertices not split).
method=${4:-}
refused_with=()
case "$method" in
  repair) refused_with=(--prepare repair) ;;
  repair-no-fill) refused_with=(--prepare repair --max-hole-fill 0) ;;
  no-handles) refused_with=(--prepare parts --max-handle-cycle 0) ;;
  exact) refused_with=(--prepare exact) ;;
esac
err=$("$spheremap" map "$mesh" -o "$out/sphere.obj" --quiet "${refused_with[@]}" 2>&1 >/dev/null)
code=$?
echo "$err"
[ "$code" -eq 2 ] || { echo "expected exit code 2, got $code"; exit 1; }
[[ "$err" == *"[$check]"* ]] || { echo "expected check [$check]"; exit 1; }
lines=$(printf '%s\n' "$err" | wc -l)
[ "$lines" -eq 1 ] || { [ "$lines" -eq 2 ] && [[ "$(printf '%s\n' "$err" | tail -1)" == "  fix: --"* ]]; } ||
  { echo "expected one line on stderr, or two with a fix"; exit 1; }
[ "$check" != components ] || [[ "$err" == *"fix: --prepare parts"* ]] || { echo "expected the fix"; exit 1; }
if [ -n "$method" ]; then
  "$spheremap" map "$mesh" -o "$out/sphere.obj" --metrics "$out/metrics.json" --quiet ||
    { echo "expected the default to map it"; exit 1; }
  python3 -c 'import json,sys; m=json.load(open(sys.argv[1])); p=m["preparation"]
assert m["bijective"] and m.get("parts_left_out", 0) == 0, m
assert sys.argv[2] != "boundary" or p["holes_filled"] > 0 or p["sheets_doubled"] > 0, p
assert sys.argv[2] != "genus" or p["handles_closed"] + p["handles_opened"] > 0 and p["handles_left"] == 0, p' "$out/metrics.json" "$check" || exit 1
fi
