#!/usr/bin/env bash
# tools/load.sh sized for CI: 32 predicting bots in one jetrace-bot process
# race one lap of `ring` at 2x real time on a 32-player server: every bot
# must finish and none may correct its prediction (no loss on 127.0.0.1);
# then 16 thin bots (--thin) in one process against 2 servers: every bot
# finishes. Prints both load reports. About 45 s on 2 cores.
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
check "$report" '.corrections == 0' "a predicting bot corrected its prediction without any loss"
check "$report" '.skipped_replays_per_bot > 0 and .replayed_ticks_per_bot > 0' "no reconciliation was measured"
report="$("$load" --server "$server" --bot "$bot" --bots 16 --servers 2 --thin --track ring --laps 1 --time-scale 2)"
echo "$report"
check "$report" '.mode == "thin" and .bot_lines == 16' "not every thin bot printed its line"
check "$report" '.finished == 16' "not every thin bot finished"
check "$report" '.replayed_ticks_per_bot == 0' "a thin bot replayed ticks"
