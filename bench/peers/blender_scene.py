"""Shared by the Blender peer scripts (blender_glued.py, blender_cubes.py): the scene they both
build (an empty scene, box meshes, the rigid-body world, bodies added in one operator call) and
the report, one JSON line on a line of its own (Blender's operator reports may leave stdout
mid-line), also written to OUT_JSON unless it is "-"."""
import json
import sys

import bpy


def empty_scene(frames, fps):
    """The current scene with every object removed, playing frames 1..frames at fps."""
    scene = bpy.context.scene
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    scene.render.fps = fps
    scene.render.fps_base = 1.0
    scene.frame_start = 1
    scene.frame_end = frames
    scene.frame_set(1)
    return scene


def box_mesh(name, half):
    """An axis-aligned cube mesh of half-size `half`, its six faces as quads."""
    h = half
    verts = [(-h, -h, -h), (h, -h, -h), (h, h, -h), (-h, h, -h), (-h, -h, h), (h, -h, h), (h, h, h), (-h, h, h)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    me = bpy.data.meshes.new(name)
    me.from_pydata(verts, [], faces)
    me.update()
    return me


def rigid_body_world(scene, frames, substeps, iterations, split_impulse=None):
    """The scene's rigid-body world, baking frames 1..frames; split impulse left as Blender's
    default unless given."""
    if scene.rigidbody_world is None:
        bpy.ops.rigidbody.world_add()
    rbw = scene.rigidbody_world
    rbw.enabled = True
    rbw.substeps_per_frame = substeps
    rbw.solver_iterations = iterations
    if split_impulse is not None:
        rbw.use_split_impulse = split_impulse
    rbw.time_scale = 1.0
    rbw.point_cache.frame_start = 1
    rbw.point_cache.frame_end = frames
    return rbw


def add_rigid_bodies(objects, kind):
    """Makes every object a rigid body of `kind` ('ACTIVE' or 'PASSIVE') in one operator call
    (one call per object re-evaluates the scene each time)."""
    view_layer = bpy.context.view_layer
    bpy.ops.object.select_all(action='DESELECT')
    for ob in objects:
        ob.select_set(True)
    view_layer.objects.active = objects[0]
    bpy.ops.rigidbody.objects_add(type=kind)


def report(out, out_json):
    line = json.dumps(out)
    if out_json and out_json != "-":
        with open(out_json, "w") as f:
            f.write(line + "\n")
    sys.stdout.write("\n")
    sys.stderr.flush()
    sys.stdout.flush()
    print(line)
    sys.stdout.flush()
