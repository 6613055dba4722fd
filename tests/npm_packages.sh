# Sourced by the shell tests that run npm packages (npm is the only download CI has).
# need_npm_packages [--ci] DIR PATH...: without npm, exit 77 (the test is skipped); when
# any PATH is missing under DIR/node_modules, install DIR's packages (`npm install`, or
# `npm ci` with --ci), and exit 1 when that fails.
# CTest runs several tests that share one DIR at once; on a clean checkout each would
# start its own `npm install` in the same node_modules and they tear each other's trees
# apart (ENOTEMPTY, half-written .bin links). So the check and the install happen under
# an exclusive lock on DIR/node_modules.lock: the first test installs, the others wait
# and then find everything there.
need_npm_packages() {
  local install=install
  [ "$1" = --ci ] && { install=ci; shift; }
  local dir=$1
  shift
  command -v npm > /dev/null || { echo "npm not found: skipped"; exit 77; }
  (
    flock 9 || { echo "FAIL: cannot lock $dir/node_modules.lock"; exit 1; }
    for path in "$@"; do
      [ -e "$dir/node_modules/$path" ] && continue
      cd "$dir" && npm "$install" --no-audit --no-fund --loglevel=error ||
        { echo "FAIL: npm $install in $dir"; exit 1; }
      exit 0
    done
  ) 9> "$dir/node_modules.lock" || exit 1
}
