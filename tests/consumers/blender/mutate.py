"""Broken copies of the GLBs (WORK/mutants/<id>/<file>), each checked like its original by
check.py, which must then fail: proof that the checks see what they claim to.

Each mutant changes one thing a real bug could change: a UV set dropped, an axis swapped, V
flipped, pivot UV sets swapped, a triangle lost, a node moved, a UV set pointing at the wrong
accessor, two primitives' materials swapped, a material's picture dropped, the normals turned.

A mesh's primitives (one per material) share their vertex accessors: an attribute is changed
on all of them, as a writer that lost or mixed up the attribute would."""

import json
import os
import struct

from glb import Glb


def write_glb(path, doc, binary):
    body = json.dumps(doc, separators=(",", ":")).encode("utf-8")
    body += b" " * (-len(body) % 4)
    binary = bytes(binary) + b"\0" * (-len(binary) % 4)
    doc_buffers = doc.get("buffers", [])
    if doc_buffers:
        doc_buffers[0]["byteLength"] = len(binary)
    total = 12 + 8 + len(body) + 8 + len(binary)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, total))
        f.write(struct.pack("<II", len(body), 0x4E4F534A) + body)
        f.write(struct.pack("<II", len(binary), 0x004E4942) + binary)


def node_named(doc, name):
    return next(n for n in doc["nodes"] if n.get("name") == name)


def primitive_of(doc, node_name):
    return doc["meshes"][node_named(doc, node_name)["mesh"]]["primitives"][0]


def attributes_of(mesh):
    """The attribute maps of all of a mesh's primitives (each a dict of its own in the JSON)."""
    return [p["attributes"] for p in mesh["primitives"]]


def rewrite_floats(g, binary, accessor_index, change):
    """Rewrites a float accessor's elements in place with change(tuple) -> tuple."""
    acc = g.json["accessors"][accessor_index]
    view = g.json["bufferViews"][acc["bufferView"]]
    width = {"VEC2": 2, "VEC3": 3, "VEC4": 4}[acc["type"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    stride = view.get("byteStride", 4 * width)
    element = struct.Struct("<%df" % width)
    new = [change(v) for v in g.accessor(accessor_index)]
    for i, v in enumerate(new):
        element.pack_into(binary, start + i * stride, *v)
    if "min" in acc:
        acc["min"] = [min(v[k] for v in new) for k in range(width)]
        acc["max"] = [max(v[k] for v in new) for k in range(width)]


def _frag_drop_uv(g, b):
    for attrs in attributes_of(g.json["meshes"][node_named(g.json, "piece_0003")["mesh"]]):
        del attrs["TEXCOORD_0"]


def _vat_drop_uv3(g, b):
    del g.json["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_3"]


def _vat_flip_lookup_v(g, b):
    rewrite_floats(g, b, g.json["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"], lambda v: (v[0], 1.0 - v[1]))


def _vat_swap_yz(g, b):
    rewrite_floats(g, b, g.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"], lambda v: (v[0], v[2], v[1]))


def _vat_swap_pivot_sets(g, b):
    attrs = g.json["meshes"][0]["primitives"][0]["attributes"]
    attrs["TEXCOORD_2"], attrs["TEXCOORD_3"] = attrs["TEXCOORD_3"], attrs["TEXCOORD_2"]


def _vat_pivot_v_unflipped(g, b):
    rewrite_floats(g, b, g.json["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_3"], lambda v: (v[0], 1.0 - v[1]))


def _city_drop_triangle(g, b):
    g.json["accessors"][primitive_of(g.json, "building_00001_lod0")["indices"]]["count"] -= 3


def _city_move_tree(g, b):
    t = node_named(g.json, "tree_00000")["translation"]
    t[0], t[2] = t[2], t[0]


def _pivots_wrong_texel_set(g, b):
    for attrs in attributes_of(g.json["meshes"][0]):
        attrs["TEXCOORD_1"] = attrs["TEXCOORD_0"]


def _species_swap_materials(g, b):
    # Wood on the leaves and leaves on the wood: each triangle keeps its _MATERIAL_ID, but its
    # primitive (and so its Blender material slot) has the other material.
    prims = g.json["meshes"][0]["primitives"]
    prims[0]["material"], prims[1]["material"] = prims[1]["material"], prims[0]["material"]


def _city_drop_picture(g, b):
    material = next(m for m in g.json["materials"] if m.get("name") == "asphalt")
    del material["pbrMetallicRoughness"]["baseColorTexture"]


def _frag_turn_normals(g, b):
    rewrite_floats(g, b, primitive_of(g.json, "piece_0000")["attributes"]["NORMAL"], lambda v: (v[1], v[2], v[0]))


# id, original (relative to WORK), what, change(glb, bytearray of the BIN chunk)
MUTANTS = [
    ("fragments-no-uv", "fracture/fragments.glb", "piece_0003 without TEXCOORD_0", _frag_drop_uv),
    ("fragments-normals", "fracture/fragments.glb", "piece_0000's normals with their axes rotated", _frag_turn_normals),
    ("vat-unreal-no-uv3", "vat_unreal/vat_unreal_mesh.glb", "TEXCOORD_3 dropped", _vat_drop_uv3),
    ("vat-unity-lookup-v", "vat_unity/vat_unity_mesh.glb", "lookup V of TEXCOORD_1 flipped", _vat_flip_lookup_v),
    ("vat-unreal-pivots", "vat_unreal/vat_unreal_mesh.glb", "TEXCOORD_2 and TEXCOORD_3 swapped", _vat_swap_pivot_sets),
    ("vat-unity-pivot-v", "vat_unity/vat_unity_mesh.glb", "TEXCOORD_3 as the Labs' (py, 1 - pz), V not flipped",
     _vat_pivot_v_unflipped),
    ("vat-native-yz", "vat_native/vat_native_mesh.glb", "POSITION y and z swapped", _vat_swap_yz),
    ("city-triangle", "city/city.glb", "building_00001_lod0 one triangle short", _city_drop_triangle),
    ("city-tree", "city/city.glb", "tree_00000 with x and z of its translation swapped", _city_move_tree),
    ("pivots-texels", "pivots/city_pivots.glb", "TEXCOORD_1 pointing at TEXCOORD_0's accessor", _pivots_wrong_texel_set),
    ("species-materials", None, "the materials of its first two primitives swapped", _species_swap_materials),
    ("city-picture", "city/city.glb", "asphalt without its base colour texture", _city_drop_picture),
]


def _species_file(work):
    trees = os.path.join(work, "city", "trees")
    return "city/trees/" + sorted(f for f in os.listdir(trees) if f.endswith(".glb"))[0]


def manifest(work):
    path = os.path.join(work, "mutants", "manifest.json")
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return json.load(f)


def write_mutants(work):
    entries = []
    for mid, original, what, change in MUTANTS:
        original = original or _species_file(work)
        g = Glb(os.path.join(work, original))
        binary = bytearray(g.bin)
        change(g, binary)
        out = os.path.join(work, "mutants", mid, os.path.basename(original))
        write_glb(out, g.json, binary)
        entries.append({"id": mid, "original": original, "file": out, "what": what})
    with open(os.path.join(work, "mutants", "manifest.json"), "w") as f:
        json.dump(entries, f, indent=1)
