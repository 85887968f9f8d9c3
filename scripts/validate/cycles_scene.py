"""Builds a scene exported by export_scene.py in Blender and renders it with Cycles to a linear 32-bit
float EXR. Runs inside Blender:

    blender -b --factory-startup -P cycles_scene.py -- SCENE.json OUT.exr WIDTH HEIGHT SAMPLES SEED THREADS [BOUNCES]

BOUNCES (default 64) is Cycles' max bounces: 0 gives direct light only (symphong's --max-depth 1).
A tenth argument `no-light-sampling` turns off Cycles' sampling of the emitters (their materials'
"Multiple Importance Sample"): light is then found by BSDF sampling alone (for the investigation in
docs/validation.md).

The scene is rebuilt to match symphong exactly: the same triangles, in the same coordinates (no axis
conversion: camera and geometry share them); each material a Lambertian Diffuse BSDF (roughness 0)
plus, for emitters, an emission from the FRONT face only (Cycles emits from both faces unless told:
a Mix Shader on Geometry.Backfacing between the emission and a black one); a black world (or the
scene's constant environment); a pinhole camera with the same vertical field of view. Cycles: CPU,
no adaptive sampling, no denoising, 64 bounces of every kind, no clamping, light threshold 0, box
pixel filter 1 px wide (symphong's pixel model), standard view transform (the EXR holds scene-linear
values either way)."""
import json
import math
import sys

import bpy
from mathutils import Matrix, Vector


def build(d, light_sampling=True):
    """Builds the exported scene `d` (export_scene.py's JSON) in an empty Blender scene and returns it."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene

    mesh = bpy.data.meshes.new("symphong")
    mesh.from_pydata([tuple(p) for p in d["positions"]], [], [tuple(t) for t in d["triangles"]])
    mesh.update()
    if len(mesh.polygons) != len(d["triangles"]):
        sys.exit(f"cycles_scene: Blender kept {len(mesh.polygons)} of {len(d['triangles'])} triangles")
    obj = bpy.data.objects.new("symphong", mesh)
    scene.collection.objects.link(obj)

    for m in d["materials"]:
        mat = bpy.data.materials.new(m["name"])
        mat.use_nodes = True
        nodes, links = mat.node_tree.nodes, mat.node_tree.links
        nodes.clear()
        out = nodes.new("ShaderNodeOutputMaterial")
        diffuse = nodes.new("ShaderNodeBsdfDiffuse")
        diffuse.inputs["Color"].default_value = (*m["rho_d"], 1.0)
        diffuse.inputs["Roughness"].default_value = 0.0
        if max(m["emission"]) > 0:
            emit = nodes.new("ShaderNodeEmission")
            emit.inputs["Color"].default_value = (*m["emission"], 1.0)
            emit.inputs["Strength"].default_value = 1.0
            black = nodes.new("ShaderNodeEmission")
            black.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
            black.inputs["Strength"].default_value = 0.0
            geometry = nodes.new("ShaderNodeNewGeometry")
            mix = nodes.new("ShaderNodeMixShader")
            links.new(geometry.outputs["Backfacing"], mix.inputs["Fac"])
            links.new(emit.outputs["Emission"], mix.inputs[1])   # front face
            links.new(black.outputs["Emission"], mix.inputs[2])  # back face
            add = nodes.new("ShaderNodeAddShader")
            links.new(diffuse.outputs["BSDF"], add.inputs[0])
            links.new(mix.outputs["Shader"], add.inputs[1])
            links.new(add.outputs["Shader"], out.inputs["Surface"])
        else:
            links.new(diffuse.outputs["BSDF"], out.inputs["Surface"])
        if not light_sampling:
            if hasattr(mat.cycles, "sample_as_light"):
                mat.cycles.sample_as_light = False  # Blender <= 3.4
            else:
                mat.cycles.emission_sampling = "NONE"  # Blender >= 3.5
        obj.data.materials.append(mat)
    for poly, material in zip(mesh.polygons, d["material"]):
        poly.material_index = material
        poly.use_smooth = False

    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    env = d["environment"]
    background.inputs["Color"].default_value = (*env, 1.0)
    background.inputs["Strength"].default_value = 1.0 if max(env) > 0 else 0.0
    scene.world = world

    c = d["camera"]
    position, target, up = Vector(c["position"]), Vector(c["target"]), Vector(c["up"])
    forward = (target - position).normalized()
    right = forward.cross(up).normalized()
    true_up = right.cross(forward)
    camera_data = bpy.data.cameras.new("camera")
    camera_data.type = "PERSP"
    camera_data.sensor_fit = "VERTICAL"
    camera_data.angle_y = math.radians(c["fov_y"])
    distance = (target - position).length
    camera_data.clip_start = 1e-4 * distance
    camera_data.clip_end = 1e4 * distance
    camera = bpy.data.objects.new("camera", camera_data)
    # Blender cameras look along their local -Z with +Y up: columns right, up, -forward.
    rotation = Matrix(((right.x, true_up.x, -forward.x), (right.y, true_up.y, -forward.y), (right.z, true_up.z, -forward.z)))
    camera.matrix_world = Matrix.Translation(position) @ rotation.to_4x4()
    scene.collection.objects.link(camera)
    scene.camera = camera
    return scene


def configure(scene, width, height, samples, seed, threads, bounces=64):
    """Cycles settings for a render that matches symphong's pixel model (see the module's text)."""
    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x, r.resolution_y, r.resolution_percentage = width, height, 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.use_motion_blur = False
    r.film_transparent = False
    r.threads_mode = "FIXED"
    r.threads = threads
    cy = scene.cycles
    cy.device = "CPU"
    cy.samples = samples
    cy.seed = seed
    cy.use_animated_seed = False
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.max_bounces = cy.diffuse_bounces = cy.glossy_bounces = cy.transmission_bounces = cy.transparent_max_bounces = bounces
    cy.volume_bounces = 0
    cy.min_light_bounces = 0
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.light_sampling_threshold = 0.0
    cy.blur_glossy = 0.0
    cy.pixel_filter_type = "BOX"
    cy.filter_width = 1.0
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    image = r.image_settings
    image.file_format = "OPEN_EXR"
    image.color_mode = "RGB"
    image.color_depth = "32"
    image.exr_codec = "ZIP"
    r.use_file_extension = False


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    desc_path, out_path = args[0], args[1]
    width, height, samples, seed, threads = (int(a) for a in args[2:7])
    bounces = int(args[7]) if len(args) > 7 else 64
    light_sampling = not (len(args) > 8 and args[8] == "no-light-sampling")
    d = json.load(open(desc_path))
    print(f"cycles_scene: Blender {bpy.app.version_string}, scene {d['name']}, {len(d['triangles'])} triangles")
    scene = build(d, light_sampling)
    configure(scene, width, height, samples, seed, threads, bounces)
    scene.render.filepath = out_path
    bpy.ops.render.render(write_still=True)
    print(f"cycles_scene: wrote {out_path}")


if __name__ == "__main__":
    main()
