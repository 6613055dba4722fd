#!/usr/bin/env bash
# Configures and builds spheremap (Release, warnings as errors) into build/.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSPHEREMAP_WERROR=ON > /dev/null
cmake --build build -j "$(nproc)"
