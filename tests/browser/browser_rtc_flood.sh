#!/usr/bin/env bash
# 100 half-finished WebRTC handshakes (offers posted to /rtc, never any ICE)
# from one address, 127.0.0.5, then an honest page from 127.0.0.1: the flood
# gets 4 answers and 96 503s, and the page still joins over its WebRTC data
# channel (docs/BROWSER.md, "What the web port refuses"); the metrics count
# the refusals (jetrace_webrtc_refused_total{reason="busy"}).
# Usage: browser_rtc_flood.sh SERVER SOURCE_DIR
set -euo pipefail
server="$1" src="$2"
. "$src/tools/server_port.sh"
[ -d "$src/node_modules/puppeteer-core" ] || { echo "no puppeteer-core in $src/node_modules: run npm ci there (tools/setup.sh does)"; exit 1; }
out="$(mktemp -d)"
spid=""
cleanup() {
  [ -n "$spid" ] && { kill "$spid" 2>/dev/null || true; wait "$spid" 2>/dev/null || true; }
  rm -rf "$out"
}
trap cleanup EXIT
"$server" --bind 127.0.0.1 --port 0 --web 127.0.0.1:0 --metrics 127.0.0.1:0 --track ring --min-players 2 \
  >"$out/server.log" 2>&1 &
spid=$!
web="$(web_port "$out/server.log")"
metrics="$(port_line "$out/server.log" 's/^metrics on \(.*\)$/\1/p' "metrics address")"
offer="$src/tests/webrtc/fixtures/chromium156_offer.sdp"
answered=0 busy=0
for _ in $(seq 1 100); do
  code="$(curl -s -o /dev/null -w '%{http_code}' --interface 127.0.0.5 -H 'Content-Type: application/sdp' \
    --data-binary @"$offer" "http://127.0.0.1:$web/rtc")"
  case "$code" in 200) answered=$((answered + 1)) ;; 503) busy=$((busy + 1)) ;; *) echo "flood: HTTP $code"; exit 1 ;; esac
done
echo "100 offers from 127.0.0.5, no ICE: $answered answered, $busy refused with 503"
[ "$answered" = 4 ] && [ "$busy" = 96 ] || { echo "FAIL: expected 4 and 96"; exit 1; }
node "$src/tests/browser/browser_rtc_flood.mjs" "http://127.0.0.1:$web/" "http://$metrics/metrics" ||
  { echo "--- server log:"; cat "$out/server.log"; exit 1; }
