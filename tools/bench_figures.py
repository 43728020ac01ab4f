#!/usr/bin/env python3
"""The tracked figures of tools/bench_compare.sh: which command gives each,
how to read it from the command's output, and the comparison of two builds.

  bench_figures.py groups [--smoke]           the commands, one a line: GROUP<TAB>COMMAND
                                              ($BENCH, $SIM stand for the side's binaries)
  bench_figures.py extract GROUP OUTPUT_FILE  the group's figures from one run: NAME<TAB>VALUE lines
  bench_figures.py compare RESULTS_FILE BASE_LABEL HEAD_LABEL
                                              one JSON line per figure, then the summary;
                                              RESULTS_FILE has SIDE<TAB>ROUND<TAB>NAME<TAB>VALUE lines

A figure is a time (lower is better; compared by medians against their
spreads) or exact (wire bytes, state hashes: deterministic, so any
difference is a change). A figure a side cannot produce (an older build
without that benchmark) is reported as new or gone, not compared.
"""
import json
import re
import statistics
import sys

# group: (command, smoke command, [(figure, unit, kind, reader)])
# A reader takes (jsons, text) and returns the value or raises.


def first(js, **match):
    for j in js:
        if all(j.get(k) == v for k, v in match.items()):
            return j
    raise KeyError(f"no JSON line with {match}")


def with_key(js, key):
    for j in js:
        if key in j:
            return j[key]
    raise KeyError(key)


def one_of(j, *keys):
    for k in keys:
        if k in j:
            return j[k]
    raise KeyError(keys[0])


def density_at(js, edge_m):
    for j in js:
        if j.get("benchmark") == "density" and abs(j.get("triangle_edge_m", -1) - edge_m) < 1e-9:
            return j["ns_per_car_step"]
    raise KeyError(f"no density line at {edge_m} m")


def wall_ms(text):
    return float(re.search(r"wall_ms=([0-9.]+)", text).group(1))


def state_hash(text):
    return re.search(r"state_hash=([0-9a-f]{16})", text).group(1)


GROUPS = {
    "step_idle": (
        "$BENCH bullet --scenario idle --jetrace-only --repeats 5",
        "$BENCH bullet --scenario idle --jetrace-only --frames 2000 --repeats 1",
        [("step_idle_ns", "ns per car-step", "time", lambda js, t: first(js, scenario="idle")["jetrace_ns_per_step"])]),
    "step_driving": (
        "$BENCH bullet --scenario driving --jetrace-only --repeats 5",
        "$BENCH bullet --scenario driving --jetrace-only --frames 200 --repeats 1",
        [("step_driving_ns", "ns per car-step", "time",
          lambda js, t: first(js, scenario="driving")["jetrace_ns_per_step"])]),
    "step_thin_wall": (
        "$BENCH bullet --scenario thin_wall --jetrace-only --repeats 3",
        "$BENCH bullet --scenario thin_wall --jetrace-only --quick --repeats 1",
        [("step_thin_wall_ns", "ns per car-step", "time",
          lambda js, t: first(js, scenario="thin_wall")["jetrace_ns_per_step"])]),
    "seed": (
        "$BENCH seed --frames 20000 --repeats 3",
        "$BENCH seed --frames 500 --repeats 1",
        [("parked_car_ns", "ns per frame", "time",
          lambda js, t: one_of(first(js, benchmark="seed"), "parked_grid_on_ns_per_frame", "grid_on_ns_per_frame")),
         ("pushout_grid_on_ns", "ns per frame", "time",
          lambda js, t: first(js, benchmark="seed")["pushout_grid_on_ns_per_frame"]),
         ("pushout_grid_off_ns", "ns per frame", "time",
          lambda js, t: first(js, benchmark="seed")["pushout_grid_off_ns_per_frame"])]),
    "race_8car": (
        "$SIM --track stadium --cars 8 --seconds 60 --seed 7",
        "$SIM --track stadium --cars 8 --seconds 2 --seed 7",
        [("race_8car_ms", "ms (in-process, run_ai)", "time", lambda js, t: wall_ms(t)),
         ("race_8car_state_hash", "state hash", "exact", lambda js, t: state_hash(t))]),
    "density": (
        "$BENCH density --squares 128 1024 --repeats 3",
        "$BENCH density --squares 128 1024 --seconds 0.2 --repeats 1",
        [("density_8m_ns", "ns per car-step", "time", lambda js, t: density_at(js, 8.0)),
         ("density_1m_ns", "ns per car-step", "time", lambda js, t: density_at(js, 1.0))]),
    "track_load": (
        "$BENCH track-load --squares 512 --repeats 5 --obj-repeats 1",
        "$BENCH track-load --squares 32 --repeats 1 --obj-repeats 1",
        [("jtrack_load_ms", "ms", "time", lambda js, t: first(js, benchmark="track-load")["jtrack_load_ms"])]),
    "replay": (
        "$BENCH replay --repeats 3",
        "$BENCH replay --cars 2 --seconds 2 --repeats 1",
        [("replay_verify_ms", "ms", "time", lambda js, t: with_key(js, "verify_ms_median"))]),
    "server": (
        "$BENCH server --bots 64 --seconds 20 --repeats 1",
        "$BENCH server --bots 4 --seconds 2 --repeats 1",
        [("server_tick_us_median", "us per tick", "time", lambda js, t: first(js, benchmark="server")["tick_us_median"]),
         ("server_plain_tick_us_median", "us per tick without snapshots", "time",
          lambda js, t: first(js, benchmark="server")["plain_tick_us_median"]),
         ("server_snapshot_tick_us_median", "us per tick with snapshots", "time",
          lambda js, t: first(js, benchmark="server")["snapshot_tick_us_median"]),
         ("server_tick_us_p99", "us per tick", "time", lambda js, t: first(js, benchmark="server")["tick_us_p99"]),
         ("wire_bytes_down_per_client_s", "bytes per client per s", "exact",
          lambda js, t: first(js, benchmark="server")["bytes_down_per_client_per_s"]),
         ("wire_bytes_up_per_client_s", "bytes per client per s", "exact",
          lambda js, t: first(js, benchmark="server")["bytes_up_per_client_per_s"]),
         ("server_state_hash", "state hash", "exact", lambda js, t: first(js, benchmark="server")["state_hash"])]),
}

# Worse: the head's median over the base's by more than this, beyond the spread.
TOLERANCE = 0.03


def groups(smoke):
    for name, (cmd, smoke_cmd, _) in GROUPS.items():
        print(f"{name}\t{smoke_cmd if smoke else cmd}")


def extract(group, path):
    text = open(path, encoding="utf-8", errors="replace").read()
    js = []
    for line in text.splitlines():
        line = line.strip()
        if line.startswith("{"):
            try:
                js.append(json.loads(line))
            except ValueError:
                pass
    for name, _unit, _kind, read in GROUPS[group][2]:
        try:
            value = read(js, text)
        except (KeyError, IndexError, AttributeError, TypeError, ValueError):
            continue  # this build does not give that figure
        print(f"{name}\t{value}")


def rel_spread(values):
    """Median absolute deviation over the median (0 for one value)."""
    med = statistics.median(values)
    if med == 0 or len(values) < 2:
        return 0.0
    return statistics.median(abs(v - med) for v in values) / abs(med)


def verdict_time(a, b):
    ma, mb = statistics.median(a), statistics.median(b)
    spread = max(rel_spread(a), rel_spread(b))
    ratio = mb / ma if ma else float("inf")
    if ratio > 1 + TOLERANCE + spread:
        v = "worse"
    elif ratio < 1 - TOLERANCE - spread:
        v = "better"
    else:
        v = "same"
    return {"base": ma, "head": mb, "ratio": round(ratio, 4), "base_spread": round(rel_spread(a), 4),
            "head_spread": round(rel_spread(b), 4), "verdict": v}


def verdict_exact(a, b):
    same = len(set(a)) == 1 and set(a) == set(b)
    out = {"base": a[0], "head": b[0], "verdict": "same" if same else "changed"}
    if len(set(a)) > 1 or len(set(b)) > 1:
        out["unsteady"] = True  # differs between rounds of one build: not deterministic
        out["verdict"] = "changed"
    return out


def parse_value(kind, s):
    if kind == "exact":
        try:
            return float(s) if re.fullmatch(r"-?[0-9.]+(e[+-]?[0-9]+)?", s) else s
        except ValueError:
            return s
    return float(s)


def compare(path, base_label, head_label):
    runs = {}
    for line in open(path, encoding="utf-8"):
        parts = line.rstrip("\n").split("\t")
        if len(parts) == 4:
            side, _round, name, value = parts
            runs.setdefault(name, {"A": [], "B": []})[side].append(value)
    summary = {"summary": True, "base": base_label, "head": head_label, "tolerance": TOLERANCE,
               "worse": [], "better": [], "changed": [], "new": [], "gone": [], "same": []}
    for _group, (_c, _s, figures) in GROUPS.items():
        for name, unit, kind, _read in figures:
            r = runs.get(name, {"A": [], "B": []})
            a = [parse_value(kind, v) for v in r["A"]]
            b = [parse_value(kind, v) for v in r["B"]]
            line = {"figure": name, "unit": unit, "kind": kind, "base_runs": a, "head_runs": b}
            if not a and not b:
                line["verdict"] = "missing"
            elif not a:
                line.update({"head": b[0] if kind == "exact" else statistics.median(b), "verdict": "new"})
            elif not b:
                line.update({"base": a[0] if kind == "exact" else statistics.median(a), "verdict": "gone"})
            else:
                line.update(verdict_exact(a, b) if kind == "exact" else verdict_time(a, b))
            summary.setdefault(line["verdict"], []).append(name)
            print(json.dumps(line))
    print(json.dumps(summary))
    bad = summary["worse"] + summary["changed"]
    msg = "worse or changed: " + ", ".join(bad) if bad else "no figure is worse"
    print(f"bench_compare: {msg} (head {head_label} against base {base_label}; "
          f"{len(summary['same'])} same, {len(summary['better'])} better, "
          f"{len(summary['new'])} new, {len(summary['gone'])} gone, {len(summary.get('missing', []))} missing)",
          file=sys.stderr)
    return 3 if bad else 0


def main(argv):
    if len(argv) >= 2 and argv[1] == "groups":
        groups("--smoke" in argv[2:])
        return 0
    if len(argv) == 4 and argv[1] == "extract" and argv[2] in GROUPS:
        extract(argv[2], argv[3])
        return 0
    if len(argv) == 5 and argv[1] == "compare":
        return compare(argv[2], argv[3], argv[4])
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
