#!/usr/bin/env python3
"""Plots for `symphong study`: reads DIR/results.json (and the heat maps and renders beside it) and writes
convergence_spp, convergence_time, efficiency, heatmaps and crops as PNG and SVG into DIR.

symphong embeds this file and runs it with Debian's python3-matplotlib; it can also be run by hand:
    python3 scripts/plot_study.py out/study
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

plt.rcParams.update({"svg.fonttype": "none", "svg.hashsalt": "symphong", "font.size": 9})

STYLE = {
    "uniform": ("#7f7f7f", "o"),
    "cosine": ("#1f77b4", "o"),
    "stratified": ("#17becf", "s"),
    "phong": ("#2ca02c", "^"),
    "paper": ("#d62728", "x"),
    "symmetric": ("#9467bd", "D"),
    "symmetric-shifted": ("#ff7f0e", "P"),
}


LINE = {"sobol": "-", "independent": "--", "stratified": "-."}


def style(name):
    return STYLE.get(name, ("#333333", "."))


def variants(data):
    """The study's variants (estimator, sampler, mode, label) in order; old results.json files have none."""
    cfg = data["config"]
    return cfg.get("variants") or [{"label": e, "estimator": e, "sampler": "independent", "mode": "branch"} for e in cfg["estimators"]]


def key(s):
    return s.get("variant", s["estimator"])


def save(fig, out_dir, stem, dpi=110):
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(out_dir, f"{stem}.{ext}"), dpi=dpi, bbox_inches="tight", metadata={"Date": None} if ext == "svg" else None)
    plt.close(fig)


def convergence(data, out_dir, x_key, stem, xlabel):
    summary = data["summary"]
    fig, ax = plt.subplots(figsize=(5.6, 4.0))
    anchor = None
    for v in variants(data):
        est = v["label"]
        pts = sorted((s[x_key], s["rmse"], s["rmse_spread"]) for s in summary if key(s) == est and s["rmse"] > 0)
        if not pts:
            continue
        xs, ys, es = zip(*pts)
        color, marker = style(v["estimator"])
        biased = any(s["bias_significant"] for s in summary if key(s) == est)
        label = est + (" (biased)" if biased else "")
        ax.errorbar(xs, ys, yerr=es, color=color, marker=marker, ms=4, lw=1.4, capsize=2, label=label,
                    ls=":" if biased else LINE.get(v["sampler"], "-"),
                    mfc="white" if v["mode"] == "spread" else color)
        if v["estimator"] == "cosine" or anchor is None:  # the 1/sqrt(N) line starts at cosine's first point
            anchor = (xs[0], ys[0])
    if anchor:
        xs = np.array([min(s[x_key] for s in summary), max(s[x_key] for s in summary)])
        ax.plot(xs, anchor[1] * np.sqrt(anchor[0] / xs), color="black", lw=0.8, ls=":", label="slope 1/sqrt(N)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("RMSE of luminance vs reference")
    ax.set_title(f"{data['config']['scene']}: RMSE against {xlabel.split(' (')[0]}")
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=7, frameon=False)
    save(fig, out_dir, stem)


def efficiency(data, out_dir):
    summary = data["summary"]
    top = max(data["config"]["spp"])
    rows = [s for s in summary if s["spp"] == top and math.isfinite(s["efficiency"]) and s["efficiency"] > 0]
    if not rows:
        return
    fig, axes = plt.subplots(1, 2, figsize=(max(9.0, 0.55 * len(rows) * 2), 3.8))
    cost = {"cpu": "CPU time", "wall": "wall time", "rays": "rays"}.get(data["config"].get("cost", "wall"), "time")
    for ax, key_, what in ((axes[0], "efficiency", f"1/(MSE x {cost})"), (axes[1], "efficiency_relmse", f"1/(relMSE x {cost})")):
        # The yardstick: plain `phong` (branch mode, no split), under the independent sampler when there are several.
        plain = [s for s in rows if s["estimator"] == "phong" and s["variant"].split("@")[0] == "phong"]
        base_row = next((s for s in plain if s.get("sampler") == "independent"), plain[0] if plain else None)
        base = base_row[key_] if base_row else max(s[key_] for s in rows)
        for i, s in enumerate(rows):
            v = s[key_] / base
            color, _ = style(s["estimator"])
            hatch = "//" if s["bias_significant"] else ("..." if s.get("mode") == "spread" else None)
            ax.bar(i, v, color=color, hatch=hatch, edgecolor="black", lw=0.5, alpha=0.55 if s.get("sampler") == "independent" else 1.0)
            ax.text(i, v, f"{v:.2g}x", ha="center", va="bottom", fontsize=7)
        ax.set_xticks(range(len(rows)))
        ax.set_xticklabels([key(s) + (" (biased)" if s["bias_significant"] else "") for s in rows], fontsize=7,
                           rotation=30, ha="right")
        ax.set_yscale("log")
        ax.set_ylabel(f"efficiency {what}\nrelative to " + (key(base_row) if base_row else "the best"))
        ax.axhline(1.0, color="black", lw=0.6)
        ax.grid(True, axis="y", which="both", alpha=0.25)
    fig.subplots_adjust(wspace=0.4)
    fig.suptitle(f"{data['config']['scene']}: efficiency at {top} spp (higher is better)", fontsize=9)
    save(fig, out_dir, "efficiency")


def heatmaps(data, out_dir):
    hm = data["config"]["heatmap"]
    w, h = hm["width"], hm["height"]
    maps = {}
    for est in (v["label"] for v in variants(data)):
        path = os.path.join(out_dir, "heatmaps", f"{est}.f32")
        if os.path.exists(path):
            maps[est] = np.fromfile(path, dtype="<f4").reshape(h, w)
    if not maps:
        return
    vmax = float(np.percentile(np.concatenate([m.ravel() for m in maps.values()]), 99)) or 1.0
    cols = min(3, len(maps))
    rows = math.ceil(len(maps) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(2.6 * cols, 2.6 * rows + 0.4), squeeze=False)
    im = None
    for ax in axes.ravel():
        ax.axis("off")
    for ax, (est, m) in zip(axes.ravel(), maps.items()):
        im = ax.imshow(m, cmap="inferno", vmin=0, vmax=vmax, interpolation="nearest")
        ax.set_title(f"{est}\nmean {m.mean():.3f}", fontsize=8)
        # One image per estimator at its own resolution, same colour scale as the figure.
        plt.imsave(os.path.join(out_dir, "heatmaps", f"{est}.png"), m, cmap="inferno", vmin=0, vmax=vmax)
    fig.colorbar(im, ax=axes.ravel().tolist(), shrink=0.8, label="|Y - Y_ref| / (Y_ref + 0.01)")
    fig.suptitle(f"Per-pixel relative error at {hm['spp']} spp (one render each)", fontsize=9)
    save(fig, out_dir, "heatmaps", dpi=90)


def crops(data, out_dir):
    hm = data["config"]["heatmap"]
    x, y, cw, ch = hm["crop"]
    panels = [("reference", os.path.join(out_dir, "reference.png"))]
    panels += [(v["label"], os.path.join(out_dir, "renders", f"{v['label']}.png")) for v in variants(data)]
    panels = [(n, p) for n, p in panels if os.path.exists(p)]
    if not panels:
        return
    fig, axes = plt.subplots(1, len(panels), figsize=(1.9 * len(panels), 2.3), squeeze=False)
    for ax, (name, path) in zip(axes[0], panels):
        img = mpimg.imread(path)
        ax.imshow(img[y:y + ch, x:x + cw], interpolation="nearest")
        ax.set_title(name, fontsize=7)
        ax.axis("off")
    fig.suptitle(f"Crops at {hm['spp']} spp: pixels ({x},{y}) to ({x + cw},{y + ch})", fontsize=8)
    save(fig, out_dir, "crops")


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else "out/study"
    with open(os.path.join(out_dir, "results.json")) as f:
        data = json.load(f)
    convergence(data, out_dir, "spp", "convergence_spp", "samples per pixel (equal samples)")
    if data["config"].get("cost", "wall") == "cpu":
        convergence(data, out_dir, "cpu_seconds", "convergence_time", "CPU time of the render in seconds (equal cost)")
    else:
        convergence(data, out_dir, "seconds", "convergence_time", "render time in seconds (equal time)")
    efficiency(data, out_dir)
    heatmaps(data, out_dir)
    crops(data, out_dir)


if __name__ == "__main__":
    main()
