#!/usr/bin/env bash
# The browser player's figures (docs/BROWSER.md, "Figures"), one JSON line
# each, in headless Chromium against live servers on loopback:
#   browser_first_frame       opening http://HOST:PORT/?name=... to the first
#                             drawn frame of the race, and the bytes downloaded
#                             (page, three.js, WebAssembly, protocol)
#   browser_input_to_display  a key's event to the first draw of a frame the
#                             client ticked with it (draws and ms; 10 probes)
#   browser_player_bandwidth  kbit/s down and up of a racing page at 8 cars
#                             (7 jetrace-bot drivers and the page, ring)
#   browser_wasm_verify       that race's replay re-simulated by the
#                             WebAssembly client in Chromium against
#                             jetrace-verify natively (medians, ratio)
#   server_tick_pages         the server's tick median and p99 with 8 pages
#                             and 8 bots, against 16 bots (ring, 1 lap)
# Usage: tools/browser_bench.sh [--rounds N]   (N: replay verifications, 5)
# Builds nothing: run tools/build.sh first.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
. "$root/tools/server_port.sh"
rounds=5
while [ $# -gt 0 ]; do
  case "$1" in
    --rounds) rounds="$2"; shift 2 ;;
    *) echo "usage: tools/browser_bench.sh [--rounds N]" >&2; exit 2 ;;
  esac
done
[[ "$rounds" =~ ^[1-9][0-9]?$ ]] || { echo "browser_bench: --rounds must be 1..99" >&2; exit 2; }
bin="$root/build"
out="$(mktemp -d)"
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; rm -rf "$out"; }
trap cleanup EXIT

# start_server NAME ARGS...: a server with --web on loopback; sets port and web.
start_server() {
  local name="$1"; shift
  "$bin/server/jetrace-server" --bind 127.0.0.1 --port 0 --web 127.0.0.1:0 --track ring --races 1 \
    --lobby-timeout 120 --countdown 3 "$@" >"$out/$name.log" 2>&1 &
  pids+=($!)
  server_pid=$!
  port="$(server_port "$out/$name.log")"
  web="$(web_port "$out/$name.log")"
}
wait_server() { timeout 300 tail --pid="$server_pid" -f /dev/null; }
tick_line() { grep '^{' "$out/$1.log" | tail -n 1; }

# 1. One page and 7 bots: first frame, bytes, input to display, bandwidth; the replay.
start_server drive --laps 1 --min-players 8 --max-players 8 --finish-window 30 --record "$out/race.jtr"
"$bin/client/jetrace-bot" --connect "127.0.0.1:$port" --count 7 --max-seconds 240 >"$out/bots.json" 2>&1 &
pids+=($!)
node "$root/tools/browser_bench.mjs" drive "http://127.0.0.1:$web/"
wait_server
python3 - "$out/bots.json" <<'PY'
import json, statistics, sys
bots = [json.loads(l) for l in open(sys.argv[1]) if l.startswith("{") and "down_bytes_per_s" in l]
down = statistics.median(b["down_bytes_per_s"] for b in bots) * 8 / 1000
print(json.dumps({"figure": "native_bot_bandwidth_same_race", "bots": len(bots), "kbit_s_down_median": round(down, 2)}))
PY

# 2. The replay re-simulated natively and in Chromium, alternately.
start_server verify --laps 1 --min-players 8 --max-players 8
node "$root/tools/browser_bench.mjs" verify "http://127.0.0.1:$web/" "$out/race.jtr" "$rounds" "$bin/tools/jetrace-verify"
kill "$server_pid" 2>/dev/null || true

# 3. The server's tick: 16 bots, then 8 bots and 8 pages (which hold no keys).
start_server bots16 --laps 1 --min-players 16 --max-players 16 --finish-window 15
"$bin/client/jetrace-bot" --connect "127.0.0.1:$port" --count 16 --max-seconds 240 >"$out/bots16.json" 2>&1 &
pids+=($!)
wait_server
bots_line="$(tick_line bots16)"
start_server pages8 --laps 1 --min-players 16 --max-players 16 --finish-window 15
node "$root/tools/browser_bench.mjs" pages "http://127.0.0.1:$web/" 8 240 &
pages_pid=$!
pids+=($pages_pid)
sleep 2
"$bin/client/jetrace-bot" --connect "127.0.0.1:$port" --count 8 --max-seconds 240 >"$out/bots8.json" 2>&1 &
pids+=($!)
wait_server
wait "$pages_pid" || true  # its pages close when the server ends the race
pages_line="$(tick_line pages8)"
python3 - "$bots_line" "$pages_line" <<'PY'
import json, sys
b, p = json.loads(sys.argv[1]), json.loads(sys.argv[2])
print(json.dumps({"figure": "server_tick_pages",
                  "bots16_tick_ms_median": round(b["tick_ms_median"], 4), "bots16_tick_ms_p99": round(b["tick_ms_p99"], 4),
                  "pages8_bots8_tick_ms_median": round(p["tick_ms_median"], 4),
                  "pages8_bots8_tick_ms_p99": round(p["tick_ms_p99"], 4)}))
PY
