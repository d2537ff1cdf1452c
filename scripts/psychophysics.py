#!/usr/bin/python3
"""Psychometric fits and figures of a discrimination experiment, with scipy.

usage:
  psychophysics.py fit DATA.csv --shape gaussian|weibull [--guess 0.5] [--lapse L | --max-lapse M] [--exponent E]
  psychophysics.py plot TRIALS.csv --out DIR [--shape gaussian|weibull] [--max-lapse M] [--exponent E]
  psychophysics.py group SUMMARY.csv

fit: DATA.csv has columns level,trials,correct. The maximum-likelihood fit of
  psi(x) = guess + (1 - guess - lapse) F(x), F a cumulative Gaussian (mean = threshold, sd =
  spread) or a Weibull 1 - exp(-ln2 (x / threshold)^spread), so that F(threshold) = 0.5 for
  both: the threshold is the JND. The guess rate is fixed; the lapse is fixed (--lapse) or
  fitted in [0, M] (--max-lapse, default 0.06); --exponent holds a Weibull's exponent. The likelihood is maximised by scipy's
  bounded Nelder-Mead over the natural parameters (threshold, spread, lapse) from the best
  point of a grid, then restarted from its optimum: an implementation independent of
  core/psychophysics/fit.cpp (another parametrisation, another optimiser), which
  tests/psychophysics compares with it. Prints JSON: threshold, spread, lapse,
  log_likelihood (without the binomial coefficients).

plot: TRIALS.csv is `enact experiment`'s trials.csv of a discrimination plan. One figure per
  subject and condition in DIR: the proportion correct at each level with binomial (Wilson
  95 %) error bars, marker area by the number of trials, and the fitted function.

group: SUMMARY.csv is `enact experiment`'s summary.csv. Per condition, the mean and SD
  (n - 1) of the fitted Weber fractions; for every pair of conditions, over the subjects who
  did both, Wilcoxon's signed-rank test (two-tailed; scipy's exact distribution without ties
  or zeros, else its normal approximation), p before and after Bonferroni. Prints JSON.
"""
import argparse
import csv
import json
import math
import os
import sys

import numpy as np
from scipy import optimize, stats


def core(shape, x, threshold, spread):
    x = np.asarray(x, dtype=float)
    if shape == "gaussian":
        return stats.norm.cdf((x - threshold) / spread)
    safe = np.maximum(x, 1e-300)
    return np.where(x > 0, -np.expm1(-math.log(2.0) * (safe / threshold) ** spread), 0.0)


def nll(params, shape, guess, data):
    threshold, spread, lapse = params
    if spread <= 0 or (shape == "weibull" and threshold <= 0):
        return np.inf
    p = guess + (1 - guess - lapse) * core(shape, data[:, 0], threshold, spread)
    p = np.clip(p, 1e-300, 1 - 1e-16)
    k, n = data[:, 2], data[:, 1]
    return -float(np.sum(k * np.log(p) + (n - k) * np.log1p(-p)))


def fit(data, shape, guess=0.5, lapse=None, max_lapse=0.06, exponent=None):
    levels = data[:, 0]
    low, high = float(levels.min()), float(levels.max())
    span = high - low if high > low else max(abs(high), 1.0)
    free = lapse is None
    fixed_lapse = 0.0 if free else lapse
    # a grid of starting points
    best, best_cost = None, np.inf
    thresholds = np.geomspace(low, high, 9) if shape == "weibull" else np.linspace(low, high, 9)
    spreads = [1.0, 2.0, 3.0, 4.0, 5.0] if shape == "weibull" else [span / 16 * 2 ** j for j in range(5)]
    for t in thresholds:
        for s in spreads:
            start = (t, exponent or s, min(0.01, max_lapse) if free else fixed_lapse)
            c = nll(start, shape, guess, data)
            if c < best_cost:
                best, best_cost = start, c
    lapse_bounds = (0.0, max_lapse) if free else (fixed_lapse, fixed_lapse)
    spread_bounds = (exponent, exponent) if exponent else (1e-12, None)
    bounds = [(1e-12 if shape == "weibull" else None, None), spread_bounds, lapse_bounds]
    x = np.array(best, dtype=float)
    for _ in range(10):
        r = optimize.minimize(nll, x, args=(shape, guess, data), method="Nelder-Mead", bounds=bounds,
                              options={"xatol": 1e-11, "fatol": 1e-13, "maxiter": 100000, "maxfev": 200000})
        moved = r.fun < best_cost - 1e-12
        x, best_cost = r.x, min(best_cost, r.fun)
        if not moved:
            break
    return {"threshold": float(x[0]), "spread": float(x[1]), "lapse": float(x[2]), "log_likelihood": -float(best_cost)}


def read_counts(path):
    rows = list(csv.DictReader(open(path, newline="")))
    return np.array([[float(r["level"]), float(r["trials"]), float(r["correct"])] for r in rows])


# fewer answers than this and a fit is warned about, as `enact experiment` does (kMinTrialsForFit,
# core/experiment/discrimination.h: 30 two-interval answers give a proportion correct near 75 %
# a 95 % interval of +-0.155, as wide as the step from 75 % to 90 % correct)
MIN_TRIALS = 30


def warn_few(trials, what):
    if trials < MIN_TRIALS:
        print("warning: %s: the fit rests on %d trials, fewer than %d: its threshold is unreliable" % (what, trials, MIN_TRIALS),
              file=sys.stderr)


def wilson(k, n, z=1.959964):
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return centre - half, centre + half


def plot(trials_path, out, shape, max_lapse, exponent):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    groups = {}
    for r in csv.DictReader(open(trials_path, newline="")):
        key = (r["subject"], r["condition"])
        level = abs(float(r["comparison"]) - float(r["reference"]))
        groups.setdefault(key, {}).setdefault(level, [0, 0])
        groups[key][level][0] += 1
        groups[key][level][1] += int(r["correct"])
    os.makedirs(out, exist_ok=True)
    for (subject, condition), by_level in sorted(groups.items()):
        data = np.array([[x, n, k] for x, (n, k) in sorted(by_level.items())])
        warn_few(int(data[:, 1].sum()), "subject %s, %s" % (subject, condition))
        f = fit(data, shape, max_lapse=max_lapse, exponent=exponent)
        fig, ax = plt.subplots(figsize=(5, 3.5))
        p = data[:, 2] / data[:, 1]
        lo_hi = np.array([wilson(k, n) for _, n, k in data])
        yerr = np.maximum(0.0, [p - lo_hi[:, 0], lo_hi[:, 1] - p])
        ax.errorbar(data[:, 0], p, yerr=yerr, fmt="none", ecolor="0.5", capsize=2)
        ax.scatter(data[:, 0], p, s=8 * data[:, 1], color="C0", zorder=3, label="answers")
        xs = np.linspace(max(1e-9, data[:, 0].min() * 0.8), data[:, 0].max() * 1.1, 200)
        ax.plot(xs, 0.5 + (0.5 - f["lapse"]) * core(shape, xs, f["threshold"], f["spread"]), color="C1",
                label="fit: JND %.4g" % f["threshold"])
        ax.axvline(f["threshold"], color="C1", ls=":")
        ax.set_xlabel("difference from the reference")
        ax.set_ylabel("proportion correct")
        ax.set_ylim(0.3, 1.02)
        ax.set_title("subject %s, %s" % (subject, condition))
        ax.legend(loc="lower right", fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "s%s_%s.png" % (subject, condition)), dpi=100)
        plt.close(fig)
    print("%d figures in %s" % (len(groups), out))


def group(summary_path):
    weber = {}
    for r in csv.DictReader(open(summary_path, newline="")):
        weber.setdefault(r["condition"], {})[r["subject"]] = float(r["weber_fraction"])
    conditions = list(weber)
    out = {"conditions": {}, "pairs": {}}
    for c in conditions:
        v = list(weber[c].values())
        out["conditions"][c] = {"subjects": len(v), "mean": float(np.mean(v)), "sd": float(np.std(v, ddof=1)) if len(v) > 1 else None}
    pairs = [(a, b) for i, a in enumerate(conditions) for b in conditions[i + 1:]]
    for a, b in pairs:
        both = sorted(set(weber[a]) & set(weber[b]))
        d = [weber[a][s] - weber[b][s] for s in both]
        r = stats.wilcoxon(d)
        out["pairs"]["%s-%s" % (a, b)] = {"subjects": len(both), "statistic": float(r.statistic), "p": float(r.pvalue),
                                          "p_bonferroni": min(1.0, float(r.pvalue) * len(pairs))}
    print(json.dumps(out, indent=1))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)
    f = sub.add_parser("fit")
    f.add_argument("data")
    f.add_argument("--shape", choices=["gaussian", "weibull"], default="gaussian")
    f.add_argument("--guess", type=float, default=0.5)
    f.add_argument("--lapse", type=float)
    f.add_argument("--max-lapse", type=float, default=0.06)
    f.add_argument("--exponent", type=float, help="hold the Weibull exponent at this value")
    p = sub.add_parser("plot")
    p.add_argument("trials")
    p.add_argument("--out", required=True)
    p.add_argument("--shape", choices=["gaussian", "weibull"], default="gaussian")
    p.add_argument("--max-lapse", type=float, default=0.06)
    p.add_argument("--exponent", type=float, help="hold the Weibull exponent at this value")
    g = sub.add_parser("group")
    g.add_argument("summary")
    a = ap.parse_args()
    if a.command == "fit":
        counts = read_counts(a.data)
        warn_few(int(counts[:, 1].sum()), a.data)
        print(json.dumps(fit(counts, a.shape, a.guess, a.lapse, a.max_lapse, a.exponent)))
    elif a.command == "plot":
        plot(a.trials, a.out, a.shape, a.max_lapse, a.exponent)
    else:
        group(a.summary)
    return 0


if __name__ == "__main__":
    sys.exit(main())
