#!/usr/bin/env bash
# Configures and builds build-sanitized/: clang with AddressSanitizer and
# UndefinedBehaviorSanitizer (any report is fatal), libFuzzer's coverage instrumentation in
# every library, line tables (-g1) for the reports' stacks, warnings as errors, no
# benchmarks. The sanitizer pass of scripts/test.sh runs the test suite in it, and
# tests/fuzz/run.sh builds its fuzzers in it.
# Why one build for both: the sanitizer pass and the fuzzers used to build the whole project
# twice more (gcc with sanitizers, then clang with sanitizers and coverage), the two
# largest parts of CI's time. A second compiler also reads the code differently: clang
# found a JSON array that gcc wrote as an array and clang as an object.
# Usage: scripts/build-sanitized.sh [TARGET...]  (no target: everything, tests included)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/compiler-cache.sh
CC=clang CXX=clang++ cmake -S . -B build-sanitized -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DSPHEREMAP_FUZZ=ON \
  -DSPHEREMAP_WERROR=ON -DSPHEREMAP_BUILD_BENCH=OFF > /dev/null
targets=()
for target in "$@"; do targets+=(--target "$target"); done
cmake --build build-sanitized -j "$(nproc)" "${targets[@]}"
