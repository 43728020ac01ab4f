#!/usr/bin/env bash
# POST /rtc on a live jetrace-server --web (docs/PROTOCOL.md, "Transport:
# WebRTC data channel"): a browser's offer gets 200 and an ICE-lite answer
# naming the UDP port; bad offers (malformed, no fingerprint, too large,
# far too large) get 400 with the reason; a foreign Origin 403; a GET 405;
# 100 offers from one address (127.0.0.5) that never do ICE get 4 answers
# and then 503, while an offer from another address (127.0.0.1) is still
# answered. (That an honest browser then connects end to end:
# test_rtc_transport, HalfFinishedHandshakesDoNotLockOutOthers.)
# Usage: rtc_signalling.sh SERVER SOURCE_DIR
set -euo pipefail
server="$1" src="$2"
. "$src/tools/server_port.sh"
out="$(mktemp -d)"
spid=""
cleanup() {
  [ -n "$spid" ] && { kill "$spid" 2>/dev/null || true; wait "$spid" 2>/dev/null || true; }
  rm -rf "$out"
}
trap cleanup EXIT
"$server" --bind 127.0.0.1 --port 0 --web 127.0.0.1:0 --track ring >"$out/server.log" 2>&1 &
spid=$!
web="$(web_port "$out/server.log")"
udp="$(port_line "$out/server.log" 's/^webrtc on .*:\([0-9]*\) (.*/\1/p' "webrtc port")"
offer="$src/tests/webrtc/fixtures/chromium156_offer.sdp"
url="http://127.0.0.1:$web/rtc"
post() { curl -s -o "$out/body" -w '%{http_code}' -H 'Content-Type: application/sdp' "$@" "$url"; }
fail() { echo "FAIL: $*"; cat "$out/server.log"; exit 1; }

code="$(post --data-binary @"$offer")"
[ "$code" = 200 ] || fail "a browser's offer: HTTP $code"
grep -q '^a=ice-lite' "$out/body" && grep -q "a=candidate:1 1 UDP [0-9]* 127.0.0.1 $udp typ host" "$out/body" ||
  fail "the answer is not ICE-lite with a host candidate on UDP $udp: $(cat "$out/body")"
echo "a browser's offer: 200, ICE-lite answer with the host candidate 127.0.0.1:$udp"

expect_400() {  # WHAT REASON CURL_ARGS...
  local what="$1" reason="$2"
  shift 2
  code="$(post "$@")"
  [ "$code" = 400 ] && grep -q "$reason" "$out/body" || fail "$what: HTTP $code $(cat "$out/body")"
  echo "$what: 400 $(cat "$out/body")"
}
expect_400 "a malformed offer" "malformed line" --data-binary 'hello'
grep -v '^a=fingerprint' "$offer" >"$out/nofp"
expect_400 "an offer without a fingerprint" "no sha-256 fingerprint" --data-binary @"$out/nofp"
head -c 20000 /dev/zero | tr '\0' a >"$out/big"
expect_400 "a 20 KB offer" "too large" --data-binary @"$out/big"
head -c 400000 /dev/zero | tr '\0' a >"$out/huge"
expect_400 "a 400 KB body" "too large" --data-binary @"$out/huge"
code="$(post -H 'Origin: http://elsewhere.example' --data-binary @"$offer")"
[ "$code" = 403 ] || fail "a foreign Origin: HTTP $code"
code="$(curl -s -o /dev/null -w '%{http_code}' "$url")"
[ "$code" = 405 ] || fail "GET /rtc: HTTP $code"
echo "a foreign Origin: 403; GET: 405"

answered=0 busy=0
for _ in $(seq 1 100); do
  code="$(post --interface 127.0.0.5 --data-binary @"$offer")"
  case "$code" in 200) answered=$((answered + 1)) ;; 503) busy=$((busy + 1)) ;; *) fail "flood: HTTP $code" ;; esac
done
[ "$answered" = 4 ] && [ "$busy" = 96 ] || fail "100 offers from 127.0.0.5: $answered answered, $busy refused"
code="$(post --data-binary @"$offer")"
[ "$code" = 200 ] || fail "an offer from 127.0.0.1 after the flood: HTTP $code"
echo "100 half-finished handshakes from 127.0.0.5: $answered answered, $busy refused with 503; 127.0.0.1 still answered 200"
