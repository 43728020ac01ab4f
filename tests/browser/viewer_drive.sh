#!/usr/bin/env bash
# jetrace-view drive mode in a real browser (headless Chromium driven by
# puppeteer-core, viewer_drive.mjs): jetrace-server races one lap of ring
# (started by the lobby timeout 15 s after the first player, then a 2 s
# countdown); jetrace-view --connect --drive joins it as the human player; the test presses keys in the page, steering toward the next gate
# it reads from the page's state hook, until the car finishes. The server's
# results must list the human as finished, and its replay must verify.
# A jetrace-bot races too: the page shows its car (interpolated) and its
# name in the standings.
# Usage: viewer_drive.sh SERVER VIEW SIM BOT SOURCE_DIR
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

"$server" --bind 127.0.0.1 --port 0 --track ring --laps 1 --min-players 3 --max-players 3 --races 1 \
  --lobby-timeout 15 --lobby-timeout-action start --countdown 2 --finish-window 120 --results "$out/results.json" --record "$out/race.jtr" >"$out/server.log" 2>&1 &
spid=$!
port="$(server_port "$out/server.log")"
"$bot" --connect "127.0.0.1:$port" --count 1 --name robot --max-seconds 200 >"$out/bot.json" 2>&1 &
bpid=$!

mkfifo "$out/stdout"
"$view" --connect "127.0.0.1:$port" --drive human --http 127.0.0.1:0 >"$out/stdout" 2>"$out/view.log" &
vpid=$!
exec 3<"$out/stdout"
read -r line <&3 || { echo "jetrace-view printed no address:"; cat "$out/view.log" "$out/server.log"; exit 1; }
url="${line#listening on }"
[ "$url" != "$line" ] || { echo "unexpected first line: $line"; exit 1; }
echo "viewer at $url, server on port $port"

node "$src/tests/browser/viewer_drive.mjs" "$url" "$out/shot.png" ||
  { echo "--- jetrace-view log:"; cat "$out/view.log"; echo "--- server log:"; cat "$out/server.log"; exit 1; }

# The race is over: the server exits after its one race.
rc=0; timeout 60 tail --pid="$spid" -f /dev/null || rc=$?
[ "$rc" = 0 ] || { echo "the server did not exit after the race"; cat "$out/server.log"; exit 1; }
wait "$spid" || true
spid=""
cat "$out/server.log"
python3 - "$out/results.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert len(d["standings"]) == 2, "two players: %r" % d
human = [s for s in d["standings"] if s["name"] == "human"]
assert human, "no standing of the human player: %r" % d
assert human[0]["finished"], "the human player did not finish: %r" % human[0]
print("server results: human finished in %s s" % human[0]["time_s"])
PY
"$sim" --verify "$out/race.jtr"
grep -q "malformed message" "$out/view.log" || { echo "no log line for the malformed keys message"; cat "$out/view.log"; exit 1; }
kill -0 "$vpid" || { echo "jetrace-view died"; cat "$out/view.log"; exit 1; }
kill -TERM "$vpid"
rc=0; wait "$vpid" || rc=$?
vpid=""
cat "$out/view.log"
[ "$rc" = 0 ] || { echo "jetrace-view exited $rc on SIGTERM"; exit 1; }
echo "viewer drive: all checks hold"
