#!/usr/bin/env bash
# The replay command lines, as a user runs them: an offline race recorded
# and signed by jetrace-sim; --verify with the right key passes (exit 0),
# with another key and with a wrong --expect fails (exit 1); --replay prints
# the race's state_hash; --diff of the replay with itself and --diff
# --rebuild say identical; --synctest holds; jetrace-verify agrees; a cut
# copy is incomplete (exit 1) and --diff finds it shorter.
# Usage: replay_tools.sh SIM TOKEN VERIFY
set -euo pipefail
sim="$1" token="$2" verify="$3"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
"$token" keygen --out "$out/k" >/dev/null
"$token" keygen --out "$out/other" >/dev/null
hash="$("$sim" --track ring --cars 3 --seconds 8 --seed 4 --record "$out/r.jtr" --sign-key "$out/k" |
  sed -n 's/^state_hash=//p')"
[ "${#hash}" = 16 ] || { echo "no state_hash from the recorded race"; exit 1; }
"$sim" --verify "$out/r.jtr" --key "$out/k.pub" --expect "$hash" | tee "$out/v.json"
grep -q '"ok":true' "$out/v.json" && grep -q '"signature":"valid"' "$out/v.json" && grep -q '"signer_trusted":true' "$out/v.json"
expect_rc() {  # expect_rc RC CMD...: CMD must exit with RC
  local want="$1" rc=0; shift
  "$@" >"$out/last" 2>&1 || rc=$?
  cat "$out/last"
  [ "$rc" = "$want" ] || { echo "exit $rc, expected $want: $*"; exit 1; }
}
expect_rc 1 "$sim" --verify "$out/r.jtr" --key "$out/other.pub"
grep -q '"problem":"untrusted_signer"' "$out/last"
expect_rc 1 "$sim" --verify "$out/r.jtr" --expect 0000000000000000
grep -q '"problem":"expect_mismatch"' "$out/last"
[ "$("$sim" --replay "$out/r.jtr" | sed -n 's/^state_hash=//p')" = "$hash" ]
expect_rc 0 "$sim" --diff "$out/r.jtr" "$out/r.jtr"
grep -q '"verdict":"identical"' "$out/last"
expect_rc 0 "$sim" --diff "$out/r.jtr" --rebuild
expect_rc 0 "$sim" --synctest "$out/r.jtr" --rollback 5
grep -q '"ok":true' "$out/last"
expect_rc 0 "$verify" "$out/r.jtr" --expect "$hash"
head -c 20000 "$out/r.jtr" >"$out/cut.jtr"
expect_rc 1 "$sim" --verify "$out/cut.jtr"
grep -Eq '"problem":"(incomplete|truncated)"' "$out/last"
expect_rc 1 "$sim" --diff "$out/r.jtr" "$out/cut.jtr"
grep -Eq '"verdict":"(shorter|unreadable)"' "$out/last"
echo "replay tools: all checks hold"
