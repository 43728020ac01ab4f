#!/usr/bin/env bash
# --nonce-file: a connect token admitted once is refused after a restart of
# the server (the spent nonce was saved), and a corrupt nonce file is
# refused at start-up (exit 2, before listening), not silently emptied.
# Usage: host_nonce_file.sh SERVER BOT TOKEN
set -euo pipefail
. "$(dirname "$0")/../tools/server_port.sh"
server="$1" bot="$2" token="$3"
out="$(mktemp -d)"
pid=""
trap '[ -n "$pid" ] && kill -9 "$pid" 2>/dev/null; rm -rf "$out"' EXIT
"$token" keygen --out "$out/race.key" >/dev/null
"$token" issue --key-file "$out/race.key" --name alice --valid-for 600 >"$out/tokens.txt"
common=(--bind 127.0.0.1 --port 0 --track ring --laps 1 --min-players 1 --races 1 --time-scale 4 --countdown 1
        --key-file "$out/race.key.pub" --nonce-file "$out/nonces" --log-level info)

"$server" "${common[@]}" >"$out/first.log" 2>&1 &
pid=$!
port="$(server_port "$out/first.log")"
timeout 60 "$bot" --connect "127.0.0.1:$port" --token-file "$out/tokens.txt" --track ring --time-scale 4 \
  --max-seconds 50 >"$out/first.json"
wait "$pid"
pid=""
grep -q '"finished":true' "$out/first.json" || { cat "$out/first.log" "$out/first.json"; echo "alice did not race"; exit 1; }
[ "$(head -n 1 "$out/nonces")" = "jetrace-nonces 1" ] && [ "$(wc -l <"$out/nonces")" = 2 ] ||
  { cat "$out/nonces"; echo "the spent nonce was not saved"; exit 1; }

# The restarted server remembers it.
"$server" "${common[@]}" >"$out/second.log" 2>&1 &
pid=$!
port="$(server_port "$out/second.log")"
rc=0
timeout 30 "$bot" --connect "127.0.0.1:$port" --token-file "$out/tokens.txt" --track ring --time-scale 4 \
  --max-seconds 20 >"$out/second.json" 2>"$out/second.err" || rc=$?
kill -TERM "$pid"
wait "$pid"
pid=""
cat "$out/second.log" "$out/second.err"
[ "$rc" = 3 ] || { echo "the reused token got exit $rc, not 3 (refused)"; exit 1; }
grep -q 'refused: connect token already used' "$out/second.err" || { echo "no refusal reason"; exit 1; }
grep -q '1 spent connect-token nonces loaded' "$out/second.log" || { echo "no load line"; exit 1; }

# A corrupt file is refused, and left as it was.
echo "not a nonce" >>"$out/nonces"
cp "$out/nonces" "$out/nonces.before"
rc=0
"$server" "${common[@]}" >"$out/corrupt.log" 2>&1 || rc=$?
cat "$out/corrupt.log"
[ "$rc" = 2 ] || { echo "a corrupt nonce file gave exit $rc, not 2"; exit 1; }
grep -q "nonce file '$out/nonces' is corrupt at line 3" "$out/corrupt.log" || { echo "no clear error"; exit 1; }
grep -q 'listening on' "$out/corrupt.log" && { echo "the server listened with a corrupt nonce file"; exit 1; }
cmp -s "$out/nonces" "$out/nonces.before" || { echo "the corrupt nonce file was changed"; exit 1; }
echo "nonce file ok"
