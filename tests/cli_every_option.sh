#!/usr/bin/env bash
# Every option a command's --help documents is accepted: each is called, with a valid
# value from the table below, on a small mesh; a usage error ("see spheremap --help") for
# a documented option fails the test, and so does a documented option missing from the
# table (a new option gets a value here when it is documented).
set -uo pipefail
spheremap=$1
fail() { echo "FAIL: $*"; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# An octahedron: closed, genus 0, maps in milliseconds.
printf 'v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n' > "$tmp/o.obj"
printf 'f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n' >> "$tmp/o.obj"

declare -A value=(
  [alpha]=0.5 [attempts]=2 [direct-iterations]=10 [draco-position-bits]=16 [layout]=welded
  [level-iterations]=20 [limit-weight]=0.5 [max-iterations]=100 [mesh]=0 [method]=paper
  [metrics]=$tmp/metrics.json [min-iterations]=5 [offset]=0.2 [offset-placement]=after
  [output]=OUTPUT [presmooth]=2 [quality]=fast [repair-iterations]=100 [safe-steps]=10
  [smooth-vertices]=10 [start-vertices]=100 [stretch-lambda]=0.5 [stretch-sweeps]=5
  [sweep]=gauss-seidel [threads]=1 [time-limit]=60 [weld-tolerance]=0.001 [resolution]=8
  [prepare]=exact [max-hole-fill]=0.1 [max-handle-cycle]=0.5 [wrap-resolution]=64 [wrap-offset]=0.01 [wrap-faces]=3000 [seconds]=2 [host]=127.0.0.1 [port]=0 [timeout]=1 [config]=$tmp/config.json
  [http-threads]=4 [job-time-limit-seconds]=60 [keep-alive-timeout-seconds]=2
  [max-body-bytes]=1000000 [max-faces]=1000 [max-jobs-kept]=10 [max-vertices]=1000
  [max-resource-bytes]=2000000 [max-image-pixels]=1000000
  [queue-capacity]=4 [read-timeout-seconds]=5 [result-memory-bytes]=1000000
  [result-ttl-seconds]=60 [shutdown-grace-seconds]=1 [sync-timeout-seconds]=5
  [threads-per-job]=1 [workers]=1 [worker-isolation]=thread [worker-memory-bytes]=4000000000
  [worker-cpu-seconds]=100 [api-keys]=$tmp/keys [tenant-max-queued]=4 [tenant-max-running]=1
  [queue]=memory:// [trusted-proxies]=127.0.0.1 [visibility-timeout-seconds]=10 [max-attempts]=2
  [redis-payload-timeout-seconds]=5 [redis-payload-timeout-seconds-per-mib]=0.25
  [tenant-result-memory-bytes]=1000000 [cors-origins]=https://a.example [health-port]=0 [geometry-image]=$tmp/gi.png)
flags=" draco largest-component no-centroid no-normal-map no-optimize quiet "
echo '{"workers": 1}' > "$tmp/config.json"
echo 'team-a 0123456789abcdef0123' > "$tmp/keys"

options_of() { "$spheremap" "$1" --help | grep -oE -- '--[a-z0-9][a-z0-9-]*' | sort -u | sed 's/^--//'; }
arguments_for() {  # the option as it is called: a flag, or the option and its value
  local command=$1 option=$2 output=$3
  if [[ "$flags" == *" $option "* ]]; then echo "--$option"; return; fi
  [ -n "${value[$option]+set}" ] || fail "$command --$option is documented but has no test value"
  local v=${value[$option]}
  [ "$v" = OUTPUT ] && v=$output
  echo "--$option" "$v"
}
usage_error() { [[ "$1" == *"see spheremap --help"* ]]; }

count=0
for command in map remesh uv morph info health; do
  output=$tmp/out.glb
  for option in $(options_of "$command"); do
    [ "$option" = help ] && continue
    # shellcheck disable=SC2207
    extra=($(arguments_for "$command" "$option" "$output"))
    case $command in
      info) args=("$tmp/o.obj") ;;
      health) args=(--port 1) ;;  # nothing listens there: not ready, but not a usage error
      *) args=("$tmp/o.obj" -o "$output") ;;
    esac
    [ "$option" = mesh ] && continue  # glTF only; called below on a GLB
    [ "$option" = draco-position-bits ] && extra+=(--draco)  # needs --draco
    [ "$command/$option" = health/port ] && extra=(--port 1)
    # Each call maps an octahedron (milliseconds): one that hangs fails by name.
    err=$(timeout 60 "$spheremap" "$command" "${args[@]}" "${extra[@]}" 2>&1 > /dev/null)
    [ $? -eq 124 ] && fail "$command ${extra[*]} did not end within 60 s"
    usage_error "$err" && fail "$command ${extra[*]}: $err"
    count=$((count + 1))
  done
done
# --mesh on a glTF input, for each command that documents it.
"$spheremap" map "$tmp/o.obj" -o "$tmp/o.glb" --quiet || fail "make a GLB"
for command in map remesh uv morph info; do
  out=$tmp/mesh_$command.glb
  [ "$command" = info ] && set -- "$tmp/o.glb" --mesh 0 || set -- "$tmp/o.glb" -o "$out" --mesh 0
  timeout 60 "$spheremap" "$command" "$@" > /dev/null 2>&1 || fail "$command --mesh 0"
  count=$((count + 1))
done
# serve: each option starts the server (logged "listening"), then SIGTERM stops it.
for option in $(options_of serve); do
  [ "$option" = help ] && continue
  # shellcheck disable=SC2207
  extra=($(arguments_for serve "$option" ""))
  port=(--port 0)
  [ "$option" = port ] && port=()
  # A log of its own per start: a "listening" line left by the previous server must not
  # be taken for this one's (the TERM would then reach the shell before it runs serve).
  log=$tmp/serve_$option.log
  "$spheremap" serve "${port[@]}" "${extra[@]}" 2> "$log" &
  pid=$!
  for _ in $(seq 400); do grep -q '"listening"' "$log" 2> /dev/null && break; sleep 0.05; done
  kill -TERM $pid 2> /dev/null
  # A serve that does not end after TERM fails here, by name, not by CTest's timeout.
  for _ in $(seq 400); do kill -0 $pid 2> /dev/null || break; sleep 0.05; done
  if kill -0 $pid 2> /dev/null; then
    kill -KILL $pid
    fail "serve ${extra[*]} did not stop within 20 s of SIGTERM: $(cat "$log")"
  fi
  wait $pid
  usage_error "$(cat "$log")" && fail "serve ${extra[*]}: $(cat "$log")"
  grep -q '"listening"' "$log" || fail "serve ${extra[*]} did not start: $(cat "$log")"
  count=$((count + 1))
done
echo "every documented option accepted: $count calls"
