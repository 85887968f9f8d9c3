"""Glossy Principled materials of known parameters, written by Blender's own FBX and OBJ exporters.

    blender -b --factory-startup --python-exit-code 1 -P scripts/blender-roundtrip/make_glossy.py -- OUTDIR

(Blender 3.4.1 from Debian 12; OUTDIR = tests/data/blender/glossy.) Never run in CI: the files it writes are
committed, and tests/test_assimp.cpp (Assimp.BlenderGlossyMaterialsAreTheirPrincipledParameters) checks that
symphong reads each material as the Phong parameters computed by hand from the Principled numbers below.

Why: the round trip of tests/data/blender has one glossy material, of Specular 0.5 (F0 0.04) on a scene lit
mostly diffusely, so an error of Blender's FBX conventions in the specular part changes its render by less
than its tolerance. Here every material is glossy and the Principled numbers differ from material to
material, so a wrong factor in the conversion of any of them (Specular, Roughness, Metallic) shows.

The scene (Blender's coordinates, +Z up, metres): one 1 x 1 m quad per material, side by side along X at
z = 0, facing +Z; no camera, no light (symphong frames and lights such a file itself). MATERIALS below: each
a Principled BSDF with Base Color, Specular, Roughness and Metallic as given, everything else Blender's
default.

Exports: scene.fbx (`export_scene.fbx`, bake_anim False), scene.obj + scene.mtl (`wm.obj_export`), every other
option Blender's default. truth.json: the materials' Principled numbers and the versions.

What the exporters write, from their sources (io_scene_fbx 4.37.1 export_fbx_bin.py fbx_data_material_elements;
the C++ OBJ exporter's MTL writer): FBX SpecularColor = Base Color, SpecularFactor = Specular / 2,
ShininessExponent = ((1 - Roughness) x 10)^2, ReflectionFactor = Metallic; MTL Ks = Specular, Ns = (1 -
Roughness)^2 x 1000, Pm = Metallic. symphong's reading (scene/exporter_conventions.h): F0 = 0.08 x Specular,
rho_s = F0 (1 - Metallic) + Base x Metallic, rho_d = Base (1 - Metallic) (1 - F0), n = 2 / alpha^2 - 2 with
alpha = Roughness^2.
"""
import json
import os
import sys

import addon_utils
import bpy

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
OUT = os.path.abspath(argv[0] if argv else "out/blender-glossy")
os.makedirs(OUT, exist_ok=True)

# name: (Base Color, Specular, Roughness, Metallic). Roughness at least 0.2 so that n stays below
# symphong's cap of 1e4; no material reflects more than 1 (rho_d + rho_s <= 1 in every channel).
MATERIALS = {
    "shiny": ((0.8, 0.3, 0.1), 1.0, 0.3, 0.0),
    "satin": ((0.2, 0.5, 0.7), 0.25, 0.5, 0.4),
    "metal": ((0.9, 0.8, 0.6), 0.5, 0.2, 1.0),
    "rough": ((0.5, 0.45, 0.4), 0.75, 0.8, 0.0),
}

for collection in (bpy.data.objects, bpy.data.meshes, bpy.data.materials, bpy.data.cameras, bpy.data.lights, bpy.data.images):
    for block in list(collection):
        collection.remove(block)
scene = bpy.context.scene

for i, (name, (base, specular, roughness, metallic)) in enumerate(MATERIALS.items()):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    p = m.node_tree.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (*base, 1.0)
    p.inputs["Specular"].default_value = specular
    p.inputs["Roughness"].default_value = roughness
    p.inputs["Metallic"].default_value = metallic
    me = bpy.data.meshes.new(name)
    x = 1.5 * i
    me.from_pydata([(x, 0, 0), (x + 1, 0, 0), (x + 1, 1, 0), (x, 1, 0)], [], [(0, 1, 2, 3)])
    me.materials.append(m)
    me.update()
    ob = bpy.data.objects.new(name, me)
    scene.collection.objects.link(ob)
bpy.context.view_layer.update()

addon_utils.enable("io_scene_fbx", default_set=True)
print("make_glossy:", bpy.ops.export_scene.fbx(filepath=os.path.join(OUT, "scene.fbx"), bake_anim=False))
print("make_glossy:", bpy.ops.wm.obj_export(filepath=os.path.join(OUT, "scene.obj")))


def addon_version(module):
    for mod in addon_utils.modules():
        if mod.__name__ == module:
            return ".".join(str(v) for v in mod.bl_info.get("version", ()))
    return None


truth = {
    "blender": bpy.app.version_string,
    "exporters": {"io_scene_fbx": addon_version("io_scene_fbx")},
    "materials": {name: {"base_color": list(base), "specular": s, "roughness": r, "metallic": mt}
                  for name, (base, s, r, mt) in MATERIALS.items()},
}
with open(os.path.join(OUT, "truth.json"), "w") as f:
    json.dump(truth, f, indent=1)
    f.write("\n")
