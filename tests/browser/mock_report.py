#!/usr/bin/env python3
"""Writes a filled study report (report.html) from the viewer template with synthetic data, for developing
and testing the page without a study: 64x48 pixels, 3 variants x 2 sample counts, one plot, one table.

The reference is a gradient with a checker and a bright disc; each variant is the reference with Gaussian
noise of its own strength (falling as 1/sqrt(spp)) and the FLIP map is a fake one made of the noise.
The data contract is documented at the top of the template (src/study/report_viewer.html).

Usage: mock_report.py TEMPLATE OUT.html [--null]   (--null: the last variant is not rendered at the last spp)
"""
import argparse
import base64
import io
import json
import sys

import numpy as np

MARKER = "@STUDY_DATA@"
W, H = 64, 48
SPP = [4, 16]
VARIANTS = [("phong", 0.35), ("symmetric-mix", 0.2), ("light-only", 0.6)]


def b64(data):
    return base64.b64encode(data).decode("ascii")


def half_b64(rgb):
    """Linear RGB (H, W, 3) as base64 of little-endian binary16, interleaved, row 0 at the top."""
    return b64(np.ascontiguousarray(rgb, dtype="<f2").tobytes())


def reference_image():
    y, x = np.mgrid[0:H, 0:W].astype(np.float64)
    u, v = x / (W - 1), y / (H - 1)
    checker = ((x // 8 + y // 8) % 2) * 0.15
    rgb = np.stack([0.15 + 0.6 * u, 0.1 + 0.5 * v, 0.6 - 0.4 * u], axis=-1) * (0.7 + checker)[..., None]
    disc = (x - 44) ** 2 + (y - 16) ** 2 < 8 ** 2
    rgb[disc] = [3.0, 2.6, 2.0]  # a light: above 1 so that exposure matters
    rgb[:4, :] *= 0.05  # a dark band where relative error is large
    return rgb


def plot_png(rmse):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(3.6, 2.6), dpi=80)
    for label, values in rmse.items():
        ax.loglog(SPP, values, marker="o", label=label)
    ax.set_xlabel("samples per pixel")
    ax.set_ylabel("RMSE")
    ax.legend(fontsize=7)
    fig.tight_layout()
    out = io.BytesIO()
    fig.savefig(out, format="png")
    plt.close(fig)
    return out.getvalue()


def study(drop_last=False):
    rng = np.random.default_rng(7)
    ref = reference_image()
    variants, rmse = [], {}
    for vi, (label, strength) in enumerate(VARIANTS):
        images = []
        for si, spp in enumerate(SPP):
            if drop_last and vi == len(VARIANTS) - 1 and si == len(SPP) - 1:
                images.append(None)
                continue
            sigma = strength / np.sqrt(spp)
            noise = rng.normal(0.0, sigma, ref.shape) * (ref + 0.05)
            img = np.maximum(ref + noise, 0.0)
            flip = np.clip(np.abs(noise).mean(axis=-1) * 2.0, 0.0, 1.0)
            err = img - ref
            images.append({
                "spp": spp, "image": half_b64(img), "flip": b64(np.round(255 * flip).astype(np.uint8).tobytes()),
                "flip_mean": float(flip.mean()), "rmse": float(np.sqrt((err ** 2).mean())),
                "relmse": float((err ** 2 / (ref ** 2 + 0.01)).mean()),
            })
        variants.append({"label": label, "images": images})
        rmse[label] = [im["rmse"] if im else np.nan for im in images]
    eff = {label: [rmse["phong"][s] ** 2 / rmse[label][s] ** 2 for s in range(len(SPP))] for label, _ in VARIANTS}
    rows = []
    for label, _ in VARIANTS:
        row = [{"text": f"`{label}`"}]
        for s in range(len(SPP)):
            value = eff[label][s]
            if np.isnan(value):
                row.append({"text": "-", "value": None})
            else:
                row.append({"text": f"{value:.2f}x [{value * 0.8:.2f}, {value * 1.2:.2f}]", "value": round(value, 4)})
        rows.append(row)
    return {
        "title": "Estimator study: mock",
        "subtitle": f"{W}x{H} pixels, 1 repeat, synthetic data from tests/browser/mock_report.py",
        "answer": ["`symmetric-mix` has the lowest error at every sample count.",
                   "`light-only` is the noisiest: about 3x the MSE of `phong`.",
                   "This page was generated from synthetic images </script> (a test of escaping)."],
        "width": W, "height": H, "spp": SPP,
        "reference": {"label": "reference (mock, 4096 spp)", "image": half_b64(ref)},
        "variants": variants,
        "plots": [{"title": "RMSE against samples per pixel", "png": b64(plot_png(rmse))}],
        "tables": [{"title": "Efficiency by MSE relative to `phong` (95% interval)",
                    "note": "Higher is better; '-' where a variant was not rendered.",
                    "columns": ["variant"] + [f"{n} spp" for n in SPP], "rows": rows}],
    }


def fill(template_text, data):
    """The template with its marker replaced by the JSON data, '</' escaped as the C++ side does."""
    if template_text.count(MARKER) != 1:
        raise SystemExit(f"the template must contain {MARKER} exactly once (found {template_text.count(MARKER)})")
    payload = json.dumps(data, allow_nan=False).replace("</", "<\\/")
    return template_text.replace(MARKER, payload)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("template")
    parser.add_argument("out")
    parser.add_argument("--null", action="store_true", help="leave the last variant unrendered at the last spp")
    args = parser.parse_args(argv)
    with open(args.template, encoding="utf-8") as f:
        text = fill(f.read(), study(args.null))
    with open(args.out, "w", encoding="utf-8") as f:
        f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
