#!/usr/bin/python3
"""Statistics and figure of a bridge experiment (`enact experiment`'s results.csv).

usage: analyze.py RESULTS.csv --out DIR [--ranking RANKING.csv]

For each measure (falls, time_out, time_total, ratio, and ranking when present) over the
subjects who did every condition:
- mean, SD (sample, n - 1) and median per condition;
- Friedman's test across the conditions (3 or more): the chi-square statistic with the
  correction for ties within a subject, its p from the chi-square distribution with k - 1
  degrees of freedom (the large-sample approximation, as in most texts and in R's
  friedman.test), and Kendall's W = chi2 / (n (k - 1));
- Wilcoxon's signed-rank test for every pair of conditions, two-tailed. Zero differences
  are dropped and n reduced (Wilcoxon's own method; Siegel & Castellan 1988). Tied |d| get
  their average rank. Up to 50 nonzero differences the p is exact: the null distribution of
  W+ over the 2^n sign assignments of the ranks actually observed (average ranks included,
  so exact with ties too: the permutation distribution conditional on the ties), counted by
  dynamic programming; beyond 50, the normal approximation with the tie correction of the
  variance and a continuity correction of 0.5. W+ and W- are both given; p before and after
  the Bonferroni correction (times the number of pairs, at most 1).
Writes DIR/report.md (tables), DIR/stats.json (every statistic and p, keyed by measure and
pair "A-B") and DIR/figure.png (one panel per measure, mean +- SD per condition, in the
style of Fig. 4 of Khatchatourov et al. 2009). Prints the summary table.

Censored trials: a trial that reached its time limit (completed = 0) has a time_total that
is only a lower bound (the subject would have taken longer). They are counted per condition
(report, summary, stats.json "censored"), and their time_total is ranked as a tie at the
limit (the largest time_total in the file) for Friedman and Wilcoxon, and so described: a
censored-censored pair is a zero difference, a censored trial is slower than every completed
one. Means with censored trials are lower bounds; the figure marks each censored trial
(a triangle at the limit). Falls and time out are counted up to the limit as they are.

The ranking: a `ranking` column in RESULTS.csv, or RANKING.csv (subject,condition,rank),
by default ranking.csv next to RESULTS.csv when it exists. Rank 1 is the preferred
condition.
"""
import argparse
import csv
import itertools
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from scipy import stats  # noqa: E402

# the measures: name, results.csv column, axis label
MEASURES = (
    ("falls", "falls", "falls"),
    ("time_out", "time_out_s", "time out (s)"),
    ("time_total", "time_total_s", "total time (s)"),
    ("ratio", "ratio", "time out / total time"),
)
COLUMNS = ("subject", "condition", "order", "falls", "time_total_s", "time_out_s", "ratio", "completed")
EXACT_MAX_N = 50


class InputError(Exception):
    """Bad input: "FILE:LINE: problem" and a fix."""

    def __init__(self, where, problem, fix):
        super().__init__(f"{where}: {problem}\n  fix: {fix}")


# ---------------------------------------------------------------------------------------
# reading

def read_csv(path, required, what):
    """rows of a CSV file as (line, dict), the header checked for the required columns"""
    try:
        with open(path, newline="", encoding="utf-8") as f:
            reader = csv.DictReader(f)
            header = reader.fieldnames or []
            missing = [c for c in required if c not in header]
            if missing:
                raise InputError(f"{path}:1", f"the header lacks {', '.join(missing)}",
                                 f"the first line of {what} is {','.join(required)}")
            return [(reader.line_num, row) for row in reader]
    except FileNotFoundError:
        raise InputError(path, "no such file", f"give the {what} file") from None


def number(path, line, row, column):
    text = (row.get(column) or "").strip()
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"{path}:{line}", f"{column} is '{text}', not a number", f"write a number in {column}") from None
    if not math.isfinite(value):
        raise InputError(f"{path}:{line}", f"{column} is {text}", f"write a finite number in {column}")
    return value


# the measure whose censored values (completed = 0) are ranked as ties at the limit
CENSORED_MEASURE = "time_total"


def load(results_path, ranking_path):
    """{measure: {subject: {condition: value}}}, the conditions in order, the number of
    trials and {subject: {condition: censored}} (completed = 0)"""
    rows = read_csv(results_path, COLUMNS, "results.csv")
    if not rows:
        raise InputError(results_path, "no trials", "run the experiment first (enact experiment)")
    data = {name: {} for name, _, _ in MEASURES}
    censored = {}
    seen = {}
    conditions = []
    has_ranking_column = "ranking" in rows[0][1]
    if has_ranking_column:
        data["ranking"] = {}
    for line, row in rows:
        subject, condition = row["subject"].strip(), row["condition"].strip()
        if not subject or not condition:
            raise InputError(f"{results_path}:{line}", "subject or condition is empty", "give both")
        if (subject, condition) in seen:
            raise InputError(f"{results_path}:{line}", f"subject {subject} has condition {condition} twice (line {seen[(subject, condition)]})",
                             "keep one measured trial per subject and condition")
        seen[(subject, condition)] = line
        if condition not in conditions:
            conditions.append(condition)
        for name, column, _ in MEASURES:
            data[name].setdefault(subject, {})[condition] = number(results_path, line, row, column)
        censored.setdefault(subject, {})[condition] = number(results_path, line, row, "completed") == 0
        if has_ranking_column and (row.get("ranking") or "").strip():
            data["ranking"].setdefault(subject, {})[condition] = number(results_path, line, row, "ranking")
    if ranking_path and not has_ranking_column:
        data["ranking"] = {}
        for line, row in read_csv(ranking_path, ("subject", "condition", "rank"), "ranking.csv"):
            data["ranking"].setdefault(row["subject"].strip(), {})[row["condition"].strip()] = number(ranking_path, line, row, "rank")
    return data, sorted(conditions), len(rows), censored


# ---------------------------------------------------------------------------------------
# statistics

def describe(values):
    n = len(values)
    mean = sum(values) / n
    sd = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1)) if n > 1 else None
    ordered = sorted(values)
    median = (ordered[(n - 1) // 2] + ordered[n // 2]) / 2
    return {"n": n, "mean": mean, "sd": sd, "median": median}


def friedman(columns):
    """Friedman's chi-square (ties corrected) over k columns of n paired values"""
    k, n = len(columns), len(columns[0])
    result = {"k": k, "n": n, "df": k - 1, "statistic": None, "p": None, "kendall_w": None, "note": ""}
    if k < 3:
        result["note"] = "needs 3 or more conditions"
        return result
    if n < 2:
        result["note"] = "needs 2 or more subjects"
        return result
    blocks = list(zip(*columns))
    if all(len(set(b)) == 1 for b in blocks):
        result["note"] = "every subject has the same value in every condition"
        return result
    chi2, p = stats.friedmanchisquare(*columns)
    result.update(statistic=float(chi2), p=float(p), kendall_w=float(chi2) / (n * (k - 1)))
    return result


def exact_upper_tail(ranks, w):
    """P(W+ >= w) under the null: each rank's sign a fair coin, over the ranks given (average
    ranks of ties included: they are counted in halves)"""
    doubled = [int(round(2 * r)) for r in ranks]
    counts = [0] * (sum(doubled) + 1)
    counts[0] = 1
    for r in doubled:
        for total in range(len(counts) - 1, r - 1, -1):
            counts[total] += counts[total - r]
    at_least = int(math.ceil(2 * w - 1e-9))
    return sum(counts[at_least:]) / 2 ** len(doubled)


def wilcoxon(a, b):
    """Wilcoxon's signed-rank test of a - b, two-tailed (choices in the module docstring)"""
    d = [x - y for x, y in zip(a, b)]
    nonzero = [v for v in d if v != 0]
    n = len(nonzero)
    result = {"n": n, "zeros": len(d) - n, "w_plus": None, "w_minus": None, "statistic": None,
              "method": None, "z": None, "p": 1.0, "note": ""}
    if n == 0:
        result["note"] = "every difference is zero"
        return result
    ranks = [float(r) for r in stats.rankdata([abs(v) for v in nonzero])]
    w_plus = sum(r for r, v in zip(ranks, nonzero) if v > 0)
    w_minus = n * (n + 1) / 2 - w_plus
    result.update(w_plus=w_plus, w_minus=w_minus, statistic=min(w_plus, w_minus))
    if n <= EXACT_MAX_N:
        result.update(method="exact", p=min(1.0, 2 * exact_upper_tail(ranks, max(w_plus, w_minus))))
        return result
    # normal approximation: variance reduced for tied |d|, continuity correction 0.5
    mean = n * (n + 1) / 4
    ties = {}
    for r in ranks:
        ties[r] = ties.get(r, 0) + 1
    variance = n * (n + 1) * (2 * n + 1) / 24 - sum(t ** 3 - t for t in ties.values()) / 48
    z = max(0.0, (abs(w_plus - mean) - 0.5) / math.sqrt(variance))
    result.update(method="normal", z=z, p=min(1.0, 2 * stats.norm.sf(z)))
    return result


def at_the_limit(by_subject, censored):
    """the values with every censored one replaced by the limit (the largest value), and
    the limit; None when nothing is censored"""
    flagged = [(s, c) for s, values in by_subject.items() for c in values if censored.get(s, {}).get(c)]
    if not flagged:
        return by_subject, None
    limit = max(v for values in by_subject.values() for v in values.values())
    tied = {s: dict(values) for s, values in by_subject.items()}
    for s, c in flagged:
        tied[s][c] = limit
    return tied, limit


def analyze(data, conditions, censored=None):
    """every statistic, keyed by measure and pair; censored: {subject: {condition: bool}}"""
    censored = censored or {}
    out = {"conditions": conditions, "measures": {}}
    for measure, by_subject in data.items():
        complete = sorted(s for s, values in by_subject.items() if all(c in values for c in conditions))
        dropped = sorted(s for s in by_subject if s not in complete)
        entry = {"subjects": complete, "dropped_subjects": dropped, "conditions": {}, "friedman": None, "pairs": {},
                 "censored": {c: sum(bool(censored.get(s, {}).get(c)) for s in complete) for c in conditions}, "censored_at": None}
        out["measures"][measure] = entry
        if not complete:
            continue
        if measure == CENSORED_MEASURE:
            by_subject, entry["censored_at"] = at_the_limit({s: by_subject[s] for s in complete}, censored)
        columns = [[by_subject[s][c] for s in complete] for c in conditions]
        for c, column in zip(conditions, columns):
            entry["conditions"][c] = describe(column)
        entry["friedman"] = friedman(columns)
        pairs = list(itertools.combinations(range(len(conditions)), 2))
        for i, j in pairs:
            w = wilcoxon(columns[i], columns[j])
            w["p_bonferroni"] = min(1.0, w["p"] * len(pairs))
            entry["pairs"][f"{conditions[i]}-{conditions[j]}"] = w
    return out


# ---------------------------------------------------------------------------------------
# writing

def fmt(value, digits=3):
    """fixed digits; a p-value (digits 4) below 1e-4 in scientific notation"""
    if value is None:
        return "-"
    if isinstance(value, int):
        return str(value)
    if digits >= 4 and 0 < value < 1e-4:
        return f"{value:.1e}"
    return f"{value:.{digits}f}"


def censoring_note(entry):
    """what was done with the censored trials of a measure, "" when none"""
    if entry["censored_at"] is None:
        return ""
    counts = ", ".join(f"{c} {n}" for c, n in entry["censored"].items())
    return (f"censored (not completed: time_total only a lower bound): {counts}; ranked as ties at the limit "
            f"{fmt(entry['censored_at'])} s for Friedman and Wilcoxon; the means are lower bounds")


def summary_table(result):
    """one line per measure: mean (SD) per condition and Friedman's p; then the censoring"""
    conditions = result["conditions"]
    lines = [f"{'measure':<11}" + "".join(f"{c:>18}" for c in conditions) + f"{'Friedman p':>12}"]
    notes = []
    for measure, entry in result["measures"].items():
        if not entry["conditions"]:
            continue
        cells = "".join(f"{fmt(entry['conditions'][c]['mean']) + ' (' + fmt(entry['conditions'][c]['sd']) + ')':>18}" for c in conditions)
        lines.append(f"{measure:<11}{cells}{fmt(entry['friedman']['p']):>12}")
        if censoring_note(entry):
            notes.append(f"{measure}: {censoring_note(entry)}")
    return "\n".join(lines + ([""] + notes if notes else []))


def report(result, results_path, trials):
    conditions = result["conditions"]
    md = ["# Bridge experiment: statistics", "",
          f"From `{results_path}`: {trials} measured trials, conditions {', '.join(conditions)}.", "",
          "Friedman's test (chi-square approximation, ties corrected) across conditions; Wilcoxon's signed-rank "
          "test per pair, two-tailed, zero differences dropped, exact p up to n = 50 (over the observed ranks, ties "
          "included), else the normal approximation with tie and continuity corrections; Bonferroni over the pairs of a measure.", ""]
    for measure, entry in result["measures"].items():
        md += [f"## {measure}", ""]
        if not entry["conditions"]:
            md += ["No subject did every condition.", ""]
            continue
        md += [f"Subjects: {len(entry['subjects'])}" + (f" (left out, not every condition: {', '.join(entry['dropped_subjects'])})" if entry["dropped_subjects"] else ""), "",
               "| condition | n | mean | SD | median |", "|---|---|---|---|---|"]
        for c in conditions:
            d = entry["conditions"][c]
            md.append(f"| {c} | {d['n']} | {fmt(d['mean'])} | {fmt(d['sd'])} | {fmt(d['median'])} |")
        if censoring_note(entry):
            md += ["", censoring_note(entry).capitalize() + "."]
        f = entry["friedman"]
        md += ["", f"Friedman: chi2 = {fmt(f['statistic'])}, df = {f['df']}, p = {fmt(f['p'], 4)}, Kendall's W = {fmt(f['kendall_w'])}"
               + (f" ({f['note']})" if f["note"] else ""), "",
               "| pair | n (zeros dropped) | W+ | W- | method | z | p | p Bonferroni |", "|---|---|---|---|---|---|---|---|"]
        for pair, w in entry["pairs"].items():
            md.append(f"| {pair} | {w['n']} ({w['zeros']}) | {fmt(w['w_plus'], 1)} | {fmt(w['w_minus'], 1)} | {w['method'] or w['note']} | "
                      f"{fmt(w['z'])} | {fmt(w['p'], 4)} | {fmt(w['p_bonferroni'], 4)} |")
        md.append("")
    return "\n".join(md)


def figure(result, path):
    labels = {name: label for name, _, label in MEASURES}
    labels["ranking"] = "ranking (1 = preferred)"
    measures = [m for m, e in result["measures"].items() if e["conditions"]]
    conditions = result["conditions"]
    fig, axes = plt.subplots(1, len(measures), figsize=(3.2 * len(measures), 3.4), squeeze=False)
    for ax, measure in zip(axes[0], measures):
        entry = result["measures"][measure]
        means = [entry["conditions"][c]["mean"] for c in conditions]
        sds = [entry["conditions"][c]["sd"] or 0.0 for c in conditions]
        ax.bar(conditions, means, yerr=sds, capsize=4, color="0.75", edgecolor="black")
        ax.set_title(labels.get(measure, measure))
        # each censored trial: an open triangle at the limit, the counts under the axis
        if entry["censored_at"] is not None:
            for i, c in enumerate(conditions):
                n = entry["censored"][c]
                ax.plot([i] * n, [entry["censored_at"]] * n, linestyle="none", marker="^", markerfacecolor="none", markeredgecolor="black")
            ax.set_xticks(range(len(conditions)), [f"{c}\n({entry['censored'][c]} cens.)" for c in conditions], fontsize=8)
            ax.set_title(f"{labels.get(measure, measure)}\n(\u25b3 not completed: at the limit)", fontsize=10)
        ax.set_ylim(bottom=0)
        p = entry["friedman"]["p"]
        ax.set_xlabel(f"Friedman p = {p:.3g}" if p is not None else "Friedman: -", fontsize=9)
    fig.suptitle(f"mean +- SD per condition ({len(result['measures'][measures[0]]['subjects'])} subjects)" if measures else "no data")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv):
    parser = argparse.ArgumentParser(description="Friedman and Wilcoxon statistics and a figure from an experiment's results.csv")
    parser.add_argument("results", help="results.csv of enact experiment")
    parser.add_argument("--out", required=True, help="folder for report.md, stats.json, figure.png")
    parser.add_argument("--ranking", help="subject,condition,rank CSV (default: ranking.csv next to RESULTS.csv, if any)")
    args = parser.parse_args(argv)
    ranking = args.ranking
    if ranking is None:
        beside = os.path.join(os.path.dirname(os.path.abspath(args.results)), "ranking.csv")
        ranking = beside if os.path.exists(beside) else None
    try:
        data, conditions, trials, censored = load(args.results, ranking)
    except InputError as e:
        print(f"analyze.py: {e}", file=sys.stderr)
        return 1
    result = analyze(data, conditions, censored)
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "stats.json"), "w", encoding="utf-8") as f:
        json.dump(result, f, indent=2, allow_nan=False)
    with open(os.path.join(args.out, "report.md"), "w", encoding="utf-8") as f:
        f.write(report(result, args.results, trials) + "\n")
    figure(result, os.path.join(args.out, "figure.png"))
    print(summary_table(result))
    print(f"\nmean (SD) per condition; Wilcoxon pairs, p before and after Bonferroni: {os.path.join(args.out, 'report.md')}")
    print(f"every statistic: {os.path.join(args.out, 'stats.json')}; figure: {os.path.join(args.out, 'figure.png')}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
