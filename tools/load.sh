#!/usr/bin/env bash
# The load report: starts --servers jetrace-server processes (each with
# --bots / --servers players) and ONE jetrace-bot process driving all the
# bots (predicting, or --thin), waits for the race, and prints one JSON line:
#   bots, finished (by the servers' results files; finished_seen_by_bots:
#   by the Results the bots received), corrections (corrections_late: the
#   snapshot shows the server stepped without the bot's input; corrections_near_car:
#   of the rest, another car within 4 radii), late_inputs (snapshots
#   showing a tick stepped without the bot's input), bot_cores (CPU time over wall time of the
#   bot process), bot_cores_per_bot, server tick median / p99 (ms, the
#   largest over the servers), bytes per client per simulated second each
#   way (mean over the bots, ENet headers included) and in kbit/s.
# Every figure comes from the processes' own JSON lines and /usr/bin/time.
#
# Usage: tools/load.sh [--bots N] [--servers S] [--track T] [--laps L]
#                      [--time-scale X] [--thin] [--build DIR] [--keep DIR]
#                      [--server BIN] [--bot BIN]   (default: under --build)
#                      [--target-margin TICKS]      (jetrace-bot's, default 2)
#                      [--input-delay TICKS]        (jetrace-bot's, default 4)
#                      [--finish-window S]          (the servers', default theirs: 60)
# Exits non-zero if a process failed to start or the server failed; the
# figures say how many bots finished (the caller decides what is enough).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
. "$root/tools/server_port.sh"

finish_window="" margin=2 delay=4 bots=8 servers=1 track=stadium laps=1 scale=1 thin="" build="$root/build" keep="" server="" bot=""
usage() { sed -n '/^# Usage/,/^# Exits/p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
need() { [ $# -ge 2 ] || { echo "load.sh: $1 needs a value" >&2; exit 2; }; }
while [ $# -gt 0 ]; do
  case "$1" in
    --bots) need "$@"; bots="$2"; shift 2 ;;
    --servers) need "$@"; servers="$2"; shift 2 ;;
    --track) need "$@"; track="$2"; shift 2 ;;
    --laps) need "$@"; laps="$2"; shift 2 ;;
    --time-scale) need "$@"; scale="$2"; shift 2 ;;
    --thin) thin="--thin"; shift ;;
    --build) need "$@"; build="$2"; shift 2 ;;
    --keep) need "$@"; keep="$2"; shift 2 ;;
    --server) need "$@"; server="$2"; shift 2 ;;
    --bot) need "$@"; bot="$2"; shift 2 ;;
    --target-margin) need "$@"; margin="$2"; shift 2 ;;
    --input-delay) need "$@"; delay="$2"; shift 2 ;;
    --finish-window) need "$@"; finish_window="$2"; shift 2 ;;
    -h|--help) usage ;;
    *) echo "load.sh: unknown argument '$1'" >&2; usage ;;
  esac
done
is_int() { [[ "$1" =~ ^[0-9]+$ ]] && [ "$1" -ge "$2" ] && [ "$1" -le "$3" ]; }
is_int "$servers" 1 8 || { echo "load.sh: --servers must be 1..8" >&2; exit 2; }
is_int "$bots" 1 256 || { echo "load.sh: --bots must be 1..256" >&2; exit 2; }
is_int "$laps" 1 100 || { echo "load.sh: --laps must be 1..100" >&2; exit 2; }
[ $((bots % servers)) = 0 ] || { echo "load.sh: --bots must be a multiple of --servers" >&2; exit 2; }
per_server=$((bots / servers))
is_int "$per_server" 1 64 || { echo "load.sh: at most 64 bots per server" >&2; exit 2; }
[[ "$scale" =~ ^[0-9]+(\.[0-9]+)?$ ]] || { echo "load.sh: --time-scale must be a number" >&2; exit 2; }
[[ "$margin" =~ ^[0-9]+(\.[0-9]+)?$ ]] || { echo "load.sh: --target-margin must be a number" >&2; exit 2; }
[[ "$delay" =~ ^[0-9]+$ ]] || { echo "load.sh: --input-delay must be a whole number of ticks" >&2; exit 2; }
[ -z "$finish_window" ] || [[ "$finish_window" =~ ^[0-9]+(\.[0-9]+)?$ ]] ||
  { echo "load.sh: --finish-window must be a number of seconds" >&2; exit 2; }
server="${server:-$build/server/jetrace-server}" bot="${bot:-$build/client/jetrace-bot}"
for b in "$server" "$bot"; do
  [ -x "$b" ] || { echo "load.sh: $b is missing (build it first)" >&2; exit 2; }
done

out="${keep:-$(mktemp -d)}"
mkdir -p "$out"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  [ -n "$keep" ] || rm -rf "$out"
}
trap cleanup EXIT

connects=()
window_arg=()
[ -z "$finish_window" ] || window_arg=(--finish-window "$finish_window")
window_s="${finish_window:-60}" window_s="${window_s%.*}"  # whole seconds, for the bots' --max-seconds
for i in $(seq 1 "$servers"); do
  /usr/bin/time -f '%U %S %e' -o "$out/server$i.time" \
    "$server" --bind 127.0.0.1 --port 0 --track "$track" --laps "$laps" \
    --min-players "$per_server" --max-players "$per_server" --races 1 --time-scale "$scale" \
    "${window_arg[@]}" --results "$out/results$i.json" --log-level warn >"$out/server$i.log" 2>&1 &
  pids+=($!)
  port="$(server_port "$out/server$i.log")"
  connects+=(--connect "127.0.0.1:$port")
done

margin_arg=""
[ "$margin" = 2 ] || margin_arg="--target-margin $margin"
rc=0
/usr/bin/time -f '%U %S %e' -o "$out/bot.time" \
  "$bot" "${connects[@]}" --count "$bots" --time-scale "$scale" $margin_arg --input-delay "$delay" $thin \
  --max-seconds "$(( laps * 120 + 60 + window_s ))" >"$out/bots.json" 2>"$out/bots.err" || rc=$?
# A server whose bots are gone ends its race and exits; one still waiting
# for players after 30 s never got them all (see bots.err).
for _ in $(seq 1 300); do
  alive=0
  for p in "${pids[@]}"; do kill -0 "$p" 2>/dev/null && alive=1; done
  [ "$alive" = 0 ] && break
  sleep 0.1
done
for i in $(seq 1 "$servers"); do
  p="${pids[$((i - 1))]}"
  kill -0 "$p" 2>/dev/null && { echo "load.sh: server $i still running after its bots left (exit $rc):" >&2; tail -5 "$out/bots.err" >&2; exit 1; }
  wait "$p" || { echo "load.sh: server $i failed:" >&2; cat "$out/server$i.log" >&2; exit 1; }
done
pids=()
[ -s "$out/bots.json" ] || { echo "load.sh: the bots printed nothing (exit $rc):" >&2; cat "$out/bots.err" >&2; exit 1; }

# The servers' figure lines (the only JSON lines in their logs).
cat "$out"/server*.log | grep '^{' >"$out/servers.json" || true
cat "$out"/results*.json >"$out/results.json" 2>/dev/null || true
read -r bot_user bot_sys bot_wall < <(tail -n 1 "$out/bot.time") 2>/dev/null || { echo "load.sh: no bot timing" >&2; exit 1; }
jq -s -c --argjson bots "$bots" --argjson servers "$servers" --arg track "$track" --argjson laps "$laps" \
  --argjson scale "$scale" --argjson margin "$margin" --argjson delay "$delay" --arg window "$finish_window" --arg mode "${thin:+thin}" --argjson cpu "$(awk -v u="$bot_user" -v s="$bot_sys" 'BEGIN { print u + s }')" \
  --argjson wall "$bot_wall" --slurpfile srv "$out/servers.json" --slurpfile res "$out/results.json" '
  def mean(f): if length == 0 then 0 else (map(f) | add / length) end;
  {
    mode: (if $mode == "thin" then "thin" else "predicting" end),
    track: $track, laps: $laps, time_scale: $scale, servers: $servers, target_margin_ticks: $margin, input_delay_ticks: $delay,
    finish_window_s: (if $window == "" then 60 else ($window | tonumber) end),
    bots: $bots,
    bot_lines: length,
    finished: ($res | map(.standings[] | select(.finished)) | length),
    finished_seen_by_bots: map(select(.finished)) | length,
    corrections: map(.corrections) | add,
    corrections_late: map(.corrections_late // 0) | add,
    corrections_near_car: map(.corrections_near_car // 0) | add,
    max_correction_m: map(.max_correction_m) | max,
    late_inputs: map(.late_inputs // 0) | add,
    reconnects: map(.reconnects) | add,
    replayed_ticks_per_bot: mean(.replayed_ticks // 0),
    skipped_replays_per_bot: mean(.skipped_replays // 0),
    reused_car_steps_per_bot: mean(.reused_car_steps // 0),
    snapshots_per_bot: mean(.snapshots),
    bot_wall_s: $wall,
    bot_cores: (if $wall > 0 then $cpu / $wall else 0 end),
    bot_cores_per_bot: (if $wall > 0 then $cpu / $wall / $bots else 0 end),
    server_tick_ms_median: ($srv | map(.tick_ms_median) | max),
    server_tick_ms_p99: ($srv | map(.tick_ms_p99) | max),
    down_bytes_per_s: mean(.down_bytes_per_s),
    up_bytes_per_s: mean(.up_bytes_per_s),
    down_kbit_per_s: (mean(.down_bytes_per_s) * 8 / 1000),
    up_kbit_per_s: (mean(.up_bytes_per_s) * 8 / 1000),
    not_finished: map(select(.finished | not) | .closed) | group_by(.) | map({(.[0]): length}) | add
  }' "$out/bots.json"
