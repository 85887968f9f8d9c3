#!/usr/bin/env python3
"""Writes docs/replication.md: each claim of the paper (Penzov, Dimov, Sirakova, Koylazov, "Monte Carlo
Estimator for Image Creation with Symmetric Sampling of Phong BRDF Model"), in our words, beside what we
measured. Every number in the page comes from this script's own runs: four `symphong furnace` commands
(one shading point, exact reference values) that it runs and names, and the studies of full renders in
docs/study (scripts/run-studies.sh) that it reads. Nothing is typed in.

Usage: python3 scripts/replication-report.py [--binary build/release/symphong] [--study docs/study]
       (about 2 minutes on 2 cores; run it after scripts/run-studies.sh)"""
import argparse
import datetime
import importlib.util
import json
import os
import statistics

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BOXES = ["cornell", "cornell-diffuse", "cornell-glossy-100", "cornell-glossy-1000", "cornell-all-glossy", "mcguire-glossy"]

CMD_BIAS = ["-e", "paper,symmetric", "--grid", "-M", "20000", "--sampler", "independent"]
CMD_DIFFUSE = ["-e", "paper,symmetric", "--rho-d", "1", "--rho-s", "0", "--n", "1", "--theta", "0,30,60,85", "-M", "20000",
               "--sampler", "independent"]
CMD_SPECULAR = ["-e", "paper,symmetric", "--rho-d", "0", "--rho-s", "1", "--n", "1,10,100,1000", "--theta", "0,30,60", "-M", "20000",
                "--sampler", "independent"]
CMD_VARIANCE = ["--environment", "all", "-e", "cosine,stratified,phong,symmetric,symmetric-shifted,symmetric-mix", "--n", "10,1000",
                "--theta", "30,70", "-M", "20000", "--sampler", "independent"]


def furnace(binary, args):
    """`symphong furnace ARGS --json`'s rows: scripts/furnace-tables.py's runner (one definition)."""
    spec = importlib.util.spec_from_file_location("furnace_tables", os.path.join(ROOT, "scripts", "furnace-tables.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.furnace(binary, args)


def pct(x):
    return f"{100 * x:+.0f}%"


def span(xs, f=pct):
    lo, hi = f(min(xs)), f(max(xs))
    return lo if lo == hi else f"{lo} to {hi}"


def low(xs):
    """Relative biases (all negative) as "33% to 83% low"."""
    a, b = sorted(-100 * x for x in xs)[0], sorted(-100 * x for x in xs)[-1]
    return f"{a:.0f}% low" if round(a) == round(b) else f"{a:.0f}% to {b:.0f}% low"


def fx(x):
    return f"{x:.0f}x" if x >= 10 else f"{x:#.2g}x"


def command(args):
    return "`symphong furnace " + " ".join(args) + "`"


def load_studies(study):
    data = {}
    for name in BOXES:
        p = os.path.join(study, name, "results.json")
        if os.path.exists(p):
            data[name] = json.load(open(p))
    regime = {}
    rdir = os.path.join(study, "regime")
    if os.path.isdir(rdir):
        for name in sorted(os.listdir(rdir)):
            p = os.path.join(rdir, name, "results.json")
            if os.path.exists(p):
                regime[name] = json.load(open(p))
    return data, regime


def cmp(d, variant, against="phong", fair=None):
    for c in d.get("comparisons", []):
        if c["variant"] == variant and c["against"] == against and (fair is None or c["fair_pair"] == fair) and c.get("mse"):
            return c["mse"]
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "release", "symphong"))
    ap.add_argument("--study", default=os.path.join(ROOT, "docs", "study"))
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "replication.md"))
    a = ap.parse_args()

    bias = furnace(a.binary, CMD_BIAS)
    diffuse = furnace(a.binary, CMD_DIFFUSE)
    specular = furnace(a.binary, CMD_SPECULAR)
    var = furnace(a.binary, CMD_VARIANCE)
    boxes, regime = load_studies(a.study)
    allscenes = {**boxes, **regime}

    paper = [r for r in bias if r["estimator"] == "paper"]
    sym = [r for r in bias if r["estimator"] == "symmetric"]
    worst = min(paper, key=lambda r: r["relative_bias"])
    paper_d = [r for r in diffuse if r["estimator"] == "paper"]
    paper_s = [r for r in specular if r["estimator"] == "paper"]
    sym_z = max(abs(r["z"]) for r in sym + [r for r in diffuse + specular if r["estimator"] == "symmetric"])

    # Variance per direction and efficiency relative to cosine and stratified, per (environment, n, theta).
    cell = {(r["environment"], r["n"], r["theta_deg"], r["estimator"]): r for r in var}
    # The constant environment apart: there the projected-solid-angle maps are exact (variance 0 up to rounding),
    # which says nothing of how they do on light that varies.
    keys = sorted({(r["environment"], r["n"], r["theta_deg"]) for r in var if r["environment"] != "constant"})
    envs = sorted({k[0] for k in keys})
    def rel(est, base, field):
        return [cell[k + (est,)][field] / cell[k + (base,)][field] for k in keys]
    v_sym_cos = rel("symmetric", "cosine", "variance_times_directions")
    v_sym_strat = rel("symmetric", "stratified", "variance_times_directions")
    v_shift_strat = rel("symmetric-shifted", "stratified", "variance_times_directions")
    v_mix_phong = rel("symmetric-mix", "phong", "variance_times_directions")
    e_sym_cos = rel("symmetric", "cosine", "efficiency")
    e_mix_phong = rel("symmetric-mix", "phong", "efficiency")
    ns_dir = {e: statistics.mean(r["seconds_per_estimate"] / r["directions_per_estimate"] for r in var if r["estimator"] == e) * 1e9
              for e in ("cosine", "phong", "symmetric", "symmetric-mix")}

    # Full renders.
    paper_img = []
    for name, d in boxes.items():
        top = max(d["config"]["spp"])
        for s in d["summary"]:
            if s["spp"] == top and s["estimator"] == "paper":
                paper_img.append((s["relative_bias"], s["variant"], name, s["bias_significant"]))
    sym_branch = [(cmp(d, "symmetric")["ratio"], n) for n, d in boxes.items() if cmp(d, "symmetric")]
    sym_spread = [(cmp(d, "symmetric+spread")["ratio"], n) for n, d in boxes.items() if cmp(d, "symmetric+spread")]
    pairs = {v: [] for v in ("symmetric-mix+spread", "symmetric-mix+orbit2", "symmetric-mix+orbit4", "symmetric-mix+orbit8")}
    for n, d in allscenes.items():
        for v in pairs:
            for c in d.get("comparisons", []):
                if c["variant"] == v and c["fair_pair"] and c.get("mse"):
                    pairs[v].append((c["mse"]["ratio"], c["mse"]["verdict"], n))
    verdicts = [v for ps in pairs.values() for _, v, _ in ps]
    count = {k: verdicts.count(k) for k in ("ahead", "behind", "equal", "not resolved")}
    best_pair = max((p for ps in pairs.values() for p in ps), default=None)

    today = datetime.date.today().isoformat()
    L = ["# Replication: what the paper claims, and what we measured", "",
         f"Generated by `python3 scripts/replication-report.py` on {today}: it runs the four `symphong furnace` commands named "
         "below (one shading point under incoming radiance whose reflected value is known exactly) and reads the studies of full "
         "renders in [docs/study](study/report.md) (`scripts/run-studies.sh`). Every figure on this page comes from those runs. "
         "The paper: [summary](../../shared/docs/paper-summary.md) (its errata list is ours); equation numbers are the paper's.", "",
         "## The answer", ""]
    ans = [
        f"**The estimator as printed (Eq. 4 + 7 = Eq. 8) is biased**: at one shading point its mean is {low([r['relative_bias'] for r in paper])} "
        f"(rho_d 0.3, rho_s 0.6, constant light), worst at grazing view ({pct(worst['relative_bias'])} at "
        f"n = {worst['n']:g}, theta = {worst['theta_deg']:g} degrees)"
        + (f"; full renders with it are {low([b for b, *_ in paper_img])} in their image mean." if paper_img else "."),
        f"**Both halves are wrong**: the diffuse part alone (Eq. 4, rho_s = 0) is {low([r['relative_bias'] for r in paper_d])}, "
        f"the specular part alone (Eq. 5-7, rho_d = 0) {low([r['relative_bias'] for r in paper_s])}.",
        f"**Corrected, the separation is unbiased**: `symmetric` (exact maps and densities) stays within {sym_z:.1f} standard errors "
        "of the exact value in every cell of the same runs.",
        f"**Variance reduction (abstract, Sec. 3, conclusion)**: exact under constant light; under the {len(envs)} varying "
        f"lights ({', '.join(envs)}), per direction, corrected `symmetric` has {span(v_sym_cos, fx)} the variance of cosine sampling and {span(v_sym_strat, fx)} that of stratified cosine sampling; with a shifted (u,v) per copy "
        f"{span(v_shift_strat, fx)}. Against Phong-lobe sampling, `symmetric-mix` has {span(v_mix_phong, fx)}.",
        f"**Efficiency from reuse (conclusion)**: the copies are cheap ({ns_dir['symmetric']:.0f} ns a direction against "
        f"{ns_dir['cosine']:.0f} for cosine), but in full renders ray casting dominates: "
        + (f"`symmetric` (its whole set from each camera sample) reaches {span([r for r, _ in sym_branch], fx)} `phong`'s "
           f"efficiency, `symmetric+spread` {span([r for r, _ in sym_spread], fx)}." if sym_branch else "no study ran it."),
        f"**At equal paths** (the fair question): `symmetric-mix` against `phong` split the same number of ways is ahead in "
        f"{count['ahead']}, behind in {count['behind']}, equal within 10% in {count['equal']}"
        + (f", not resolved in {count['not resolved']}" if count["not resolved"] else "")
        + f" of {len(verdicts)} scene x orbit pairs"
        + (f"; its best is {fx(best_pair[0])} ({best_pair[2]})." if best_pair else "."),
        "**So**: the paper's estimator does not compute what it claims; corrected, symmetric sampling is a valid estimator whose "
        "advantage over Phong-lobe importance sampling is small and depends on the light and the exponent (the regime map below).",
    ]
    L += ["- " + l for l in ans[:10]] + [""]

    L += ["## Claim by claim", "",
          "| the paper says | where | we measured | how |", "|---|---|---|---|",
          f"| Eq. (4) estimates the diffuse integral L1 | Sec. 3, Eq. (3)-(4) | biased: {span([r['relative_bias'] for r in paper_d])} "
          "(the quadrangle map lands on the mirror of the triangle; the sub-domain probabilities weigh instead of dividing) | "
          f"{command(CMD_DIFFUSE)} |",
          f"| Eq. (7) estimates the specular integral L2 over a cone approximated by rotated triangles | Sec. 3, Eq. (2), (5)-(7) | "
          f"biased: {span([r['relative_bias'] for r in paper_s])} (the product of integrals in Eq. 5; no density weight in Eq. 7; the "
          "rotated face is not the cone and dips under the horizon past 45 degrees) | " + command(CMD_SPECULAR) + " |",
          f"| Eq. (8) = (4) + (7) estimates the reflected radiance | Sec. 3 | biased: {span([r['relative_bias'] for r in paper])} over "
          f"n in 1..10^4, view 0..85 degrees | {command(CMD_BIAS)} |",
          f"| Uniform Separation reduces variance | abstract, Sec. 3, conclusion | corrected, per direction against cosine sampling: "
          f"{span(v_sym_cos, fx)}; against stratified: {span(v_sym_strat, fx)} (one (u,v) gives every copy the same elevation); "
          f"shifted copies against stratified: {span(v_shift_strat, fx)} | {command(CMD_VARIANCE)} |",
          f"| Reuse by symmetry and rotation is fast and improves efficiency | conclusion | at one point, efficiency 1/(variance x time) "
          f"of `symmetric` against cosine: {span(e_sym_cos, fx)}, of `symmetric-mix` against `phong`: {span(e_mix_phong, fx)}; in "
          "renders: the answer's lines 5 and 6 | the same, and docs/study |",
          "| Easy to parallelise and to port to the GPU | conclusion | not measured here (the path tracer is parallel over tiles "
          "and MPI ranks for every estimator alike) | - |", ""]

    L += ["## In full renders", "",
          "Efficiency 1/(MSE x CPU time) against `phong` at the study's top spp with its 95% interval (paired repeats until every "
          "comparison is decided within +-10%, or the scene's budget): [docs/study/report.md](study/report.md) has every scene, "
          "variant and interval.", "",
          "| scene | `paper` bias (image mean) | `symmetric` | `symmetric+spread` | `symmetric-mix+spread` | orbit 2 vs split 2 | "
          "orbit 4 vs split 4 | orbit 8 vs split 8 |", "|---|---:|---:|---:|---:|---:|---:|---:|"]
    def cellt(m):
        return f"{fx(m['ratio'])} [{m['lo']:.2f}, {m['hi']:.2f}] {m['verdict']}" if m else "-"
    for name, d in allscenes.items():
        pb = [b for b, v, n, sig in paper_img if n == name]
        L.append(f"| {name} | {', '.join(pct(b) for b in pb) or '-'} | {cellt(cmp(d, 'symmetric'))} | {cellt(cmp(d, 'symmetric+spread'))} | "
                 f"{cellt(cmp(d, 'symmetric-mix+spread'))} | {cellt(cmp(d, 'symmetric-mix+orbit2', 'phong+split2'))} | "
                 f"{cellt(cmp(d, 'symmetric-mix+orbit4', 'phong+split4'))} | {cellt(cmp(d, 'symmetric-mix+orbit8', 'phong+split8'))} |")
    L += ["", "## The regime map", "",
          "![symmetric-mix against phong with equal paths, by light size and exponent](study/regime-map.png)", "",
          "A glossy sphere on a glossy floor (`scenes/regime/`, rho_d 0.15, rho_s 0.6) under a small or a large area light of the "
          "same power, a smooth sky, or that sky with a sun, at n = 1, 10, 100, 1000: where, if anywhere, symmetric copies of one "
          "point beat as many independent Phong-lobe directions. Drawn by `scripts/study-report.py` from the same studies.", "",
          "## The estimator as printed, cell by cell", "",
          f"Relative bias of the mean of 20,000 estimates (z-score in brackets), {command(CMD_BIAS)}:", "",
          "| view | " + " | ".join(f"n = {n:g}" for n in sorted({r['n'] for r in paper})) + " |",
          "|---|" + "---:|" * len({r["n"] for r in paper})]
    for t in sorted({r["theta_deg"] for r in paper}):
        row = sorted((r for r in paper if r["theta_deg"] == t), key=lambda r: r["n"])
        L.append(f"| theta {t:g} | " + " | ".join(f"{100 * r['relative_bias']:+.1f}% ({r['z']:+.0f})" for r in row) + " |")
    L += ["", "docs/estimators.md derives each error and the corrected maps; `tests/test_separation.cpp` and "
          "`tests/test_furnace.cpp` test them against closed forms.", ""]
    with open(a.out, "w") as f:
        f.write("\n".join(L))
    print(f"{a.out} written")


if __name__ == "__main__":
    main()
