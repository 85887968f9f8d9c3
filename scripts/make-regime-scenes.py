#!/usr/bin/env python3
"""Writes scenes/regime/: the scene set of the estimator study that asks in which regime symmetric sampling
of the Phong BRDF could beat Phong-lobe importance sampling. One glossy sphere on a glossy floor, seen by
one camera, under four kinds of light (a small and a large area light of equal power, a smooth sky, the
same sky with a sun) at four Phong exponents (n = 1, 10, 100, 1000): the set spans light size and
glossiness, and most of what the camera sees is a first glossy bounce. Standard library only; the output
is the same, byte for byte, on every run.

  sphere.obj/.mtl       a smooth-shaded UV sphere (64 x 32 segments, vertex normals) of radius 1 resting
                        on an 8 x 8 floor at y = 0 facing +y; materials `sphere` and `floor`
  smooth-sky.hdr        a 512 x 256 lat-long Radiance HDR sky: bluish-white horizon to a blue zenith, dim
                        grey ground, blended over a few degrees below the horizon: no sharp feature
  sun-sky.hdr           the same sky plus a sun: a disc of 1 degree angular radius at 35 degrees elevation
                        (anti-aliased), whose irradiance on a horizontal surface is SUN_TO_SKY times the
                        sky's, as the renderer integrates the map (texel centres, sin(theta) solid angle)
  {light}-n{N}.json     light in small, large, sky, sun; N in 1, 10, 100, 1000: sphere and floor both
                        glossy (kd 0.15, ks 0.6, ns N; the floor a little warmer)
  albedo-diffuse.json   kd 0.6, ks 0.1, ns 100 under the sky
  albedo-specular.json  kd 0.03, ks 0.9, ns 100 under the sky
  bunny.json            the Stanford bunny of the shared scenes (not copied: found through
                        ../../../shared/scenes), kd 0.2, ks 0.5, ns 100, under the sun sky, on a floor
                        made of a quad light of radiance 0 (the JSON format's only way to add geometry to
                        an OBJ: that light's own material `lights[0]` is overridden to a glossy floor)

Lights: the small one is 0.25 x 0.25 units at LIGHT_CENTRE (3 above the floor, off to the right and a
little towards the camera), facing down, radiance 1280; the large one 4 x 4 with the same centre and the
same power (radiance x area: 5). Both scenes have a black environment. The sky scenes use
smooth-sky.hdr as it is; the sun scenes and the bunny use sun-sky.hdr at "scale" SUN_SCALE (0.3), so
that they are no brighter than the others. The radiances and the scale were chosen from 64-spp renders
(phong, 160 x 120) so that every scene's mean linear luminance lies in about 0.1 - 0.5. The sky maps are
run-length coded RGBE (read back here and checked). Run from anywhere:
python3 scripts/make-regime-scenes.py (scenes/README.md describes the set).
"""
import json
import math
import os

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "regime")

EXPONENTS = (1, 10, 100, 1000)
GLOSSY = {"kd": 0.15, "ks": 0.6}
FLOOR_TINT = (1.0, 0.8, 2.0 / 3.0)  # kd [0.15, 0.12, 0.1] for the glossy floor

SPHERE_SLICES, SPHERE_STACKS = 64, 32
FLOOR_HALF = 4.0

LIGHT_CENTRE = (1.5, 3.0, 1.0)
SMALL_SIZE, LARGE_SIZE = 0.25, 4.0
SMALL_RADIANCE = 1280.0
LARGE_RADIANCE = SMALL_RADIANCE * SMALL_SIZE ** 2 / LARGE_SIZE ** 2  # equal power

CAMERA = {"position": [0.0, 2.4, 6.0], "target": [0.0, 0.75, 0.0], "up": [0, 1, 0], "fov": 40}

SKY_W, SKY_H = 512, 256
SUN_ELEVATION, SUN_AZIMUTH, SUN_RADIUS = 35.0, 30.0, 1.0  # degrees; azimuth from -Z towards +X
SUN_COLOUR = (1.0, 0.93, 0.82)
SUN_TO_SKY = 4.0
SUN_SCALE = 0.3  # the sun scenes' "scale": their mean luminance comes out like the sky scenes'
LUMINANCE = (0.2126, 0.7152, 0.0722)


def fmt(x):
    """A number as JSON and OBJ want it: 6 decimals, no trailing zeros, no '-0'."""
    s = f"{x:.6f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


# --- geometry -------------------------------------------------------------------------------------------

def geometry():
    v, vn, faces = [], [], []  # faces: (material, [(vi, ni), ...]), 1-based
    # The sphere: centre (0, 1, 0), radius 1; the poles are single vertices (no degenerate triangles).
    v.append((0.0, 2.0, 0.0))
    vn.append((0.0, 1.0, 0.0))
    for i in range(1, SPHERE_STACKS):
        th = math.pi * i / SPHERE_STACKS
        for j in range(SPHERE_SLICES):
            ph = 2 * math.pi * j / SPHERE_SLICES
            n = (math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph))
            v.append((n[0], 1.0 + n[1], n[2]))
            vn.append(n)
    v.append((0.0, 0.0, 0.0))
    vn.append((0.0, -1.0, 0.0))
    top, bottom = 1, len(v)
    ring = lambda i, j: 2 + (i - 1) * SPHERE_SLICES + j % SPHERE_SLICES  # i in 1..STACKS-1
    for j in range(SPHERE_SLICES):  # counter-clockwise seen from outside
        faces.append(("sphere", [top, ring(1, j), ring(1, j + 1)]))
        for i in range(1, SPHERE_STACKS - 1):
            a, b, c, d = ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1)
            faces.append(("sphere", [a, b, c]))
            faces.append(("sphere", [a, c, d]))
        faces.append(("sphere", [ring(SPHERE_STACKS - 1, j), bottom, ring(SPHERE_STACKS - 1, j + 1)]))
    # The floor: an 8 x 8 square at y = 0, facing +y.
    h = FLOOR_HALF
    base = len(v)
    v.extend([(-h, 0.0, h), (h, 0.0, h), (h, 0.0, -h), (-h, 0.0, -h)])
    floor_n = len(vn) + 1
    vn.append((0.0, 1.0, 0.0))

    with open(os.path.join(OUT, "sphere.obj"), "w", newline="\n") as f:
        f.write("# scripts/make-regime-scenes.py: a UV sphere (radius 1, 64 x 32, smooth) on an 8 x 8 floor\n")
        f.write("mtllib sphere.mtl\n")
        f.writelines(f"v {fmt(p[0])} {fmt(p[1])} {fmt(p[2])}\n" for p in v)
        f.writelines(f"vn {fmt(n[0])} {fmt(n[1])} {fmt(n[2])}\n" for n in vn)
        f.write("usemtl sphere\n")
        f.writelines("f " + " ".join(f"{k}//{k}" for k in corners) + "\n" for _, corners in faces)
        f.write("usemtl floor\n")
        f.write("f " + " ".join(f"{base + k}//{floor_n}" for k in (1, 2, 3, 4)) + "\n")
    with open(os.path.join(OUT, "sphere.mtl"), "w", newline="\n") as f:
        f.write("# Phong parameters: Kd -> rho_d, Ks -> rho_s, Ns -> n (the JSON scenes override both)\n")
        f.write("newmtl sphere\nKd 0.15 0.15 0.15\nKs 0.6 0.6 0.6\nNs 100\n\n")
        f.write("newmtl floor\nKd 0.15 0.12 0.1\nKs 0.6 0.6 0.6\nNs 100\n")


# --- environment maps -----------------------------------------------------------------------------------

def rgbe(rgb):
    m = max(rgb)
    if m < 1e-32:
        return (0, 0, 0, 0)
    mant, e = math.frexp(m)  # m = mant 2^e, mant in [0.5, 1)
    scale = mant * 256.0 / m
    return tuple(min(255, int(c * scale + 0.5)) for c in rgb) + (e + 128,)  # rounded: unbiased


def rle(values):
    """One component of a scanline in the adaptive run-length code of Radiance (and stb_image): a count
    byte above 128 is a run of (count - 128) copies of the next byte, else `count` literal bytes follow."""
    out, i, n = bytearray(), 0, len(values)
    while i < n:
        run = 1
        while i + run < n and run < 127 and values[i + run] == values[i]:
            run += 1
        if run >= 3:
            out += bytes([128 + run, values[i]])
            i += run
            continue
        j = i  # literals until the next run of 3 or more (or 128 bytes)
        while j < n and j - i < 128 and not (j + 2 < n and values[j] == values[j + 1] == values[j + 2]):
            j += 1
        out += bytes([j - i]) + bytes(values[i:j])
        i = j
    return out


def write_hdr(path, w, h, rows):
    """rows: h lists of w (r, g, b) linear; run-length coded RGBE scanlines (8 <= w < 32768), row 0 at
    the top. Most rows of these skies are one colour, so the files are small."""
    out = bytearray(b"#?RADIANCE\n# scripts/make-regime-scenes.py\nFORMAT=32-bit_rle_rgbe\n\n")
    out += f"-Y {h} +X {w}\n".encode()
    for row in rows:
        pixels = [rgbe(rgb) for rgb in row]
        out += bytes([2, 2, w >> 8, w & 255])
        for k in range(4):
            out += rle([p[k] for p in pixels])
    with open(path, "wb") as f:
        f.write(out)


def read_hdr(path):
    """The reverse of write_hdr (a check that the run-length code reads back): rows of (r, g, b)."""
    data = open(path, "rb").read()
    head, _, body = data.partition(b"\n\n")
    line, _, body = body.partition(b"\n")
    _, h, _, w = line.split()
    h, w, i, rows = int(h), int(w), 0, []
    for _ in range(h):
        assert body[i:i + 2] == b"\2\2" and (body[i + 2] << 8 | body[i + 3]) == w
        i += 4
        comps = []
        for _ in range(4):
            c = []
            while len(c) < w:
                count = body[i]
                if count > 128:
                    c += [body[i + 1]] * (count - 128)
                    i += 2
                else:
                    c += list(body[i + 1:i + 1 + count])
                    i += 1 + count
            assert len(c) == w
            comps.append(c)
        rows.append([tuple(0.0 if e == 0 else m * 2.0 ** (e - 136) for m in (r, g, b))  # as stb_image
                     for r, g, b, e in zip(*comps)])
    assert i == len(body)
    return rows


def direction(u, t):
    """scenes/environment_map.h's mapping: u = 1/2 + atan2(dx, -dz) / 2 pi, theta = pi t (t = row / H)."""
    phi, theta = 2 * math.pi * (u - 0.5), math.pi * t
    return (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))


def smoothstep(a, b, x):
    x = min(1.0, max(0.0, (x - a) / (b - a)))
    return x * x * (3 - 2 * x)


def sky_radiance(d):
    horizon, zenith, ground = (1.0, 1.05, 1.12), (0.22, 0.38, 0.85), (0.16, 0.16, 0.16)
    elevation = math.asin(max(-1.0, min(1.0, d[1])))
    s = math.sin(max(0.0, elevation)) ** 0.6
    above = tuple(hz + (zn - hz) * s for hz, zn in zip(horizon, zenith))
    k = smoothstep(math.radians(-6.0), 0.0, elevation)  # ground to sky over 6 degrees below the horizon
    return tuple(g + (a - g) * k for g, a in zip(ground, above))


def luminance(rgb):
    return sum(c * w for c, w in zip(rgb, LUMINANCE))


def horizontal_irradiance(rows):
    """Luminance irradiance on an up-facing surface, summed over texel centres as the renderer maps them."""
    e = 0.0
    for y, row in enumerate(rows):
        t = (y + 0.5) / SKY_H
        cos_t, sin_t = math.cos(math.pi * t), math.sin(math.pi * t)
        if cos_t <= 0:
            continue
        dw = (2 * math.pi / SKY_W) * (math.pi / SKY_H) * sin_t
        e += sum(luminance(rgb) for rgb in row) * cos_t * dw
    return e


def skies():
    sky = [[sky_radiance(direction((x + 0.5) / SKY_W, (y + 0.5) / SKY_H)) for x in range(SKY_W)] for y in range(SKY_H)]
    write_hdr(os.path.join(OUT, "smooth-sky.hdr"), SKY_W, SKY_H, sky)

    el, az = math.radians(SUN_ELEVATION), math.radians(SUN_AZIMUTH)
    sun = (math.sin(az) * math.cos(el), math.sin(el), -math.cos(az) * math.cos(el))
    cos_r = math.cos(math.radians(SUN_RADIUS))
    cos_near = math.cos(math.radians(SUN_RADIUS + 2.0))
    sub = 8  # coverage of the disc by 8 x 8 points per texel: an anti-aliased edge
    coverage = {}
    for y in range(SKY_H):
        for x in range(SKY_W):
            if sum(a * b for a, b in zip(direction((x + 0.5) / SKY_W, (y + 0.5) / SKY_H), sun)) < cos_near:
                continue
            inside = sum(1 for i in range(sub) for j in range(sub)
                         if sum(a * b for a, b in zip(direction((x + (i + 0.5) / sub) / SKY_W,
                                                                (y + (j + 0.5) / sub) / SKY_H), sun)) > cos_r)
            if inside:
                coverage[(x, y)] = inside / sub ** 2
    # The sun's radiance L: irradiance of the disc's texels (L x coverage) = SUN_TO_SKY x the sky's.
    unit = [[(0.0, 0.0, 0.0)] * SKY_W for _ in range(SKY_H)]
    for (x, y), c in coverage.items():
        unit[y][x] = tuple(c * k for k in SUN_COLOUR)
    level = SUN_TO_SKY * horizontal_irradiance(sky) / horizontal_irradiance(unit)
    sun_sky = [list(row) for row in sky]
    for (x, y), c in coverage.items():
        sun_sky[y][x] = tuple(s + level * c * k for s, k in zip(sky[y][x], SUN_COLOUR))
    write_hdr(os.path.join(OUT, "sun-sky.hdr"), SKY_W, SKY_H, sun_sky)
    # Read both back as the renderer will: the code is right and the sun gives what it should.
    sky_e = horizontal_irradiance(read_hdr(os.path.join(OUT, "smooth-sky.hdr")))
    both_e = horizontal_irradiance(read_hdr(os.path.join(OUT, "sun-sky.hdr")))
    assert abs(sky_e / horizontal_irradiance(sky) - 1) < 0.01, sky_e
    assert abs((both_e - sky_e) / sky_e / SUN_TO_SKY - 1) < 0.01, both_e
    return sky_e, both_e - sky_e, level


# --- scenes ---------------------------------------------------------------------------------------------

def material(kd, ks, ns, tint=(1.0, 1.0, 1.0)):
    return {"kd": [round(kd * t, 6) for t in tint], "ks": ks, "ns": ns}


def quad_light(size, radiance):
    cx, cy, cz = LIGHT_CENTRE
    # cross(edge1, edge2) = (size, 0, 0) x (0, 0, size) = (0, -size^2, 0): it faces down.
    return {"type": "quad", "corner": [cx - size / 2, cy, cz - size / 2], "edge1": [size, 0, 0],
            "edge2": [0, 0, size], "radiance": radiance}


def write_scene(name, scene):
    """One key a line; materials and lights one entry a line."""
    doc = {"obj": scene.pop("obj", "sphere.obj"), "name": name}
    doc.update(scene)
    one = lambda v: json.dumps(v, separators=(", ", ": "))
    lines = []
    for key, value in doc.items():
        if isinstance(value, dict) and all(isinstance(v, dict) for v in value.values()):
            inner = ",\n".join(f"    {json.dumps(k)}: {one(v)}" for k, v in value.items())
            lines.append(f"  {json.dumps(key)}: {{\n{inner}\n  }}")
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            inner = ",\n".join(f"    {one(v)}" for v in value)
            lines.append(f"  {json.dumps(key)}: [\n{inner}\n  ]")
        else:
            lines.append(f"  {json.dumps(key)}: {one(value)}")
    with open(os.path.join(OUT, name + ".json"), "w", newline="\n") as f:
        f.write("{\n" + ",\n".join(lines) + "\n}\n")


def scenes():
    lights = {
        "small": {"lights": [quad_light(SMALL_SIZE, SMALL_RADIANCE)], "environment": 0},
        "large": {"lights": [quad_light(LARGE_SIZE, LARGE_RADIANCE)], "environment": 0},
        "sky": {"environment": {"map": "smooth-sky.hdr"}},
        "sun": {"environment": {"map": "sun-sky.hdr", "scale": SUN_SCALE}},
    }
    for light, setting in lights.items():
        for n in EXPONENTS:
            write_scene(f"{light}-n{n}", {
                "camera": CAMERA,
                "materials": {"sphere": material(GLOSSY["kd"], GLOSSY["ks"], n),
                              "floor": material(GLOSSY["kd"], GLOSSY["ks"], n, FLOOR_TINT)},
                **json.loads(json.dumps(setting)),
            })
    for name, kd, ks in (("albedo-diffuse", 0.6, 0.1), ("albedo-specular", 0.03, 0.9)):
        write_scene(name, {
            "camera": CAMERA,
            "materials": {"sphere": material(kd, ks, 100), "floor": material(kd, ks, 100, FLOOR_TINT)},
            "environment": {"map": "smooth-sky.hdr"},
        })
    # The bunny (bounds x -0.095..0.061, y 0.033..0.187, z -0.062..0.059; 'default' is its only material).
    floor_y, half = 0.0329, 2.0
    write_scene("bunny", {
        "obj": "../../../shared/scenes/bunny/stanford-bunny.obj",
        "camera": {"position": [0.0, 0.2, 0.42], "target": [-0.015, 0.1, 0.0], "up": [0, 1, 0], "fov": 35},
        "materials": {"default": material(0.2, 0.5, 100),
                      "lights[0]": material(GLOSSY["kd"], GLOSSY["ks"], 100, FLOOR_TINT)},
        "environment": {"map": "sun-sky.hdr", "scale": SUN_SCALE},
        # A quad light of radiance 0 is only geometry (no emitter): the floor, facing +y.
        "lights": [{"type": "quad", "corner": [-half, floor_y, half], "edge1": [2 * half, 0, 0],
                    "edge2": [0, 0, -2 * half], "radiance": 0}],
    })


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    geometry()
    sky_e, sun_e, sun_level = skies()
    scenes()
    print(f"wrote {os.path.normpath(OUT)}")
    print(f"  horizontal irradiance (luminance, as read back): sky {sky_e:.4f}, sun {sun_e:.4f} "
          f"({sun_e / sky_e:.3f} x the sky's); sun radiance {sun_level:.1f} x {SUN_COLOUR}")
    print(f"  small light radiance {SMALL_RADIANCE:g} ({SMALL_SIZE} x {SMALL_SIZE}), "
          f"large {LARGE_RADIANCE:g} ({LARGE_SIZE} x {LARGE_SIZE}): power {SMALL_RADIANCE * SMALL_SIZE ** 2:g} each")
