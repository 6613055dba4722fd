#!/usr/bin/env bash
# The map's cost in CSR sweeps counted in instructions instead of seconds: callgrind
# counts the instructions of map_to_sphere and of the CSR one-ring sweeps that
# quality_bench times (one thread, so the count does not depend on the machine, its
# load or the VM's pace; the same binary and input give the same count). Timed sweeps
# moved by up to 1.7x between back-to-back runs here; this does not move. It leaves out
# what time sees and instructions do not: memory stalls and idle cores (the hierarchy is
# serial and waits on memory, the CSR sweep streams on every core).
#
#   bench/quality/instruction_sweeps.sh QUALITY MESH...
#
# Prints one line per mesh: instructions of the map, of one CSR sweep, and their ratio.
set -euo pipefail
cd "$(dirname "$0")/../.."
quality=$1
shift
command -v valgrind > /dev/null || { echo "needs valgrind (apt-get install valgrind)" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for mesh in "$@"; do
  OMP_NUM_THREADS=1 valgrind --tool=callgrind --callgrind-out-file="$out/cg" \
    build/bench/quality_bench --quality "$quality" --resolution 0 "$mesh" > /dev/null 2> "$out/log"
  counts=$(callgrind_annotate --inclusive=yes "$out/cg" 2> /dev/null)
  map=$(grep -m1 'spheremap::map_to_sphere(' <<< "$counts" | awk '{print $1}' | tr -d ,)
  # The sweep's loop body (an OpenMP outlined function); quality_bench runs 111 sweeps
  # once at the start and once before and after the map, in the file's vertex order and
  # in Morton order (the same instructions either way): 666.
  csr=$(grep -m1 'CsrSweep::median_seconds() \[clone' <<< "$counts" | awk '{print $1}' | tr -d ,)
  python3 -c "
m, c = $map, $csr / 666
print(f'$(basename "$mesh" .obj) $quality: map {m:,} instructions, CSR sweep {c:,.0f}, {m / c:,.0f} sweeps')"
done
