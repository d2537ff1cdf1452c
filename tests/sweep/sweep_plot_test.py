#!/usr/bin/python3
"""scripts/sweep_plot.py and scripts/power.py on a sweep's folder with known values: each job's
mean over its subjects, the point's mean over the replicates and its 95 % t interval (checked
against the textbook value), the figure written; power.py takes one grid point's replicates
and asks for --point when the sweep has several."""
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HEADER = "rate_hz,replicate,seed,subject,condition,order,falls,time_total_s,time_out_s,ratio,completed,missed_deadlines"


def fail(message):
    print("FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def make_sweep(folder):
    """2 points x 3 replicates x 2 subjects x 2 conditions; ratio = job's base + subject's 0.1"""
    jobs, rows = [], []
    base = {("1000", 1): 0.2, ("1000", 2): 0.4, ("1000", 3): 0.9, ("5000", 1): 0.1, ("5000", 2): 0.1, ("5000", 3): 0.1}
    for (rate, rep), b in base.items():
        name = f"rate_hz-{rate}_r{rep:03d}"
        job_rows = []
        for subject in (1, 2):
            for c, condition in enumerate(("CM0", "CM1")):
                ratio = b + 0.1 * (subject - 1) + 0.05 * c
                job_rows.append(f"{subject},{condition},{c + 1},{subject + c},10,{10 * ratio:.6g},{ratio:.6g},0,0")
        os.makedirs(os.path.join(folder, "jobs", name))
        with open(os.path.join(folder, "jobs", name, "results.csv"), "w") as f:
            f.write(HEADER.split(",seed,")[1] + "\n")
            f.write("".join(r + "\n" for r in job_rows))
        rows += [f"{rate},{rep},{rep},{r}" for r in job_rows]
        jobs.append({"index": len(jobs), "name": name, "coords": {"rate_hz": rate}, "replicate": rep, "seed": rep, "state": "done"})
    with open(os.path.join(folder, "results.csv"), "w") as f:
        f.write(HEADER + "\n" + "".join(r + "\n" for r in rows))
    with open(os.path.join(folder, "manifest.json"), "w") as f:
        json.dump({"grid": {"rate_hz": ["1000", "5000"]}, "jobs": jobs}, f)


def main():
    with tempfile.TemporaryDirectory(prefix="enact_sweep_plot_") as folder:
        make_sweep(folder)
        r = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "scripts", "sweep_plot.py"), folder], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if r.returncode != 0:
            fail(f"sweep_plot.py: exit {r.returncode}\n{r.stdout}{r.stderr}")
        with open(os.path.join(folder, "plots", "ratio.csv")) as f:
            table = {(row["rate_hz"], row["condition"]): row for row in csv.DictReader(f)}
        # rate 1000, CM0: the jobs' means over the subjects 0.25, 0.45, 0.95 (base + 0.05)
        means = [0.25, 0.45, 0.95]
        mean = sum(means) / 3
        sd = math.sqrt(sum((m - mean) ** 2 for m in means) / 2)
        half = 4.302652729911275 * sd / math.sqrt(3)  # t(0.975, 2)
        row = table[("1000", "CM0")]
        if abs(float(row["mean"]) - mean) > 1e-5 or abs(float(row["ci95_half"]) - half) > 1e-4 or row["replicates"] != "3":
            fail(f"rate 1000, CM0: {row}, expected mean {mean:.6g}, half-width {half:.6g}, 3 replicates")
        row = table[("5000", "CM1")]
        if abs(float(row["mean"]) - 0.2) > 1e-5 or abs(float(row["ci95_half"])) > 1e-9:
            fail(f"rate 5000, CM1: {row}, expected 0.2 exactly (equal replicates)")
        if not os.path.getsize(os.path.join(folder, "plots", "ratio.png")) > 1000:
            fail("no figure written")
        # a column that is not there: named with the fix
        r = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "scripts", "sweep_plot.py"), folder, "--measure", "speed"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if r.returncode == 0 or "results.csv:1: no column 'speed'" not in r.stderr or "fix:" not in r.stderr:
            fail(f"an unknown measure: exit {r.returncode}\n{r.stderr}")
        # power.py: several points ask for --point; one point's 3 replicates pool 6 subjects
        power = os.path.join(ROOT, "scripts", "power.py")
        r = subprocess.run(["/usr/bin/python3", power, folder, "--subjects", "2-2", "--draws", "20"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if r.returncode != 1 or "--point" not in r.stderr:
            fail(f"power.py on a sweep of 2 points: exit {r.returncode}, expected 1 asking for --point\n{r.stdout}{r.stderr}")
        r = subprocess.run(["/usr/bin/python3", power, folder, "--subjects", "2-4", "--draws", "20", "--point", "rate_hz=1000"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if r.returncode != 0 or "from 6 virtual subjects of 3 replicates" not in r.stdout:
            fail(f"power.py on one point: exit {r.returncode}, expected 6 subjects of 3 replicates\n{r.stdout}{r.stderr}")
    print("sweep_plot: ok")


if __name__ == "__main__":
    main()
