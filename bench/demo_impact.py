#!/usr/bin/env python3
"""The demo's impact point on a fractured building: from the pieces' bounds in fragments.glb,
the middle in x, 45 % of the height, the +z face. usage: demo_impact.py FRACTURE_DIR"""
import json
import struct
import sys

data = open(f"{sys.argv[1]}/fragments.glb", "rb").read()
length, = struct.unpack_from("<I", data, 12)
gltf = json.loads(data[20:20 + length])
lo, hi = [1e30] * 3, [-1e30] * 3
for node in gltf["nodes"]:
    if "mesh" not in node:
        continue
    t = node.get("translation", [0, 0, 0])
    acc = gltf["accessors"][gltf["meshes"][node["mesh"]]["primitives"][0]["attributes"]["POSITION"]]
    lo = [min(a, b + c) for a, b, c in zip(lo, acc["min"], t)]
    hi = [max(a, b + c) for a, b, c in zip(hi, acc["max"], t)]
print(f"{(lo[0] + hi[0]) / 2},{lo[1] + 0.45 * (hi[1] - lo[1])},{hi[2]}")
