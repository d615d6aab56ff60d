#!/usr/bin/python3
"""Work-precision plots from rengine-bench's CSV: one PNG per scene, and a summary table.

    /usr/bin/python3 tools/plot_bench.py BENCH.csv OUTDIR

Log-log, x = stepping time per simulated second (ms_per_step / dt), y = the scene's `error`
column, one series per (method, iterations): the marker and line style tell the method
(REngine, bullet), the colour the solver iterations; each point is labelled with its step
size. Errors below ERROR_FLOOR (exact answers: 0 or rounding, ~1e-16) are drawn at the
floor, and the y label says so.

Also writes OUTDIR/summary.md (and prints it): per scene, at dt = 1/60 and 10 iterations
(the solver's default; scenes without contacts have no iterations), ms_per_step and error
of each method side by side. Needs Debian's python3-matplotlib.
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
    "inelastic_pair": ("max |v - v'| / |v'|, e = 0.5", "velocity error after the collision"),
    "sliding_box": ("|d - v0²/(2μg)| / (v0²/(2μg))", "stopping-distance error"),
    "incline": ("|d - d*| / d*,  d* = g(sin θ - μ cos θ)T²/2",
                "distance slid down a 20° incline"),
    "stack10": ("|x_top(T) - x_top(0)| (m)", "top box drift"),
    "debris_cloud": ("|E(T) - E0| / E0", "final kinetic-energy change (elastic: should be 0)"),
    "asteroid_field": ("max |L(t) - L0| / Σ(|x × mv| + |L_spin|)",
                       "angular momentum about the origin"),
}

# An error of 0 (or of rounding size) has no place on a log axis: it is drawn at this floor,
# and the axis label says so, rather than dropped (a dropped point would read as a missing
# run).
ERROR_FLOOR = 1e-16

METHOD_STYLE = {  # marker, line style
    "REngine": ("o", "-"),
    "bullet": ("s", "--"),
}
OTHER_MARKERS = ["^", "D", "v", "P", "X"]
ITERATION_COLORS = {"": "tab:blue", "4": "tab:orange", "10": "tab:blue", "20": "tab:green"}

SUMMARY_RATE = 60
SUMMARY_ITERATIONS = "10"


def read_rows(csv_path):
    with open(csv_path, newline="") as f:
        return list(csv.DictReader(f))


def method_style(method, others):
    if method in METHOD_STYLE:
        return METHOD_STYLE[method]
    if method not in others:
        others[method] = OTHER_MARKERS[len(others) % len(OTHER_MARKERS)]
    return others[method], ":"


def plot(rows, out_dir):
    series = defaultdict(lambda: defaultdict(list))  # scene -> (method, iterations) -> points
    for row in rows:
        if not row["error"]:
            continue
        # Cost of one simulated second (ms per step / dt): what a smaller step really costs,
        # so the grid spreads along the x axis as a work-precision diagram.
        dt = float(row["dt"])
        series[row["scene"]][(row["method"], row["iterations"])].append(
            (float(row["ms_per_step"]) / dt, float(row["error"]), dt))

    others = {}
    for scene, by_key in sorted(series.items()):
        y_label, what = ERROR_LABELS.get(scene, ("error", "error"))
        fig, ax = plt.subplots(figsize=(7.5, 5.5))
        clamped = False

        # REngine first, then bullet, then anything else; numeric order of iterations (4, 10,
        # 20), not string order; empty (no solver) first.
        def order(item):
            method, iterations = item[0]
            rank = list(METHOD_STYLE).index(method) if method in METHOD_STYLE else 99
            return (rank, method, int(iterations) if iterations else -1)

        for (method, iterations), points in sorted(by_key.items(), key=order):
            points.sort(key=lambda p: -p[2])  # largest step first: a path along the grid
            xs = [p[0] for p in points]
            ys = [max(p[1], ERROR_FLOOR) for p in points]
            clamped |= any(p[1] < ERROR_FLOOR for p in points)
            marker, line = method_style(method, others)
            color = ITERATION_COLORS.get(iterations, None)
            label = method + (f", {iterations} iterations" if iterations else "")
            ax.plot(xs, ys, marker=marker, linestyle=line, color=color, label=label,
                    markerfacecolor="none" if method != "REngine" else color)
            for x, y, (_, _, dt) in zip(xs, ys, points):
                ax.annotate(f"1/{round(1 / dt)}", (x, y), textcoords="offset points",
                            xytext=(4, 4), fontsize=7)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("stepping time per simulated second (ms) = ms per step / dt")
        if clamped:
            y_label += (f"\n(values below {ERROR_FLOOR:g}, i.e. 0 or rounding, "
                        f"drawn at {ERROR_FLOOR:g})")
        ax.set_ylabel(y_label)
        ax.set_title(f"{scene}: {what} against cost")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        out = os.path.join(out_dir, f"{scene}.png")
        fig.savefig(out, dpi=120)
        plt.close(fig)
        print(f"wrote {out}")


def summary(rows):
    """Markdown: per scene, each method's ms/step and error at dt = 1/60, 10 iterations."""
    scenes, methods = [], []
    at = {}  # (scene, method) -> row
    for row in rows:
        if row["scene"] not in scenes:
            scenes.append(row["scene"])
        if row["method"] not in methods:
            methods.append(row["method"])
        if round(1 / float(row["dt"])) != SUMMARY_RATE:
            continue
        if row["iterations"] not in ("", SUMMARY_ITERATIONS):
            continue
        at[(row["scene"], row["method"])] = row
    methods.sort(key=lambda m: list(METHOD_STYLE).index(m) if m in METHOD_STYLE else 99)

    def cell(row, key, fmt):
        return fmt.format(float(row[key])) if row and row[key] else ""

    head = ["scene"]
    for m in methods:
        head += [f"{m} ms/step", f"{m} error"]
    if "REngine" in methods and len(methods) > 1:
        head += [f"{m} / REngine time" for m in methods if m != "REngine"]
    lines = [
        f"Work-precision summary at dt = 1/{SUMMARY_RATE} s, {SUMMARY_ITERATIONS} solver "
        f"iterations (scenes without contacts: no solver). `error` as in "
        f"tools/rengine-bench/main.cpp.",
        "",
        "| " + " | ".join(head) + " |",
        "|" + "---|" * len(head),
    ]
    for scene in scenes:
        cells = [scene]
        for m in methods:
            row = at.get((scene, m))
            cells += [cell(row, "ms_per_step", "{:.4g}"), cell(row, "error", "{:.3g}")]
        if "REngine" in methods and len(methods) > 1:
            base = at.get((scene, "REngine"))
            for m in methods:
                if m == "REngine":
                    continue
                row = at.get((scene, m))
                if base and row and float(base["ms_per_step"]) > 0:
                    cells.append(f"{float(row['ms_per_step']) / float(base['ms_per_step']):.2f}")
                else:
                    cells.append("")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    csv_path, out_dir = argv[1], argv[2]
    rows = read_rows(csv_path)
    os.makedirs(out_dir, exist_ok=True)
    plot(rows, out_dir)
    table = summary(rows)
    out = os.path.join(out_dir, "summary.md")
    with open(out, "w") as f:
        f.write(table)
    print()
    print(table, end="")
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
