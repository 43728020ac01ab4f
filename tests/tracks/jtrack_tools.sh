#!/usr/bin/env bash
# Compiled tracks from the command line, as a user runs them: jetrace-track
# build compiles ring, stadium and a real level (its manifest); jetrace-sim
# races each compiled track to the same state_hash as its source; a cut and
# a damaged copy are refused with a message and exit non-zero; build reports
# a failed write. About 20 s (three 6-second races per track, twice).
# Usage: jtrack_tools.sh TRACK_TOOL SIM SOURCE_DIR
set -euo pipefail
track="$1" sim="$2" src="$3"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
hash_of() { "$sim" --track "$1" --cars 4 --seconds 6 --seed 5 | sed -n 's/^state_hash=//p'; }
for source in ring stadium "$src/docs/tracks/truck_town.track.json"; do
  name="$(basename "$source" .track.json)"
  "$track" build "$source" --out "$out/$name.jtrack" | tee "$out/build.json"
  grep -q '"identity":"[0-9a-f]\{16\}"' "$out/build.json"
  want="$(hash_of "$source")"
  got="$(hash_of "$out/$name.jtrack")"
  echo "$name: source state_hash=$want compiled state_hash=$got"
  [ "${#want}" = 16 ] && [ "$want" = "$got" ] || { echo "state_hash differs on $name"; exit 1; }
done
expect_refused() {  # expect_refused MESSAGE CMD...: CMD exits non-zero naming MESSAGE
  local message="$1" rc=0; shift
  "$@" >"$out/last" 2>&1 || rc=$?
  cat "$out/last"
  [ "$rc" != 0 ] || { echo "exit 0, expected a refusal: $*"; exit 1; }
  grep -q -- "$message" "$out/last" || { echo "no '$message' in the output of: $*"; exit 1; }
}
head -c 1000 "$out/ring.jtrack" >"$out/cut.jtrack"
expect_refused "truncated" "$sim" --track "$out/cut.jtrack" --seconds 1
cp "$out/ring.jtrack" "$out/bad.jtrack"
printf '\377' | dd of="$out/bad.jtrack" bs=1 seek=200 conv=notrunc status=none
expect_refused "payload checksum mismatch" "$sim" --track "$out/bad.jtrack" --seconds 1
expect_refused "payload checksum mismatch" "$track" inspect "$out/bad.jtrack"
expect_refused "cannot create" "$track" build ring --out /proc/jetrace-no-such/x.jtrack
echo "jtrack tools: ok"
