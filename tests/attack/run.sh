#!/usr/bin/env bash
# The attack suite (issue 14): the real server, under a memory cap (prlimit: 2 GiB of
# address space; worker processes 1 GiB), with 4 API threads and a health port, takes
# attack.py's hostile requests. Each must get its specific 4xx, /healthz on the health
# port must answer within 2 s throughout, the server must serve a good job afterwards,
# and its peak resident memory (VmHWM) must stay under 1.5 GiB.
set -uo pipefail
spheremap=$1 make_meshes=$2
here=$(cd "$(dirname "$0")" && pwd)
command -v prlimit > /dev/null || { echo "prlimit not found: skipped"; exit 77; }
# AddressSanitizer reserves terabytes of address space: no RLIMIT_AS for its build.
# gcc links ASan as libasan.so, clang into the binary: both name __asan_init in it.
if grep -q __asan_init "$spheremap"; then echo "AddressSanitizer build: skipped"; exit 77; fi
tmp=$(mktemp -d)
trap 'kill $server 2> /dev/null; wait 2> /dev/null; rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; tail -n 5 "$tmp/server.log"; exit 1; }
"$make_meshes" "$tmp" > /dev/null || fail "make_test_meshes"
prlimit --as=2147483648 "$spheremap" serve --port 0 --health-port 0 --http-threads 4 \
  --workers 1 --worker-memory-bytes 1073741824 --max-body-bytes 8388608 \
  --read-timeout-seconds 5 --header-timeout-seconds 2 --body-timeout-seconds 2 \
  --max-connections-per-address 3 2> "$tmp/server.log" &
server=$!
for _ in $(seq 200); do
  grep -q '"event":"listening"' "$tmp/server.log" && break
  sleep 0.05
done
url=$(grep '"event":"listening"' "$tmp/server.log" | grep -o '"url":"[^"]*"' | cut -d'"' -f4)
health=$(grep '"event":"health_listening"' "$tmp/server.log" | grep -o '"url":"[^"]*"' | cut -d'"' -f4)
[ -n "$url" ] && [ -n "$health" ] || fail "the server did not start"
python3 "$here/attack.py" "$url" "$health" "$tmp/icosphere4.glb" || fail "attack suite"
kill -0 "$server" 2> /dev/null || fail "the server died"
peak_kb=$(awk '/^VmHWM/ {print $2}' "/proc/$server/status")
echo "server peak resident memory: $((peak_kb / 1024)) MiB (cap 1536)"
[ "$peak_kb" -lt $((1536 * 1024)) ] || fail "peak RSS ${peak_kb} kB"
echo "attack suite: ok"
