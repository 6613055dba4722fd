#!/usr/bin/env bash
# Maps every mesh of the shared corpus (its OBJ files) under each given prepare method and
# prints the sha256 of the sphere written (OBJ), one line per mesh and method (or the exit
# status when it did not map). Run it before and after a change and diff the outputs:
# equal hashes say the map did not change on that mesh ("Corpus maps unchanged", issue
# Reach I). The map is deterministic for any thread count (deterministic_outputs).
# Usage: bench/corpus/hashes.sh SPHEREMAP [CORPUS_DIR] [METHOD...]   (default: exact parts)
set -euo pipefail
spheremap=$1
corpus=${2:-../shared/meshes}
shift $(($# < 2 ? $# : 2))
methods=("$@")
[ ${#methods[@]} -gt 0 ] || methods=(exact parts)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for mesh in "$corpus"/*.obj; do
  name=$(basename "$mesh" .obj)
  for method in "${methods[@]}"; do
    status=0
    "$spheremap" map "$mesh" -o "$work/out.obj" --metrics "$work/m.json" --prepare "$method" \
      --quiet > /dev/null 2>&1 || status=$?
    if [ $status -ne 0 ]; then
      echo -e "$name\t$method\texit $status"
      continue
    fi
    sphere=$(sha256sum < "$work/out.obj" | cut -c1-16)
    echo -e "$name\t$method\t$sphere"
  done
done
