#!/usr/bin/env bash
# --lobby-timeout: one player where --min-players is 3. With the default
# action the race starts anyway after the timeout (the lone bot finishes,
# the server exits 0 after its --races 1); with --lobby-timeout-action
# cancel the bot is told why and leaves (exit 5: the server said goodbye),
# and the server goes on waiting. Either way the lobby logs "waiting 1/3".
# Usage: host_lobby.sh SERVER BOT
set -euo pipefail
. "$(dirname "$0")/../tools/server_port.sh"
server="$1" bot="$2"
out="$(mktemp -d)"
pid=""
trap '[ -n "$pid" ] && kill -9 "$pid" 2>/dev/null; rm -rf "$out"' EXIT
common=(--bind 127.0.0.1 --port 0 --track ring --laps 1 --min-players 3 --max-players 3 --races 1
        --time-scale 4 --countdown 1 --lobby-timeout 4 --log-level info)

# Start anyway.
"$server" "${common[@]}" --results "$out/results.json" >"$out/start.log" 2>&1 &
pid=$!
port="$(server_port "$out/start.log")"
timeout 60 "$bot" --connect "127.0.0.1:$port" --track ring --time-scale 4 --max-seconds 50 >"$out/start.json"
timeout 20 tail --pid="$pid" -f /dev/null
wait "$pid"
pid=""
cat "$out/start.log" "$out/start.json"
grep -q 'lobby: waiting 1/3 players' "$out/start.log" || { echo "no 'waiting 1/3' line"; exit 1; }
grep -q 'lobby timed out after 4 s with 1 of 3 players: starting anyway' "$out/start.log" ||
  { echo "no lobby timeout line"; exit 1; }
grep -q '"finished":true' "$out/start.json" || { echo "the lone bot did not race to the finish"; exit 1; }
python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert len(d['standings'])==1, d" "$out/results.json"

# Cancel.
"$server" "${common[@]}" --lobby-timeout-action cancel >"$out/cancel.log" 2>&1 &
pid=$!
port="$(server_port "$out/cancel.log")"
rc=0
timeout 60 "$bot" --connect "127.0.0.1:$port" --track ring --time-scale 4 --max-seconds 50 \
  >"$out/cancel.json" 2>"$out/cancel.err" || rc=$?
cat "$out/cancel.log" "$out/cancel.json" "$out/cancel.err"
[ "$rc" = 5 ] || { echo "the bot exited $rc, not 5 (the server said goodbye)"; exit 1; }
grep -q '"closed":"server: lobby timed out after 4 s with 1 of 3 players: race cancelled"' "$out/cancel.json" ||
  { echo "the bot was not told why"; exit 1; }
kill -0 "$pid" || { echo "the server stopped after cancelling"; exit 1; }
grep -q 'race 1' "$out/cancel.log" && { echo "a cancelled lobby started a race"; exit 1; }
kill -TERM "$pid"
wait "$pid"
pid=""
