#!/usr/bin/env python3
"""Prints the tables of scripts/run-first-bounce-studies.sh (Markdown) from the studies' results.json:
efficiency ratios as medians over the repeats (1/(MSE x time) at the top spp), MSE ratios as medians.
Usage: first-bounce-table.py ROOT   (ROOT = docs/study/first-bounce)"""
import json
import os
import statistics
import sys


def load(path):
    with open(os.path.join(path, "results.json")) as f:
        return json.load(f)


def med(d, variant, key):
    top = max(d["config"]["spp"])
    vals = [r[key] for r in d["rows"] if r["variant"] == variant and r["spp"] == top]
    return statistics.median(vals) if vals else float("nan")


def main(root):
    out = []
    scenes = ("cornell", "cornell-glossy-100")
    out += ["### First-hit splitting: `phong --split K` against `phong` (efficiency by MSE; MSE)", "",
            "| scene | K = 2 | K = 4 | K = 8 |", "|---|---:|---:|---:|"]
    for s in scenes:
        d = load(f"{root}/splits/{s}")
        cells = []
        for k in (2, 4, 8):
            v = f"phong+split{k}"
            cells.append(f"{med(d, v, 'efficiency') / med(d, 'phong', 'efficiency'):.2f}x ({med(d, v, 'mse') / med(d, 'phong', 'mse'):.2f}x)")
        out.append(f"| {s} | " + " | ".join(cells) + " |")
    out += ["", "### Orbits: `symmetric-mix --symmetric-orbit R` against `phong` (efficiency by MSE; MSE)", "",
            "| scene | R | spread (1 path per camera sample) | branch (R paths per camera sample) | `phong --split R` (R paths) |",
            "|---|---:|---:|---:|---:|"]
    for s in scenes:
        splits = load(f"{root}/splits/{s}")
        for r in (1, 2, 4, 8):
            d = load(f"{root}/orbits/{s}-orbit{r}")
            base_e, base_m = med(d, "phong", "efficiency"), med(d, "phong", "mse")
            spread = f"{med(d, 'symmetric-mix+spread', 'efficiency') / base_e:.2f}x ({med(d, 'symmetric-mix+spread', 'mse') / base_m:.2f}x)"
            branch = f"{med(d, 'symmetric-mix', 'efficiency') / base_e:.2f}x ({med(d, 'symmetric-mix', 'mse') / base_m:.2f}x)"
            if r == 1:
                split = "1x (1x)"
            else:
                sb_e, sb_m = med(splits, "phong", "efficiency"), med(splits, "phong", "mse")
                split = f"{med(splits, f'phong+split{r}', 'efficiency') / sb_e:.2f}x ({med(splits, f'phong+split{r}', 'mse') / sb_m:.2f}x)"
            out.append(f"| {s} | {r} | {spread} | {branch} | {split} |")
    out += ["", "### The joint 4D pattern against padded pairs (MSE ratio joint / padded; efficiency ratio)", "",
            "| scene | `cosine` | `phong` | `symmetric-mix+spread` |", "|---|---:|---:|---:|"]
    for s in ("cornell", "cornell-diffuse", "cornell-glossy-100", "cornell-glossy-1000", "cornell-all-glossy", "mcguire-glossy"):
        padded, joint = load(f"{root}/joint/{s}-padded"), load(f"{root}/joint/{s}-joint")
        cells = []
        for v in ("cosine", "phong", "symmetric-mix+spread"):
            cells.append(f"{med(joint, v, 'mse') / med(padded, v, 'mse'):.2f} ({med(joint, v, 'efficiency') / med(padded, v, 'efficiency'):.2f}x)")
        out.append(f"| {s} | " + " | ".join(cells) + " |")
    print("\n".join(out))


if __name__ == "__main__":
    main(sys.argv[1])
