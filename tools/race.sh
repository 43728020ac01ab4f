#!/usr/bin/env bash
# The main job: set-up (dependencies, build), then a race on loopback: a
# jetrace-server and 4 jetrace-bot AI drivers, 3 laps of `stadium`; prints
# the results table, the server's and the bots' figures, and checks that the
# recorded replay re-simulates to the server's final state hash.
#
# Environment: JETRACE_TRACK (stadium), JETRACE_LAPS (3), JETRACE_BOTS (4),
# JETRACE_TIME_SCALE (1 = real time; larger runs the clocks faster).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
. "$root/tools/server_port.sh"
"$root/tools/setup.sh"
# The build's progress, in tenths (a fresh build takes about 20 minutes on 2
# cores): ninja's [N/M] lines thinned out, and any error in full.
echo "race: building into build/ (and the browser client into build-wasm/)"
"$root/tools/build.sh" 2>&1 | awk '
  /^\[[0-9]+\/[0-9]+\]/ {
    step = $1; gsub(/[][]/, "", step); split(step, a, "/"); p = int(100 * a[1] / a[2])
    if (p < last) last = -10
    if (p >= last + 10 || a[1] == a[2]) { printf "race: build %d%% (%s steps)\n", p, a[2]; last = p; fflush() }
    next
  }
  /^build: / { print "race: " substr($0, 8); fflush(); next }
  /error|Error|FAILED|warning:/ { print; fflush() }'

track="${JETRACE_TRACK:-stadium}"
laps="${JETRACE_LAPS:-3}"
bots="${JETRACE_BOTS:-4}"
scale="${JETRACE_TIME_SCALE:-1}"
bin="$root/build"
out="$(mktemp -d)"
trap 'kill "$server_pid" 2>/dev/null || true; rm -rf "$out"' EXIT

"$bin/server/jetrace-server" --bind 127.0.0.1 --port 0 --track "$track" --laps "$laps" \
  --min-players "$bots" --max-players "$bots" --races 1 --time-scale "$scale" \
  --results "$out/results.json" --record "$out/race.replay" --log-level warn >"$out/server.log" 2>&1 &
server_pid=$!
port="$(server_port "$out/server.log")"
echo "race: server on 127.0.0.1:$port, $bots bots, $laps laps of $track (time scale $scale)"

"$bin/client/jetrace-bot" --connect "127.0.0.1:$port" --count "$bots" --time-scale "$scale" >"$out/bots.json" || true
wait "$server_pid" || { echo "race: server failed"; cat "$out/server.log"; exit 1; }

grep -v '^{' "$out/server.log" | grep -v '^listening' || true
echo "server figures: $(grep '^{' "$out/server.log")"
echo "bot figures:"
cat "$out/bots.json"
server_hash="$(sed -n 's/^state_hash=//p' "$out/server.log" | tail -n 1)"
replay_hash="$("$bin/tools/jetrace-sim" --replay "$out/race.replay" | sed -n 's/^state_hash=//p')"
echo "replay: server state_hash=$server_hash, re-simulated state_hash=$replay_hash"
[ "$server_hash" = "$replay_hash" ] || { echo "race: replay does not reproduce the race"; exit 1; }
