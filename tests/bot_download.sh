#!/usr/bin/env bash
# jetrace-bot without --track against a jetrace-server racing an OBJ track
# (the small oval of the obj_import seed corpus, which no build has built
# in): the bots download the server's compiled track and finish; the server
# logs no refusal and no drop.
# Usage: bot_download.sh SERVER BOT OBJ
set -euo pipefail
. "$(dirname "$0")/../tools/server_port.sh"
server="$1" bot="$2" obj="$3"
out="$(mktemp -d)"
pid=""
trap '[ -n "$pid" ] && kill "$pid" 2>/dev/null; rm -rf "$out"' EXIT
"$server" --bind 127.0.0.1 --port 0 --track "$obj" --laps 1 --min-players 2 --max-players 2 --races 1 \
  --time-scale 4 --countdown 1 --log-level info >"$out/server.log" 2>&1 &
pid=$!
port="$(server_port "$out/server.log")"
timeout 120 "$bot" --connect "127.0.0.1:$port" --count 2 --time-scale 4 --max-seconds 100 --log-level info \
  >"$out/bots.json" 2>"$out/bots.err"
wait "$pid"
pid=""
cat "$out/bots.json"
[ "$(grep -c '"finished":true' "$out/bots.json")" = 2 ] || { cat "$out/bots.err" "$out/server.log"; echo "not every bot finished"; exit 1; }
[ "$(grep -c 'downloaded the track' "$out/bots.err")" = 2 ] || { cat "$out/bots.err"; echo "the bots did not download the track"; exit 1; }
if grep -E 'refusing client|dropping client' "$out/server.log"; then echo "the server refused or dropped a bot"; exit 1; fi
echo "bot download ok"
