#!/usr/bin/env bash
# A mixed race (docs/BROWSER.md): 4 pages of jetrace-server --web and 4
# jetrace-bot drivers race one lap of ring; every page (browser_mixed.mjs)
# and every bot must finish, the server's results must list all 8 as
# finished, and its replay must verify.
# Usage: browser_mixed.sh SERVER SIM BOT SOURCE_DIR
set -euo pipefail
server="$1" sim="$2" bot="$3" src="$4"
. "$src/tools/server_port.sh"
out="$(mktemp -d)"
spid="" bpid=""
cleanup() {
  for p in $bpid $spid; do kill "$p" 2>/dev/null || true; wait "$p" 2>/dev/null || true; done
  rm -rf "$out"
}
trap cleanup EXIT
"$server" --bind 127.0.0.1 --port 0 --web 127.0.0.1:0 --track ring --laps 1 --min-players 8 --max-players 8 \
  --races 1 --lobby-timeout 120 --countdown 3 --finish-window 120 --results "$out/results.json" \
  --record "$out/race.jtr" >"$out/server.log" 2>&1 &
spid=$!
port="$(server_port "$out/server.log")"
web="$(web_port "$out/server.log")"
"$bot" --connect "127.0.0.1:$port" --count 4 --name robot --max-seconds 300 >"$out/bots.json" 2>&1 &
bpid=$!
node "$src/tests/browser/browser_mixed.mjs" "http://127.0.0.1:$web/" 4 || { cat "$out/server.log"; exit 1; }
rc=0; timeout 120 tail --pid="$spid" -f /dev/null || rc=$?
[ "$rc" = 0 ] || { echo "the server did not exit after the race"; cat "$out/server.log"; exit 1; }
wait "$spid" || true
spid=""
python3 - "$out/results.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
s = d["standings"]
assert len(s) == 8, "8 players: %r" % s
assert all(x["finished"] for x in s), "not all finished: %r" % s
print("server results: all 8 finished: " + ", ".join("%s %.3f s" % (x["name"], x["time_s"]) for x in s))
PY
"$sim" --verify "$out/race.jtr"
