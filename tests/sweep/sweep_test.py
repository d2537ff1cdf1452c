#!/usr/bin/python3
"""enact sweep on real executors (docs/experiments.md, "Sweeps"): nothing mocked.

  sweep_test.py BUILD local   a bad grid value refused before any job runs (the sweep file's
                              line); the local run twice the same; resume runs only the jobs
                              missing (a killed job's partial folder never merged); a missing
                              shared file named with the host; the manifest names the git
                              commit enact was built from
  sweep_test.py BUILD slurm   a real single-node Slurm (scripts/slurm_local.sh): the merged
                              table byte-identical to the local run's, the per-job hashes
                              equal; a cancelled (scancel) array task run again on the re-run
  sweep_test.py BUILD dask    a real Dask scheduler and two workers on 127.0.0.1: the same;
                              a worker killed mid-sweep, its job run again, counted once; a
                              worker that does not see the sweep's folder (a tmpfs over it in
                              its own mount namespace, another working directory): the same
                              bytes again, the files travelling by content; with
                              --dask-files shared, the host and the missing path said;
                              the folders come straight from workers this machine
                              reaches, else through the scheduler
Exit 77 (skipped, with the reason) when not root or the packages are missing (scripts/setup.sh).
"""
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.abspath(sys.argv[1])
MODE = sys.argv[2]
ENACT = os.path.join(BUILD, "nodes", "enact", "enact")
EXPERIMENTS = os.path.join(ROOT, "launch", "experiments")
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import local_dask  # noqa: E402  (scripts/local_dask.py)

# the quick bridge experiment, its trials cut to 2 s (few messages: quick jobs); its subject a
# copy in the test's folder, named by its absolute path (a worker without that folder gets it
# by content, the path pointed at the copy)
EXPERIMENT = """name: sweep_test_experiment
seed: 1
subjects: 1
virtual_subject: {tmp}/subjects/quick.yaml
conditions: [CM1]
limit_s: 2
graph: {experiments}/trial_rt.yaml
"""

# 4 jobs of about a second each: 2 loop rates x 2 replicates
SWEEP = """name: sweep_test
experiment: experiment.yaml
seed: 5
replicates: 2
subjects: 1
conditions: [CM1]
grid:
  rate_hz: [1000, 2000]
"""


def fail(message):
    print("FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def skip(reason):
    print("SKIP: " + reason)
    sys.exit(77)


def sweep(*args, check=None, env=None):
    """enact sweep ARGS: (exit status, stderr)."""
    r = subprocess.run([ENACT, "sweep", *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env, timeout=240)
    if check is not None and r.returncode != check:
        fail(f"enact sweep {' '.join(args)}: exit {r.returncode}, expected {check}\n{r.stdout}\n{r.stderr}")
    return r.returncode, r.stderr


def read(path):
    with open(path, "rb") as f:
        return f.read()


def hashes(out):
    """each job's results.csv sha256 from the manifest, by name."""
    with open(os.path.join(out, "manifest.json")) as f:
        m = json.load(f)
    return {j["name"]: j.get("results_sha256") for j in m["jobs"]}


def same_as(reference, out, what):
    if read(os.path.join(reference, "results.csv")) != read(os.path.join(out, "results.csv")):
        fail(f"{what}: the merged results.csv differs from the local run's")
    if hashes(reference) != hashes(out):
        fail(f"{what}: the jobs' hashes differ from the local run's: {hashes(out)} vs {hashes(reference)}")
    rows = read(os.path.join(out, "results.csv")).decode().splitlines()[1:]
    keys = [",".join(r.split(",")[:2]) for r in rows]
    if len(rows) != 4 or len(set(keys)) != 4:
        fail(f"{what}: the merged table holds {len(rows)} rows for 4 jobs (each once): {rows}")


def local_reference(tmp, sweep_file):
    out = os.path.join(tmp, "local")
    sweep(sweep_file, "--out", out, "--jobs", "2", check=0)
    return out


def test_local(tmp, sweep_file):
    # a bad value: refused with its line, before any job runs
    bad = os.path.join(tmp, "bad.yaml")
    with open(bad, "w") as f:
        f.write(SWEEP.replace("rate_hz: [1000, 2000]", "rate_hz:\n    - 1000\n    - 0"))
    code, err = sweep(bad, "--out", os.path.join(tmp, "bad"))
    if code != 1 or f"{bad}:10: rate_hz: 0:" not in err or "rate_hz" not in err:
        fail(f"a bad grid value: exit {code}, expected 1 and '{bad}:10: rate_hz: 0:' in:\n{err}")
    if os.path.exists(os.path.join(tmp, "bad", "jobs")) and any(not n.endswith(".lock") for n in os.listdir(os.path.join(tmp, "bad", "jobs"))):
        fail("a bad grid value: a job ran: " + str(os.listdir(os.path.join(tmp, "bad", "jobs"))))
    # an axis that is not a launch argument: its line
    with open(bad, "w") as f:
        f.write(SWEEP.replace("rate_hz: [1000, 2000]", "rate_hz: [1000]\n  stiffness: [1, 2]"))
    code, err = sweep(bad, "--out", os.path.join(tmp, "bad"))
    if code != 1 or f"{bad}:9:" not in err or "stiffness" not in err:
        fail(f"an unknown grid parameter: exit {code}, expected 1 and '{bad}:9:' naming it in:\n{err}")

    # the same sweep twice (two at once, one at a time): the same bytes
    reference = local_reference(tmp, sweep_file)
    again = os.path.join(tmp, "again")
    sweep(sweep_file, "--out", again, "--jobs", "1", check=0)
    same_as(reference, again, "local, one at a time")
    header = read(os.path.join(again, "results.csv")).decode().splitlines()[0]
    if not header.startswith("rate_hz,replicate,seed,subject,condition"):
        fail("the merged table's columns: " + header)
    # the manifest: the commit enact was built from (this source's, "-dirty" when it differed
    # from it; "unknown" when this source is not a git checkout)
    with open(os.path.join(again, "manifest.json")) as f:
        commit = json.load(f)["enact_commit"]
    head = subprocess.run(["git", "-C", ROOT, "rev-parse", "--show-toplevel", "HEAD"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    lines = head.stdout.split()
    if head.returncode == 0 and os.path.realpath(lines[0]) == os.path.realpath(ROOT):
        if commit not in (lines[1], lines[1] + "-dirty"):
            fail(f"the manifest's enact_commit {commit!r}: expected this source's commit {lines[1]} (built from it)")
    elif commit != "unknown":
        fail(f"the manifest's enact_commit {commit!r} for a source outside git: expected 'unknown'")

    # a path in the grid, the sweep's files in two folders: the merged table names the value
    # as the sweep file writes it, so the two tables are the same bytes (the seeds too)
    tables = []
    for place in ("one", "two"):
        folder = os.path.join(tmp, "moved_" + place)
        os.makedirs(folder)
        shutil.copy(os.path.join(tmp, "experiment.yaml"), folder)
        shutil.copy(os.path.join(ROOT, "launch", "scenes", "bridge.yaml"), os.path.join(folder, "scene.yaml"))
        with open(os.path.join(folder, "sweep.yaml"), "w") as f:
            f.write(SWEEP.replace("replicates: 2", "replicates: 1").replace("rate_hz: [1000, 2000]", "rate_hz: [1000]\n  scene: [$(dirname)/scene.yaml]"))
        sweep(os.path.join(folder, "sweep.yaml"), "--out", os.path.join(folder, "out"), check=0)
        tables.append(read(os.path.join(folder, "out", "results.csv")).decode())
    if tables[0] != tables[1] or ",$(dirname)/scene.yaml,1," not in tables[0]:
        fail("a path in the grid: the merged tables of the same sweep in two folders differ, or name the path otherwise than the sweep "
             f"file:\n{tables[0]}\n{tables[1]}")

    # resume: a job gone, another's folder left partial by a killed run: only those run again,
    # the partial one never merged
    jobs = sorted(n for n in os.listdir(os.path.join(again, "jobs")) if not n.endswith(".lock"))
    gone, killed = jobs[0], jobs[1]
    shutil.rmtree(os.path.join(again, "jobs", gone))
    os.rename(os.path.join(again, "jobs", killed), os.path.join(again, "jobs", killed + ".partial"))
    os.remove(os.path.join(again, "jobs", killed + ".partial", "job.json"))
    with open(os.path.join(again, "jobs", killed + ".partial", "results.csv"), "a") as f:
        f.write("1,CM1,1,99,9,9,1,0,0\n")
    dry = subprocess.run([ENACT, "sweep", sweep_file, "--out", again, "--dry-run"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    listed = re.findall(r"'--job' '(\d+)'", dry.stdout)
    if dry.returncode != 0 or len(listed) != 2:
        fail(f"resume: the dry run lists {listed}, expected the 2 jobs not done:\n{dry.stdout}{dry.stderr}")
    code, err = sweep(sweep_file, "--out", again, check=0)
    if "2 jobs to run (2 done before)" not in err:
        fail("resume: not only the missing jobs ran:\n" + err)
    same_as(reference, again, "resumed")
    _, err = sweep(sweep_file, "--out", again, check=0)
    if "0 jobs to run (4 done before)" not in err:
        fail("a finished sweep run again ran jobs:\n" + err)

    # more replicates: only the new jobs run, the others keep their rows
    grown = os.path.join(tmp, "grown.yaml")
    with open(grown, "w") as f:
        f.write(SWEEP.replace("replicates: 2", "replicates: 3"))
    _, err = sweep(grown, "--out", again, check=0)
    if "2 jobs to run (4 done before)" not in err:
        fail("more replicates: not only the new jobs ran:\n" + err)
    before = read(os.path.join(reference, "results.csv")).decode().splitlines()
    after = read(os.path.join(again, "results.csv")).decode().splitlines()
    if len(after) != 7 or [r for r in after if r.split(",")[1] != "3"] != before:
        fail(f"more replicates: the table {after} does not hold the earlier rows {before} and 2 more")
    # the experiment edited: its folder refused, nothing run
    with open(os.path.join(tmp, "experiment.yaml"), "a") as f:
        f.write("practice_s: 1\n")
    code, err = sweep(sweep_file, "--out", again)
    if code != 1 or "sweep.txt" not in err or "jobs to run" in err:
        fail(f"an edited experiment: exit {code}, expected 1 naming sweep.txt, nothing run:\n{err}")

    # a shared file missing where the job runs: the host and the path
    code, err = sweep(os.path.join(tmp, "nowhere", "sweep.yaml"), "--out", again, "--job", "0")
    host = socket.gethostname()
    if code == 0 or f"on host {host}" not in err or os.path.join(tmp, "nowhere", "sweep.yaml") not in err:
        fail(f"a missing sweep file on a worker: exit {code}, expected the host {host} and the path in:\n{err}")


def test_slurm(tmp, sweep_file):
    if os.geteuid() != 0:
        skip("a local Slurm needs root (slurmd runs the jobs as their users)")
    for exe in ("munged", "slurmctld", "slurmd", "sbatch", "squeue", "scancel"):
        if shutil.which(exe) is None:
            skip(f"{exe} is not installed (apt-get install slurm-wlm munge; scripts/setup.sh)")
    reference = local_reference(tmp, sweep_file)
    state = os.path.join(tmp, "slurm")
    env = dict(os.environ, ENACT_SLURMCTLD_PORT="16817", ENACT_SLURMD_PORT="16818")
    start = subprocess.run([os.path.join(ROOT, "scripts", "slurm_local.sh"), "start", state], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)
    try:
        if start.returncode != 0:
            fail("scripts/slurm_local.sh start:\n" + start.stdout)
        env["SLURM_CONF"] = os.path.join(state, "slurm.conf")
        # the same sweep through a job array: the same bytes
        out = os.path.join(tmp, "slurm_out")
        sweep(sweep_file, "--out", out, "--executor", "slurm", check=0, env=env)
        same_as(reference, out, "slurm")
        # one task at a time; a pending task and (when caught) a running one cancelled
        out = os.path.join(tmp, "slurm_cancel")
        run = subprocess.Popen([ENACT, "sweep", sweep_file, "--out", out, "--executor", "slurm", "--jobs", "1"], stderr=subprocess.PIPE, text=True, env=env)
        array = None
        deadline = time.time() + 60
        while array is None and time.time() < deadline:
            q = subprocess.run(["squeue", "-h", "-r", "-o", "%i %T"], stdout=subprocess.PIPE, text=True, env=env).stdout.split()
            tasks = dict(zip(q[0::2], q[1::2]))
            running = [t for t, s in tasks.items() if s == "RUNNING"]
            if running:
                array = running[0].split("_")[0]
                subprocess.run(["scancel", f"{array}_3"], env=env, check=True)  # pending: never runs
                subprocess.run(["scancel", running[0]], env=env, check=True)
            time.sleep(0.1)
        _, err = run.communicate(timeout=180)
        if array is None:
            fail("no array task ever ran:\n" + err)
        if run.returncode != 1 or not re.search(r"jobs did not start \((\d+, )*3[,)]", err):
            fail(f"a cancelled task: exit {run.returncode}, expected 1 naming job 3 (cancelled before it started):\n{err}")
        rows = read(os.path.join(out, "results.csv")).decode().splitlines()[1:]
        done = [n for n in os.listdir(os.path.join(out, "jobs")) if not n.endswith((".lock", ".partial"))]
        if len(rows) != len(done) or len(done) >= 4 or any(r.startswith("2000,2,") for r in rows):
            fail(f"the cancelled jobs' rows: {rows} for the jobs done {done}")
        _, err = sweep(sweep_file, "--out", out, "--executor", "slurm", check=0, env=env)
        if f"{4 - len(done)} jobs to run ({len(done)} done before)" not in err:
            fail("the re-run did not run only the cancelled jobs:\n" + err)
        same_as(reference, out, "slurm, cancelled tasks run again")
    finally:
        subprocess.run([os.path.join(ROOT, "scripts", "slurm_local.sh"), "stop", state], env=env)


def test_dask(tmp, sweep_file):
    dask = local_dask.dask_executable()
    if dask is None:
        skip("Dask distributed is not installed (apt-get install python3-distributed; scripts/setup.sh)")
    reference = local_reference(tmp, sweep_file)
    logs = open(os.path.join(tmp, "dask.log"), "w")
    address, scheduler = local_dask.start_scheduler(tmp, logs)
    procs = [scheduler]

    def worker(name):
        procs.append(local_dask.start_worker(address, name, tmp, logs))
        return procs[-1]

    try:
        workers = [worker("w1"), worker("w2")]
        # which way the jobs' folders come back: straight from workers this machine reaches,
        # else through the scheduler (a closed port stands for a worker behind a firewall)
        import dask_sweep

        class Workers:
            def __init__(self, *addresses):
                self.addresses = addresses

            def scheduler_info(self):
                return {"workers": {a: {} for a in self.addresses}}

        with socket.socket() as listening:
            listening.bind(("127.0.0.1", 0))
            listening.listen(1)
            reached = f"tcp://127.0.0.1:{listening.getsockname()[1]}"
            with socket.socket() as closed:
                closed.bind(("127.0.0.1", 0))
                unreached = f"tcp://127.0.0.1:{closed.getsockname()[1]}"
                if not dask_sweep.reach_workers(Workers(reached)):
                    fail("a worker listening on 127.0.0.1 is taken as out of reach")
                if dask_sweep.reach_workers(Workers(reached, unreached)) or dask_sweep.reach_workers(Workers("tls://127.0.0.1:1")):
                    fail("a worker out of reach (a closed port, an address other than tcp://) is taken as reached")
        out = os.path.join(tmp, "dask_out")
        code, err = sweep(sweep_file, "--out", out, "--executor", "dask://" + address, check=0)
        if "dashboard http://" not in err:
            fail("the dashboard's address is not printed:\n" + err)
        same_as(reference, out, "dask")
        # a worker killed while its job runs: the job runs again (this run or the next), once
        out = os.path.join(tmp, "dask_kill")
        run = subprocess.Popen([ENACT, "sweep", sweep_file, "--out", out, "--executor", "dask://" + address], stderr=subprocess.PIPE, text=True)
        deadline = time.time() + 60
        killed = False
        while not killed and time.time() < deadline:
            # a job running on w1: its folder under the worker's own (the job's files came by content)
            if any(d.endswith(".partial") for _, dirs, _ in os.walk(os.path.join(tmp, "dask_w1")) for d in dirs):
                workers[0].send_signal(signal.SIGKILL)
                killed = True
            time.sleep(0.05)
        _, err = run.communicate(timeout=180)
        if not killed:
            fail("no job ever ran on Dask:\n" + err)
        worker("w3")
        code, err = sweep(sweep_file, "--out", out, "--executor", "dask://" + address, check=0)
        same_as(reference, out, "dask, a worker killed")

        # a worker that does not see the sweep's folder (a tmpfs over it in its own mount
        # namespace; its working directory /), alone on its scheduler: by content (the
        # default) the same bytes; through a shared folder, each job's error names the host
        # and the path
        if os.geteuid() != 0 or shutil.which("unshare") is None:
            print("sweep dask: the worker without the sweep's folder needs root and unshare: not tried")
            return
        blind, blind_scheduler = local_dask.start_scheduler(tmp, logs)
        procs.append(blind_scheduler)
        procs.append(subprocess.Popen(["unshare", "-m", "--propagation", "private", "sh", "-c",
                                       f'mount -t tmpfs tmpfs "{tmp}" && exec "{dask}" worker tcp://{blind} --nthreads 1 --no-nanny --name blind --local-directory "{tmp}"'],
                                      stdout=logs, stderr=logs, cwd="/"))
        out = os.path.join(tmp, "dask_blind")
        sweep(sweep_file, "--out", out, "--executor", f"dask://{blind}", check=0)
        same_as(reference, out, "dask, a worker without the sweep's folder")
        with open(os.path.join(out, "inputs.txt")) as f:
            travelled = f.read().split()
        for name in (sweep_file, os.path.join(tmp, "experiment.yaml"), os.path.join(tmp, "subjects", "quick.yaml")):
            if name not in travelled:
                fail(f"{name} did not travel with the jobs (inputs.txt: {travelled})")
        code, err = sweep(sweep_file, "--out", os.path.join(tmp, "dask_blind_shared"), "--executor", f"dask://{blind}", "--dask-files", "shared")
        host = socket.gethostname()
        if code != 1 or f"on host {host}: the sweep file {sweep_file} is missing here" not in err:
            fail(f"a worker without the shared folder: exit {code}, expected 1 and the host and the sweep file's path in:\n{err}")
    finally:
        local_dask.stop(procs)
        logs.close()


def main():
    if not os.path.exists(ENACT):
        fail(f"no enact at {ENACT}: build it first")
    tmp = tempfile.mkdtemp(prefix="enact_sweep_")
    try:
        os.makedirs(os.path.join(tmp, "subjects"))
        shutil.copy(os.path.join(EXPERIMENTS, "subjects", "quick.yaml"), os.path.join(tmp, "subjects"))
        with open(os.path.join(tmp, "experiment.yaml"), "w") as f:
            f.write(EXPERIMENT.format(tmp=tmp, experiments=EXPERIMENTS))
        sweep_file = os.path.join(tmp, "sweep.yaml")
        with open(sweep_file, "w") as f:
            f.write(SWEEP)
        {"local": test_local, "slurm": test_slurm, "dask": test_dask}[MODE](tmp, sweep_file)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print(f"sweep {MODE}: ok")


if __name__ == "__main__":
    main()
