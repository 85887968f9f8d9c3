"""Run inside Blender (the add-on enabled, the module importable) on a saved scene: converts it with the
add-on under several resolutions and sensor fits, exports each with Blender's glTF exporter, loads that with
symphong's glTF reader, and prints one JSON line per variant (prefixed "INSPECT ") with both cameras, both
material lists and both triangle counts, for tests/blender/test_blender_addon.py to compare.

    blender -b scene.blend --python-use-system-env --addons symphong_blender --python inspect_conversion.py -- OUTDIR
"""
import json
import os
import sys

import bpy
import symphong
from symphong_blender import convert

out = sys.argv[sys.argv.index("--") + 1]
scene = bpy.context.scene
cam = scene.camera.data
variants = [(160, 90, "AUTO"), (90, 160, "AUTO"), (160, 90, "VERTICAL"), (90, 160, "HORIZONTAL")]
for i, (w, h, fit) in enumerate(variants):
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = w, h, 100
    cam.sensor_fit, cam.sensor_height = fit, 20.0
    bpy.context.view_layer.update()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    kwargs, reports = convert.convert(depsgraph, w, h)
    built = symphong.Scene.from_arrays(**kwargs)
    path = os.path.join(out, f"variant{i}.glb")
    bpy.ops.export_scene.gltf(filepath=path, export_format="GLB", export_cameras=True, export_lights=True)
    read = symphong.load_scene(path)
    print("INSPECT " + json.dumps({
        "variant": [w, h, fit],
        "camera": [built.camera, read.camera],
        "materials": [built.materials, read.materials],
        "triangles": [built.triangle_count, read.triangle_count],
        "bounds": [built.bounds, read.bounds],
        "reports": reports,
    }))
