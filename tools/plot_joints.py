#!/usr/bin/env python3
"""Plots bench_joints' CSV: one panel per scene, each figure's error as a bar per engine (log
scale; an error of exactly 0 is drawn at the floor, hatched), the median us/step in the title.
Prints the table (markdown) to stdout.

    /usr/bin/python3 tools/plot_joints.py tools/bench-results/joints.csv tools/bench-results/joints.png
"""
import csv
import math
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FLOOR = 1e-16  # where an error of 0 is drawn
ENGINES = [("rengine", "REngine", "tab:blue"), ("bullet", "Bullet", "tab:orange")]


def read(path):
    scenes = {}  # name -> {engine: (us_per_step, [(figure, value)])}
    order = []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            figures = []
            for k in range(1, 6):
                name = row.get(f"figure{k}", "")
                if name:
                    figures.append((name, float(row[f"value{k}"])))
            if row["scene"] not in scenes:
                scenes[row["scene"]] = {}
                order.append(row["scene"])
            scenes[row["scene"]][row["engine"]] = (float(row["us_per_step"]), figures)
    return order, scenes


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_joints.py JOINTS.csv OUT.png")
    order, scenes = read(sys.argv[1])
    cols = 3
    rows = math.ceil(len(order) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(5.2 * cols, 4.6 * rows), squeeze=False)
    print("| scene | figure | REngine | Bullet |")
    print("| --- | --- | --- | --- |")
    for i, scene in enumerate(order):
        ax = axes[i // cols][i % cols]
        data = scenes[scene]
        names = [n for n, _ in data["rengine"][1]]
        width = 0.38
        for e, (key, label, colour) in enumerate(ENGINES):
            if key not in data:
                continue
            values = [v for _, v in data[key][1]]
            shown = [v if v > FLOOR else FLOOR for v in values]
            xs = [k + (e - 0.5) * width for k in range(len(values))]
            bars = ax.bar(xs, shown, width, color=colour, label=f"{label} ({data[key][0]:.1f} us/step)")
            for bar, v in zip(bars, values):
                if math.isnan(v):
                    bar.set_hatch("xx")
                elif v <= FLOOR:
                    bar.set_hatch("//")
                    bar.set_alpha(0.5)
        ax.set_yscale("log")
        ax.set_ylim(FLOOR / 3, 1e4)
        ax.set_xticks(range(len(names)))
        ax.set_xticklabels(["\n".join(textwrap.wrap(n, 14)) for n in names], fontsize=6.5)
        ax.set_title(scene, fontsize=10)
        ax.grid(axis="y", which="major", alpha=0.3)
        ax.legend(fontsize=7, loc="best")
        for k, name in enumerate(names):
            r = data["rengine"][1][k][1]
            b = data["bullet"][1][k][1] if "bullet" in data else float("nan")
            print(f"| {scene} | {name} | {r:.2g} | {b:.2g} |")
    for j in range(len(order), rows * cols):
        axes[j // cols][j % cols].axis("off")
    print("| **us/step (median)** | | | |")
    for scene in order:
        data = scenes[scene]
        b = data["bullet"][0] if "bullet" in data else float("nan")
        print(f"| {scene} | us/step | {data['rengine'][0]:.1f} | {b:.1f} |")
    fig.suptitle("Joints at 60 Hz, 10 iterations: error against the closed form (0 drawn hatched at 1e-16)",
                 fontsize=11)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=110)


if __name__ == "__main__":
    main()
