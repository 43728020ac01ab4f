#!/usr/bin/env bash
# jetrace-server against the real Agones SDK sidecar (local mode), on free
# ports, every run bounded. MODE:
#   lifecycle        Ready, Health pings, players refused before the allocation,
#                    Allocated with annotations that configure the race (ring,
#                    1 lap, min 2 players), two bots race and finish, Shutdown,
#                    exit 0
#   bad_annotation   an allocation with jetrace.dev/laps "0": exit 2, Shutdown
#   sidecar_lost     the sidecar dies after Ready: exit 1 past the deadline
#   sidecar_missing  no sidecar at all: exit 1 past --agones-connect-timeout
# The sidecar is not part of the repository: JETRACE_AGONES_SDK_SERVER names
# it, else SIDECAR (CMake's default: ../shared/tools/agones/sdk-server beside
# the checkout). Without one, the modes that run it are skipped (exit 77,
# CTest's SKIP_RETURN_CODE) with a message; sidecar_missing needs none.
# Usage: agones_lifecycle.sh SERVER BOT SIDECAR MODE
set -euo pipefail
here="$(dirname "$0")"
server="$1" bot="$2" sidecar="${JETRACE_AGONES_SDK_SERVER:-$3}" mode="$4"
if [ "$mode" != sidecar_missing ] && [ ! -x "$sidecar" ]; then
  echo "SKIP: no Agones SDK sidecar at '$sidecar': set JETRACE_AGONES_SDK_SERVER to one (the Agones release's sdk-server, run in --local mode), or put ../shared/tools/agones/ beside the checkout"
  exit 77
fi
. "$here/ops_support.sh"

http_port="$(free_port)" grpc_port="$(free_port)"
sdk="http://localhost:$http_port"
state() { http GET "$sdk/gameserver" | python3 -c 'import json,sys; print(json.load(sys.stdin)["status"]["state"])'; }
state_is() { [ "$(state)" = "$1" ]; }
health_pings() { grep -c 'Health Ping Received!' "$out/sidecar.log" || true; }
pings_at_least() { [ "$(health_pings)" -ge "$1" ]; }

laps='"1"'
[ "$mode" = bad_annotation ] && laps='"0"'
cat >"$out/gameserver.json" <<JSON
{"apiVersion": "agones.dev/v1", "kind": "GameServer",
 "metadata": {"name": "jetrace-test", "annotations": {
   "jetrace.dev/track": "ring", "jetrace.dev/laps": $laps, "jetrace.dev/min-players": "2"}},
 "status": {"state": "Scheduled"}}
JSON

start_sidecar() {
  "$sidecar" --local --address localhost --http-port "$http_port" --grpc-port "$grpc_port" --timeout 170 \
    -f "$out/gameserver.json" >"$out/sidecar.log" 2>&1 &
  sidecar_pid=$!
  pids+=("$sidecar_pid")
  wait_for 15 "the sidecar answers GET /gameserver" http GET "$sdk/gameserver"
  check "the GameServer starts Scheduled (so Ready can only come from the server)" state_is Scheduled
}

start_server() {
  AGONES_SDK_HTTP_PORT="$http_port" "$server" --bind 127.0.0.1 --port 0 --track ring --laps 3 --min-players 1 \
    --races 1 --time-scale 4 --countdown 1 --results "$out/results.json" --agones-health-period 0.5 "$@" \
    >"$out/server.out" 2>"$out/server.log" &
  server_pid=$!
  pids+=("$server_pid")
  . "$here/../tools/server_port.sh"
  port="$(server_port "$out/server.out")"
}

show_logs() { echo "--- server stdout"; cat "$out/server.out"; echo "--- server log"; cat "$out/server.log"; }
trap 'rc=$?; [ $rc -ne 0 ] && show_logs; cleanup; exit $rc' EXIT

case "$mode" in
lifecycle)
  start_sidecar
  start_server
  wait_for 15 "the GameServer is Ready" state_is Ready
  check "the sidecar logged the Ready call" grep -q 'Ready request has been received!' "$out/sidecar.log"
  wait_for 15 "at least 3 Health pings" pings_at_least 3
  # Before the allocation the server takes nobody.
  rc=0
  timeout 30 "$bot" --connect "127.0.0.1:$port" --count 1 --track ring --join-window 5 --max-seconds 10 \
    >"$out/early.json" 2>/dev/null || rc=$?
  check "a bot joining before the allocation is refused (exit $rc)" test "$rc" -ne 0
  check "... with the reason 'not allocated yet'" grep -q 'refused: not allocated yet' "$out/early.json"
  http POST "$sdk/allocate" '{}' >/dev/null
  wait_for 15 "the server read the allocation: 1 lap, min 2 players" \
    grep -q 'allocation: 1 laps, min 2 players' "$out/server.log"
  timeout 120 "$bot" --connect "127.0.0.1:$port" --count 1 --name first --time-scale 4 --max-seconds 100 \
    >"$out/bot1.json" &
  bot1=$!
  pids+=("$bot1")
  wait_for 15 "the first bot joined" grep -q "is 'first0'" "$out/server.log"
  sleep 2
  check "one player does not start the race (min-players 2 from the annotation)" \
    test "$(grep -c 'race 1 on' "$out/server.log" || true)" = 0
  timeout 120 "$bot" --connect "127.0.0.1:$port" --count 1 --name second --time-scale 4 --max-seconds 100 \
    >"$out/bot2.json"
  wait "$bot1"
  check "both bots finished" test "$(cat "$out/bot1.json" "$out/bot2.json" | grep -c '"finished":true')" = 2
  wait_exit "$server_pid" 20; rc="$exit_code"
  check "the server exited 0 after its last race (got $rc)" test "$rc" = 0
  check "the results say 1 lap on ring, 2 players" python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
assert d["laps"] == 1 and d["track"] == "ring" and len(d["standings"]) == 2, d' "$out/results.json"
  check "the GameServer is Shutdown" state_is Shutdown
  check "the sidecar logged the Shutdown call" grep -q 'Shutdown request has been received!' "$out/sidecar.log"
  echo "health pings: $(health_pings)"
  ;;
bad_annotation)
  start_sidecar
  start_server
  wait_for 15 "the GameServer is Ready" state_is Ready
  http POST "$sdk/allocate" '{}' >/dev/null
  wait_exit "$server_pid" 20; rc="$exit_code"
  check "a bad annotation ends the server with exit 2 (got $rc)" test "$rc" = 2
  check "the log names the annotation" grep -q 'jetrace.dev/laps="0"' "$out/server.log"
  check "the GameServer is Shutdown" state_is Shutdown
  ;;
sidecar_lost)
  start_sidecar
  start_server --agones-connect-timeout 2
  wait_for 15 "the GameServer is Ready" state_is Ready
  kill "$sidecar_pid"
  wait_exit "$server_pid" 20; rc="$exit_code"
  check "a lost sidecar ends the server with exit 1 (got $rc)" test "$rc" = 1
  check "the log says the sidecar stopped answering" grep -q 'has not answered for 2 s' "$out/server.log"
  ;;
sidecar_missing)
  start_server --agones-connect-timeout 1
  wait_exit "$server_pid" 20; rc="$exit_code"
  check "no sidecar ends the server with exit 1 (got $rc)" test "$rc" = 1
  check "the log says no sidecar answered" grep -q 'no Agones sidecar answered' "$out/server.log"
  ;;
*) echo "unknown mode '$mode'"; exit 2 ;;
esac
