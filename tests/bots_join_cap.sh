#!/usr/bin/env bash
# jetrace-bot against the server's pre-Hello cap (--pre-hello-limit, 4 by
# default: connections one address holds before their Hello; docs/PROTOCOL.md,
# "Connection slots and the pre-Hello cap").
# 1. 64 bots in one process join a 64-player server with default options
#    (ring, 1 lap, --finish-window 30 to end the race sooner) at real time:
#    they open their connections --join-limit (4) at a time, so the server
#    refuses none (no "pre-Hello cap" line in its log), every bot is in the
#    race's standings, races it to its end (no bot refused, lost or stopped,
#    no bot giving up on stderr) and at least 56 finish. (The back rows of
#    ring's 64-car grid can stay stuck at the first gate, as they do in
#    jetrace-sim offline; the finish window then ends the race.)
# 2. 4 bots joining 4 at a time against a server capped at 1: the refused
#    ones (close code 2008) try again within their --join-window, and all 4
#    finish.
# 3. With --join-window 0 a refused bot gives up at once: exit 3, and one
#    stderr line with its name, the reason and the code.
# About 60 s on 2 cores.
# Usage: bots_join_cap.sh SERVER BOT
set -euo pipefail
. "$(dirname "$0")/../tools/server_port.sh"
server="$1" bot="$2"
out="$(mktemp -d)"
pid=""
trap '[ -n "$pid" ] && kill -9 "$pid" 2>/dev/null; rm -rf "$out"' EXIT
fail() { echo "bots_join_cap: $*"; exit 1; }

# 1. 64 bots, the server's defaults.
"$server" --bind 127.0.0.1 --port 0 --track ring --laps 1 --min-players 64 --max-players 64 --races 1 \
  --finish-window 30 --results "$out/r64.json" >"$out/s64.log" 2>&1 &
pid=$!
port="$(server_port "$out/s64.log")"
start=$(date +%s)
rc=0
timeout 120 "$bot" --connect "127.0.0.1:$port" --count 64 --max-seconds 110 >"$out/b64.json" 2>"$out/b64.err" || rc=$?
took=$(( $(date +%s) - start ))
wait "$pid" || fail "the server failed: $(tail -5 "$out/s64.log")"
pid=""
finished="$(jq '[.standings[] | select(.finished)] | length' "$out/r64.json")"
echo "64 bots: exit $rc, $finished of 64 finished, $took s"
jq -c -s 'map(.outcome) | group_by(.) | map({(.[0]): length}) | add' "$out/b64.json"
# 5 (server_gone): a bot still connected when the server, its one race over,
# shut down (its Goodbye can come before the bot's own leave); the outcomes
# below must all be finished, did_not_finish or server_gone.
[ "$rc" = 0 ] || [ "$rc" = 1 ] || [ "$rc" = 5 ] || { cat "$out/b64.err"; fail "jetrace-bot exited $rc, not 0, 1 or 5"; }
[ "$(grep -c '^{' "$out/b64.json")" = 64 ] || fail "not 64 bot lines"
! grep -q 'pre-Hello cap' "$out/s64.log" || { grep 'pre-Hello cap' "$out/s64.log"; fail "the server refused bots"; }
! grep -q '^jetrace-bot: ' "$out/b64.err" || { grep '^jetrace-bot: ' "$out/b64.err"; fail "a bot gave up"; }
jq -e -s 'all(.outcome == "finished" or .outcome == "did_not_finish" or .outcome == "server_gone")' \
  "$out/b64.json" >/dev/null || fail "a bot was refused, lost or stopped"
[ "$(jq '[.standings[].name] | unique | length' "$out/r64.json")" = 64 ] || fail "not every bot was in the race"
[ "$finished" -ge 56 ] || fail "only $finished of 64 finished"

# 2. A server capped at 1, bots joining 4 at a time: refused, tried again, in.
"$server" --bind 127.0.0.1 --port 0 --track ring --laps 1 --min-players 4 --max-players 4 --races 1 \
  --pre-hello-limit 1 --time-scale 4 --countdown 1 >"$out/s4.log" 2>&1 &
pid=$!
port="$(server_port "$out/s4.log")"
rc=0
timeout 60 "$bot" --connect "127.0.0.1:$port" --count 4 --join-limit 4 --time-scale 4 --max-seconds 50 \
  >"$out/b4.json" 2>"$out/b4.err" || rc=$?
wait "$pid" || fail "the capped server failed: $(tail -5 "$out/s4.log")"
pid=""
grep -q 'pre-Hello cap: refusing connection requests from 127.0.0.1' "$out/s4.log" ||
  { cat "$out/s4.log"; fail "the capped server refused nobody"; }
[ "$rc" = 0 ] || { cat "$out/b4.err" "$out/b4.json"; fail "refused bots did not all join and finish (exit $rc)"; }
[ "$(grep -c '"finished":true' "$out/b4.json")" = 4 ] || fail "not every refused bot finished"
echo "capped at 1: 4 of 4 joined after refusals and finished"

# 3. No join window: the refused bot gives up and says why.
"$server" --bind 127.0.0.1 --port 0 --track ring --min-players 2 --max-players 2 --pre-hello-limit 1 \
  >"$out/s2.log" 2>&1 &
pid=$!
port="$(server_port "$out/s2.log")"
rc=0
"$bot" --connect "127.0.0.1:$port" --count 2 --name capped --join-limit 2 --join-window 0 --max-seconds 3 \
  >"$out/b2.json" 2>"$out/b2.err" || rc=$?
[ "$rc" = 3 ] || { cat "$out/b2.err" "$out/b2.json"; fail "a bot refused by the cap exited $rc, not 3"; }
grep -E -q '^jetrace-bot: capped[01]: refused: too many connections from this address are waiting for their Hello.* \[refused_pre_hello_cap 2008\]: .*--pre-hello-limit' \
  "$out/b2.err" || { cat "$out/b2.err"; fail "no line says why the bot gave up"; }
[ "$(grep -c '^jetrace-bot: ' "$out/b2.err")" = 1 ] || { cat "$out/b2.err"; fail "not one give-up line"; }
grep '^jetrace-bot: ' "$out/b2.err"
echo "bots join within the pre-Hello cap ok"
