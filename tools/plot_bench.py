#!/usr/bin/python3
"""Work-precision plots from rengine-bench's CSV: one PNG per scene.

    /usr/bin/python3 tools/plot_bench.py BENCH.csv OUTDIR

Log-log, x = ms per step, y = the scene's `error` column, one series per (method,
iterations), each point labelled with its step size. Needs Debian's python3-matplotlib.
"""
import csv
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")  # files only: no display needed
import matplotlib.pyplot as plt  # noqa: E402

# What `error` means per scene (kept in step with tools/rengine-bench/main.cpp).
ERROR_LABELS = {
    "tumbling": ("max |L(t) - L0| / |L0|", "relative angular-momentum drift"),
    "projectile": ("|x(T) - closed form| (m)", "final position error"),
    "elastic_pair": ("max |v - v'| / |v'|", "velocity error after the collision"),
    "sliding_box": ("|d - v0²/(2μg)| / (v0²/(2μg))", "stopping-distance error"),
    "stack10": ("|x_top(T) - x_top(0)| (m)", "top box drift"),
}

# An error of exactly 0 has no place on a log axis: it is drawn at this floor, with a
# note in the title, rather than dropped (a dropped point would read as a missing run).
ZERO_FLOOR = 1e-17


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    csv_path, out_dir = argv[1], argv[2]
    series = defaultdict(lambda: defaultdict(list))  # scene -> (method, iterations) -> rows
    with open(csv_path, newline="") as f:
        for row in csv.DictReader(f):
            if not row["error"]:
                continue
            key = (row["method"], row["iterations"])
            # Cost of one simulated second (ms per step / dt): what a smaller step really
            # costs, so the grid spreads along the x axis as a work-precision diagram.
            dt = float(row["dt"])
            series[row["scene"]][key].append(
                (float(row["ms_per_step"]) / dt, float(row["error"]), dt))
    os.makedirs(out_dir, exist_ok=True)

    for scene, by_key in sorted(series.items()):
        y_label, what = ERROR_LABELS.get(scene, ("error", "error"))
        fig, ax = plt.subplots(figsize=(7, 5))
        any_zero = False
        # Numeric order of iterations (4, 10, 20), not string order; empty (no solver) first.
        def order(item):
            method, iterations = item[0]
            return (method, int(iterations) if iterations else -1)

        for (method, iterations), points in sorted(by_key.items(), key=order):
            points.sort(key=lambda p: -p[2])  # largest step first: a path along the grid
            xs = [p[0] for p in points]
            ys = [max(p[1], ZERO_FLOOR) for p in points]
            any_zero |= any(p[1] <= 0 for p in points)
            label = method + (f", {iterations} iterations" if iterations else "")
            ax.plot(xs, ys, marker="o", label=label)
            for x, y, (_, _, dt) in zip(xs, ys, points):
                ax.annotate(f"1/{round(1 / dt)}", (x, y), textcoords="offset points",
                            xytext=(4, 4), fontsize=7)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("stepping time per simulated second (ms)")
        ax.set_ylabel(y_label)
        title = f"{scene}: {what} against cost"
        if any_zero:
            title += f"\n(an error of exactly 0 is drawn at {ZERO_FLOOR:g})"
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        out = os.path.join(out_dir, f"{scene}.png")
        fig.savefig(out, dpi=120)
        plt.close(fig)
        print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
