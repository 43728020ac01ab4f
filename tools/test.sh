#!/usr/bin/env bash
# Set-up, build and every test:
#   1. installs dependencies (tools/setup.sh),
#   2. builds everything with g++ -O3, CMake's Release (into build/; a
#      build/ configured here is without link-time optimisation, which would
#      compile the libraries again for each of the 50 executables) and runs
#      the whole CTest suite,
#   3. rebuilds the core and the determinism test with g++ -O0, g++ -O2 with
#      link-time optimisation (as the README's build makes the programs),
#      clang++ -O2 and clang++ -O0 and runs it in each: the pinned golden
#      state hash must come out the same from every compiler, optimisation
#      level and link,
#   4. builds jetrace-verify for aarch64 (build-aarch64/, run under qemu) and
#      WebAssembly (build-wasm/, run under node) and checks that they and the
#      native build print that same golden state hash (tools/cross.sh),
#   5. builds everything with AddressSanitizer + UndefinedBehaviorSanitizer
#      and libFuzzer's coverage (clang++ -O1 with line tables only: file and
#      line in every report, a seventh less compile time than -g; asserts on;
#      UBSan leaves Boost's headers out, cmake/ubsan_ignore.txt) into
#      build-asan/ and runs the whole CTest suite there (the fuzz corpus
#      replays included),
#   6. runs every libFuzzer target of that build for a bounded time
#      (tools/fuzz.sh).
# Options: JETRACE_TEST_LABELS="quick" to run only some labels (default: all);
# JETRACE_FUZZ_SECONDS per fuzz target (default 6).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/tools/setup.sh"
JETRACE_LTO="${JETRACE_LTO:-OFF}" "$root/tools/build.sh"

labels=()
if [ -n "${JETRACE_TEST_LABELS:-}" ]; then labels=(-L "$JETRACE_TEST_LABELS"); fi
ctest --test-dir "$root/build" --output-on-failure -j "$(nproc)" "${labels[@]}"

for cfg in "g++ Debug -O0 OFF" "g++ Release -O2 ON" "clang++ Release -O2 ON" "clang++ Debug -O0 OFF"; do
  read -r cxx type opt lto <<<"$cfg"
  dir="$root/build-determinism-${cxx%++}${opt}"
  echo "== determinism: $cxx $opt (link-time optimisation $lto)"
  cmake -S "$root" -B "$dir" -G Ninja -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE="$type" \
    -DCMAKE_CXX_FLAGS_DEBUG="-O0 -g" -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" \
    -DJETRACE_LTO="$lto" -DJETRACE_DETERMINISM_ONLY=ON >/dev/null
  cmake --build "$dir" -j "$(nproc)" --target test_determinism
  ctest --test-dir "$dir" --output-on-failure
done

echo "== cross-platform: the golden state hash on x86-64, aarch64 (qemu) and wasm (node) (tools/cross.sh)"
"$root/tools/cross.sh"

echo "== sanitizers: ASan + UBSan build of the whole suite and the fuzz targets (clang++, build-asan/)"
# One build for both: clang++ with coverage for libFuzzer in every library,
# so the fuzz targets link against the libraries the suite tests.
asan="$root/build-asan"
if [ ! -f "$asan/CMakeCache.txt" ]; then
  launcher=()
  if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
  cmake -S "$root" -B "$asan" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DJETRACE_SANITIZE=ON -DJETRACE_FUZZ=ON \
    -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -gline-tables-only" "${launcher[@]}" >/dev/null
fi
cmake --build "$asan" -j "$(nproc)"
# The loopback races run on virtual time over real sockets: under ASan they
# are slow enough that two at once can fall behind, so the net tests run one
# at a time there.
# Tests labelled realtime (processes keeping pace with a faster-than-real-time
# clock through the proxy, and the soak's memory check), bench (the
# regression guard's smoke run) and browser (headless Chromium against the
# release binaries; the WebSocket transport's hostile sockets run here in
# test_web_transport, labelled net) run in the build above only.
ctest --test-dir "$asan" --output-on-failure -j "$(nproc)" -LE "net|realtime|bench|browser" "${labels[@]}"
# Tests labelled hosting (the release binaries' files, exit codes, lobby and
# drain controls, Agones, Prometheus) run in the build above only: the
# in-process suites drive the same server code here.
ctest --test-dir "$asan" --output-on-failure -L net -LE "realtime|hosting" "${labels[@]}"

echo "== fuzzing: every target for ${JETRACE_FUZZ_SECONDS:-6} s (tools/fuzz.sh, the targets of build-asan/)"
JETRACE_FUZZ_BUILD="$asan" "$root/tools/fuzz.sh" "${JETRACE_FUZZ_SECONDS:-6}"
