#!/usr/bin/env python3
"""Writes the LDR pair of tests/test_flip.cpp: ldr_reference.png, a 256x256 crop of NVIDIA's FLIP example
image (github.com/NVlabs/flip, images/reference.png, BSD-3-Clause: LICENSE-NVIDIA-FLIP), and ldr_test.png,
that crop with a blur, noise and a colour shift each in one part of it (README.md says how the reference
tool's results were made from them).

Deterministic: the blur is our own separable Gaussian, the noise comes from NumPy's legacy RandomState
(whose streams NumPy keeps frozen), and every value is rounded to 8 bits the same way.

Run: /usr/bin/python3 tests/data/flip/make_pairs.py [PATH/TO/NVlabs-flip/images/reference.png]
(Debian's python3-numpy and python3-pil). Without the path, the crop already here is kept and only the
test image is rewritten."""
import pathlib
import sys

import numpy as np
from PIL import Image

HERE = pathlib.Path(__file__).resolve().parent
CROP = (720, 620, 976, 876)  # left, top, right, bottom in NVIDIA's 1920x1080 image: the rug, toy blocks, a wooden floor
SIZE = 256


def gaussian_blur(img, sigma):
    """Separable Gaussian (radius 3 sigma, edges repeated) on an HxWxC float array."""
    r = int(np.ceil(3 * sigma))
    x = np.arange(-r, r + 1, dtype=np.float64)
    k = np.exp(-x * x / (2 * sigma * sigma))
    k /= k.sum()
    padded = np.pad(img, ((r, r), (0, 0), (0, 0)), mode="edge")
    img = sum(k[i] * padded[i:i + img.shape[0]] for i in range(2 * r + 1))
    padded = np.pad(img, ((0, 0), (r, r), (0, 0)), mode="edge")
    return sum(k[i] * padded[:, i:i + img.shape[1]] for i in range(2 * r + 1))


def degrade(ref):
    """The test image from the reference (8-bit sRGB values as floats in [0,255]): four quadrants, the
    top left blurred (sigma 1.5 pixels), the top right with Gaussian noise (sigma 12 of 255), the bottom
    left shifted in colour (red x1.10, blue x0.88) and the bottom right untouched."""
    test = ref.copy()
    h = SIZE // 2
    test[:h, :h] = gaussian_blur(ref, 1.5)[:h, :h]
    noise = np.random.RandomState(20240611).normal(0.0, 12.0, size=(h, h, 3))
    test[:h, h:] = ref[:h, h:] + noise
    test[h:, :h] = ref[h:, :h] * np.array([1.10, 1.0, 0.88])
    return np.clip(np.floor(test + 0.5), 0, 255).astype(np.uint8)


def main():
    ref_path = HERE / "ldr_reference.png"
    if len(sys.argv) > 1:
        full = Image.open(sys.argv[1]).convert("RGB")
        if full.size != (1920, 1080):
            sys.exit(f"{sys.argv[1]}: expected NVIDIA's 1920x1080 images/reference.png, got {full.size}")
        full.crop(CROP).save(ref_path)
    ref = np.asarray(Image.open(ref_path).convert("RGB"), dtype=np.float64)
    assert ref.shape == (SIZE, SIZE, 3)
    Image.fromarray(degrade(ref), "RGB").save(HERE / "ldr_test.png")


if __name__ == "__main__":
    main()
