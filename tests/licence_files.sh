#!/usr/bin/env bash
# The licence and the third-party notices are present, name every dependency the build
# finds, and ship in the npm package (the container image is checked by
# docker/smoke-test.sh, which needs an engine). Usage: tests/licence_files.sh
set -euo pipefail
cd "$(dirname "$0")/.."
fail() { echo "FAIL: $*"; exit 1; }
[ -f LICENSE ] || fail "no LICENSE"
grep -q '^MIT License' LICENSE || fail "LICENSE is not the MIT licence the notices describe"
[ -f THIRD_PARTY_NOTICES.md ] || fail "no THIRD_PARTY_NOTICES.md"
# Every library CMake looks for, by the name the notices use.
declare -A notice_name=([nlohmann_json]=nlohmann/json [draco]=Draco [meshoptimizer]=meshoptimizer
  [ZLIB]=zlib [OpenMP]=libgomp [cpp-httplib]=cpp-httplib [hiredis]=hiredis [libturbojpeg]=libjpeg-turbo
  [PNG]=libpng [Eigen3]=Eigen [GTest]=GoogleTest [PkgConfig]=)
deps=$(git ls-files 'CMakeLists.txt' '*/CMakeLists.txt' | xargs sed -n \
  -e 's/.*find_package(\([A-Za-z0-9_]*\).*/\1/p' \
  -e 's/.*pkg_check_modules([A-Z]* REQUIRED IMPORTED_TARGET \([a-z0-9-]*\)).*/\1/p' | sort -u)
for dep in $deps; do
  [ -n "${notice_name[$dep]+set}" ] || fail "CMake finds '$dep': add it to THIRD_PARTY_NOTICES.md and this test"
  name=${notice_name[$dep]}
  [ -z "$name" ] || grep -q -- "$name" THIRD_PARTY_NOTICES.md || fail "THIRD_PARTY_NOTICES.md does not name $name ($dep)"
done
# Every npm package bundled into what we ship (the page's dependencies).
for pkg in $(node -e 'console.log(Object.keys(require("./web/package.json").dependencies).join(" "))'); do
  grep -qi "npm \`$pkg\`" THIRD_PARTY_NOTICES.md || fail "THIRD_PARTY_NOTICES.md does not name npm package $pkg"
done
for f in LICENSE THIRD_PARTY_NOTICES.md; do
  cmp -s "$f" "clients/js/$f" || fail "clients/js/$f differs from ./$f (copy it again)"
done
grep -q '"license": "MIT"' clients/js/package.json || fail "clients/js/package.json: no MIT license field"
packed=$(cd clients/js && npm pack --dry-run --json 2> /dev/null)
for f in LICENSE THIRD_PARTY_NOTICES.md; do
  echo "$packed" | grep "\"path\": \"$f\"" > /dev/null || fail "npm pack of clients/js leaves out $f"
done
echo "licence files: LICENSE (MIT), notices naming $(echo $deps | wc -w) CMake dependencies, in the npm package"
