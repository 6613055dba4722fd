#!/usr/bin/env bash
# Slow and non-reading clients (issue 31, item 7): the real server under a memory cap
# (prlimit: 2 GiB of address space), 4 API threads, takes slow_clients.py's 1,000
# connections from 127.0.0.2-5 (slow headers, slow bodies, never-reading downloads of a
# 6 MB artifact). /healthz on the API port must answer each probe within 2 s, the
# server must live, serve a good job afterwards, keep its peak resident memory under
# 1.5 GiB, and end within its grace period on SIGTERM.
# Usage: slow_clients.sh SPHEREMAP MAKE_TEST_MESHES [HOLD_SECONDS]
set -uo pipefail
spheremap=$1 make_meshes=$2 hold=${3:-20}
here=$(cd "$(dirname "$0")" && pwd)
command -v prlimit > /dev/null || { echo "prlimit not found: skipped"; exit 77; }
# gcc links ASan as libasan.so, clang into the binary: both name __asan_init in it.
if grep -q __asan_init "$spheremap"; then echo "AddressSanitizer build: skipped"; exit 77; fi
tmp=$(mktemp -d)
trap 'kill $server 2> /dev/null; wait 2> /dev/null; rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; tail -n 5 "$tmp/server.log"; exit 1; }
"$make_meshes" "$tmp" > /dev/null || fail "make_test_meshes"
# Every attacking connection held at once: 250 from each address may be open.
prlimit --as=2147483648 "$spheremap" serve --port 0 --health-port 0 --http-threads 4 \
  --workers 1 --worker-memory-bytes 1073741824 --max-body-bytes 8388608 \
  --read-timeout-seconds 5 --max-connections-per-address 250 \
  --shutdown-grace-seconds 5 2> "$tmp/server.log" &
server=$!
for _ in $(seq 200); do
  grep -q '"event":"listening"' "$tmp/server.log" && break
  sleep 0.05
done
url=$(grep '"event":"listening"' "$tmp/server.log" | grep -o '"url":"[^"]*"' | cut -d'"' -f4)
health=$(grep '"event":"health_listening"' "$tmp/server.log" | grep -o '"url":"[^"]*"' | cut -d'"' -f4)
[ -n "$url" ] && [ -n "$health" ] || fail "the server did not start"
python3 "$here/slow_clients.py" "$url" "$server" "$tmp/icosphere4.glb" "$hold" || fail "slow clients"
kill -0 "$server" 2> /dev/null || fail "the server died"
curl -sf --max-time 2 "$health/healthz" > /dev/null || fail "the health port after the attack"
peak_kb=$(awk '/^VmHWM/ {print $2}' "/proc/$server/status")
echo "server peak resident memory: $((peak_kb / 1024)) MiB (cap 1536)"
[ "$peak_kb" -lt $((1536 * 1024)) ] || fail "peak RSS ${peak_kb} kB"
abandoned=$(grep -c '"event":"response_abandoned"' "$tmp/server.log")
echo "responses abandoned (clients that never read, logged): $abandoned"
# SIGTERM: the process ends within its grace period (5 s) and a margin.
kill -TERM "$server"
for _ in $(seq 150); do kill -0 "$server" 2> /dev/null || break; sleep 0.1; done
kill -0 "$server" 2> /dev/null && fail "still running 15 s after SIGTERM"
wait "$server"; code=$?
[ "$code" -eq 0 ] || fail "exit status $code after SIGTERM"
echo "slow clients: ok"
