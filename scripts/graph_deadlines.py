#!/usr/bin/python3
"""How many deadlines a shipped graph misses on this machine.

usage: graph_deadlines.py [--runs N] [--duration S] [--enact PATH] [LAUNCH_FILE] [-- --arg NAME=VALUE ...]

Runs `enact launch LAUNCH_FILE --duration S` N times (default: launch/bridge.yaml, 3 runs
of 10 s, no other argument: the measurement in docs/performance.md), reads the loop's last report of each
run (the FFD driver's, or the co-located container's: its verdict, deadlines missed, tick
latency percentiles, watchdog episodes) and prints each run and the median of the runs, with
the machine: its CPU, load, and the probe's floor (how late a sleeping thread wakes, the pipe
round trip on one CPU) as the launcher said it. Exit status 1 when a run fails or prints no
report. Arguments after `--` go to enact launch.
"""
import argparse
import os
import re
import shutil
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# the loop's last lines (nodes/enact-ffd/main.cpp, nodes/enact-rt/main.cpp, core/rt/loop_stats.cpp,
# core/graph/watchdog_log.cpp)
LATENCY = re.compile(r"^(ffd|rt): \d+ Hz loop: (\d+) ticks, (\d+) overruns\..*?Tick latency p50 ([\d.]+) us, p99 ([\d.]+) us", re.M)
VERDICT = re.compile(r"^(ffd|rt): verdict: (this machine (?:held|did NOT hold) [\d.]+ Hz: (\d+) of (\d+) deadlines missed.*)$", re.M)
STALE = re.compile(r"late answers: (\d+)")
PROFILE = re.compile(r"^enact launch: (real-time profile: .*)$", re.M)
FLOOR = re.compile(r"^enact launch: (this machine wakes .*?): enact doctor", re.M)


def default_enact():
    """the build's enact beside this script's tree, else (installed) the enact on PATH"""
    built = os.path.join(os.environ.get("ENACT_BUILD_DIR", os.path.join(ROOT, "build")), "nodes/enact/enact")
    return built if os.path.exists(built) else shutil.which("enact") or built


def one_run(enact, launch_file, duration, extra):
    cmd = [enact, "launch", launch_file, "--duration", str(duration)] + extra
    # from where the user stands: enact finds the shipped launch files itself (enact share)
    done = subprocess.run(cmd, capture_output=True, text=True)
    out = done.stderr + done.stdout
    lat, verdict = LATENCY.search(out), VERDICT.search(out)
    if done.returncode != 0 or not lat or not verdict:
        sys.stderr.write(out)
        raise SystemExit(f"graph_deadlines.py: {' '.join(cmd)} failed (exit {done.returncode}) or printed no loop report")
    stale = STALE.search(out)
    profile, floor = PROFILE.search(out), FLOOR.search(out)
    return {"ticks": int(verdict.group(4)), "overruns": int(lat.group(3)), "p50_us": float(lat.group(4)), "p99_us": float(lat.group(5)),
            "missed": int(verdict.group(3)), "late": int(stale.group(1)) if stale else 0, "verdict": verdict.group(2),
            "profile": profile.group(1) if profile else "(none)", "floor": floor.group(1) if floor else "(not said)"}


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def main():
    argv = sys.argv[1:]
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    argv = argv[:argv.index("--")] if "--" in argv else argv
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("launch_file", nargs="?", default="launch/bridge.yaml")
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--duration", type=float, default=10.0)
    p.add_argument("--enact", default=default_enact())
    a = p.parse_args(argv)
    if a.runs < 1 or a.duration <= 0:
        p.error("--runs must be >= 1 and --duration > 0")
    with open("/proc/loadavg") as f:
        load = " ".join(f.read().split()[:3])
    print(f"machine: {os.cpu_count()} CPUs ({cpu_model()}), load average {load} before the runs")
    runs = []
    for i in range(a.runs):
        r = one_run(a.enact, a.launch_file, a.duration, extra)
        runs.append(r)
        print(f"run {i + 1}: {r['verdict']}; late answers {r['late']}; tick (sample-to-force) p50 {r['p50_us']:.1f} us, p99 {r['p99_us']:.1f} us",
              flush=True)
    print(runs[0]["profile"])
    print(runs[0]["floor"])
    med = statistics.median(100.0 * r["missed"] / max(1, r["ticks"]) for r in runs)
    p99 = statistics.median(r["p99_us"] for r in runs)
    p50 = statistics.median(r["p50_us"] for r in runs)
    spread = ", ".join(f"{100.0 * r['missed'] / max(1, r['ticks']):.3f}" for r in runs)
    print(f"median of {a.runs} runs: {med:.3f} % of deadlines missed (runs: {spread} %), tick p50 {p50:.1f} us, p99 {p99:.1f} us")


if __name__ == "__main__":
    main()
