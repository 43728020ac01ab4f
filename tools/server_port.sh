# Sourced by scripts that start jetrace-server with --port 0 (and --web):
#   port="$(server_port LOG)" || exit 1   waits (up to 30 s) for its line
#                                          "listening on ADDR:PORT" and prints PORT
#   web="$(web_port LOG)" || exit 1       waits (up to 30 s) for its line
#                                          "web on ADDR:PORT (...)" (--web) and prints PORT

# port_line LOG SED_SCRIPT WHAT: waits for SED_SCRIPT to print a port from LOG.
port_line() {
  local log="$1" script="$2" what="$3" port=""
  for _ in $(seq 1 300); do
    port="$(sed -n "$script" "$log")"
    [ -n "$port" ] && { echo "$port"; return 0; }
    sleep 0.1
  done
  echo "the server printed no $what:" >&2
  cat "$log" >&2
  return 1
}

server_port() { port_line "$1" 's/^listening on .*:\([0-9]*\)$/\1/p' "port (it did not start)"; }
web_port() { port_line "$1" 's/^web on .*:\([0-9]*\) (.*/\1/p' "web port"; }
