#!/usr/bin/env bash
# The README's second command and what CI runs: installs what is missing, builds with
# warnings as errors, checks formatting, and runs the whole test suite through CTest,
# then again built with AddressSanitizer + UndefinedBehaviorSanitizer (any report fails
# the run; SPHEREMAP_SKIP_SANITIZERS=1 skips that pass for quick local runs), then the
# libFuzzer targets for a minute each, then the container smoke test.
# Corpus tests read ../shared/meshes (or $SPHEREMAP_CORPUS) and are skipped without it.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
if command -v clang-format > /dev/null; then
  git ls-files '*.cpp' '*.h' | xargs clang-format --dry-run --Werror
fi
(cd build && ctest --output-on-failure -j "$(nproc)")
if [ "${SPHEREMAP_SKIP_SANITIZERS:-0}" != 1 ]; then
  flags="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSPHEREMAP_WERROR=ON \
    -DSPHEREMAP_BUILD_BENCH=OFF -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" > /dev/null
  cmake --build build-asan -j "$(nproc)"
  # redis_scale_out (kills and restarts of servers, workers and Redis, 2 minutes plain)
  # took 8.5 minutes under the sanitizers, the pass's longest test by 4 minutes: it runs
  # in the plain pass; the Redis queue's code runs sanitized in RedisQueueTest.
  (cd build-asan && ASAN_OPTIONS=detect_leaks=1 ctest --output-on-failure -j "$(nproc)" \
    -E '^redis_scale_out$')
fi
# libFuzzer (clang, ASan + UBSan) for a fixed time from seeds: the glTF reader, and the
# whole request path (content type, query, body, multipart parts) with inputs up to 4 MB,
# and the bytes of a connection through the connection layer and the HTTP parser.
# A crash fails the run; its input is in build-fuzz/crashes/ (SPHEREMAP_SKIP_FUZZ=1 skips).
if [ "${SPHEREMAP_SKIP_FUZZ:-0}" != 1 ]; then
  tests/fuzz/run.sh "${SPHEREMAP_FUZZ_SECONDS:-60}" request_fuzzer
  tests/fuzz/run.sh "${SPHEREMAP_FUZZ_SECONDS:-60}" connection_fuzzer
  tests/fuzz/run.sh "${SPHEREMAP_FUZZ_SECONDS:-60}" gltf_fuzzer
fi
# The container: build the image, map a mesh in it, SIGTERM (docker/smoke-test.sh;
# SPHEREMAP_SKIP_CONTAINER=1 skips it).
if [ "${SPHEREMAP_SKIP_CONTAINER:-0}" != 1 ]; then
  docker/smoke-test.sh
fi
