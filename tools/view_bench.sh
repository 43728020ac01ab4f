#!/usr/bin/env bash
# The browser viewer's benchmark (docs/PERFORMANCE.md, "The browser viewer"):
# builds a landscape track (jetrace-bench landscape: 2 n^2 triangles, a
# 16-gate lap) and two AI races on it (jetrace-sim --record: BIG and SMALL
# cars), serves each with jetrace-view --replay ... --http 127.0.0.1:0 and
# plays it in headless Chromium (tools/view_bench.mjs) for SECONDS per case:
# the big race in 1 page, then in PAGES pages, the small one in 1 page.
# Prints ONE JSON object: the page's draw time (median, p99) and frame rate,
# WebSocket bytes per second per page, jetrace-view's CPU per page.
# Usage: tools/view_bench.sh [--squares N] [--cars BIG] [--small-cars SMALL]
#          [--race-seconds S] [--seconds S] [--pages P]
# Binaries from $JETRACE_BUILD (default: build/ of this checkout), or each
# named by $JETRACE_BENCH, $JETRACE_SIM, $JETRACE_VIEW.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${JETRACE_BUILD:-$root/build}"
squares=500 big=64 small=8 race_s=60 seconds=20 pages=4

usage() { echo "usage: $0 [--squares 2..1414] [--cars 1..64] [--small-cars 1..64] [--race-seconds 1..3600] [--seconds 1..600] [--pages 1..16]" >&2; exit 2; }
# int NAME VALUE MIN MAX: VALUE must be a whole number in [MIN, MAX].
int() {
  [[ "$2" =~ ^[0-9]{1,6}$ ]] && (( 10#$2 >= $3 && 10#$2 <= $4 )) || { echo "$0: $1 must be a whole number in $3..$4 (got '$2')" >&2; exit 2; }
  echo $((10#$2))
}
while [ $# -gt 0 ]; do
  [ $# -ge 2 ] || usage
  case "$1" in
    --squares) squares="$(int --squares "$2" 2 1414)" ;;
    --cars) big="$(int --cars "$2" 1 64)" ;;
    --small-cars) small="$(int --small-cars "$2" 1 64)" ;;
    --race-seconds) race_s="$(int --race-seconds "$2" 1 3600)" ;;
    --seconds) seconds="$(int --seconds "$2" 1 600)" ;;
    --pages) pages="$(int --pages "$2" 1 16)" ;;
    *) usage ;;
  esac
  shift 2
done

bench="${JETRACE_BENCH:-$build/tools/jetrace-bench}" sim="${JETRACE_SIM:-$build/tools/jetrace-sim}"
view="${JETRACE_VIEW:-$build/client/view/jetrace-view}"
for b in "$bench" "$sim" "$view"; do [ -x "$b" ] || { echo "$0: no $b (cmake --build build --target jetrace-bench jetrace-sim jetrace-view)" >&2; exit 1; }; done
[ -d "$root/node_modules/puppeteer-core" ] || { echo "$0: no puppeteer-core in $root/node_modules: run npm ci (tools/setup.sh does)" >&2; exit 1; }
[ -x /usr/bin/chromium ] || { echo "$0: no /usr/bin/chromium (tools/setup.sh installs it)" >&2; exit 1; }

tmp="$(mktemp -d)"
pid=""
cleanup() {
  if [ -n "$pid" ]; then kill "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true; fi
  rm -rf "$tmp"
}
trap cleanup EXIT
load_before="$(cut -d' ' -f1-3 /proc/loadavg)"

"$bench" landscape --squares "$squares" --spawns "$big" --out "$tmp/land.obj" >"$tmp/landscape.json"
"$sim" --track "$tmp/land.obj" --cars "$big" --seconds "$race_s" --record "$tmp/big.jtr" >"$tmp/sim_big.txt"
"$sim" --track "$tmp/land.obj" --cars "$small" --seconds "$race_s" --record "$tmp/small.jtr" >"$tmp/sim_small.txt"

# run_case NAME REPLAY PAGES: one jetrace-view, PAGES pages for $seconds; writes $tmp/NAME.json.
run_case() {
  local name="$1" replay="$2" n="$3" line url rc=0
  rm -f "$tmp/stdout"
  mkfifo "$tmp/stdout"
  "$view" --replay "$replay" --track "$tmp/land.obj" --http 127.0.0.1:0 --paused --max-pages 32 \
    >"$tmp/stdout" 2>"$tmp/$name.log" &
  pid=$!
  exec 3<"$tmp/stdout"
  read -r line <&3 || { echo "$0: jetrace-view printed no address:" >&2; cat "$tmp/$name.log" >&2; exit 1; }
  exec 3<&-
  url="${line#listening on }"
  node "$root/tools/view_bench.mjs" "$url" "$pid" "$n" "$seconds" >"$tmp/$name.json" ||
    { echo "$0: the page run failed; jetrace-view's log:" >&2; cat "$tmp/$name.log" >&2; exit 1; }
  kill -TERM "$pid"
  wait "$pid" || rc=$?
  pid=""
  [ "$rc" = 0 ] || { echo "$0: jetrace-view exited $rc" >&2; cat "$tmp/$name.log" >&2; exit 1; }
  # jetrace-view's own count per page at close: "page N: ...; X bytes sent in Y s (Z B/s)".
  sed -n 's/.*bytes sent in [0-9.]* s (\([0-9]*\) B\/s).*/\1/p' "$tmp/$name.log" | paste -sd, >"$tmp/$name.logbps"
}

run_case big_1 "$tmp/big.jtr" 1
run_case big_n "$tmp/big.jtr" "$pages"
run_case small_1 "$tmp/small.jtr" 1

TMP="$tmp" LOAD="$load_before" SQUARES="$squares" node --input-type=module -e '
import { readFileSync } from "node:fs";
const dir = process.env.TMP;
const read = (name) => JSON.parse(readFileSync(`${dir}/${name}.json`, "utf8"));
const logRates = (name) => readFileSync(`${dir}/${name}.logbps`, "utf8").trim().split(",").filter((x) => x).map(Number);
const land = JSON.parse(readFileSync(`${dir}/landscape.json`, "utf8"));
const cases = {};
for (const name of ["big_1", "big_n", "small_1"]) cases[name] = { ...read(name), view_log_bytes_per_s: logRates(name) };
const big = cases.big_1, many = cases.big_n, small = cases.small_1;
console.log(JSON.stringify({
  benchmark: "view", track: land.track, triangles: land.triangles, load_average_before: process.env.LOAD,
  cars_big: big.cars, cars_small: small.cars, pages_many: many.pages,
  render_ms_median: big.render_ms_median, render_ms_p99: big.render_ms_p99,
  frame_interval_ms_median: big.frame_interval_ms_median, frame_interval_ms_p99: big.frame_interval_ms_p99,
  fps: big.fps, frames_received_per_s: big.frames_received_per_s,
  ws_bytes_per_s_big: big.ws_bytes_per_s, ws_bytes_per_s_small: small.ws_bytes_per_s,
  ws_bytes_per_frame_big: big.ws_bytes_per_frame, ws_bytes_per_frame_small: small.ws_bytes_per_frame,
  view_cpu_fraction_1_page: big.view_cpu_fraction, view_cpu_fraction_per_page_many: many.view_cpu_fraction_per_page,
  fps_many: many.per_page.map((p) => p.fps),
  cases,
}));
'
