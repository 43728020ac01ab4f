#!/usr/bin/env bash
# jetrace-view in a real browser (headless Chromium driven by puppeteer-core,
# viewer_replay.mjs): two offline races on ring recorded by jetrace-sim,
# one played with the other as a ghost on a port the system picks. The page
# must show, after seeking to tick N, exactly the car positions jetrace-sim
# re-simulates for tick N (ghost included); a screenshot must not be blank;
# malformed messages must close only their own socket; a page over
# --max-pages is refused. Takes about 15-30 s
# on a 2-core machine.
# Usage: viewer_replay.sh SIM VIEW SOURCE_DIR
set -euo pipefail
sim="$1" view="$2" src="$3"
[ -d "$src/node_modules/puppeteer-core" ] || { echo "no puppeteer-core in $src/node_modules: run npm ci there (tools/setup.sh does)"; exit 1; }
[ -x /usr/bin/chromium ] || { echo "no /usr/bin/chromium: apt-get install chromium (tools/setup.sh does)"; exit 1; }
out="$(mktemp -d)"
pid=""
cleanup() {
  if [ -n "$pid" ]; then kill "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true; fi
  rm -rf "$out"
}
trap cleanup EXIT

"$sim" --track ring --cars 3 --seconds 12 --seed 4 --record "$out/main.jtr" >/dev/null
"$sim" --track ring --cars 2 --seconds 10 --seed 9 --record "$out/ghost.jtr" >/dev/null
tick=977
"$sim" --replay "$out/main.jtr" --stop-tick "$tick" >"$out/expected.json"
"$sim" --replay "$out/ghost.jtr" --stop-tick "$tick" >"$out/expected_ghost.json"
cat "$out/expected.json" "$out/expected_ghost.json"

mkfifo "$out/stdout"
"$view" --replay "$out/main.jtr" --ghost "$out/ghost.jtr" --http 127.0.0.1:0 --paused --max-pages 3 \
  >"$out/stdout" 2>"$out/view.log" &
pid=$!
exec 3<"$out/stdout"
read -r line <&3 || { echo "jetrace-view printed no address:"; cat "$out/view.log"; exit 1; }
url="${line#listening on }"
[ "$url" != "$line" ] || { echo "unexpected first line: $line"; exit 1; }
echo "viewer at $url"

node "$src/tests/browser/viewer_replay.mjs" "$url" "$tick" "$out/expected.json" "$out/expected_ghost.json" \
  "$out/shot.png" || { echo "--- jetrace-view log:"; cat "$out/view.log"; exit 1; }

kill -0 "$pid" || { echo "jetrace-view died"; cat "$out/view.log"; exit 1; }
cat "$out/view.log"
grep -q "malformed message" "$out/view.log" || { echo "no log line for the malformed messages"; exit 1; }
kill -TERM "$pid"
rc=0; wait "$pid" || rc=$?
pid=""
[ "$rc" = 0 ] || { echo "jetrace-view exited $rc on SIGTERM"; exit 1; }
echo "viewer replay: all checks hold"
