#!/usr/bin/env bash
# Checks the rules of shared/'s libraries (CTest: shared_layout):
#   - which library's headers each folder may include:
#       core/    jetrace/core only
#       ai/      jetrace/core and jetrace/ai
#       tracks/  jetrace/core and jetrace/tracks
#       replay/  jetrace/core, jetrace/ai and jetrace/replay
#   - core/ and ai/ (what steps a race, in every client and the WebAssembly
#     build) use no file, stream, clock, thread or environment API, and core/
#     no third-party header but Eigen's.
# Prints every breach with its file and line; exits 1 if there is one.
# Usage: tools/check_layout.sh [SOURCE_DIR]
set -euo pipefail
root="${1:-$(cd "$(dirname "$0")/.." && pwd)}"
shared="$root/shared"
[ -d "$shared/core" ] || { echo "check_layout: no $shared/core" >&2; exit 2; }
status=0

breach() {  # folder, what, grep output
  [ -z "$3" ] && return
  echo "shared/$1: $2:"
  echo "$3" | sed "s|^$root/||; s|^|  |"
  status=1
}

sources() { find "$shared/$1" -type f \( -name '*.cpp' -o -name '*.hpp' -o -name '*.inl' \) | sort; }

# A library's own headers and the ones below it in the dependency order.
check_includes() {  # folder, allowed libraries (regex alternatives)
  local found
  found="$(sources "$1" | xargs grep -nE '#include +"jetrace/' | grep -vE "#include +\"jetrace/($2)/" || true)"
  breach "$1" "includes a header of a library it may not use (allowed: $2)" "$found"
}
check_includes core 'core'
check_includes ai 'core|ai'
check_includes tracks 'core|tracks'
check_includes replay 'core|ai|replay'

# No I/O, clocks, threads or environment in the step or the AI.
io_headers='fstream|iostream|istream|ostream|filesystem|chrono|thread|mutex|future|condition_variable|ctime|unistd\.h|fcntl\.h|sys/[a-z_]+\.h'
io_calls='\b(fopen|freopen|fread|fwrite|fclose|getenv|system|time|clock|printf|puts|rand|srand)\(|std::(chrono|this_thread|thread|cout|cerr|clog|random_device)\b'
for lib in core ai; do
  found="$(sources "$lib" | xargs grep -nE "#include +<($io_headers)>" || true)"
  breach "$lib" "includes a file, stream, clock or thread header" "$found"
  # Comments are not code: drop // comments before looking for calls.
  found="$(sources "$lib" | xargs grep -nE "$io_calls" | grep -vE '^[^:]+:[0-9]+: *//' || true)"
  breach "$lib" "calls a file, stream, clock, thread or environment API" "$found"
done
# The AI draws its drivers' skills from a seeded std::mt19937_64 (a fixed
# sequence; std::random_device is refused above); the step draws nothing.
found="$(sources core | xargs grep -nE '#include +<random>' || true)"
breach core "includes <random>" "$found"
found="$(sources core | xargs grep -nE '#include +<[^>]*/' | grep -vE '#include +<Eigen/' || true)"
breach core "includes a third-party header other than Eigen's" "$found"

if [ "$status" = 0 ]; then echo "check_layout: shared/ core, ai, tracks and replay keep their rules"; fi
exit "$status"
