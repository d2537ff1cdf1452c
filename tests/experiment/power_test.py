#!/usr/bin/python3
"""scripts/power.py on replicate folders made here with a known truth: conditions that do not
differ give a power near alpha (Friedman's false-positive rate), conditions far apart give
a power near 1 that grows with the number of subjects; and its refusals."""
import csv
import os
import random
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "..", "scripts", "power.py")
CONDITIONS = ("CM0", "CM1", "CM2", "CM3")


def make_replicates(folder, replicates, subjects, shift, seed):
    """replicate_NNN/results.csv: every subject's four conditions, falls and times drawn
    around a subject's own level, condition c shifted by c * shift"""
    rng = random.Random(seed)
    for r in range(1, replicates + 1):
        path = os.path.join(folder, f"replicate_{r:03d}")
        os.makedirs(path)
        with open(os.path.join(path, "results.csv"), "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["subject", "condition", "order", "falls", "time_total_s", "time_out_s", "ratio", "completed", "missed_deadlines"])
            for s in range(1, subjects + 1):
                level = rng.gauss(30.0, 5.0)
                for c, name in enumerate(CONDITIONS):
                    total = level + c * shift + rng.gauss(0.0, 3.0)
                    out = max(0.0, 0.2 * total + rng.gauss(0.0, 1.0))
                    w.writerow([s, name, c + 1, max(0, round(rng.gauss(2.0, 1.0) + c * shift / 10)), f"{total:.4f}", f"{out:.4f}",
                                f"{out / total:.4f}", 1, 0])


def run(folder, *args):
    return subprocess.run([sys.executable, SCRIPT, folder, *args], capture_output=True, text=True)


def power(folder, n, measure):
    with open(os.path.join(folder, "power", "power.csv")) as f:
        for row in csv.DictReader(f):
            if int(row["n"]) == n and row["measure"] == measure:
                return float(row["power"]), float(row["se"])
    raise KeyError((n, measure))


class Power(unittest.TestCase):
    def test_no_difference_gives_about_alpha(self):
        with tempfile.TemporaryDirectory() as d:
            make_replicates(d, 10, 12, shift=0.0, seed=3)
            r = run(d, "--subjects", "12-12", "--draws", "1000")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("not people's", r.stdout)
            p, se = power(d, 12, "time_total")
            # Friedman's large-sample p is a little conservative at 12 subjects: between
            # half alpha and alpha, give or take the draws' error
            self.assertGreater(p, 0.02 - 3 * se)
            self.assertLess(p, 0.05 + 3 * se)

    def test_a_real_difference_is_found_more_often_with_more_subjects(self):
        with tempfile.TemporaryDirectory() as d:
            make_replicates(d, 10, 12, shift=2.0, seed=4)
            r = run(d, "--subjects", "4-16", "--step", "4", "--draws", "200")
            self.assertEqual(r.returncode, 0, r.stderr)
            low, _ = power(d, 4, "time_total")
            high, _ = power(d, 16, "time_total")
            self.assertGreater(high, 0.9)
            self.assertLess(low, high - 0.2)
            self.assertTrue(os.path.exists(os.path.join(d, "power", "power.png")))

    def test_too_few_subjects_and_no_replicates_are_refused(self):
        with tempfile.TemporaryDirectory() as d:
            r = run(d)
            self.assertEqual(r.returncode, 1)
            self.assertIn("--replicates N", r.stderr)
            make_replicates(d, 1, 12, shift=0.0, seed=5)
            r = run(d, "--subjects", "6-24")
            self.assertEqual(r.returncode, 1)
            self.assertIn("fewer than the 24", r.stderr)
            self.assertIn("fix:", r.stderr)


if __name__ == "__main__":
    unittest.main()
