"""A portrait (taller than wide) camera, written by Blender's own exporters.

    blender -b --factory-startup --python-exit-code 1 -P scripts/blender-roundtrip/make_portrait.py -- OUTDIR

(Blender 3.4.1 from Debian 12; OUTDIR = tests/data/blender/portrait.) Never run in CI.

The scene (Blender coordinates, +Z up, metres; the exports are +Y up: (x, y, z) -> (x, z, -y)):
- "floor": a 4 x 4 m quad at z = 0 facing +Z, Principled Base Color 0.8 grey.
- three boxes standing on the floor (unit cubes placed by their object transforms), Principled Base Color
  red / green / blue, Specular 0, Roughness 1, Metallic 0.
- "light": a 1 x 1 m quad at z = 3 facing down, Principled Base Color black, Emission white, Strength 10.
- "Camera": perspective, focal length 50 mm, sensor 36 x 24 mm (sensor_width 36 as asked; sensor_height
  Blender's default 24), sensor fit AUTO, at (0, -7, 2.2), rotation (80, 0, 0) degrees XYZ Euler (it looks
  along +Y, 10 degrees down); render resolution 60 x 80 (portrait), pixel aspect 1.

Under sensor fit AUTO Blender fits the sensor width (36 mm) to the LONGER side of the picture: for a portrait
frame the vertical side. So the picture's vertical field of view is 2 atan(18 / 50) = 39.5978 degrees and
its horizontal one 2 atan(18 / 50 x 60 / 80) = 30.2192 degrees. (Blender's cam.angle_x = 2 atan(18 / 50) =
39.5978 and cam.angle_y = 2 atan(12 / 50) = 26.9915 both ignore the fit; cam.angle = angle_x.)

Exports: scene.glb (export_cameras), scene.fbx (bake_anim False), scene.dae (defaults); every other option
Blender's default. truth.json: the fields of view (computed, and Blender's own from
Camera.calc_matrix_camera, i.e. the projection Blender renders with), the camera's placement in Z-up and
Y-up coordinates, the objects, the versions.
"""
import json
import math
import os
import sys

import addon_utils
import bpy
from mathutils import Vector

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
OUT = os.path.abspath(argv[0] if argv else "out/blender-portrait")
os.makedirs(OUT, exist_ok=True)

WIDTH, HEIGHT = 60, 80
LENS, SENSOR_W, SENSOR_H = 50.0, 36.0, 24.0
CAM_LOCATION, CAM_ROTATION_DEG = (0.0, -7.0, 2.2), (80.0, 0.0, 0.0)
BOXES = {  # name: (colour, location, scale, rotation about Z in degrees)
    "box_red": ((0.63, 0.065, 0.05), (-0.7, 0.3, 0.4), (0.8, 0.8, 0.8), 15.0),
    "box_green": ((0.14, 0.45, 0.091), (0.6, 0.8, 0.75), (0.7, 0.7, 1.5), -20.0),
    "box_blue": ((0.1, 0.15, 0.6), (0.1, -0.8, 0.25), (0.5, 0.5, 0.5), 40.0),
}
FLOOR_GREY, EMISSION_STRENGTH = 0.8, 10.0

for collection in (bpy.data.objects, bpy.data.meshes, bpy.data.materials, bpy.data.cameras, bpy.data.lights, bpy.data.images):
    for block in list(collection):
        collection.remove(block)
scene = bpy.context.scene
render = scene.render
render.resolution_x, render.resolution_y, render.resolution_percentage = WIDTH, HEIGHT, 100
render.pixel_aspect_x = render.pixel_aspect_y = 1.0
scene.unit_settings.system, scene.unit_settings.scale_length = "METRIC", 1.0


def principled(name, base, emission=None, strength=1.0):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    p = m.node_tree.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (*base, 1.0)
    p.inputs["Specular"].default_value = 0.0
    p.inputs["Roughness"].default_value = 1.0
    p.inputs["Metallic"].default_value = 0.0
    if emission is not None:
        p.inputs["Emission"].default_value = (*emission, 1.0)
        p.inputs["Emission Strength"].default_value = strength
    m.diffuse_color = (*base, 1.0)
    return m


def add_object(name, verts, faces, material):
    me = bpy.data.meshes.new(name)
    me.from_pydata(verts, [], faces)
    me.materials.append(material)
    me.validate()
    me.update()
    ob = bpy.data.objects.new(name, me)
    scene.collection.objects.link(ob)
    return ob


add_object("floor", [(-2, -2, 0), (2, -2, 0), (2, 2, 0), (-2, 2, 0)], [(0, 1, 2, 3)], principled("floor", (FLOOR_GREY,) * 3))
add_object("light", [(-0.5, -0.5, 3), (-0.5, 0.5, 3), (0.5, 0.5, 3), (0.5, -0.5, 3)], [(0, 1, 2, 3)],
           principled("light", (0, 0, 0), emission=(1, 1, 1), strength=EMISSION_STRENGTH))
cube_v = [(x, y, z) for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]
cube_f = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
for name, (colour, location, scale, turn) in BOXES.items():
    ob = add_object(name, cube_v, cube_f, principled(name, colour))
    ob.location, ob.scale, ob.rotation_euler = location, scale, (0.0, 0.0, math.radians(turn))

cam_data = bpy.data.cameras.new("Camera")
cam_data.type, cam_data.lens, cam_data.sensor_width, cam_data.sensor_height, cam_data.sensor_fit = "PERSP", LENS, SENSOR_W, SENSOR_H, "AUTO"
cam_data.clip_start, cam_data.clip_end = 0.1, 100.0
camera = bpy.data.objects.new("Camera", cam_data)
camera.location = CAM_LOCATION
camera.rotation_euler = tuple(math.radians(a) for a in CAM_ROTATION_DEG)
scene.collection.objects.link(camera)
scene.camera = camera
bpy.context.view_layer.update()

# The fields of view: from the rule (AUTO fits the sensor width to the longer side) and from Blender's own
# projection matrix (P[0][0] = 1 / tan(h / 2), P[1][1] = 1 / tan(v / 2)).
longer = max(WIDTH, HEIGHT)
v_fov = 2 * math.atan(SENSOR_W / 2 / LENS * HEIGHT / longer)
h_fov = 2 * math.atan(SENSOR_W / 2 / LENS * WIDTH / longer)
depsgraph = bpy.context.evaluated_depsgraph_get()
P = camera.calc_matrix_camera(depsgraph, x=WIDTH, y=HEIGHT, scale_x=1.0, scale_y=1.0)
h_blender, v_blender = 2 * math.atan(1 / P[0][0]), 2 * math.atan(1 / P[1][1])
assert abs(h_blender - h_fov) < 1e-6 and abs(v_blender - v_fov) < 1e-6, (math.degrees(h_blender), math.degrees(v_blender))


def yup(v):
    return [round(v[0], 6) + 0.0, round(v[2], 6) + 0.0, round(-v[1], 6) + 0.0]


rot = camera.matrix_world.to_3x3()
forward, up, pos = rot @ Vector((0, 0, -1)), rot @ Vector((0, 1, 0)), camera.matrix_world.translation

for module in ("io_scene_gltf2", "io_scene_fbx"):
    addon_utils.enable(module, default_set=True)
failed = {}


def export(label, op, **kwargs):
    try:
        print(f"make_portrait: {label}: {op(**kwargs)}")
    except Exception as e:
        failed[label] = str(e)
        print(f"make_portrait: {label} FAILED: {e}")


def path(name):
    return os.path.join(OUT, name)


export("glb", bpy.ops.export_scene.gltf, filepath=path("scene.glb"), export_format="GLB", export_cameras=True)
export("fbx", bpy.ops.export_scene.fbx, filepath=path("scene.fbx"), bake_anim=False)
export("dae", bpy.ops.wm.collada_export, filepath=path("scene.dae"))


def addon_version(module):
    for mod in addon_utils.modules():
        if mod.__name__ == module:
            return ".".join(map(str, mod.bl_info.get("version", ())))
    return None


truth = {
    "blender": bpy.app.version_string,
    "exporters": {m: addon_version(m) for m in ("io_scene_gltf2", "io_scene_fbx")},
    "exporters_failed": failed,
    "units": "metres; Blender +Z up; exports +Y up: (x, y, z) -> (x, z, -y)",
    "camera": {
        "lens_mm": LENS, "sensor_width_mm": SENSOR_W, "sensor_height_mm": SENSOR_H, "sensor_fit": "AUTO",
        "resolution": [WIDTH, HEIGHT], "pixel_aspect": 1.0, "aspect_width_over_height": WIDTH / HEIGHT, "clip": [0.1, 100.0],
        "rule": "sensor fit AUTO: the sensor width applies to the longer side of the picture (here the vertical one)",
        "vertical_fov_deg": math.degrees(v_fov), "horizontal_fov_deg": math.degrees(h_fov),
        "vertical_fov_rad": v_fov, "horizontal_fov_rad": h_fov,
        "from_blender_projection_matrix_deg": {"horizontal": math.degrees(h_blender), "vertical": math.degrees(v_blender)},
        "blender_angle_x_deg": math.degrees(cam_data.angle_x), "blender_angle_y_deg": math.degrees(cam_data.angle_y),
        "blender_angle_deg": math.degrees(cam_data.angle),
        "blender_location": list(CAM_LOCATION), "blender_rotation_deg_xyz": list(CAM_ROTATION_DEG),
        "yup": {"position": yup(pos), "target": yup(pos + forward), "up": yup(up), "forward": yup(forward),
                "fov": round(math.degrees(v_fov), 4)},
    },
    "objects": {
        "floor": {"quad": "4 x 4 m at z = 0 facing +Z", "base_color": [FLOOR_GREY] * 3},
        "light": {"quad": "1 x 1 m at z = 3 facing -Z", "emission": [1, 1, 1], "emission_strength": EMISSION_STRENGTH},
        **{name: {"base_color": list(c), "location": list(loc), "scale": list(s), "rotation_z_deg": t, "mesh": "unit cube"}
           for name, (c, loc, s, t) in BOXES.items()},
        "materials": "Principled BSDF, Specular 0, Roughness 1, Metallic 0",
    },
    "exports": {"scene.glb": "export_scene.gltf export_format=GLB export_cameras=True", "scene.fbx": "export_scene.fbx bake_anim=False",
                "scene.dae": "wm.collada_export defaults"},
}
with open(path("truth.json"), "w") as f:
    json.dump(truth, f, indent=1)
    f.write("\n")
print(f"make_portrait: vertical fov {math.degrees(v_fov):.6f}, horizontal {math.degrees(h_fov):.6f} degrees; wrote {OUT}")
sys.exit(1 if failed else 0)
