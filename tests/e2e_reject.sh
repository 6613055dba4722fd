#!/usr/bin/env bash
# A bad corpus mesh must be refused with exit code 2 and the named check on stderr.
set -uo pipefail
spheremap=$1 mesh=$2 check=$3
[ -f "$mesh" ] || { echo "corpus mesh $mesh not found: skipped"; exit 77; }
err=$("$spheremap" map "$mesh" -o /dev/null --quiet 2>&1 >/dev/null)
code=$?
echo "$err"
[ "$code" -eq 2 ] || { echo "expected exit code 2, got $code"; exit 1; }
[[ "$err" == *"[$check]"* ]] || { echo "expected check [$check]"; exit 1; }
[ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || { echo "expected one line on stderr"; exit 1; }
