# Peer benchmark: Blender 3.4's rigid-body bake (Bullet) on the bodies `dawnforge simulate` simulates.
#
# Usage:
#   blender -b --factory-startup --python-exit-code 1 \
#       --python blender_glued.py -- FRACTURE_DIR FRAMES ITERATIONS SUBSTEPS [OUT_JSON|-]
#
# Reads FRACTURE_DIR/fragments.glb and FRACTURE_DIR/fracture.json (ARCHITECTURE.md 4.1, 4.2) with
# plain Python (struct + json; Blender's glTF importer is not used). Each piece is a GLB node whose
# translation is its centre of mass, with mesh positions relative to it. dawnforge is Y-up, Blender
# Z-up: (x, y, z)_dawnforge -> (x, -z, y)_blender.
#
# Scene, following dawnforge's defaults (`simulate` options, sim/src/rigidbody.cpp):
# - one ACTIVE rigid body per piece, origin at its centre of mass, mass from fracture.json,
#   collision shape CONVEX_HULL, friction 0.6, restitution 0.1, linear damping 0.02, angular
#   damping 0.05; deactivation on with Bullet's default sleeping thresholds (0.8 m/s, 1 rad/s,
#   for Bullet's 2 s, which Blender does not expose; Blender's default is never to sleep).
#   dawnforge's are tighter (0.1 m/s, 0.2 rad/s for 0.4 s), but with them Blender's jointed
#   sphere never sleeps and its bake takes three times as long: Blender gets its fastest;
# - collision hull as dawnforge builds it: the convex hull of the piece shrunk by the 0.01 m margin
#   (at most a quarter of the distance from its centroid to its nearest face) and cut down to 48
#   vertices by farthest-point sampling; the object's mesh is those points alone, and the body has
#   use_margin with collision_margin = the shrink, so Bullet adds back what was taken off
#   (Blender would otherwise embed its own 0.04 m margin);
# - a PASSIVE ground box (200 m x 200 m x 2 m) whose top is at the lowest point of the pieces,
#   friction 0.6, restitution 0.1 (dawnforge: a static plane there);
# - one FIXED rigid-body constraint per bond, on an Empty at the bond's centroid, between its two
#   pieces, disable_collisions, use_breaking with breaking_threshold = strength * area /
#   (fps * substeps): the bond's force limit as an impulse per substep (strength: the bond's own,
#   else 1e6 Pa, dawnforge's default --strength; no per-bond variation);
# - 30 fps, rigidbody_world substeps_per_frame = SUBSTEPS, solver_iterations = ITERATIONS,
#   split impulse on (as dawnforge), scene and point cache frames 1..FRAMES.
# Timed: bpy.ops.ptcache.bake_all(bake=True) alone (time.perf_counter); setup is not timed.
#
# Not the same as dawnforge: Bullet gives each body the inertia of its hull's bounding box in
# world axes (dawnforge: the piece's exact tensor, principal axes); no CCD (dawnforge sweeps a
# sphere per piece); a constraint breaks when any one of its six rows' impulse in a substep
# exceeds the threshold, the angular rows' N*m*s included, and the load it carries at rest counts
# (dawnforge breaks a bond on its principal stress above its rest stress, with the strength varied
# +-20 % per bond by the seed). And dawnforge solves no joints: a set of glued pieces is one
# compound body, fixed where it rests on the ground (sim.json glue.bodies, fixed_bodies), split
# when a bond breaks. The hull and dual hull are computed here in double precision with NumPy
# (bundled with Blender): bmesh.ops.convex_hull works in float and returns faces that are not
# supporting planes on a fracture piece's many coplanar points.
#
# Prints one JSON line {"tool": "blender-glued", "pieces", "bonds", "frames", "seconds", ...} with
# sanity figures: the mean and max drop of the pieces' centres (z at frame 1 minus z at the last
# frame), and, since Blender does not expose whether a constraint broke, "bonds_apart": how many
# bonds' two anchor points ended more than 5 mm apart or turned more than 2 degrees against each
# other (an estimate of the broken bonds; bench/peer_simulate.sh computes the same from dawnforge's
# transforms.bin). Writes the same object to OUT_JSON unless it is "-".

import json
import math
import os
import struct
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_scene import add_rigid_bodies, box_mesh, empty_scene, report, rigid_body_world  # noqa: E402
import numpy as np
from mathutils import Vector

FPS = 30
DEFAULT_STRENGTH = 1e6    # Pa, dawnforge simulate --strength
MARGIN = 0.01             # m, --margin
HULL_VERTICES = 48        # --hull-vertices
FRICTION, RESTITUTION = 0.6, 0.1
LINEAR_DAMPING, ANGULAR_DAMPING = 0.02, 0.05
APART_DISTANCE, APART_DEGREES = 0.005, 2.0


def parse_args():
    argv = sys.argv
    argv = argv[argv.index("--") + 1:] if "--" in argv else []
    if len(argv) < 4:
        sys.stderr.write("usage: ... -- FRACTURE_DIR FRAMES ITERATIONS SUBSTEPS [OUT_JSON|-]\n")
        sys.exit(2)
    return argv[0], int(argv[1]), int(argv[2]), int(argv[3]), (argv[4] if len(argv) > 4 else "-")


def to_blender(p):  # dawnforge Y-up -> Blender Z-up
    return (p[0], -p[2], p[1])


def read_glb(path):
    """{node name: (translation, [positions relative to it])} in dawnforge's axes."""
    with open(path, "rb") as f:
        data = f.read()
    magic, version, _ = struct.unpack_from("<III", data, 0)
    if magic != 0x46546C67 or version != 2:
        raise ValueError(f"{path}: not a glTF 2 binary")
    gltf, blob, at = None, b"", 12
    while at < len(data):
        length, kind = struct.unpack_from("<II", data, at)
        chunk = data[at + 8:at + 8 + length]
        if kind == 0x4E4F534A:
            gltf = json.loads(chunk)
        elif kind == 0x004E4942:
            blob = chunk
        at += 8 + length
    sizes = {5126: ("f", 4)}
    counts = {"VEC3": 3}

    def positions(index):
        acc = gltf["accessors"][index]
        fmt, size = sizes[acc["componentType"]]
        n = counts[acc["type"]]
        view = gltf["bufferViews"][acc["bufferView"]]
        stride = view.get("byteStride") or size * n
        base = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
        return [struct.unpack_from("<" + fmt * n, blob, base + i * stride) for i in range(acc["count"])]

    out = {}
    for node in gltf["nodes"]:
        if "mesh" not in node:
            continue
        pts = []
        for prim in gltf["meshes"][node["mesh"]]["primitives"]:
            pts += positions(prim["attributes"]["POSITION"])
        out[node["name"]] = (tuple(node.get("translation", (0.0, 0.0, 0.0))), pts)
    return out


def simple_loop(step):
    """Whether the directed edges {start: end} form one closed loop through every start."""
    if len(step) < 3:
        return False
    first = next(iter(step))
    at, n = first, 0
    while True:
        at = step.get(at)
        n += 1
        if at is None or n > len(step):
            return False
        if at == first:
            return n == len(step)


def merge_close(points, rel_tol):
    """points (n x 3) with those within about rel_tol x their extent of an earlier one left out."""
    extent = float(np.max(points.max(axis=0) - points.min(axis=0))) or 1.0
    keys = np.round(points / (rel_tol * extent)).astype(np.int64)
    _, first = np.unique(keys, axis=0, return_index=True)
    return points[np.sort(first)]


def convex_hull(points, rel_eps=1e-10):
    """The convex hull of points (an n x 3 array) in double precision: incremental, with a point
    counted as beyond a face only when it is more than rel_eps x the points' extent above it.
    Returns (outward unit normals F x 3, offsets F, triangles F x 3), or None when the points are
    flat. (bmesh.ops.convex_hull works in float and on a fracture piece's many coplanar and
    nearly collinear points it can return faces that are not supporting planes.)"""
    pts = np.unique(np.asarray(points, dtype=np.float64), axis=0)
    if len(pts) < 4:
        return None
    extent = float(np.max(pts.max(axis=0) - pts.min(axis=0)))
    eps = rel_eps * max(extent, 1e-30)
    # a first tetrahedron from extreme points
    i0 = int(np.argmin(pts[:, 0]))
    i1 = int(np.argmax(np.linalg.norm(pts - pts[i0], axis=1)))
    d01 = pts[i1] - pts[i0]
    if np.linalg.norm(d01) <= eps:
        return None
    i2 = int(np.argmax(np.linalg.norm(np.cross(pts - pts[i0], d01), axis=1)))
    nrm = np.cross(d01, pts[i2] - pts[i0])
    if np.linalg.norm(nrm) <= eps * np.linalg.norm(d01):
        return None
    nrm /= np.linalg.norm(nrm)
    off = (pts - pts[i0]) @ nrm
    i3 = int(np.argmax(np.abs(off)))
    if abs(off[i3]) <= eps:
        return None
    inside = (pts[i0] + pts[i1] + pts[i2] + pts[i3]) / 4.0
    cap = 64
    N, H = np.zeros((cap, 3)), np.full(cap, np.inf)  # a dead face has offset +inf: never visible
    edges = {}  # directed edge -> face
    count = [0]

    P = pts.tolist()
    cx, cy, cz = inside.tolist()
    faces = {}  # face -> (a, b, c), as Python ints

    def add_face(a, b, c):
        nonlocal N, H
        (ax, ay, az), (bx, by, bz), (qx, qy, qz) = P[a], P[b], P[c]
        ux, uy, uz, vx, vy, vz = bx - ax, by - ay, bz - az, qx - ax, qy - ay, qz - az
        nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
        length = math.sqrt(nx * nx + ny * ny + nz * nz) or 1.0
        nx, ny, nz = nx / length, ny / length, nz / length
        if nx * (cx - ax) + ny * (cy - ay) + nz * (cz - az) > 0:  # keep it outward (only the first four can need it)
            b, c, nx, ny, nz = c, b, -nx, -ny, -nz
        f = count[0]
        if f == len(H):
            N = np.vstack([N, np.zeros_like(N)])
            H = np.concatenate([H, np.full(len(H), np.inf)])
        count[0] += 1
        N[f] = (nx, ny, nz)
        H[f] = nx * ax + ny * ay + nz * az
        faces[f] = (a, b, c)
        edges[(a, b)] = edges[(b, c)] = edges[(c, a)] = f

    for tri in ((i0, i1, i2), (i0, i1, i3), (i0, i2, i3), (i1, i2, i3)):
        add_face(*tri)
    order = np.argsort(-np.linalg.norm(pts - inside, axis=1))  # far points first: fewer faces
    for p in order:
        p = int(p)
        if p in (i0, i1, i2, i3):
            continue
        visible = set(np.nonzero(N[:count[0]] @ pts[p] - H[:count[0]] > eps)[0].tolist())
        if not visible:
            continue
        horizon = {}
        for f in visible:
            a, b, c = faces[f]
            for e in ((a, b), (b, c), (c, a)):
                if edges.get((e[1], e[0])) not in visible:
                    horizon[e[0]] = e[1]
        if not simple_loop(horizon):  # a point within rounding of the hull seen inconsistently: leave it
            continue
        for f in visible:
            a, b, c = faces.pop(f)
            H[f] = np.inf
            for e in ((a, b), (b, c), (c, a)):
                if edges.get(e) == f:
                    del edges[e]
        for a, b in horizon.items():
            add_face(a, b, p)
    ids = sorted(faces)
    return N[ids], H[ids], np.array([faces[f] for f in ids], dtype=np.int64).reshape(-1, 3), pts


def shrink_hull(points, margin, clamp=0.25):
    """btConvexHullComputer::compute(..., shrink = margin, shrinkClamp = clamp), as dawnforge's
    buildHull calls it: the hull with every face moved in by the margin, at most clamp times the
    distance from the hull's volume centroid to its nearest face. Returns (vertices, the amount),
    or None when the hull is flat."""
    hull = convex_hull(points)
    if hull is None:
        return None
    normals, offsets, tris, pts = hull
    # the volume centroid, from tetrahedra on an inner point
    ref = pts[np.unique(tris)].mean(axis=0)
    a, b, c = pts[tris[:, 0]] - ref, pts[tris[:, 1]] - ref, pts[tris[:, 2]] - ref
    vols = np.abs(np.einsum("ij,ij->i", a, np.cross(b, c))) / 6.0
    if vols.sum() <= 1e-15:
        return None
    cen = ref + (vols[:, None] * (a + b + c) / 4.0).sum(axis=0) / vols.sum()
    h = offsets - normals @ cen  # distances of the face planes from the centroid
    if h.min() <= 0.0:
        return None
    amount = min(margin, clamp * float(h.min()))
    shifted = h - amount
    # the vertices of {x: n.x <= h'} are the faces of the hull of the dual points n / h'
    # a cut face comes as many coplanar triangles: one dual point each, equal but for rounding
    dual = convex_hull(merge_close(normals / shifted[:, None], 1e-7), rel_eps=1e-10)
    if dual is None:
        return None
    dn, dh = dual[0], dual[1]
    keep = dh > 0
    verts = dn[keep] / dh[keep][:, None]
    ok = (verts @ normals.T - shifted[None, :]).max(axis=1) <= 1e-7 * max(1.0, float(h.max()))
    verts = merge_close(verts[ok], 1e-6) + cen if ok.any() else verts[:0]
    return (verts, amount) if len(verts) >= 4 else None


def collision_points(points, margin, budget):
    """dawnforge's buildHull: the hull shrunk by the margin, cut to `budget` points by
    farthest-point sampling from the centre of mass (the origin), first the farthest point.
    Returns (a list of points, the margin to give Bullet)."""
    shrunk = shrink_hull(points, margin)
    if shrunk is not None:
        pts, used = shrunk[0], max(shrunk[1], 1e-4)
    else:  # a flat or tiny piece: its points, a small margin
        pts, used = np.asarray(points, dtype=np.float64), 1e-4
    if len(pts) > budget:
        nearest = np.full(len(pts), np.inf)
        pick = int(np.argmax((pts * pts).sum(axis=1)))
        chosen = []
        for _ in range(budget):
            chosen.append(pick)
            nearest = np.minimum(nearest, ((pts - pts[pick]) ** 2).sum(axis=1))
            pick = int(np.argmax(nearest))
        pts = pts[chosen]
    return [tuple(map(float, p)) for p in pts], used


def quat_angle_deg(q):
    w = min(1.0, abs(q.w))
    return math.degrees(2.0 * math.acos(w))


def main():
    frac_dir, frames, iterations, substeps, out_json = parse_args()
    t_setup = time.perf_counter()
    with open(os.path.join(frac_dir, "fracture.json")) as f:
        frac = json.load(f)
    nodes = read_glb(os.path.join(frac_dir, "fragments.glb"))
    pieces_in, bonds_in = frac["pieces"], frac.get("bonds", [])

    scene = empty_scene(frames, FPS)
    coll = scene.collection

    lowest = float("inf")  # dawnforge's default ground height: the lowest point of the pieces (its y)
    pieces, coms, margins, hull_sizes = [], [], [], []
    for p in pieces_in:
        trans, local = nodes[p["name"]]
        lowest = min(lowest, min(trans[1] + v[1] for v in local))
        pts_b = [to_blender(v) for v in local]
        hull, margin = collision_points(pts_b, MARGIN, HULL_VERTICES)
        me = bpy.data.meshes.new(p["name"])
        me.from_pydata(hull, [], [])
        ob = bpy.data.objects.new(p["name"], me)
        ob.location = to_blender(trans)
        coll.objects.link(ob)
        pieces.append(ob)
        coms.append(Vector(to_blender(trans)))  # the body's origin (= center_of_mass, as floats)
        margins.append(margin)
        hull_sizes.append(len(hull))

    ground = bpy.data.objects.new("ground", box_mesh("ground", 0.5))
    ground.scale = (200.0, 200.0, 2.0)
    ground.location = (0.0, 0.0, lowest - 1.0)
    coll.objects.link(ground)

    view_layer = bpy.context.view_layer
    view_layer.update()

    rbw = rigid_body_world(scene, frames, substeps, iterations, split_impulse=True)
    add_rigid_bodies(pieces, 'ACTIVE')
    for ob, p, margin in zip(pieces, pieces_in, margins):
        rb = ob.rigid_body
        rb.collision_shape = 'CONVEX_HULL'
        rb.mesh_source = 'BASE'
        rb.mass = p["mass"]
        rb.friction = FRICTION
        rb.restitution = RESTITUTION
        rb.linear_damping = LINEAR_DAMPING
        rb.angular_damping = ANGULAR_DAMPING
        rb.use_margin = True
        rb.collision_margin = margin
        rb.use_deactivation = True
        rb.deactivate_linear_velocity = 0.8
        rb.deactivate_angular_velocity = 1.0

    add_rigid_bodies([ground], 'PASSIVE')
    ground.rigid_body.collision_shape = 'BOX'
    ground.rigid_body.friction = FRICTION
    ground.rigid_body.restitution = RESTITUTION

    # glue: one FIXED constraint per bond on an Empty at the bond's centroid. The operator adds one
    # (calling it per bond re-evaluates the scene each time: minutes for thousands); the others
    # are copies of that Empty, which carry its constraint into the constraints collection.
    template = bpy.data.objects.new("bond_template", None)
    coll.objects.link(template)
    view_layer.objects.active = template
    bpy.ops.rigidbody.constraint_add(type='FIXED')
    constraints = rbw.constraints
    anchors = []
    for i, b in enumerate(bonds_in):
        centroid = b.get("centroid")
        at = Vector(to_blender(centroid)) if centroid else (coms[b["a"]] + coms[b["b"]]) / 2.0
        e = template.copy()
        e.name = "bond_%05d" % i
        e.empty_display_size = 0.02
        e.location = at
        coll.objects.link(e)
        if e.name not in constraints.objects:
            constraints.objects.link(e)
        rbc = e.rigid_body_constraint
        rbc.type = 'FIXED'
        rbc.object1 = pieces[b["a"]]
        rbc.object2 = pieces[b["b"]]
        rbc.disable_collisions = True
        rbc.use_breaking = True
        strength = b.get("strength") or DEFAULT_STRENGTH
        rbc.breaking_threshold = strength * b["area"] / (FPS * substeps)
        anchors.append((b["a"], b["b"], at - coms[b["a"]], at - coms[b["b"]]))
    bpy.data.objects.remove(template, do_unlink=True)
    view_layer.update()
    setup_seconds = time.perf_counter() - t_setup

    n_bodies = len(rbw.collection.objects) if rbw.collection else 0
    n_constraints = len(rbw.constraints.objects) if rbw.constraints else 0
    start = [ob.matrix_world.copy() for ob in pieces]

    t0 = time.perf_counter()
    ret = bpy.ops.ptcache.bake_all(bake=True)
    seconds = time.perf_counter() - t0

    scene.frame_set(frames)
    end = [ob.matrix_world.copy() for ob in pieces]
    drops = [s.translation.z - e.translation.z for s, e in zip(start, end)]
    apart = 0
    for ia, ib, la, lb in anchors:
        pa = end[ia] @ la  # the anchor in each piece's local frame, now in the world
        pb = end[ib] @ lb
        rel = end[ia].to_quaternion().rotation_difference(end[ib].to_quaternion())
        if (pa - pb).length > APART_DISTANCE or quat_angle_deg(rel) > APART_DEGREES:
            apart += 1
    pc = rbw.point_cache

    out = {
        "tool": "blender-glued",
        "fracture": frac_dir,
        "pieces": len(pieces),
        "bonds": len(bonds_in),
        "frames": frames,
        "seconds": round(seconds, 4),
        "ms_per_frame": round(1000.0 * seconds / max(frames - 1, 1), 3),
        "setup_seconds": round(setup_seconds, 2),
        "bodies_in_world": n_bodies,
        "constraints_in_world": n_constraints,
        "substeps_per_frame": rbw.substeps_per_frame,
        "solver_iterations": rbw.solver_iterations,
        "fps": scene.render.fps,
        "ground_height": lowest,
        "hull_vertices_mean": round(sum(hull_sizes) / max(len(hull_sizes), 1), 1),
        "margin_mean": round(sum(margins) / max(len(margins), 1), 5),
        "cache_baked": bool(pc.is_baked),
        "cache_frames": [pc.frame_start, pc.frame_end],
        "mean_drop_m": sum(drops) / len(drops) if drops else 0.0,
        "max_drop_m": max(drops) if drops else 0.0,
        "bonds_apart": apart,
        "bonds_apart_rule": f"anchors > {APART_DISTANCE * 1000:g} mm apart or turned > {APART_DEGREES:g} deg",
        "operator_result": sorted(ret),
        "blender": bpy.app.version_string,
    }
    report(out, out_json)


if __name__ == "__main__":
    main()
