#!/usr/bin/env bash
# Cross-platform determinism: builds jetrace-verify for
#   native   x86-64, the normal build (build/, tools/build.sh),
#   aarch64  g++-aarch64-linux-gnu into build-aarch64/, run under qemu-aarch64,
#   wasm     emscripten into build-wasm/, run under node,
# (aarch64 and wasm: JETRACE_PORTABLE_ONLY, Ninja, Release, -O2), runs
# `jetrace-verify --golden` on each, and fails unless all three print the
# golden state hash pinned in tests/core/test_determinism.cpp (kGoldenStadiumHash).
# Then a race of the x86-64 jetrace-server with 3 jetrace-bot drivers (ring, 1
# lap, 4x real time) is recorded as a signed replay; jetrace-sim --verify
# --key checks it natively, and jetrace-verify on every platform must find
# it whole with the server's final state hash (--expect).
# Prints the JSON lines and a summary line per check. Configures a build directory
# only when it has not been (Ninja re-runs CMake itself when a CMakeLists.txt
# changes), so a second run only checks.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
jobs="${JETRACE_JOBS:-$(nproc)}"
# emcc's optimizer needs Debian's acorn module, which node does not find by itself.
export NODE_PATH="/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}"
platforms=(native aarch64 wasm)
. "$root/tools/server_port.sh"

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
  golden="$(sed -n 's/.*kGoldenStadiumHash = 0x\([0-9a-f]\{16\}\)ull;.*/\1/p' "$root/tests/core/test_determinism.cpp")"
  [ "${#golden}" -eq 16 ] || fail "kGoldenStadiumHash not found in tests/core/test_determinism.cpp"
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

# A live race recorded by the x86-64 server verifies on every platform.
check_replay() {
  local out server_pid port server_hash line signer
  out="$(mktemp -d)"
  # shellcheck disable=SC2064  # expand now: out is local
  trap "kill \$server_pid 2>/dev/null || true; rm -rf '$out'" RETURN
  "$root/build/tools/jetrace-token" keygen --out "$out/replay.key" >/dev/null
  "$root/build/server/jetrace-server" --bind 127.0.0.1 --port 0 --track ring --laps 1 --min-players 3 \
    --max-players 3 --races 1 --time-scale 4 --countdown 1 --record "$out/race.jtr" --sign-key "$out/replay.key" \
    --log-level warn >"$out/server.log" 2>&1 &
  server_pid=$!
  port="$(server_port "$out/server.log")"
  timeout 120 "$root/build/client/jetrace-bot" --connect "127.0.0.1:$port" --count 3 --time-scale 4 \
    --max-seconds 100 >"$out/bots.json" 2>"$out/bots.log" || { cat "$out/bots.log" >&2; fail "the bots failed"; }
  wait "$server_pid" || { cat "$out/server.log" >&2; fail "the server failed"; }
  server_hash="$(sed -n 's/^state_hash=//p' "$out/server.log" | tail -n 1)"
  [ "${#server_hash}" -eq 16 ] || fail "the server printed no state_hash"
  line="$("$root/build/tools/jetrace-sim" --verify "$out/race.jtr" --key "$out/replay.key.pub" --expect "$server_hash")" \
    || { echo "$line"; fail "native jetrace-sim --verify --key refused the server's replay"; }
  echo "$line"
  signer="$(json_field "$line" signer)"
  for p in "${platforms[@]}"; do
    # WebAssembly has no libsodium: there the signature is unchecked, so only the rest is required.
    local want=(--signer "$signer")
    [ "$p" = wasm ] && want=()
    line="$(verify "$p" "$out/race.jtr" --expect "$server_hash" "${want[@]}")" \
      || { echo "$line"; fail "$p: the replay does not verify"; }
    echo "$line"
  done
  echo "cross: replay of a live race ($(stat -c %s "$out/race.jtr") bytes, signed): ${platforms[*]} all verify it" \
    "with the server's state_hash $server_hash (signature by the server's key: checked on native and aarch64)"
}

build_all
check_golden
check_replay
