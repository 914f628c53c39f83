# Runs inside Blender: imports a GLB written by `dawnforge anim` with Blender's own glTF importer
# (default options) at the simulation's frame rate, plays its animation frame by frame and
# writes every mesh object's world matrix at every frame as JSON. It judges nothing;
# anim_compare.py compares the matrices with transforms.bin.
#
#   blender -b --factory-startup --python-exit-code 1 --python anim_play.py -- FILE.glb FPS FRAMES OUT.json
import json
import sys

import numpy

if "bool" not in numpy.__dict__:  # Debian's Blender 3.4 importer and NumPy >= 1.24 (import_report.py)
    numpy.bool = bool

import bpy  # noqa: E402

glb, fps, frames, out = sys.argv[sys.argv.index("--") + 1:]
scene = bpy.context.scene
# The importer turns key times into frames at the scene's rate: at the simulation's, key k
# of the simulation lands on frame k.
scene.render.fps, scene.render.fps_base = int(round(float(fps))), 1.0
for obj in list(bpy.data.objects):
    bpy.data.objects.remove(obj)
bpy.ops.import_scene.gltf(filepath=glb)
objects = sorted((o for o in scene.objects if o.type == "MESH"), key=lambda o: o.name)
matrices = {}
for k in range(int(frames)):
    scene.frame_set(k)
    for o in objects:
        matrices.setdefault(o.name, []).append([list(row) for row in o.matrix_world])
json.dump({"fps": scene.render.fps, "matrices": matrices}, open(out, "w"))
