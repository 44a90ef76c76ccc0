#!/usr/bin/env bash
# Builds and runs every test, as the README's second command and CI (.ci/run) do:
#   1. installs any missing Debian package of .ci/packages (what ringtol needs) and
#      .ci/test-packages (what its tests need; needs root, as on a fresh machine),
#   2. Release build with warnings as errors (benchmarks compiled, not run), all tests;
#      a unity build, each library's files compiled as one, where two files' helpers of
#      one name collide,
#   3. a build under AddressSanitizer + UndefinedBehaviorSanitizer (-O1 -g1), all tests;
#      each file compiled alone, where a file that lacks an include fails.
set -euo pipefail
cd "$(dirname "$0")/.."

missing=()
while read -r package; do
  [ -n "$package" ] || continue
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done < <(cat .ci/packages .ci/test-packages)
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  apt-get update
  DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
fi

jobs=$(nproc)
# A test still running after this many seconds fails by name instead of holding the run
# until CI's limit; the slowest, under the sanitizers, take about a minute.
test_seconds=900
# Each stage says how long it took, so that a run near CI's limit shows where its time went.
stage() {
  local started=$SECONDS
  "$@"
  echo "run_all: $(( SECONDS - started )) s: $*"
}
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DRINGTOL_WERROR=ON -DRINGTOL_BENCHMARKS=ON \
  -DCMAKE_UNITY_BUILD=ON
stage cmake --build build/release -j "$jobs"
stage ctest --test-dir build/release -j "$jobs" --output-on-failure --timeout "$test_seconds"

cmake -S . -B build/sanitize -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRINGTOL_WERROR=ON -DRINGTOL_SANITIZE=ON
stage cmake --build build/sanitize -j "$jobs"
LSAN_OPTIONS="suppressions=$PWD/tests/support/lsan.supp" stage ctest --test-dir build/sanitize -j "$jobs" --output-on-failure --timeout "$test_seconds"
