#!/usr/bin/env bash
# End to end with the real binaries: jetrace-server and jetrace-bot as
# separate processes on 127.0.0.1 (port chosen by the system), one lap of
# `ring` at 4x real time; every bot must finish, the results file must be
# valid JSON, the server's SIGTERM-free exit JSON present, and the replay must
# reproduce the server's final state hash.
# Usage: race_processes.sh SERVER BOT SIM
set -euo pipefail
. "$(dirname "$0")/../tools/server_port.sh"
server="$1" bot="$2" sim="$3"
out="$(mktemp -d)"
trap 'kill "$pid" 2>/dev/null || true; rm -rf "$out"' EXIT
"$server" --bind 127.0.0.1 --port 0 --track ring --laps 1 --min-players 3 --max-players 3 --races 1 \
  --time-scale 4 --countdown 1 --results "$out/results.json" --record "$out/race.replay" --log-level warn \
  >"$out/server.log" 2>&1 &
pid=$!
port="$(server_port "$out/server.log")"
timeout 120 "$bot" --connect "127.0.0.1:$port" --count 3 --time-scale 4 --max-seconds 100 >"$out/bots.json"
wait "$pid"
cat "$out/server.log" "$out/bots.json"
[ "$(grep -c '"finished":true' "$out/bots.json")" = 3 ] || { echo "not every bot finished"; exit 1; }
python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert len(d['standings'])==3" "$out/results.json"
grep -q '"tick_ms_median"' "$out/server.log" || { echo "no server figures"; exit 1; }
server_hash="$(sed -n 's/^state_hash=//p' "$out/server.log" | tail -n 1)"
replay_hash="$("$sim" --replay "$out/race.replay" | sed -n 's/^state_hash=//p')"
echo "server $server_hash replay $replay_hash"
[ -n "$server_hash" ] && [ "$server_hash" = "$replay_hash" ]
