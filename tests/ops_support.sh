# Sourced by the ops tests (agones_lifecycle.sh, prometheus_scrape.sh):
# free ports, HTTP through python3, bounded waits, process clean-up.

# Processes to stop at exit (by id); `cleanup` is the EXIT trap.
pids=()
out="$(mktemp -d)"
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  rm -rf "$out"
}
trap cleanup EXIT

# A TCP port free on 127.0.0.1 right now.
free_port() {
  python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'
}

# http METHOD URL [BODY]: prints the response body; non-zero on failure.
http() {
  python3 - "$@" <<'PY'
import sys, urllib.request
method, url = sys.argv[1], sys.argv[2]
body = sys.argv[3].encode() if len(sys.argv) > 3 else None
req = urllib.request.Request(url, data=body, method=method, headers={"Content-Type": "application/json"})
with urllib.request.urlopen(req, timeout=5) as r:
    sys.stdout.write(r.read().decode())
PY
}

# wait_for SECONDS WHAT COMMAND...: retries COMMAND every 0.2 s.
wait_for() {
  local seconds="$1" what="$2"; shift 2
  local end=$((SECONDS + seconds))
  until "$@" >/dev/null 2>&1; do
    if [ "$SECONDS" -ge "$end" ]; then echo "FAIL: $what (waited $seconds s)"; return 1; fi
    sleep 0.2
  done
  echo "ok: $what"
}

# wait_exit PID SECONDS: waits for PID (a child of this shell) to end and
# sets exit_code to its exit code ("timeout" if it is still running).
wait_exit() {
  local pid="$1" end=$((SECONDS + $2))
  exit_code=0
  while kill -0 "$pid" 2>/dev/null; do
    if [ "$SECONDS" -ge "$end" ]; then exit_code=timeout; return 0; fi
    sleep 0.1
  done
  wait "$pid" || exit_code=$?
}

# check DESCRIPTION COMMAND...: prints ok/FAIL; exits on failure.
check() {
  local what="$1"; shift
  if "$@"; then echo "ok: $what"; else echo "FAIL: $what"; exit 1; fi
}
