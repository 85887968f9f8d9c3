"""A tangent-space normal map, written by Blender's own exporters, with a Cycles picture of its effect.

    blender -b --factory-startup --python-exit-code 1 -P scripts/blender-roundtrip/make_normal_map.py -- OUTDIR [--no-render]

(Blender 3.4.1 from Debian 12; OUTDIR = tests/data/blender/normalmap.) Never run in CI.

The scene (Blender coordinates, +Z up, metres; the exports are +Y up: (x, y, z) -> (x, z, -y)):
- "ground": a 2 x 2 m plane facing +Z made of two quads that share the edge x = 0 (local coordinates),
  turned 30 degrees about +Z by its object transform. Its UVs are NOT aligned with the axes:
    quad A (x in [-1, 0]): u = (y + 1) / 2, v = -x   -> +U along local +Y, +V along local -X (T x B = +N)
    quad B (x in [ 0, 1]): u = (y + 1) / 2, v = +x   -> +U along local +Y, +V along local +X (mirrored:
                                                        T x B = -N, glTF tangent w = -1)
  (quad B is quad A's UV layout mirrored in V, so that a wrong bitangent sign shows.)
  Material "bumpy": Principled BSDF, Base Color 0.5 grey, Specular 0, Roughness 1, Metallic 0, Normal from a
  Normal Map node (Tangent Space, UV map "UVMap", Strength 1) whose Color is an Image Texture of bumps.png
  (Non-Color, Linear interpolation, Repeat).
- bumps.png: 64 x 64 RGB 8 bit, written here: the tangent-space normal (OpenGL convention, R = +U, G = +V,
  B = +N) n = normalize(A sin(2 pi 4 u), A sin(2 pi 2 v), 1), A = 0.6, at the pixel centres
  u = (i + 0.5) / 64, v = (j + 0.5) / 64 (j = 0 the bottom row of the picture, v = 0), stored as
  byte = round(255 (n / 2 + 1 / 2)).
- "emitter": a 1 x 1 m quad centred 3 m from the origin at elevation 30 degrees above the +X axis (world;
  (2.598, 0, 1.5)), facing the origin; Principled Base Color black, Specular 0, Roughness 1, Emission white,
  Emission Strength 50.
- "Camera": at (0, 0, 4) looking straight down (-Z), up +Y; 50 mm lens, 36 x 24 mm sensor, fit AUTO;
  render 96 x 96 (field of view 2 atan(18 / 50) = 39.5978 degrees both ways).
- World black.

Exports: scene.glb (export_cameras; no tangents), scene_tangents.glb (export_cameras, export_tangents),
scene.obj + scene.mtl (wm.obj_export defaults), scene.fbx (bake_anim False), scene_tspace.fbx (bake_anim
False, use_tspace True), scene.dae (defaults); and scene_strength05.glb / .obj (+ .mtl) / .fbx: the same
with the Normal Map node's Strength 0.5 (where each format keeps the strength: at 1 glTF and FBX leave it
out). Every other option is Blender's default.

cycles_reference.exr: Cycles' picture of this scene, 96 x 96, 256 samples, with the settings of
docs/validation.md (no adaptive sampling, no denoising, bounces 64, no clamping, light threshold 0, filter
glossy 0, box pixel filter 1 px, seed 0, black world, view transform Standard, look None, exposure 0,
gamma 1, 32-bit float RGB EXR). For that picture the ground's Principled BSDF is replaced by a Diffuse BSDF
(roughness 0, i.e. Lambert, colour 0.5; the same Normal Map node on its Normal): Cycles' Principled
diffuse at Roughness 1 is not Lambertian (retro-reflection), and the exports stand for a Lambertian 0.5.
The emitter's material is an Emission shader (white, strength 50) on front faces only (Mix on
Geometry.Backfacing), as in docs/validation.md; only its front faces the ground anyway.

truth.json: every number above, Blender's own tangents (mesh.calc_tangents: per face corner, object and
world space, Z up and Y up), and the exporter versions and options.
"""
import json
import math
import os
import sys

import addon_utils
import bpy
from mathutils import Matrix, Vector

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
RENDER = "--no-render" not in argv
argv = [a for a in argv if a != "--no-render"]
OUT = os.path.abspath(argv[0] if argv else "out/blender-normalmap")
os.makedirs(OUT, exist_ok=True)

SIZE = 64
AMPLITUDE, PERIODS_U, PERIODS_V = 0.6, 4, 2
GREY = 0.5
OBJECT_TURN_DEG = 30.0
EMITTER_DISTANCE, EMITTER_ELEVATION_DEG, EMITTER_AZIMUTH_DEG, EMITTER_SIZE, EMITTER_STRENGTH = 3.0, 30.0, 0.0, 1.0, 50.0
WIDTH = HEIGHT = 96
LENS, SENSOR_W, SENSOR_H = 50.0, 36.0, 24.0
CAM_LOCATION = (0.0, 0.0, 4.0)
SAMPLES = 256
STRENGTH_VARIANT = 0.5

for collection in (bpy.data.objects, bpy.data.meshes, bpy.data.materials, bpy.data.cameras, bpy.data.lights, bpy.data.images):
    for block in list(collection):
        collection.remove(block)
scene = bpy.context.scene
scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = WIDTH, HEIGHT, 100
scene.unit_settings.system, scene.unit_settings.scale_length = "METRIC", 1.0
world = scene.world or bpy.data.worlds.new("World")
scene.world = world
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0


# ---------------------------------------------------------------------------------------------------
# bumps.png
def tangent_normal(u, v):
    n = Vector((AMPLITUDE * math.sin(2 * math.pi * PERIODS_U * u), AMPLITUDE * math.sin(2 * math.pi * PERIODS_V * v), 1.0))
    return n.normalized()


image = bpy.data.images.new("bumps", SIZE, SIZE, alpha=False, float_buffer=False)
image.colorspace_settings.name = "Non-Color"
expected_bytes = []  # [row j from the bottom][column i] = (r, g, b)
pixels = []
for j in range(SIZE):
    row = []
    for i in range(SIZE):
        n = tangent_normal((i + 0.5) / SIZE, (j + 0.5) / SIZE)
        rgb = tuple(int(round(255 * (0.5 * c + 0.5))) for c in n)
        row.append(rgb)
        pixels += [rgb[0] / 255, rgb[1] / 255, rgb[2] / 255, 1.0]
    expected_bytes.append(row)
image.pixels = pixels
image.filepath_raw = os.path.join(OUT, "bumps.png")
image.file_format = "PNG"
image.save()
# Read the file back (Blender's loader): the bytes must be the formula's.
check = bpy.data.images.load(os.path.join(OUT, "bumps.png"), check_existing=False)
check.colorspace_settings.name = "Non-Color"
px = list(check.pixels)
worst = max(abs(round(px[4 * (j * SIZE + i) + c] * 255) - expected_bytes[j][i][c]) for j in range(SIZE) for i in range(SIZE) for c in range(3))
bpy.data.images.remove(check)
print(f"make_normal_map: bumps.png read back: largest byte difference from the formula {worst}")
assert worst == 0, "bumps.png does not hold the formula's bytes"


# ---------------------------------------------------------------------------------------------------
# Materials.
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


bumpy = principled("bumpy", (GREY,) * 3)
nt = bumpy.node_tree
tex = nt.nodes.new("ShaderNodeTexImage")
tex.image, tex.interpolation, tex.extension = image, "Linear", "REPEAT"
nmap = nt.nodes.new("ShaderNodeNormalMap")
nmap.space, nmap.uv_map = "TANGENT", "UVMap"
nmap.inputs["Strength"].default_value = 1.0
nt.links.new(tex.outputs["Color"], nmap.inputs["Color"])
nt.links.new(nmap.outputs["Normal"], nt.nodes["Principled BSDF"].inputs["Normal"])
light_mat = principled("light", (0.0, 0.0, 0.0), emission=(1.0, 1.0, 1.0), strength=EMITTER_STRENGTH)

# ---------------------------------------------------------------------------------------------------
# Geometry.
ground_v = [(-1, -1, 0), (0, -1, 0), (1, -1, 0), (-1, 1, 0), (0, 1, 0), (1, 1, 0)]
ground_f = [(0, 1, 4, 3), (1, 2, 5, 4)]  # A (x <= 0), B (x >= 0), both counter-clockwise seen from +Z
me = bpy.data.meshes.new("ground")
me.from_pydata(ground_v, [], ground_f)
uvl = me.uv_layers.new(name="UVMap")
for poly in me.polygons:
    for li in poly.loop_indices:
        x, y, _ = me.vertices[me.loops[li].vertex_index].co
        uvl.data[li].uv = ((y + 1) / 2, -x if poly.index == 0 else x)
me.materials.append(bumpy)
me.validate()
me.update()
ground = bpy.data.objects.new("ground", me)
ground.rotation_euler = (0.0, 0.0, math.radians(OBJECT_TURN_DEG))
scene.collection.objects.link(ground)

el, az = math.radians(EMITTER_ELEVATION_DEG), math.radians(EMITTER_AZIMUTH_DEG)
centre = EMITTER_DISTANCE * Vector((math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)))
facing = -centre.normalized()
e1 = Vector((-math.sin(az), math.cos(az), 0.0)) * EMITTER_SIZE  # horizontal, perpendicular to the centre
e2 = facing.cross(e1).normalized() * EMITTER_SIZE  # so that e1 x e2 = facing
corner = centre - 0.5 * e1 - 0.5 * e2
em_v = [corner, corner + e1, corner + e1 + e2, corner + e2]
me2 = bpy.data.meshes.new("emitter")
me2.from_pydata([tuple(v) for v in em_v], [], [(0, 1, 2, 3)])
me2.materials.append(light_mat)
me2.update()
emitter = bpy.data.objects.new("emitter", me2)
scene.collection.objects.link(emitter)
assert (me2.polygons[0].normal - facing).length < 1e-5

cam_data = bpy.data.cameras.new("Camera")
cam_data.type, cam_data.lens, cam_data.sensor_width, cam_data.sensor_height, cam_data.sensor_fit = "PERSP", LENS, SENSOR_W, SENSOR_H, "AUTO"
cam_data.clip_start, cam_data.clip_end = 0.1, 100.0
camera = bpy.data.objects.new("Camera", cam_data)
camera.location = CAM_LOCATION
scene.collection.objects.link(camera)
scene.camera = camera
bpy.context.view_layer.update()


# ---------------------------------------------------------------------------------------------------
# Blender's own tangents (MikkTSpace, as Cycles and the exporters use).
def yup(v):
    return [round(v[0], 6) + 0.0, round(v[2], 6) + 0.0, round(-v[1], 6) + 0.0]


def r6(v):
    return [round(c, 6) + 0.0 for c in v]


me.calc_tangents(uvmap="UVMap")
uvl = me.uv_layers["UVMap"]  # (the reference taken before validate() / update() no longer reads the mesh)
rot = ground.matrix_world.to_3x3()
corners = []
for poly in me.polygons:
    for li in poly.loop_indices:
        loop = me.loops[li]
        t, n, s = loop.tangent, loop.normal, loop.bitangent_sign
        b = loop.bitangent  # = s * cross(n, t)
        corners.append({
            "face": "AB"[poly.index], "vertex": loop.vertex_index, "position_object": r6(me.vertices[loop.vertex_index].co),
            "position_world_yup": yup(ground.matrix_world @ me.vertices[loop.vertex_index].co), "uv_blender": r6(uvl.data[li].uv),
            "uv_gltf": r6((uvl.data[li].uv[0], 1 - uvl.data[li].uv[1])),
            "tangent_object": r6(t), "bitangent_object": r6(b), "bitangent_sign": s, "normal_object": r6(n),
            "tangent_world_yup": yup(rot @ t), "bitangent_world_yup": yup(rot @ b), "normal_world_yup": yup(rot @ n),
            "bitangent_equals_sign_times_n_cross_t": (b - s * n.cross(t)).length < 1e-5,
        })
me.free_tangents()

# ---------------------------------------------------------------------------------------------------
# Exports.
for module in ("io_scene_gltf2", "io_scene_fbx"):
    addon_utils.enable(module, default_set=True)
dropped, failed = {}, {}


def export(label, op, **kwargs):
    props = op.get_rna_type().properties.keys()
    use = {k: v for k, v in kwargs.items() if k in props}
    dropped[label] = sorted(set(kwargs) - set(use))
    try:
        print(f"make_normal_map: {label}: {op(**use)}")
    except Exception as e:
        failed[label] = str(e)
        print(f"make_normal_map: {label} FAILED: {e}")


def path(name):
    return os.path.join(OUT, name)


export("glb", bpy.ops.export_scene.gltf, filepath=path("scene.glb"), export_format="GLB", export_cameras=True)
export("glb_tangents", bpy.ops.export_scene.gltf, filepath=path("scene_tangents.glb"), export_format="GLB", export_cameras=True,
       export_tangents=True)
export("obj", bpy.ops.wm.obj_export, filepath=path("scene.obj"))
export("fbx", bpy.ops.export_scene.fbx, filepath=path("scene.fbx"), bake_anim=False)
export("fbx_tspace", bpy.ops.export_scene.fbx, filepath=path("scene_tspace.fbx"), bake_anim=False, use_tspace=True)
export("dae", bpy.ops.wm.collada_export, filepath=path("scene.dae"))
# The same with the Normal Map node's Strength 0.5, to show where each format keeps it (at 1 some leave it out).
nmap.inputs["Strength"].default_value = STRENGTH_VARIANT
export("glb_strength05", bpy.ops.export_scene.gltf, filepath=path("scene_strength05.glb"), export_format="GLB", export_cameras=True)
export("obj_strength05", bpy.ops.wm.obj_export, filepath=path("scene_strength05.obj"))
export("fbx_strength05", bpy.ops.export_scene.fbx, filepath=path("scene_strength05.fbx"), bake_anim=False)
nmap.inputs["Strength"].default_value = 1.0


def addon_version(module):
    for mod in addon_utils.modules():
        if mod.__name__ == module:
            return ".".join(map(str, mod.bl_info.get("version", ())))
    return None


# ---------------------------------------------------------------------------------------------------
# Cycles' picture (a Lambertian copy of the ground's material, a front-only Emission for the emitter).
cycles = {}
if RENDER:
    ref = bpy.data.materials.new("bumpy_lambert")
    ref.use_nodes = True
    rn = ref.node_tree
    for node in list(rn.nodes):
        rn.nodes.remove(node)
    out = rn.nodes.new("ShaderNodeOutputMaterial")
    diffuse = rn.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (GREY, GREY, GREY, 1.0)
    diffuse.inputs["Roughness"].default_value = 0.0
    rtex = rn.nodes.new("ShaderNodeTexImage")
    rtex.image, rtex.interpolation, rtex.extension = image, "Linear", "REPEAT"
    rmap = rn.nodes.new("ShaderNodeNormalMap")
    rmap.space, rmap.uv_map = "TANGENT", "UVMap"
    rmap.inputs["Strength"].default_value = 1.0
    rn.links.new(rtex.outputs["Color"], rmap.inputs["Color"])
    rn.links.new(rmap.outputs["Normal"], diffuse.inputs["Normal"])
    rn.links.new(diffuse.outputs["BSDF"], out.inputs["Surface"])
    me.materials[0] = ref

    em = bpy.data.materials.new("light_front")
    em.use_nodes = True
    en = em.node_tree
    for node in list(en.nodes):
        en.nodes.remove(node)
    eout = en.nodes.new("ShaderNodeOutputMaterial")
    emission = en.nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (1, 1, 1, 1)
    emission.inputs["Strength"].default_value = EMITTER_STRENGTH
    transparent = en.nodes.new("ShaderNodeBsdfTransparent")
    transparent.inputs["Color"].default_value = (0, 0, 0, 1)  # black: the back face neither emits nor lets light through
    geometry = en.nodes.new("ShaderNodeNewGeometry")
    mix = en.nodes.new("ShaderNodeMixShader")
    en.links.new(geometry.outputs["Backfacing"], mix.inputs["Fac"])
    en.links.new(emission.outputs["Emission"], mix.inputs[1])
    en.links.new(transparent.outputs["BSDF"], mix.inputs[2])
    en.links.new(mix.outputs["Shader"], eout.inputs["Surface"])
    me2.materials[0] = em

    r = scene.render
    r.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = SAMPLES
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = 0
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = c.transparent_max_bounces = 64
    c.volume_bounces = 0
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = c.caustics_refractive = True
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    r.film_transparent = False
    vs = scene.view_settings
    vs.view_transform, vs.look, vs.exposure, vs.gamma = "Standard", "None", 0.0, 1.0
    scene.display_settings.display_device = "sRGB"
    scene.sequencer_colorspace_settings.name = "sRGB"
    ims = r.image_settings
    ims.file_format, ims.color_mode, ims.color_depth, ims.exr_codec = "OPEN_EXR", "RGB", "32", "ZIP"
    r.filepath = path("cycles_reference.exr")
    r.use_file_extension = False
    bpy.ops.render.render(write_still=True)
    print("make_normal_map: rendered", r.filepath)
    cycles = {
        "file": "cycles_reference.exr", "resolution": [WIDTH, HEIGHT], "samples": SAMPLES, "device": "CPU", "seed": 0,
        "adaptive_sampling": False, "denoising": False, "max_bounces": 64, "diffuse_glossy_transmission_transparent_bounces": 64,
        "clamp_direct": 0.0, "clamp_indirect": 0.0, "light_sampling_threshold": 0.0, "filter_glossy": 0.0, "caustics": True,
        "pixel_filter": "BOX", "filter_width_px": 1.0, "film_transparent": False, "world": "black (Background strength 0)",
        "view_transform": "Standard", "look": "None", "exposure": 0.0, "gamma": 1.0, "file_format": "OPEN_EXR RGB 32-bit float, ZIP",
        "ground_material_for_the_render": "Diffuse BSDF (roughness 0 = Lambert), colour 0.5, Normal <- the same Normal Map node "
                                          "(tangent space, UVMap, strength 1) <- bumps.png (Non-Color, Linear, Repeat)",
        "emitter_material_for_the_render": f"Emission (1, 1, 1) strength {EMITTER_STRENGTH}, front faces only "
                                           "(Mix Shader, Fac = Geometry.Backfacing, back face black Transparent BSDF)",
        "blender_version": bpy.app.version_string,
    }

# ---------------------------------------------------------------------------------------------------
h_fov = 2 * math.atan(SENSOR_W / 2 / LENS)
truth = {
    "blender": bpy.app.version_string,
    "exporters": {m: addon_version(m) for m in ("io_scene_gltf2", "io_scene_fbx")},
    "exporter_options_dropped": dropped,
    "exporters_failed": failed,
    "units": "metres; Blender +Z up; exports +Y up: (x, y, z) -> (x, z, -y)",
    "image": {
        "file": "bumps.png", "size": [SIZE, SIZE], "format": "PNG RGB 8 bit, Non-Color (data), Linear interpolation, Repeat",
        "convention": "tangent space, OpenGL: R = +X = direction of increasing U, G = +Y = direction of increasing V, B = +Z = surface normal",
        "formula": f"n = normalize({AMPLITUDE} sin(2 pi {PERIODS_U} u), {AMPLITUDE} sin(2 pi {PERIODS_V} v), 1); byte = round(255 (n / 2 + 1 / 2))",
        "texel_centres": "u = (i + 0.5) / 64, v = (j + 0.5) / 64, i = column from the left, j = row from the BOTTOM of the picture (v = 0)",
        "amplitude": AMPLITUDE, "periods_u": PERIODS_U, "periods_v": PERIODS_V,
        "largest_tilt_deg": math.degrees(math.atan(AMPLITUDE * math.sqrt(2))),
    },
    "ground": {
        "object_rotation_deg_about_z": OBJECT_TURN_DEG,
        "vertices_object": ground_v, "faces": {"A": ground_f[0], "B": ground_f[1]},
        "uv": {"A": "u = (y + 1) / 2, v = -x (object coordinates): +U along object +Y, +V along object -X; T x B = +N (tangent sign +1)",
               "B": "u = (y + 1) / 2, v = +x: +U along object +Y, +V along object +X; T x B = -N (mirrored, tangent sign -1)"},
        "material": {"name": "bumpy", "principled": {"base_color": [GREY] * 3, "specular": 0.0, "roughness": 1.0, "metallic": 0.0},
                     "normal_map_node": {"space": "TANGENT", "uv_map": "UVMap", "strength": 1.0}, "image": "bumps.png"},
        "blender_tangents_per_face_corner": corners,
    },
    "emitter": {
        "centre_world_zup": r6(centre), "facing_world_zup": r6(facing), "size_m": [EMITTER_SIZE, EMITTER_SIZE],
        "corners_world_zup": [r6(v) for v in em_v], "corners_world_yup": [yup(v) for v in em_v],
        "elevation_deg": EMITTER_ELEVATION_DEG, "azimuth_deg_from_+x": EMITTER_AZIMUTH_DEG, "distance_m": EMITTER_DISTANCE,
        "material": {"name": "light", "principled": {"base_color": [0, 0, 0], "specular": 0.0, "roughness": 1.0, "emission": [1, 1, 1],
                                                     "emission_strength": EMITTER_STRENGTH}},
        "direction_to_light_from_origin_world_yup": yup(centre.normalized()),
    },
    "camera": {
        "lens_mm": LENS, "sensor_width_mm": SENSOR_W, "sensor_height_mm": SENSOR_H, "sensor_fit": "AUTO", "resolution": [WIDTH, HEIGHT],
        "clip": [0.1, 100.0], "blender_location": list(CAM_LOCATION), "blender_rotation_deg": [0, 0, 0],
        "fov_deg_both": math.degrees(h_fov),
        "yup": {"position": yup(CAM_LOCATION), "target": yup((0, 0, 0)), "up": yup((0, 1, 0)), "fov": round(math.degrees(h_fov), 4)},
    },
    "world": "black",
    "exports": {
        "scene.glb": "export_scene.gltf export_format=GLB export_cameras=True",
        "scene_tangents.glb": "export_scene.gltf export_format=GLB export_cameras=True export_tangents=True",
        "scene.obj": "wm.obj_export defaults", "scene.fbx": "export_scene.fbx bake_anim=False",
        "scene_tspace.fbx": "export_scene.fbx bake_anim=False use_tspace=True", "scene.dae": "wm.collada_export defaults",
    },
    "cycles_reference": cycles,
}
with open(path("truth.json"), "w") as f:
    json.dump(truth, f, indent=1)
    f.write("\n")
print("make_normal_map: wrote", OUT)
sys.exit(1 if failed else 0)
