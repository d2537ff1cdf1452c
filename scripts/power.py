#!/usr/bin/python3
"""The virtual baseline's statistical power against the number of subjects.

usage: power.py DIR [--subjects 6-24] [--step 2] [--draws 2000] [--alpha 0.05] [--seed 1]
                    [--point AXIS=VALUE,...] [--out DIR/power]

DIR holds the replicates of `enact experiment FILE --clock simulated --replicates N --out
DIR` (DIR/replicate_NNN/results.csv), or is a sweep's folder (`enact sweep FILE --out DIR`:
the replicates of one grid point, its done jobs DIR/jobs/<coordinates>/results.csv; --point
chooses the point when the grid has several, e.g. --point rate_hz=1000). Every replicate's subjects are fresh draws from the
same virtual population (their traits and noise from independent seeds), so they are pooled.
For each number of subjects n, `draws` studies of n subjects are drawn from the pool without
replacement and analysed as scripts/analyze.py does (Friedman's test across the conditions,
censored total times ranked as ties at the limit); the power of a measure is the share of
studies with p < alpha, given with its binomial standard error.

This is the power of the virtual baseline subject and the simulator, under their
assumptions, not the power of an experiment with people: it says how many virtual subjects
show the conditions apart, a lower bound on what a lab would plan for. A pool smaller than
about four times the largest n makes the draws share most of their subjects, and the power
is then known less well than its standard error says (the script warns).

Writes OUT/power.csv (n, measure, power, se, draws) and OUT/power.png, and prints the table.
"""
import argparse
import csv
import glob
import json
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import analyze  # noqa: E402  (same folder: the loading and the tests are analyze.py's)

import matplotlib  # noqa: E402
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def sweep_files(folder, point):
    """a sweep's done jobs' results.csv at one grid point (`point`: "AXIS=VALUE,..." or "")"""
    with open(os.path.join(folder, "manifest.json")) as f:
        jobs = [j for j in json.load(f)["jobs"] if j.get("state") == "done"]
    wanted = dict(kv.split("=", 1) for kv in point.split(",") if "=" in kv)
    chosen = [j for j in jobs if all(j["coords"].get(k) == v for k, v in wanted.items())]
    points = sorted({tuple(sorted(j["coords"].items())) for j in chosen})
    if len(points) > 1:
        names = "; ".join(",".join(f"{k}={v}" for k, v in p) for p in points)
        raise analyze.InputError(folder, f"the sweep's jobs are at {len(points)} grid points ({names})",
                                 "choose one with --point, e.g. --point " + ",".join(f"{k}={v}" for k, v in points[0]))
    return [os.path.join(folder, "jobs", j["name"], "results.csv") for j in chosen]


def pool(folder, point=""):
    """{measure: {subject: {condition: value}}}, {subject: {condition: censored}}, the
    conditions and the replicates read; subjects named REPLICATE/SUBJECT"""
    if os.path.isfile(os.path.join(folder, "manifest.json")):
        files = sweep_files(folder, point)
    else:
        files = sorted(glob.glob(os.path.join(folder, "replicate_*", "results.csv")))
    if not files:
        raise analyze.InputError(folder, "no replicate_*/results.csv",
                                 "run the replicates first: enact experiment FILE --clock simulated --replicates N --out " + folder)
    data, censored, conditions = {}, {}, None
    for path in files:
        replicate = os.path.basename(os.path.dirname(path))
        d, c, _, cens = analyze.load(path, None)
        if conditions is None:
            conditions = c
        elif c != conditions:
            raise analyze.InputError(path, f"conditions {c} differ from the other replicates' {conditions}", "give every replicate the same conditions")
        for measure, by_subject in d.items():
            for subject, values in by_subject.items():
                if all(k in values for k in conditions):
                    data.setdefault(measure, {})[f"{replicate}/{subject}"] = values
        for subject, values in cens.items():
            censored[f"{replicate}/{subject}"] = values
    return data, censored, conditions, len(files)


def p_value(by_subject, subjects, conditions, censored, measure):
    """Friedman's p for `subjects` (analyze.py's test and its censoring rule); None when it
    cannot be computed (every subject the same in every condition)"""
    chosen = {s: by_subject[s] for s in subjects}
    if measure == analyze.CENSORED_MEASURE:
        chosen, _ = analyze.at_the_limit(chosen, censored)
    columns = [[chosen[s][c] for s in subjects] for c in conditions]
    return analyze.friedman(columns)["p"]


def power_table(data, censored, conditions, sizes, draws, alpha, seed):
    rng = random.Random(seed)
    rows = []
    for n in sizes:
        for measure, by_subject in data.items():
            if measure == "ranking":
                continue
            subjects = sorted(by_subject)
            significant = 0
            for _ in range(draws):
                p = p_value(by_subject, rng.sample(subjects, n), conditions, censored, measure)
                significant += p is not None and p < alpha
            power = significant / draws
            rows.append({"n": n, "measure": measure, "power": power, "se": math.sqrt(power * (1 - power) / draws), "draws": draws})
    return rows


def sizes_of(text, step):
    low, _, high = text.partition("-")
    try:
        low, high = int(low), int(high or low)
    except ValueError:
        raise analyze.InputError("--subjects", f"'{text}' is not a range", "write e.g. --subjects 6-24")
    if low < 2 or high < low or step < 1:
        raise analyze.InputError("--subjects", f"'{text}' (step {step})", "give 2 <= LOW <= HIGH and --step >= 1")
    return list(range(low, high + 1, step))


def write(rows, out, pooled, replicates, alpha):
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "power.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["n", "measure", "power", "se", "draws"])
        w.writeheader()
        w.writerows(rows)
    measures = list(dict.fromkeys(r["measure"] for r in rows))
    fig, ax = plt.subplots(figsize=(6, 4))
    for m in measures:
        mine = [r for r in rows if r["measure"] == m]
        ax.errorbar([r["n"] for r in mine], [r["power"] for r in mine], yerr=[1.96 * r["se"] for r in mine], marker="o", capsize=3, label=m)
    ax.axhline(0.8, color="grey", linestyle="--", linewidth=1)
    ax.set_xlabel("subjects")
    ax.set_ylabel(f"P(Friedman p < {alpha})")
    ax.set_ylim(0, 1)
    ax.set_title(f"virtual baseline's power ({pooled} virtual subjects, {replicates} replicates)", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "power.png"), dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folder")
    parser.add_argument("--subjects", default="6-24")
    parser.add_argument("--step", type=int, default=2)
    parser.add_argument("--draws", type=int, default=2000)
    parser.add_argument("--alpha", type=float, default=0.05)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--point", default="", help="a sweep's grid point: AXIS=VALUE,...")
    parser.add_argument("--out")
    a = parser.parse_args()
    try:
        sizes = sizes_of(a.subjects, a.step)
        data, censored, conditions, replicates = pool(a.folder, a.point)
        pooled = len(next(iter(data.values())))
        if pooled < max(sizes):
            raise analyze.InputError(a.folder, f"{pooled} virtual subjects in {replicates} replicates, fewer than the {max(sizes)} asked for",
                                     "run more replicates (--replicates N resumes and adds), or ask for fewer subjects")
        if pooled < 4 * max(sizes):
            print(f"power.py: warning: {pooled} pooled subjects for studies of up to {max(sizes)}: the draws share most of their subjects; "
                  f"about {4 * max(sizes)} make the power at {max(sizes)} well known", file=sys.stderr)
        rows = power_table(data, censored, conditions, sizes, a.draws, a.alpha, a.seed)
    except analyze.InputError as e:
        print(f"power.py: error: {e}", file=sys.stderr)
        return 1
    out = a.out or os.path.join(a.folder, "power")
    write(rows, out, pooled, replicates, a.alpha)
    measures = list(dict.fromkeys(r["measure"] for r in rows))
    print(f"the virtual baseline's power (not people's): P(Friedman p < {a.alpha}) across {', '.join(conditions)}, "
          f"{a.draws} studies per size drawn from {pooled} virtual subjects of {replicates} replicates")
    print("subjects " + "".join(f"{m:>15}" for m in measures))
    for n in sizes:
        cells = "".join(f"{r['power']:>8.2f} ({r['se']:.2f})" for m in measures for r in rows if r["n"] == n and r["measure"] == m)
        print(f"{n:>8} {cells}")
    print(f"wrote {out}/power.csv and {out}/power.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
