#!/usr/bin/env python3
"""Medians of interleaved repetitions of bench_churn, and their ratios to the constant step.

    tools/bench/churn_ratio.py [build/bin/bench_churn] [--repetitions N]

Google Benchmark runs the benchmarks' repetitions in random interleaved order
(--benchmark_enable_random_interleaving), so a slow spell of a shared machine falls on all of
them alike; the ratios are of medians within the one run.
"""
import json
import statistics
import subprocess
import sys


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    binary = args[0] if args else "build/bin/bench_churn"
    reps = 15
    for a in sys.argv[1:]:
        if a.startswith("--repetitions="):
            reps = int(a.split("=", 1)[1])
    out = subprocess.run(
        [binary, f"--benchmark_repetitions={reps}", "--benchmark_enable_random_interleaving=true",
         "--benchmark_min_time=0.2", "--benchmark_format=json"],
        check=True, capture_output=True, text=True).stdout
    runs = {}
    asleep = {}
    for b in json.loads(out)["benchmarks"]:
        if b.get("run_type") != "iteration":
            continue
        name = b["run_name"]
        unit = {"ns": 1e-3, "us": 1.0, "ms": 1e3}[b["time_unit"]]
        runs.setdefault(name, []).append(b["real_time"] * unit)
        if "asleep" in b:
            asleep.setdefault(name, []).append(b["asleep"])
    med = {name: statistics.median(times) for name, times in runs.items()}
    print(f"medians of {reps} interleaved repetitions")
    for name, m in med.items():
        per = m / 10 if name.startswith("BM_Pile") else m
        what = "us/step" if name.startswith("BM_Pile") else "us/body"
        extra = (f"  (asleep at the end: {min(asleep[name]):.0f} to {max(asleep[name]):.0f})"
                 if name in asleep else "")
        print(f"  {name:28s} {per:10.3f} {what}{extra}")
    c = med["BM_Pile_Constant"]
    print(f"churn / constant step:         {med['BM_Pile_Churn'] / c:.3f}  (target: at most 1.5)")
    print(f"vector churn / constant step:  {med['BM_Pile_ChurnVector'] / c:.1f}")
    print(f"pooled / constant step:        {med['BM_Pile_Pooled'] / c:.3f}")
    print(f"spawn from shape / prepared:   "
          f"{med['BM_Spawn_FromShape'] / med['BM_Spawn_FromPreparedShape']:.0f}")


if __name__ == "__main__":
    main()
