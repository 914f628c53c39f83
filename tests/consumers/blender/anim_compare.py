#!/usr/bin/env python3
"""Compares what Blender played (anim_play.py's JSON) with the simulation, sharing no code
with the product: sim.json and transforms.bin read here with json and struct.

    anim_compare.py SIM_DIR PLAYED.json [MAX_POSITION_M MAX_DEGREES]
    anim_compare.py --mutate IN.glb OUT.glb    a copy whose first piece's translation keys are
                                             moved 5 mm along x, which the check must catch

Every piece (an object named as sim.json's piece_names) at every frame: its position within
1 mm, its rotation within 0.1 degrees. Blender is Z-up: its importer maps glTF's (x, y, z) to
(x, -z, y), undone here. Exit 1 with one FAIL line per kind of miss."""
import json
import math
import struct
import sys



def mutate(src, dst):
    glb = bytearray(open(src, "rb").read())
    length, = struct.unpack_from("<I", glb, 12)
    gltf = json.loads(glb[20:20 + length])
    bin_start = 20 + length + 8
    animation = gltf["animations"][0]
    channel = next(c for c in animation["channels"] if c["target"]["path"] == "translation")
    accessor = gltf["accessors"][animation["samplers"][channel["sampler"]]["output"]]
    view = gltf["bufferViews"][accessor["bufferView"]]
    at = bin_start + view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    for key in range(accessor["count"]):
        x, = struct.unpack_from("<f", glb, at + 12 * key)
        struct.pack_into("<f", glb, at + 12 * key, x + 0.005)
    open(dst, "wb").write(glb)


if sys.argv[1] == "--mutate":
    mutate(sys.argv[2], sys.argv[3])
    sys.exit(0)
sim_dir, played = sys.argv[1], json.load(open(sys.argv[2]))
max_position = float(sys.argv[3]) if len(sys.argv) > 3 else 0.001
max_degrees = float(sys.argv[4]) if len(sys.argv) > 4 else 0.1
sim = json.load(open(f"{sim_dir}/sim.json"))
n, frames, names = sim["pieces"], sim["frames"], sim["piece_names"]
data = open(f"{sim_dir}/transforms.bin", "rb").read()
assert len(data) == frames * n * 28, "transforms.bin does not match sim.json"


def rotation_matrix(x, y, z, w):
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def to_gltf(m):
    """Blender's world matrix (Z-up) back in glTF axes: C^-1 M C with C (x, y, z) -> (x, -z, y)."""
    c = [[1, 0, 0], [0, 0, -1], [0, 1, 0]]
    ct = [list(r) for r in zip(*c)]
    r = [[m[i][j] for j in range(3)] for i in range(3)]
    mul = lambda a, b: [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    p = [m[0][3], m[1][3], m[2][3]]
    return mul(mul(ct, r), c), [sum(ct[i][k] * p[k] for k in range(3)) for i in range(3)]


missing = [name for name in names if name not in played["matrices"]]
if missing:
    print(f"FAIL Blender has no object for {len(missing)} of {n} pieces (first: {missing[0]})")
    sys.exit(1)
worst_p, worst_d, where = 0.0, 0.0, ""
for i, name in enumerate(names):
    mats = played["matrices"][name]
    if len(mats) != frames:
        print(f"FAIL {name}: {len(mats)} frames played, {frames} simulated")
        sys.exit(1)
    for k in range(frames):
        px, py, pz, qx, qy, qz, qw = struct.unpack_from("<7f", data, (k * n + i) * 28)
        r, p = to_gltf(mats[k])
        want = rotation_matrix(qx, qy, qz, qw)
        # |R - W| (Frobenius) is 2 sqrt(2) sin(angle / 2): well conditioned near 0, unlike the trace.
        diff = math.sqrt(sum((want[a][b] - r[a][b]) ** 2 for a in range(3) for b in range(3)))
        degrees = math.degrees(2 * math.asin(min(1.0, diff / (2 * math.sqrt(2)))))
        dist = math.dist(p, (px, py, pz))
        if not (math.isfinite(dist) and math.isfinite(degrees)):  # max() and > would skip a NaN
            print(f"FAIL {name} at frame {k}: Blender played a pose that is not a number")
            sys.exit(1)
        if dist > worst_p:
            worst_p = dist
        if degrees > worst_d:
            worst_d, where = degrees, f"{name} at frame {k}"
print(f"blender played {n} pieces x {frames} frames: worst position {worst_p * 1000:.3f} mm, "
      f"worst rotation {worst_d:.4f} deg ({where})")
if worst_p > max_position or worst_d > max_degrees:
    print(f"FAIL beyond {max_position * 1000:g} mm or {max_degrees:g} deg")
    sys.exit(1)
