#!/usr/bin/env bash
# tools/load.sh sized for CI: 32 predicting bots in one jetrace-bot process
# race one lap of `ring` at 2x real time on a 32-player server: every bot must
# finish (the server's results) and receive the Results before the server
# exits (its own line), every bot's reconciliation must have taken
# its shortcuts, and corrections must stay below 2 % of the snapshots (with
# no loss on 127.0.0.1 a correction comes only from a stall: an input that
# reached the server too late, or snapshots too far apart for the upcoming
# inputs they carry, which a loaded shared machine causes now and then, more
# often at 2x where the one bot process has half the time per tick; that
# the shortened replay equals the full one bit for bit is test_predictor's,
# and zero corrections on an unloaded link test_loopback's). Then 16 thin
# bots (--thin) in one process against 2 servers at 2x: every bot finishes
# and receives the Results. Prints both load reports. About 40 s on 2 cores.
# Usage: load_bots.sh SERVER BOT
set -euo pipefail
server="$1" bot="$2"
load="$(dirname "$0")/../tools/load.sh"
check() {  # check JSON EXPR MESSAGE
  jq -e "$2" >/dev/null <<<"$1" || { echo "load_bots: $3"; exit 1; }
}
report="$("$load" --server "$server" --bot "$bot" --bots 32 --track ring --laps 1 --time-scale 2)"
echo "$report"
check "$report" '.bot_lines == 32' "not every bot printed its line"
check "$report" '.finished == 32' "not every predicting bot finished"
check "$report" '.finished_seen_by_bots == 32' "not every predicting bot received the Results"
check "$report" '.corrections <= 0.02 * .snapshots_per_bot * .bots' "predicting bots corrected too often without loss"
check "$report" '.skipped_replays_per_bot > 0 and .reused_car_steps_per_bot > 0' "a reconciliation shortcut never ran"
report="$("$load" --server "$server" --bot "$bot" --bots 16 --servers 2 --thin --track ring --laps 1 --time-scale 2)"
echo "$report"
check "$report" '.mode == "thin" and .bot_lines == 16' "not every thin bot printed its line"
check "$report" '.finished == 16' "not every thin bot finished"
check "$report" '.finished_seen_by_bots == 16' "not every thin bot received the Results"
check "$report" '.replayed_ticks_per_bot == 0' "a thin bot replayed ticks"
