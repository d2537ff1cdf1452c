#!/usr/bin/python3
"""Plot `enact bench physics --json FILE`: speed against error, and error against rate.

Left: x = ns per step (median), y = global error of the undamped oscillator, one line per
integrator across the rates (annotated in kHz). Middle: error against rate per integrator;
the legend gives the fitted slope, the observed order of convergence. Right (when the JSON
has bridge_rows): the bridge scene itself along its scripted path, x = ns per step, y = rms
error of the force sent to the device against the high-rate reference, per integrator.
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
BRIDGE_KEYS = ("integrator", "rate_hz", "ns_per_step", "force_rms_error_n")
# an error of exactly 0 N drawn at this floor on the log axis
ERROR_FLOOR_N = 1e-15


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


# rows grouped by integrator, sorted by rate, rows without a number (null) for `keys` dropped
def by_integrator(rows, keys=ROW_KEYS):
    groups = {}
    for row in rows:
        if isinstance(row, dict) and all(isinstance(row.get(k), (int, float)) for k in keys[1:]):
            groups.setdefault(row["integrator"], []).append(row)
    return {name: sorted(group, key=lambda r: r["rate_hz"]) for name, group in groups.items()}


# speed against the device force's error along the bridge's scripted path
def plot_bridge(ax, rows):
    for name, group in by_integrator(rows, BRIDGE_KEYS).items():
        ns = [r["ns_per_step"] for r in group]
        err = [max(r["force_rms_error_n"], ERROR_FLOOR_N) for r in group]
        line, = ax.loglog(ns, err, "o-", label=name)
        for x, y, r in zip(ns, err, group):
            ax.annotate(f"{r['rate_hz'] / 1e3:g}k", (x, y), textcoords="offset points", xytext=(4, 3), fontsize=7,
                        color=line.get_color())
    ax.set(xlabel="ns per step (whole path)", ylabel="device force rms error (N)",
           title="the bridge along its scripted path\nagainst the high-rate reference (labels: rate)")


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
    bridge_rows = data.get("bridge_rows")
    panels = 3 if isinstance(bridge_rows, list) and bridge_rows else 2
    fig, axes = plt.subplots(1, panels, figsize=(6.5 * panels, 5.5))
    speed, order = axes[0], axes[1]
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
    for ax in axes[::2]:
        ax.xaxis.set_major_formatter(plain)
        ax.xaxis.set_minor_formatter(plain)
    if panels == 3:
        plot_bridge(axes[2], bridge_rows)
    for ax in axes:
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
