#!/usr/bin/env bash
# The README's second command and what CI runs: installs what is missing, builds with
# warnings as errors, checks formatting, and runs the whole test suite through CTest.
# Corpus tests read ../shared/meshes (or $SPHEREMAP_CORPUS) and are skipped without it.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
if command -v clang-format > /dev/null; then
  git ls-files '*.cpp' '*.h' | xargs clang-format --dry-run --Werror
fi
cd build
ctest --output-on-failure -j "$(nproc)"
