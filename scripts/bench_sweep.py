#!/usr/bin/python3
"""What the executors of `enact sweep` cost, side by side in one run.

usage: bench_sweep.py ENACT [--experiment FILE] [--replicates N] [--rounds R]
                            [--arms local1,local2,slurm,dask[,dask_shared]] [--json FILE]

One sweep (docs/experiments.md, "Sweeps"): the experiment (default the paper's 48-trial
protocol, launch/experiments/bridge.yaml) in simulated time, N replicates (default 2) of one
grid point: N jobs. It runs on each arm, R rounds (default 3), the arms' order turned each
round so none always runs first:

  local1  --executor local --jobs 1   (one worker: the baseline)
  local2  --executor local --jobs 2   (two workers)
  slurm   a single-node Slurm here (scripts/slurm_local.sh, needs root), 2 tasks at once
  dask    a Dask scheduler and two one-thread workers on 127.0.0.1 (Debian's python3-distributed),
          the files by content (the jobs' folders come back through Dask)
  dask_shared  the same workers with --dask-files shared (the folders written in place)

and prints each arm's wall time (median, min..max), the speed-up of two local workers over one
(local1 / local2) and each executor's own cost: its time over local2's, less one (the jobs are
the same; what is left is submission, transfer, polling and merge). Every arm's merged
results.csv must be byte-identical. The engines are started here and stopped at the end.
Nothing else should run meanwhile: the figures are this machine's (its CPUs are printed).
"""
import argparse
import hashlib
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import local_dask  # noqa: E402  (beside this script)


def cpu_name():
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def spread(values):
    return statistics.median(values), min(values), max(values)


def text(values, fmt="%.1f"):
    m, lo, hi = spread(values)
    return f"{fmt % m} ({fmt % lo}..{fmt % hi})"


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("enact", help="the enact executable (build/nodes/enact/enact)")
    p.add_argument("--experiment", default=os.path.join(ROOT, "launch", "experiments", "bridge.yaml"))
    p.add_argument("--replicates", type=int, default=2, help="jobs of the sweep (default 2)")
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--arms", default="local1,local2,slurm,dask")
    p.add_argument("--json", help="write the figures here too")
    a = p.parse_args()
    enact = os.path.abspath(a.enact)
    if not os.access(enact, os.X_OK):
        sys.exit(f"bench_sweep: {a.enact} is not an executable\n  fix: give the enact executable (scripts/build.sh builds build/nodes/enact/enact)")
    if not os.path.isfile(a.experiment):
        sys.exit(f"bench_sweep: no experiment file {a.experiment}")
    if a.replicates < 1 or a.rounds < 1:
        sys.exit("bench_sweep: --replicates and --rounds need a whole number >= 1")
    arms = a.arms.split(",")
    unknown = [x for x in arms if x not in ("local1", "local2", "slurm", "dask", "dask_shared")]
    if unknown:
        sys.exit(f"bench_sweep: unknown arm {unknown[0]}\n  fix: --arms from local1, local2, slurm, dask, dask_shared")
    if "slurm" in arms and os.geteuid() != 0:
        sys.exit("bench_sweep: the slurm arm starts a local Slurm, which needs root\n  fix: run as root, or leave slurm out of --arms")
    dask_arms = [x for x in arms if x.startswith("dask")]
    if dask_arms and local_dask.dask_executable() is None:
        sys.exit("bench_sweep: no dask on PATH\n  fix: apt-get install python3-distributed (scripts/setup.sh), or leave dask out of --arms")

    tmp = tempfile.mkdtemp(prefix="enact-bench-sweep-")
    sweep_file = os.path.join(tmp, "sweep.yaml")
    with open(sweep_file, "w") as f:
        f.write(f"name: bench_sweep\nexperiment: {os.path.abspath(a.experiment)}\nseed: 1\nreplicates: {a.replicates}\n"
                "grid:\n  rate_hz: [5000]\n")
    env = dict(os.environ)
    procs, slurm_state = [], None
    logs = open(os.path.join(tmp, "engines.log"), "w")
    executor = {"local1": ["--executor", "local", "--jobs", "1"], "local2": ["--executor", "local", "--jobs", "2"]}
    try:
        if "slurm" in arms:
            slurm_state = os.path.join(tmp, "slurm")
            start = subprocess.run([os.path.join(ROOT, "scripts", "slurm_local.sh"), "start", slurm_state], stdout=subprocess.PIPE,
                                   stderr=subprocess.STDOUT, text=True, env=env)
            if start.returncode != 0:
                sys.exit("bench_sweep: scripts/slurm_local.sh start failed:\n" + start.stdout)
            env["SLURM_CONF"] = os.path.join(slurm_state, "slurm.conf")
            executor["slurm"] = ["--executor", "slurm", "--jobs", "2"]
        if dask_arms:
            address, scheduler = local_dask.start_scheduler(tmp, logs)
            procs.append(scheduler)
            procs += [local_dask.start_worker(address, name, tmp, logs) for name in ("w1", "w2")]
            executor["dask"] = ["--executor", f"dask://{address}"]
            executor["dask_shared"] = executor["dask"] + ["--dask-files", "shared"]
            time.sleep(3)  # the workers registered (a sweep waits for them too)
        times = {arm: [] for arm in arms}
        digests = {}
        for r in range(a.rounds):
            order = arms[r % len(arms):] + arms[:r % len(arms)]
            for arm in order:
                out = os.path.join(tmp, f"{arm}_{r}")
                print(f"round {r + 1} of {a.rounds}: {arm} ...", file=sys.stderr, flush=True)
                t0 = time.monotonic()
                run = subprocess.run([enact, "sweep", sweep_file, "--out", out] + executor[arm], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     text=True, env=env)
                seconds = time.monotonic() - t0
                if run.returncode != 0:
                    sys.exit(f"bench_sweep: the {arm} sweep failed (exit {run.returncode}):\n{run.stderr[-3000:]}")
                times[arm].append(seconds)
                with open(os.path.join(out, "results.csv"), "rb") as f:
                    digests.setdefault(hashlib.sha256(f.read()).hexdigest(), []).append(arm)
                shutil.rmtree(out, ignore_errors=True)
        same = len(digests) == 1
        print(f"sweep: {a.replicates} jobs of {os.path.relpath(a.experiment, ROOT)} in simulated time, {a.rounds} rounds: median (min..max) s")
        for arm in arms:
            print(f"  {arm:7s} {text(times[arm])}")
        figures = {"jobs": a.replicates, "rounds": a.rounds, "cpus": os.cpu_count(), "cpu": cpu_name(), "identical_results": same}
        for arm in arms:
            figures[f"{arm}_s"], figures[f"{arm}_s_min"], figures[f"{arm}_s_max"] = spread(times[arm])
        if "local1" in arms and "local2" in arms:
            ratios = [one / two for one, two in zip(times["local1"], times["local2"])]
            figures["speedup_2_workers"], figures["speedup_2_workers_min"], figures["speedup_2_workers_max"] = spread(ratios)
            print(f"  two local workers over one: {text(ratios, '%.2f')}x (each round's pair)")
        for arm in ("slurm", "dask", "dask_shared"):
            if arm in arms and "local2" in arms:
                costs = [mine / local - 1.0 for mine, local in zip(times[arm], times["local2"])]
                figures[f"{arm}_cost"], figures[f"{arm}_cost_min"], figures[f"{arm}_cost_max"] = spread(costs)
                print(f"  {arm}'s own cost over two local workers: {text([100 * c for c in costs], '%.1f')} % of the sweep's time")
        print(f"  merged results.csv byte-identical on every arm and round: {'yes' if same else 'NO: ' + str(digests)}")
        print(f"machine: {os.cpu_count()} CPUs, {cpu_name()}")
        if a.json:
            with open(a.json, "w") as f:
                json.dump(figures, f, indent=1)
        return 0 if same else 1
    finally:
        local_dask.stop(procs)
        if slurm_state:
            subprocess.run([os.path.join(ROOT, "scripts", "slurm_local.sh"), "stop", slurm_state], env=env, stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
