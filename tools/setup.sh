#!/usr/bin/env bash
# Installs every dependency of jetrace from Debian 12 (bookworm) packages.
# Idempotent: does nothing if all are installed. Runs apt-get directly as
# root, through sudo otherwise. Works on a minimal system that has only apt.
#
#   tools/setup.sh           everything (build, tests, tools, cross checks), then
#                            `npm ci` (package-lock.json: three.js for the viewer's
#                            page, puppeteer-core for its tests) when node_modules
#                            is missing or older than the lock file
#   tools/setup.sh --server  only what building jetrace-server needs
#                            (-DJETRACE_TESTS=OFF; deploy/Dockerfile uses it)
set -euo pipefail

# What building jetrace-server needs, and nothing else.
SERVER_PACKAGES=(
  g++ make cmake ninja-build pkg-config
  libenet-dev libeigen3-dev libflatbuffers-dev flatbuffers-compiler
  libcli11-dev libspdlog-dev nlohmann-json3-dev libtinyobjloader-dev libtinygltf-dev libsodium-dev
  libcpp-httplib-dev prometheus-cpp-dev
  # --web: Boost.Beast (header-only) for the game page and browser players' WebSocket, zlib to gzip the page, OpenSSL for --web-cert
  libboost-dev zlib1g-dev libssl-dev
  # WebRTC data channels (server/webrtc): SCTP in user space (OpenSSL does STUN's HMAC and DTLS)
  libusrsctp-dev
)

PACKAGES=(
  # toolchain and build
  build-essential g++ clang cmake ninja-build pkg-config git ca-certificates
  # libraries (all found with find_package / pkg-config)
  libenet-dev libeigen3-dev libflatbuffers-dev flatbuffers-compiler
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev libspdlog-dev nlohmann-json3-dev
  libtinyobjloader-dev libtinygltf-dev libbullet-dev libsodium-dev
  # hosting (server/ops): HTTP (Agones SDK, metrics endpoint), Prometheus text format;
  # prometheus itself for the ops test that scrapes the server
  libcpp-httplib-dev prometheus-cpp-dev prometheus
  # charts, fuzzing runtime
  gnuplot-nox libclang-rt-14-dev
  # cross-platform determinism (tools/cross.sh): aarch64 under qemu, WebAssembly under node;
  # the aarch64 replay verifier checks signatures with Debian's arm64 libsodium (multiarch)
  g++-aarch64-linux-gnu qemu-user emscripten nodejs libsodium-dev:arm64
  # scripts
  python3 procps
  # the browser viewer (client/view): Boost.Beast for HTTP and WebSocket; headless Chromium and a font
  # for its browser tests (the page's three.js and the tests' puppeteer-core come from npm, below)
  libboost-dev zlib1g-dev libssl-dev chromium fonts-dejavu-core
  # WebRTC data channels for browser players (server/webrtc): SCTP in user space
  libusrsctp-dev
)

NPM=1
case "${1:-}" in
  "") ;;
  --server) PACKAGES=("${SERVER_PACKAGES[@]}"); NPM=0 ;;
  *) echo "usage: tools/setup.sh [--server]" >&2; exit 2 ;;
esac

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

# npm: a Node.js that carries its own npm conflicts with Debian's npm
# package, so npm comes from apt only where there is no npm command.
if [ "$NPM" = 1 ] && ! command -v npm >/dev/null 2>&1 && ! dpkg-query -W -f='${Status}' npm 2>/dev/null | grep -q "install ok installed"; then
  missing+=(npm)
fi

npm_ci() {
  [ "$NPM" = 1 ] || return 0
  local root
  root="$(cd "$(dirname "$0")/.." && pwd)"
  if [ -f "$root/node_modules/.package-lock.json" ] && [ "$root/node_modules/.package-lock.json" -nt "$root/package-lock.json" ]; then
    echo "setup: node_modules up to date"
    return 0
  fi
  echo "setup: npm ci"
  (cd "$root" && npm ci --no-audit --no-fund)
}

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} packages already installed"
  npm_ci
  exit 0
fi

SUDO=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO=(sudo); else
    echo "setup: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; fi
fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
# Packages of another architecture (name:arch) need it added to dpkg first.
for p in "${missing[@]}"; do
  arch="${p#*:}"
  if [ "$arch" != "$p" ] && ! dpkg --print-foreign-architectures | grep -qx "$arch"; then
    "${SUDO[@]}" dpkg --add-architecture "$arch"
  fi
done
"${SUDO[@]}" apt-get update -qq
"${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
npm_ci
