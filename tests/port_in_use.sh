#!/usr/bin/env bash
# A second `spheremap serve` on a port another process listens on must not start: it
# exits non-zero and says which port on which host is taken, for the API port and for the
# health port. (cpp-httplib's default SO_REUSEPORT let it bind, log "listening" and take
# part of the first one's connections.)
set -uo pipefail
spheremap=$1
here=$(cd "$(dirname "$0")" && pwd)
. "$here/start_server.sh"
fail() { echo "FAIL: $*"; exit 1; }
work=$(mktemp -d)
server=
trap '[ -n "$server" ] && kill $server 2> /dev/null; wait 2> /dev/null; rm -rf "$work"' EXIT
start_server "$work/first.log" --health-port 0 --workers 1
port=${url##*:}
health=$(grep -o '"event":"health_listening"[^}]*' "$work/first.log" | grep -o '"port":[0-9]*' |
  cut -d: -f2)
[ -n "$health" ] || fail "no health_listening line: $(cat "$work/first.log")"

# Runs a second serve with the given flags; it must end by itself (10 s at most).
expect_refused() {
  local name=$1 taken=$2
  shift 2
  timeout 10 "$spheremap" serve --workers 1 "$@" 2> "$work/$name.log"
  local code=$?
  [ "$code" = 124 ] && fail "$name: the second serve kept running: $(cat "$work/$name.log")"
  [ "$code" != 0 ] || fail "$name: the second serve exited 0"
  grep '"event":"listening"' "$work/$name.log" && fail "$name: the second serve logged listening"
  grep -q "port $taken on 127.0.0.1 is in use by another process" "$work/$name.log" ||
    fail "$name: no clear message: $(cat "$work/$name.log")"
  echo "$name: exit $code, $(grep -o '"error":"[^"]*"' "$work/$name.log")"
}
expect_refused api "$port" --port "$port"
expect_refused health "$health" --port 0 --health-port "$health"
# The first server still answers on both.
curl -sf -m 5 -o /dev/null "$url/healthz" || fail "the first server stopped answering"
curl -sf -m 5 -o /dev/null "http://127.0.0.1:$health/healthz" || fail "the first health port"
echo "port in use: ok"
