#!/usr/bin/python3
"""scripts/agreement.py on runs made here with a known truth: a run equal to the simulated
one, or drawn from the same subjects with small noise, agrees; a run with one condition
moved far, or with the conditions' difference gone, disagrees and names what differs; the
bootstrap interval has its textbook width; bad input is refused with the file and the fix."""
import csv
import json
import math
import os
import random
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPTS = os.path.join(HERE, "..", "..", "scripts")
SCRIPT = os.path.join(SCRIPTS, "agreement.py")
sys.path.insert(0, SCRIPTS)
import agreement  # noqa: E402

CONDITIONS = ("CM0", "CM1", "CM2", "CM3")


def subjects(n, shift, seed):
    """{subject: {condition: (falls, time_total, time_out)}}: condition c shifted by c * shift"""
    rng = random.Random(seed)
    out = {}
    for s in range(1, n + 1):
        level = rng.gauss(30.0, 5.0)
        out[s] = {}
        for c, name in enumerate(CONDITIONS):
            total = level + c * shift + rng.gauss(0.0, 3.0)
            out[s][name] = (max(0, round(rng.gauss(2.0, 1.0) + c * shift / 5)), total, max(0.0, 0.2 * total + rng.gauss(0.0, 1.0)))
    return out


def write(path, table, noise=0.0, seed=0, move=None):
    """results.csv of `table`; noise: added to every time; move: (condition, seconds) added
    to that condition's time out"""
    rng = random.Random(seed)
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["subject", "condition", "order", "falls", "time_total_s", "time_out_s", "ratio", "completed", "missed_deadlines"])
        for s, by_condition in table.items():
            for c, name in enumerate(CONDITIONS):
                falls, total, out = by_condition[name]
                out = max(0.0, out + rng.gauss(0.0, noise) + (move[1] if move and move[0] == name else 0.0))
                w.writerow([s, name, c + 1, falls, f"{total:.4f}", f"{out:.4f}", f"{out / total:.4f}", 1, 0])
    return path


def run(*args):
    return subprocess.run([sys.executable, SCRIPT, *args, "--resamples", "2000"], capture_output=True, text=True)


class Agreement(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.table = subjects(12, shift=6.0, seed=5)  # a real difference across conditions
        self.simulated = write(self.file("sim.csv"), self.table)

    def tearDown(self):
        self.dir.cleanup()

    def file(self, name):
        return os.path.join(self.dir.name, name)

    def test_the_same_run_agrees(self):
        r = run(self.simulated, write(self.file("rt.csv"), self.table), "--json", self.file("a.json"))
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("every run agrees", r.stdout)
        with open(self.file("a.json"), encoding="utf-8") as f:
            report = json.load(f)
        rows = [row for run_ in report["runs"].values() for row in run_["rows"] if "condition" in row]
        self.assertEqual(len(rows), 2 * len(CONDITIONS))  # falls and time out by default
        self.assertTrue(all(row["low"] <= row["simulated_mean"] <= row["high"] for row in rows))

    def test_a_little_noise_agrees(self):
        r = run(self.simulated, write(self.file("rt.csv"), self.table, noise=0.2, seed=9))
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)

    def test_one_condition_moved_far_disagrees_and_is_named(self):
        r = run(self.simulated, write(self.file("rt.csv"), self.table, move=("CM2", 8.0)))
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
        self.assertIn("time_out CM2: mean", r.stdout)
        self.assertNotIn("time_out CM1: mean", r.stdout)

    def test_a_lost_difference_is_another_conclusion(self):
        flat = subjects(12, shift=0.0, seed=5)
        # the same means per condition as the simulated run would need a shift: compare the
        # Friedman conclusions alone, on time out, over a wide interval
        r = run(self.simulated, write(self.file("rt.csv"), flat), "--measures", "time_out", "--level", "0.999999")
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
        self.assertIn("not the same conclusion at 0.05", r.stdout)

    def test_each_run_is_judged_on_its_own(self):
        good = write(self.file("colocated.csv"), self.table)
        bad = write(self.file("distributed.csv"), self.table, move=("CM0", 8.0))
        r = run(self.simulated, good, bad)
        self.assertEqual(r.returncode, 1)
        self.assertIn(bad + ": time_out CM0", r.stdout)
        self.assertNotIn(good + ":", r.stdout.split("disagree:")[1])

    def test_the_interval_has_the_textbook_width(self):
        # the percentile interval of a mean of n draws: about mean +- 1.96 sd / sqrt(n)
        rng = random.Random(2)
        values = [rng.gauss(10.0, 2.0) for _ in range(200)]
        mean = sum(values) / len(values)
        sd = math.sqrt(sum((v - mean) ** 2 for v in values) / (len(values) - 1))
        low, high = agreement.bootstrap_interval(values, 0.95, 4000, random.Random(3))
        half = 1.96 * sd / math.sqrt(len(values))
        self.assertAlmostEqual(low, mean - half, delta=0.15 * half)
        self.assertAlmostEqual(high, mean + half, delta=0.15 * half)
        self.assertEqual(agreement.bootstrap_interval([3.0] * 12, 0.95, 500, random.Random(1)), (3.0, 3.0))

    def test_bad_input_is_refused_with_the_fix(self):
        other = subjects(11, shift=6.0, seed=5)
        r = run(self.simulated, write(self.file("fewer.csv"), other))
        self.assertEqual(r.returncode, 2)
        self.assertIn("fewer.csv: subjects", r.stderr)
        self.assertIn("fix: compare runs of the same experiment file", r.stderr)
        r = run(self.simulated, self.file("missing.csv"))
        self.assertEqual(r.returncode, 2)
        self.assertIn("missing.csv: no such file", r.stderr)
        r = run(self.simulated, self.simulated, "--measures", "fals")
        self.assertEqual(r.returncode, 2)
        self.assertIn("name some of falls, time_out, time_total, ratio", r.stderr)


if __name__ == "__main__":
    unittest.main()
