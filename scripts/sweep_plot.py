#!/usr/bin/python3
"""A sweep's measures per grid point, with their intervals.

usage: sweep_plot.py DIR [--measure ratio] [--out DIR/plots]

DIR is the folder of `enact sweep FILE --out DIR` (docs/experiments.md, "Sweeps"): its merged
DIR/results.csv (the grid's coordinates first, then each job's rows) and DIR/manifest.json
(the grid). For each grid point and condition, a job's value is the mean of its subjects';
the point's value is the mean over its replicates with a 95 % t interval (a point of one
replicate has none). The first axis of the grid is the x axis, one line per value of the
other axes and condition. Writes OUT/<measure>.png and OUT/<measure>.csv (the table, also
printed). Needs Debian's python3-matplotlib (scripts/setup.sh) for the figure.
"""
import argparse
import csv
import json
import math
import os
import sys

MEASURES = ["falls", "time_total_s", "time_out_s", "ratio", "completed"]


def t_quantile(df):
    """the two-sided 95 % quantile of Student's t with df degrees of freedom"""
    try:
        from scipy import stats
        return float(stats.t.ppf(0.975, df))
    except ImportError:
        table = {1: 12.706, 2: 4.303, 3: 3.182, 4: 2.776, 5: 2.571, 6: 2.447, 7: 2.365, 8: 2.306, 9: 2.262, 10: 2.228}
        return table.get(df, 1.96 + 2.5 / df)


def load(folder, measure):
    """the grid's axes, and {(point, condition): [job means]} in the grid's order"""
    manifest_path = os.path.join(folder, "manifest.json")
    results_path = os.path.join(folder, "results.csv")
    for path in (manifest_path, results_path):
        if not os.path.isfile(path):
            sys.exit(f"sweep_plot.py: {path}: not there\n  fix: give the folder of a sweep (enact sweep FILE --out DIR) once it ran")
    with open(manifest_path) as f:
        axes = list(json.load(f)["grid"].keys())
    jobs = {}
    with open(results_path) as f:
        reader = csv.DictReader(f)
        if measure not in (reader.fieldnames or []):
            sys.exit(f"sweep_plot.py: {results_path}:1: no column '{measure}'\n  fix: give --measure one of {', '.join(MEASURES)}")
        for line, row in enumerate(reader, start=2):
            try:
                value = float(row[measure])
            except ValueError:
                sys.exit(f"sweep_plot.py: {results_path}:{line}: '{row[measure]}' is not a number ({measure})")
            point = tuple(row[a] for a in axes)
            key = (point, row["condition"], row["replicate"])
            jobs.setdefault(key, []).append(value)
    by_point = {}
    for (point, condition, _), values in jobs.items():
        by_point.setdefault((point, condition), []).append(sum(values) / len(values))
    return axes, by_point


def summary(values):
    """mean, half-width of its 95 % t interval (nan with one value), n"""
    n = len(values)
    mean = sum(values) / n
    if n < 2:
        return mean, float("nan"), n
    sd = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1))
    return mean, t_quantile(n - 1) * sd / math.sqrt(n), n


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("dir", help="the sweep's folder (enact sweep --out DIR)")
    p.add_argument("--measure", default="ratio", help="the column of results.csv to draw (default ratio: time out / total)")
    p.add_argument("--out", help="where the figure and table go (default DIR/plots)")
    a = p.parse_args()
    axes, by_point = load(a.dir, a.measure)
    if not by_point:
        sys.exit(f"sweep_plot.py: {a.dir}/results.csv holds no job's rows yet\n  fix: run the sweep (enact sweep FILE --out {a.dir})")
    out = a.out or os.path.join(a.dir, "plots")
    os.makedirs(out, exist_ok=True)
    rows = [(point, condition, *summary(values)) for (point, condition), values in by_point.items()]
    table = os.path.join(out, f"{a.measure}.csv")
    with open(table, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow([*axes, "condition", "mean", "ci95_half", "replicates"])
        for point, condition, mean, half, n in rows:
            w.writerow([*point, condition, f"{mean:.6g}", "" if math.isnan(half) else f"{half:.6g}", n])
    print(f"{'  '.join(axes)}  condition  {a.measure} (mean +- 95 % CI, replicates)")
    for point, condition, mean, half, n in rows:
        print(f"{'  '.join(point)}  {condition}  {mean:.4g} +- {'-' if math.isnan(half) else f'{half:.3g}'}  ({n})")
    print(f"table: {table}")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("sweep_plot.py: matplotlib is not installed (apt-get install python3-matplotlib; scripts/setup.sh): the table only", file=sys.stderr)
        return 0
    # x: the first axis's values in the grid's order; a line per other coordinates and condition
    xs = list(dict.fromkeys(point[0] for point, *_ in rows))
    lines = {}
    for point, condition, mean, half, n in rows:
        # the condition named unless an axis is the model (then it is that axis's value)
        # (a path's file name: the table keeps the whole path)
        label = ", ".join([f"{ax}={os.path.basename(v) if os.sep in v else v}" for ax, v in zip(axes[1:], point[1:])] +
                          ([] if "model" in axes else [condition])) or condition
        lines.setdefault(label, []).append((xs.index(point[0]), mean, 0.0 if math.isnan(half) else half))
    fig, ax = plt.subplots(figsize=(7, 4.5))
    shift = 0.08 * (len(lines) > 1)
    for i, (label, points) in enumerate(lines.items()):
        offset = (i - (len(lines) - 1) / 2) * shift
        ax.errorbar([x + offset for x, _, _ in points], [m for _, m, _ in points], yerr=[h for _, _, h in points], marker="o", capsize=3, label=label)
    ax.set_xticks(range(len(xs)))
    ax.set_xticklabels(xs)
    ax.set_xlabel(axes[0] if axes else "")
    ax.set_ylabel(f"{a.measure} (mean, 95 % CI over replicates)")
    ax.set_title(os.path.basename(os.path.normpath(a.dir)))
    ax.legend(fontsize="small")
    fig.tight_layout()
    figure = os.path.join(out, f"{a.measure}.png")
    fig.savefig(figure, dpi=120)
    print(f"figure: {figure}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
