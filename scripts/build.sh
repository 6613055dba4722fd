#!/usr/bin/env bash
# Configures and builds spheremap (Release, warnings as errors) into build/.
# Usage: scripts/build.sh [TARGET...]  (no target: everything, tests included; the
# service alone is the target `spheremap`). Ninja prints its progress ([n/N]).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -f web/node_modules/three/build/three.module.js ]; then
  # Configuring runs it too, silently; said here so a first run does not look stuck.
  echo "installing three.js for the page (npm ci in web/)"
  (cd web && npm ci --no-audit --no-fund)
fi
echo "configuring build/ (cmake)"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSPHEREMAP_WERROR=ON > /dev/null
targets=()
for target in "$@"; do targets+=(--target "$target"); done
echo "building ${*:-everything} with $(nproc) jobs"
cmake --build build -j "$(nproc)" "${targets[@]}"
