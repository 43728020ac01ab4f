#!/usr/bin/env bash
# A private race with the real binaries: jetrace-token makes a key and two
# tokens, jetrace-server --key-file admits the two bots presenting them
# (one lap of `ring` at 4x real time, both must finish) and refuses a bot
# without a token with the reason.
# Usage: private_race_processes.sh SERVER BOT TOKEN
set -euo pipefail
. "$(dirname "$0")/../tools/server_port.sh"
server="$1" bot="$2" token="$3"
out="$(mktemp -d)"
pid=""
trap '[ -n "$pid" ] && kill "$pid" 2>/dev/null; rm -rf "$out"' EXIT
"$token" keygen --out "$out/race.key" >/dev/null
for name in alice bob; do
  "$token" issue --key-file "$out/race.key" --name "$name" --valid-for 600 --race-id cup >>"$out/tokens.txt"
done
"$server" --bind 127.0.0.1 --port 0 --track ring --laps 1 --min-players 2 --max-players 3 --races 1 \
  --time-scale 4 --countdown 1 --key-file "$out/race.key.pub" --race-id cup --log-level info \
  >"$out/server.log" 2>&1 &
pid=$!
port="$(server_port "$out/server.log")"
if "$bot" --connect "127.0.0.1:$port" --track ring --time-scale 4 --max-seconds 20 >"$out/intruder.json" 2>&1; then
  echo "a bot without a token got in"; cat "$out/intruder.json"; exit 1
fi
grep -q 'refused: private race: a connect token is required' "$out/intruder.json" ||
  { echo "no refusal reason"; cat "$out/intruder.json"; exit 1; }
timeout 120 "$bot" --connect "127.0.0.1:$port" --token-file "$out/tokens.txt" --track ring --time-scale 4 \
  --max-seconds 100 >"$out/bots.json"
wait "$pid"
pid=""
cat "$out/server.log" "$out/intruder.json" "$out/bots.json"
grep -q "refusing client .*private race: a connect token is required" "$out/server.log" ||
  { echo "the server did not log the refusal"; exit 1; }
for name in alice bob; do
  grep -q "\"finished\":true.*\"name\":\"$name\"" "$out/bots.json" || { echo "$name did not finish"; exit 1; }
done
