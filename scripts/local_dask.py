"""A Dask scheduler and its workers on 127.0.0.1, started as processes and stopped by pid, for
the sweep tests and scripts/bench_sweep.py (a lab starts its own: `dask scheduler`, `dask
worker HOST:PORT`). Needs `dask` on PATH (Debian's python3-distributed): callers ask
dask_executable() once first."""
import os
import shutil
import socket
import subprocess


def free_port():
    """a TCP port free on 127.0.0.1 now"""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def dask_executable():
    """the `dask` command, or None when Dask distributed is not installed"""
    dask = shutil.which("dask")
    if dask is None or subprocess.run(["/usr/bin/python3", "-c", "import distributed"], stderr=subprocess.DEVNULL).returncode != 0:
        return None
    return dask


def start_scheduler(folder, logs):
    """a scheduler on a free port, its output into the open file `logs`: (HOST:PORT, process)"""
    port = free_port()
    proc = subprocess.Popen([shutil.which("dask") or "dask", "scheduler", "--host", "127.0.0.1", "--port", str(port), "--dashboard-address",
                             f"127.0.0.1:{free_port()}"], stdout=logs, stderr=logs, cwd=folder)
    return f"127.0.0.1:{port}", proc


def start_worker(address, name, folder, logs):
    """a one-thread worker named `name` (no nanny: killing it kills the worker) of the
    scheduler at HOST:PORT, its files under folder/dask_NAME"""
    return subprocess.Popen([shutil.which("dask") or "dask", "worker", "tcp://" + address, "--nthreads", "1", "--no-nanny", "--name", name,
                             "--local-directory", os.path.join(folder, "dask_" + name)], stdout=logs, stderr=logs, cwd=folder)


def stop(procs):
    """SIGTERM to each (the last started first), then wait for each, 10 s at most, else SIGKILL"""
    for proc in reversed(procs):
        proc.terminate()
    for proc in procs:
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
