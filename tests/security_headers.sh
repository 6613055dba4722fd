#!/usr/bin/env bash
# The real server's response headers: the page (GET /) with a Content-Security-Policy
# that allows its inline import map by the hash of the map it serves (computed here with
# Python's hashlib) and nothing framing it; nosniff everywhere; no CORS header unless
# --cors-origins lists the origin; with API keys, /metrics on the API port needs a key
# while the health port serves it without one.
set -uo pipefail
spheremap=$1
here=$(cd "$(dirname "$0")" && pwd)
. "$here/start_server.sh"
fail() { echo "FAIL: $*"; exit 1; }
work=$(mktemp -d)
server=
trap '[ -n "$server" ] && kill $server 2> /dev/null; wait 2> /dev/null; rm -rf "$work"' EXIT
header() { grep -i "^$1:" "$2" | head -1 | cut -d: -f2- | sed 's/^ *//; s/\r$//'; }

start_server "$work/default.log" --workers 1
curl -sf -m 5 -D "$work/page.h" -o "$work/page.html" -H 'Origin: https://elsewhere.example' "$url/" ||
  fail "GET /"
policy=$(header Content-Security-Policy "$work/page.h")
[ -n "$policy" ] || fail "no Content-Security-Policy on the page"
echo "policy: $policy"
# The import map's SHA-256 as CSP writes it (base64), from the page as served.
hash=$(python3 -c '
import base64, hashlib, re, sys
page = open(sys.argv[1], encoding="utf-8").read()
found = re.search(r"<script type=\"importmap\">([^<]*)</script>", page)
print(base64.b64encode(hashlib.sha256(found.group(1).encode()).digest()).decode())' \
  "$work/page.html") || fail "no import map in the page"
case "$policy" in *"'sha256-$hash'"*) ;; *) fail "the policy does not allow the import map (sha256-$hash)" ;; esac
case "$policy" in *"frame-ancestors 'none'"*) ;; *) fail "the page may be framed" ;; esac
case "$policy" in *"'unsafe-inline'"* | *"'unsafe-eval'"*) fail "unsafe-inline or unsafe-eval" ;; esac
[ "$(header X-Content-Type-Options "$work/page.h")" = nosniff ] || fail "page: no nosniff"
[ "$(header X-Frame-Options "$work/page.h")" = DENY ] || fail "page: no X-Frame-Options"
for path in /web/app.js /v1/openapi.yaml /healthz /v1/jobs/0123456789abcdef0123456789abcdef; do
  curl -s -m 5 -D "$work/h" -o /dev/null -H 'Origin: https://elsewhere.example' "$url$path"
  [ "$(header X-Content-Type-Options "$work/h")" = nosniff ] || fail "$path: no nosniff"
  grep -qi '^Access-Control-Allow-Origin' "$work/h" && fail "$path: CORS header by default"
done
curl -s -m 5 -D "$work/h" -o /dev/null -X OPTIONS -H 'Origin: https://elsewhere.example' \
  -H 'Access-Control-Request-Method: POST' "$url/v1/jobs"
grep -qi '^Access-Control-Allow' "$work/h" && fail "preflight allowed by default"
kill "$server"; wait "$server" 2> /dev/null; server=

keys=$work/keys
printf 'alpha alpha-key-0123456789abcdef\n' > "$keys"
start_server "$work/keys.log" --workers 1 --api-keys "$keys" --health-port 0 \
  --cors-origins https://a.example
health=$(grep -o '"event":"health_listening"[^}]*' "$work/keys.log" | grep -o '"url":"[^"]*"' |
  cut -d'"' -f4)
code=$(curl -s -m 5 -o /dev/null -w '%{http_code}' "$url/metrics")
[ "$code" = 401 ] || fail "/metrics on the API port without a key: $code"
code=$(curl -s -m 5 -o /dev/null -w '%{http_code}' -H 'Authorization: Bearer alpha-key-0123456789abcdef' "$url/metrics")
[ "$code" = 200 ] || fail "/metrics on the API port with a key: $code"
curl -sf -m 5 "$health/metrics" | grep -q spheremap_queue_capacity || fail "/metrics on the health port"
curl -s -m 5 -D "$work/h" -o /dev/null -H 'Origin: https://a.example' "$url/healthz"
[ "$(header Access-Control-Allow-Origin "$work/h")" = https://a.example ] || fail "a listed origin"
curl -s -m 5 -D "$work/h" -o /dev/null -H 'Origin: https://b.example' "$url/healthz"
grep -qi '^Access-Control-Allow-Origin' "$work/h" && fail "an origin not listed got CORS"
echo "security headers: ok"
