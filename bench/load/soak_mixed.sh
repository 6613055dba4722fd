#!/usr/bin/env bash
# The hostile soak: SECONDS (default 600) of mixed traffic against one server: valid
# jobs (async, synchronous, with remesh/uv/morph), a genus-1 mesh, truncated and garbage
# bodies, wrong types, unknown ids (wrk, bench/load/mixed_jobs.lua), while a second client
# keeps submitting slow jobs and cancelling them. Then checks: the server is still up,
# every accepted job reached a terminal state (accepted = succeeded + failed + cancelled,
# nothing queued or running), and prints resident memory sampled every minute.
# Usage: bench/load/soak_mixed.sh [SECONDS] [corpus dir]
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-600}
corpus=$(realpath "${2:-../shared/meshes}")
scripts/build.sh > /dev/null
work=$(mktemp -d)
trap 'kill $server $canceller 2>/dev/null || true; rm -rf "$work"' EXIT
build/tests/make_test_meshes "$work"
medium=$work/icosphere4.glb
[ -f "$corpus/spot.glb" ] && medium=$corpus/spot.glb
port=18090
url=http://127.0.0.1:$port
build/cli/spheremap serve --port $port --result-memory-bytes 134217728 2> "$work/server.log" &
server=$!
sleep 1
metric() { curl -s $url/metrics | awk -v m="$1" '$1 == m { print $2 }'; }
rss() { curl -s $url/metrics | awk '/^spheremap_resident_memory_bytes/{printf "%.1f", $2/1048576}'; }

echo "Machine: $(nproc) cores; $(date -u +%Y-%m-%d). Command: bench/load/soak_mixed.sh $seconds"
# Slow jobs (the paper's loop on a horseshoe never finishes), each cancelled 0-0.3 s later:
# some while queued, some while running.
(
  while true; do
    id=$(curl -s -X POST -H 'Content-Type: model/gltf-binary' --data-binary @"$work/horseshoe.glb" \
      "$url/v1/jobs?method=paper&max_iterations=1000000&time_limit_seconds=30" |
      grep -o '"id": "[0-9a-f]*"' | cut -d'"' -f4)
    sleep "0.$((RANDOM % 3))"
    [ -n "$id" ] && curl -s -o /dev/null -X DELETE "$url/v1/jobs/$id"
  done
) &
canceller=$!
wrk -t 2 -c 8 -d "${seconds}s" --timeout 60s -s bench/load/mixed_jobs.lua $url -- \
  "$work/icosphere2.glb" "$medium" "$work/torus.glb" > "$work/wrk.txt" &
wrk_pid=$!
samples="$(rss)"
for _ in $(seq $(( seconds / 60 ))); do sleep 60; samples="$samples $(rss)"; done
wait $wrk_pid
kill $canceller 2>/dev/null || true
wait $canceller 2>/dev/null || true
echo "RSS every 60 s (MiB): $samples"
grep '^LOAD' "$work/wrk.txt"
for _ in $(seq 120); do
  [ "$(metric 'spheremap_jobs{state="queued"}')" = 0 ] &&
    [ "$(metric 'spheremap_jobs{state="running"}')" = 0 ] && break
  sleep 1
done
kill -0 $server || { echo "FAIL: the server died"; exit 1; }
accepted=$(metric spheremap_input_faces_count)
ended=0
for s in succeeded failed cancelled; do
  c=$(metric "spheremap_jobs_finished_total{status=\"$s\"}")
  echo "jobs $s: $c"
  ended=$((ended + c))
done
echo "jobs accepted: $accepted, ended: $ended"
curl -s $url/metrics | grep -E '^spheremap_(http_responses_total|rejections_total)' | tr '\n' ' '
echo
[ "$accepted" = "$ended" ] || { echo "FAIL: $((accepted - ended)) accepted jobs did not end"; exit 1; }
echo "soak ok: server up, every accepted job ended"
