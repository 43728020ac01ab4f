#!/usr/bin/env bash
# tools/fuzz.sh [seconds_per_target]: builds the libFuzzer targets of fuzz/
# with clang++ (ASan + UBSan, asserts on) in build-fuzz/ and runs each for
# seconds_per_target (default 15) on a fresh copy of its seed corpus
# (fuzz/corpus/<target>/, never modified), with fuzz/dict/<target>.dict if
# there is one. Prints one JSON line per target and one for the total:
# executions are libFuzzer's stat::number_of_executed_units.
# Exit status non-zero if any target crashed, leaked, hung or failed an
# invariant; the input that did it is in build-fuzz/artifacts/<target>/
# (reproduce: build-fuzz/fuzz/fuzz_<target> FILE; keep it as a regression:
# copy it into fuzz/corpus/<target>/).
# Targets run side by side, one a core (JETRACE_JOBS, default: the cores).
# Options: JETRACE_FUZZ_TARGETS="a b" runs only those targets;
# JETRACE_FUZZ_BUILD=DIR uses a build dir configured with -DJETRACE_FUZZ=ON
# (tools/test.sh's sanitizer build) instead of build-fuzz/.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds="${1:-15}"
if ! [[ "$seconds" =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: tools/fuzz.sh [seconds_per_target] (a whole number >= 1, got '$seconds')" >&2
  exit 2
fi
build="${JETRACE_FUZZ_BUILD:-$root/build-fuzz}"
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DJETRACE_FUZZ=ON -DJETRACE_TESTS=OFF \
    -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O2 -g" "${launcher[@]}" >/dev/null
fi
cmake --build "$build" -j "${JETRACE_JOBS:-$(nproc)}" --target fuzz_all

read -r -a targets <<<"${JETRACE_FUZZ_TARGETS:-$(tr '\n' ' ' <"$build/fuzz_targets.txt")}"
runs="$build/runs"
rm -rf "$runs"
for t in "${targets[@]}"; do
  if [ ! -x "$build/fuzz/fuzz_$t" ]; then echo "fuzz.sh: no fuzz target '$t'" >&2; exit 2; fi
done

# Runs target $1 into $runs/$1 (log, corpus, and its exit status in status).
fuzz_one() {
  local t="$1" work="$runs/$1" status=0
  mkdir -p "$work/corpus" "$build/artifacts/$t"
  if [ -d "$root/fuzz/corpus/$t" ]; then cp "$root/fuzz/corpus/$t"/* "$work/corpus/"; fi
  local args=(-max_total_time="$seconds" -print_final_stats=1 -timeout=10 -rss_limit_mb=2048 -max_len=8192
              -artifact_prefix="$build/artifacts/$t/")
  if [ -f "$root/fuzz/dict/$t.dict" ]; then args+=(-dict="$root/fuzz/dict/$t.dict"); fi
  "$build/fuzz/fuzz_$t" "${args[@]}" "$work/corpus" >"$work/log" 2>&1 || status=$?
  echo "$status" >"$work/status"
}

# One target a core at a time (JETRACE_JOBS, default: the cores), then the
# report in the targets' order.
jobs="${JETRACE_JOBS:-$(nproc)}"
for t in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
  fuzz_one "$t" &
done
wait

total=0
failed=0
for t in "${targets[@]}"; do
  work="$runs/$t"
  status="$(cat "$work/status")"
  execs="$(sed -n 's/^stat::number_of_executed_units: *\([0-9]*\).*/\1/p' "$work/log" | tail -1)"
  execs="${execs:-0}"
  total=$((total + execs))
  crashed=false
  if [ "$status" -ne 0 ]; then
    crashed=true
    failed=1
    echo "fuzz.sh: $t failed (exit $status); log: $work/log" >&2
    grep -E "ERROR|SUMMARY|invariant|Test unit written|runtime error" "$work/log" | head -20 >&2 || true
  fi
  printf '{"target":"%s","seconds":%s,"executions":%s,"corpus_after":%s,"crashed":%s}\n' \
    "$t" "$seconds" "$execs" "$(find "$work/corpus" -type f | wc -l)" "$crashed"
done
printf '{"target":"total","targets":%s,"seconds_per_target":%s,"executions":%s,"crashed":%s}\n' \
  "${#targets[@]}" "$seconds" "$total" "$([ "$failed" -eq 0 ] && echo false || echo true)"
exit "$failed"
