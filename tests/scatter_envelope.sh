#!/usr/bin/env bash
# The envelope of 20,000 scattered quads (make_test_meshes --scatter 20000 2) maps certified
# under `map --prepare wrap`: a closed genus-0 body of many blobs joined where handles were
# filled, whose level of 11,000 vertices fails insertions that the narrower retry cannot
# place (session 41: not_bijective after 8 attempts, 170 s; coarse_to_fine.cpp retry_level).
# Plain pass only (scripts/test.sh): about 50 s here, mostly the envelope's reduction.
set -uo pipefail
spheremap=$1
make_test_meshes=$2
fail() { echo "FAIL: $*"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$make_test_meshes" "$work" --scatter 20000 2 || fail "could not write the scatter"
"$spheremap" map "$work/scatter_20000_2.obj" -o "$work/sphere.obj" --metrics "$work/metrics.json" \
  --prepare wrap --quiet || fail "map --prepare wrap exited $?"
python3 - "$work/metrics.json" <<'PY' || fail "metrics"
import json, sys
m = json.load(open(sys.argv[1]))
p = m["preparation"]
assert p["method"] == "wrap", p
assert p["handles_filled"] > 100, p
assert m["bijective"] is True and m["bijective_as_written"] is True, m.get("problem")
assert m["degenerate_triangles"] == 0 and m["folds"] == 0, m
PY
echo "PASS"
