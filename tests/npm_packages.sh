# Sourced by the shell tests that run npm packages (npm is the only download CI has).
# need_npm_packages [--ci] DIR PATH...: without npm, exit 77 (the test is skipped); when
# any PATH is missing under DIR/node_modules, install DIR's packages (`npm install`, or
# `npm ci` with --ci), and exit 1 when that fails.
need_npm_packages() {
  local install=install
  [ "$1" = --ci ] && { install=ci; shift; }
  local dir=$1 path
  shift
  command -v npm > /dev/null || { echo "npm not found: skipped"; exit 77; }
  for path in "$@"; do
    [ -e "$dir/node_modules/$path" ] && continue
    (cd "$dir" && npm "$install" --no-audit --no-fund --loglevel=error) ||
      { echo "FAIL: npm $install in $dir"; exit 1; }
    return
  done
}
