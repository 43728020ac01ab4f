#!/usr/bin/env bash
# The server's files. (1) --races 2 with %n: each race its own results and
# replay; a racer killed mid-race (no reconnect grace) is listed as dropped
# and not finished (its car coasts on neutral inputs once the input hold is
# over, so it cannot finish before ENet times it out); the lobby timeout
# starts race 2 with the two left.
# (2) The results directory removed while the server runs: race 1's results
# are lost, the log says so with errno, and the exit code is 1. (3) A
# results name without %n whose second write fails: the first race's file
# is moved to NAME.stale, so it does not pass for the second race's.
# Usage: host_files.sh SERVER BOT
set -euo pipefail
. "$(dirname "$0")/../tools/server_port.sh"
server="$1" bot="$2"
out="$(mktemp -d)"
pid="" extra=""
trap '[ -n "$pid" ] && kill -9 "$pid" 2>/dev/null; [ -n "$extra" ] && kill -9 "$extra" 2>/dev/null; rm -rf "$out"' EXIT
common=(--bind 127.0.0.1 --port 0 --track ring --laps 1 --max-players 3 --time-scale 4 --countdown 1 --log-level info)
wait_for() {  # wait_for PATTERN LOG
  for _ in $(seq 1 400); do grep -q "$1" "$2" && return 0; sleep 0.05; done
  cat "$2"; echo "never saw '$1'"; return 1
}

# 1. Two races, two sets of files; a dropped racer is a DNF.
"$server" "${common[@]}" --min-players 3 --races 2 --reconnect-grace 0 --lobby-timeout 2 \
  --results "$out/r-%n.json" --record "$out/race-%n.replay" >"$out/two.log" 2>&1 &
pid=$!
port="$(server_port "$out/two.log")"
"$bot" --connect "127.0.0.1:$port" --track ring --name quitter --time-scale 4 --max-seconds 60 \
  >/dev/null 2>&1 &
extra=$!
timeout 120 "$bot" --connect "127.0.0.1:$port" --track ring --count 2 --races 2 --time-scale 4 --max-seconds 110 \
  >"$out/two.json" &
bots=$!
wait_for 'race 1: go' "$out/two.log"
sleep 0.5
kill -9 "$extra"
extra=""
wait "$bots"
wait "$pid"
pid=""
cat "$out/two.log"
python3 - "$out" <<'PY'
import json, os, sys
out = sys.argv[1]
r1, r2 = (json.load(open(f"{out}/r-{n}.json")) for n in (1, 2))
assert r1["race"] == 1 and r2["race"] == 2, (r1, r2)
q = [s for s in r1["standings"] if s["name"] == "quitter0"]
assert len(r1["standings"]) == 3 and len(q) == 1 and q[0]["dropped"] and not q[0]["finished"], r1
assert len(r2["standings"]) == 2 and all(s["finished"] and not s["dropped"] for s in r2["standings"]), r2
for n in (1, 2):
    assert os.path.getsize(f"{out}/race-{n}.replay") > 0
assert not [f for f in os.listdir(out) if f.endswith(".tmp")], os.listdir(out)
PY

# 2. The directory goes away: the results are lost, and the server says so.
mkdir "$out/gone"
"$server" "${common[@]}" --min-players 1 --races 1 --results "$out/gone/results.json" >"$out/lost.log" 2>&1 &
pid=$!
port="$(server_port "$out/lost.log")"
rm -rf "$out/gone"
timeout 60 "$bot" --connect "127.0.0.1:$port" --track ring --time-scale 4 --max-seconds 50 >/dev/null
rc=0
wait "$pid" || rc=$?
pid=""
cat "$out/lost.log"
[ "$rc" = 1 ] || { echo "the server exited $rc after losing the results"; exit 1; }
grep -q "race 1's results are lost: cannot create the temporary file of '$out/gone/results.json': No such file or directory" \
  "$out/lost.log" || { echo "the log does not say what was lost"; exit 1; }

# 3. The second race's write fails: the first race's file does not stay current.
"$server" "${common[@]}" --min-players 1 --races 2 --results "$out/results.json" >"$out/stale.log" 2>&1 &
pid=$!
port="$(server_port "$out/stale.log")"
timeout 60 "$bot" --connect "127.0.0.1:$port" --track ring --time-scale 4 --max-seconds 50 >/dev/null
mkdir "$out/results.json.tmp"  # the next write cannot create its temporary file
timeout 60 "$bot" --connect "127.0.0.1:$port" --track ring --time-scale 4 --max-seconds 50 >/dev/null
rc=0
wait "$pid" || rc=$?
pid=""
cat "$out/stale.log"
[ "$rc" = 1 ] || { echo "the server exited $rc after losing race 2's results"; exit 1; }
[ ! -e "$out/results.json" ] || { echo "race 1's results still pass for the latest"; exit 1; }
python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert d['race']==1, d" "$out/results.json.stale"
grep -q "race 2's results are lost: .*moved to '$out/results.json.stale'" "$out/stale.log" ||
  { echo "the log does not say where the stale results went"; exit 1; }
echo "files ok"
