#!/usr/bin/env bash
# `spheremap map --prepare wrap` on a torus OBJ (genus 1; refused under exact, which does not close handles):
# exit 0, a certified map of its envelope, and metrics.preparation with method "wrap", one
# handle cut or filled and the envelope's distances. A hostile resolution is refused with
# the cap in the message (exit 2).
set -uo pipefail
spheremap=$1
fail() { echo "FAIL: $*"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 - "$work/torus.obj" <<'PY' || fail "could not write the torus"
import math, sys
n, m, R, r = 24, 48, 2.0, 0.7
with open(sys.argv[1], "w") as f:
    for j in range(m):
        for i in range(n):
            u, v = 2 * math.pi * i / n, 2 * math.pi * j / m
            f.write("v %.9f %.9f %.9f\n" % ((R + r * math.cos(u)) * math.cos(v),
                                           (R + r * math.cos(u)) * math.sin(v), r * math.sin(u)))
    for j in range(m):
        for i in range(n):
            a, b = j * n + i, j * n + (i + 1) % n
            c, d = ((j + 1) % m) * n + (i + 1) % n, ((j + 1) % m) * n + i
            f.write("f %d %d %d %d\n" % (a + 1, d + 1, c + 1, b + 1))
PY
"$spheremap" map "$work/torus.obj" -o "$work/sphere.glb" --prepare exact --quiet > /dev/null 2>&1 &&
  fail "the torus mapped as it is (exact)"
"$spheremap" map "$work/torus.obj" -o "$work/sphere.glb" --metrics "$work/metrics.json" \
  --prepare wrap --wrap-resolution 128 --quiet || fail "map --prepare wrap exited $?"
python3 - "$work/metrics.json" <<'PY' || fail "metrics"
import json, sys
m = json.load(open(sys.argv[1]))
p = m["preparation"]
assert m["bijective"] is True, m.get("problem")
assert p["method"] == "wrap", p
assert p["handles_cut"] + p["handles_filled"] == 1, p
assert p["voxels_changed"] > 0 and p["envelope_faces"] > 0, p
assert 0 < p["envelope_rms"] <= p["envelope_hausdorff"] < 0.2, p
assert abs(p["offset"] - 1.5 * p["voxel_size"]) < 1e-9, p
PY
out=$("$spheremap" map "$work/torus.obj" -o "$work/big.glb" --prepare wrap \
  --wrap-resolution 4096 --wrap-offset 0.2 --quiet 2>&1)
code=$?
[ $code -eq 2 ] || fail "a grid past the cap exited $code: $out"
echo "$out" | grep -q "cap" || fail "no cap in the refusal: $out"
echo "PASS"
