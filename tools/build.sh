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
