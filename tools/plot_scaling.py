#!/usr/bin/python3
"""Scaling plot from `rengine-bench --scaling` CSVs: ms/step against body count, log-log.

    /usr/bin/python3 tools/plot_scaling.py OUT.png SCALING.csv [MORE.csv ...]

One colour per series (debris, pile awake, pile sleeping, sparse), one line style per engine:
REngine (solid; with the broad phase, the default), REngine's all-pairs reference loop
(dotted; rows with broadphase=off), REngine on more threads (dashed), Bullet of the same run
(dash-dot, one thread), and Jolt of the same run (open markers, one line style per thread
count: the jolt_ms_per_step column, present when rengine-bench was built with
REngine_JOLT_DIR). CSVs written before the Jolt series (their Jolt column was an estimate)
give no Jolt points.
Where several files hold the same point (series, engine, body count), the first file's is
drawn: give the main run first.

Prints, and the caller keeps beside the plot: the results (the first file's rows plus the
others' all-pairs rows) and the growth exponent of each series and engine, the slope of a
least-squares line through log(ms/step) against log(bodies) (the cost grows as
bodies^exponent; 1 is linear). Needs Debian's python3-matplotlib.
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")  # files only: no display needed
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

SERIES = {  # series -> (label, colour)
    "debris": ("debris cloud (zero g, e = 1)", "tab:blue"),
    "pile_awake": ("box pile, sleeping off", "tab:red"),
    "pile_sleep": ("box pile, sleeping on", "tab:green"),
    "sparse": ("sparse field of hulls (zero g)", "tab:purple"),
}
ENGINES = {  # engine -> (label, line style, marker, filled)
    "REngine": ("REngine", "-", "o", True),
    "REngine all pairs": ("REngine, all-pairs loop (broad phase off)", ":", "x", True),
    "REngine 2 threads": ("REngine, 2 threads", (0, (5, 1)), "D", True),
    "Bullet": ("Bullet 3.24, one thread", "-.", "s", True),
    "Jolt": ("Jolt 5.5", "--", "^", False),
    "Jolt 2 threads": ("Jolt 5.5, 2 threads", (0, (1, 1)), "v", False),
}


def number(text):
    return float(text) if text not in ("", None) else None


def read_points(paths):
    """{(series, engine): {bodies: ms}} and the result rows printed in the table."""
    points, rows = {}, []
    for index, path in enumerate(paths):
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                bodies, series = int(row["bodies"]), row["series"]
                broadphase = row["broadphase"] == "on"
                threads = int(row.get("threads") or 1)
                engine = "REngine" if broadphase else "REngine all pairs"
                if threads != 1:
                    engine = f"REngine {threads} threads"
                    ENGINES.setdefault(engine, (f"REngine, {threads} threads", (0, (5, 1)), "D", True))
                jolt = "Jolt" if threads == 1 else f"Jolt {threads} threads"
                if threads not in (1, 2):
                    ENGINES.setdefault(jolt, (f"Jolt 5.5, {threads} threads", (0, (1, 1)), "v", False))
                values = {engine: number(row["rengine_ms_per_step"])}
                if broadphase:  # Jolt does not depend on REngine's setting: once per thread count
                    values[jolt] = number(row.get("jolt_ms_per_step"))
                first = broadphase and threads == 1
                if first:  # Bullet does not depend on REngine's setting: once per run
                    values["Bullet"] = number(row["bullet_ms_per_step"])
                for engine, ms in values.items():
                    if ms is not None:
                        points.setdefault((series, engine), {}).setdefault(bodies, ms)
                if index == 0 or not broadphase:
                    rows.append(row)
    return points, rows


def exponent(curve):
    """Least-squares slope of log(ms) against log(bodies); None below two points."""
    if len(curve) < 2:
        return None
    xs = [math.log(n) for n in curve]
    ys = [math.log(ms) for ms in curve.values()]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


def cell(text, fmt):
    return fmt % float(text) if text not in ("", None) else ""


def print_results(rows):
    print("| scene | bodies | steps | sleeping | broad phase | threads | REngine ms/step "
          "| Bullet ms/step (1 thread) | Jolt ms/step | REngine / Jolt |")
    print("| --- | ---: | ---: | --- | --- | ---: | ---: | ---: | ---: | ---: |")
    for r in rows:
        print(f"| {r['scene']} | {r['bodies']} | {r['steps']} | {r['sleeping']} "
              f"| {r['broadphase']} | {r.get('threads') or 1} | {cell(r['rengine_ms_per_step'], '%.3g')} "
              f"| {cell(r['bullet_ms_per_step'], '%.3g')} "
              f"| {cell(r.get('jolt_ms_per_step'), '%.3g')} | {cell(r.get('rengine_over_jolt'), '%.2f')} |")


def print_exponents(points):
    engines = [e for e in ENGINES if any((s, e) in points for s in SERIES)]
    print("\nGrowth exponent k (ms/step ~ bodies^k, least squares on log-log; "
          "points in brackets)\n")
    print("| series | " + " | ".join(ENGINES[e][0] for e in engines) + " |")
    print("| --- |" + " ---: |" * len(engines))
    for series in SERIES:
        cells = []
        for engine in engines:
            curve = points.get((series, engine), {})
            k = exponent(curve)
            cells.append("" if k is None else f"{k:.2f} ({len(curve)})")
        print(f"| {series} | " + " | ".join(cells) + " |")


def plot(points, out_path):
    fig, ax = plt.subplots(figsize=(9, 6.5))
    for (series, engine), curve in sorted(points.items()):
        if series not in SERIES or engine not in ENGINES:
            continue
        _, colour = SERIES[series]
        _, style, marker, filled = ENGINES[engine]
        xs = sorted(curve)
        ax.plot(xs, [curve[x] for x in xs], linestyle=style, marker=marker, color=colour,
                markerfacecolor=colour if filled else "none", markersize=6, linewidth=1.4,
                alpha=0.75 if engine.startswith("Jolt") else 1.0)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("bodies (dynamic)")
    ax.set_ylabel("ms per step (median of interleaved runs)")
    ax.set_title("Cost per step against body count, 60 Hz, 10 iterations (one thread unless marked)")
    ax.grid(True, which="both", alpha=0.3)
    series_legend = ax.legend(
        [Line2D([], [], color=c, linewidth=3) for _, c in SERIES.values()],
        [label for label, _ in SERIES.values()], loc="upper left", fontsize=8, title="series")
    ax.add_artist(series_legend)
    used = [e for e in ENGINES if any(k[1] == e for k in points)]
    ax.legend([Line2D([], [], color="0.3", linestyle=ENGINES[e][1], marker=ENGINES[e][2],
                      markerfacecolor="0.3" if ENGINES[e][3] else "none") for e in used],
              [ENGINES[e][0] for e in used], loc="lower right", fontsize=8, title="engine")
    fig.tight_layout()
    fig.savefig(out_path, dpi=110)


def main(argv):
    if len(argv) < 3 or argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(argv) > 1 and argv[1] in ("-h", "--help") else 2
    points, rows = read_points(argv[2:])
    print_results(rows)
    print_exponents(points)
    plot(points, argv[1])
    print(f"\nwrote {argv[1]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
