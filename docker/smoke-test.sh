#!/usr/bin/env bash
# Builds the image (docker, or podman when no Docker engine runs), starts it on a free
# loopback port, maps a mesh over HTTP and checks the result is a bijective sphere, then
# sends SIGTERM and checks a clean exit (0). Prints the image size and the start-to-ready
# time. Without a registry it makes the base image debian:bookworm-slim itself with
# debootstrap (minbase) and imports it. Leaves the host as it found it: no configuration
# file is written (podman's settings go through $CONTAINERS_CONF, a temporary file) and
# every image the test added (the service, its builder stage, a debootstrapped base) is
# removed at the end. Usage: docker/smoke-test.sh [MESH.glb]
set -euo pipefail
cd "$(dirname "$0")/.."
mesh=${1:-examples/spot.glb}
# Per run (two CI runs on one machine must not share a tag, a container or a port): the
# host port is whichever free one the engine picks on loopback.
image=spheremap:smoke-$$
name=spheremap-smoke-$$
port=
sudo=
[ "$(id -u)" = 0 ] || sudo=sudo
work=$(mktemp -d)
images_before= tracking=
cleanup() {
  $engine rm -f "$name" > /dev/null 2>&1 || true
  if [ -n "$tracking" ]; then  # remove exactly the images this run added
    comm -13 <(echo "$images_before") <($engine images -aq --no-trunc | sort -u) |
      xargs -r $engine rmi -f > /dev/null 2>&1 || true
  fi
  rm -rf "$work"
}
fail() { echo "FAIL: $*"; $engine logs "$name" 2>&1 | tail -20 || true; exit 1; }

if command -v docker > /dev/null && docker info > /dev/null 2>&1; then
  engine=docker
else
  engine=podman
  if ! command -v podman > /dev/null || ! command -v runc > /dev/null ||
     ! command -v debootstrap > /dev/null; then
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
      podman buildah runc debootstrap uidmap > /dev/null
  fi
  # podman here runs with runc (crun is not usable in this sandbox) and ulimits no higher
  # than this process's own hard limits (raising them is not permitted here), set for
  # this run only.
  nofile=$(ulimit -Hn) nproc=$(( $(ulimit -Hu) < 4096 ? $(ulimit -Hu) : 4096 ))
  printf '[containers]\ndefault_ulimits = ["nofile=%s:%s", "nproc=%s:%s"]\n\n[engine]\nruntime = "runc"\n' \
    "$nofile" "$nofile" "$nproc" "$nproc" > "$work/containers.conf"
  export CONTAINERS_CONF=$work/containers.conf
fi
images_before=$($engine images -aq --no-trunc | sort -u) tracking=1
trap cleanup EXIT
echo "engine: $engine"

if ! $engine image inspect debian:bookworm-slim > /dev/null 2>&1 &&
   ! timeout 60 $engine pull -q docker.io/library/debian:bookworm-slim > /dev/null 2>&1; then
  echo "no registry: making debian:bookworm-slim with debootstrap"
  rootfs=$work/rootfs
  $sudo debootstrap --variant=minbase bookworm "$rootfs" http://deb.debian.org/debian > /dev/null
  $sudo rm -rf "$rootfs"/var/cache/apt/archives/*.deb "$rootfs"/var/lib/apt/lists/*
  $sudo tar -C "$rootfs" -c . | $engine import - debian:bookworm-slim > /dev/null
  $sudo rm -rf "$rootfs"
fi

build_start=$(date +%s)
build_options=()
[ "$engine" = podman ] && build_options=(--network=host --format docker)  # docker format keeps HEALTHCHECK
# podman build can mount the host's compiler cache (scripts/compiler-cache.sh): the image's
# Release build of the sources the host just built is then mostly cache hits.
# ccache hashes the locale, so the host's goes in too (only what is set).
if [ "$engine" = podman ] && [ -d "${CCACHE_DIR:-}" ]; then
  build_options+=(-v "$CCACHE_DIR:/ccache")
  for variable in LANG LC_ALL LC_CTYPE LC_MESSAGES; do
    [ -n "${!variable+set}" ] && build_options+=(--build-arg "$variable=${!variable}")
  done
fi
$engine build "${build_options[@]}" -q -f docker/Dockerfile -t $image . > /dev/null
echo "built $image in $(( $(date +%s) - build_start )) s"
size=$($engine image inspect $image --format '{{.Size}}')
echo "image size: $(( size / 1024 / 1024 )) MiB"
[ "$size" -lt $(( 150 * 1024 * 1024 )) ] || fail "the image is over 150 MiB"

start=$(date +%s.%N)
$engine run -d --name "$name" -p 127.0.0.1::8080 -e SPHEREMAP_WORKERS=2 $image > /dev/null
port=$($engine port "$name" 8080/tcp | head -1 | sed 's/.*://')
[ -n "$port" ] || fail "no host port published"
ready=
for _ in $(seq 200); do
  if curl -sf "http://127.0.0.1:$port/readyz" > /dev/null; then ready=1; break; fi
  sleep 0.05
done
[ -n "$ready" ] || fail "not ready"
echo "start to ready: $(echo "$(date +%s.%N) - $start" | bc) s"
$engine exec "$name" /usr/local/bin/spheremap health || fail "HEALTHCHECK command"
curl -sf "http://127.0.0.1:$port/" | grep '<input id="file" type="file"' > /dev/null || fail "GET / is not the page"
[ "$($engine inspect "$name" --format '{{.Config.User}}')" = 10001:10001 ] || fail "runs as root"
# The licences travel with the binary (the image has no shell: copy them out).
for f in LICENSE THIRD_PARTY_NOTICES.md copyright/libdraco-dev copyright/libpng16-16; do
  $engine cp "$name:/usr/share/doc/spheremap/$f" "$work/licence" > /dev/null 2>&1 ||
    fail "the image lacks /usr/share/doc/spheremap/$f"
done
cmp -s LICENSE <($engine cp "$name:/usr/share/doc/spheremap/LICENSE" - 2> /dev/null | tar -xO) ||
  fail "the image's LICENSE differs from the repository's"

if [ ! -f "$mesh" ]; then  # a fresh clone without the corpus: a generated mesh
  build/tests/make_test_meshes "$work" 2> /dev/null || fail "no mesh: build the project first"
  mesh=$work/icosphere4.glb
fi
code=$(curl -sS -o "$work/sphere.glb" -D "$work/headers" -w '%{http_code}' \
  -H 'Content-Type: model/gltf-binary' --data-binary @"$mesh" "http://127.0.0.1:$port/v1/map")
[ "$code" = 200 ] || fail "POST /v1/map answered $code: $(cat "$work/sphere.glb")"
grep -qi '^Spheremap-Bijective: true' "$work/headers" || fail "not bijective: $(cat "$work/headers")"
job=$(grep -i '^Spheremap-Job:' "$work/headers" | tr -d '\r' | cut -d' ' -f2)
curl -sSf "http://127.0.0.1:$port/v1/jobs/$job/artifacts/metrics.json" -o "$work/metrics.json"
grep -q '"bijective": true' "$work/metrics.json" || fail "metrics: not bijective"
grep -q '"bijective_as_written": true' "$work/metrics.json" || fail "metrics: folds as written"
[ "$(head -c 4 "$work/sphere.glb")" = glTF ] || fail "not a GLB"
echo "mapped $(basename "$mesh"): bijective sphere ($(stat -c %s "$work/sphere.glb") bytes)"

$engine kill --signal TERM "$name" > /dev/null
status=$($engine wait "$name")
[ "$status" = 0 ] || fail "exit status $status after SIGTERM"
$engine logs "$name" 2>&1 | grep '"event":"stopped"' > /dev/null || fail "no clean stop in the log"
echo "SIGTERM: drained and exited 0"
echo "container smoke test passed"
