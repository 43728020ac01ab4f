# Sourced by scripts that start jetrace-server with --port 0 (and --web). server_port waits (up to
# 30 s) for its line "listening on ADDR:PORT" in LOG and prints PORT.
# Usage: port="$(server_port LOG)" || exit 1
server_port() {
  local log="$1" port=""
  for _ in $(seq 1 300); do
    port="$(sed -n 's/^listening on .*:\([0-9]*\)$/\1/p' "$log")"
    [ -n "$port" ] && { echo "$port"; return 0; }
    sleep 0.1
  done
  echo "the server did not start:" >&2
  cat "$log" >&2
  return 1
}

# Waits (up to 10 s) for jetrace-server's line "web on ADDR:PORT (...)" in
# LOG (--web) and prints PORT.
# Usage: web="$(web_port LOG)" || exit 1
web_port() {
  local log="$1" port=""
  for _ in $(seq 1 100); do
    port="$(sed -n 's/^web on .*:\([0-9]*\) (.*/\1/p' "$log")"
    [ -n "$port" ] && { echo "$port"; return 0; }
    sleep 0.1
  done
  echo "the server printed no web port:" >&2
  cat "$log" >&2
  return 1
}
