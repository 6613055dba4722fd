#!/usr/bin/env bash
# The README's first command: installs what is missing (apt), builds the service alone
# (not the tests), and starts it on http://127.0.0.1:8080 with its built-in defaults
# (Ctrl-C stops it gracefully). Arguments go to `spheremap serve` (e.g. --port 9000,
# --config FILE). When it is ready it prints "spheremap ready: open http://...".
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh spheremap
exec build/cli/spheremap serve "$@"
