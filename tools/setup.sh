#!/usr/bin/env bash
# Installs every dependency of jetrace from Debian 12 (bookworm) packages.
# Idempotent: does nothing if all are installed. Runs apt-get directly as
# root, through sudo otherwise. Works on a minimal system that has only apt.
set -euo pipefail

PACKAGES=(
  # toolchain and build
  build-essential g++ clang cmake ninja-build pkg-config git ca-certificates
  # libraries (all found with find_package / pkg-config)
  libenet-dev libeigen3-dev libflatbuffers-dev flatbuffers-compiler
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev libspdlog-dev nlohmann-json3-dev
  libtinyobjloader-dev libbullet-dev libsodium-dev
  # hosting (server/ops): HTTP (Agones SDK, metrics endpoint), Prometheus text format;
  # prometheus itself for the ops test that scrapes the server
  libcpp-httplib-dev prometheus-cpp-dev prometheus
  # charts, fuzzing runtime
  gnuplot-nox libclang-rt-14-dev
  # cross-platform determinism (tools/cross.sh): aarch64 under qemu, WebAssembly under node
  g++-aarch64-linux-gnu qemu-user emscripten nodejs
  # scripts
  python3 procps
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi

SUDO=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO=(sudo); else
    echo "setup: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; fi
fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${SUDO[@]}" apt-get update -qq
"${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
