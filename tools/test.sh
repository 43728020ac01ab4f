#!/usr/bin/env bash
# Set-up, build and every test:
#   1. installs dependencies (tools/setup.sh),
#   2. builds everything with g++ -O2 and runs the whole CTest suite,
#   3. rebuilds the core and the determinism test with g++ -O0, clang++ -O2
#      and clang++ -O0 and runs it in each: the pinned golden state hash must
#      come out the same from every compiler and optimisation level.
# Options: JETRACE_TEST_LABELS="quick" to run only some labels (default: all).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/tools/setup.sh"
"$root/tools/build.sh"

labels=()
if [ -n "${JETRACE_TEST_LABELS:-}" ]; then labels=(-L "$JETRACE_TEST_LABELS"); fi
ctest --test-dir "$root/build" --output-on-failure -j "$(nproc)" "${labels[@]}"

for cfg in "g++ Debug -O0" "clang++ Release -O2" "clang++ Debug -O0"; do
  read -r cxx type opt <<<"$cfg"
  dir="$root/build-determinism-${cxx%++}${opt}"
  echo "== determinism: $cxx $opt"
  cmake -S "$root" -B "$dir" -G Ninja -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE="$type" \
    -DCMAKE_CXX_FLAGS_DEBUG="-O0 -g" -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" \
    -DJETRACE_DETERMINISM_ONLY=ON >/dev/null
  cmake --build "$dir" -j "$(nproc)" --target test_determinism
  ctest --test-dir "$dir" --output-on-failure
done
