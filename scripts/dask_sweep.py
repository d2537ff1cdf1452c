#!/usr/bin/python3
"""Run a sweep's jobs on a Dask distributed scheduler (what `enact sweep --executor
dask://HOST:PORT` calls; docs/experiments.md, "Sweeps").

One task per job: the task runs `COMMAND... --job K` (enact sweep FILE --out DIR) on a worker
as a process, through the folder the sweep's files are on (shared with the workers, the same
path). The job writes its own folder; the task returns its exit code, host and output, which
this script appends to LOGS/job_K.log. A worker that dies while running a task: the scheduler
runs the task again on another worker (the job starts afresh; `enact sweep` merges only jobs
done). Exit status 0 when every task ran (the jobs' own success is in their folders), 1 when a
task could not run (e.g. its workers kept dying), 2 for bad arguments or no scheduler.

Needs Debian's python3-distributed (scripts/setup.sh).
"""
import argparse
import os
import socket
import subprocess
import sys


def run_job(command, k):
    """On a worker: the job as a process; (k, exit code, host, output)."""
    import ctypes
    import signal

    host = socket.gethostname()

    def die_with_worker():
        # the job stops when this worker does (PR_SET_PDEATHSIG = 1): it runs again elsewhere
        ctypes.CDLL(None).prctl(1, signal.SIGTERM)

    if not os.path.exists(command[0]):
        return k, 127, host, f"enact sweep: on host {host}: the enact executable {command[0]} is missing here\n  fix: run the workers where the build (or install) is on a folder shared with this host (the same path)\n"
    try:
        done = subprocess.run(command + ["--job", str(k)], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, preexec_fn=die_with_worker, check=False)
    except OSError as e:
        return k, 127, host, f"enact sweep: on host {host}: cannot run {command[0]}: {e}\n"
    return k, done.returncode, host, done.stdout.decode(errors="replace")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--scheduler", required=True, help="HOST:PORT of a running Dask scheduler")
    p.add_argument("--logs", required=True, help="the sweep's logs folder (DIR/logs)")
    p.add_argument("--jobs", required=True, help="the jobs to run, comma-separated numbers")
    p.add_argument("command", nargs=argparse.REMAINDER, help="-- enact sweep FILE --out DIR")
    a = p.parse_args()
    command = a.command[1:] if a.command[:1] == ["--"] else a.command
    if not command:
        p.error("give the job's command after --")
    try:
        from distributed import Client, as_completed
    except ImportError:
        print("dask_sweep.py: Dask distributed is not installed: apt-get install python3-distributed (scripts/setup.sh)", file=sys.stderr)
        return 2
    jobs = [int(k) for k in a.jobs.split(",") if k]
    try:
        client = Client(a.scheduler if "://" in a.scheduler else "tcp://" + a.scheduler, timeout=15)
    except OSError as e:
        print(f"dask_sweep.py: no Dask scheduler at {a.scheduler}: {e}\n  fix: start one (dask scheduler) and its workers (dask worker {a.scheduler})", file=sys.stderr)
        return 2
    print(f"enact sweep: Dask scheduler {a.scheduler}, {len(client.scheduler_info()['workers'])} workers, dashboard {client.dashboard_link}", file=sys.stderr, flush=True)
    os.makedirs(a.logs, exist_ok=True)
    futures = [client.submit(run_job, command, k, key=f"enact-sweep-{os.getpid()}-{k}", pure=False) for k in jobs]
    lost = 0
    for f in as_completed(futures):
        try:
            k, code, host, output = f.result()
        except Exception as e:  # the task could not run (e.g. KilledWorker: its workers kept dying)
            lost += 1
            print(f"enact sweep: a Dask task did not run ({type(e).__name__}: {e}); the job runs on the next run", file=sys.stderr, flush=True)
            continue
        with open(os.path.join(a.logs, f"job_{k}.log"), "a") as log:
            log.write(output)
        if code != 0:
            said = "".join("\n  " + line for line in output.strip().splitlines()[-3:])
            print(f"enact sweep: job {k} failed on {host} (exit {code}); log {a.logs}/job_{k}.log:{said}", file=sys.stderr, flush=True)
    client.close()
    return 1 if lost else 0


if __name__ == "__main__":
    sys.exit(main())
