"""Writes what symphong renders of a scene (geometry, materials, camera, environment) as JSON for
cycles_scene.py, which runs inside Blender and cannot import our module. Run with Debian's python3 and
PYTHONPATH=build/release/python:

    export_scene.py SCENE OUT.json

Validation compares diffuse scenes only (Cycles has no Phong BRDF): a material with rho_s > 0, a
point/spot/directional light, the default sky, an environment map or a texture is refused with exit code 2."""
import json
import sys

import symphong


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: export_scene.py SCENE OUT.json")
    spec, out = sys.argv[1:]
    try:
        scene = symphong.load_scene(spec)
    except (ValueError, FileNotFoundError) as e:
        print(f"export_scene: {e}", file=sys.stderr)
        sys.exit(2)
    problems = [f"material '{m['name']}' has rho_s {m['rho_s']}" for m in scene.materials if max(m["rho_s"]) > 0]
    if scene.lights:
        problems.append(f"{len(scene.lights)} point/spot/directional light(s) (the default sky's sun counts)")
    if scene.sky is not None:
        problems.append("the default sky (the scene has no light)")
    if scene.environment_map is not None:
        problems.append("an environment map (not translated for Cycles)")
    if scene.textures:
        problems.append(f"{len(scene.textures)} texture(s) (not translated for Cycles)")
    if problems:
        print(f"export_scene: {spec}: not a diffuse scene that Cycles can match: " + "; ".join(problems), file=sys.stderr)
        sys.exit(2)
    mesh = scene.mesh()
    # A triangle listed twice (McGuire's boxes repeat two faces) is one surface to symphong, whose rays
    # leave a surface by an offset along its normal; Cycles leaves a surface by ignoring that primitive
    # and hits its twin at once, which darkens both. Each triangle is handed to Cycles once.
    seen, keep = set(), []
    for i, (tri, material) in enumerate(zip(mesh["triangles"].tolist(), mesh["material"].tolist())):
        key = (tuple(sorted(tri)), material)
        if key not in seen:
            seen.add(key)
            keep.append(i)
    dropped = len(mesh["triangles"]) - len(keep)
    if dropped:
        print(f"export_scene: {spec}: {dropped} duplicated triangle(s) handed to Cycles once", file=sys.stderr)
    desc = {
        "spec": spec,
        "name": scene.name,
        "positions": mesh["positions"].tolist(),
        "triangles": mesh["triangles"][keep].tolist(),
        "material": mesh["material"][keep].tolist(),
        "duplicates_dropped": dropped,
        "materials": [{"name": m["name"], "rho_d": list(m["rho_d"]), "emission": list(m["emission"])} for m in scene.materials],
        "camera": {k: (list(v) if isinstance(v, tuple) else v) for k, v in scene.camera.items()},
        "environment": list(scene.environment),
    }
    with open(out, "w") as f:
        json.dump(desc, f)


if __name__ == "__main__":
    main()
