#!/usr/bin/env bash
# Compares two builds of jetrace on every tracked figure (docs/PERFORMANCE.md,
# "Comparing two builds"): BASE, a commit, against the working tree as it is
# (uncommitted changes included).
#   1. builds BASE (in a git worktree, build-bench/src-SHA) and the working
#      tree into their own folders (build-bench/base-SHA, build-bench/head)
#      with the same flags: Release, link-time optimisation as the README's
#      build (JETRACE_LTO=OFF to build faster), jetrace-bench and jetrace-sim;
#   2. runs every figure's command A B, then B A, ... (--rounds rounds, the
#      order alternating) on one core (taskset -c --core);
#   3. prints one JSON line per figure (both medians, their spreads, the
#      ratio head/base, a verdict) and a summary naming every figure that is
#      worse by more than 3 % beyond its spread, or, for a deterministic one
#      (wire bytes, state hashes), that changed.
# The figures and how each is read: tools/bench_figures.py.
#
# Usage: tools/bench_compare.sh [BASE] [--rounds N] [--core C] [--smoke]
#                               [--base-build DIR] [--head-build DIR] [--keep DIR]
#   BASE          a commit (default: $JETRACE_BENCH_BASE, else the merge base
#                 with the branch's upstream, else where the branch was when
#                 this checkout began: the oldest entry of its reflog)
#   --rounds N    A/B rounds (default 5; 1 with --smoke)
#   --core C      the core to pin to (default: the last one)
#   --smoke       tiny runs of every command (checks the tool works, not speed)
#   --base-build, --head-build DIR
#                 use binaries already built in DIR instead of building
#   --keep DIR    keep every run's output there
# Exit: 0 nothing worse, 3 a figure worse or changed (0 with --smoke), 1 a
# build or a run failed, 2 bad arguments.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
figures="$root/tools/bench_figures.py"

base="${JETRACE_BENCH_BASE:-}" rounds="" core="" smoke="" base_build="" head_build="" keep=""
usage() { sed -n '/^# Usage/,/^# Exit/p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
need() { [ $# -ge 2 ] || { echo "bench_compare: $1 needs a value" >&2; exit 2; }; }
while [ $# -gt 0 ]; do
  case "$1" in
    --rounds) need "$@"; rounds="$2"; shift 2 ;;
    --core) need "$@"; core="$2"; shift 2 ;;
    --smoke) smoke=1; shift ;;
    --base-build) need "$@"; base_build="$2"; shift 2 ;;
    --head-build) need "$@"; head_build="$2"; shift 2 ;;
    --keep) need "$@"; keep="$2"; shift 2 ;;
    -h|--help) usage ;;
    -*) echo "bench_compare: unknown option '$1'" >&2; usage ;;
    *) [ -z "$base" ] || [ -n "${JETRACE_BENCH_BASE:-}" ] || { echo "bench_compare: one BASE only" >&2; exit 2; }
       base="$1"; shift ;;
  esac
done
[ -n "$rounds" ] || rounds=$([ -n "$smoke" ] && echo 1 || echo 5)
[[ "$rounds" =~ ^[0-9]+$ ]] && [ "$rounds" -ge 1 ] && [ "$rounds" -le 50 ] || { echo "bench_compare: --rounds must be 1..50" >&2; exit 2; }
cores="$(nproc)"
[ -n "$core" ] || core=$((cores - 1))
[[ "$core" =~ ^[0-9]+$ ]] && [ "$core" -lt "$cores" ] || { echo "bench_compare: --core must be 0..$((cores - 1))" >&2; exit 2; }
for d in "$base_build" "$head_build"; do
  [ -z "$d" ] || [ -x "$d/tools/jetrace-bench" ] || { echo "bench_compare: no tools/jetrace-bench in '$d'" >&2; exit 2; }
done
# The runs start in a scratch folder: the binaries' paths must not be relative.
[ -z "$base_build" ] || base_build="$(cd "$base_build" && pwd)"
[ -z "$head_build" ] || head_build="$(cd "$head_build" && pwd)"

cd "$root"
if [ -z "$base" ]; then
  if upstream="$(git rev-parse --abbrev-ref --symbolic-full-name '@{upstream}' 2>/dev/null)"; then
    base="$(git merge-base HEAD "$upstream")"
  else
    # Where the branch was when this checkout began: its reflog's oldest entry.
    branch="$(git symbolic-ref -q --short HEAD || echo HEAD)"
    base="$(git reflog show --format=%H "$branch" 2>/dev/null | tail -1)"
    base="${base:-HEAD}"
  fi
fi
base_sha="$(git rev-parse --verify --quiet "$base^{commit}")" || { echo "bench_compare: '$base' is not a commit" >&2; exit 2; }
head_label="$(git rev-parse --short HEAD)$(git diff --quiet HEAD -- && echo "" || echo "+changes")"
base_label="$(git rev-parse --short "$base_sha")"

build_tree() {  # SOURCE_DIR BUILD_DIR
  local launcher=()
  if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); export CCACHE_BASEDIR="$root"; fi
  echo "bench_compare: building $1 into $2" >&2
  if [ ! -f "$2/CMakeCache.txt" ]; then
    cmake -S "$1" -B "$2" -G Ninja "${launcher[@]}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="${CXX:-g++}" \
      -DJETRACE_LTO="${JETRACE_LTO:-ON}" -DJETRACE_TESTS=OFF >"$2.configure.log" 2>&1 ||
      { cat "$2.configure.log" >&2; return 1; }
  fi
  cmake --build "$2" -j "$cores" --target jetrace-bench jetrace-sim >"$2.build.log" 2>&1 ||
    { tail -40 "$2.build.log" >&2; return 1; }
}

bench_dir="$root/build-bench"
mkdir -p "$bench_dir"
if [ -z "$base_build" ]; then
  src="$bench_dir/src-$base_label"
  if [ ! -d "$src" ]; then
    git worktree add --detach "$src" "$base_sha" >/dev/null 2>&1 || { echo "bench_compare: cannot check out $base_label" >&2; exit 1; }
  fi
  base_build="$bench_dir/base-$base_label"
  mkdir -p "$base_build"
  build_tree "$src" "$base_build" || { echo "bench_compare: the base build failed" >&2; exit 1; }
fi
if [ -z "$head_build" ]; then
  head_build="$bench_dir/head"
  mkdir -p "$head_build"
  build_tree "$root" "$head_build" || { echo "bench_compare: the working tree's build failed" >&2; exit 1; }
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
out_dir="${keep:-$work}"
mkdir -p "$out_dir"
results="$work/results.tsv"
: >"$results"

run_side() {  # SIDE BUILD_DIR ROUND GROUP COMMAND
  local side="$1" dir="$2" round="$3" group="$4" cmd="$5" log
  log="$out_dir/$group.$side.$round.out"
  cmd="${cmd//\$BENCH/$dir/tools/jetrace-bench}"
  cmd="${cmd//\$SIM/$dir/tools/jetrace-sim}"
  # A build without that benchmark fails here: its figures are then missing.
  if ! (cd "$work" && eval "taskset -c $core $cmd") >"$log" 2>&1; then
    echo "bench_compare: $side ($group) exited non-zero: $cmd (see --keep)" >&2
  fi
  python3 "$figures" extract "$group" "$log" | sed "s/^/$side\t$round\t/" >>"$results"
}

mapfile -t groups < <(python3 "$figures" groups ${smoke:+--smoke})
for ((r = 1; r <= rounds; r++)); do
  echo "bench_compare: round $r of $rounds" >&2
  for line in "${groups[@]}"; do
    group="${line%%$'\t'*}" cmd="${line#*$'\t'}"
    if ((r % 2 == 1)); then order=(A B); else order=(B A); fi
    for side in "${order[@]}"; do
      if [ "$side" = A ]; then run_side A "$base_build" "$r" "$group" "$cmd"; else run_side B "$head_build" "$r" "$group" "$cmd"; fi
    done
  done
done

status=0
python3 "$figures" compare "$results" "$base_label" "$head_label" || status=$?
[ -n "$keep" ] && cp "$results" "$keep/results.tsv"
if [ -n "$smoke" ] && [ "$status" = 3 ]; then status=0; fi
exit "$status"
