#!/usr/bin/env python3
"""Writes the page that answers across the studies, DIR/report.md (DIR: docs/study), and the regime map
DIR/regime-map.png, from each study's results.json as scripts/run-studies.sh writes them: the answer first
(at most ten lines), the regime map, the fair pairs of every scene, every variant against `phong`, and what
ended each study's repeats. Every number comes from the studies' own "comparisons" (symphong study computes
each ratio and its interval once: study/comparisons.h); nothing is written by hand.

  study-report.py [--out DIR] [--minutes M] BOX_SCENE... -- REGIME_SCENE...
  study-report.py --compare DIR_A DIR_B BOX_SCENE... -- REGIME_SCENE...   (two runs side by side, Markdown on stdout)

A box scene's study is DIR/<basename>, a regime scene's DIR/regime/<basename>."""
import json
import math
import os
import sys

PAIR_ORDER = ["symmetric-mix+spread", "symmetric-mix+orbit2", "symmetric-mix+orbit4", "symmetric-mix+orbit8"]
LIGHTS = [("small", "small area light"), ("large", "large area light"), ("sky", "smooth sky, no sun"), ("sun", "HDR sky with a sun")]
EXPONENTS = [1, 10, 100, 1000]
MARK = {"ahead": "+", "behind": "-", "equal": "=", "not resolved": "?"}


def parse(argv):
    opts = {"out": "docs/study", "minutes": None, "compare": None}
    i = 0
    boxes, regime, seen_sep = [], [], False
    while i < len(argv):
        a = argv[i]
        if a == "--out":
            opts["out"] = argv[i + 1]
            i += 2
        elif a == "--minutes":
            opts["minutes"] = argv[i + 1]
            i += 2
        elif a == "--compare":
            opts["compare"] = (argv[i + 1], argv[i + 2])
            i += 3
        elif a == "--":
            seen_sep = True
            i += 1
        else:
            (regime if seen_sep else boxes).append(os.path.splitext(os.path.basename(a))[0])
            i += 1
    return opts, boxes, regime


def load(top, boxes, regime):
    data = {}
    for name in boxes:
        data[name] = json.load(open(f"{top}/{name}/results.json"))
    for name in regime:
        data[name] = json.load(open(f"{top}/regime/{name}/results.json"))
    return data


def link(name, regime):
    return f"regime/{name}/report.md" if name in regime else f"{name}/report.md"


def fmt_factor(x):
    return f"{x:.0f}x" if x >= 10 else f"{x:#.2g}x"


def fmt_cell(c, key="mse"):
    m = c.get(key)
    if not m:
        return "-"
    lo, hi = m["lo"], m["hi"]
    return f"{fmt_factor(m['ratio'])} [{lo:.2f}, {hi:.2f}]"


def comparison(d, variant, against=None, fair=None):
    for c in d.get("comparisons", []):
        if c["variant"] == variant and (against is None or c["against"] == against) and (fair is None or c["fair_pair"] == fair):
            return c
    return None


def fair_pair(d, variant):
    return comparison(d, variant, fair=True)


def verdict(c):
    return c["mse"]["verdict"] if c and c.get("mse") else None


def repeats_range(d):
    top = max(d["config"]["spp"])
    reps = [s["repeats"] for s in d["summary"] if s["spp"] == top]
    return min(reps), max(reps)


def regime_map(data, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import TwoSlopeNorm
    fig, axes = plt.subplots(1, 4, figsize=(15, 4.2), constrained_layout=True)
    norm = TwoSlopeNorm(vmin=-1.0, vcenter=0.0, vmax=1.0)
    titles = {"symmetric-mix+spread": "spread (1 path) vs phong",
              "symmetric-mix+orbit2": "orbit 2 vs phong split 2",
              "symmetric-mix+orbit4": "orbit 4 vs phong split 4",
              "symmetric-mix+orbit8": "orbit 8 vs phong split 8"}
    image = None
    for ax, variant in zip(axes, PAIR_ORDER):
        grid = [[math.nan] * len(EXPONENTS) for _ in LIGHTS]
        for i, (light, _) in enumerate(LIGHTS):
            for j, n in enumerate(EXPONENTS):
                d = data.get(f"{light}-n{n}")
                c = fair_pair(d, variant) if d else None
                if c and c.get("mse"):
                    r = c["mse"]["ratio"]
                    grid[i][j] = math.log2(r)
                    ax.text(j, i, f"{r:.2f}x\n{MARK[c['mse']['verdict']]}", ha="center", va="center", fontsize=9,
                            color="white" if abs(math.log2(r)) > 0.6 else "black")
        image = ax.imshow(grid, cmap="RdBu", norm=norm)
        ax.set_xticks(range(len(EXPONENTS)), [f"n = {n}" for n in EXPONENTS], fontsize=8)
        ax.set_yticks(range(len(LIGHTS)), [label for _, label in LIGHTS], fontsize=8)
        ax.set_title(titles[variant], fontsize=10)
    cb = fig.colorbar(image, ax=axes, shrink=0.8, ticks=[-1, -0.5, 0, 0.5, 1])
    cb.ax.set_yticklabels(["0.5x", "0.71x", "1x", "1.41x", "2x"])
    cb.set_label("efficiency of symmetric-mix / phong\n(equal paths per camera sample)", fontsize=8)
    fig.suptitle("Where could symmetric copies pay? Efficiency 1/(MSE x CPU time) of symmetric-mix against phong with the same paths "
                 "per camera sample\n(+ ahead, - behind, = equal within 10%, ? not resolved: by the 95% interval)", fontsize=10)
    fig.savefig(f"{out}/regime-map.png", dpi=100)
    plt.close(fig)


def answer_lines(data, names, regime):
    lines = []
    counts = {"ahead": 0, "behind": 0, "equal": 0, "not resolved": 0}
    per_variant = {}
    for variant in PAIR_ORDER:
        vs = []
        for name in names:
            c = fair_pair(data[name], variant)
            if c and c.get("mse"):
                counts[c["mse"]["verdict"]] += 1
                vs.append((c["mse"]["ratio"], c["mse"]["verdict"], name))
        per_variant[variant] = vs
    total = sum(counts.values())
    ahead, behind, equal, unresolved = counts["ahead"], counts["behind"], counts["equal"], counts["not resolved"]
    word = ("Yes" if ahead and not behind else "No" if behind and not ahead else "It depends on the scene and on R" if ahead and behind
            else "No gain")
    lines.append(f"**Does symmetric sampling pay?** {word}: of {total} fair pairs on {len(names)} scenes (`symmetric-mix` "
                 f"against `phong` with the same paths per camera sample, efficiency by CPU time) it is ahead in {ahead}, "
                 f"behind in {behind}, equal within 10% in {equal}" + (f", not resolved in {unresolved}" if unresolved else "") + ".")
    against = {"symmetric-mix+spread": "`phong`", "symmetric-mix+orbit2": "`phong+split2`",
               "symmetric-mix+orbit4": "`phong+split4`", "symmetric-mix+orbit8": "`phong+split8`"}
    for variant in PAIR_ORDER:
        vs = per_variant[variant]
        if not vs:
            continue
        by = {k: sum(1 for _, v, _ in vs if v == k) for k in counts}
        best = max(vs)
        worst = min(vs)
        lines.append(f"`{variant}` against {against[variant]}: ahead on {by['ahead']}, behind on {by['behind']}, equal on {by['equal']}"
                     + (f", not resolved on {by['not resolved']}" if by["not resolved"] else "")
                     + f" of {len(vs)} scenes; from {fmt_factor(worst[0])} ({worst[2]}) to {fmt_factor(best[0])} ({best[2]}).")
    # Splitting alone.
    split_best = []
    for name in names:
        d = data[name]
        opts = [(c["mse"]["ratio"], c["variant"]) for c in d.get("comparisons", [])
                if c["against"] == "phong" and c["variant"].startswith("phong+split") and c.get("mse")]
        if opts:
            split_best.append((max(opts)[0], max(opts)[1], name))
    if split_best:
        gains = sorted(r for r, _, _ in split_best)
        lines.append(f"**Splitting alone** (the best of `phong+split2/4/8` against `phong`): from {fmt_factor(gains[0])} to "
                     f"{fmt_factor(gains[-1])} (median {fmt_factor(gains[len(gains) // 2])}); the best K differs by scene, as issue 32 expects.")
    biased = []
    for name in names:
        for s in data[name]["summary"]:
            if s["spp"] == max(data[name]["config"]["spp"]) and s["bias_significant"]:
                biased.append((s["variant"], s["relative_bias"], name))
    if biased:
        paper = [b for b in biased if b[0].startswith("paper")]
        others = [b for b in biased if not b[0].startswith("paper")]
        if paper:
            lo = min(b[1] for b in paper)
            hi = max(b[1] for b in paper)
            lines.append(f"**The paper's estimator as printed** is biased on every scene it ran on: {100 * lo:+.0f}% to {100 * hi:+.0f}% "
                         "in the image mean (docs/replication.md).")
        if others:
            lines.append("**Also flagged biased**: " + ", ".join(f"`{v}` on {n} ({100 * b:+.1f}%)" for v, b, n in others) + ".")
    settled = [n for n in names if data[n].get("stopped_by") == "target"]
    timed = [n for n in names if data[n].get("stopped_by") != "target"]
    lines.append(f"**Settled**: on {len(settled)} of {len(names)} scenes every comparison was decided within +-10% before the "
                 f"scene's budget" + (f"; the budget ended {', '.join(timed)}" if timed else "") + " (the last table).")
    return lines[:10]


def write(opts, boxes, regime):
    top = opts["out"]
    names = boxes + regime
    data = load(top, boxes, regime)
    cfg_box = data[boxes[0]]["config"] if boxes else None
    cfg_reg = data[regime[0]]["config"] if regime else None
    regime_map(data, top)
    L = ["# Does symmetric sampling pay? The study across {} scenes".format(len(names)), ""]
    minutes = f" ({opts['minutes']} minutes on 2 cores)" if opts["minutes"] else ""
    desc = (f"Generated by `scripts/run-studies.sh`{minutes}: `symphong study` on each scene, then `scripts/study-report.py`. "
            "Efficiency is 1/(MSE x CPU time of the render's threads) (`--cost cpu`: another program on the machine does not bend it); "
            "a variant's is 1/(mean MSE x mean cost) over its repeats, repeat r of every variant with seed r (paired). "
            "Each ratio's [a, b] is its 95% interval (delta method on the log ratio of means; its coverage is tested in "
            "`tests/test_study_intervals.cpp`). A study adds paired repeats at its top spp until every comparison "
            "says ahead, behind or equal (its whole interval inside [0.9, 1.1]) with a half-width of at most 10% of its ratio "
            "(`--target-interval 0.1`), or its `--time` runs out. ")
    if cfg_box:
        desc += (f"The boxes: {cfg_box['width']}x{cfg_box['height']}, {', '.join(map(str, cfg_box['spp']))} spp, at least "
                 f"{cfg_box['repeats']} repeats, reference `phong` at {cfg_box['reference']['spp']} spp. ")
    if cfg_reg:
        desc += (f"The regime scenes (`scenes/regime/`: a glossy sphere on a glossy floor, rho_d 0.15, rho_s 0.6): "
                 f"{cfg_reg['width']}x{cfg_reg['height']}, {', '.join(map(str, cfg_reg['spp']))} spp, reference at "
                 f"{cfg_reg['reference']['spp']} spp. ")
    desc += ("`+orbitR`: `symmetric-mix` tracing R symmetric copies of one point from each camera sample (R paths); `+splitK`: K "
             "independent directions from each camera sample's first hit; `+spread`: the symmetric set spread over a pixel's "
             "camera samples (one path each).")
    L += [desc, "", "## The answer", ""] + ["- " + l for l in answer_lines(data, names, regime)] + [""]
    L += ["## The regime map", "",
          "![Efficiency of symmetric-mix against phong with equal paths, by light size and Phong exponent](regime-map.png)", "",
          "Each cell is one scene of `scenes/regime/` (`<light>-n<N>.json`), its study's fair-pair ratio with its verdict.", ""]
    # Fair pairs per scene.
    L += ["## Fair pairs: `symmetric-mix` against `phong` with the same paths per camera sample", "",
          "| scene | spread vs `phong` | orbit 2 vs `phong+split2` | orbit 4 vs `phong+split4` | orbit 8 vs `phong+split8` |",
          "|---|---:|---:|---:|---:|"]
    for name in names:
        cells = []
        for variant in PAIR_ORDER:
            c = fair_pair(data[name], variant)
            cells.append(f"{fmt_cell(c)} {verdict(c)}" if c and c.get("mse") else "-")
        L.append(f"| [{name}]({link(name, regime)}) | " + " | ".join(cells) + " |")
    L.append("")
    # Every variant against phong.
    variants = []
    for name in names:
        for v in data[name]["config"]["variants"]:
            if v["label"] not in variants and v["label"] != "phong":
                variants.append(v["label"])
    for group, title in ((boxes, "the boxes"), (regime, "the regime scenes")):
        if not group:
            continue
        vs = [v for v in variants if any(comparison(data[n], v, "phong") for n in group)]
        L += [f"## Every variant against `phong`: {title}", "",
              "Efficiency 1/(MSE x CPU time) over `phong`'s, at the top spp, with its 95% interval; (biased): significantly biased "
              "against the reference (|z| > 4), its efficiency means little.", "",
              "| variant | " + " | ".join(f"[{n}]({link(n, regime)})" for n in group) + " |", "|---|" + "---:|" * len(group)]
        for v in vs:
            cells = []
            for n in group:
                c = comparison(data[n], v, "phong")
                cells.append((fmt_cell(c) + (" (biased)" if c["biased"] else "")) if c else "-")
            L.append(f"| `{v}` | " + " | ".join(cells) + " |")
        L.append("")
    # How each study ended.
    L += ["## How each study ended", "",
          "| scene | stopped by | repeats at the top spp (fewest to most) | minutes |", "|---|---|---:|---:|"]
    for name in names:
        d = data[name]
        lo, hi = repeats_range(d)
        L.append(f"| {name} | {d.get('stopped_by', '-')} | {lo} to {hi} | {d.get('study_seconds', 0) / 60:.1f} |")
    L += ["", "`target`: every comparison decided within +-10%; `time`: the scene's `--time` budget ended the rounds first "
          "(the comparisons still open are named in that scene's report.md).", "",
          "## Each scene", "",
          "Each scene's `report.md` answers for that scene with its own intervals and tables; `details.md` has every measure, the "
          "variance budget and the plots; `report.html` (open it from a clone: it holds its images) flips between the reference "
          "and every render at the top spp with error and FLIP maps.", ""]
    for name in names:
        L.append(f"- [{name}]({link(name, regime)})")
    L.append("")
    with open(f"{top}/report.md", "w") as f:
        f.write("\n".join(L))


def compare(opts, boxes, regime):
    a_dir, b_dir = opts["compare"]
    names = boxes + regime
    a, b = load(a_dir, boxes, regime), load(b_dir, boxes, regime)
    print("| scene | comparison | run A | run B | same verdict |")
    print("|---|---|---:|---:|---|")
    same = total = 0
    for name in names:
        for ca in a[name].get("comparisons", []):
            if ca["biased"] or not ca.get("mse"):
                continue
            cb = comparison(b[name], ca["variant"], ca["against"])
            if not cb or not cb.get("mse"):
                continue
            va, vb = ca["mse"]["verdict"], cb["mse"]["verdict"]
            total += 1
            same += va == vb
            print(f"| {name} | `{ca['variant']}` vs `{ca['against']}` | {fmt_cell(ca)} {va} | {fmt_cell(cb)} {vb} | "
                  f"{'yes' if va == vb else '**no**'} |")
    print(f"\n{same} of {total} comparisons have the same verdict in both runs.")


def main(argv):
    opts, boxes, regime = parse(argv)
    if opts["compare"]:
        compare(opts, boxes, regime)
    else:
        write(opts, boxes, regime)


if __name__ == "__main__":
    main(sys.argv[1:])
