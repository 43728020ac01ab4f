#!/usr/bin/env bash
# Configures (once) and builds jetrace (Release) into build/. Used by the other scripts.
# JETRACE_LTO=OFF configures a new build dir without link-time optimisation
# (tools/test.sh does: each executable's LTO link compiles the libraries it
# uses again, which is most of a full build's time with 50 executables).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${JETRACE_BUILD_DIR:-$root/build}"
jobs="${JETRACE_JOBS:-$(nproc)}"
if [ ! -f "$build/CMakeCache.txt" ]; then
  launcher=()
  if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
  cmake -S "$root" -B "$build" -G Ninja "${launcher[@]}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="${CXX:-g++}" \
    -DJETRACE_LTO="${JETRACE_LTO:-ON}" >/dev/null
fi
cmake --build "$build" -j "$jobs"

# The game page's client library in WebAssembly (client/web: jetrace_web.js
# and .wasm in build-wasm/client/web/, served by jetrace-server --web), with
# Debian's emscripten; the same build directory as tools/cross.sh's
# WebAssembly jetrace-verify. Skipped with a message where emscripten is not
# installed (tools/setup.sh --server).
if command -v emcmake >/dev/null 2>&1 && [ -z "${JETRACE_NO_WEB:-}" ]; then
  wasm="$root/build-wasm"
  # emcc's optimizer needs Debian's acorn module, which node does not find by itself.
  export NODE_PATH="/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}"
  if [ ! -f "$wasm/build.ninja" ]; then
    echo "build: configuring the WebAssembly client (emscripten) in $wasm"
    # Eigen's CMake config is on the host, outside emscripten's sysroot.
    emcmake cmake -S "$root" -B "$wasm" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" \
      -DJETRACE_PORTABLE_ONLY=ON -DCMAKE_FIND_ROOT_PATH_MODE_PACKAGE=BOTH >/dev/null
  fi
  echo "build: the WebAssembly client (jetrace-web)"
  cmake --build "$wasm" -j "$jobs" --target jetrace-web
else
  echo "build: no emscripten (emcmake): the WebAssembly client for jetrace-server --web is not built"
fi
