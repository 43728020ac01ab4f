#!/usr/bin/env bash
# The main job: set-up, build, then an offline race of 8 AI cars over 3 laps
# of the seed's `stadium` track on the shared deterministic core, followed by
# the seed's benchmark. (The networked race on loopback replaces the offline
# one once the server and bots exist.)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/tools/setup.sh"
"$root/tools/build.sh" >/dev/null
"$root/build/tools/jetrace-sim" --track stadium --cars 8 --laps 3 --seconds 330 --seed 1
"$root/build/tools/jetrace-bench" seed
