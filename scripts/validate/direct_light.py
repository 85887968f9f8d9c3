"""The back-wall excess, settled with a closed form: direct light only (symphong --max-depth 1, Cycles
max bounces 0) on the classic Cornell box's back, left and right walls above the tall block (y >= 340:
nothing stands between those points and the light), against Lambert's formula for the light polygon,
pixel by pixel (averaged over 4x4 points of each pixel; pixels whose 3x3 neighbourhood does not all
see that wall are left out), in bands of wall height. Run by direct_light.sh:

    direct_light.py DIR    (DIR holds scene.json, symphong-{1,2}.exr, cycles-{1,2}.exr, cycles-bsdf-{1,2}.exr)

Prints a Markdown table: each renderer's band mean over the exact one, with the standard error from
its two seeds."""
import json
import sys

import numpy as np

import symphong

LUMA = np.array([0.2126, 0.7152, 0.0722])


def main():
    d = sys.argv[1]
    desc = json.load(open(f"{d}/scene.json"))
    P = np.array(desc["positions"])
    T = np.array(desc["triangles"])
    mats = desc["materials"]
    lights = [t for t, m in zip(T, desc["material"]) if max(mats[m]["emission"]) > 0]
    emission = np.array(next(m["emission"] for m in mats if max(m["emission"]) > 0))
    cam = desc["camera"]
    pos, tgt, up = (np.array(cam[k], float) for k in ("position", "target", "up"))
    fwd = (tgt - pos) / np.linalg.norm(tgt - pos)
    right = np.cross(fwd, up)
    right /= np.linalg.norm(right)
    up2 = np.cross(right, fwd)
    th = np.tan(np.radians(cam["fov_y"]) / 2)
    W = H = 256
    light_y = P[lights[0][0], 1]
    lo, hi = P.min(axis=0), P.max(axis=0)
    names = [m["name"] for m in mats]
    scene = symphong.load_scene(desc["spec"])
    hits = scene.primary_hits(W, H)
    tri_material = np.array(desc["material"])

    def irradiance(p, n):
        # Lambert: E = 1/2 sum_i theta_i n . unit(r_i x r_i+1), over each emitting triangle (radiance 1).
        total = 0.0
        for tri in lights:
            s = 0.0
            for i in range(3):
                a, b = P[tri[i]] - p, P[tri[(i + 1) % 3]] - p
                a, b = a / np.linalg.norm(a), b / np.linalg.norm(b)
                c = np.cross(a, b)
                sn = np.linalg.norm(c)
                s += np.arctan2(sn, a @ b) * (n @ c) / sn
            total += 0.5 * abs(s)
        return total

    # (name, axis, plane coordinate, inward normal, material)
    walls = [("back wall", 2, hi[2], np.array([0, 0, -1.0]), "white"),
             ("right wall (green)", 0, lo[0], np.array([1.0, 0, 0]), "green"),
             ("left wall (red)", 0, hi[0], np.array([-1.0, 0, 0]), "red")]
    images = {name: [symphong.read_image(f"{d}/{name}-{s}.exr").astype(float) @ LUMA for s in (1, 2)]
              for name in ("symphong", "cycles", "cycles-bsdf")}
    bands = [(500, 553), (450, 500), (400, 450), (340, 400)]
    print("| wall, height | pixels | exact (Lambert) | symphong / exact | Cycles / exact | Cycles without light sampling / exact |")
    print("|---|---:|---:|---:|---:|---:|")
    K = 4
    for wall, axis, coord, n, material in walls:
        rho = np.array(mats[names.index(material)]["rho_d"])
        # Pixels whose centre and 8 neighbours all see a triangle of this wall.
        on_plane = np.zeros(len(T), bool)
        for t, tri in enumerate(T):
            on_plane[t] = np.allclose(P[tri][:, axis], coord) and names[tri_material[t]] == material
        seen = np.where(hits >= 0, on_plane[np.maximum(hits, 0)], False)
        inner = seen.copy()
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                inner &= np.roll(np.roll(seen, dy, axis=0), dx, axis=1)
        exact = np.full((H, W), np.nan)
        wall_y = np.full((H, W), np.nan)
        for y, x in zip(*np.nonzero(inner)):
            e, ys = 0.0, []
            for j in range(K):
                for i in range(K):
                    px, py = x + (i + 0.5) / K, y + (j + 0.5) / K
                    dvec = fwd + right * ((2 * px / W - 1) * th) + up2 * ((1 - 2 * py / H) * th)
                    q = pos + dvec * ((coord - pos[axis]) / dvec[axis])
                    e += irradiance(q, n)
                    ys.append(q[1])
            if min(ys) >= 340 and max(ys) < light_y - 1:
                exact[y, x] = (rho / np.pi * emission * e / K**2) @ LUMA
                wall_y[y, x] = np.mean(ys)
        for lo_y, hi_y in bands:
            m = (wall_y >= lo_y) & (wall_y < hi_y)
            if m.sum() < 20:
                continue
            want = exact[m].sum()
            cells = []
            for name in ("symphong", "cycles", "cycles-bsdf"):
                r = [img[m].sum() / want for img in images[name]]
                cells.append(f"{np.mean(r):.4f} ± {abs(r[0] - r[1]) / 2:.4f}")
            print(f"| {wall}, y {lo_y}-{hi_y} | {m.sum()} | {exact[m].mean():.5f} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
