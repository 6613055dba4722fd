#!/usr/bin/env bash
# Load benchmark of the Redis queue: the same synchronous maps (POST /v1/map, wrk) as
# run.sh, through one API replica (no workers) and 1, 2 and 4 worker nodes (one worker
# each) on a local redis-server, next to the embedded memory:// queue with the same
# number of workers. The difference is the queue's cost per job. Then a soak of mixed
# load with 2 worker nodes, sampling every process's resident memory (ps) each minute,
# and a count of accepted vs finished jobs (nothing lost).
# Usage: bench/load/redis.sh [seconds per level] [soak seconds] [clients]
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-10}
soak=${2:-600}
clients=${3:-4}
command -v wrk > /dev/null || { sudo=; [ "$(id -u)" = 0 ] || sudo=sudo; $sudo apt-get install -y -qq wrk; }
scripts/build.sh > /dev/null
work=$(mktemp -d)
pids=()
stop_all() { for p in "${pids[@]}"; do kill "$p" 2> /dev/null || true; done; wait 2> /dev/null || true; pids=(); }
trap 'stop_all; redis-cli -p $redis_port shutdown nosave > /dev/null 2>&1 || true; rm -rf "$work"' EXIT
build/tests/make_test_meshes "$work" > /dev/null
small=$work/icosphere2.glb   # 320 triangles
medium=$work/icosphere4.glb  # 5,120 triangles
spheremap=build/cli/spheremap
redis_port=16399 api_port=18090
redis-server --port $redis_port --bind 127.0.0.1 --save "" --appendonly no --daemonize yes \
  --logfile "$work/redis.log" --dir "$work"
sleep 0.5
queue=redis://127.0.0.1:$redis_port
url=http://127.0.0.1:$api_port

wait_ready() { for _ in $(seq 100); do curl -sf $url/readyz > /dev/null && return; sleep 0.1; done; }
level() {  # level LABEL FILES...
  local label=$1
  shift
  printf '%-28s ' "$label"
  wrk -t 2 -c "$clients" -d "${seconds}s" --timeout 30s -s bench/load/post_mesh.lua $url -- "$@" |
    grep '^LOAD' | cut -d' ' -f2-
}

echo "Machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); $(date -u +%Y-%m-%d)"
echo "Command: bench/load/redis.sh $seconds $soak $clients   (wrk, $clients clients, POST /v1/map)"
for nodes in 1 2 4; do
  $spheremap serve --port $api_port --workers "$nodes" --threads-per-job 1 2> "$work/memory.log" &
  pids+=($!)
  wait_ready
  level "memory:// $nodes workers small" "$small"
  level "memory:// $nodes workers medium" "$medium"
  stop_all
  redis-cli -p $redis_port flushall > /dev/null
  $spheremap serve --port $api_port --workers 0 --queue $queue 2> "$work/api.log" &
  pids+=($!)
  for i in $(seq "$nodes"); do
    $spheremap worker --queue $queue --workers 1 --threads-per-job 1 2> "$work/worker$i.log" &
    pids+=($!)
  done
  wait_ready
  sleep 0.5
  level "redis:// $nodes nodes small" "$small"
  level "redis:// $nodes nodes medium" "$medium"
  stop_all
done

if [ "$soak" -gt 0 ]; then
  redis-cli -p $redis_port flushall > /dev/null
  $spheremap serve --port $api_port --workers 0 --queue $queue --queue-capacity 256 \
    --result-memory-bytes 134217728 2> "$work/api.log" &
  api=$!
  pids+=($api)
  # The result limits apply where results are stored: on the worker nodes too.
  $spheremap worker --queue $queue --workers 1 --threads-per-job 1 \
    --result-memory-bytes 134217728 2> "$work/worker1.log" &
  w1=$!
  pids+=($w1)
  $spheremap worker --queue $queue --workers 1 --threads-per-job 1 \
    --result-memory-bytes 134217728 2> "$work/worker2.log" &
  w2=$!
  pids+=($w2)
  wait_ready
  redis=$(pgrep -f "redis-server 127.0.0.1:$redis_port")
  rss() { ps -o rss= -p "$1" | awk '{printf "%.1f", $1/1024}'; }
  sample() { echo "api $(rss $api) / nodes $(rss $w1), $(rss $w2) / redis $(rss "$redis") MiB"; }
  echo "Soak: mixed load, c=8, ${soak}s, 2 worker nodes; RSS every 60 s:"
  wrk -t 2 -c 8 -d "${soak}s" --timeout 30s -s bench/load/post_mesh.lua $url -- \
    "$small" "$medium" > "$work/soak.txt" &
  wrk_pid=$!
  echo "  start: $(sample)"
  for m in $(seq $((soak / 60))); do sleep 60; echo "  ${m} min: $(sample)"; done
  wait $wrk_pid
  grep '^LOAD' "$work/soak.txt" | sed 's/^LOAD/  soak/'
  sleep 2
  accepted=$(grep -c '"status":"queued"' "$work/api.log")
  echo "  accepted $accepted; in Redis: $(redis-cli -p $redis_port mget spheremap:count:succeeded \
    spheremap:count:failed spheremap:count:cancelled | paste -sd' ' | \
    awk '{print "succeeded " $1 ", failed " $2 ", cancelled " $3}')"
fi
