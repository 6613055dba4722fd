#!/usr/bin/env bash
# Installs what spheremap needs to build and test, from Debian 12's packages only.
# Idempotent: installs nothing when everything is already there.
set -euo pipefail
packages=(build-essential cmake ninja-build pkg-config nlohmann-json3-dev libgtest-dev libdraco-dev
  libcpp-httplib-dev libhiredis-dev redis-server libmeshoptimizer-dev libeigen3-dev zlib1g-dev libpng-dev libturbojpeg0-dev clang-format curl
  # a compiler cache: rebuilds of unchanged sources (scripts/compiler-cache.sh)
  ccache
  # headless Chromium drives the web page in the tests (with npm playwright-core)
  chromium
  # the libFuzzer targets (tests/fuzz) build with clang and its fuzzer runtime
  clang libclang-rt-14-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep "install ok installed" > /dev/null || missing+=("$p")
done
# node and npm: three.js for the page (web/, built into the binary), and in the tests the
# Khronos glTF validator, gltfpack, gltf-transform and playwright-core (npm registry).
command -v npm > /dev/null || missing+=(nodejs npm)
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
