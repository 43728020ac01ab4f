#!/usr/bin/env bash
# A race through jetrace-netsim: jetrace-server, the proxy (latency, jitter,
# 5 % loss, duplication, reordering in both directions) and 3 jetrace-bot
# drivers, as separate processes on 127.0.0.1, one lap of `ring` at 4x real
# time. Every bot must finish, the server must have seen 3 distinct players,
# the proxy's counters must show the conditions at work (after SIGTERM) and
# its input delay stay within the latency and jitter plus a few send
# intervals, and
# the replay must reproduce the server's final state hash.
# Usage: netsim_race.sh SERVER BOT SIM NETSIM
set -euo pipefail
. "$(dirname "$0")/../tools/server_port.sh"
server="$1" bot="$2" sim="$3" netsim="$4"
out="$(mktemp -d)"
cleanup() {
  rc=$?
  kill "$server_pid" "$netsim_pid" 2>/dev/null || true
  if [ "$rc" != 0 ]; then
    echo "netsim_race: failed (exit $rc); logs:"
    cat "$out"/*.log "$out/bots.json" 2>/dev/null || true
  fi
  rm -rf "$out"
}
server_pid="" netsim_pid=""
trap cleanup EXIT
"$server" --bind 127.0.0.1 --port 0 --track ring --laps 1 --min-players 3 --max-players 3 --races 1 \
  --time-scale 4 --countdown 1 --record "$out/race.replay" --log-level warn >"$out/server.log" 2>&1 &
server_pid=$!
port="$(server_port "$out/server.log")"
"$netsim" --listen 0 --forward "127.0.0.1:$port" --latency 15 --jitter 10 --loss 0.05 --dup 0.01 --reorder 0.01 \
  --seed 7 --log-level info >"$out/netsim.log" 2>&1 &
netsim_pid=$!
proxy_port="$(server_port "$out/netsim.log")"
timeout 120 "$bot" --connect "127.0.0.1:$proxy_port" --track ring --count 3 --time-scale 4 --max-seconds 100 \
  >"$out/bots.json"
wait "$server_pid"
kill -TERM "$netsim_pid"
wait "$netsim_pid"
cat "$out/server.log" "$out/netsim.log" "$out/bots.json"
[ "$(grep -c '"finished":true' "$out/bots.json")" = 3 ] || { echo "not every bot finished"; exit 1; }
grep -q '"max_players":3' "$out/server.log" || { echo "the server did not see 3 players"; exit 1; }
python3 - "$out/netsim.log" <<'PY'
import json, sys
line = [l for l in open(sys.argv[1]) if l.startswith("{")][-1]
c = json.loads(line)
assert c["clients"] == 3, c
for d in ("up", "down"):
    assert c[d]["forwarded"] > 500 and c[d]["dropped"] > 0, (d, c[d])
    out = c[d]["forwarded"] + c[d]["dropped"] + c[d]["rate_limited"] + c[d]["send_failed"] + c[d]["pending"]
    assert c[d]["received"] + c[d]["duplicated"] == out, (d, c[d])
# Input delay (client -> server, first datagram carrying a tick to the first
# forwarded with it): at least the latency, at most latency + jitter + a few
# send intervals (a lost batch's inputs come with the next one).
d = c["up"]["input_delay_ms"]
assert d["n"] > 1000, d
assert 15 <= d["p50"] <= 15 + 10 + 2, d
assert d["p99"] <= 15 + 10 + 40, d
print("netsim counters ok; input delay", d)
PY
server_hash="$(sed -n 's/^state_hash=//p' "$out/server.log" | tail -n 1)"
replay_hash="$("$sim" --replay "$out/race.replay" | sed -n 's/^state_hash=//p')"
echo "server $server_hash replay $replay_hash"
[ -n "$server_hash" ] && [ "$server_hash" = "$replay_hash" ]
