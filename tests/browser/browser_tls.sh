#!/usr/bin/env bash
# jetrace-server --web with --web-cert/--web-key (a self-signed ECDSA P-256
# certificate made here with openssl): the page loads over HTTPS and joins
# over WSS in headless Chromium (browser_tls.mjs); plain HTTP on that port
# gets no page.
# Usage: browser_tls.sh SERVER SOURCE_DIR
set -euo pipefail
server="$1" src="$2"
. "$src/tools/server_port.sh"
out="$(mktemp -d)"
pid=""
trap '[ -n "$pid" ] && kill "$pid" 2>/dev/null; rm -rf "$out"' EXIT
openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -days 2 -subj /CN=127.0.0.1 \
  -addext subjectAltName=IP:127.0.0.1 -keyout "$out/key.pem" -out "$out/cert.pem" 2>/dev/null
spki="$(openssl x509 -in "$out/cert.pem" -pubkey -noout | openssl pkey -pubin -outform der | openssl dgst -sha256 -binary | base64)"
"$server" --bind 127.0.0.1 --port 0 --web 127.0.0.1:0 --web-cert "$out/cert.pem" --web-key "$out/key.pem" \
  --track ring --min-players 2 >"$out/server.log" 2>&1 &
pid=$!
server_port "$out/server.log" >/dev/null
web="$(web_port "$out/server.log")"
grep -q "open https://" "$out/server.log" || { echo "the server does not say https"; cat "$out/server.log"; exit 1; }
if curl -s --max-time 5 "http://127.0.0.1:$web/" | grep -q "<html"; then
  echo "plain HTTP got the page from a TLS port"; exit 1
fi
node "$src/tests/browser/browser_tls.mjs" "https://127.0.0.1:$web/" "$spki" || { cat "$out/server.log"; exit 1; }
grep -q "is 'secure' in slot" "$out/server.log" || { echo "the server did not take the page's Hello"; cat "$out/server.log"; exit 1; }
