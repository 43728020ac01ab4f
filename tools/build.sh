#!/usr/bin/env bash
# Configures (once) and builds jetrace (Release) into build/. Used by the other scripts.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${JETRACE_BUILD_DIR:-$root/build}"
jobs="${JETRACE_JOBS:-$(nproc)}"
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="${CXX:-g++}" >/dev/null
fi
cmake --build "$build" -j "$jobs"
