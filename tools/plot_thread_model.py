#!/usr/bin/env python3
"""Plots rengine-bench --scaling --model-threads's CSV: each scene's modelled speed-up
against its thread count, with the ideal line and, where the machine had the threads, the
measured speed-up (REngine's own rows of the same run).

Usage: /usr/bin/python3 tools/plot_thread_model.py OUT.png thread_model.csv
(Debian's python3-matplotlib, through /usr/bin/python3.)
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# Each family its colour map; its scenes darker as they grow.
FAMILIES = [("debris", "Blues"), ("pile_", "Reds"), ("sparse", "Purples")]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    out, path = sys.argv[1], sys.argv[2]
    scenes = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            scenes.setdefault(row["scene"], []).append(row)
    fig, ax = plt.subplots(figsize=(9, 6))
    most = 1
    counts = {}
    for name in scenes:
        prefix = next((p for p, _ in FAMILIES if name.startswith(p)), "")
        counts[prefix] = counts.get(prefix, 0) + 1
    seen = {}
    for name, rows in scenes.items():
        prefix = next((p for p, _ in FAMILIES if name.startswith(p)), "")
        k = seen[prefix] = seen.get(prefix, 0) + 1
        cmap = matplotlib.colormaps[next((m for p, m in FAMILIES if p == prefix), "Greys")]
        colour = cmap(0.35 + 0.65 * k / counts[prefix])
        style = ":" if name.endswith("_sleep") else "-"
        threads = [int(r["threads"]) for r in rows]
        most = max(most, max(threads))
        ax.plot(threads, [float(r["speedup"]) for r in rows], style, marker="o", color=colour, label=name)
        one = next((float(r["measured_ms"]) for r in rows if int(r["threads"]) == 1), math.nan)
        for r in rows:
            measured = float(r["measured_ms"])
            if int(r["threads"]) > 1 and not math.isnan(measured) and not math.isnan(one):
                ax.plot([int(r["threads"])], [one / measured], marker="x", color=colour, markersize=9)
    ax.plot([1, most], [1, most], "k--", linewidth=1, label="ideal")
    ax.set_xscale("log", base=2)
    ax.set_yscale("log", base=2)
    ticks = [t for t in (1, 2, 4, 8, 16, 32) if t <= most]
    ax.set_xticks(ticks, [str(t) for t in ticks])
    ax.set_yticks(ticks, [str(t) for t in ticks])
    ax.set_xlabel("threads")
    ax.set_ylabel("speed-up over one thread")
    ax.set_title("REngine's step on P threads, modelled from one thread's task times (x: measured)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    print("wrote", out)


if __name__ == "__main__":
    main()
