#!/usr/bin/env bash
# jetrace-bot's exits: --max-seconds and SIGTERM say Goodbye (the server
# frees the slot at once, not after its reconnect grace), print a JSON line
# per bot and exit 6; a refused bot exits 3 with the reason on stderr; an
# unreachable server gives 4 (and the bot says why on stderr); a server that
# shuts down gives 5.
# Usage: bot_exits.sh SERVER BOT
set -euo pipefail
. "$(dirname "$0")/../tools/server_port.sh"
server="$1" bot="$2"
out="$(mktemp -d)"
pid="" waiting=""
trap '[ -n "$pid" ] && kill -9 "$pid" 2>/dev/null; [ -n "$waiting" ] && kill -9 "$waiting" 2>/dev/null; rm -rf "$out"' EXIT
wait_for() {  # wait_for PATTERN LOG
  for _ in $(seq 1 300); do grep -q "$1" "$2" && return 0; sleep 0.05; done
  cat "$2"; echo "never saw '$1'"; return 1
}
# Two slots (the race starts with both), a reconnect grace longer than the test.
"$server" --bind 127.0.0.1 --port 0 --track ring --min-players 2 --max-players 2 --reconnect-grace 600 --drain-timeout 1 \
  --log-level info >"$out/server.log" 2>&1 &
pid=$!
port="$(server_port "$out/server.log")"
bot_run() { "$bot" --connect "127.0.0.1:$port" --track ring "$@"; }
bot_bg() { exec "$bot" --connect "127.0.0.1:$port" --track ring "$@"; }  # its pid is the bot's

rc=0
bot_run --name timed --max-seconds 1 >"$out/timed.json" 2>"$out/timed.err" || rc=$?
[ "$rc" = 6 ] || { cat "$out/timed.err"; echo "--max-seconds exited $rc, not 6"; exit 1; }
grep -q '"outcome":"stopped"' "$out/timed.json" || { cat "$out/timed.json"; echo "no JSON line"; exit 1; }
wait_for "(timed0) said goodbye" "$out/server.log"

bot_bg --name term --max-seconds 60 >"$out/term.json" 2>"$out/term.err" &
waiting=$!
wait_for "is 'term0'" "$out/server.log"
kill -TERM "$waiting"
rc=0
wait "$waiting" || rc=$?
waiting=""
[ "$rc" = 6 ] || { echo "SIGTERM exited $rc, not 6"; exit 1; }
grep -q '"closed":"bot stopped by a signal".*"name":"term0"' "$out/term.json" || { cat "$out/term.json"; exit 1; }
wait_for "(term0) said goodbye" "$out/server.log"

# Fill both slots (a race starts), and a third is refused.
bot_bg --count 2 --name held --max-seconds 60 >/dev/null 2>&1 &
waiting=$!
wait_for "is 'held1'" "$out/server.log"
rc=0
bot_run --name extra --max-seconds 20 >"$out/extra.json" 2>"$out/extra.err" || rc=$?
[ "$rc" = 3 ] || { echo "a refused bot exited $rc, not 3"; exit 1; }
grep -q 'jetrace-bot: extra0: refused: server full (2 players)' "$out/extra.err" || { cat "$out/extra.err"; exit 1; }

# The server shuts down (SIGTERM, then the drain timeout): the racing bots hear it.
kill -TERM "$pid"
rc=0
wait "$waiting" || rc=$?
waiting=""
wait "$pid" || true
pid=""
[ "$rc" = 5 ] || { echo "bots of a server that shut down exited $rc, not 5"; exit 1; }

# Nobody there.
rc=0
bot_run --name lonely --join-window 1 --max-seconds 20 >"$out/lonely.json" 2>"$out/lonely.err" || rc=$?
[ "$rc" = 4 ] || { cat "$out/lonely.json"; echo "an unreachable server gave $rc, not 4"; exit 1; }
grep -q '"outcome":"lost_connection"' "$out/lonely.json" || { cat "$out/lonely.json"; exit 1; }
# The bot that gave up says why: its name, the reason and the close code.
grep -q '^jetrace-bot: lonely0: disconnected: could not join within 1.* \[local_connection_lost 3003\]' "$out/lonely.err" ||
  { cat "$out/lonely.err"; echo "the lonely bot did not say why it gave up"; exit 1; }
echo "bot exits ok"
