#!/usr/bin/env bash
# Times the quick start's compile (the `ringtol` target, Release, tests off) as a normal
# build and as a unity build (-DCMAKE_UNITY_BUILD=ON), cold (ccache off, every object
# removed), alternated ROUNDS times so that a drift of the machine's speed hits both
# alike. Run on a quiet machine from the repository:
#
#   tests/benchmarks/quick_start_build_modes.sh [ROUNDS] [BUILD_ROOT]
#
# Prints one line a build: wall, user and system seconds, and the load average after it.
set -euo pipefail

repo=$(git -C "$(dirname "$0")" rev-parse --show-toplevel)
rounds=${1:-2}
root=${2:-$(mktemp -d /var/tmp/ringtol-build-modes.XXXXXX)}
cmake -S "$repo" -B "$root/normal" -G Ninja -DCMAKE_BUILD_TYPE=Release -DRINGTOL_TESTS=OFF >/dev/null
cmake -S "$repo" -B "$root/unity" -G Ninja -DCMAKE_BUILD_TYPE=Release -DRINGTOL_TESTS=OFF \
  -DCMAKE_UNITY_BUILD=ON >/dev/null
for round in $(seq "$rounds"); do
  for mode in normal unity; do
    ninja -C "$root/$mode" -t clean >/dev/null
    CCACHE_DISABLE=1 /usr/bin/time -f "%e %U %S" -o "$root/time.txt" \
      cmake --build "$root/$mode" --target ringtol -j 2 >/dev/null
    read -r wall user system <"$root/time.txt"
    printf 'round %s %-6s %7.1f s wall %7.1f s user %5.1f s sys  load %s\n' "$round" "$mode" "$wall" "$user" \
      "$system" "$(cut -d' ' -f1-3 /proc/loadavg)"
  done
done
