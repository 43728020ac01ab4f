#!/usr/bin/env bash
# A private race joined from the browser (docs/BROWSER.md): jetrace-token
# makes a key and a token for alice, and a token from another key;
# jetrace-server --key-file --web admits the page whose URL carries alice's
# token (#token=...) and refuses the other with close code 2001, which the
# page shows (browser_private.mjs).
# Usage: browser_private.sh SERVER TOKEN SOURCE_DIR
set -euo pipefail
server="$1" token="$2" src="$3"
. "$src/tools/server_port.sh"
out="$(mktemp -d)"
pid=""
trap '[ -n "$pid" ] && kill "$pid" 2>/dev/null; rm -rf "$out"' EXIT
"$token" keygen --out "$out/race.key" >/dev/null
"$token" keygen --out "$out/other.key" >/dev/null
good="$("$token" issue --key-file "$out/race.key" --name alice --valid-for 600)"
bad="$("$token" issue --key-file "$out/other.key" --name mallory --valid-for 600)"
"$server" --bind 127.0.0.1 --port 0 --web 127.0.0.1:0 --track ring --min-players 2 --key-file "$out/race.key.pub" \
  >"$out/server.log" 2>&1 &
pid=$!
server_port "$out/server.log" >/dev/null
web="$(web_port "$out/server.log")"
node "$src/tests/browser/browser_private.mjs" "http://127.0.0.1:$web/" "$good" "$bad" ||
  { cat "$out/server.log"; exit 1; }
grep -q "refusing client .*not signed with this server's key" "$out/server.log" ||
  { echo "the server did not log the refusal"; cat "$out/server.log"; exit 1; }
