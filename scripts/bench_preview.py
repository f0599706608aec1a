#!/usr/bin/env python3
"""How much the live preview slows a render: `nori --preview` watched by a client that
fetches what the page fetches (/status every 250 ms, the beauty's float data after every
published pass), against the same render without --preview. Two measures:
  - wall time with and without, runs alternating so that drift of the machine's speed hits
    both alike (medians; on a shared VM the spread of single runs is several percent);
  - the cost nori reports itself under --preview: the time all workers wait while a pass
    is developed plus the CPU time of the server's threads, as a share of the render's
    CPU time (threads × seconds). This one is not blurred by the machine's noise.

Usage: scripts/bench_preview.py [--nori build/nori] [--scene scenes/cbox/cbox.xml]
                                [--spp 64] [--runs 5] [--threads N]
"""
import argparse
import json
import os
import re
import socket
import statistics
import subprocess
import tempfile
import threading
import time
import urllib.request

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--nori", default="build/nori")
parser.add_argument("--scene", default="scenes/cbox/cbox.xml")
parser.add_argument("--spp", type=int, default=64)
parser.add_argument("--runs", type=int, default=5)
parser.add_argument("--threads", type=int, default=0, help="0: all cores")
args = parser.parse_args()


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def watch(url, done, counts):
    """Fetches what the page does until `done` is set."""
    shown = 0
    while not done.is_set():
        try:
            with urllib.request.urlopen(url + "status", timeout=5) as response:
                status = json.load(response)
            counts["status"] += 1
            if status["frame"] > shown:
                with urllib.request.urlopen(url + "image?layer=", timeout=5) as response:
                    counts["bytes"] += len(response.read())
                counts["images"] += 1
                shown = status["frame"]
        except OSError:
            pass  # not serving yet, or already gone
        time.sleep(0.25)


def render(preview, output):
    """Wall seconds of the whole nori process (nori prints its render time to 0.1 s only,
    too coarse here) and the client's request counts."""
    command = [args.nori, "--no-progress", "--spp", str(args.spp), "-D", "integrator=path_mis",
               "-o", output, args.scene]
    if args.threads:
        command += ["--threads", str(args.threads)]
    counts = {"status": 0, "images": 0, "bytes": 0}
    done = threading.Event()
    watcher = None
    if preview:
        port = free_port()
        command += ["--preview", str(port)]
        watcher = threading.Thread(target=watch, args=(f"http://127.0.0.1:{port}/", done, counts))
        watcher.start()
    start = time.perf_counter()
    result = subprocess.run(command, capture_output=True, text=True, check=True)
    seconds = time.perf_counter() - start
    # "Preview: developing 7 of 7 passes took 34 ms, the server used 12 ms of CPU: 0.28% of ..."
    cost = re.search(r"Preview: developing .* CPU: ([0-9.]+)% of", result.stderr)
    counts["cost"] = float(cost.group(1)) if cost else None
    done.set()
    if watcher:
        watcher.join()
    return seconds, counts


with tempfile.TemporaryDirectory() as folder:
    output = os.path.join(folder, "bench")
    render(False, output)  # warm the caches (files, page cache)
    plain, watched, costs = [], [], []
    for run in range(args.runs):
        seconds, _ = render(False, output)
        plain.append(seconds)
        seconds_preview, counts = render(True, output)
        watched.append(seconds_preview)
        costs.append(counts["cost"])
        print(f"run {run + 1}: without {seconds:.3f} s, with --preview {seconds_preview:.3f} s "
              f"({counts['status']} status, {counts['images']} images, "
              f"{counts['bytes'] / 1e6:.1f} MB fetched; cost reported by nori "
              f"{counts['cost']:.2f}%)", flush=True)
median_plain, median_watched = statistics.median(plain), statistics.median(watched)
print(f"{args.scene} at {args.spp} spp, {args.runs} runs each: median {median_plain:.3f} s "
      f"without, {median_watched:.3f} s with --preview and a watching client: overhead "
      f"{100 * (median_watched / median_plain - 1):+.2f}% (goal: at most 2%)")
print(f"cost reported by nori (develop wait × threads + server CPU) / render CPU: median "
      f"{statistics.median(costs):.2f}%, largest {max(costs):.2f}% (goal: at most 2%)")
print(f"spread without: {min(plain):.3f}-{max(plain):.3f} s; with: "
      f"{min(watched):.3f}-{max(watched):.3f} s")
