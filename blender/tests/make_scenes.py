"""Builds one test scene in Blender by script and saves it for the add-on's tests and agreement table.

    blender -b --factory-startup --python blender/tests/make_scenes.py -- OUTDIR SCENE [WIDTH HEIGHT SPP]

SCENE is one of
  cornell-diffuse  the Cornell box of five walls, two white blocks and an emissive ceiling quad; every material a
                   Principled BSDF with Specular 0 (symphong: rho_d = base colour exactly, rho_s = 0)
  cornell-glossy   the same box with a glossy tall block (Specular 0.5, Roughness 0.2) and a metallic sphere
                   (Metallic 1, Roughness 0.3, smooth shading)
  textured         a plane with an image texture (checker) and a tangent-space normal map (round bumps; Normal
                   Map node, strength 1), Specular 0.5, Roughness 0.5, lit by an emissive quad
  hdr              a smooth white sphere (Specular 0) on a floor, lit only by an environment texture (a float
                   lat-long sky with a sun patch, written as sky.exr) with a Mapping node turning it 30 degrees
  lights           a diffuse floor and two walls lit by a point light, a sun and a square area light
  spot             the same lit by a spot light alone
  odd              a cube with a Toon BSDF, a volume object, a hair system and a Principled with Transmission:
                   what the add-on cannot map (its reports)

Writes OUTDIR/SCENE.blend (render engine SYMPHONG, WIDTH x HEIGHT, symphong at SPP samples per pixel, 32-bit
float OpenEXR output), OUTDIR/SCENE.glb (Blender's glTF exporter: cameras on, +Y up) and for the two scenes
where the Phong mapping is exact (cornell-diffuse, hdr, lights, spot) OUTDIR/SCENE-cycles.blend: the same scene for Cycles
with each Principled BSDF replaced by a Diffuse BSDF (Lambertian: what symphong renders for Specular 0;
Cycles' Principled diffuse is Disney's, not Lambertian) at SPP samples, no denoising or adaptive sampling,
1-pixel box filter, emitters emitting from their front only. The hdr scene also gets OUTDIR/hdr.json: the glb
with the sky as a JSON scene's environment map (glTF has no environment).
"""
import json
import math
import os
import sys

import bpy
from mathutils import Vector

argv = sys.argv[sys.argv.index("--") + 1:]
OUT, NAME = os.path.abspath(argv[0]), argv[1]
WIDTH, HEIGHT, SPP = (int(x) for x in (argv[2:5] if len(argv) >= 5 else (128, 128, 64)))
os.makedirs(OUT, exist_ok=True)

for ob in list(bpy.data.objects):
    bpy.data.objects.remove(ob)
for coll in (bpy.data.meshes, bpy.data.materials, bpy.data.lights, bpy.data.cameras, bpy.data.images):
    for item in list(coll):
        coll.remove(item)
scene = bpy.context.scene

WHITE, RED, GREEN = (0.725, 0.71, 0.68), (0.63, 0.065, 0.05), (0.14, 0.45, 0.091)


def principled(name, base, specular=0.0, roughness=1.0, metallic=0.0, emission=None, strength=1.0):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    p = m.node_tree.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (*base, 1.0)
    p.inputs["Specular"].default_value = specular
    p.inputs["Roughness"].default_value = roughness
    p.inputs["Metallic"].default_value = metallic
    if emission is not None:
        p.inputs["Emission"].default_value = (*emission, 1.0)
        p.inputs["Emission Strength"].default_value = strength
    m.diffuse_color = (*base, 1.0)
    return m


def add_object(name, verts, faces, material, uvs=None, smooth=False):
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(v) for v in verts], [], faces)
    if uvs is not None:
        layer = me.uv_layers.new(name="UVMap")
        for loop in me.loops:
            layer.data[loop.index].uv = uvs[loop.vertex_index]
    for poly in me.polygons:
        poly.use_smooth = smooth
    me.materials.append(material)
    me.validate()
    me.update()
    ob = bpy.data.objects.new(name, me)
    scene.collection.objects.link(ob)
    return ob


def quad(corner, e1, e2):
    """The parallelogram corner + s e1 + t e2, facing cross(e1, e2); UV (s, t)."""
    c, a, b = Vector(corner), Vector(e1), Vector(e2)
    return [c, c + a, c + a + b, c + b], [(0, 0), (1, 0), (1, 1), (0, 1)]


def add_quad(name, corner, e1, e2, material):
    verts, uvs = quad(corner, e1, e2)
    return add_object(name, verts, [(0, 1, 2, 3)], material, uvs=uvs)


def add_block(name, material, scale, angle, location):
    cube_v = [(x, y, z) for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]
    cube_f = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    ob = add_object(name, cube_v, cube_f, material)
    ob.scale, ob.rotation_euler, ob.location = scale, (0.0, 0.0, math.radians(angle)), location
    return ob


def add_sphere(name, material, radius, location, segments=48):
    verts, faces = [], []
    rings = segments // 2
    verts.append((0, 0, -radius))
    for j in range(1, rings):
        theta = math.pi * j / rings - math.pi / 2
        for i in range(segments):
            phi = 2 * math.pi * i / segments
            verts.append((radius * math.cos(theta) * math.cos(phi), radius * math.cos(theta) * math.sin(phi), radius * math.sin(theta)))
    verts.append((0, 0, radius))
    top = len(verts) - 1
    for i in range(segments):
        faces.append((0, 1 + (i + 1) % segments, 1 + i))
    for j in range(rings - 2):
        for i in range(segments):
            a, b = 1 + j * segments + i, 1 + j * segments + (i + 1) % segments
            faces.append((a, b, b + segments, a + segments))
    base = 1 + (rings - 2) * segments
    for i in range(segments):
        faces.append((base + i, base + (i + 1) % segments, top))
    ob = add_object(name, verts, faces, material, smooth=True)
    ob.location = location
    return ob


def add_camera(location, rotation, lens=40.0, sensor=36.0, fit="AUTO"):
    data = bpy.data.cameras.new("Camera")
    data.lens, data.sensor_width, data.sensor_fit = lens, sensor, fit
    cam = bpy.data.objects.new("Camera", data)
    cam.location, cam.rotation_euler = location, tuple(math.radians(a) for a in rotation)
    scene.collection.objects.link(cam)
    scene.camera = cam


def black_world():
    world = bpy.data.worlds.new("World") if scene.world is None else scene.world
    scene.world = world
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
    return world


def cornell(glossy):
    mats = {"white": principled("white", WHITE), "red": principled("red", RED), "green": principled("green", GREEN),
            "light": principled("light", (0, 0, 0), emission=(1, 1, 1), strength=17.0)}
    # One material per wall, so that each is a region of the agreement table (the glTF keeps material names).
    add_quad("floor", (-1, -1, 0), (2, 0, 0), (0, 2, 0), mats["white"])
    add_quad("ceiling", (-1, -1, 2), (0, 2, 0), (2, 0, 0), principled("ceiling", WHITE))
    add_quad("back", (-1, 1, 0), (2, 0, 0), (0, 0, 2), principled("back", WHITE))
    add_quad("left", (-1, -1, 0), (0, 2, 0), (0, 0, 2), mats["red"])
    add_quad("right", (1, -1, 0), (0, 0, 2), (0, 2, 0), mats["green"])
    add_quad("light", (-0.25, -0.25, 1.98), (0, 0.5, 0), (0.5, 0, 0), mats["light"])
    add_block("short", principled("short", WHITE), (0.6, 0.6, 0.6), -17, (0.35, -0.3, 0.3))
    if glossy:
        add_block("tall", principled("glossy", (0.75, 0.55, 0.25), specular=0.5, roughness=0.2), (0.6, 0.6, 1.2), 20, (-0.35, 0.35, 0.6))
        add_sphere("sphere", principled("metal", (0.9, 0.9, 0.9), specular=0.5, roughness=0.3, metallic=1.0), 0.22, (0.35, -0.3, 0.82))
    else:
        add_block("tall", principled("tall", WHITE), (0.6, 0.6, 1.2), 20, (-0.35, 0.35, 0.6))
    add_camera((0, -3.9, 1), (90, 0, 0))
    black_world()


def image(name, width, height, pixels, path, float_buffer=False, colorspace="sRGB"):
    img = bpy.data.images.new(name, width, height, float_buffer=float_buffer, alpha=False)
    img.pixels = pixels
    img.filepath_raw = path
    img.file_format = "OPEN_EXR" if float_buffer else "PNG"
    img.save()
    img.colorspace_settings.name = "Linear" if float_buffer else colorspace
    img.pack()  # the .blend carries it; the add-on reads its pixels, the exporter embeds it
    return img


def textured():
    n = 64
    checker = []
    for y in range(n):
        for x in range(n):
            c = (0.85, 0.8, 0.7) if (x // 8 + y // 8) % 2 == 0 else (0.15, 0.25, 0.55)
            checker += [*c, 1.0]
    # Round bumps: a height field h = sum of cosine bumps, its tangent-space normal (OpenGL: +Y = increasing v).
    normal = []
    for y in range(n):
        for x in range(n):
            u, v = (x + 0.5) / n * 4, (y + 0.5) / n * 4
            du = 0.6 * math.pi * math.sin(2 * math.pi * u) * (0.5 - 0.5 * math.cos(2 * math.pi * v)) * 0.5
            dv = 0.6 * math.pi * math.sin(2 * math.pi * v) * (0.5 - 0.5 * math.cos(2 * math.pi * u)) * 0.5
            nv = Vector((-du, -dv, 1.0)).normalized()
            normal += [0.5 * nv.x + 0.5, 0.5 * nv.y + 0.5, 0.5 * nv.z + 0.5, 1.0]
    tex = image("checker", n, n, checker, os.path.join(OUT, "checker.png"))
    nrm = image("bumps", n, n, normal, os.path.join(OUT, "bumps.png"), colorspace="Non-Color")
    m = principled("plane", (1, 1, 1), specular=0.5, roughness=0.5)
    nodes, links = m.node_tree.nodes, m.node_tree.links
    p = nodes["Principled BSDF"]
    t = nodes.new("ShaderNodeTexImage")
    t.image = tex
    links.new(t.outputs["Color"], p.inputs["Base Color"])
    tn = nodes.new("ShaderNodeTexImage")
    tn.image = nrm
    nm = nodes.new("ShaderNodeNormalMap")
    nm.inputs["Strength"].default_value = 1.0
    links.new(tn.outputs["Color"], nm.inputs["Color"])
    links.new(nm.outputs["Normal"], p.inputs["Normal"])
    add_quad("plane", (-1, -1, 0), (2, 0, 0), (0, 2, 0), m)
    add_quad("light", (-1.5, -0.5, 2.0), (0, 1, 0), (1, 0, 0), principled("light", (0, 0, 0), emission=(1, 1, 1), strength=12.0))
    add_camera((0, -2.2, 1.9), (48, 0, 0))
    black_world()


def hdr():
    w, h = 128, 64
    sky = []
    for y in range(h):  # Blender's rows start at the bottom: y = 0 is the nadir
        for x in range(w):
            elevation = (y + 0.5) / h * math.pi - math.pi / 2
            azimuth = (x + 0.5) / w * 2 * math.pi
            if elevation > 0:
                c = [0.35 + 0.4 * (1 - elevation / (math.pi / 2)), 0.5 + 0.3 * (1 - elevation / (math.pi / 2)), 0.9]
            else:
                c = [0.12, 0.1, 0.08]
            # A warm sun patch at elevation 35, azimuth 60 degrees, and a dimmer cool one opposite.
            if abs(elevation - math.radians(35)) < 0.12 and abs(azimuth - math.radians(60)) < 0.16:
                c = [60.0, 50.0, 35.0]
            if abs(elevation - math.radians(20)) < 0.1 and abs(azimuth - math.radians(240)) < 0.2:
                c = [2.0, 4.0, 9.0]
            sky += [*c, 1.0]
    img = image("sky", w, h, sky, os.path.join(OUT, "sky.exr"), float_buffer=True)
    world = bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    env = nodes.new("ShaderNodeTexEnvironment")
    env.image = img
    mapping = nodes.new("ShaderNodeMapping")
    mapping.inputs["Rotation"].default_value = (0, 0, math.radians(30))
    coord = nodes.new("ShaderNodeTexCoord")
    links.new(coord.outputs["Generated"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], env.inputs["Vector"])
    links.new(env.outputs["Color"], nodes["Background"].inputs["Color"])
    nodes["Background"].inputs["Strength"].default_value = 1.0
    add_sphere("sphere", principled("sphere", (0.8, 0.8, 0.8)), 0.5, (0, 0, 0.5))
    add_quad("floor", (-2, -2, 0), (4, 0, 0), (0, 4, 0), principled("floor", (0.5, 0.45, 0.4)))
    add_camera((2.4, -2.4, 1.6), (72, 0, 45))
    return 30.0  # the Mapping node's Z rotation, degrees


def odd():
    cube_mat = bpy.data.materials.new("toon")
    cube_mat.use_nodes = True
    nodes = cube_mat.node_tree.nodes
    toon = nodes.new("ShaderNodeBsdfToon")
    cube_mat.node_tree.links.new(toon.outputs["BSDF"], nodes["Material Output"].inputs["Surface"])
    add_block("cube", cube_mat, (1, 1, 1), 0, (0, 0, 0.5))
    glass = principled("glass", (1, 1, 1), specular=0.5, roughness=0.1)
    glass.node_tree.nodes["Principled BSDF"].inputs["Transmission"].default_value = 1.0
    add_block("glass", glass, (0.5, 0.5, 0.5), 0, (1.2, 0, 0.25))
    floor = add_quad("floor", (-3, -3, 0), (6, 0, 0), (0, 6, 0), principled("floor", (0.5, 0.5, 0.5)))
    hair = floor.modifiers.new("hair", "PARTICLE_SYSTEM")
    hair.particle_system.settings.type = "HAIR"
    hair.particle_system.settings.count = 10
    vol = bpy.data.volumes.new("fog")
    vol_ob = bpy.data.objects.new("fog", vol)
    scene.collection.objects.link(vol_ob)
    sun = bpy.data.lights.new("sun", "SUN")
    sun.energy = 3.0
    sun_ob = bpy.data.objects.new("sun", sun)
    sun_ob.rotation_euler = (math.radians(30), 0, math.radians(20))
    scene.collection.objects.link(sun_ob)
    add_camera((4, -4, 3), (65, 0, 45))
    black_world()


def lights(spot):
    """Diffuse floor and walls lit by Blender lights only: point, sun and a square area light (or a spot alone)."""
    add_quad("floor", (-2, -2, 0), (4, 0, 0), (0, 4, 0), principled("floor", (0.7, 0.7, 0.7)))
    add_quad("back", (-2, 2, 0), (4, 0, 0), (0, 0, 3), principled("back", (0.6, 0.5, 0.4)))
    add_quad("left", (-2, -2, 0), (0, 4, 0), (0, 0, 3), principled("left", (0.3, 0.5, 0.6)))

    def light(kind, name, location, rotation=(0, 0, 0), **props):
        data = bpy.data.lights.new(name, kind)
        for k, v in props.items():
            setattr(data, k, v)
        ob = bpy.data.objects.new(name, data)
        ob.location, ob.rotation_euler = location, tuple(math.radians(a) for a in rotation)
        scene.collection.objects.link(ob)

    if spot:
        light("SPOT", "spot", (0.3, 0.2, 2.5), (20, 0, 0), energy=300.0, spot_size=math.radians(70), spot_blend=0.3, shadow_soft_size=0.0)
    else:
        light("POINT", "point", (-1.0, 0.5, 1.5), energy=80.0, color=(1.0, 0.8, 0.6), shadow_soft_size=0.0)
        light("SUN", "sun", (0, 0, 5), (40, 0, 160), energy=1.5, angle=0.0)
        # Above and behind the camera's view, and out of the sun's way: symphong's quad is a surface (seen by the camera,
        # casting shadows), Cycles' area light is not.
        light("AREA", "area", (1.0, -3.0, 3.4), (50, 0, 0), energy=60.0, size=0.8, color=(0.6, 0.8, 1.0))
    add_camera((0.5, -4.5, 2.4), (68, 0, 5))
    black_world()


builders = {"cornell-diffuse": lambda: cornell(False), "cornell-glossy": lambda: cornell(True), "textured": textured, "hdr": hdr,
            "odd": odd, "lights": lambda: lights(False), "spot": lambda: lights(True)}
if NAME not in builders:
    sys.exit(f"make_scenes.py: unknown scene {NAME} (one of {', '.join(builders)})")
rotation = builders[NAME]()
bpy.context.view_layer.update()

r = scene.render
r.resolution_x, r.resolution_y, r.resolution_percentage = WIDTH, HEIGHT, 100
r.image_settings.file_format = "OPEN_EXR"
r.image_settings.color_depth = "32"
r.image_settings.color_mode = "RGB"
r.use_file_extension = True
import addon_utils  # noqa: E402

# With the add-on found (BLENDER_USER_SCRIPTS), the scene is saved set to render with it at SPP; without it, the
# settings are stored as the ID property its settings group reads, and -E SYMPHONG picks the engine.
if addon_utils.enable("symphong_blender", default_set=False) is not None and hasattr(scene, "symphong"):
    r.engine = "SYMPHONG"
    scene.symphong.spp = SPP
else:
    scene["symphong"] = {"spp": SPP}
scene.view_settings.view_transform = "Standard"
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(OUT, NAME + ".blend"))

# The glTF export (+Y up, cameras), as a user would make it.
addon_utils.enable("io_scene_gltf2", default_set=True)
bpy.ops.export_scene.gltf(filepath=os.path.join(OUT, NAME + ".glb"), export_format="GLB", export_cameras=True, export_lights=True)
if NAME == "hdr":
    with open(os.path.join(OUT, "hdr.json"), "w") as f:
        # Blender's equirectangular lookup is symphong's lat-long at rotation 90 in the +Y-up frame; the Mapping
        # node turns the lookup vector by +30 degrees about Z, which adds 30 (docs/blender.md).
        json.dump({"mesh": "hdr.glb", "environment": {"map": "sky.exr", "rotation": 90.0 + rotation}}, f, indent=1)

if NAME in {"cornell-diffuse", "hdr", "lights", "spot"}:
    # The Cycles twin: Diffuse BSDF for every Principled (specular 0: symphong's rho_d = base colour), emitters
    # from their front faces only (symphong's emitters are one-sided), Cycles settings of docs/validation.md.
    for m in bpy.data.materials:
        nodes, links = m.node_tree.nodes, m.node_tree.links
        p = nodes.get("Principled BSDF")
        if p is None:
            continue
        out = nodes["Material Output"]
        emission = p.inputs["Emission Strength"].default_value * Vector(p.inputs["Emission"].default_value[:3])
        if emission.length > 0:
            e = nodes.new("ShaderNodeEmission")
            e.inputs["Color"].default_value = (*p.inputs["Emission"].default_value[:3], 1)
            e.inputs["Strength"].default_value = p.inputs["Emission Strength"].default_value
            geo, mix, black = nodes.new("ShaderNodeNewGeometry"), nodes.new("ShaderNodeMixShader"), nodes.new("ShaderNodeBsdfDiffuse")
            black.inputs["Color"].default_value = (0, 0, 0, 1)
            links.new(geo.outputs["Backfacing"], mix.inputs["Fac"])
            links.new(e.outputs["Emission"], mix.inputs[1])
            links.new(black.outputs["BSDF"], mix.inputs[2])
            links.new(mix.outputs["Shader"], out.inputs["Surface"])
        else:
            d = nodes.new("ShaderNodeBsdfDiffuse")
            d.inputs["Color"].default_value = p.inputs["Base Color"].default_value
            d.inputs["Roughness"].default_value = 0.0
            links.new(d.outputs["BSDF"], out.inputs["Surface"])
        nodes.remove(p)
    r.engine = "CYCLES"
    c = scene.cycles
    c.device, c.samples, c.use_adaptive_sampling, c.use_denoising = "CPU", SPP, False, False
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = c.transparent_max_bounces = 16
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold, c.blur_glossy = 0.0, 0.0
    c.pixel_filter_type, c.filter_width = "BOX", 1.0
    c.seed = 1
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(OUT, NAME + "-cycles.blend"))
print(f"make_scenes: {NAME} written to {OUT}")
