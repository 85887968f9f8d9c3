"""Builds one Cornell-like scene in Blender from scratch and writes it with Blender's own exporters.

    blender --background --factory-startup --python scripts/blender-roundtrip/make_scene.py -- OUTDIR

(Blender 3.4 from Debian 12; run.sh runs it with OUTDIR = tests/data/blender.) Never run in CI.

The scene (Blender's coordinates: +Z up, metres; the exports are +Y up, see below):
- five diffuse walls, one quad each, facing into the box x, y in [-1, 1], z in [0, 2]: floor, ceiling
  and back wall (y = 1) "white", left wall (x = -1) "red", right wall (x = 1) "green". Principled BSDF:
  Base Color as in the classic Cornell box (linear), Specular 0, Roughness 1, Metallic 0.
- "glossy": a box 0.6 x 0.6 x 1.2 (a unit cube scaled by its object transform, turned 20 degrees about
  +Z and moved: the exporters' node transforms are exercised), Principled Base Color
  (0.75, 0.55, 0.25), Specular 0.5, Roughness 0.2, Metallic 0.
- "light": a 0.5 x 0.5 quad at z = 1.98 facing down, Principled Base Color black, Specular 0,
  Roughness 1, Emission (1, 1, 1), Emission Strength 17 (radiance 17 in Cycles).
- "checker": a 0.7 x 0.7 quad 1 cm in front of the back wall (2 x 2 faces), UV (0,0)-(1,1) with u
  along +X and v along +Z, Principled Base Color from an Image Texture of checker.png (64 x 64, written
  by this script: 8 x 8 squares, every other one sRGB (230, 230, 230), the others a colour per
  quadrant of UV space, CHECKER_QUADRANTS), Specular 0, Roughness 1, Metallic 0.
- "Camera": perspective, focal length 40 mm, sensor 36 x 24 mm, sensor fit AUTO, at (0, -3.9, 1)
  looking along +Y (rotation X 90 degrees), clip 0.1 - 100; render resolution 640 x 480. Under sensor
  fit AUTO a landscape frame fits the sensor width horizontally, so the horizontal field of view is
  2 atan(18 / 40) = 48.4555 degrees and the vertical one 2 atan(18 / 40 x 480 / 640) = 37.2991 degrees.
  (Blender's own cam.angle_y, 2 atan(12 / 40) = 33.40 degrees, is not the picture's: it ignores the fit.)

Exports (all +Y up, -Z forward, as glTF and symphong's automatic camera use): scene.glb, scene.gltf
(+ scene.bin, checker.png), scene.fbx (binary; no animation), scene.dae, scene.obj (+ scene.mtl),
scene.ply (geometry only; Blender's PLY exporter writes Z up unless told, so axis_forward -Z, axis_up Y
is passed, and only the meshes are selected). Every other exporter option is Blender's default, except glTF's "export_cameras" (off by
default) so that the camera is written.

Beside them, the scene in symphong's own formats, written by this script from the same triangles:
twin.obj + twin.mtl (the materials as the Phong parameters the Blender materials stand for, see TWIN
below), twin.json (twin.obj with the Blender camera: fov = the vertical field of view above),
twin-regions.json (the triangles of each object, in twin.obj's order, for the region masks), and
truth.json (every number above: the Blender materials, the twin's Phong values, the camera's fields
and fields of view, the triangles per object, the Blender and exporter versions).
"""
import json
import math
import os
import sys

import addon_utils
import bpy
from mathutils import Vector

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
OUT = os.path.abspath(argv[0] if argv else "out/blender-roundtrip")
os.makedirs(OUT, exist_ok=True)

WIDTH, HEIGHT = 640, 480
LENS, SENSOR_W, SENSOR_H = 40.0, 36.0, 24.0
CAM_LOCATION = (0.0, -3.9, 1.0)

WHITE = (0.725, 0.71, 0.68)
RED = (0.63, 0.065, 0.05)
GREEN = (0.14, 0.45, 0.091)
GLOSSY_BASE = (0.75, 0.55, 0.25)
GLOSSY_SPECULAR, GLOSSY_ROUGHNESS = 0.5, 0.2
EMISSION_STRENGTH = 17.0
CHECKER_A = (230, 230, 230)  # sRGB bytes: every other square
# the other squares, per quadrant of UV space: (u < 1/2, v < 1/2), (u > 1/2, v < 1/2), (u < 1/2, v > 1/2), (u > 1/2, v > 1/2)
CHECKER_QUADRANTS = [(50, 70, 170), (170, 50, 50), (50, 150, 50), (60, 60, 60)]

# TWIN: the Phong parameters the twin gives each Blender material. Diffuse Principled (Specular 0,
# Roughness 1, Metallic 0): rho_d = base colour, rho_s = 0. The glossy block, a dielectric: Blender's
# Specular s gives the normal-incidence reflectance F0 = 0.08 s = 0.04; the energy-consistent split
# gives rho_s = F0 and rho_d = base colour x (1 - F0); the lobe's exponent is the GGX-width match of
# docs/scene-format.md, n = 2 / alpha^2 - 2 with alpha = roughness^2. The light: rho_d = 0 (black
# base colour), emission = colour x strength.
F0 = 0.08 * GLOSSY_SPECULAR
ALPHA = GLOSSY_ROUGHNESS ** 2
TWIN = {
    "white": {"Kd": WHITE, "Ks": (0, 0, 0)},
    "red": {"Kd": RED, "Ks": (0, 0, 0)},
    "green": {"Kd": GREEN, "Ks": (0, 0, 0)},
    "glossy": {"Kd": tuple(round(c * (1 - F0), 6) for c in GLOSSY_BASE), "Ks": (F0, F0, F0), "Ns": round(2 / ALPHA ** 2 - 2, 3)},
    "light": {"Kd": (0, 0, 0), "Ks": (0, 0, 0), "Ke": (EMISSION_STRENGTH,) * 3},
    "checker": {"map_Kd": "checker.png", "Ks": (0, 0, 0)},
}

# ---------------------------------------------------------------------------------------------------
# An empty scene.
for collection in (bpy.data.objects, bpy.data.meshes, bpy.data.materials, bpy.data.cameras, bpy.data.lights, bpy.data.images):
    for block in list(collection):
        collection.remove(block)
scene = bpy.context.scene
scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = WIDTH, HEIGHT, 100
scene.unit_settings.system = "METRIC"
scene.unit_settings.scale_length = 1.0

# The texture: 64 x 64, four quadrants (in UV space) of 8 x 8 checks, each quadrant its own pair of
# colours so that a flipped or mirrored texture shows in the checker's quadrant regions. Blender's
# pixel rows run from the bottom (v = 0) up.
image = bpy.data.images.new("checker", 64, 64, alpha=False)
pixels = []
for y in range(64):
    for x in range(64):
        other = CHECKER_QUADRANTS[(1 if y >= 32 else 0) * 2 + (1 if x >= 32 else 0)]
        c = CHECKER_A if (x // 8 + y // 8) % 2 == 0 else other
        pixels += [c[0] / 255, c[1] / 255, c[2] / 255, 1.0]
image.pixels = pixels
image.filepath_raw = os.path.join(OUT, "checker.png")
image.file_format = "PNG"
image.save()


def principled(name, base, specular, roughness, metallic=0.0, emission=None, strength=1.0, texture=None):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nodes = m.node_tree.nodes
    p = nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (*base, 1.0)
    p.inputs["Specular"].default_value = specular
    p.inputs["Roughness"].default_value = roughness
    p.inputs["Metallic"].default_value = metallic
    if emission is not None:
        p.inputs["Emission"].default_value = (*emission, 1.0)
        p.inputs["Emission Strength"].default_value = strength
    if texture is not None:
        t = nodes.new("ShaderNodeTexImage")
        t.image = texture
        m.node_tree.links.new(t.outputs["Color"], p.inputs["Base Color"])
    m.diffuse_color = (*base, 1.0)  # the viewport colour only
    return m


materials = {
    "white": principled("white", WHITE, 0.0, 1.0),
    "red": principled("red", RED, 0.0, 1.0),
    "green": principled("green", GREEN, 0.0, 1.0),
    "glossy": principled("glossy", GLOSSY_BASE, GLOSSY_SPECULAR, GLOSSY_ROUGHNESS),
    "light": principled("light", (0.0, 0.0, 0.0), 0.0, 1.0, emission=(1.0, 1.0, 1.0), strength=EMISSION_STRENGTH),
    "checker": principled("checker", (1.0, 1.0, 1.0), 0.0, 1.0, texture=image),
}


def quad(corner, e1, e2):
    """The parallelogram corner + s e1 + t e2, facing cross(e1, e2); UV (s, t)."""
    c, a, b = Vector(corner), Vector(e1), Vector(e2)
    return [c, c + a, c + a + b, c + b], [(0, 0), (1, 0), (1, 1), (0, 1)]


def add_object(name, verts, faces, material, uvs=None):
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(v) for v in verts], [], faces)
    if uvs is not None:
        layer = me.uv_layers.new(name="UVMap")
        for loop in me.loops:
            layer.data[loop.index].uv = uvs[loop.vertex_index]
    me.materials.append(material)
    me.update()
    ob = bpy.data.objects.new(name, me)
    scene.collection.objects.link(ob)
    return ob


walls = {
    "floor": (quad((-1, -1, 0), (2, 0, 0), (0, 2, 0)), "white"),
    "ceiling": (quad((-1, -1, 2), (0, 2, 0), (2, 0, 0)), "white"),
    "back": (quad((-1, 1, 0), (2, 0, 0), (0, 0, 2)), "white"),
    "left": (quad((-1, -1, 0), (0, 2, 0), (0, 0, 2)), "red"),
    "right": (quad((1, -1, 0), (0, 0, 2), (0, 2, 0)), "green"),
}
for name, ((verts, _), mat) in walls.items():
    add_object(name, verts, [(0, 1, 2, 3)], materials[mat])

verts, _ = quad((-0.25, -0.25, 1.98), (0, 0.5, 0), (0.5, 0, 0))
add_object("light", verts, [(0, 1, 2, 3)], materials["light"])

# The checker quad as 2 x 2 faces (a region per quadrant of the texture).
grid = [Vector((0.1 + 0.35 * i, 0.99, 0.9 + 0.35 * j)) for j in range(3) for i in range(3)]
grid_uv = [(0.5 * i, 0.5 * j) for j in range(3) for i in range(3)]
add_object("checker", grid, [(j * 3 + i, j * 3 + i + 1, j * 3 + i + 4, j * 3 + i + 3) for j in range(2) for i in range(2)],
           materials["checker"], uvs=grid_uv)

# The glossy block: a unit cube (outward faces) placed by its object transform.
cube_v = [(x, y, z) for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]
cube_f = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
block = add_object("glossy", cube_v, cube_f, materials["glossy"])
block.scale = (0.6, 0.6, 1.2)
block.rotation_euler = (0.0, 0.0, math.radians(20.0))
block.location = (-0.35, 0.35, 0.6)
for me in bpy.data.meshes:
    me.validate()
    me.update()
# Outward normals for the cube (from_pydata keeps the winding given; check it).
bpy.context.view_layer.update()

cam_data = bpy.data.cameras.new("Camera")
cam_data.type = "PERSP"
cam_data.lens, cam_data.sensor_width, cam_data.sensor_height, cam_data.sensor_fit = LENS, SENSOR_W, SENSOR_H, "AUTO"
cam_data.clip_start, cam_data.clip_end = 0.1, 100.0
camera = bpy.data.objects.new("Camera", cam_data)
camera.location = CAM_LOCATION
camera.rotation_euler = (math.radians(90.0), 0.0, 0.0)
scene.collection.objects.link(camera)
scene.camera = camera
bpy.context.view_layer.update()

# ---------------------------------------------------------------------------------------------------
# The twin, in symphong's formats, from the evaluated triangles (Y up: (x, y, z) -> (x, z, -y), as the
# exporters below write).
def yup(v):
    return (v[0], v[2], -v[1])


depsgraph = bpy.context.evaluated_depsgraph_get()
lines = ["# twin of the Blender scene (make_scene.py): the same triangles, Y up, symphong's Phong materials", "mtllib twin.mtl"]
vcount = tcount = tvcount = 0
regions, per_object = {}, {}
for ob in sorted((o for o in scene.objects if o.type == "MESH"), key=lambda o: o.name):
    ev = ob.evaluated_get(depsgraph)
    me = ev.to_mesh()
    me.calc_loop_triangles()
    uvl = me.uv_layers.active.data if me.uv_layers.active else None
    lines += [f"o {ob.name}", f"usemtl {me.materials[0].name}"]
    first = tcount
    for tri in me.loop_triangles:
        if ob.name == "checker":  # a region per quadrant of UV space: checker-u0v0 (u, v < 1/2), ...
            cu, cv = (sum(uvl[li].uv[k] for li in tri.loops) / 3 for k in (0, 1))
            regions.setdefault(f"checker-u{int(cu > 0.5)}v{int(cv > 0.5)}", []).append(tcount)
        idx = []
        for li, vi in zip(tri.loops, tri.vertices):
            p = yup(ob.matrix_world @ me.vertices[vi].co)
            lines.append("v %.6f %.6f %.6f" % p)
            vcount += 1
            if uvl is not None:
                u = uvl[li].uv
                lines.append("vt %.6f %.6f" % (u[0], u[1]))
                tvcount += 1
                idx.append(f"{vcount}/{tvcount}")
            else:
                idx.append(f"{vcount}")
        lines.append("f " + " ".join(idx))
        tcount += 1
    regions[ob.name] = list(range(first, tcount))
    per_object[ob.name] = {"material": me.materials[0].name, "triangles": tcount - first, "blender_vertices": len(me.vertices),
                           "blender_faces": len(me.polygons)}
    ev.to_mesh_clear()
with open(os.path.join(OUT, "twin.obj"), "w") as f:
    f.write("\n".join(lines) + "\n")
mtl = ["# twin materials: the Phong parameters the Blender materials stand for (make_scene.py, TWIN)"]
for name, m in TWIN.items():
    mtl.append(f"newmtl {name}")
    for key, value in m.items():
        mtl.append(f"{key} {value}" if isinstance(value, (str, float, int)) else f"{key} " + " ".join(f"{x:g}" for x in value))
    mtl.append("")
with open(os.path.join(OUT, "twin.mtl"), "w") as f:
    f.write("\n".join(mtl))

h_fov = 2 * math.atan(SENSOR_W / 2 / LENS)
v_fov = 2 * math.atan(math.tan(h_fov / 2) * HEIGHT / WIDTH)
cam_world = camera.matrix_world
forward = (cam_world.to_3x3() @ Vector((0, 0, -1))).normalized()
up = (cam_world.to_3x3() @ Vector((0, 1, 0))).normalized()
pos = cam_world.translation
twin_camera = {"position": list(yup(pos)), "target": list(yup(pos + forward)), "up": list(yup(up)), "fov": round(math.degrees(v_fov), 4)}
twin_camera = {k: [round(x, 6) + 0.0 for x in v] if isinstance(v, list) else v for k, v in twin_camera.items()}
with open(os.path.join(OUT, "twin.json"), "w") as f:
    json.dump({"obj": "twin.obj", "name": "twin", "camera": twin_camera}, f, indent=1)
    f.write("\n")
with open(os.path.join(OUT, "twin-regions.json"), "w") as f:
    json.dump({"comment": "the triangles (0-based, in twin.obj order) of each object and of each quadrant of the checker's UV space", "regions": regions}, f, indent=1)
    f.write("\n")

# ---------------------------------------------------------------------------------------------------
# The exports. Each exporter is called with the options named here and Blender's defaults for the rest;
# options this Blender's exporter does not have are dropped and listed in truth.json.
for module in ("io_scene_gltf2", "io_scene_fbx", "io_mesh_ply"):
    addon_utils.enable(module, default_set=True)
dropped, failed = {}, {}


def export(label, op, **kwargs):
    try:
        props = op.get_rna_type().properties.keys()
    except Exception as e:  # the operator does not exist in this build
        failed[label] = f"no such operator: {e}"
        print(f"make_scene: {label}: {failed[label]}")
        return
    use = {k: v for k, v in kwargs.items() if k in props}
    dropped[label] = sorted(set(kwargs) - set(use))
    try:
        result = op(**use)
        print(f"make_scene: {label}: {result}")
    except Exception as e:
        failed[label] = str(e)
        print(f"make_scene: {label} FAILED: {e}")


def path(name):
    return os.path.join(OUT, name)


export("glb", bpy.ops.export_scene.gltf, filepath=path("scene.glb"), export_format="GLB", export_cameras=True)
export("gltf", bpy.ops.export_scene.gltf, filepath=path("scene.gltf"), export_format="GLTF_SEPARATE", export_cameras=True)
export("fbx", bpy.ops.export_scene.fbx, filepath=path("scene.fbx"), bake_anim=False)
export("dae", bpy.ops.wm.collada_export, filepath=path("scene.dae"))
export("obj", bpy.ops.wm.obj_export, filepath=path("scene.obj"))
# PLY: the meshes only (with the camera selected too, the exporter prints "Object does not have geometry data").
for ob in scene.objects:
    ob.select_set(ob.type == "MESH")
export("ply", bpy.ops.export_mesh.ply, filepath=path("scene.ply"), use_selection=True, axis_forward="-Z", axis_up="Y")


def addon_version(module):
    for mod in addon_utils.modules():
        if mod.__name__ == module:
            return ".".join(map(str, mod.bl_info.get("version", ())))
    return None


truth = {
    "blender": bpy.app.version_string,
    "exporters": {m: addon_version(m) for m in ("io_scene_gltf2", "io_scene_fbx", "io_mesh_ply")},
    "exporter_options_dropped": dropped,
    "exporters_failed": failed,
    "units": "metres; Blender +Z up; exports and twin +Y up: (x, y, z) -> (x, z, -y)",
    "materials": {
        "white": {"base_color": WHITE, "specular": 0.0, "roughness": 1.0, "metallic": 0.0},
        "red": {"base_color": RED, "specular": 0.0, "roughness": 1.0, "metallic": 0.0},
        "green": {"base_color": GREEN, "specular": 0.0, "roughness": 1.0, "metallic": 0.0},
        "glossy": {"base_color": GLOSSY_BASE, "specular": GLOSSY_SPECULAR, "roughness": GLOSSY_ROUGHNESS, "metallic": 0.0},
        "light": {"base_color": (0, 0, 0), "specular": 0.0, "roughness": 1.0, "metallic": 0.0, "emission": (1, 1, 1),
                  "emission_strength": EMISSION_STRENGTH},
        "checker": {"base_color": "checker.png (sRGB)", "specular": 0.0, "roughness": 1.0, "metallic": 0.0,
                    "checker_srgb_bytes": {"every_other_square": CHECKER_A, "quadrants_u_lo_v_lo__u_hi_v_lo__u_lo_v_hi__u_hi_v_hi": CHECKER_QUADRANTS}},
        "viewport_defaults_left_as_blender_sets_them": {"specular_intensity": materials["white"].specular_intensity,
                                                        "roughness": materials["white"].roughness,
                                                        "metallic": materials["white"].metallic},
    },
    "twin_phong": {k: {kk: list(vv) if isinstance(vv, tuple) else vv for kk, vv in v.items()} for k, v in TWIN.items()},
    "camera": {
        "lens_mm": LENS, "sensor_width_mm": SENSOR_W, "sensor_height_mm": SENSOR_H, "sensor_fit": "AUTO",
        "resolution": [WIDTH, HEIGHT], "clip": [0.1, 100.0],
        "blender_location": list(CAM_LOCATION), "blender_rotation_deg": [90, 0, 0],
        "horizontal_fov_deg": math.degrees(h_fov), "vertical_fov_deg": math.degrees(v_fov),
        "blender_angle_x_deg": math.degrees(cam_data.angle_x), "blender_angle_y_deg": math.degrees(cam_data.angle_y),
        "yup": twin_camera,
    },
    "objects": per_object,
    "twin_triangles": tcount,
}
with open(path("truth.json"), "w") as f:
    json.dump(truth, f, indent=1)
    f.write("\n")
print("make_scene: wrote", OUT)
sys.exit(1 if failed else 0)
