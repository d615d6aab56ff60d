#!/usr/bin/python3
"""Plots a rengine-sim trajectory: each body's angular velocity in its own principal frame
(where a tumbling body's flips show) and the drift of its rotational energy and world angular
momentum (the invariants of torque-free motion).

usage: plot_trajectory.py TRAJ.csv DESCRIBE.json OUT.png [--bodies N]
DESCRIBE.json is `rengine-sim SCENE --describe`: the step-0 principal axes and moments.
"""
import argparse
import csv
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def quat_to_matrix(w, x, y, z):
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("describe")
    ap.add_argument("out")
    ap.add_argument("--bodies", type=int, default=3, help="plot at most this many bodies")
    args = ap.parse_args()

    with open(args.describe) as f:
        describe = json.load(f)
    rows = {}
    with open(args.csv) as f:
        for r in csv.DictReader(f):
            rows.setdefault(r["body"], []).append(r)

    moving = [d for d in describe if d["mass"] > 0][: args.bodies]
    fig, axes = plt.subplots(len(moving), 2, figsize=(13, 4 * len(moving)), squeeze=False)
    for (ax_w, ax_err), d in zip(axes, moving):
        traj = rows[d["name"]]
        t = np.array([float(r["time"]) for r in traj])
        q = np.array([[float(r[k]) for k in ("qw", "qx", "qy", "qz")] for r in traj])
        w_world = np.array([[float(r[k]) for k in ("wx", "wy", "wz")] for r in traj])
        moments = np.array(d["principal_moments"])
        axes0 = np.array(d["principal_axes"]).T  # columns: principal axes, world, step 0
        # The principal frame is fixed in the shape frame: R_SB = R_WS(0)^T R_WB(0).
        r_sb = quat_to_matrix(*q[0]).T @ axes0
        w_body = np.empty_like(w_world)
        energy = np.empty(len(t))
        l_world = np.empty_like(w_world)
        for i in range(len(t)):
            r_wb = quat_to_matrix(*q[i]) @ r_sb
            w_body[i] = r_wb.T @ w_world[i]
            l_body = moments * w_body[i]
            energy[i] = 0.5 * w_body[i] @ l_body
            l_world[i] = r_wb @ l_body
        for k, label in enumerate(("smallest", "intermediate", "largest")):
            ax_w.plot(t, w_body[:, k], lw=0.8, label=f"ω about {label} moment axis")
        window = min(t[-1], 120.0)  # a few periods read better than a solid band
        ax_w.set_xlim(0, window)
        ax_w.set_xlabel("time (s)")
        ax_w.set_ylabel("body-frame angular velocity (rad/s)")
        ax_w.set_title(f"{d['name']}: angular velocity in the principal frame "
                       f"(first {window:g} s)")
        ax_w.legend(loc="upper right", fontsize=8)

        e_err = np.abs(energy / energy[0] - 1) if energy[0] > 0 else np.zeros(len(t))
        l0 = np.linalg.norm(l_world[0])
        l_err = np.linalg.norm(l_world - l_world[0], axis=1) / l0 if l0 > 0 else np.zeros(len(t))
        floor = 1e-17  # exact zeros have no logarithm; rounding lives near 1e-16
        ax_err.semilogy(t, np.maximum(e_err, floor), lw=0.8, label="|E/E₀ − 1| rotational energy")
        ax_err.semilogy(t, np.maximum(l_err, floor), lw=0.8, label="|L − L₀|/|L₀| world angular momentum")
        ax_err.axhline(1e-6, color="red", ls="--", lw=0.8, label="required bound 1e-6")
        ax_err.set_ylim(1e-17, 1e-3)
        ax_err.set_xlabel("time (s)")
        ax_err.set_ylabel("relative drift")
        ax_err.set_title(f"{d['name']}: conservation (from the written CSV, 17 digits)")
        ax_err.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)


if __name__ == "__main__":
    main()
