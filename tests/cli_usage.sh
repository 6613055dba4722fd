#!/usr/bin/env bash
# The command-line contract: help, exit codes for usage errors and missing files, info.
set -uo pipefail
spheremap=$1
fail() { echo "FAIL: $*"; exit 1; }
help=$("$spheremap" --help) || fail "--help exit 0"
[[ "$help" == *"spheremap map INPUT"* ]] || fail "--help"
help=$("$spheremap" map --help) || fail "map --help exit 0"
[[ "$help" == *"--method"* ]] || fail "map --help lists options"
[[ "$help" == *"default 0.25"* ]] || fail "map --help shows defaults"
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
# The same tetrahedron as ASCII STL (three corners per facet, welded) and as PLY; the
# extension in any case.
stl_facet() { printf 'facet normal 0 0 0\nouter loop\nvertex %s\nvertex %s\nvertex %s\nendloop\nendfacet\n' "$@"; }
{ echo "solid tet"; stl_facet "1 1 1" "1 -1 -1" "-1 1 -1"; stl_facet "1 1 1" "-1 -1 1" "1 -1 -1"
  stl_facet "1 1 1" "-1 1 -1" "-1 -1 1"; stl_facet "1 -1 -1" "-1 -1 1" "-1 1 -1"; echo "endsolid tet"; } > "$tmp/tet.STL"
"$spheremap" info "$tmp/tet.STL" > "$tmp/info_stl.json" || fail "info reads STL"
grep -q '"vertices": 4,' "$tmp/info_stl.json" || fail "STL corners welded to 4 vertices"
"$spheremap" map "$tmp/tet.STL" -o "$tmp/tet_stl.glb" --metrics "$tmp/m_stl.json" --quiet || fail "map STL"
grep -q '"bijective": true' "$tmp/m_stl.json" || fail "STL tetrahedron bijective"
printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n' > "$tmp/tet.ply"
printf 'element face 4\nproperty list uchar int vertex_indices\nend_header\n' >> "$tmp/tet.ply"
printf '1 1 1\n1 -1 -1\n-1 1 -1\n-1 -1 1\n3 0 1 2\n3 0 3 1\n3 0 2 3\n3 1 3 2\n' >> "$tmp/tet.ply"
"$spheremap" map "$tmp/tet.ply" -o "$tmp/tet_ply.obj" --quiet || fail "map PLY"
msg=$("$spheremap" info "$tmp/tet.3ds" 2>&1); [ $? -eq 2 ] || fail "unknown extension exit 2"
[[ "$msg" == *"'.stl', '.ply'"* ]] || fail "unknown extension lists the formats: $msg"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$tmp/tri.obj"
"$spheremap" info "$tmp/tri.obj" --prepare parts > /dev/null; [ $? -eq 2 ] || fail "info on open mesh exit 2"
# The default (auto) serves it closed by its own back, and says so; --prepare wrap as its
# envelope.
msg=$("$spheremap" info "$tmp/tri.obj") || fail "info on open mesh under auto exit 0"
[[ "$msg" == *'"decided": "repair"'* && "$msg" == *'"sheets_doubled": 1'* ]] ||
  fail "info under auto says it doubles the sheet: $msg"
msg=$("$spheremap" info "$tmp/tri.obj" --prepare wrap) || fail "info on open mesh under wrap exit 0"
[[ "$msg" == *'"method": "wrap"'* ]] || fail "info under wrap says it wraps: $msg"
# Two tetrahedra: both mapped by default (--prepare auto, as parts); one part at a time (--prepare
# repair) an error naming the components and parts as the fix; the larger with
# --largest-component.
printf 'v 1 1 1\nv 1 -1 -1\nv -1 1 -1\nv -1 -1 1\nv 11 1 1\nv 11 -1 -1\nv 9 1 -1\nv 9 -1 1\nv 10 0 5\n' > "$tmp/two.obj"
printf 'f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\nf 5 6 7\nf 5 8 6\nf 5 7 8\nf 6 8 7\n' >> "$tmp/two.obj"
msg=$("$spheremap" map "$tmp/two.obj" -o "$tmp/two_s.obj" --quiet 2>&1) || fail "two parts mapped"
[ -z "$msg" ] || fail "nothing left out, nothing said: $msg"
[ "$(grep -c '^f' "$tmp/two_s.obj")" -eq 8 ] || fail "two parts keep 8 faces"
# A part left out (here an open triangle under --prepare parts) exits 0 with the rest, and
# says so on stderr even with --quiet, not only in the metrics.
{ cat "$tmp/tet.obj"; printf 'v 5 0 0\nv 6 0 0\nv 5 1 0\nf 5 6 7\n'; } > "$tmp/tet_tri.obj"
msg=$("$spheremap" map "$tmp/tet_tri.obj" -o "$tmp/tt.obj" --prepare parts --quiet 2>&1) ||
  fail "a part left out exits 0"
[[ "$msg" == *"warning: 1 part of 2 left out (1 of 5 faces; metrics.parts lists each): part 1 (1 face): mesh has 1 boundary loop"* ]] ||
  fail "the part left out is said: $msg"
msg=$("$spheremap" map "$tmp/two.obj" -o "$tmp/two_s.obj" --prepare repair 2>&1)
[ $? -eq 2 ] || fail "two parts exit 2 under repair"
[[ "$msg" == *"[components]"*"2 connected components"* ]] || fail "components message: $msg"
[[ "$msg" == *"fix: --prepare parts maps every one of its 2 parts"* ]] || fail "parts fix: $msg"
"$spheremap" map "$tmp/two.obj" -o "$tmp/two_s.obj" --largest-component --quiet || fail "largest component"
[ "$(grep -c '^f' "$tmp/two_s.obj")" -eq 4 ] || fail "largest component keeps 4 faces"
# GLB output, and the welded layout.
"$spheremap" map "$tmp/tet.obj" -o "$tmp/tet.glb" --quiet || fail "glb output"
[ "$(head -c 4 "$tmp/tet.glb")" = "glTF" ] || fail "glb magic"
"$spheremap" info "$tmp/tet.glb" > /dev/null || fail "info reads glb"
"$spheremap" map "$tmp/tet.obj" -o "$tmp/w.obj" --layout welded --quiet || fail "welded layout"
"$spheremap" map "$tmp/tet.obj" -o "$tmp/w.obj" --layout bogus 2> /dev/null; [ $? -eq 1 ] || fail "bad layout exit 1"
echo "cli usage: ok"
