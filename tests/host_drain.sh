#!/usr/bin/env bash
# The drain: SIGTERM mid-race with --races 3 lets the race finish (the
# results say "finished"), refuses a newcomer meanwhile with the reason, and
# exits 0 with "server terminated" (not "hosted its last race"). SIGHUP in the
# countdown drains too; a second SIGHUP stops at once, and a race stopped
# before its start is no result. Two SIGINTs mid-race abort the race at
# once (results say "aborted"). SIGHUP in an empty lobby exits at once.
# Usage: host_drain.sh SERVER BOT
set -euo pipefail
. "$(dirname "$0")/../tools/server_port.sh"
server="$1" bot="$2"
out="$(mktemp -d)"
pid="" bots=""
trap '[ -n "$pid" ] && kill -9 "$pid" 2>/dev/null; [ -n "$bots" ] && kill "$bots" 2>/dev/null; rm -rf "$out"' EXIT
common=(--bind 127.0.0.1 --port 0 --track ring --laps 1 --min-players 2 --max-players 3 --time-scale 4 --log-level info)
wait_for() {  # wait_for PATTERN LOG
  for _ in $(seq 1 300); do grep -q "$1" "$2" && return 0; sleep 0.05; done
  cat "$2"; echo "never saw '$1'"; return 1
}

# 1. SIGTERM mid-race: the race finishes.
"$server" "${common[@]}" --races 3 --countdown 1 --results "$out/r-%n.json" >"$out/drain.log" 2>&1 &
pid=$!
port="$(server_port "$out/drain.log")"
timeout 100 "$bot" --connect "127.0.0.1:$port" --track ring --count 2 --races 3 --time-scale 4 --max-seconds 90 \
  >"$out/drain.json" 2>&1 &
bots=$!
wait_for 'race 1: go' "$out/drain.log"
kill -TERM "$pid"
wait_for 'draining' "$out/drain.log"
rc=0
timeout 30 "$bot" --connect "127.0.0.1:$port" --track ring --name late --time-scale 4 --max-seconds 20 \
  >"$out/late.json" 2>"$out/late.err" || rc=$?
server_rc=0
wait "$pid" || server_rc=$?
pid=""
wait "$bots" || true
bots=""
cat "$out/drain.log" "$out/drain.json" "$out/late.json" "$out/late.err"
[ "$server_rc" = 0 ] || { echo "the server exited $server_rc"; exit 1; }
[ "$rc" = 3 ] || { echo "the newcomer exited $rc, not 3 (refused)"; exit 1; }
grep -q 'refused: server draining' "$out/late.err" || { echo "no refusal on the newcomer's stderr"; exit 1; }
grep -q 'server shutting down: server terminated' "$out/drain.log" || { echo "no drain shutdown line"; exit 1; }
grep -q 'hosted its last race' "$out/drain.log" && { echo "SIGTERM reported as the last race"; exit 1; }
[ "$(grep -c '"finished":true' "$out/drain.json")" = 2 ] || { echo "the drained race did not finish"; exit 1; }
[ ! -e "$out/r-2.json" ] || { echo "a second race ran during the drain"; exit 1; }
python3 - "$out/r-1.json" <<'PY'
import json, re, sys
d = json.load(open(sys.argv[1]))
assert d["end_reason"] in ("finished", "finish window") and d["aborted"] is False, d
iso = re.compile(r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ$")
assert iso.match(d["start_utc"]) and iso.match(d["end_utc"]) and d["start_utc"] <= d["end_utc"], d
assert len(d["standings"]) == 2 and all(s["finished"] for s in d["standings"]), d
PY

# 2. SIGHUP in the countdown, then SIGHUP again: no result.
"$server" "${common[@]}" --countdown 60 --results "$out/hup.json" >"$out/hup.log" 2>&1 &
pid=$!
port="$(server_port "$out/hup.log")"
timeout 60 "$bot" --connect "127.0.0.1:$port" --track ring --count 2 --time-scale 4 --max-seconds 50 \
  >"$out/hup.json.bots" 2>&1 &
bots=$!
wait_for 'start in' "$out/hup.log"
kill -HUP "$pid"
wait_for 'draining' "$out/hup.log"
kill -HUP "$pid"
server_rc=0
timeout 10 tail --pid="$pid" -f /dev/null
wait "$pid" || server_rc=$?
pid=""
bot_rc=0
wait "$bots" || bot_rc=$?
bots=""
cat "$out/hup.log" "$out/hup.json.bots"
[ "$server_rc" = 0 ] || { echo "the server exited $server_rc"; exit 1; }
[ "$bot_rc" = 5 ] || { echo "the bots exited $bot_rc, not 5 (the server said goodbye)"; exit 1; }
grep -q 'race 1 stopped in its countdown: no result' "$out/hup.log" || { echo "no countdown stop line"; exit 1; }
[ ! -e "$out/hup.json" ] || { echo "a race stopped in its countdown was reported"; cat "$out/hup.json"; exit 1; }

# 3. SIGINT twice mid-race with --races 3: aborted at once, and said so.
"$server" "${common[@]}" --races 3 --countdown 1 --results "$out/int.json" >"$out/int.log" 2>&1 &
pid=$!
port="$(server_port "$out/int.log")"
timeout 60 "$bot" --connect "127.0.0.1:$port" --track ring --count 2 --time-scale 4 --max-seconds 50 \
  >"$out/int.bots" 2>&1 &
bots=$!
wait_for 'race 1: go' "$out/int.log"
sleep 0.5
kill -INT "$pid"
wait_for 'draining' "$out/int.log"
kill -INT "$pid"
server_rc=0
wait "$pid" || server_rc=$?
pid=""
wait "$bots" || true
bots=""
cat "$out/int.log" "$out/int.bots"
[ "$server_rc" = 0 ] || { echo "the server exited $server_rc"; exit 1; }
grep -q 'server shutting down: server interrupted (again: stopping at once)' "$out/int.log" ||
  { echo "no immediate stop line"; exit 1; }
grep -q 'hosted its last race' "$out/int.log" && { echo "SIGINT reported as the last race"; exit 1; }
python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert d['end_reason']=='aborted' and d['aborted'], d" \
  "$out/int.json"

# 4. SIGHUP in an empty lobby: at once.
"$server" "${common[@]}" >"$out/idle.log" 2>&1 &
pid=$!
server_port "$out/idle.log" >/dev/null
kill -HUP "$pid"
timeout 5 tail --pid="$pid" -f /dev/null || { echo "the idle server did not exit at once"; exit 1; }
wait "$pid"
pid=""
grep -q 'server shutting down: server hung up' "$out/idle.log" || { cat "$out/idle.log"; exit 1; }
echo "drain ok"
