"""Region masks and region ratios for comparing two renders of one scene (tests/blender/test_blender_addon.py and
scripts/blender-addon/agreement.py): the pixels whose centre sees each material (symphong.Scene.primary_hits),
eroded by a pixel, and each material's image quadrants; a region's mean luminance ratio with its standard error
from the paired difference image (pixels are independent draws of the renders' noise)."""
import numpy as np

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def regions(scene, width, height):
    """Masks of the pixels whose centre sees each material, eroded by a pixel (no edge pixel counts)."""
    hits = scene.primary_hits(width, height)
    material = np.where(hits >= 0, scene.mesh()["material"][np.maximum(hits, 0)], -1)
    inner = np.full(material.shape, False)
    inner[1:-1, 1:-1] = True
    for dy, dx in ((0, 1), (0, -1), (1, 0), (-1, 0)):
        inner &= np.roll(material, (dy, dx), axis=(0, 1)) == material
    masks = {m["name"]: inner & (material == i) for i, m in enumerate(scene.materials)}
    # Each material's image quadrants too (a texture's or a lit side's error shows in part of a surface).
    h, w = material.shape
    for name, mask in list(masks.items()):
        for qy, top in ((slice(0, h // 2), "top"), (slice(h // 2, h), "bottom")):
            for qx, side in ((slice(0, w // 2), "left"), (slice(w // 2, w), "right")):
                q = np.zeros_like(mask)
                q[qy, qx] = mask[qy, qx]
                masks[f"{name}, {top} {side}"] = q
    return {name: mask for name, mask in masks.items() if mask.sum() >= 20}


def ratio(test, reference, mask):
    """Mean luminance ratio test / reference over a mask, and its standard error from the difference image."""
    a, b = test[mask] @ LUMINANCE, reference[mask] @ LUMINANCE
    d = a - b
    return a.mean() / b.mean(), d.std(ddof=1) / np.sqrt(d.size) / b.mean()
