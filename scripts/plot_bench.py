#!/usr/bin/python3
"""Plot `enact bench physics --json FILE`: speed against error, and error against rate.

Left: x = ns per step (median), y = global error of the undamped oscillator, one line per
integrator across the rates (annotated in kHz). Right: error against rate per integrator;
the legend gives the fitted slope, the observed order of convergence.
"""
import argparse
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import FuncFormatter  # noqa: E402
import numpy as np  # noqa: E402

ROW_KEYS = ("integrator", "rate_hz", "ns_per_step", "error")


def fail(message):
    sys.exit(f"plot_bench.py: {message}")


# the bench JSON, checked for the fields the plot needs
def load(path):
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except FileNotFoundError:
        fail(f"{path}: no such file (write one with: enact bench physics --json {path})")
    except json.JSONDecodeError as e:
        fail(f"{path}: not JSON ({e})")
    rows = data.get("rows") if isinstance(data, dict) else None
    if not isinstance(rows, list) or not rows:
        fail(f"{path}: no \"rows\" list: not the output of enact bench physics --json")
    for i, row in enumerate(rows):
        missing = [k for k in ROW_KEYS if not isinstance(row, dict) or k not in row]
        if missing:
            fail(f"{path}: row {i} lacks {', '.join(missing)}: not the output of enact bench physics --json")
    return data


# rows grouped by integrator, sorted by rate, rows without a number (null) dropped
def by_integrator(rows):
    groups = {}
    for row in rows:
        if all(isinstance(row[k], (int, float)) for k in ROW_KEYS[1:]):
            groups.setdefault(row["integrator"], []).append(row)
    return {name: sorted(group, key=lambda r: r["rate_hz"]) for name, group in groups.items()}


# slope of log(error) against log(rate), negated: the observed order
def observed_order(group):
    rates = np.log([r["rate_hz"] for r in group])
    errors = np.log([r["error"] for r in group])
    return -np.polyfit(rates, errors, 1)[0]


def title(data):
    m = data.get("machine", {})
    machine = f"{m.get('cpu', '?')}, {m.get('arch', '?')}, {m.get('cores', '?')} cores"
    bridge = data.get("bridge_step_ns_median")
    bridge_text = f"; bridge step {bridge:.0f} ns at 44 kHz" if isinstance(bridge, (int, float)) else ""
    return (f"enact bench physics: 50 Hz oscillator, 1 s\n{machine}; "
            f"medians of {data.get('repetitions', '?')} repetitions{bridge_text}")


def plot(data, out):
    groups = by_integrator(data["rows"])
    if not groups:
        fail("no row has numbers for rate_hz, ns_per_step and error")
    fig, (speed, order) = plt.subplots(1, 2, figsize=(13, 5.5))
    for name, group in groups.items():
        ns = [r["ns_per_step"] for r in group]
        err = [r["error"] for r in group]
        rates = [r["rate_hz"] for r in group]
        line, = speed.loglog(ns, err, "o-", label=name)
        for x, y, rate in zip(ns, err, rates):
            speed.annotate(f"{rate / 1e3:g}k", (x, y), textcoords="offset points", xytext=(4, 3), fontsize=7,
                           color=line.get_color())
        order.loglog(rates, err, "o-", color=line.get_color(), label=f"{name} (order {observed_order(group):.2f})")
    speed.set(xlabel="ns per step (median)", ylabel="global error  max|x - x_exact| / A",
              title="speed against error (labels: rate)")
    order.set(xlabel="rate (Hz)", ylabel="global error  max|x - x_exact| / A",
              title="error against rate (slope: order)")
    # ns per step spans a narrow range: plain numbers on its log axis
    plain = FuncFormatter(lambda v, _: f"{v:g}")
    speed.xaxis.set_major_formatter(plain)
    speed.xaxis.set_minor_formatter(plain)
    for ax in (speed, order):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(title(data), fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("bench_json", metavar="BENCH.json", help="output of: enact bench physics --json BENCH.json")
    parser.add_argument("-o", "--out", default="bench_physics.png", help="image to write (default: bench_physics.png)")
    args = parser.parse_args()
    plot(load(args.bench_json), args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
