#!/usr/bin/env bash
# jetrace-view watch mode in a real browser (headless Chromium driven by
# puppeteer-core, viewer_watch.mjs): jetrace-view --connect joins a
# jetrace-server as an observer, two jetrace-bots race one lap of ring, and
# the page is sampled while they race. Each sample names the render tick and
# the two snapshot ticks the page interpolates between; the server's
# recorded race, re-simulated by jetrace-sim --replay --stop-tick at both,
# interpolated alike, must put every car where the page showed it, to 1 cm.
# The observer must change nothing: the replay verifies and lists 2 players.
# With JETRACE_VIEW_SHOT=FILE.png set, the page's screenshot is kept there
# (docs/images/live_view.png comes from it).
# Usage: viewer_watch.sh SERVER VIEW SIM BOT SOURCE_DIR
set -euo pipefail
server="$1" view="$2" sim="$3" bot="$4" src="$5"
. "$src/tools/server_port.sh"
[ -d "$src/node_modules/puppeteer-core" ] || { echo "no puppeteer-core in $src/node_modules: run npm ci there (tools/setup.sh does)"; exit 1; }
[ -x /usr/bin/chromium ] || { echo "no /usr/bin/chromium: apt-get install chromium (tools/setup.sh does)"; exit 1; }
out="$(mktemp -d)"
spid="" vpid="" bpid=""
cleanup() {
  for p in $vpid $bpid $spid; do kill "$p" 2>/dev/null || true; wait "$p" 2>/dev/null || true; done
  rm -rf "$out"
}
trap cleanup EXIT

"$server" --bind 127.0.0.1 --port 0 --track ring --laps 1 --min-players 2 --max-players 2 --races 1 \
  --countdown 3 --finish-window 60 --results "$out/results.json" --record "$out/race.jtr" >"$out/server.log" 2>&1 &
spid=$!
port="$(server_port "$out/server.log")"

mkfifo "$out/stdout"
"$view" --connect "127.0.0.1:$port" --http 127.0.0.1:0 >"$out/stdout" 2>"$out/view.log" &
vpid=$!
exec 3<"$out/stdout"
read -r line <&3 || { echo "jetrace-view printed no address:"; cat "$out/view.log" "$out/server.log"; exit 1; }
url="${line#listening on }"
[ "$url" != "$line" ] || { echo "unexpected first line: $line"; exit 1; }
echo "viewer at $url, server on port $port"

# The bots join once the page is up, so that it sees the whole race.
node "$src/tests/browser/viewer_watch.mjs" "$url" "$out/samples.json" "$out/shot.png" "$out/ready" &
npid=$!
for _ in $(seq 1 1200); do [ -e "$out/ready" ] || ! kill -0 "$npid" 2>/dev/null && break; sleep 0.1; done
"$bot" --connect "127.0.0.1:$port" --count 2 --name robot --max-seconds 200 >"$out/bot.json" 2>&1 &
bpid=$!
wait "$npid" ||
  { echo "--- jetrace-view log:"; cat "$out/view.log"; echo "--- server log:"; cat "$out/server.log"; exit 1; }

if [ -n "${JETRACE_VIEW_SHOT:-}" ]; then cp "$out/shot.png" "$JETRACE_VIEW_SHOT"; fi
rc=0; timeout 90 tail --pid="$spid" -f /dev/null || rc=$?
[ "$rc" = 0 ] || { echo "the server did not exit after the race"; cat "$out/server.log"; exit 1; }
wait "$spid" || true
spid=""
"$sim" --verify "$out/race.jtr"
grep -q "observing (1 of at most" "$out/server.log" || { echo "the server saw no observer"; cat "$out/server.log"; exit 1; }

python3 - "$sim" "$out/race.jtr" "$out/samples.json" "$out/results.json" <<'PY'
import json, subprocess, sys
sim, replay, samples_path, results_path = sys.argv[1:]
results = json.load(open(results_path))
assert len(results["standings"]) == 2, "the observer took no slot: %r" % results
cache = {}
def world(tick):
    if tick not in cache:
        out = subprocess.run([sim, "--replay", replay, "--stop-tick", str(tick)], check=True,
                             capture_output=True, text=True).stdout
        cache[tick] = {c["slot"]: c for c in json.loads(out)["cars"]}
    return cache[tick]
samples = json.load(open(samples_path))
worst = 0.0
for s in samples:
    r = s["render"]
    a, b, t = r["from"], r["to"], r["tick"]
    assert a <= t < b, "render tick %r outside its snapshots %r..%r" % (t, a, b)
    f = (t - a) / (b - a)
    wa, wb = world(a), world(b)
    for car in s["cars"]:
        ca, cb = wa[car["slot"]], wb[car["slot"]]
        pa, pb = ca["p"], cb["p"]
        # A car that respawned in between is drawn where it was at `from`.
        g = 0.0 if ca["respawns"] != cb["respawns"] else f
        want = [pa[i] + (pb[i] - pa[i]) * g for i in range(3)]
        gap = sum((car["p"][i] - want[i]) ** 2 for i in range(3)) ** 0.5
        worst = max(worst, gap)
        assert gap <= 0.01, "tick %.3f car %d shown at %r, the race had it at %r (%.4f m off)" % (t, car["slot"], car["p"], want, gap)
print("%d samples, %d cars each: every car within %.6f m of the recorded race (limit 0.01 m)" % (len(samples), len(samples[0]["cars"]), worst))
PY
kill -0 "$vpid" || { echo "jetrace-view died"; cat "$out/view.log"; exit 1; }
kill -TERM "$vpid"
rc=0; wait "$vpid" || rc=$?
vpid=""
cat "$out/view.log"
[ "$rc" = 0 ] || { echo "jetrace-view exited $rc on SIGTERM"; exit 1; }
echo "viewer watch: all checks hold"
