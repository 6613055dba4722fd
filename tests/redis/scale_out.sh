#!/usr/bin/env bash
# Scale-out on Redis, end to end with real processes: a redis-server on a loopback port
# (AOF in a temporary folder, so that a restart of Redis keeps what it acknowledged), two
# API replicas with no workers and two worker nodes. Checks, in order:
#   1. a job submitted to one replica is polled and downloaded through the other,
#      byte-identical, and listed the same by both;
#   2. a running job is cancelled through the other replica within seconds;
#   3. SIGKILL of a worker node mid-job: its job is reclaimed and every job succeeds;
#   4. a poison job (its worker process killed at every start) fails as worker_crashed
#      after max_attempts, and the next job succeeds;
#   5. every replica and worker restarted (SIGTERM, grace 0): no job is lost, earlier
#      results are still downloadable;
#   6. Redis stopped: submissions get 503 + Retry-After, readiness fails; Redis started
#      again: the service recovers by itself and the jobs accepted before finish.
# Exit 77 (skipped) without redis-server.
set -uo pipefail
spheremap=$1 make_meshes=$2
command -v redis-server > /dev/null || { echo "redis-server not found: skipped"; exit 77; }
tmp=$(mktemp -d)
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill -9 "$pid" 2> /dev/null; done
  [ -n "${redis_pid:-}" ] && kill -9 "$redis_pid" 2> /dev/null
  wait 2> /dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*"
  for log in "$tmp"/*.log; do echo "--- $log"; tail -n 5 "$log"; done
  exit 1
}
free_port() {
  python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

mkdir -p "$tmp/meshes" "$tmp/redis"
"$make_meshes" "$tmp/meshes" > /dev/null || fail "make_test_meshes"
"$make_meshes" "$tmp/meshes" --stress-glb > /dev/null || fail "make_test_meshes --stress-glb"
small=$tmp/meshes/icosphere4.glb
slow=$tmp/meshes/stress_fingers.glb  # with quality=high: a few seconds of mapping

redis_port=$(free_port)
queue=redis://127.0.0.1:$redis_port
start_redis() {
  redis-server --port "$redis_port" --bind 127.0.0.1 --save "" --appendonly yes \
    --appendfsync always --dir "$tmp/redis" --logfile "$tmp/redis.log" &
  redis_pid=$!
  for _ in $(seq 100); do
    redis-cli -p "$redis_port" ping 2> /dev/null | grep PONG > /dev/null && return
    sleep 0.05
  done
  fail "redis-server did not start"
}

# start_api NAME: an API replica without workers; sets api_NAME to its url.
# The log is emptied here, by this shell, before the replica starts: emptied by the
# background job's own redirection instead, a restart could be read before the child ran
# and the previous replica's "listening" url taken for the new one's (a loaded machine
# then polled a port nothing listened on: healthz 000, jobs "lost").
start_api() {
  local log=$tmp/api_$1.log
  : > "$log"
  "$spheremap" serve --port 0 --workers 0 --queue "$queue" --shutdown-grace-seconds 0 2>> "$log" &
  pids+=($!)
  eval "api_pid_$1=$!"
  for _ in $(seq 200); do
    # The url, not the event alone: a line read while it is being written has no url yet.
    local url
    url=$(grep '"event":"listening"' "$log" | grep -o '"url":"[^"]*"' | cut -d'"' -f4)
    if [ -n "$url" ]; then
      eval "api_$1=$url"
      return
    fi
    sleep 0.05
  done
  fail "API replica $1 did not start"
}
# start_worker NAME: a worker node with one worker; sets worker_pid_NAME.
# Its log keeps the earlier starts' lines: only a line after them tells this start's.
start_worker() {
  local log=$tmp/worker_$1.log
  local before
  before=$(cat "$log" 2> /dev/null | wc -l)
  "$spheremap" worker --queue "$queue" --workers 1 --threads-per-job 1 \
    --visibility-timeout-seconds 3 --shutdown-grace-seconds 0 2>> "$log" &
  pids+=($!)
  eval "worker_pid_$1=$!"
  for _ in $(seq 200); do
    tail -n +$((before + 1)) "$log" | grep -q '"event":"worker_node"' && return
    sleep 0.05
  done
  fail "worker node $1 did not start"
}
# submit URL FILE [QUERY]: prints the new job's id.
submit() {
  curl -s -D - -o /dev/null -X POST -H 'Content-Type: model/gltf-binary' \
    --data-binary "@$2" "$1/v1/jobs${3:+?$3}" | tr -d '\r' | awk 'tolower($1) == "spheremap-job:" {print $2}'
}
field() {  # field URL ID KEY: a top-level field of the job's JSON
  curl -s "$1/v1/jobs/$2" | python3 -c "import json,sys; print(json.load(sys.stdin).get(sys.argv[1], ''))" "$3"
}
# wait_status URL ID STATUS SECONDS
wait_status() {
  local now
  for _ in $(seq $((${4} * 10))); do
    now=$(field "$1" "$2" status)
    [ "$now" = "$3" ] && return 0
    case $now in succeeded | failed | cancelled) [ "$now" != "$3" ] && break ;; esac
    sleep 0.1
  done
  # What the replica answers at all (000: nothing listens at $1), to tell a lost job from
  # a replica that is gone.
  fail "job $2 is '$now', expected '$3': $(curl -s "$1/v1/jobs/$2" | head -c 600)" \
    "(GET $1/healthz: $(curl -s -o /dev/null -w '%{http_code}' "$1/healthz"))"
}

start_redis
start_api a
start_api b
start_worker 1
start_worker 2

# 1. One replica takes the job, the other serves it.
id=$(submit "$api_a" "$small")
[ -n "$id" ] || fail "submission to replica a"
wait_status "$api_b" "$id" succeeded 30
curl -sf -o "$tmp/from_a.glb" "$api_a/v1/jobs/$id/artifacts/sphere.glb" || fail "download from a"
curl -sf -o "$tmp/from_b.glb" "$api_b/v1/jobs/$id/artifacts/sphere.glb" || fail "download from b"
cmp -s "$tmp/from_a.glb" "$tmp/from_b.glb" || fail "replicas serve different bytes"
[ -s "$tmp/from_a.glb" ] || fail "empty sphere.glb"
first=$id
[ "$(field "$api_a" "$id" status)" = "$(field "$api_b" "$id" status)" ] || fail "replicas disagree"
id=$(submit "$api_b" "$small")
wait_status "$api_a" "$id" succeeded 30
code=$(curl -s -o /dev/null -w '%{http_code}' -X DELETE "$api_a/v1/jobs/$id")
[ "$code" = 204 ] || fail "DELETE of a finished job through a: $code"
code=$(curl -s -o /dev/null -w '%{http_code}' "$api_b/v1/jobs/$id")
[ "$code" = 404 ] || fail "a deleted job through b: $code"
echo "1. submitted to a, polled and downloaded through b: identical ($(wc -c < "$tmp/from_a.glb") bytes); deleted through a, gone from b"

# 2. Progress as Server-Sent Events from the other replica, then cancel through it.
id=$(submit "$api_a" "$slow" "quality=high")
wait_status "$api_b" "$id" running 30
curl -s -N -m 2 "$api_b/v1/jobs/$id/events" > "$tmp/events.txt"
grep -q '^event: progress' "$tmp/events.txt" || fail "no progress events through b: $(head -c 300 "$tmp/events.txt")"
grep -q '"status":"running"' "$tmp/events.txt" || fail "the events show no running job"
code=$(curl -s -o /dev/null -w '%{http_code}' -X DELETE "$api_b/v1/jobs/$id")
[ "$code" = 202 ] || fail "DELETE of a running job through b: $code"
wait_status "$api_a" "$id" cancelled 5
echo "2. a job submitted to a streamed its progress through b, and was cancelled through b"

# 3. A worker node killed mid-job: its job is finished by the other node.
j1=$(submit "$api_a" "$slow" "quality=high")
j2=$(submit "$api_b" "$slow" "quality=high")
wait_status "$api_a" "$j1" running 30
wait_status "$api_a" "$j2" running 30
kill -9 "$worker_pid_1"
wait "$worker_pid_1" 2> /dev/null
wait_status "$api_b" "$j1" succeeded 90
wait_status "$api_b" "$j2" succeeded 90
start_worker 1
echo "3. worker node 1 SIGKILLed mid-job: both jobs succeeded"

# 4. A poison job: its worker process dies at every start.
id=$(submit "$api_a" "$slow" "quality=high")
for _ in $(seq 600); do
  status=$(field "$api_a" "$id" status)
  case $status in succeeded | failed | cancelled) break ;; esac
  [ "$status" = running ] && pkill -9 -P "$worker_pid_1,$worker_pid_2" -f "worker-process"
  sleep 0.1
done
[ "$status" = failed ] || fail "poison job ended '$status'"
curl -s "$api_b/v1/jobs/$id" | grep '"type": "/v1/problems/worker_crashed"' > /dev/null ||
  fail "poison job: $(curl -s "$api_b/v1/jobs/$id")"
curl -s "$api_b/v1/jobs/$id" | grep 'attempt 3 of 3' > /dev/null || fail "poison job: attempts not said"
id=$(submit "$api_b" "$small")
wait_status "$api_a" "$id" succeeded 30
echo "4. poison job failed as worker_crashed after 3 attempts; the next job succeeded"

# 5. Every replica and worker restarted while jobs wait and run.
jobs=()
for _ in 1 2; do jobs+=("$(submit "$api_a" "$slow" "quality=high")"); done
for _ in 1 2; do jobs+=("$(submit "$api_b" "$small")"); done
sleep 1
for pid in $api_pid_a $api_pid_b $worker_pid_1 $worker_pid_2; do kill -TERM "$pid"; done
for pid in $api_pid_a $api_pid_b $worker_pid_1 $worker_pid_2; do wait "$pid"; done
start_api a
start_api b
start_worker 1
start_worker 2
for id in "${jobs[@]}"; do wait_status "$api_b" "$id" succeeded 120; done
curl -sf -o "$tmp/again.glb" "$api_b/v1/jobs/$first/artifacts/sphere.glb" || fail "earlier result lost"
cmp -s "$tmp/again.glb" "$tmp/from_a.glb" || fail "earlier result changed"
echo "5. every process restarted: ${#jobs[@]} jobs succeeded, an earlier result still downloadable"

# 6. Redis stopped, then started again.
jobs=("$(submit "$api_a" "$slow" "quality=high")" "$(submit "$api_b" "$small")")
redis-cli -p "$redis_port" shutdown > /dev/null 2>&1
wait "$redis_pid" 2> /dev/null
headers=$(curl -s -D - -o /dev/null -X POST -H 'Content-Type: model/gltf-binary' \
  --data-binary "@$small" "$api_a/v1/jobs" | tr -d '\r')
[[ "$headers" == "HTTP/1.1 503"* ]] || fail "submission with Redis down: $headers"
grep -qi '^retry-after:' <<< "$headers" || fail "no Retry-After with Redis down"
code=$(curl -s -o /dev/null -w '%{http_code}' "$api_b/readyz")
[ "$code" = 503 ] || fail "readyz with Redis down: $code"
sleep 2
start_redis
for _ in $(seq 100); do
  [ "$(curl -s -o /dev/null -w '%{http_code}' "$api_a/readyz")" = 200 ] && break
  sleep 0.1
done
for id in "${jobs[@]}"; do wait_status "$api_a" "$id" succeeded 120; done
id=$(submit "$api_b" "$small")
wait_status "$api_a" "$id" succeeded 30
echo "6. Redis stopped and started: 503 + Retry-After meanwhile, then every job succeeded"
echo "scale-out: ok"
