#!/usr/bin/env bash
# The health port answers while clients hold every API connection: a server with two
# HTTP threads and --health-port 0 gets 8 connections that send half a request line and
# stall (slowloris); /healthz, /readyz and /metrics on the health port must still answer
# within 2 s, and the API's routes must not be served there.
set -uo pipefail
spheremap=$1
here=$(cd "$(dirname "$0")" && pwd)
. "$here/start_server.sh"
fail() { echo "FAIL: $*"; exit 1; }
work=$(mktemp -d)
server=
trap '[ -n "$server" ] && kill $server 2> /dev/null; wait 2> /dev/null; rm -rf "$work"' EXIT
start_server "$work/server.log" --http-threads 2 --health-port 0 --read-timeout-seconds 30 \
  --workers 1
health=$(grep -o '"event":"health_listening"[^}]*' "$work/server.log" | grep -o '"url":"[^"]*"' |
  cut -d'"' -f4)
[ -n "$health" ] || fail "no health_listening line: $(cat "$work/server.log")"
port=${url##*:}
fds=()
for _ in $(seq 8); do
  exec {fd}<> "/dev/tcp/127.0.0.1/$port" || fail "connect"
  printf 'GET /healthz HTTP/1.1\r\nHost: a\r\nX-Slow: ' >&$fd
  fds+=("$fd")
done
sleep 0.5
if curl -s -m 2 -o /dev/null "$url/healthz"; then
  echo "note: the API port still answered with every thread held"
else
  echo "the API port is held by the stalled clients (as expected with 2 threads)"
fi
for path in healthz readyz metrics; do
  start=$(date +%s%N)
  curl -sf -m 2 -o "$work/$path" "$health/$path" || fail "health port /$path did not answer within 2 s"
  echo "health port /$path: $(( ($(date +%s%N) - start) / 1000000 )) ms"
done
grep -q '"status": *"ok"' "$work/healthz" || fail "healthz body: $(cat "$work/healthz")"
grep -q 'spheremap_queue_capacity' "$work/metrics" || fail "metrics body"
code=$(curl -s -m 2 -o /dev/null -w '%{http_code}' "$health/v1/openapi.yaml")
[ "$code" = 404 ] || fail "the health port serves the API (/v1/openapi.yaml: $code)"
for fd in "${fds[@]}"; do exec {fd}>&-; done
echo "health port: ok"
