#!/usr/bin/env bash
# A server killed mid-race (SIGKILL: no chance to write a trailer) leaves a
# replay that reads as incomplete, never as a shorter complete race:
# jetrace-sim --verify exits 1 with problem "incomplete" (or "truncated" if
# the kill cut a write), and --replay exits non-zero too. A server stopped
# at once (SIGTERM twice: the first one drains, the second stops) writes the
# trailer: end_reason "aborted", and it verifies.
# Usage: sigkill_replay.sh SERVER BOT SIM
set -euo pipefail
. "$(dirname "$0")/../tools/server_port.sh"
server="$1" bot="$2" sim="$3"
out="$(mktemp -d)"
trap 'kill -9 "$server_pid" 2>/dev/null || true; kill "$bots_pid" 2>/dev/null || true; rm -rf "$out"' EXIT
race() {  # race SIGNAL: starts a race, sends SIGNAL to the server 2 s after the start
  "$server" --bind 127.0.0.1 --port 0 --track ring --laps 3 --min-players 2 --max-players 2 --time-scale 4 \
    --countdown 1 --record "$out/$1.replay" --log-level info >"$out/server.log" 2>&1 &
  server_pid=$!
  port="$(server_port "$out/server.log")"
  timeout 60 "$bot" --connect "127.0.0.1:$port" --track ring --count 2 --time-scale 4 --max-seconds 50 \
    >/dev/null 2>&1 &
  bots_pid=$!
  for _ in $(seq 1 200); do grep -q 'race 1: go' "$out/server.log" && break; sleep 0.05; done
  grep -q 'race 1: go' "$out/server.log" || { cat "$out/server.log"; echo "the race did not start"; exit 1; }
  sleep 2
  kill "-$1" "$server_pid"
  if [ "$1" = TERM ]; then
    for _ in $(seq 1 100); do grep -q 'draining' "$out/server.log" && break; sleep 0.05; done
    kill -TERM "$server_pid"
  fi
  wait "$server_pid" || true
  kill "$bots_pid" 2>/dev/null || true
  wait "$bots_pid" || true
}
race KILL
rc=0
"$sim" --verify "$out/KILL.replay" >"$out/verdict.json" || rc=$?
cat "$out/verdict.json"
[ "$rc" = 1 ] || { echo "--verify of a killed server's replay exited $rc, not 1"; exit 1; }
grep -Eq '"problem":"(incomplete|truncated)"' "$out/verdict.json" || { echo "not reported as incomplete"; exit 1; }
if "$sim" --replay "$out/KILL.replay"; then echo "--replay accepted an incomplete replay"; exit 1; fi
race TERM
"$sim" --verify "$out/TERM.replay" | tee "$out/verdict.json"
grep -q '"end_reason":"aborted"' "$out/verdict.json" || { echo "the stopped race is not marked aborted"; exit 1; }
