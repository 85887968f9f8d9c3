#!/usr/bin/env python3
"""Measures the tables of docs/estimators.md section 8 and prints them as Markdown.

Usage: python3 scripts/furnace-tables.py [--binary build/release/symphong] [--sampler independent]

Runs the two `symphong furnace` commands the section names (the bias grid and the variance and
efficiency sweep), reads their --json output and prints: the relative bias and z-score of every
estimator in every (n, theta) cell; the variance per direction and the efficiency 1/(var x time), both
relative to `cosine`, in every (environment, n, theta) cell; and each estimator's directions and time
per estimate. Every number printed comes from those runs; nothing is typed in.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
from collections import defaultdict

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def furnace(binary, args):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "furnace.json")
        subprocess.run([binary, "furnace", *args, "--json", out], check=True, stdout=subprocess.DEVNULL)
        with open(out) as f:
            return json.load(f)


def fmt(x):
    return f"{x:.3g}"


def bias_table(rows):
    estimators = list(dict.fromkeys(r["estimator"] for r in rows))
    ns = sorted({r["n"] for r in rows})
    thetas = sorted({r["theta_deg"] for r in rows})
    cell = {(r["estimator"], r["theta_deg"], r["n"]): r for r in rows}
    print("| estimator | " + " | ".join(f"n={n:g}" for n in ns) + " |")
    print("|---|" + "---:|" * len(ns))
    for e in estimators:
        for t in thetas:
            parts = []
            for n in ns:
                r = cell[(e, t, n)]
                parts.append(f"{100 * r['relative_bias']:+.2f}% ({r['z']:+.1f})")
            print(f"| {e}, theta {t:g} | " + " | ".join(parts) + " |")


def relative_tables(rows, biased):
    estimators = list(dict.fromkeys(r["estimator"] for r in rows))
    keys = list(dict.fromkeys((r["environment"], r["n"], r["theta_deg"]) for r in rows))
    cell = {(r["environment"], r["n"], r["theta_deg"], r["estimator"]): r for r in rows}
    header = "| environment | n | theta | " + " | ".join(estimators) + " |"
    rule = "|---|---:|---:|" + "---:|" * len(estimators)
    for title, field, invert in (("Variance per direction, relative to `cosine`:", "variance_times_directions", False),
                                 ("Efficiency `1/(var x time)` at the single-point level, relative to `cosine`:", "efficiency", False)):
        print(title)
        print()
        print(header)
        print(rule)
        for env, n, theta in keys:
            base = cell[(env, n, theta, "cosine")][field]
            vals = []
            for e in estimators:
                v = cell[(env, n, theta, e)][field] / base
                vals.append(fmt(v) + ("*" if e in biased and field != "efficiency" else ""))
            print(f"| {env} | {n:g} | {theta:g} | " + " | ".join(vals) + " |")
        print()
    per = defaultdict(list)
    for r in rows:
        per[r["estimator"]].append(r)
    print("Mean directions and time per estimate over those runs (one thread):")
    print()
    print("| estimator | directions | us per estimate | ns per direction |")
    print("|---|---:|---:|---:|")
    for e in estimators:
        rs = per[e]
        d = sum(r["directions_per_estimate"] for r in rs) / len(rs)
        s = sum(r["seconds_per_estimate"] for r in rs) / len(rs)
        print(f"| {e} | {d:.1f} | {1e6 * s:.2f} | {1e9 * s / d:.0f} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "release", "symphong"))
    ap.add_argument("--sampler", default="independent")
    args = ap.parse_args()
    grid = ["--grid", "-M", "20000", "--sampler", args.sampler]
    sweep = ["--environment", "all", "-e", "all", "--n", "10,1000", "--theta", "30,70", "-M", "20000", "--sampler", args.sampler]
    print(f"### Bias: `symphong furnace {' '.join(grid)}`")
    print()
    bias_table(furnace(args.binary, grid))
    print()
    print(f"### Variance and efficiency: `symphong furnace {' '.join(sweep)}`")
    print()
    rows = furnace(args.binary, sweep)
    biased = {r["estimator"] for r in rows if abs(r["z"]) > 10}
    relative_tables(rows, biased)
    return 0


if __name__ == "__main__":
    sys.exit(main())
