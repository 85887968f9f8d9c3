#!/usr/bin/env python3
"""Writes scenes/textured/: the README's textured, environment-lit scene, made from nothing but code so
that every byte of it is ours to ship (standard library only).

  textured.obj/.mtl  a floor with a tiled checkerboard (map_Kd), a glossy striped globe (map_Kd + Ks),
                     a crate with planks (map_Kd, map_Ks) and a perforated screen (map_d cut-out)
  *.png              the textures, 8-bit sRGB (the cut-out mask is linear grey)
  sky.hdr            a 512 x 256 lat-long Radiance HDR sky: blue gradient, a 2-degree sun, brown ground

Run from the repository root: python3 scripts/make-textured-scene.py (scenes/textured.json uses them).
"""
import math
import os
import struct
import zlib

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "textured")


def write_png(path, w, h, channels, pixel):
    """pixel(x, y) -> tuple of `channels` ints in 0..255; row 0 at the top."""
    raw = bytearray()
    for y in range(h):
        raw.append(0)
        for x in range(w):
            raw.extend(pixel(x, y))
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    colour = {1: 0, 3: 2, 4: 6}[channels]
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, colour, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(bytes(raw), 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def write_hdr(path, w, h, radiance):
    """radiance(x, y) -> (r, g, b) linear; flat (uncompressed) RGBE scanlines."""
    out = bytearray(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n" + f"-Y {h} +X {w}\n".encode())
    for y in range(h):
        for x in range(w):
            rgb = radiance(x, y)
            m = max(rgb)
            if m < 1e-32:
                out.extend(b"\0\0\0\0")
                continue
            mant, e = math.frexp(m)
            scale = mant * 256.0 / m
            out.extend(bytes([min(255, int(c * scale)) for c in rgb] + [e + 128]))
    with open(path, "wb") as f:
        f.write(out)


def srgb8(v):
    v = max(0.0, min(1.0, v))
    s = 12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055
    return int(round(s * 255))


def textures():
    def checker(x, y):
        a = ((x // 32) + (y // 32)) % 2 == 0
        return (srgb8(0.75), srgb8(0.72), srgb8(0.66)) if a else (srgb8(0.12), srgb8(0.13), srgb8(0.16))
    write_png(os.path.join(OUT, "checker.png"), 64, 64, 3, checker)

    def stripes(x, y):  # the globe: warm bands and a grid of meridians
        band = (y // 16) % 2 == 0
        meridian = x % 32 in (0, 1)
        if meridian:
            return (srgb8(0.9), srgb8(0.9), srgb8(0.85))
        return (srgb8(0.70), srgb8(0.22), srgb8(0.08)) if band else (srgb8(0.85), srgb8(0.60), srgb8(0.15))
    write_png(os.path.join(OUT, "globe.png"), 256, 128, 3, stripes)

    def planks(x, y):  # the crate: planks with dark seams and a little grain
        seam = y % 32 in (0, 1) or (x + 64 * ((y // 32) % 2)) % 128 in (0, 1)
        grain = 0.06 * math.sin(x * 0.35 + 3 * math.sin(y * 0.2))
        if seam:
            return (srgb8(0.05), srgb8(0.04), srgb8(0.03))
        return (srgb8(0.45 + grain), srgb8(0.30 + grain), srgb8(0.16 + grain))
    write_png(os.path.join(OUT, "planks.png"), 128, 128, 3, planks)

    def plank_gloss(x, y):  # varnish: shiny planks, matte seams
        seam = y % 32 in (0, 1) or (x + 64 * ((y // 32) % 2)) % 128 in (0, 1)
        return (srgb8(0.0),) * 3 if seam else (srgb8(0.25),) * 3
    write_png(os.path.join(OUT, "planks-gloss.png"), 128, 128, 3, plank_gloss)

    def holes(x, y):  # the screen: round holes on a 16-pixel grid (linear grey: 255 solid, 0 hole)
        cx, cy = x % 16 - 7.5, y % 16 - 7.5
        return (0,) if cx * cx + cy * cy < 30 else (255,)
    write_png(os.path.join(OUT, "holes.png"), 128, 128, 1, holes)


def sky():
    w, h = 512, 256
    sun_dir = (math.sin(math.radians(-40)) * math.cos(math.radians(35)), math.sin(math.radians(35)),
               -math.cos(math.radians(-40)) * math.cos(math.radians(35)))
    cos_sun = math.cos(math.radians(2.0))

    def radiance(x, y):
        # scenes/environment_map.h's mapping: u = 1/2 + atan2(dx, -dz) / 2 pi, theta = pi (y + 1/2) / H.
        u, t = (x + 0.5) / w, (y + 0.5) / h
        phi, theta = 2 * math.pi * (u - 0.5), math.pi * t
        d = (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))
        if sum(a * b for a, b in zip(d, sun_dir)) > cos_sun:
            return (900.0, 820.0, 700.0)
        if d[1] >= 0:
            s = math.sqrt(d[1])
            return (0.85 + (0.25 - 0.85) * s, 0.9 + (0.45 - 0.9) * s, 1.0 + (0.95 - 1.0) * s)
        return (0.22, 0.18, 0.14)
    write_hdr(os.path.join(OUT, "sky.hdr"), w, h, radiance)


def geometry():
    v, vt, vn, faces = [], [], [], []  # faces: (material, [(vi, ti, ni)...])

    def quad(p, uv, n, material):
        base_v, base_t = len(v), len(vt)
        v.extend(p)
        vt.extend(uv)
        vn.append(n)
        ni = len(vn)
        faces.append((material, [(base_v + i + 1, base_t + i + 1, ni) for i in range(4)]))

    quad([(-6, 0, 6), (6, 0, 6), (6, 0, -6), (-6, 0, -6)], [(0, 0), (6, 0), (6, 6), (0, 6)], (0, 1, 0), "floor")
    # The crate: 1.2 on a side, centred at (1.5, 0.6, 0.2), planks on every face.
    c, r = (1.5, 0.6, 0.2), 0.6
    corners = lambda sx, sy, sz: (c[0] + sx * r, c[1] + sy * r, c[2] + sz * r)
    uv = [(0, 0), (1, 0), (1, 1), (0, 1)]
    quad([corners(-1, -1, 1), corners(1, -1, 1), corners(1, 1, 1), corners(-1, 1, 1)], uv, (0, 0, 1), "crate")
    quad([corners(1, -1, -1), corners(-1, -1, -1), corners(-1, 1, -1), corners(1, 1, -1)], uv, (0, 0, -1), "crate")
    quad([corners(1, -1, 1), corners(1, -1, -1), corners(1, 1, -1), corners(1, 1, 1)], uv, (1, 0, 0), "crate")
    quad([corners(-1, -1, -1), corners(-1, -1, 1), corners(-1, 1, 1), corners(-1, 1, -1)], uv, (-1, 0, 0), "crate")
    quad([corners(-1, 1, 1), corners(1, 1, 1), corners(1, 1, -1), corners(-1, 1, -1)], uv, (0, 1, 0), "crate")
    # The screen: a 2.4 x 1.6 panel behind the scene, holes through it (both sides face the camera's way).
    quad([(-2.6, 0, -1.6), (0.2, 0, -1.6), (0.2, 1.9, -1.6), (-2.6, 1.9, -1.6)], [(0, 0), (3, 0), (3, 2), (0, 2)], (0, 0, 1), "screen")
    # The globe: a UV sphere of radius 0.7 at (-1, 0.7, 0.5), smooth normals, u round the axis.
    g, R, stacks, slices = (-1.0, 0.7, 0.5), 0.7, 32, 64
    base_v, base_t, base_n = len(v), len(vt), len(vn)
    for i in range(stacks + 1):
        th = math.pi * i / stacks
        for j in range(slices + 1):
            ph = 2 * math.pi * j / slices
            n = (math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph))
            v.append(tuple(g[k] + R * n[k] for k in range(3)))
            vn.append(n)
            vt.append((j / slices, 1 - i / stacks))
    at = lambda i, j: i * (slices + 1) + j + 1
    for i in range(stacks):
        for j in range(slices):
            a, b, cc, d = at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)
            faces.append(("globe", [(base_v + k, base_t + k, base_n + k) for k in (a, b, cc)]))
            faces.append(("globe", [(base_v + k, base_t + k, base_n + k) for k in (a, cc, d)]))

    with open(os.path.join(OUT, "textured.obj"), "w") as f:
        f.write("# scripts/make-textured-scene.py: the README's textured, environment-lit scene\nmtllib textured.mtl\n")
        f.writelines(f"v {p[0]:.6f} {p[1]:.6f} {p[2]:.6f}\n" for p in v)
        f.writelines(f"vt {t[0]:.6f} {t[1]:.6f}\n" for t in vt)
        f.writelines(f"vn {n[0]:.6f} {n[1]:.6f} {n[2]:.6f}\n" for n in vn)
        current = None
        for material, corners_ in faces:
            if material != current:
                f.write(f"usemtl {material}\n")
                current = material
            f.write("f " + " ".join(f"{a}/{b}/{c}" for a, b, c in corners_) + "\n")
    with open(os.path.join(OUT, "textured.mtl"), "w") as f:
        f.write("""# Phong parameters: Kd -> rho_d, Ks -> rho_s, Ns -> n; a map multiplies its constant
newmtl floor
Kd 1 1 1
Ks 0.08 0.08 0.08
Ns 40
map_Kd checker.png

newmtl globe
Kd 1 1 1
Ks 0.2 0.2 0.2
Ns 120
map_Kd globe.png

newmtl crate
Kd 1 1 1
Ks 1 1 1
Ns 60
map_Kd planks.png
map_Ks planks-gloss.png

newmtl screen
Kd 0.55 0.6 0.65
Ks 0.1 0.1 0.1
Ns 20
map_d holes.png
""")


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    textures()
    sky()
    geometry()
    print("wrote", os.path.normpath(OUT))
