#!/usr/bin/python3
"""scripts/analyze.py against textbook examples with published results, its handling of
zero differences, ties and the Bonferroni correction, its files, and bad input."""
import csv
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "..", "scripts", "analyze.py")
spec = importlib.util.spec_from_file_location("analyze", SCRIPT)
analyze = importlib.util.module_from_spec(spec)
spec.loader.exec_module(analyze)

# Hollander & Wolfe, Nonparametric Statistical Methods (2nd ed. 1999), Table 7.1, p. 274:
# times (s) of 22 baseball players rounding first base by three methods (round out, narrow
# angle, wide angle). Friedman's statistic with ties: 11.14, p = 0.0038 (also the example of
# R's friedman.test: chi-squared = 11.143, df = 2, p-value = 0.003805).
FIRST_BASE = [
    (5.40, 5.50, 5.55), (5.85, 5.70, 5.75), (5.20, 5.60, 5.50), (5.55, 5.50, 5.40), (5.90, 5.85, 5.70),
    (5.45, 5.55, 5.60), (5.40, 5.40, 5.35), (5.45, 5.50, 5.35), (5.25, 5.15, 5.00), (5.85, 5.80, 5.70),
    (5.25, 5.20, 5.10), (5.65, 5.55, 5.45), (5.60, 5.35, 5.45), (5.05, 5.00, 4.95), (5.50, 5.50, 5.40),
    (5.45, 5.55, 5.50), (5.55, 5.55, 5.35), (5.45, 5.50, 5.55), (5.50, 5.45, 5.25), (5.65, 5.60, 5.40),
    (5.70, 5.65, 5.55), (6.30, 6.30, 6.25),
]

# Hollander, Wolfe & Chicken, Nonparametric Statistical Methods (3rd ed. 2014), Example 3.1
# (1st ed. 1973, p. 29): Hamilton depression scale factor IV of 9 patients at the first (x)
# and second (y) visit. T+ = 40; exact upper-tail P(T+ >= 40) = 0.0195, two-tailed 0.039
# (R's wilcox.test example: V = 40).
DEPRESSION_X = [1.83, 0.50, 1.62, 2.48, 1.68, 1.88, 1.55, 3.06, 1.30]
DEPRESSION_Y = [0.878, 0.647, 0.598, 2.05, 1.06, 1.29, 1.06, 3.14, 1.29]

METHODS = ("round_out", "narrow", "wide")


def write_results(path, rows):
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(analyze.COLUMNS)
        w.writerows(rows)


def run_script(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


class Friedman(unittest.TestCase):
    def test_first_base_published_statistic(self):
        columns = [[row[i] for row in FIRST_BASE] for i in range(3)]
        f = analyze.friedman(columns)
        self.assertAlmostEqual(f["statistic"], 11.143, places=3)
        self.assertAlmostEqual(f["p"], 0.003805, places=6)
        self.assertEqual(f["df"], 2)
        self.assertAlmostEqual(f["kendall_w"], 11.142857 / (22 * 2), places=5)

    def test_first_base_through_results_csv(self):
        # the same data as an experiment's total times, rows shuffled by method
        with tempfile.TemporaryDirectory() as d:
            rows = [(s + 1, METHODS[i], i + 1, 0, t, 0, 0, 1) for s, times in enumerate(FIRST_BASE) for i, t in enumerate(times)]
            write_results(os.path.join(d, "results.csv"), list(reversed(rows)))
            r = run_script(os.path.join(d, "results.csv"), "--out", os.path.join(d, "out"))
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(d, "out", "stats.json"), encoding="utf-8") as f:
                result = json.load(f)
            friedman = result["measures"]["time_total"]["friedman"]
            self.assertAlmostEqual(friedman["statistic"], 11.143, places=3)
            self.assertAlmostEqual(friedman["p"], 0.003805, places=6)
            self.assertIsNone(result["measures"]["falls"]["friedman"]["p"], "all zero falls: no test")
            self.assertIn("time_total", r.stdout)
            for name in ("report.md", "stats.json", "figure.png"):
                self.assertTrue(os.path.getsize(os.path.join(d, "out", name)) > 0, name)
            with open(os.path.join(d, "out", "figure.png"), "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")

    def test_two_conditions_have_no_friedman(self):
        self.assertIsNone(analyze.friedman([[1, 2, 3], [2, 3, 4]])["p"])


class Wilcoxon(unittest.TestCase):
    def test_depression_published_statistic(self):
        w = analyze.wilcoxon(DEPRESSION_X, DEPRESSION_Y)
        self.assertEqual(w["w_plus"], 40)
        self.assertEqual(w["w_minus"], 5)
        self.assertEqual(w["method"], "exact")
        self.assertAlmostEqual(w["p"], 0.0390625, places=7)
        # the published one-tailed value
        self.assertAlmostEqual(analyze.exact_upper_tail(list(range(1, 10)), 40), 0.0195, places=4)

    def test_zero_differences_are_dropped(self):
        w = analyze.wilcoxon(DEPRESSION_X + [1.0, 2.0, 3.0], DEPRESSION_Y + [1.0, 2.0, 3.0])
        self.assertEqual(w["n"], 9)
        self.assertEqual(w["zeros"], 3)
        self.assertEqual(w["w_plus"], 40)
        self.assertAlmostEqual(w["p"], 0.0390625, places=7)

    def test_all_zero_differences_give_no_evidence(self):
        w = analyze.wilcoxon([1, 2, 3], [1, 2, 3])
        self.assertEqual(w["p"], 1.0)
        self.assertIsNone(w["w_plus"])

    def test_ties_are_exact_over_the_observed_ranks(self):
        # d = 1, 1, 1, 2, -2, 3: |d| ranks 2, 2, 2, 4.5, 4.5, 6; W+ = 16.5, n = 6
        a = [2, 3, 4, 7, 5, 9]
        b = [1, 2, 3, 5, 7, 6]
        w = analyze.wilcoxon(a, b)
        self.assertEqual(w["method"], "exact")
        self.assertEqual(w["w_plus"], 16.5)
        # by brute force: every one of the 2^6 sign assignments of those ranks
        ranks = [2, 2, 2, 4.5, 4.5, 6]
        sums = [sum(r for r, bit in zip(ranks, range(6)) if mask >> bit & 1) for mask in range(64)]
        self.assertAlmostEqual(w["p"], 2 * sum(s >= 16.5 for s in sums) / 64, places=12)

    def test_more_than_50_use_the_normal_approximation_with_corrections(self):
        # 60 pairs: d = 1 (x20), -1 (x10), 2 (x30): ties throughout
        d = [1] * 20 + [-1] * 10 + [2] * 30
        w = analyze.wilcoxon(d, [0] * len(d))
        self.assertEqual(w["method"], "normal")
        n = 60
        # |d| = 1 takes ranks 1..30 (mean 15.5), |d| = 2 ranks 31..60 (mean 45.5)
        self.assertEqual(w["w_plus"], 20 * 15.5 + 30 * 45.5)
        variance = n * (n + 1) * (2 * n + 1) / 24 - ((30 ** 3 - 30) + (30 ** 3 - 30)) / 48
        z = (w["w_plus"] - n * (n + 1) / 4 - 0.5) / variance ** 0.5
        self.assertAlmostEqual(w["z"], z, places=12)
        self.assertAlmostEqual(w["p"], 2 * analyze.stats.norm.sf(z), places=12)

    def test_bonferroni_multiplies_by_the_pairs(self):
        data = {"falls": {str(s): {c: v for c, v in zip(METHODS, row)} for s, row in enumerate(FIRST_BASE)}}
        result = analyze.analyze(data, list(METHODS))
        pairs = result["measures"]["falls"]["pairs"]
        self.assertEqual(sorted(pairs), ["narrow-wide", "round_out-narrow", "round_out-wide"])
        for w in pairs.values():
            self.assertAlmostEqual(w["p_bonferroni"], min(1.0, 3 * w["p"]))
        # "A-B" tests A - B: round out is slower than wide angle for most players
        direct = analyze.wilcoxon([r[0] for r in FIRST_BASE], [r[2] for r in FIRST_BASE])
        self.assertEqual(pairs["round_out-wide"]["w_plus"], direct["w_plus"])
        self.assertGreater(direct["w_plus"], direct["w_minus"])


# 6 subjects x 3 conditions of total times; None marks a trial that reached the limit
# (completed = 0), recorded at slightly different times at or under it
CENSORED_TIMES = [
    (180.0, 179.5, 50.0), (40.0, 179.9998, 60.0), (30.0, 45.0, 70.0),
    (179.9, 180.0, 20.0), (35.0, 40.0, 179.8), (25.0, 60.0, 55.0),
]
CENSORED = [(True, True, False), (False, True, False), (False, False, False),
            (True, True, False), (False, False, True), (False, False, False)]


def censored_data():
    data = {"time_total": {str(s): dict(zip(METHODS, times)) for s, times in enumerate(CENSORED_TIMES)}}
    censored = {str(s): dict(zip(METHODS, flags)) for s, flags in enumerate(CENSORED)}
    return data, censored


class Censored(unittest.TestCase):
    def test_censored_times_are_ranked_as_ties_at_the_limit(self):
        data, censored = censored_data()
        entry = analyze.analyze(data, list(METHODS), censored)["measures"]["time_total"]
        self.assertEqual(entry["censored"], {"round_out": 2, "narrow": 3, "wide": 1})
        self.assertEqual(entry["censored_at"], 180.0)
        # by hand: every censored time at 180 s, then the plain tests
        tied = [[180.0 if flags[i] else times[i] for times, flags in zip(CENSORED_TIMES, CENSORED)] for i in range(3)]
        self.assertAlmostEqual(entry["friedman"]["statistic"], analyze.friedman(tied)["statistic"], places=12)
        # subjects 0 and 3 reached the limit in both round out and narrow: zero differences
        pair = entry["pairs"]["round_out-narrow"]
        self.assertEqual(pair["zeros"], 2)
        self.assertAlmostEqual(pair["p"], analyze.wilcoxon(tied[0], tied[1])["p"], places=12)
        # taken at face value, the times under the limit would order those trials
        raw = analyze.analyze(data, list(METHODS))["measures"]["time_total"]
        self.assertNotAlmostEqual(raw["friedman"]["statistic"], entry["friedman"]["statistic"], places=6)
        self.assertEqual(raw["pairs"]["round_out-narrow"]["zeros"], 0)
        self.assertIsNone(raw["censored_at"])

    def test_only_time_total_is_censored(self):
        data, censored = censored_data()
        data["falls"] = {s: {c: 1.0 for c in METHODS} for s in data["time_total"]}
        entry = analyze.analyze(data, list(METHODS), censored)["measures"]["falls"]
        self.assertIsNone(entry["censored_at"])
        self.assertEqual(entry["censored"]["narrow"], 3, "counted for every measure")

    def test_the_script_counts_them_says_so_and_marks_them(self):
        with tempfile.TemporaryDirectory() as d:
            rows = [(s + 1, c, i + 1, 0, t, 0, 0, 0 if flags[i] else 1)
                    for s, (times, flags) in enumerate(zip(CENSORED_TIMES, CENSORED)) for i, (c, t) in enumerate(zip(METHODS, times))]
            write_results(os.path.join(d, "results.csv"), rows)
            r = run_script(os.path.join(d, "results.csv"), "--out", os.path.join(d, "out"))
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("narrow 3, round_out 2, wide 1", r.stdout)  # conditions sorted
            self.assertIn("ties at the limit 180.000 s", r.stdout)
            with open(os.path.join(d, "out", "report.md"), encoding="utf-8") as f:
                self.assertIn("ranked as ties at the limit", f.read())
            with open(os.path.join(d, "out", "stats.json"), encoding="utf-8") as f:
                self.assertEqual(json.load(f)["measures"]["time_total"]["censored"]["narrow"], 3)


class Input(unittest.TestCase):
    def test_missing_column_names_the_file_line_and_fix(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "results.csv")
            with open(path, "w", encoding="utf-8") as f:
                f.write("subject,condition,falls\n1,CM0,2\n")
            r = run_script(path, "--out", os.path.join(d, "out"))
            self.assertEqual(r.returncode, 1)
            self.assertIn("results.csv:1:", r.stderr)
            self.assertIn("fix:", r.stderr)

    def test_bad_number_names_its_line(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "results.csv")
            write_results(path, [(1, "CM0", 1, 0, 10, 0, 0, 1), (1, "CM1", 2, "many", 10, 0, 0, 1)])
            r = run_script(path, "--out", os.path.join(d, "out"))
            self.assertEqual(r.returncode, 1)
            self.assertIn("results.csv:3: falls is 'many'", r.stderr)

    def test_ranking_file_next_to_the_results_is_analysed(self):
        with tempfile.TemporaryDirectory() as d:
            rows, ranks = [], []
            for s in range(1, 5):
                for i, c in enumerate(METHODS):
                    rows.append((s, c, i + 1, 0, 10 + i, 0, 0, 1))
                    ranks.append((s, c, 3 - i))
            write_results(os.path.join(d, "results.csv"), rows)
            with open(os.path.join(d, "ranking.csv"), "w", newline="", encoding="utf-8") as f:
                csv.writer(f).writerows([("subject", "condition", "rank"), *ranks])
            r = run_script(os.path.join(d, "results.csv"), "--out", os.path.join(d, "out"))
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(d, "out", "stats.json"), encoding="utf-8") as f:
                ranking = json.load(f)["measures"]["ranking"]
            self.assertEqual(ranking["conditions"]["wide"]["mean"], 1.0)
            # every subject ranks the same way: chi2 = n (k - 1) = 8, W = 1
            self.assertAlmostEqual(ranking["friedman"]["statistic"], 8.0)
            self.assertAlmostEqual(ranking["friedman"]["kendall_w"], 1.0)


if __name__ == "__main__":
    unittest.main()
