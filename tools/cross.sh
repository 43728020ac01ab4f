#!/usr/bin/env bash
# Cross-platform determinism: builds jetrace-verify for
#   native   x86-64, the normal build (build/, tools/build.sh),
#   aarch64  g++-aarch64-linux-gnu into build-aarch64/, run under qemu-aarch64,
#   wasm     emscripten into build-wasm/, run under node,
# (aarch64 and wasm: JETRACE_PORTABLE_ONLY, Ninja, Release, -O2), runs
# `jetrace-verify --golden` on each, and fails unless all three print the
# golden state hash pinned in tests/test_determinism.cpp (kGoldenStadiumHash).
# Prints the three JSON lines and a summary line. Configures a build directory
# only when it has not been (Ninja re-runs CMake itself when a CMakeLists.txt
# changes), so a second run only checks.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
jobs="${JETRACE_JOBS:-$(nproc)}"
# emcc's optimizer needs Debian's acorn module, which node does not find by itself.
export NODE_PATH="/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}"
platforms=(native aarch64 wasm)

fail() { echo "cross: $*" >&2; exit 1; }

# configure DIR CMD...: runs CMD (a CMake configure) unless DIR is configured.
configure() {
  local dir="$1"; shift
  if [ ! -f "$dir/build.ninja" ]; then "$@" >/dev/null; fi
}

portable_flags=(-G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" -DJETRACE_PORTABLE_ONLY=ON)

build_all() {
  "$root/tools/build.sh"
  configure "$root/build-aarch64" cmake -S "$root" -B "$root/build-aarch64" "${portable_flags[@]}" \
    -DCMAKE_TOOLCHAIN_FILE="$root/cmake/aarch64-linux-gnu.cmake"
  cmake --build "$root/build-aarch64" -j "$jobs" --target jetrace-verify
  # Eigen's CMake config is on the host, outside emscripten's sysroot.
  configure "$root/build-wasm" emcmake cmake -S "$root" -B "$root/build-wasm" "${portable_flags[@]}" \
    -DCMAKE_FIND_ROOT_PATH_MODE_PACKAGE=BOTH
  cmake --build "$root/build-wasm" -j "$jobs" --target jetrace-verify
}

# verify PLATFORM ARGS...: runs that platform's jetrace-verify with ARGS.
verify() {
  local platform="$1"; shift
  case "$platform" in
    native) "$root/build/tools/jetrace-verify" "$@" ;;
    aarch64) qemu-aarch64 -L /usr/aarch64-linux-gnu "$root/build-aarch64/tools/jetrace-verify" "$@" ;;
    wasm) node "$root/build-wasm/tools/jetrace-verify.js" "$@" ;;
  esac
}

# json_field LINE KEY: the value of KEY in a flat JSON line (quotes stripped).
json_field() {
  sed -n "s/.*\"$2\":\"\{0,1\}\([^\",}]*\).*/\1/p" <<<"$1"
}

# The golden race: the same state hash everywhere, and the pinned one.
check_golden() {
  local golden line hash
  golden="$(sed -n 's/.*kGoldenStadiumHash = 0x\([0-9a-f]\{16\}\)ull;.*/\1/p' "$root/tests/test_determinism.cpp")"
  [ "${#golden}" -eq 16 ] || fail "kGoldenStadiumHash not found in tests/test_determinism.cpp"
  declare -A ns
  local bad=0
  for p in "${platforms[@]}"; do
    line="$(verify "$p" --golden)" || fail "$p: jetrace-verify --golden failed"
    echo "$line"
    hash="$(json_field "$line" state_hash)"
    ns[$p]="$(json_field "$line" ns_per_car_step)"
    if [ "$hash" != "$golden" ]; then
      echo "cross: $p: state_hash $hash, pinned golden hash $golden" >&2
      bad=1
    fi
  done
  [ "$bad" -eq 0 ] || fail "golden race: the platforms do not all reproduce the pinned hash"
  echo "cross: golden race: ${platforms[*]} all print the pinned state_hash $golden;" \
    "ns_per_car_step native ${ns[native]}, aarch64 (qemu) ${ns[aarch64]}, wasm (node) ${ns[wasm]}," \
    "wasm/native $(awk -v w="${ns[wasm]}" -v n="${ns[native]}" 'BEGIN { printf "%.2f", w / n }')"
}

build_all
check_golden
