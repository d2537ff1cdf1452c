#!/usr/bin/python3
"""How many 5 kHz samples the shipped distributed graph leaves unanswered.

usage: graph_deadlines.py [--runs N] [--duration S] [--enact PATH] [LAUNCH_FILE] [-- --arg NAME=VALUE ...]

Runs `enact launch LAUNCH_FILE --duration S` N times (default: launch/bridge.yaml, 3 runs
of 10 s, no other argument: the README's measurement), reads the FFD driver's last report
of each run (samples without an answer in time, sample-to-force percentiles, missed
deadlines) and prints each run and the median of the runs, with the machine's load.
Exit status 1 when a run fails or prints no report. Arguments after `--` go to enact launch.
"""
import argparse
import os
import re
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# the FFD driver's last lines (nodes/enact-ffd/main.cpp, core/rt/loop_stats.cpp)
TICKS = re.compile(r"^ffd: .*?(\d+) ticks, (\d+) overruns\..*?Tick latency p50 ([\d.]+) us, p99 ([\d.]+) us.*?"
                   r"Samples without an answer in time: (\d+), late answers: (\d+)", re.M)
PROFILE = re.compile(r"^enact launch: (real-time profile: .*)$", re.M)


def one_run(enact, launch_file, duration, extra):
    cmd = [enact, "launch", launch_file, "--duration", str(duration)] + extra
    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    m = TICKS.search(done.stderr)
    if done.returncode != 0 or not m:
        sys.stderr.write(done.stderr)
        raise SystemExit(f"graph_deadlines.py: {' '.join(cmd)} failed (exit {done.returncode}) or printed no FFD report")
    ticks, overruns, p50, p99, missing, late = m.groups()
    profile = PROFILE.search(done.stderr)
    return {"ticks": int(ticks), "overruns": int(overruns), "p50_us": float(p50), "p99_us": float(p99),
            "unanswered": int(missing), "late": int(late), "profile": profile.group(1) if profile else "(none)"}


def main():
    argv = sys.argv[1:]
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    argv = argv[:argv.index("--")] if "--" in argv else argv
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("launch_file", nargs="?", default="launch/bridge.yaml")
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--duration", type=float, default=10.0)
    p.add_argument("--enact", default=os.path.join(os.environ.get("ENACT_BUILD_DIR", os.path.join(ROOT, "build")), "nodes/enact/enact"))
    a = p.parse_args(argv)
    if a.runs < 1 or a.duration <= 0:
        p.error("--runs must be >= 1 and --duration > 0")
    with open("/proc/loadavg") as f:
        load = " ".join(f.read().split()[:3])
    print(f"machine: {os.cpu_count()} CPUs, load average {load} before the runs")
    runs = []
    for i in range(a.runs):
        r = one_run(a.enact, a.launch_file, a.duration, extra)
        runs.append(r)
        frac = 100.0 * r["unanswered"] / max(1, r["ticks"])
        print(f"run {i + 1}: {r['unanswered']} of {r['ticks']} samples unanswered ({frac:.3f} %), late answers {r['late']}, "
              f"missed deadlines {r['overruns']}; sample-to-force p50 {r['p50_us']:.1f} us, p99 {r['p99_us']:.1f} us", flush=True)
    print(runs[0]["profile"])
    med = statistics.median(100.0 * r["unanswered"] / max(1, r["ticks"]) for r in runs)
    p99 = statistics.median(r["p99_us"] for r in runs)
    p50 = statistics.median(r["p50_us"] for r in runs)
    print(f"median of {a.runs} runs: {med:.3f} % unanswered (goal <= 0.05 %), sample-to-force p50 {p50:.1f} us, p99 {p99:.1f} us (goal < 100 us)")


if __name__ == "__main__":
    main()
