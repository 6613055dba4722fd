# Sourced by the shell tests: start_server LOG [serve flags...] starts `$spheremap serve`
# on a free loopback port and waits until it listens; sets $server (its pid) and $url.
# The caller's EXIT trap stops it (kill $server).
start_server() {
  local log=$1
  shift
  # Emptied by this shell before the server starts, not by the background job's
  # redirection: a LOG used twice must not show the earlier server's url.
  : > "$log"
  "$spheremap" serve --port 0 "$@" 2>> "$log" &
  server=$!
  url=
  for _ in $(seq 400); do
    if grep -q '"event":"listening"' "$log"; then
      url=$(grep '"event":"listening"' "$log" | grep -o '"url":"[^"]*"' | head -1 | cut -d'"' -f4)
      break
    fi
    sleep 0.05
  done
  [ -n "$url" ] || { echo "FAIL: the server did not start: $(tail -3 "$log")"; exit 1; }
}
