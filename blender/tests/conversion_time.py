"""Times the add-on's conversion of a mesh of about a million triangles (run inside Blender, the add-on enabled):

    blender -b --factory-startup --python-use-system-env --addons symphong_blender --python blender/tests/conversion_time.py [-- REPEATS]

A grid of 708 x 708 quads (1,000,000 triangles after triangulation; smooth shading, so per-corner normals are
handed over too, and UVs) with one Principled material. Prints, per repeat, the seconds of convert.convert
(depsgraph -> arrays), of symphong.Scene.from_arrays (arrays -> scene, checks included) and their sum, as CPU
time of the process (what the conversion costs; a machine busy with other work stretches wall time, not this)
and as wall time: the add-on's overhead before the first pass (the acceleration structure, built on the first pass, is the
renderer's own work and the same for a file). Each repeat converts afresh (no cache carried over).
"""
import sys
import time

import bpy
import symphong
from symphong_blender import convert

repeats = int(sys.argv[sys.argv.index("--") + 1]) if "--" in sys.argv else 5
for ob in list(bpy.data.objects):
    bpy.data.objects.remove(ob)
bpy.ops.mesh.primitive_grid_add(x_subdivisions=708, y_subdivisions=708, size=4)
grid = bpy.context.active_object
bpy.ops.object.shade_smooth()
mat = bpy.data.materials.new("grey")
mat.use_nodes = True
grid.data.materials.append(mat)
cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
cam.location = (0, -6, 4)
cam.rotation_euler = (0.9, 0, 0)
bpy.context.scene.collection.objects.link(cam)
bpy.context.scene.camera = cam
depsgraph = bpy.context.evaluated_depsgraph_get()
for i in range(repeats):
    t0, c0 = time.perf_counter(), time.process_time()
    kwargs, reports = convert.convert(depsgraph, 640, 480)
    t1, c1 = time.perf_counter(), time.process_time()
    scene = symphong.Scene.from_arrays(**kwargs)
    t2, c2 = time.perf_counter(), time.process_time()
    print(f"CONVERSION triangles={scene.triangle_count} cpu: convert={c1 - c0:.3f} from_arrays={c2 - c1:.3f} total={c2 - c0:.3f}"
          f" wall: convert={t1 - t0:.3f} from_arrays={t2 - t1:.3f} total={t2 - t0:.3f}")
