"""Compares symphong's renders with Cycles' region by region and writes docs/validation.md's generated
part (between its validate markers) and the images in docs/images/validation/. Run by run.sh:

    compare.py OUT_DIR DOC IMAGE_DIR SCENE_KEY... (with PYTHONPATH=build/release/python)

OUT_DIR/<key>/ holds scene.json (export_scene.py), symphong-<seed>.exr, cycles-<seed>.exr, info.json.
Regions are surfaces: the triangles of one material and one plane, found under each pixel centre with
Scene.primary_hits; walls are named, the back and side walls split into four bands of image rows;
masks are eroded by a pixel (pixels on an edge mix surfaces). Per region: mean luminance on each side
(mean of two seeds), the ratio symphong/Cycles, its standard error from the seeds (a side's SE =
|m1 - m2| / 2), and per-channel ratios; a region is flagged when it differs by more than 0.5% and by
more than 3 standard errors."""
import json
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import symphong  # noqa: E402

LUMA = np.array([0.2126, 0.7152, 0.0722])


def erode(mask):
    m = mask.copy()
    m[1:, :] &= mask[:-1, :]
    m[:-1, :] &= mask[1:, :]
    m[:, 1:] &= mask[:, :-1]
    m[:, :-1] &= mask[:, 1:]
    m[0, :] = m[-1, :] = m[:, 0] = m[:, -1] = False
    return m


def surfaces(scene_json, hits):
    """(name, mask) of every surface seen, walls first."""
    d = json.load(open(scene_json))
    P = np.array(d["positions"])
    T = np.array(d["triangles"])
    mat = np.array(d["material"])
    names = [m["name"] for m in d["materials"]]
    emissive = [max(m["emission"]) > 0 for m in d["materials"]]
    a, b, c = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    n = np.cross(b - a, c - a)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    lo, hi = P.min(axis=0), P.max(axis=0)
    size = (hi - lo).max()
    # Plane key: the normal up to sign and the plane's offset, rounded.
    sign = np.where(np.take_along_axis(n, np.argmax(np.abs(n), axis=1)[:, None], axis=1) < 0, -1.0, 1.0)
    un = n * sign
    offset = np.einsum("ij,ij->i", un, a)
    keys = {}
    for t in range(len(T)):
        key = (mat[t], tuple(np.round(un[t], 3)), round(offset[t] / size, 3))
        keys.setdefault(key, []).append(t)
    cam = d["camera"]
    forward = np.array(cam["target"]) - np.array(cam["position"])
    right = np.cross(forward, np.array(cam["up"]))
    out = []
    for (m, normal, off), tris in keys.items():
        mask = np.isin(hits, tris)
        if mask.sum() == 0:
            continue
        centre = (a[tris] + b[tris] + c[tris]).mean(axis=0) / 3
        axis = int(np.argmax(np.abs(normal)))
        at_lo = abs(centre[axis] - lo[axis]) < 0.02 * size
        at_hi = abs(centre[axis] - hi[axis]) < 0.02 * size
        name = None
        if emissive[m]:
            name = f"light ('{names[m]}')"
        elif axis == 1 and at_lo:
            name = "floor"
        elif axis == 1 and at_hi:
            name = "ceiling"
        elif axis in (0, 2) and (at_lo or at_hi):
            along = np.zeros(3)
            along[axis] = 1 if at_hi else -1
            if abs(np.dot(along, forward / np.linalg.norm(forward))) > 0.7:
                name = "back wall"
            else:
                name = "left wall" if np.dot(along, right) < 0 else "right wall"
        if name is None:
            name = f"'{names[m]}' face, normal ({normal[0]:+.2f}, {normal[1]:+.2f}, {normal[2]:+.2f})"
        out.append((name, mask))
    # A wall made of two triangles that are not coplanar (McGuire's box is not a perfect cube) is one wall.
    merged = {}
    for name, mask in out:
        merged[name] = merged[name] | mask if name in merged else mask
    out = list(merged.items())
    order = {"floor": 0, "ceiling": 1, "back wall": 2, "left wall": 3, "right wall": 4}
    out.sort(key=lambda x: (order.get(x[0], 5 if x[0].startswith("light") else 6), x[0]))
    regions = []
    for name, mask in out:
        if name in ("back wall", "left wall", "right wall"):
            rows = np.where(mask.any(axis=1))[0]
            edges = np.linspace(rows.min(), rows.max() + 1, 5).round().astype(int)
            for k in range(4):
                band = np.zeros_like(mask)
                band[edges[k]:edges[k + 1]] = mask[edges[k]:edges[k + 1]]
                regions.append((f"{name}, rows {25 * k}-{25 * (k + 1)}% from the top", band))
        regions.append((name, mask))
    return regions


def side_stats(images, mask):
    """Mean RGB over the mask for each seed's image -> (mean RGB, SE RGB, mean luminance, SE luminance)."""
    per_seed = np.array([img[mask].mean(axis=0) for img in images])
    mean = per_seed.mean(axis=0)
    se = np.abs(per_seed[0] - per_seed[1]) / 2 if len(images) == 2 else per_seed.std(axis=0, ddof=1) / np.sqrt(len(images))
    lum = per_seed @ LUMA
    lum_se = abs(lum[0] - lum[1]) / 2 if len(images) == 2 else lum.std(ddof=1) / np.sqrt(len(images))
    return mean, se, lum.mean(), lum_se


def ratio(a, sa, b, sb):
    r = a / b
    return r, abs(r) * np.sqrt((sa / a) ** 2 + (sb / b) ** 2)


def smooth(img, k=4):
    h, w = img.shape[:2]
    h2, w2 = h // k * k, w // k * k
    blocks = img[:h2, :w2].reshape(h2 // k, k, w2 // k, k, *img.shape[2:]).mean(axis=(1, 3))
    return np.repeat(np.repeat(blocks, k, axis=0), k, axis=1)


def tonemap(img):
    return np.clip(img, 0, 1) ** (1 / 2.2)


def scene_section(key, out_dir, image_dir):
    d = out_dir / key
    info = json.load(open(d / "info.json"))
    ours = [symphong.read_image(str(d / f"symphong-{s}.exr")).astype(np.float64) for s in info["seeds"]]
    cyc = [symphong.read_image(str(d / f"cycles-{s}.exr")).astype(np.float64) for s in info["seeds"]]
    scene = symphong.load_scene(info["spec"])
    h, w = ours[0].shape[:2]
    hits = scene.primary_hits(w, h)
    lines = [f"### {info['title']}\n", f"`{info['spec']}`, {w}x{h}: symphong {info['symphong_spp']} spp "
             f"({', '.join(f'{t:.0f} s' for t in info['symphong_seconds'])}), Cycles {info['cycles_spp']} spp "
             f"({', '.join(f'{t:.0f} s' for t in info['cycles_seconds'])}), seeds {', '.join(map(str, info['seeds']))}.\n"]
    dropped = json.load(open(d / "scene.json")).get("duplicates_dropped", 0)
    if dropped:
        lines.append(f"The file lists {dropped} triangles twice; Cycles gets each once (with both copies Cycles darkens "
                     "those faces: it leaves a surface by ignoring that primitive, and hits its twin at once).\n")
    whole = np.ones((h, w), bool)
    _, _, la, sa = side_stats(ours, whole)
    _, _, lb, sb = side_stats(cyc, whole)
    r, sr = ratio(la, sa, lb, sb)
    lines.append(f"Whole image: symphong {la:.5f}, Cycles {lb:.5f}, ratio **{r:.4f} ± {sr:.4f}**.\n")
    lines.append("| region | pixels | symphong | Cycles | ratio ± SE | R | G | B | |\n|---|---:|---:|---:|---:|---:|---:|---:|---|")
    flagged = []
    rows = []
    for name, mask in surfaces(d / "scene.json", hits):
        m = erode(mask)
        if m.sum() < 30:
            continue
        ma, mas, la, sa = side_stats(ours, m)
        mb, mbs, lb, sb = side_stats(cyc, m)
        if lb <= 0:
            continue
        r, sr = ratio(la, sa, lb, sb)
        channels = [f"{x / y:.4f}" if y > 0 else "-" for x, y in zip(ma, mb)]
        flag = abs(r - 1) > 0.005 and abs(r - 1) > 3 * sr
        if flag:
            flagged.append(name)
        rows.append({"region": name, "pixels": int(m.sum()), "symphong": la, "cycles": lb, "ratio": r, "se": sr})
        lines.append(f"| {name} | {m.sum()} | {la:.5f} | {lb:.5f} | {r:.4f} ± {sr:.4f} | {' | '.join(channels)} | {'**differs**' if flag else ''} |")
    lines.append("")
    lines.append(f"Regions differing by more than 0.5% and 3 SE: {', '.join(flagged) if flagged else 'none'}.\n")

    # Pictures: symphong | Cycles | ratio (4x4-pixel blocks).
    a, b = np.mean(ours, axis=0), np.mean(cyc, axis=0)
    la_img, lb_img = a @ LUMA, b @ LUMA
    with np.errstate(divide="ignore", invalid="ignore"):
        rimg = smooth(la_img) / smooth(lb_img)
    fig, ax = plt.subplots(1, 3, figsize=(12, 4.2))
    ax[0].imshow(tonemap(a))
    ax[0].set_title("symphong")
    ax[1].imshow(tonemap(b))
    ax[1].set_title("Cycles")
    im = ax[2].imshow(rimg, cmap="RdBu_r", vmin=0.95, vmax=1.05)
    ax[2].set_title("luminance ratio symphong / Cycles (4x4 blocks)")
    fig.colorbar(im, ax=ax[2], fraction=0.046)
    for x in ax:
        x.set_axis_off()
    fig.tight_layout()
    image_dir.mkdir(parents=True, exist_ok=True)
    fig.savefig(image_dir / f"{key}.png", dpi=80)
    plt.close(fig)
    lines.append(f"![symphong, Cycles and their ratio](images/validation/{key}.png)\n")

    # The back wall, row by row.
    back = [mask for name, mask in surfaces(d / "scene.json", hits) if name == "back wall"]
    if back:
        m = erode(back[0])
        rows_idx = [y for y in range(h) if m[y].sum() >= 8]
        prof = []
        for y in rows_idx:
            row_mask = np.zeros_like(m)
            row_mask[y] = m[y]
            _, _, la, sa = side_stats(ours, row_mask)
            _, _, lb, sb = side_stats(cyc, row_mask)
            prof.append((y, *ratio(la, sa, lb, sb)))
        prof = np.array(prof)
        fig, ax = plt.subplots(figsize=(7, 3.5))
        ax.fill_between(prof[:, 0], prof[:, 1] - 2 * prof[:, 2], prof[:, 1] + 2 * prof[:, 2], alpha=0.3, label="±2 SE (two seeds a side)")
        ax.plot(prof[:, 0], prof[:, 1], lw=1, label="symphong / Cycles")
        ax.axhline(1, color="k", lw=0.5)
        ax.axhspan(0.995, 1.005, color="g", alpha=0.1, label="±0.5%")
        ax.set_xlabel("image row (0 = top)")
        ax.set_ylabel("back wall luminance ratio")
        ax.set_ylim(0.96, 1.04)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(image_dir / f"{key}-back-wall.png", dpi=80)
        plt.close(fig)
        lines.append(f"![The back wall's ratio, row by row](images/validation/{key}-back-wall.png)\n")
    return "\n".join(lines), rows, flagged


def main():
    out_dir, doc, image_dir = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
    keys = sys.argv[4:]
    meta = json.load(open(out_dir / "run.json"))
    parts = [
        "<!-- validate:begin -->",
        "<!-- Generated by scripts/validate/run.sh: do not edit by hand between these markers. -->",
        "## Against Blender Cycles\n",
        f"Command: `{meta['command']}`. Machine: {meta['machine']}. {meta['blender']}.\n",
        "Each scene is loaded by symphong's Python module and handed to Cycles as it is rendered (the same triangles, "
        "materials, camera); Cycles settings: " + meta["cycles_settings"] + ". symphong: " + meta["symphong_settings"] + ".\n",
    ]
    summary = {}
    for key in keys:
        text, rows, flagged = scene_section(key, out_dir, image_dir)
        parts.append(text)
        summary[key] = {"rows": rows, "flagged": flagged}
    parts.append("<!-- validate:end -->")
    generated = "\n".join(parts)
    text = doc.read_text() if doc.exists() else "# Validation\n\n<!-- validate:begin -->\n<!-- validate:end -->\n"
    begin, end = text.find("<!-- validate:begin -->"), text.find("<!-- validate:end -->")
    if begin < 0 or end < 0:
        text = text.rstrip() + "\n\n" + generated + "\n"
    else:
        text = text[:begin] + generated + text[end + len("<!-- validate:end -->"):]
    doc.write_text(text)
    json.dump(summary, open(out_dir / "summary.json", "w"), indent=1)
    for key in keys:
        print(f"{key}: flagged {summary[key]['flagged'] or 'none'}")


if __name__ == "__main__":
    main()
