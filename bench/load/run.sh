#!/usr/bin/env bash
# Load benchmark of the HTTP service: synchronous maps (POST /v1/map) of small meshes at
# several concurrency levels and a mixed load, measured with wrk (Debian); then a soak of
# SOAK_SECONDS (default 600) of mixed load, sampling the server's resident memory.
# Prints the lines BENCHMARKS.md quotes.
# Usage: [ISOLATION=process|thread] [LEVELS="small:1 medium:4 ..."] bench/load/run.sh [corpus dir]
#        [seconds per level] [soak seconds]
set -euo pipefail
cd "$(dirname "$0")/../.."
corpus=$(realpath "${1:-../shared/meshes}")
seconds=${2:-20}
soak=${3:-600}
command -v wrk > /dev/null || { sudo=; [ "$(id -u)" = 0 ] || sudo=sudo; $sudo apt-get install -y -qq wrk; }
scripts/build.sh > /dev/null
work=$(mktemp -d)
trap 'kill $server 2>/dev/null || true; rm -rf "$work"' EXIT
build/tests/make_test_meshes "$work"
small=$work/icosphere2.glb      # 320 triangles
medium=$work/icosphere4.glb     # 5,120 triangles
[ -f "$corpus/spot.glb" ] && medium=$corpus/spot.glb  # 5,856 triangles, a real model
port=18080
# Results are kept within 128 MiB (default 1 GiB) so the soak reaches the cap and shows
# the plateau.
isolation=${ISOLATION:-process}
build/cli/spheremap serve --port $port --queue-capacity 256 --result-memory-bytes 134217728 \
  --worker-isolation "$isolation" 2> "$work/server.log" &
server=$!
sleep 1
url=http://127.0.0.1:$port
rss() { curl -s $url/metrics | awk '/^spheremap_resident_memory_bytes/{printf "%.1f", $2/1048576}'; }

echo "Machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); $(date -u +%Y-%m-%d)"
echo "Command: ISOLATION=$isolation bench/load/run.sh $corpus $seconds $soak (server defaults: workers = cores)"
echo "small = $(basename "$small") ($(stat -c %s "$small") B), medium = $(basename "$medium") ($(stat -c %s "$medium") B)"
echo "RSS at start: $(rss) MiB"
# mixed c=16 overloads on purpose: more than http_threads/2 synchronous waiters get 202 at
# once and a full queue gets 429 (the non2xx column), while accepted jobs keep their latency.
levels=${LEVELS:-"small:1 small:2 small:4 small:8 medium:1 medium:4 mixed:4 mixed:8 mixed:16"}
for load in $levels; do
  load=${load/:/ }
  set -- $load
  files=$small
  [ "$1" = medium ] && files=$medium
  [ "$1" = mixed ] && files="$small $medium"
  printf '%-7s c=%-3s ' "$1" "$2"
  wrk -t "$(( $2 < 2 ? 1 : 2 ))" -c "$2" -d "${seconds}s" --timeout 30s \
    -s bench/load/post_mesh.lua $url -- $files | grep '^LOAD' | cut -d' ' -f2-
done
echo "RSS after the levels: $(rss) MiB"
# Let the overload's accepted jobs finish, so the soak starts from an empty queue.
for _ in $(seq 300); do
  curl -s $url/metrics | grep '^spheremap_queue_depth 0$' > /dev/null && break
  sleep 1
done
if [ "$soak" -gt 0 ]; then
  echo "Soak: mixed load, c=8, ${soak}s; RSS every 60 s (MiB):"
  wrk -t 2 -c 8 -d "${soak}s" --timeout 30s -s bench/load/post_mesh.lua $url -- \
    "$small" "$medium" > "$work/soak.txt" &
  wrk_pid=$!
  samples="$(rss)"
  for _ in $(seq $(( soak / 60 ))); do sleep 60; samples="$samples $(rss)"; done
  wait $wrk_pid
  echo "  $samples"
  grep '^LOAD' "$work/soak.txt" | sed 's/^LOAD/  soak/'
fi
echo "RSS at end: $(rss) MiB"
echo "Responses by code over the whole run:"
curl -s $url/metrics | grep -E '^spheremap_(http_responses_total|jobs_finished_total)' | tr '\n' ' '
echo
