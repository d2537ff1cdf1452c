#!/usr/bin/python3
"""Do real-time runs of an experiment agree with its simulated-time run?

usage: agreement.py SIMULATED.csv OTHER.csv [OTHER.csv ...] [--measures falls,time_out]
                    [--level 0.95] [--alpha 0.05] [--resamples 10000] [--seed 1] [--json FILE]

SIMULATED.csv is `enact experiment FILE --clock simulated`'s results.csv; each OTHER.csv the
same experiment (the same plan: subjects, conditions, seeds) run another way, e.g. in real
time on the co-located and on the distributed graph. For each measure asked for and each
condition, the simulated run's interval of the mean at --level is computed by the bootstrap
over subjects (the subjects drawn with replacement, --resamples times, the percentile
interval; Efron & Tibshirani 1993, ch. 13). A run agrees when:
- each condition's mean lies inside the simulated run's interval, and
- Friedman's test across the conditions (scripts/analyze.py's, censored total times ranked
  as ties at the limit) reaches the same conclusion at --alpha (p < alpha in both or in
  neither) for each measure.
Prints one table per run (the simulated mean and interval, the run's mean, inside or not; the
two Friedman p) and a verdict; --json writes every figure. Exit status: 0 every run agrees,
1 one does not (each disagreement named), 2 bad input (the file, the line and the fix).
"""
import argparse
import json
import random
import sys
import os

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import analyze  # noqa: E402  (same folder: the loading and the statistics are analyze.py's)

MEASURE_NAMES = [name for name, _, _ in analyze.MEASURES]


def bootstrap_interval(values, level, resamples, rng):
    """the percentile interval of the mean of `values` at `level`, over subjects drawn with
    replacement"""
    n = len(values)
    means = sorted(sum(rng.choices(values, k=n)) / n for _ in range(resamples))
    tail = (1.0 - level) / 2.0
    low = means[int(tail * (resamples - 1))]
    high = means[int(round((1.0 - tail) * (resamples - 1)))]
    return low, high


def read_run(path):
    data, conditions, _, censored = analyze.load(path, None)
    return {"path": path, "data": data, "conditions": conditions, "censored": censored}


def check_same_plan(reference, other):
    if other["conditions"] != reference["conditions"]:
        raise analyze.InputError(other["path"], f"conditions {other['conditions']} differ from {reference['path']}'s {reference['conditions']}",
                                 "compare runs of the same experiment file")
    subjects, theirs = sorted(reference["data"]["falls"]), sorted(other["data"]["falls"])
    if subjects != theirs:
        raise analyze.InputError(other["path"], f"subjects {theirs} differ from {reference['path']}'s {subjects}",
                                 "compare runs of the same experiment file (the same subjects and seeds)")


def friedman_p(run, measure):
    result = analyze.analyze({measure: run["data"][measure]}, run["conditions"], run["censored"])
    test = result["measures"][measure]["friedman"]
    return None if test is None else test["p"]


def compare(reference, other, measures, intervals, alpha):
    """every figure of one run against the simulated one, and what disagrees"""
    rows, problems = [], []
    for measure in measures:
        for condition in reference["conditions"]:
            column = [v[condition] for v in other["data"][measure].values()]
            mean = sum(column) / len(column)
            low, high, sim_mean = intervals[(measure, condition)]
            inside = low <= mean <= high
            rows.append({"measure": measure, "condition": condition, "simulated_mean": sim_mean, "low": low, "high": high, "mean": mean, "inside": inside})
            if not inside:
                problems.append(f"{measure} {condition}: mean {mean:.4g} outside the simulated run's interval [{low:.4g}, {high:.4g}]")
        p_sim, p_other = friedman_p(reference, measure), friedman_p(other, measure)
        same = (p_sim is not None and p_sim < alpha) == (p_other is not None and p_other < alpha)
        rows.append({"measure": measure, "friedman_p_simulated": p_sim, "friedman_p": p_other, "same_conclusion": same})
        if not same:
            problems.append(f"{measure}: Friedman p {analyze.fmt(p_other)} against the simulated run's {analyze.fmt(p_sim)}: "
                            f"not the same conclusion at {alpha}")
    return rows, problems


def print_table(path, rows, level, alpha):
    print(f"\n{path} against the simulated run ({level:.0%} bootstrap interval of each mean; Friedman at {alpha}):")
    print(f"{'measure':<11} {'condition':<9} {'simulated':>10} {'interval':>21} {'this run':>10}  inside")
    for r in rows:
        if "condition" in r:
            interval = f"[{r['low']:.4g}, {r['high']:.4g}]"
            print(f"{r['measure']:<11} {r['condition']:<9} {r['simulated_mean']:>10.4g} {interval:>21} {r['mean']:>10.4g}  {'yes' if r['inside'] else 'NO'}")
        else:
            print(f"{r['measure']:<11} Friedman p: simulated {analyze.fmt(r['friedman_p_simulated'])}, this run {analyze.fmt(r['friedman_p'])}: "
                  f"{'the same conclusion' if r['same_conclusion'] else 'NOT the same conclusion'}")


def parse_measures(text):
    measures = [m.strip() for m in text.split(",") if m.strip()]
    unknown = [m for m in measures if m not in MEASURE_NAMES]
    if unknown or not measures:
        raise analyze.InputError("--measures", f"'{text}'", f"name some of {', '.join(MEASURE_NAMES)}, separated by commas")
    return measures


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], epilog="Exit status: 0 agree, 1 disagree, 2 bad input.")
    parser.add_argument("simulated", help="results.csv of the simulated-time run")
    parser.add_argument("others", nargs="+", help="results.csv of each run to compare with it")
    parser.add_argument("--measures", default="falls,time_out", help="measures compared (default falls,time_out; also time_total, ratio)")
    parser.add_argument("--level", type=float, default=0.95, help="the interval's level (default 0.95)")
    parser.add_argument("--alpha", type=float, default=0.05, help="Friedman's significance level (default 0.05)")
    parser.add_argument("--resamples", type=int, default=10000, help="bootstrap resamples (default 10000)")
    parser.add_argument("--seed", type=int, default=1, help="the bootstrap's random seed (default 1)")
    parser.add_argument("--json", help="write every figure to this file")
    a = parser.parse_args(argv)
    try:
        if not 0.0 < a.level < 1.0 or not 0.0 < a.alpha < 1.0 or a.resamples < 100:
            raise analyze.InputError("options", f"--level {a.level}, --alpha {a.alpha}, --resamples {a.resamples}",
                                     "give 0 < level < 1, 0 < alpha < 1 and at least 100 resamples")
        measures = parse_measures(a.measures)
        reference = read_run(a.simulated)
        others = [read_run(p) for p in a.others]
        for other in others:
            check_same_plan(reference, other)
    except analyze.InputError as e:
        print(f"agreement.py: {e}", file=sys.stderr)
        return 2
    rng = random.Random(a.seed)
    intervals = {}
    for measure in measures:
        for condition in reference["conditions"]:
            column = [v[condition] for v in reference["data"][measure].values()]
            low, high = bootstrap_interval(column, a.level, a.resamples, rng)
            intervals[(measure, condition)] = (low, high, sum(column) / len(column))
    report, failed = {"simulated": a.simulated, "level": a.level, "alpha": a.alpha, "runs": {}}, []
    for other in others:
        rows, problems = compare(reference, other, measures, intervals, a.alpha)
        print_table(other["path"], rows, a.level, a.alpha)
        report["runs"][other["path"]] = {"rows": rows, "problems": problems, "agrees": not problems}
        failed += [f"{other['path']}: {p}" for p in problems]
    if a.json:
        with open(a.json, "w", encoding="utf-8") as f:
            json.dump(report, f, indent=1)
    if failed:
        print("\nagreement.py: disagree:\n  " + "\n  ".join(failed))
        return 1
    print(f"\nagreement.py: every run agrees with the simulated one ({', '.join(measures)}: each condition's mean inside the "
          f"simulated {a.level:.0%} interval, the same Friedman conclusions at {a.alpha})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
