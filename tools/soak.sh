#!/usr/bin/env bash
# Load and soak: jetrace-server, jetrace-netsim in front of it (loss, delay,
# jitter in both directions) and many jetrace-bot drivers racing one race
# after another. Checks that every bot finished every race, samples the
# server's resident memory (/proc/PID/status VmRSS) over time, and reports
# the memory growth after the first race and the server's CPU per tick.
# Exits non-zero on a lost race (a bot that did not finish, or a race without
# every bot), a crash, or memory growth >= the limit.
#
# Environment (defaults: the 10-minute soak):
#   JETRACE_SOAK_SECONDS (600)   run this long, then stop after the race in progress
#   JETRACE_SOAK_RACES (0)       if > 0: exactly this many races instead
#   JETRACE_SOAK_BOTS (16)       bots, all in every race (1..64). Each bot
#                                steps every car 120 times a second: 64 bots
#                                need about 8 cores to keep real time
#                                (docs/PERFORMANCE.md), 16 fit in 2
#   JETRACE_SOAK_BOTS_PER_PROCESS (8)
#   JETRACE_SOAK_LOSS (0.05)     loss per direction
#   JETRACE_SOAK_LATENCY_MS (35), JETRACE_SOAK_JITTER_MS (30): one-way delay
#                                latency + uniform [0, jitter] per direction, so
#                                the round trip is 100 +- 30 ms
#   JETRACE_SOAK_TRACK (ring), JETRACE_SOAK_LAPS (1)
#   JETRACE_SOAK_TIME_SCALE (1)  >1 runs the game clocks faster; the proxy's
#                                delays are divided by it, so that the game
#                                sees the same delays in its own time
#   JETRACE_SOAK_SAMPLE_S (1)    RSS sampling period
#   JETRACE_SOAK_LOG_LEVEL (info) of the server, the proxy and the bots
#   JETRACE_SOAK_MAX_GROWTH_KIB (1024)
#   JETRACE_SOAK_DEADLINE_S (0: none) give up after this many wall-clock
#                                seconds, printing what the server and bots logged
#   JETRACE_BUILD_DIR (build), JETRACE_SOAK_OUT (a temporary directory, removed)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
. "$root/tools/server_port.sh"
bin="${JETRACE_BUILD_DIR:-$root/build}"
seconds="${JETRACE_SOAK_SECONDS:-600}"
races="${JETRACE_SOAK_RACES:-0}"
bots="${JETRACE_SOAK_BOTS:-16}"
per_process="${JETRACE_SOAK_BOTS_PER_PROCESS:-8}"
loss="${JETRACE_SOAK_LOSS:-0.05}"
latency="${JETRACE_SOAK_LATENCY_MS:-35}"
jitter="${JETRACE_SOAK_JITTER_MS:-30}"
track="${JETRACE_SOAK_TRACK:-ring}"
laps="${JETRACE_SOAK_LAPS:-1}"
scale="${JETRACE_SOAK_TIME_SCALE:-1}"
sample_s="${JETRACE_SOAK_SAMPLE_S:-1}"
log_level="${JETRACE_SOAK_LOG_LEVEL:-info}"
max_growth_kib="${JETRACE_SOAK_MAX_GROWTH_KIB:-1024}"
deadline_s="${JETRACE_SOAK_DEADLINE_S:-0}"
for v in seconds races bots per_process max_growth_kib deadline_s; do
  [[ "${!v}" =~ ^[0-9]+$ ]] || { echo "soak: $v must be a whole number, got '${!v}'" >&2; exit 2; }
done
[ "$bots" -ge 1 ] && [ "$bots" -le 64 ] || { echo "soak: JETRACE_SOAK_BOTS must be in 1..64" >&2; exit 2; }
[ "$per_process" -ge 1 ] || { echo "soak: JETRACE_SOAK_BOTS_PER_PROCESS must be >= 1" >&2; exit 2; }
for b in server/jetrace-server client/jetrace-bot tools/jetrace-netsim; do
  [ -x "$bin/$b" ] || { echo "soak: $bin/$b is missing (build first)" >&2; exit 2; }
done

out="${JETRACE_SOAK_OUT:-}"
keep=1
if [ -z "$out" ]; then out="$(mktemp -d)"; keep=0; fi
mkdir -p "$out"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  [ "$keep" = 1 ] || rm -rf "$out"
}
# What went wrong, from the logs: the server's last lines, the bots' warnings
# and errors, and the proxy's counters.
show_logs() {
  echo "soak: server log (last 40 lines):"; tail -n 40 "$out/server.log" | sed 's/^/  /'
  for f in "$out"/bots*.log; do
    echo "soak: $(basename "$f") warnings, errors, joins and closes (last 20):"
    { grep -E '\[(warning|error|critical)\]|welcome|joining again|closed' "$f" || true; } | tail -n 20 | sed 's/^/  /'
  done
  echo "soak: netsim log (last 5 lines):"; tail -n 5 "$out/netsim.log" | sed 's/^/  /'
  for f in "$out"/bots*.json; do
    [ -s "$f" ] && { echo "soak: $(basename "$f"):"; sed 's/^/  /' "$f"; }
  done
  return 0
}
trap cleanup EXIT

# The server hosts races until it is stopped in the results pause after the
# last one (so that memory is sampled at the end of every race).
bot_races=1000000
if [ "$races" -gt 0 ]; then bot_races="$races"; fi
# Every bot reaches the server through jetrace-netsim, so all share the
# proxy's address and its pre-Hello cap (docs/HOSTING.md, "Availability"):
# jetrace-bot opens their connections --join-limit (4, the cap's default)
# at a time, and one the cap refuses all the same is tried again.
"$bin/server/jetrace-server" --bind 127.0.0.1 --port 0 --track "$track" --laps "$laps" \
  --min-players "$bots" --max-players "$bots" --races 0 --time-scale "$scale" --results "$out/results.json" \
  --record "$out/race.replay" --log-level "$log_level" >"$out/server.log" 2>&1 &
server_pid=$!
pids+=("$server_pid")
port="$(server_port "$out/server.log")"
real_latency="$(awk -v v="$latency" -v s="$scale" 'BEGIN { printf "%.3f", v / s }')"
real_jitter="$(awk -v v="$jitter" -v s="$scale" 'BEGIN { printf "%.3f", v / s }')"
"$bin/tools/jetrace-netsim" --listen 0 --forward "127.0.0.1:$port" --loss "$loss" --latency "$real_latency" \
  --jitter "$real_jitter" --seed 1 --max-clients 256 --log-level "$log_level" >"$out/netsim.log" 2>&1 &
netsim_pid=$!
pids+=("$netsim_pid")
proxy="127.0.0.1:$(server_port "$out/netsim.log")"
echo "soak: $bots bots through netsim ($proxy -> :$port; loss $loss, one-way ${latency} ms + [0, ${jitter}] ms)," \
  "$([ "$races" -gt 0 ] && echo "$races races" || echo "${seconds} s"), $laps lap(s) of $track, time scale $scale"

bot_pids=()
started=0 p=0
while [ "$started" -lt "$bots" ]; do
  n=$(( bots - started < per_process ? bots - started : per_process ))
  "$bin/client/jetrace-bot" --connect "$proxy" --track "$track" --count "$n" --name "p${p}bot" --seed "$((p + 1))" \
    --races "$bot_races" --time-scale "$scale" --log-level "$log_level" --max-seconds "$((seconds + 600))" >"$out/bots$p.json" 2>"$out/bots$p.log" &
  bot_pids+=("$!")
  pids+=("$!")
  started=$((started + n)) p=$((p + 1))
done

rss_kib() { sed -n 's/^VmRSS:[[:space:]]*\([0-9]*\) kB/\1/p' "/proc/$1/status" 2>/dev/null || true; }
finished_races() { grep -c '^race [0-9]* finished' "$out/server.log" || true; }
start_s=$(date +%s.%N)
elapsed() { awk -v a="$(date +%s.%N)" -v b="$start_s" 'BEGIN { printf "%.1f", a - b }'; }
: >"$out/rss.tsv"
seen=0 stop_sent=0
declare -a race_end_rss=()
while kill -0 "$server_pid" 2>/dev/null; do
  rss="$(rss_kib "$server_pid")"
  [ -n "$rss" ] && printf '%s\t%s\t%s\n' "$(elapsed)" "$rss" "$(rss_kib "$netsim_pid")" >>"$out/rss.tsv"
  now_races="$(finished_races)"
  if [ "$now_races" -gt "$seen" ]; then
    seen="$now_races"
    race_end_rss+=("${rss:-0}")
    # Stop in the results pause after the last race, or once the time is up.
    if [ "$stop_sent" = 0 ] && { { [ "$races" -gt 0 ] && [ "$seen" -ge "$races" ]; } ||
        { [ "$races" = 0 ] && awk -v e="$(elapsed)" -v s="$seconds" 'BEGIN { exit !(e >= s) }'; }; }; then
      kill -TERM "$server_pid"; stop_sent=1; evaluated="$seen"
    fi
  fi
  if [ "$deadline_s" -gt 0 ] && awk -v e="$(elapsed)" -v d="$deadline_s" 'BEGIN { exit !(e >= d) }'; then
    echo "soak: no result after ${deadline_s} s (JETRACE_SOAK_DEADLINE_S): $seen race(s) finished"
    show_logs
    exit 1
  fi
  sleep "$sample_s"
done
server_rc=0
wait "$server_pid" || server_rc=$?
crash=0
# The bots leave once the server has gone; a bot still running 30 s later
# is killed and counts as a crash (so that the soak never hangs here).
for _ in $(seq 1 120); do
  alive=0
  for bp in "${bot_pids[@]}"; do if kill -0 "$bp" 2>/dev/null; then alive=1; fi; done
  [ "$alive" = 0 ] && break
  sleep 0.25
done
for bp in "${bot_pids[@]}"; do
  if kill -0 "$bp" 2>/dev/null; then
    echo "soak: bot process $bp still running 30 s after the server stopped: killed"
    kill -KILL "$bp" 2>/dev/null || true
    crash=1
  fi
done
for bp in "${bot_pids[@]}"; do
  rc=0; wait "$bp" || rc=$?
  if [ "$rc" -ge 128 ]; then echo "soak: a bot process died with status $rc"; crash=1; fi
done
kill -TERM "$netsim_pid" 2>/dev/null || true
netsim_rc=0
wait "$netsim_pid" || netsim_rc=$?
[ "$netsim_rc" = 0 ] || { echo "soak: jetrace-netsim exited with $netsim_rc"; crash=1; }
[ "$server_rc" = 0 ] || { echo "soak: jetrace-server exited with $server_rc"; crash=1; }
evaluated="${evaluated:-$seen}"  # the server stopped before it was told: evaluate what it finished

if python3 - "$out" "$bots" "$evaluated" "$max_growth_kib" "${race_end_rss[*]:-}" "$crash" <<'PY'
import json, re, sys
out, bots, evaluated, max_growth, rss_at_ends, crash = sys.argv[1:7]
bots, evaluated, max_growth, crash = int(bots), int(evaluated), int(max_growth), int(crash)
log = open(f"{out}/server.log").read().splitlines()
races, current = [], None
for line in log:
    m = re.match(r"race (\d+) finished after (\d+) ticks", line)
    if m:
        current = {"race": int(m.group(1)), "ticks": int(m.group(2)), "finished": 0, "dnf": 0}
        races.append(current)
    elif current is not None and re.match(r"\s+\d+\. ", line):
        current["finished" if " finished " in line else "dnf"] += 1
    elif line.startswith("state_hash="):
        current = None
races = races[:evaluated]
lost = [r for r in races if r["finished"] != bots or r["dnf"] != 0]
figures = [json.loads(l) for l in log if l.startswith("{")]
server = figures[-1] if figures else {}
samples = [l.split("\t") for l in open(f"{out}/rss.tsv").read().splitlines() if l]
ends = [int(x) for x in rss_at_ends.split()][:max(evaluated, 1)]
growth = ends[-1] - ends[0] if len(ends) >= 2 else None
netsim = [json.loads(l) for l in open(f"{out}/netsim.log") if l.startswith("{")]
report = {
    "races": len(races), "bots": bots, "lost_races": len(lost),
    "server_rss_kib_first_race_end": ends[0] if ends else None,
    "server_rss_kib_last_race_end": ends[-1] if ends else None,
    "server_rss_growth_kib": growth,
    "server_rss_kib_max": max((int(s[1]) for s in samples), default=None),
    "netsim_rss_kib_max": max((int(s[2]) for s in samples if len(s) > 2 and s[2]), default=None),
    "tick_ms_median": server.get("tick_ms_median"), "tick_ms_p99": server.get("tick_ms_p99"),
    "server_ticks": server.get("ticks"), "server_wall_s": server.get("wall_s"),
    "netsim": netsim[-1] if netsim else None,
}
print(json.dumps(report))
for r in lost:
    print(f"soak: race {r['race']} lost: {r['finished']} of {bots} bots finished, {r['dnf']} did not")
ok = not lost and not crash and evaluated >= 1 and server
if not races:
    print("soak: no race finished"); ok = False
if growth is not None and growth >= max_growth:
    print(f"soak: server memory grew by {growth} KiB after the first race (limit {max_growth} KiB)"); ok = False
sys.exit(0 if ok else 1)
PY
then :; else rc=$?; show_logs; exit "$rc"; fi
