#!/usr/bin/env bash
# The server process terminated mid-race: jetrace-server and 3 jetrace-bot
# drivers on 127.0.0.1 (ring, 3 laps, 4x real time); SIGTERM to the server
# about 2 s after the start, with --drain-timeout 0.5: the drain cuts the
# race short. The server must exit cleanly (0, its figures printed), the
# results so far must be complete JSON (written atomically: no temporary
# file left, every car listed, the end reason "drained"), the bots must get
# those results, and the replay so far must re-simulate to the state hash
# the server printed.
# Usage: sigterm_midrace.sh SERVER BOT SIM
set -euo pipefail
. "$(dirname "$0")/../tools/server_port.sh"
server="$1" bot="$2" sim="$3"
out="$(mktemp -d)"
trap 'kill "$server_pid" "$bots_pid" 2>/dev/null || true; rm -rf "$out"' EXIT
"$server" --bind 127.0.0.1 --port 0 --track ring --laps 3 --min-players 3 --max-players 3 --time-scale 4 \
  --countdown 1 --drain-timeout 0.5 --results "$out/results.json" --record "$out/race.replay" --log-level info >"$out/server.log" 2>&1 &
server_pid=$!
port="$(server_port "$out/server.log")"
timeout 120 "$bot" --connect "127.0.0.1:$port" --track ring --count 3 --time-scale 4 --max-seconds 100 \
  >"$out/bots.json" 2>"$out/bots.log" &
bots_pid=$!
for _ in $(seq 1 200); do grep -q 'race 1: go' "$out/server.log" && break; sleep 0.05; done
grep -q 'race 1: go' "$out/server.log" || { cat "$out/server.log"; echo "the race did not start"; exit 1; }
sleep 2
kill -TERM "$server_pid"
server_rc=0
wait "$server_pid" || server_rc=$?
wait "$bots_pid" || true  # the bots did not finish: that is the point
cat "$out/server.log" "$out/bots.json"
[ "$server_rc" = 0 ] || { echo "the server exited with $server_rc"; exit 1; }
grep -q 'server shutting down: server terminated' "$out/server.log" || { echo "no shutdown line"; exit 1; }
grep -q '"tick_ms_median"' "$out/server.log" || { echo "no server figures"; exit 1; }
[ ! -e "$out/results.json.tmp" ] || { echo "a temporary results file was left behind"; exit 1; }
python3 - "$out/results.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d["race"] == 1 and len(d["standings"]) == 3, d
assert not all(s["finished"] for s in d["standings"]), "the race was not cut short"
assert d["ticks"] > 240, d
assert d["end_reason"] == "drained" and d["aborted"] is True, d
print("results so far:", json.dumps(d["standings"]))
PY
# Every bot got the results so far (and left, or heard the server go).
[ "$(grep -c '"position":[1-3]' "$out/bots.json")" = 3 ] || { echo "a bot did not get the results"; exit 1; }
server_hash="$(sed -n 's/^state_hash=//p' "$out/server.log" | tail -n 1)"
replay_hash="$("$sim" --replay "$out/race.replay" | sed -n 's/^state_hash=//p')"
echo "server $server_hash replay $replay_hash"
[ -n "$server_hash" ] && [ "$server_hash" = "$replay_hash" ]
