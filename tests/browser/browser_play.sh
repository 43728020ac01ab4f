#!/usr/bin/env bash
# A player races from a browser with nothing installed (docs/BROWSER.md):
# jetrace-server --web serves the page and the WebAssembly client, which
# joins over the server's WebSocket. 2 jetrace-bot drivers and 1 page race
# one lap of ring; headless Chromium (puppeteer-core, browser_play.mjs)
# drives the page with keys until it finishes, with no corrections on
# loopback but touches and late inputs; the page drew its car where the
# server's recording, re-simulated, has it at the ticks it compared (bit for
# bit, but near another car or after a late input); a ?watch page shows every car without a slot; a late page is
# refused (the race is full) and shows the reason; the metrics count the
# page's player under transport="websocket". The server's results
# must list the page's player as finished, and its replay must verify.
# MODE (docs/BROWSER.md, "Transports"): websocket (the default: the page is
# told ?transport=websocket), webrtc (the page's preferred WebRTC data
# channel: the metrics count it under transport="webrtc"), or fallback (the
# server's SDP answer names a UDP port nothing listens on, as when a
# firewall drops the page's UDP: its ICE fails and it races over the
# WebSocket after its wait, and shows it).
# Usage: browser_play.sh SERVER SIM BOT SOURCE_DIR [MODE]
set -euo pipefail
server="$1" sim="$2" bot="$3" src="$4" mode="${5:-websocket}"
. "$src/tools/server_port.sh"
[ -d "$src/node_modules/puppeteer-core" ] || { echo "no puppeteer-core in $src/node_modules: run npm ci there (tools/setup.sh does)"; exit 1; }
[ -x /usr/bin/chromium ] || { echo "no /usr/bin/chromium: apt-get install chromium (tools/setup.sh does)"; exit 1; }
out="$(mktemp -d)"
spid="" bpid=""
cleanup() {
  for p in $bpid $spid; do kill "$p" 2>/dev/null || true; wait "$p" 2>/dev/null || true; done
  rm -rf "$out"
}
trap cleanup EXIT

rtc_flags=()
if [ "$mode" = fallback ]; then
  # A UDP port bound and released: nothing listens there.
  closed="$(python3 -c 'import socket; s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
  rtc_flags=(--webrtc-candidate-port "$closed")
fi
"$server" --bind 127.0.0.1 --port 0 --web 127.0.0.1:0 "${rtc_flags[@]}" --metrics 127.0.0.1:0 --track ring --laps 1 --min-players 3 --max-players 3 \
  --races 1 --lobby-timeout 60 --countdown 5 --finish-window 120 --results "$out/results.json" \
  --record "$out/race.jtr" >"$out/server.log" 2>&1 &
spid=$!
port="$(server_port "$out/server.log")"
web="$(web_port "$out/server.log")"
metrics="$(sed -n 's/^metrics on \(.*\)$/\1/p' "$out/server.log")"
grep -q "is missing" "$out/server.log" && { echo "the server lacks page files:"; cat "$out/server.log"; exit 1; }
"$bot" --connect "127.0.0.1:$port" --count 2 --name robot --max-seconds 200 >"$out/bot.json" 2>&1 &
bpid=$!
echo "server: ENet port $port, web port $web"

node "$src/tests/browser/browser_play.mjs" "http://127.0.0.1:$web/" "$out/shot.png" "http://$metrics/metrics" \
  "$out/drawn.json" "$mode" ||
  { echo "--- server log:"; cat "$out/server.log"; exit 1; }

rc=0; timeout 60 tail --pid="$spid" -f /dev/null || rc=$?
[ "$rc" = 0 ] || { echo "the server did not exit after the race"; cat "$out/server.log"; exit 1; }
wait "$spid" || true
spid=""
cat "$out/server.log"
python3 - "$out/results.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
names = sorted(s["name"] for s in d["standings"])
assert names == ["human", "robot0", "robot1"], "three players, the watcher not among them: %r" % names
human = [s for s in d["standings"] if s["name"] == "human"][0]
assert human["finished"], "the page's player did not finish: %r" % human
print("server results: human finished in %s s" % human["time_s"])
PY
"$sim" --verify "$out/race.jtr"
# Where the page drew its car at ticks the server confirmed, against the
# recording re-simulated to those ticks: the page's verdict must be the
# recording's (the same doubles, or not), and a tick drawn elsewhere must
# have a cause (a car near, a late input).
python3 - "$sim" "$out/race.jtr" "$out/drawn.json" <<'PY'
import json, subprocess, sys
sim, replay, samples = sys.argv[1], sys.argv[2], json.load(open(sys.argv[3]))
step = max(1, len(samples) // 80)
samples = samples[::step]
assert len(samples) >= 20, "too few ticks compared: %d" % len(samples)
same = 0
for s in samples:
    out = subprocess.run([sim, "--replay", replay, "--stop-tick", str(s["tick"])], capture_output=True, text=True, check=True)
    line = [l for l in out.stdout.splitlines() if l.startswith("{")][-1]
    car = [c for c in json.loads(line)["cars"] if c["slot"] == s["slot"]][0]
    equal = car["p"] == s["p"]
    assert equal == s["same"], "tick %d: the page drew %r and judged it %s; the recording has %r" % (
        s["tick"], s["p"], "the server's" if s["same"] else "off", car["p"])
    assert equal or s["cause"] in ("near_car", "late_input"), "tick %d: drawn off with no cause: %r" % (s["tick"], s)
    same += equal
assert same * 2 >= len(samples), "the page's car was drawn off the server's at %d of %d ticks" % (len(samples) - same, len(samples))
print("the page drew its car at the recording's position, bit for bit, at %d of %d ticks compared (the others near a car or after a late input)" % (same, len(samples)))
PY
