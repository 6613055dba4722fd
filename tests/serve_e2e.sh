#!/usr/bin/env bash
# `spheremap serve` as a process: the README's curl session (submit, poll, download),
# configuration from the environment and flags, then SIGTERM while jobs are queued and
# running: readiness fails, new jobs get 503, every accepted job reaches a terminal
# state that its GET reports (and the log records), and the process exits 0.
# Usage: serve_e2e.sh SPHEREMAP MAKE_TEST_MESHES
set -euo pipefail
spheremap=$1
make_meshes=$2
work=$(mktemp -d)
trap 'kill -9 $server 2>/dev/null || true; rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; echo "--- server log"; tail -40 "$work/server.log"; exit 1; }

# Inputs the test makes itself: a small valid mesh, and a horseshoe (a bent tube) that
# keeps the paper's loop busy for as long as the test wants.
"$make_meshes" "$work"
cp "$work/icosphere2.glb" "$work/mesh.glb"

SPHEREMAP_QUEUE_CAPACITY=16 "$spheremap" serve --port 0 --workers 1 --shutdown-grace-seconds 1 \
  2> "$work/server.log" &
server=$!
for _ in $(seq 100); do grep -q '"event":"listening"' "$work/server.log" && break; sleep 0.1; done
url=$(grep -o '"url":"[^"]*"' "$work/server.log" | head -1 | cut -d'"' -f4)
[ -n "$url" ] || fail "the server did not log its address"
grep -q '"queue_capacity":16' "$work/server.log" || fail "SPHEREMAP_QUEUE_CAPACITY not applied"
grep -q '"workers":1' "$work/server.log" || fail "--workers not applied"

# The README's session.
curl -sS -o "$work/job.json" -D "$work/headers" -X POST \
  -H 'Content-Type: model/gltf-binary' --data-binary @"$work/mesh.glb" "$url/v1/jobs"
grep -q '^HTTP/1.1 202' "$work/headers" || fail "submit: $(head -1 "$work/headers")"
job=$(grep -i '^Location:' "$work/headers" | tr -d '\r' | cut -d' ' -f2)
for _ in $(seq 300); do
  status=$(curl -sS "$url$job" | grep -o '"status": "[a-z]*"' | cut -d'"' -f4)
  [ "$status" = succeeded ] && break
  sleep 0.1
done
[ "$status" = succeeded ] || fail "job ended $status"
curl -sS -f -o "$work/sphere.glb" "$url$job/artifacts/sphere.glb"
curl -sS -f -o "$work/metrics.json" "$url$job/artifacts/metrics.json"
[ "$(head -c 4 "$work/sphere.glb")" = glTF ] || fail "sphere.glb is not a GLB"
grep -q '"bijective_as_written": true' "$work/metrics.json" || fail "metrics.json"

# SIGTERM with one job running (busy for up to 60 s) and three queued behind it.
ids=()
submit() {
  curl -sS -X POST -H "Content-Type: $2" --data-binary @"$1" "$url$3" |
    grep -o '"id": "[0-9a-f]*"' | cut -d'"' -f4
}
ids+=("$(submit "$work/horseshoe.glb" model/gltf-binary \
  '/v1/jobs?method=paper&max_iterations=1000000&time_limit_seconds=60')")
for _ in 1 2 3; do ids+=("$(submit "$work/mesh.glb" model/gltf-binary /v1/jobs)"); done
[ "${#ids[@]}" = 4 ] && [ -n "${ids[3]}" ] || fail "submissions: ${ids[*]}"
sleep 0.3
kill -TERM $server
sleep 0.2
[ "$(curl -sS -o /dev/null -w '%{http_code}' "$url/readyz")" = 503 ] || fail "readyz while draining"
code=$(curl -sS -o /dev/null -w '%{http_code}' -X POST -H 'Content-Type: model/gltf-binary' \
  --data-binary @"$work/mesh.glb" "$url/v1/jobs")
[ "$code" = 503 ] || fail "a job submitted while draining got $code"
wait $server || fail "exit code $?"
for id in "${ids[@]}"; do
  grep "\"job\":\"$id\"" "$work/server.log" |
    grep -q -E '"status":"(succeeded|failed|cancelled)"' || fail "job $id has no terminal state"
done
grep "\"job\":\"${ids[0]}\"" "$work/server.log" | grep '"status":"cancelled"' > /dev/null ||
  fail "the running job was not cancelled at the end of the grace period"
grep -q '"event":"stopped"' "$work/server.log" || fail "no stopped line"
# A second SIGTERM during a long grace period cancels at once: the process is gone in
# seconds, not after the 60 s of grace.
"$spheremap" serve --port 0 --workers 1 --shutdown-grace-seconds 60 2> "$work/server2.log" &
server=$!
for _ in $(seq 100); do grep -q '"event":"listening"' "$work/server2.log" && break; sleep 0.1; done
url=$(grep -o '"url":"[^"]*"' "$work/server2.log" | head -1 | cut -d'"' -f4)
slow=$(submit "$work/horseshoe.glb" model/gltf-binary \
  '/v1/jobs?method=paper&max_iterations=1000000&time_limit_seconds=60')
[ -n "$slow" ] || fail "slow job not accepted"
sleep 0.3
kill -TERM $server
sleep 0.3
start=$(date +%s)
kill -TERM $server
wait $server || fail "exit code $? after two SIGTERMs"
[ $(( $(date +%s) - start )) -le 5 ] || fail "a second SIGTERM did not cut the grace short"
grep "\"job\":\"$slow\"" "$work/server2.log" | grep '"status":"cancelled"' > /dev/null ||
  fail "the running job was not cancelled by the second SIGTERM"
echo "serve e2e: session ok, ${#ids[@]} jobs drained, exit 0; a second SIGTERM cancels at once"
