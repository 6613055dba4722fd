#!/usr/bin/env bash
# The README's second command and what CI runs: installs what is missing, builds with
# warnings as errors, checks formatting, and runs the whole test suite through CTest,
# then again built by clang with AddressSanitizer + UndefinedBehaviorSanitizer (any report
# fails the run; SPHEREMAP_SKIP_SANITIZERS=1 skips that pass for quick local runs), then
# the libFuzzer targets (from the same build) for a minute each, then the container smoke
# test. Corpus tests read ../shared/meshes (or $SPHEREMAP_CORPUS) and are reported skipped
# without it; the fuzzers then seed from examples/. The last lines say what ran, what was
# skipped and why, the seconds of each step, and the counts.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/compiler-cache.sh
ran=() skipped=() times=() passed=0 failed=0 skipped_tests=0
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT

# ctest_pass NAME DIR [ctest args]: runs CTest in DIR, adds its counts to the totals.
ctest_pass() {
  local name=$1 dir=$2
  shift 2
  local status=0
  (cd "$dir" && ctest --output-on-failure -j "$(nproc)" "$@") 2>&1 | tee "$logs/$name" || status=$?
  local total fails skips
  total=$(sed -n 's/.*tests failed out of \([0-9]*\).*/\1/p' "$logs/$name" | tail -1)
  fails=$(sed -n 's/.* \([0-9]*\) tests failed out of.*/\1/p' "$logs/$name" | tail -1)
  skips=$(grep -c '(Skipped)' "$logs/$name" || true)
  passed=$((passed + ${total:-0} - ${fails:-0} - skips))
  failed=$((failed + ${fails:-0}))
  skipped_tests=$((skipped_tests + skips))
  ran+=("$name CTest (${total:-0} tests, $skips skipped)")
  return $status
}

# timed NAME COMMAND...: runs COMMAND and keeps its wall seconds for the summary, so a CI
# log says where its time went.
timed() {
  local name=$1 start=$SECONDS status=0
  shift
  "$@" || status=$?
  times+=("$name $((SECONDS - start)) s")
  return $status
}

summary() {
  local status=$?
  if [ ! -d "${SPHEREMAP_CORPUS:-../shared/meshes}" ]; then
    skipped+=("corpus tests (no ${SPHEREMAP_CORPUS:-../shared/meshes}: set SPHEREMAP_CORPUS)")
  fi
  echo
  echo "ran: $(IFS=';'; echo "${ran[*]:-nothing}" | sed 's/;/; /g')"
  echo "skipped: $(IFS=';'; echo "${skipped[*]:-nothing}" | sed 's/;/; /g')"
  echo "seconds: $(IFS=';'; echo "${times[*]:-none}" | sed 's/;/, /g'); whole run $SECONDS s"
  [ $status -eq 0 ] || echo "FAILED (exit $status): see the output above"
  echo "tests: $passed passed, $failed failed, $skipped_tests skipped"
  rm -rf "$logs"
}
trap summary EXIT

timed "install" scripts/install-deps.sh
timed "build" scripts/build.sh
if command -v clang-format > /dev/null; then
  git ls-files '*.cpp' '*.h' | xargs clang-format --dry-run --Werror
  ran+=("clang-format")
else
  skipped+=("clang-format (not installed)")
fi
timed "plain pass" ctest_pass plain build
if [ "${SPHEREMAP_SKIP_SANITIZERS:-0}" != 1 ]; then
  # One clang build serves this pass and the fuzzers below (scripts/build-sanitized.sh:
  # ASan + UBSan, libFuzzer's coverage instrumentation, line tables).
  timed "sanitized build" scripts/build-sanitized.sh
  # Run in the plain pass only, to keep CI within its time (the sanitized code they reach
  # runs sanitized in other tests):
  # - redis_scale_out (kills and restarts of servers, workers and Redis, 2 minutes plain)
  #   took 8.5 minutes here; the Redis queue's code runs sanitized in RedisQueueTest;
  # - web_page, js_client and gltf_validator_assets spend their time in Chromium, node
  #   and the validator (200, 14 and 97 s here): the server's routes and outputs they
  #   reach run sanitized in service_tests and textured_outputs;
  # - scatter_envelope (50 s plain: one 20,000-part envelope and its map); the envelope
  #   runs sanitized in envelope_test; its wider retry (retry_level's second pass) is
  #   reached by no smaller mesh we found (scatters of 3,000 and 6,000 quads never fail).
  # (The attack suite skips itself here: it caps the server's address space.)
  export ASAN_OPTIONS=detect_leaks=1
  timed "sanitizer pass" ctest_pass sanitizer build-sanitized \
    -E '^(redis_scale_out|web_page|js_client|gltf_validator_assets|scatter_envelope)$'
  unset ASAN_OPTIONS
else
  skipped+=("sanitizer pass (SPHEREMAP_SKIP_SANITIZERS=1)")
fi
# libFuzzer (clang, ASan + UBSan) for a fixed time from seeds: the glTF reader, and the
# whole request path (content type, query, body, multipart parts) with inputs up to 4 MB,
# and the bytes of a connection through the connection layer and the HTTP parser.
# A crash fails the run; its input is in build-sanitized/crashes/ (SPHEREMAP_SKIP_FUZZ=1 skips).
if [ "${SPHEREMAP_SKIP_FUZZ:-0}" != 1 ]; then
  fuzzers=(request_fuzzer connection_fuzzer gltf_fuzzer mesh_binary_fuzzer)
  # Built together, run nproc at a time (each uses one core).
  timed fuzzers tests/fuzz/run.sh "${SPHEREMAP_FUZZ_SECONDS:-60}" "$(IFS=,; echo "${fuzzers[*]}")"
  ran+=("fuzzers ${fuzzers[*]} (${SPHEREMAP_FUZZ_SECONDS:-60} s each)")
else
  skipped+=("fuzzers (SPHEREMAP_SKIP_FUZZ=1)")
fi
# The container: build the image, map a mesh in it, SIGTERM (docker/smoke-test.sh;
# SPHEREMAP_SKIP_CONTAINER=1 skips it).
if [ "${SPHEREMAP_SKIP_CONTAINER:-0}" != 1 ]; then
  timed "container smoke test" docker/smoke-test.sh
  ran+=("container smoke test")
else
  skipped+=("container smoke test (SPHEREMAP_SKIP_CONTAINER=1)")
fi
