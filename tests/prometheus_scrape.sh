#!/usr/bin/env bash
# jetrace-server's --metrics scraped by the real Prometheus (Debian's
# /usr/bin/prometheus, every second, its own storage in a temporary folder,
# on free loopback ports): after a race of two bots on ring, Prometheus's
# HTTP API must report what the race did: 2 players at most, 1 race started
# and finished, ticks timed. Also checks /healthz and /status directly.
# Usage: prometheus_scrape.sh SERVER BOT [PROMETHEUS]
set -euo pipefail
here="$(dirname "$0")"
. "$here/ops_support.sh"
. "$here/../tools/server_port.sh"
server="$1" bot="$2" prometheus="${3:-/usr/bin/prometheus}"
if [ ! -x "$prometheus" ]; then echo "FAIL: no Prometheus at '$prometheus' (tools/setup.sh installs it)"; exit 1; fi

"$server" --bind 127.0.0.1 --port 0 --metrics 127.0.0.1:0 --track ring --laps 1 --min-players 2 --max-players 2 \
  --time-scale 4 --countdown 1 >"$out/server.out" 2>"$out/server.log" &
server_pid=$!
pids+=("$server_pid")
trap 'rc=$?; [ $rc -ne 0 ] && { cat "$out/server.out" "$out/server.log"; tail -20 "$out/prometheus.log"; }; cleanup; exit $rc' EXIT
port="$(server_port "$out/server.out")"
metrics_port="$(sed -n 's/^metrics on .*:\([0-9]*\)$/\1/p' "$out/server.out")"
check "the server serves /healthz" test "$(http GET "http://127.0.0.1:$metrics_port/healthz")" = ok

prom_port="$(free_port)"
cat >"$out/prometheus.yml" <<YAML
global:
  scrape_interval: 1s
  scrape_timeout: 900ms
scrape_configs:
  - job_name: jetrace
    static_configs:
      - targets: ["127.0.0.1:$metrics_port"]
YAML
"$prometheus" --config.file "$out/prometheus.yml" --storage.tsdb.path "$out/tsdb" \
  --web.listen-address "127.0.0.1:$prom_port" >"$out/prometheus.log" 2>&1 &
pids+=("$!")
api="http://127.0.0.1:$prom_port"
wait_for 30 "Prometheus is ready" http GET "$api/-/ready"

# query PROMQL: prints the value of the single result ("" if none).
query() {
  http GET "$api/api/v1/query?query=$(python3 -c 'import sys, urllib.parse; print(urllib.parse.quote(sys.argv[1]))' "$1")" |
    python3 -c 'import json, sys; r = json.load(sys.stdin)["data"]["result"]; print(r[0]["value"][1] if len(r) == 1 else "")'
}
query_is() { [ "$(query "$1")" = "$2" ]; }
wait_for 30 "Prometheus scrapes the server (up == 1)" query_is 'up{job="jetrace"}' 1

timeout 120 "$bot" --connect "127.0.0.1:$port" --count 2 --time-scale 4 --max-seconds 100 >"$out/bots.json"
check "both bots finished" test "$(grep -c '"finished":true' "$out/bots.json")" = 2
check "the server finished one race" test "$(grep -c '^race [0-9]* finished' "$out/server.out")" = 1
wait_for 20 "Prometheus saw 1 race finished" query_is 'jetrace_races_finished_total{job="jetrace"}' 1
check "Prometheus saw 1 race started" query_is 'jetrace_races_started_total{job="jetrace"}' 1
check "Prometheus saw no race aborted" query_is 'jetrace_races_aborted_total{job="jetrace"}' 0
check "Prometheus saw at most 2 players" query_is 'max_over_time(jetrace_players{job="jetrace"}[10m])' 2
check "Prometheus saw ticks timed" test "$(query 'jetrace_tick_duration_seconds_count{job="jetrace"} > 0')" != ""
check "Prometheus saw bytes received" test "$(query 'jetrace_network_bytes_received_total{job="jetrace"} > 0')" != ""
check "/status is JSON with the race number" python3 -c '
import json, sys
d = json.loads(sys.argv[1])
assert d["race"] == 1 and d["races_finished"] == 1 and d["phase"] in ("finished", "lobby"), d' \
  "$(http GET "http://127.0.0.1:$metrics_port/status")"
kill -TERM "$server_pid"
wait_exit "$server_pid" 20
check "the server exited 0 on SIGTERM (got $exit_code)" test "$exit_code" = 0
