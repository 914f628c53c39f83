# Peer benchmark: Blender 3.4 rigid-body (Bullet) bake.
#
# Usage:
#   blender -b --factory-startup --python-exit-code 1 \
#       --python blender_cubes.py -- N_PIECES FRAMES OUT_JSON [sleep]
#
# Scene: N_PIECES active rigid bodies, 0.5 m cubes (8-vertex meshes, collision
# shape CONVEX_HULL, margin default), laid out as a 10 x 10 x ceil(N/100) grid
# (0.55 m pitch, i.e. 5 cm gaps; bottom layer 5 cm above the ground), with a
# small seeded random rotation/offset so the stack actually settles and
# collides; a passive BOX ground (40 m x 40 m x 1 m slab). Blender's default
# is never to deactivate a body; with `sleep` the bodies deactivate below
# Bullet's default thresholds (0.8 m/s, 1 rad/s) for Bullet's 2 s, which
# Blender does not expose (dawnforge: 0.1 m/s, 0.2 rad/s for 0.4 s).
# rigidbody_world: substeps_per_frame=4, solver_iterations=10, 30 fps,
# scene + point-cache frame range 1..FRAMES.
# Timed: bpy.ops.ptcache.bake_all(bake=True) alone (time.perf_counter).
#
# Prints one JSON line {"tool":"blender-rigidbody","pieces":..,"frames":..,
# "seconds":..,...} and writes the same object to OUT_JSON ("-" = don't).

import json
import math
import random
import os
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_scene import add_rigid_bodies, box_mesh, empty_scene, report, rigid_body_world  # noqa: E402
from mathutils import Vector


def parse_args():
    argv = sys.argv
    argv = argv[argv.index("--") + 1:] if "--" in argv else []
    if len(argv) < 2 or (len(argv) > 3 and argv[3] != "sleep"):
        sys.stderr.write("usage: ... -- N_PIECES FRAMES [OUT_JSON|-] [sleep]\n")
        sys.exit(2)
    return int(argv[0]), int(argv[1]), (argv[2] if len(argv) > 2 else "-"), len(argv) > 3


def main():
    n, frames, out_json, sleep = parse_args()
    rng = random.Random(12345)
    scene = empty_scene(frames, 30)
    coll = scene.collection

    # ground: passive box slab, top face at z = 0
    ground = bpy.data.objects.new("ground", box_mesh("ground", 0.5))
    ground.scale = (40.0, 40.0, 1.0)
    ground.location = (0.0, 0.0, -0.5)
    coll.objects.link(ground)

    size = 0.5
    pitch = 0.55
    side = 10
    layers = int(math.ceil(n / float(side * side)))
    shared = box_mesh("piece", size / 2.0)  # shared mesh data; each object is its own body
    pieces = []
    for i in range(n):
        layer, rem = divmod(i, side * side)
        iy, ix = divmod(rem, side)
        ob = bpy.data.objects.new("piece_%04d" % i, shared)
        ob.location = (
            (ix - (side - 1) / 2.0) * pitch + rng.uniform(-0.02, 0.02),
            (iy - (side - 1) / 2.0) * pitch + rng.uniform(-0.02, 0.02),
            0.05 + size / 2.0 + layer * pitch,
        )
        ob.rotation_euler = (rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05),
                             rng.uniform(-0.3, 0.3))
        coll.objects.link(ob)
        pieces.append(ob)

    view_layer = bpy.context.view_layer
    view_layer.update()

    # rigid body world + bodies (setup is not timed)
    rbw = rigid_body_world(scene, frames, substeps=4, iterations=10)
    add_rigid_bodies(pieces, 'ACTIVE')
    for ob in pieces:
        rb = ob.rigid_body
        rb.collision_shape = 'CONVEX_HULL'
        rb.mass = 1.0
        rb.use_deactivation = sleep
        rb.deactivate_linear_velocity = 0.8
        rb.deactivate_angular_velocity = 1.0

    add_rigid_bodies([ground], 'PASSIVE')
    ground.rigid_body.collision_shape = 'BOX'

    n_bodies = len(rbw.collection.objects) if rbw.collection else 0
    z0 = [ob.matrix_world.translation.z for ob in pieces]

    t0 = time.perf_counter()
    ret = bpy.ops.ptcache.bake_all(bake=True)
    seconds = time.perf_counter() - t0

    # sanity: cache baked, bodies actually moved
    scene.frame_set(frames)
    z1 = [ob.matrix_world.translation.z for ob in pieces]
    dz = [a - b for a, b in zip(z0, z1)]
    pc = rbw.point_cache

    out = {
        "tool": "blender-rigidbody",
        "pieces": n,
        "frames": frames,
        "seconds": round(seconds, 4),
        "ms_per_frame": round(1000.0 * seconds / max(frames, 1), 3),
        "bodies_in_world": n_bodies,
        "substeps_per_frame": rbw.substeps_per_frame,
        "solver_iterations": rbw.solver_iterations,
        "deactivation": sleep,
        "fps": scene.render.fps,
        "cache_baked": bool(pc.is_baked),
        "cache_frames": [pc.frame_start, pc.frame_end],
        "mean_drop_m": sum(dz) / len(dz) if dz else 0.0,
        "min_z_end": min(z1) if z1 else None,
        "operator_result": sorted(ret),
        "blender": bpy.app.version_string,
    }
    report(out, out_json)


if __name__ == "__main__":
    main()
