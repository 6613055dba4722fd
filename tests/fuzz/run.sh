#!/usr/bin/env bash
# Builds the glTF reader's libFuzzer target with clang (ASan + UBSan) and runs it for
# SECONDS (default 60) from a seed corpus: the shared corpus's GLB and Draco GLB files.
# Crashes land in build-fuzz/crashes/; turn each into a regression test.
# Usage: tests/fuzz/run.sh [SECONDS] [CORPUS_DIR]
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-60}
corpus=${2:-../shared/meshes}
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSPHEREMAP_FUZZ=ON -DSPHEREMAP_BUILD_TESTS=OFF > /dev/null
cmake --build build-fuzz --target gltf_fuzzer > /dev/null
mkdir -p build-fuzz/seeds build-fuzz/crashes
find "$corpus" -name '*.glb' -size -2M -exec cp {} build-fuzz/seeds/ \; 2> /dev/null || true
build-fuzz/tests/fuzz/gltf_fuzzer -max_total_time="$seconds" -max_len=4000000 -rss_limit_mb=2048 \
  -artifact_prefix=build-fuzz/crashes/ -print_final_stats=1 build-fuzz/seeds
