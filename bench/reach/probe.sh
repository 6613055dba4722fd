#!/usr/bin/env bash
# Reach probe: for every mesh file under the given folders (.glb .gltf .obj .off .stl
# .ply), asks `spheremap info` whether it maps as it is (--prepare exact) and after the
# safe cleaning (--prepare repair), and prints one line per file (verdicts and the first
# failed check) and a summary per folder. Only reads; maps nothing, so it is fast.
# Usage: bench/reach/probe.sh SPHEREMAP DIR...   (a DIR per source: the summary is per DIR)
set -uo pipefail
spheremap=$1
shift
first_check() {  # the first failed check of an info report, or "ok"
  python3 -c 'import json,sys
try: d=json.load(sys.stdin)
except Exception: print("unreadable"); sys.exit()
if "error" in d: print("read:" + d["error"]["check"]); sys.exit()
f=d.get("failures") or []
print("ok" if d.get("mappable") else (f[0]["check"] if f else "?"))'
}
for dir in "$@"; do
  total=0 exact_ok=0 repair_ok=0
  while IFS= read -r -d '' file; do
    exact=$(timeout 60 "$spheremap" info "$file" --prepare exact 2> /dev/null | first_check)
    repair=$(timeout 60 "$spheremap" info "$file" --prepare repair 2> /dev/null | first_check)
    total=$((total + 1))
    [ "$exact" = ok ] && exact_ok=$((exact_ok + 1))
    [ "$repair" = ok ] && repair_ok=$((repair_ok + 1))
    printf '%-14s %-14s %s\n' "$exact" "$repair" "${file#"$dir"/}"
  done < <(find "$dir" -type f \( -iname '*.glb' -o -iname '*.gltf' -o -iname '*.obj' -o \
             -iname '*.off' -o -iname '*.stl' -o -iname '*.ply' \) -print0 | sort -z)
  echo "== $(basename "$dir"): $total files, mappable as they are $exact_ok, after repair $repair_ok"
done
