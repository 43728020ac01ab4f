#!/usr/bin/env python3
"""What TCP costs a racer under loss: native ENet, the WebRTC data channel
and a WebSocket side by side (docs/PERFORMANCE.md, "Browser transports
under loss").

For each loss rate and transport it races CARS cars one race of ring on
127.0.0.1, every link at LATENCY ms one way and that loss in both
directions:
  enet       CARS jetrace-bot drivers through jetrace-netsim;
  webrtc     CARS-1 bots through jetrace-netsim and one player in the game
             page (headless Chromium, race_page.mjs) over the data channel,
             conditioned inside the server (jetrace-server --web-link);
  websocket  the same, the page over its WebSocket (one TCP stream: a lost
             segment holds back everything after it until it is resent).
Every driver has no input delay (jetrace-bot --input-delay 0, as the page):
its own inputs reach the others only through the server. It measures the
players it can see: all the bots for enet, the page for the browser
transports:
  corrections per minute of racing, the largest correction (m), and the
  input-to-server delay at p50 and p99 (ms: from the first datagram carrying
  an input tick reaching the link to the first one handed on with it;
  jetrace-netsim's and --web-link's meters).
Writes DIR/data/transports.csv, DIR/transports.svg (gnuplot) and prints one
JSON line per run.

Usage: tools/transports/transport_chart.py [--losses 0,1,2,5,10] [--latency 50]
       [--cars 8] [--laps 1] [--repeats 1] [--seed 1] [--build build] [--out docs/charts] [--logs DIR]
       tools/transports/transport_chart.py --csv A.csv [--csv B.csv] [--out DIR]   (draw again from runs' CSV)
"""
import argparse
import csv
import json
import math
import os
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TRANSPORTS = ("enet", "webrtc", "websocket")


def wait_port(log, pattern, proc, what):
    for _ in range(600):
        with open(log) as f:
            m = re.search(pattern, f.read(), re.M)
        if m:
            return int(m.group(1))
        if proc.poll() is not None:
            break
        time.sleep(0.05)
    sys.exit(f"transport_chart: {what} printed no port:\n" + open(log).read())


def json_lines(path):
    out = []
    for line in open(path):
        line = line.strip()
        if line.startswith("{"):
            try:
                out.append(json.loads(line))
            except json.JSONDecodeError:
                pass
    return out


def run_one(a, transport, loss, seed, work):
    build = os.path.join(ROOT, a.build)
    server, bot, netsim = (os.path.join(build, p) for p in ("server/jetrace-server", "client/jetrace-bot",
                                                            "tools/jetrace-netsim"))
    results = os.path.join(work, "results.json")
    # The server and the proxy run ahead of the clients (nice -5, as root):
    # on 2 cores shared with Chromium and the bots their stalls would be
    # measured as network delay.
    boost = ["nice", "-n", "-5"] if os.geteuid() == 0 else []
    cmd = boost + [server, "--bind", "127.0.0.1", "--port", "0", "--track", "ring", "--laps", str(a.laps),
           "--min-players", str(a.cars), "--max-players", str(a.cars), "--races", "1", "--countdown", "3",
           "--lobby-timeout", "120", "--finish-window", "60", "--results", results]
    browser = transport != "enet"
    if browser:
        cmd += ["--web", "127.0.0.1:0", "--web-link", f"latency={a.latency},loss={loss / 100}"]
    slog = os.path.join(work, "server.log")
    procs = []
    try:
        sp = subprocess.Popen(cmd, stdout=open(slog, "w"), stderr=subprocess.STDOUT)
        procs.append(sp)
        port = wait_port(slog, r"^listening on .*:(\d+)$", sp, "jetrace-server")
        nlog = os.path.join(work, "netsim.log")
        np_ = subprocess.Popen(boost + [netsim, "--listen", "0", "--forward", f"127.0.0.1:{port}", "--latency",
                                str(a.latency), "--loss", str(loss / 100), "--seed", str(seed)],
                               stdout=open(nlog, "w"), stderr=subprocess.STDOUT)
        procs.append(np_)
        proxy = wait_port(nlog, r"^listening on .*:(\d+)$", np_, "jetrace-netsim")
        bots = a.cars - (1 if browser else 0)
        blog = os.path.join(work, "bots.json")
        bp = subprocess.Popen([bot, "--connect", f"127.0.0.1:{proxy}", "--count", str(bots), "--name", "robot",
                               "--input-delay", "0", "--max-seconds", "300"], stdout=open(blog, "w"), stderr=subprocess.DEVNULL)
        procs.append(bp)
        page = None
        if browser:
            web = wait_port(slog, r"^web on .*:(\d+) \(", sp, "jetrace-server --web")
            out = subprocess.run(["node", os.path.join(ROOT, "tools/transports/race_page.mjs"),
                                  f"http://127.0.0.1:{web}/", transport, "page"],
                                 capture_output=True, text=True, timeout=600)
            lines = [json.loads(l) for l in out.stdout.splitlines() if l.startswith("{")]
            if not lines:
                sys.exit(f"transport_chart: the page did not race ({transport}, {loss} %):\n{out.stdout}\n{out.stderr}")
            page = lines[-1]
        sp.wait(timeout=600)
        bp.wait(timeout=60)
        np_.send_signal(signal.SIGTERM)
        np_.wait(timeout=30)
    finally:
        for p in procs:
            if p.poll() is None:
                p.kill()
                p.wait()
    standings = {s["name"]: s for s in json.load(open(results))["standings"]}
    if browser:
        link = [j for j in json_lines(slog) if "web_link" in j][-1]["web_link"][transport]
        delay = link["input_delay_ms"]
        t = standings["page"]["time_s"]
        players = [(page["net"]["corrections"], page["net"]["max_correction_m"], t, standings["page"]["finished"])]
    else:
        delay = [j for j in json_lines(nlog) if "up" in j][-1]["up"]["input_delay_ms"]
        players = [(b["corrections"], b["max_correction_m"], standings[b["name"]]["time_s"],
                    standings[b["name"]]["finished"]) for b in json_lines(blog) if "corrections" in b]
    per_min = [c / (t / 60) for c, _, t, fin in players if fin and t > 0]
    return {
        "transport": transport, "loss_percent": loss, "latency_ms": a.latency, "cars": a.cars, "seed": seed,
        "players_measured": len(players), "finished": sum(1 for p in players if p[3]),
        "corrections_per_min": round(statistics.mean(per_min), 2) if per_min else float("nan"),
        "largest_correction_m": round(max(p[1] for p in players), 3),
        "input_delay_p50_ms": round(delay["p50"], 1), "input_delay_p99_ms": round(delay["p99"], 1),
        "input_delay_n": delay["n"],
    }


def plot(rows, out):
    data = os.path.join(out, "data", "transports.csv")
    keys = list(rows[0].keys())
    os.makedirs(os.path.dirname(data), exist_ok=True)
    with open(data, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    if not shutil.which("gnuplot"):
        print("transport_chart: no gnuplot (apt-get install gnuplot-nox): CSV only", file=sys.stderr)
        return
    # One table a transport: the medians over repeats at each loss.
    tables = {}
    for t in TRANSPORTS:
        path = os.path.join(tempfile.gettempdir(), f"transports_{t}.dat")
        with open(path, "w") as f:
            for loss in sorted({r["loss_percent"] for r in rows}):
                rs = [r for r in rows if r["transport"] == t and r["loss_percent"] == loss]
                if not rs:
                    continue
                med = lambda k: statistics.median(r[k] for r in rs)
                f.write(f"{loss} {med('corrections_per_min')} {med('largest_correction_m')} "
                        f"{med('input_delay_p50_ms')} {med('input_delay_p99_ms')}\n")
        tables[t] = path
    panels = [(2, "corrections per minute"), (3, "largest correction (m)"), (4, "input delay p50 (ms)"),
              (5, "input delay p99 (ms)")]
    latency = rows[0]["latency_ms"]
    cars = rows[0]["cars"]
    script = [f"set terminal svg size 960,720 font 'sans,12' background '#ffffff'",
              f"set output '{os.path.join(out, 'transports.svg')}'",
              f"set multiplot layout 2,2 title '{cars:g} cars, {latency:g} ms one way, loss both ways (medians)'",
              "set key top left", "set grid", "set xlabel 'loss (%)'"]
    styles = {"enet": "lc rgb '#1b9e77' pt 7", "webrtc": "lc rgb '#7570b3' pt 5", "websocket": "lc rgb '#d95f02' pt 9"}
    names = {"enet": "ENet (bots)", "webrtc": "WebRTC data channel (page)", "websocket": "WebSocket (page)"}
    for col, title in panels:
        script.append(f"set title '{title}'")
        script.append("plot " + ", ".join(f"'{tables[t]}' using 1:{col} with linespoints {styles[t]} title '{names[t]}'"
                                            for t in TRANSPORTS if t in tables))
    script.append("unset multiplot")
    subprocess.run(["gnuplot"], input="\n".join(script), text=True, check=True)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--losses", default="0,1,2,5,10", help="loss rates (%%), comma separated")
    p.add_argument("--latency", type=float, default=50, help="one-way delay (ms)")
    p.add_argument("--cars", type=int, default=8)
    p.add_argument("--laps", type=int, default=1)
    p.add_argument("--repeats", type=int, default=1, help="races per transport and loss (the chart: medians)")
    p.add_argument("--seed", type=int, default=1, help="jetrace-netsim's seed (repeat r uses seed + r)")
    p.add_argument("--transports", default=",".join(TRANSPORTS))
    p.add_argument("--build", default="build")
    p.add_argument("--out", default="docs/charts")
    p.add_argument("--logs", default="", help="keep each run's logs in DIR/TRANSPORT_LOSS_REPEAT")
    p.add_argument("--csv", action="append", default=[],
                   help="draw from this CSV of earlier runs (repeatable: their rows are pooled) instead of racing")
    a = p.parse_args()
    try:
        losses = [float(x) for x in a.losses.split(",")]
    except ValueError:
        p.error(f"--losses must be numbers, got {a.losses!r}")
    if any(not math.isfinite(x) or x < 0 or x > 100 for x in losses):
        p.error("--losses must be in [0, 100]")
    if not (math.isfinite(a.latency) and 0 <= a.latency <= 1000):
        p.error("--latency must be in [0, 1000]")
    if not 2 <= a.cars <= 16 or not 1 <= a.laps <= 10 or not 1 <= a.repeats <= 20:
        p.error("--cars 2..16, --laps 1..10, --repeats 1..20")
    out = os.path.join(ROOT, a.out) if not os.path.isabs(a.out) else a.out
    if a.csv:
        rows = []
        for path in a.csv:
            with open(path) as f:
                for r in csv.DictReader(f):
                    rows.append({k: (v if k == "transport" else float(v)) for k, v in r.items()})
        plot(rows, out)
        return
    transports = a.transports.split(",")
    if any(t not in TRANSPORTS for t in transports):
        p.error(f"--transports: {TRANSPORTS}")
    rows = []
    for loss in losses:
        for t in transports:
            for r in range(a.repeats):
                if a.logs:
                    work = os.path.join(a.logs, f"{t}_{loss:g}_{r}")
                    os.makedirs(work, exist_ok=True)
                    row = run_one(a, t, loss, a.seed + r, work)
                else:
                    with tempfile.TemporaryDirectory() as work:
                        row = run_one(a, t, loss, a.seed + r, work)
                print(json.dumps(row), flush=True)
                rows.append(row)
    plot(rows, out)


if __name__ == "__main__":
    main()
