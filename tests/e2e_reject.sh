#!/usr/bin/env bash
# A bad corpus mesh must be refused with exit code 2 and the named check on stderr (one
# line, and a second "  fix:" line when an option would map it).
set -uo pipefail
spheremap=$1 mesh=$2 check=$3
[ -f "$mesh" ] || { echo "corpus mesh $mesh not found: skipped"; exit 77; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
err=$("$spheremap" map "$mesh" -o "$out/sphere.obj" --quiet 2>&1 >/dev/null)
code=$?
echo "$err"
[ "$code" -eq 2 ] || { echo "expected exit code 2, got $code"; exit 1; }
[[ "$err" == *"[$check]"* ]] || { echo "expected check [$check]"; exit 1; }
lines=$(printf '%s\n' "$err" | wc -l)
[ "$lines" -eq 1 ] || { [ "$lines" -eq 2 ] && [[ "$(printf '%s\n' "$err" | tail -1)" == "  fix: --"* ]]; } ||
  { echo "expected one line on stderr, or two with a fix"; exit 1; }
[ "$check" != components ] || [[ "$err" == *"fix: --largest-component"* ]] || { echo "expected the fix"; exit 1; }
