#!/usr/bin/env python3
"""The driving AI over many skill seeds on every track: finishes, respawns
a car, mean lap and the spread of finish times, from jetrace-sim's offline
races (8 cars, 1 lap, 300 s each).

  tools/ai_table.py [--sim build/tools/jetrace-sim] [--base OTHER_SIM]
                    [--seeds 12] [--track T ...] [--jobs 2]

Prints one JSON line per track (and per build, with --base) and then a
Markdown table; with --base each figure of the table has the base build's
in brackets.
"""
import argparse
import concurrent.futures
import json
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TRACKS = ["ring", "stadium", "docs/tracks/truck_town.track.json", "docs/tracks/zdm2.track.json",
          "docs/tracks/fdm6.track.json", "docs/tracks/pandora.track.json", "docs/tracks/dutility.track.json"]
ROW = re.compile(r"^\s*(\d+)\s+(\d+)\s+(\w+)\s+(\d+)\s+(\S+)\s+(\d+)\s+(\S+)\s*$")


def race(sim, track, seed, cars):
    cmd = [sim, "--track", track, "--cars", str(cars), "--laps", "1", "--seconds", "300", "--seed", str(seed)]
    out = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit(f"ai_table: {' '.join(cmd)} exited {out.returncode}: {out.stderr.strip()}")
    cars_out = []
    for line in out.stdout.splitlines():
        m = ROW.match(line)
        if m:
            cars_out.append({"finished": m.group(3) == "finished", "respawns": int(m.group(6)),
                             "time_s": float(m.group(7)) if m.group(3) == "finished" else None})
    if len(cars_out) != cars:
        raise SystemExit(f"ai_table: {' '.join(cmd)} printed {len(cars_out)} cars, not {cars}")
    return cars_out


def summary(sim, track, seeds, cars, jobs):
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        runs = list(pool.map(lambda s: race(sim, track, s, cars), range(1, seeds + 1)))
    every = [c for r in runs for c in r]
    times = sorted(c["time_s"] for c in every if c["finished"])
    return {"track": os.path.basename(track).split(".")[0], "sim": sim, "seeds": seeds, "cars": len(every),
            "finished": len(times), "all_finished_seeds": sum(all(c["finished"] for c in r) for r in runs),
            "respawns_per_car": round(sum(c["respawns"] for c in every) / len(every), 3),
            "mean_lap_s": round(sum(times) / len(times), 2) if times else None,
            "first_s": times[0] if times else None, "last_s": times[-1] if times else None}


def cell(head, base, key, fmt):
    text = fmt(head[key])
    return f"{text} ({fmt(base[key])})" if base is not None else text


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sim", default="build/tools/jetrace-sim")
    ap.add_argument("--base", help="another jetrace-sim: its figures in brackets")
    ap.add_argument("--seeds", type=int, default=12, help="skill seeds 1..N (1..1000)")
    ap.add_argument("--cars", type=int, default=8, help="cars a race (1..64)")
    ap.add_argument("--track", action="append", help="a track (default: the built-in and docs/tracks levels)")
    ap.add_argument("--jobs", type=int, default=2, help="races at once (1..64)")
    a = ap.parse_args()
    if not 1 <= a.seeds <= 1000 or not 1 <= a.cars <= 64 or not 1 <= a.jobs <= 64:
        ap.error("--seeds must be 1..1000, --cars 1..64, --jobs 1..64")
    for sim in [a.sim] + ([a.base] if a.base else []):
        if not os.access(os.path.join(ROOT, sim), os.X_OK):
            ap.error(f"no jetrace-sim at {sim}")
    rows = []
    for track in a.track or TRACKS:
        head = summary(a.sim, track, a.seeds, a.cars, a.jobs)
        base = summary(a.base, track, a.seeds, a.cars, a.jobs) if a.base else None
        for r in [head] + ([base] if base else []):
            print(json.dumps(r), flush=True)
        rows.append((head, base))
    print()
    print("| track | finished | respawns a car | mean lap | first to last finisher |")
    print("| --- | --- | --- | --- | --- |")
    for head, base in rows:
        spread = f"{head['first_s']:.1f} to {head['last_s']:.1f} s" if head["finished"] else "-"
        n = head["cars"]
        print(f"| `{head['track']}` | {cell(head, base, 'finished', lambda v: f'{v}/{n}')} | "
              f"{cell(head, base, 'respawns_per_car', lambda v: f'{v:.2f}')} | "
              f"{cell(head, base, 'mean_lap_s', lambda v: '-' if v is None else f'{v:.1f} s')} | {spread} |")


if __name__ == "__main__":
    sys.exit(main())
