#!/usr/bin/env bash
# Other tick rates end to end: jetrace-server --tick-rate 60, 50 (its
# default snapshot rate then is 50) and 240, two bots each (built with the
# default 120 Hz scenes: they adopt the server's rate from its Welcome);
# both finish, and the replay reproduces the server's state hash.
# Usage: tick_rates.sh SERVER BOT SIM
set -euo pipefail
. "$(dirname "$0")/../tools/server_port.sh"
server="$1" bot="$2" sim="$3"
out="$(mktemp -d)"
pid=""
trap '[ -n "$pid" ] && kill -9 "$pid" 2>/dev/null; rm -rf "$out"' EXIT
for rate in 60 50 240; do
  scale=4
  [ "$rate" = 240 ] && scale=2
  "$server" --bind 127.0.0.1 --port 0 --track ring --laps 1 --min-players 2 --max-players 2 --races 1 \
    --tick-rate "$rate" --time-scale "$scale" --countdown 1 --record "$out/$rate.replay" --log-level info \
    >"$out/$rate.log" 2>&1 &
  pid=$!
  port="$(server_port "$out/$rate.log")"
  rc=0
  timeout 100 "$bot" --connect "127.0.0.1:$port" --count 2 --time-scale "$scale" --max-seconds 90 \
    >"$out/$rate.json" 2>"$out/$rate.err" || rc=$?
  wait "$pid"
  pid=""
  cat "$out/$rate.json" "$out/$rate.err"
  [ "$rc" = 0 ] || { cat "$out/$rate.log"; echo "tick rate $rate: the bots exited $rc"; exit 1; }
  [ "$(grep -c '"finished":true' "$out/$rate.json")" = 2 ] || { echo "tick rate $rate: not every bot finished"; exit 1; }
  server_hash="$(sed -n 's/^state_hash=//p' "$out/$rate.log" | tail -n 1)"
  replay_hash="$("$sim" --replay "$out/$rate.replay" | sed -n 's/^state_hash=//p')"
  echo "tick rate $rate: server $server_hash replay $replay_hash"
  [ -n "$server_hash" ] && [ "$server_hash" = "$replay_hash" ] || exit 1
done
echo "tick rates ok"
