#!/usr/bin/env bash
# Builds the jetrace-server container image (deploy/Dockerfile) with podman,
# runs it with --network=host on a free UDP port, races jetrace-bot bots from
# the host build against it, checks that every bot finished and that the
# server exited 0, and removes the container. Takes minutes (the image build
# compiles the server): not part of tools/test.sh or CTest.
#
# Follows the podman recipe of these machines: runc with no default ulimits
# (CONTAINERS_CONF), --network=host, a Debian 12 base image made by
# debootstrap and imported as localhost/debian-base:12 (made if missing).
#
#   JETRACE_BOTS (2)   bots, all on one 1-lap race of JETRACE_TRACK (ring)
#   JETRACE_IMAGE (jetrace-server)   the image's name
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
bots="${JETRACE_BOTS:-2}"
track="${JETRACE_TRACK:-ring}"
image="${JETRACE_IMAGE:-jetrace-server}"
base=localhost/debian-base:12
name="jetrace-race-$$"

for tool in podman runc debootstrap; do
  command -v "$tool" >/dev/null || { echo "container_race: $tool not found (apt-get install podman runc debootstrap)" >&2; exit 2; }
done
runc_bin="$(command -v runc)"
conf="$(mktemp)"
out="$(mktemp -d)"
printf '[containers]\ndefault_ulimits = []\n' >"$conf"
export CONTAINERS_CONF="$conf"
pod() { podman --runtime "$runc_bin" "$@"; }
cleanup() {
  pod rm -f "$name" >/dev/null 2>&1 || true
  rm -rf "$out" "$conf"
}
trap cleanup EXIT

if ! podman image exists "$base"; then
  echo "container_race: making $base with debootstrap"
  rootfs="$(mktemp -d)"
  mirror="$(sed -n 's/^URIs: //p' /etc/apt/sources.list.d/debian.sources 2>/dev/null | head -1)"
  debootstrap --variant=minbase bookworm "$rootfs" "${mirror:-http://deb.debian.org/debian}" >"$out/debootstrap.log"
  tar -C "$rootfs" -c . | podman import - "$base" >/dev/null
  rm -rf "$rootfs"
fi

# The bots run from the host build.
[ -x build/client/jetrace-bot ] || cmake --build build --target jetrace-bot >/dev/null

start=$(date +%s)
pod build --pull=never --network=host --build-arg BASE="$base" -t "$image" -f deploy/Dockerfile . >"$out/build.log" 2>&1 ||
  { tail -n 40 "$out/build.log" >&2; echo "container_race: image build failed" >&2; exit 1; }
build_s=$(( $(date +%s) - start ))
size_mb=$(( $(podman image inspect "$image" --format '{{.Size}}') / 1000000 ))
echo "container_race: built $image in ${build_s} s, ${size_mb} MB"

# A free UDP port: bind port 0 on the host, then hand it to the container.
port="$(python3 -c 'import socket; s=socket.socket(socket.AF_INET, socket.SOCK_DGRAM); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
pod run -d --name "$name" --network=host "$image" --bind 127.0.0.1 --port "$port" --track "$track" --laps 1 \
  --min-players "$bots" --max-players "$bots" --races 1 --countdown 1 --log-level info >/dev/null
for _ in $(seq 1 100); do
  pod logs "$name" 2>/dev/null | grep -q '^listening on' && break
  sleep 0.1
done
pod logs "$name" 2>/dev/null | grep -q '^listening on' ||
  { pod logs "$name" >&2 || true; echo "container_race: the server did not start" >&2; exit 1; }
echo "container_race: server in container $name on 127.0.0.1:$port, $bots bots, 1 lap of $track"

race_start=$(date +%s)
build/client/jetrace-bot --connect "127.0.0.1:$port" --track "$track" --count "$bots" --max-seconds 300 \
  >"$out/bots.json" 2>"$out/bots.log" || true
code="$(timeout 60 podman wait "$name" || echo timeout)"
race_s=$(( $(date +%s) - race_start ))
pod logs "$name" >"$out/server.log" 2>&1 || true
grep -v '^{' "$out/server.log" | grep -iv '^\[' | grep -v '^listening' || true
echo "server figures: $(grep '^{' "$out/server.log" || true)"
echo "bot figures:"
cat "$out/bots.json"
finished="$(grep -c '"finished":true' "$out/bots.json" || true)"
echo "container_race: $finished of $bots bots finished in ${race_s} s; the server exited with $code"
[ "$code" = 0 ] || { tail -n 30 "$out/server.log" >&2; echo "container_race: the server did not exit 0" >&2; exit 1; }
[ "$finished" = "$bots" ] || { cat "$out/bots.log" >&2; echo "container_race: not every bot finished" >&2; exit 1; }
echo "container_race: ok"
