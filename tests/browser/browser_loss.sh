#!/usr/bin/env bash
# A browser player under loss: every link at 20 ms one way and 5 % loss in
# both directions, the bots' through jetrace-netsim, the page's injected
# inside jetrace-server (--web-link, the same scheduler), one lap of ring
# with 3 jetrace-bot drivers and one page in headless Chromium
# (tools/transports/race_page.mjs) over TRANSPORT (webrtc: the data
# channel, whose lost inputs and snapshots are gone; websocket: one TCP
# stream, whose losses are resent and hold back what follows).
# The page must finish; the server's meter must show the loss at work and
# an input delay of at least the latency; on the data channel the page's
# corrections per minute of racing must stay within the bots' (the worst
# bot's, with room for one race's noise: twice it, plus 10). The bots drive
# with no input delay, as the page does (jetrace-bot --input-delay 0).
# Usage: browser_loss.sh SERVER BOT NETSIM SOURCE_DIR TRANSPORT
set -euo pipefail
server="$1" bot="$2" netsim="$3" src="$4" transport="$5"
. "$src/tools/server_port.sh"
[ -d "$src/node_modules/puppeteer-core" ] || { echo "no puppeteer-core in $src/node_modules: run npm ci there (tools/setup.sh does)"; exit 1; }
[ -x /usr/bin/chromium ] || { echo "no /usr/bin/chromium: apt-get install chromium (tools/setup.sh does)"; exit 1; }
out="$(mktemp -d)"
spid="" npid="" bpid=""
cleanup() {
  for p in $bpid $npid $spid; do kill "$p" 2>/dev/null || true; wait "$p" 2>/dev/null || true; done
  rm -rf "$out"
}
trap cleanup EXIT

"$server" --bind 127.0.0.1 --port 0 --web 127.0.0.1:0 --web-link latency=20,loss=0.05 --track ring --laps 1 \
  --min-players 4 --max-players 4 --races 1 --lobby-timeout 60 --countdown 3 --finish-window 90 \
  --results "$out/results.json" >"$out/server.log" 2>&1 &
spid=$!
port="$(server_port "$out/server.log")"
web="$(web_port "$out/server.log")"
"$netsim" --listen 0 --forward "127.0.0.1:$port" --latency 20 --loss 0.05 --seed 5 >"$out/netsim.log" 2>&1 &
npid=$!
proxy="$(server_port "$out/netsim.log")"
"$bot" --connect "127.0.0.1:$proxy" --count 3 --name robot --input-delay 0 --max-seconds 200 >"$out/bots.json" 2>/dev/null &
bpid=$!
node "$src/tools/transports/race_page.mjs" "http://127.0.0.1:$web/" "$transport" page >"$out/page.json" ||
  { echo "the page did not finish:"; cat "$out/page.json" "$out/server.log"; exit 1; }
rc=0; timeout 60 tail --pid="$spid" -f /dev/null || rc=$?
[ "$rc" = 0 ] || { echo "the server did not exit after the race"; cat "$out/server.log"; exit 1; }
wait "$spid" || true
spid=""
wait "$bpid" || true
bpid=""
cat "$out/server.log" "$out/page.json" "$out/bots.json"
python3 - "$transport" "$out/results.json" "$out/server.log" "$out/page.json" "$out/bots.json" <<'PY'
import json, sys
transport, results, server_log, page_json, bots_json = sys.argv[1:]
def lines(path):
    return [json.loads(l) for l in open(path) if l.startswith("{")]
times = {s["name"]: (s["time_s"], s["finished"]) for s in json.load(open(results))["standings"]}
page = lines(page_json)[-1]
assert page["finished"] and times["page"][1], "the page's car did not finish: %r" % (page, )
link = [j for j in lines(server_log) if "web_link" in j][-1]["web_link"][transport]
d = link["input_delay_ms"]
assert d["n"] > 500 and d["p50"] >= 20, "the page's inputs did not cross the 20 ms link: %r" % d
assert link["sent"]["offered"] > 500, link
if transport == "webrtc":
    assert link["sent"]["dropped"] > 0, "5 %% loss dropped none of the server's datagrams: %r" % link
else:
    assert link["sent"]["retransmitted"] > 0, "5 %% loss resent none of the server's messages: %r" % link
per_min = lambda corrections, name: corrections / (times[name][0] / 60)
bots = {b["name"]: per_min(b["corrections"], b["name"]) for b in lines(bots_json) if "corrections" in b and times.get(b["name"], (0, False))[1]}
assert len(bots) == 3, "not every bot finished: %r" % bots
mine = per_min(page["net"]["corrections"], "page")
print("page (%s): %.1f corrections/min, largest %.3f m; bots: %s; input delay %r" % (
    transport, mine, page["net"]["max_correction_m"], ", ".join("%.1f" % v for v in sorted(bots.values())), d))
if transport == "webrtc":
    worst = max(bots.values())
    assert mine <= 2 * worst + 10, "the page's corrections (%.1f/min) are beyond the bots' (worst %.1f/min)" % (mine, worst)
PY
