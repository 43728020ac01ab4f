#!/usr/bin/env bash
# jetrace-view --connect (watch) without --track against a jetrace-server
# racing an OBJ track no build has built in (the small oval of the
# obj_import seed corpus): the viewer downloads the server's track before it
# serves, and the page's /track.bin is that track's mesh (36 bytes a
# triangle), not a built-in one's.
# Usage: view_download.sh SERVER VIEW OBJ SOURCE_DIR
set -euo pipefail
server="$1" view="$2" obj="$3" src="$4"
. "$src/tools/server_port.sh"
out="$(mktemp -d)"
spid="" vpid=""
cleanup() {
  for p in $vpid $spid; do kill "$p" 2>/dev/null || true; wait "$p" 2>/dev/null || true; done
  rm -rf "$out"
}
trap cleanup EXIT

"$server" --bind 127.0.0.1 --port 0 --track "$obj" --laps 1 --min-players 2 --races 1 >"$out/server.log" 2>&1 &
spid=$!
port="$(server_port "$out/server.log")"
mkfifo "$out/stdout"
"$view" --connect "127.0.0.1:$port" --http 127.0.0.1:0 >"$out/stdout" 2>"$out/view.log" &
vpid=$!
exec 3<"$out/stdout"
read -r line <&3 || { echo "jetrace-view printed no address:"; cat "$out/view.log" "$out/server.log"; exit 1; }
url="${line#listening on }"
cat "$out/view.log"
triangles="$(sed -n "s/.*downloaded the track 'gen_tiny_oval' (\([0-9]*\) triangles).*/\1/p" "$out/view.log")"
[ -n "$triangles" ] || { echo "the viewer did not download the track"; exit 1; }
grep -q "watching 127.0.0.1:$port as observer jetrace-view, track gen_tiny_oval" "$out/view.log" ||
  { echo "the viewer watches another track than the server's"; exit 1; }
bytes="$(python3 -c 'import sys, urllib.request; print(len(urllib.request.urlopen(sys.argv[1] + "track.bin", timeout=30).read()))' "$url")"
[ "$bytes" = "$((36 * triangles))" ] || { echo "/track.bin has $bytes bytes, not the $triangles triangles' $((36 * triangles))"; exit 1; }
echo "view download: the page is served the server's track ($triangles triangles, $bytes bytes)"
