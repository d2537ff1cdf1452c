#!/usr/bin/python3
"""Run a sweep's jobs on a Dask distributed scheduler (what `enact sweep --executor
dask://HOST:PORT` calls; docs/experiments.md, "Sweeps").

One task per job, each running `ENACT sweep SWEEP --out DIR --job K` on a worker as a process.
With --inputs (enact's default, --dask-files content) the files the jobs read travel by
content: their bytes go to the workers once, each task writes them into a folder of its own on
its worker (at their paths under it, an absolute path naming one of them in a text file
pointed there), runs the job there and sends the job's folder back, which this script writes
into DIR/jobs/ (renamed from .partial once the job succeeded, as a job does itself); so a
worker needs no folder shared with this machine, only the enact executable. A job's folder
comes straight from its worker where this machine reaches the workers (else through the
scheduler, said at the start), uncompressed: its recordings are compressed already (timed
here, a 713 MB folder: 3.7 s relayed by the scheduler with Dask's lz4, 2.9 s straight with it,
1.2 s straight without). Without
--inputs the workers use the sweep's files and DIR at their paths (a shared folder).
The task's output goes to DIR/logs/job_K.log. A worker that dies while running a task: the
scheduler runs the task again on another worker (the job starts afresh; `enact sweep` merges
only jobs done). Exit status 0 when every task ran (the jobs' own success is in their
folders), 1 when a task could not run (e.g. its workers kept dying), 2 for bad arguments or
no scheduler.

Needs Debian's python3-distributed (scripts/setup.sh).
"""
import argparse
import json
import os
import re
import shutil
import socket
import subprocess
import sys
import tempfile


def run(command, cwd=None):
    """The job as a process that stops when this worker does: (exit code, output)."""
    import ctypes
    import signal

    def die_with_worker():
        # PR_SET_PDEATHSIG = 1: the job stops with the worker, and runs again elsewhere
        ctypes.CDLL(None).prctl(1, signal.SIGTERM)

    try:
        done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, preexec_fn=die_with_worker, cwd=cwd, check=False)
    except OSError as e:
        return 127, f"enact sweep: on host {socket.gethostname()}: cannot run {command[0]}: {e}\n"
    return done.returncode, done.stdout.decode(errors="replace")


def missing_enact(enact):
    host = socket.gethostname()
    return f"enact sweep: on host {host}: the enact executable {enact} is missing here\n  fix: run the workers where the build (or install) is at the same path\n"


def run_job_shared(enact, sweep, out, k):
    """On a worker: the job through the shared folder; (k, exit code, host, output, None)."""
    host = socket.gethostname()
    if not os.path.exists(enact):
        return k, 127, host, missing_enact(enact), None
    code, output = run([enact, "sweep", sweep, "--out", out, "--job", str(k)])
    return k, code, host, output, None


def placed(inputs, root):
    """Each input's bytes as written under `root`: text files with the inputs' paths pointed
    under `root` too (a path naming another file, not a longer name that starts with it)."""
    pattern = re.compile(r"(?<![\w./-])(" + "|".join(re.escape(p) for p in sorted(inputs, key=len, reverse=True)) + r")(?![\w.-])")
    files = {}
    for path, data in inputs.items():
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError:
            text = None
        if text is not None and "\0" not in text:
            data = pattern.sub(lambda m: root + m.group(1), text).encode("utf-8")
        files[root + path] = data
    return files


def run_job_by_content(enact, sweep, inputs, k):
    """On a worker: the job in a folder of its own from the inputs' bytes. Its result is one
    dict of bytearrays, which Dask sends a frame each without copying them into a pickle (a
    job's folder inside a tuple went twice as slowly: 4.4 s against 2.0 s for 495 MB here):
    the job's folder's files by relative path, and under META what by_content_result() reads."""
    from distributed import get_worker

    host = socket.gethostname()
    if not os.path.exists(enact):
        return packed(k, 127, host, missing_enact(enact), None, {})
    work = tempfile.mkdtemp(prefix=f"enact-sweep-job{k}-", dir=get_worker().local_directory)
    try:
        for path, data in placed(inputs, os.path.join(work, "files")).items():
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "wb") as f:
                f.write(data)
        jobs = os.path.join(work, "out", "jobs")
        os.makedirs(jobs)
        code, output = run([enact, "sweep", os.path.join(work, "files") + sweep, "--out", os.path.join(work, "out"), "--job", str(k)], cwd=work)
        folders = [n for n in os.listdir(jobs) if os.path.isdir(os.path.join(jobs, n))]
        if len(folders) != 1:
            return packed(k, code or 1, host, output, None, {})
        folder = os.path.join(jobs, folders[0])
        files = {}
        for parent, _, names in os.walk(folder):
            for n in names:
                path = os.path.join(parent, n)
                data = bytearray(os.path.getsize(path))
                with open(path, "rb") as f:
                    f.readinto(data)
                files[os.path.relpath(path, folder)] = data
        return packed(k, code, host, output, folders[0], files)
    finally:
        shutil.rmtree(work, ignore_errors=True)


# the key of a by-content result's own line (no file's relative path is empty)
META = ""


def packed(k, code, host, output, folder, files):
    """a by-content task's result: the files, and under META the rest as JSON"""
    files[META] = bytearray(json.dumps({"k": k, "code": code, "host": host, "output": output, "folder": folder}).encode())
    return files


def unpacked(result):
    """(k, exit code, host, output, (folder name, files) or None), as run_job_shared gives"""
    if not isinstance(result, dict):
        return result
    meta = json.loads(bytes(result.pop(META)))
    return meta["k"], meta["code"], meta["host"], meta["output"], (meta["folder"], result) if meta["folder"] else None


def reach_workers(client):
    """whether this machine reaches every worker's address (tcp://HOST:PORT) within 2 s: then
    results come from the workers, not relayed by the scheduler"""
    for address in client.scheduler_info()["workers"]:
        m = re.fullmatch(r"tcp://\[?([^\]]+)\]?:(\d+)", address)
        if not m:
            return False
        try:
            socket.create_connection((m.group(1), int(m.group(2))), timeout=2).close()
        except OSError:
            return False
    return True


def keep_job(jobs, folder):
    """A job's folder sent back by its worker, written into DIR/jobs as the job writes it:
    NAME.partial first, renamed NAME once its job.json says it succeeded."""
    name, files = folder
    name = name[: -len(".partial")] if name.endswith(".partial") else name
    if os.sep in name or name.startswith(".") or any(os.path.isabs(r) or ".." in r.split(os.sep) for r in files):
        raise ValueError(f"a worker sent back a job folder with a bad name: {name}")
    done, partial = os.path.join(jobs, name), os.path.join(jobs, name + ".partial")
    if os.path.exists(os.path.join(done, "job.json")):
        return  # done before (a task run twice)
    shutil.rmtree(partial, ignore_errors=True)
    for relative, data in files.items():
        os.makedirs(os.path.dirname(os.path.join(partial, relative)), exist_ok=True)
        with open(os.path.join(partial, relative), "wb") as f:
            f.write(data)
    if folder[0] == name:  # the worker renamed it: the job succeeded
        os.rename(partial, done)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--scheduler", required=True, help="HOST:PORT of a running Dask scheduler")
    p.add_argument("--enact", required=True, help="the enact executable (the same path on the workers)")
    p.add_argument("--sweep", required=True, help="the sweep file (absolute)")
    p.add_argument("--out", required=True, help="the sweep's folder (absolute)")
    p.add_argument("--jobs", required=True, help="the jobs to run, comma-separated numbers")
    p.add_argument("--inputs", help="a file listing the files the jobs read (absolute, one a line): they travel by content")
    a = p.parse_args()
    try:
        from distributed import Client, as_completed
    except ImportError:
        print("dask_sweep.py: Dask distributed is not installed: apt-get install python3-distributed (scripts/setup.sh)", file=sys.stderr)
        return 2
    jobs = [int(k) for k in a.jobs.split(",") if k]
    if a.inputs:
        import dask

        # offered on this client's connections, which then carry the folders uncompressed
        dask.config.set({"distributed.comm.compression": None})
    try:
        client = Client(a.scheduler if "://" in a.scheduler else "tcp://" + a.scheduler, timeout=15)
    except OSError as e:
        print(f"dask_sweep.py: no Dask scheduler at {a.scheduler}: {e}\n  fix: start one (dask scheduler) and its workers (dask worker {a.scheduler})", file=sys.stderr)
        return 2
    print(f"enact sweep: Dask scheduler {a.scheduler}, {len(client.scheduler_info()['workers'])} workers, dashboard {client.dashboard_link}", file=sys.stderr, flush=True)
    logs = os.path.join(a.out, "logs")
    os.makedirs(logs, exist_ok=True)
    key = f"enact-sweep-{os.getpid()}"
    direct = False
    if a.inputs:
        direct = reach_workers(client)
        if not direct:
            print("enact sweep: this machine does not reach every worker: the jobs' folders come through the scheduler", file=sys.stderr, flush=True)
        with open(a.inputs) as f:
            paths = [line.rstrip("\n") for line in f if line.strip()]
        inputs = {}
        for path in paths:
            with open(path, "rb") as f:
                inputs[path] = f.read()
        # sent to the workers once, not with each task
        [sent] = client.scatter([inputs], broadcast=True)
        futures = [client.submit(run_job_by_content, a.enact, a.sweep, sent, k, key=f"{key}-{k}", pure=False) for k in jobs]
    else:
        futures = [client.submit(run_job_shared, a.enact, a.sweep, a.out, k, key=f"{key}-{k}", pure=False) for k in jobs]
    lost = 0
    pending = as_completed(futures)
    # each task's result let go once taken: a worker keeps a result while a future names it,
    # and by content each is a job's whole folder (713 MB for the 48-trial protocol): the list
    # kept to the end held every job's folder in the workers' memory until the sweep ended
    del futures
    for f in pending:
        try:
            k, code, host, output, folder = unpacked(client.gather(f, direct=direct))
        except Exception as e:  # the task could not run (e.g. KilledWorker: its workers kept dying)
            lost += 1
            print(f"enact sweep: a Dask task did not run ({type(e).__name__}: {e}); the job runs on the next run", file=sys.stderr, flush=True)
            continue
        with open(os.path.join(logs, f"job_{k}.log"), "a") as log:
            log.write(output)
        if folder is not None:
            keep_job(os.path.join(a.out, "jobs"), folder)
        if code != 0:
            said = "".join("\n  " + line for line in output.strip().splitlines()[-3:])
            print(f"enact sweep: job {k} failed on {host} (exit {code}); log {logs}/job_{k}.log:{said}", file=sys.stderr, flush=True)
    client.close()
    return 1 if lost else 0


if __name__ == "__main__":
    sys.exit(main())
