#!/usr/bin/env python3
"""Checks what Blender saw (import_report.py's JSON lines) against figures of our own.

    check.py files WORK                list the GLBs for Blender to import (with the mutants)
    check.py mutate WORK               write broken copies of some GLBs under WORK/mutants
    check.py check WORK REPORT.jsonl   check every file; each mutant must fail

Two kinds of figures, neither from dawnforge's code nor from Blender's:
- the GLB itself, read with glb.py (expect.py): objects, matrices, vertex and triangle counts,
  material slots and the faces of each, UV maps and their statistics (also per material),
  normals, volume, bounds, materials and their pictures. This catches a file Blender reads
  differently from what it holds (a wrong accessor, an axis, an index buffer, a material).
- the JSON reports dawnforge writes beside it (city.json, fracture.json, _data.json,
  _pivots.json), the input of the step (fragments.glb for the VATs, city.glb for the Pivot
  Painter files) and the file formats of ARCHITECTURE.md: which UV maps and materials each
  mesh must have, which files carry pictures, triangle counts, the lookup and texel UVs, pivots, bounds, volumes, foot
  points. These catch a file that is wrong in itself (a missing UV set agrees with itself).

WORK is the folder blender.sh fills: city/ (city.glb, city.json, trees/), fracture/, sim/,
vat_<preset>/vat_<preset>_mesh.glb for native, unity and unreal, pivots/city_pivots.glb.
"""

import json
import math
import os
import struct
import sys
from collections import Counter

from expect import MATERIALS, FileFigures, material_id, to_blender
import mutate

PRESETS = ("native", "unity", "unreal")
VAT_SCALE = {"native": 1.0, "unity": 1.0, "unreal": 100.0}
# The files that embed one picture per material (the rest have plain colours), and its size.
TEXTURED = ("city", "fragments")
PICTURE_SIZE = [256, 256]
UV = ["UVMap", "UVMap.001", "UVMap.002", "UVMap.003"]
MAX_LINES_PER_FILE = 12
_FIGURES = {}


def figures(path):
    """FileFigures of a GLB, read once (city.glb and fragments.glb serve several checks)."""
    path = os.path.abspath(path)
    if path not in _FIGURES:
        _FIGURES[path] = FileFigures(path)
    return _FIGURES[path]


def originals(work):
    files = ["city/city.glb"]
    trees = os.path.join(work, "city", "trees")
    files += ["city/trees/" + f for f in sorted(os.listdir(trees)) if f.endswith(".glb")]
    files += ["fracture/fragments.glb"]
    files += ["vat_%s/vat_%s_mesh.glb" % (p, p) for p in PRESETS]
    files += ["pivots/city_pivots.glb"]
    return files


def kind_of(rel):
    if rel == "city/city.glb":
        return "city"
    if rel.startswith("city/trees/"):
        return "species"
    if rel == "fracture/fragments.glb":
        return "fragments"
    if rel.startswith("vat_"):
        return "vat"
    if rel.startswith("pivots/"):
        return "pivots"
    raise ValueError("no checks for " + rel)


# --------------------------------------------------------------------------------------------
# Comparisons


def tol(v, rel=1e-6, abs_=1e-4):
    return abs_ + rel * abs(v)


def close(a, b, rel=1e-6, abs_=1e-4):
    return abs(a - b) <= tol(b, rel, abs_)


def close_vec(a, b, rel=1e-6, abs_=1e-4):
    return len(a) == len(b) and all(close(x, y, rel, abs_) for x, y in zip(a, b))


def fmt(v):
    if isinstance(v, float):
        return "%.6g" % v
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(fmt(x) for x in v) + "]"
    return str(v)


def json_close(a, b):
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(json_close(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(json_close(x, y) for x, y in zip(a, b))
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        return close(a, b, 1e-9, 1e-9)
    return a == b


def match_points(seen, expected, tolerance):
    """seen: [[u, v, count]] from Blender; expected: {(u, v): count}. Each Blender point must be
    near expected points whose counts add up to its count, and every expected point near one
    Blender point. Returns problems as text."""
    problems = []
    grid = 10 ** max(0, int(-math.log10(tolerance)) - 1)
    buckets = {}
    for i, (u, v, _) in enumerate(seen):
        buckets.setdefault((round(u * grid), round(v * grid)), []).append(i)
    want = [0] * len(seen)
    for (u, v), count in sorted(expected.items()):
        key = (round(u * grid), round(v * grid))
        hit = None
        for du in (-1, 0, 1):
            for dv in (-1, 0, 1):
                for i in buckets.get((key[0] + du, key[1] + dv), []):
                    su, sv, _ = seen[i]
                    if abs(su - u) <= tolerance * max(1.0, abs(u)) and abs(sv - v) <= tolerance * max(1.0, abs(v)):
                        hit = i
        if hit is None:
            problems.append("expected (%s, %s) x%d, Blender has no such UV" % (fmt(u), fmt(v), count))
        else:
            want[hit] += count
    for i, (u, v, count) in enumerate(seen):
        if want[i] != count:
            problems.append("Blender has (%s, %s) on %d corners, expected %d" % (fmt(u), fmt(v), count, want[i]))
    return problems


class Checker:
    def __init__(self):
        self.failures = []
        self.notes = []
        self.checks = 0
        self.label = ""

    def begin(self, label):
        self.label = label
        self.failures = []
        self.notes = []
        self.checks = 0

    def expect(self, ok, what):
        self.checks += 1
        if not ok:
            self.failures.append(what() if callable(what) else what)
        return ok

    def equal(self, seen, want, what):
        return self.expect(seen == want, lambda: "%s: Blender has %s, expected %s" % (what, fmt(seen), fmt(want)))

    def near(self, seen, want, what, rel=1e-6, abs_=1e-4):
        ok = (close_vec(seen, want, rel, abs_) if isinstance(want, (list, tuple)) else close(seen, want, rel, abs_))
        return self.expect(ok, lambda: "%s: Blender has %s, expected %s" % (what, fmt(seen), fmt(want)))


# --------------------------------------------------------------------------------------------
# Blender against the file itself


def blender_mesh(report, name):
    obj = report["objects"].get(name)
    return report["meshes"].get(obj["data"]) if obj and obj.get("data") else None


def check_against_file(c, report, fig):
    """Every object and mesh Blender made against what the GLB holds."""
    seen_names = set(report["objects"])
    want_names = set(fig.objects)
    c.expect(seen_names == want_names, lambda: "objects: Blender has %d (%s), the file's scene has %d (%s)" % (
        len(seen_names), ", ".join(sorted(seen_names - want_names)[:5]) or "no others",
        len(want_names), ", ".join(sorted(want_names - seen_names)[:5]) or "no others"))
    c.equal(report["orphan_objects"], 0, "objects outside the scene")
    used = {fig.doc["materials"][p["material"]]["name"] for m in fig.doc.get("meshes", [])
            for p in m["primitives"] if "material" in p}
    c.equal(report["materials"], sorted(used), "materials")
    check_materials_against_file(c, report, fig)
    c.expect(json_close(report["scene_extras"], fig.scene_extras),
             lambda: "scene custom properties (glTF scene extras): Blender has %s, the file %s" % (
                 report["scene_extras"], fig.scene_extras))
    meshes_done = set()
    for name in fig.order:
        want = fig.objects[name]
        seen = report["objects"].get(name)
        if seen is None:
            continue
        c.equal(seen["type"], want["type"], "%s: object type" % name)
        c.equal(seen["parent"], want["parent"], "%s: parent" % name)
        c.near([v for row in seen["matrix"] for v in row], [v for row in want["matrix"] for v in row],
               "%s: world matrix" % name, 1e-6, 2e-5)
        c.expect(json_close(seen["extras"], want["extras"]),
                 lambda: "%s: custom properties (node extras): Blender has %s, the file %s" % (
                     name, seen["extras"], want["extras"]))
        if want["mesh"] is None or seen["type"] != "MESH":
            continue
        mf = fig.mesh(want["mesh"])
        lo, hi = fig.world_bounds(name)
        c.near(seen.get("bounds", [[], []])[0] + seen.get("bounds", [[], []])[1], lo + hi, "%s: world bounds (min, max)" % name)
        bm = report["meshes"].get(seen["data"])
        if seen["data"] in meshes_done or not c.expect(bm is not None, "%s: no mesh data" % name):
            continue
        meshes_done.add(seen["data"])
        check_mesh_against_file(c, name, bm, mf)


def check_mesh_against_file(c, name, bm, mf):
    c.equal(bm["vertices"], mf.vertices, "%s: vertices (the ones the indices use)" % name)
    c.equal(bm["triangles"], mf.triangles - mf.degenerate_index_triangles, "%s: triangles" % name)
    c.equal(bm["polygons"], bm["triangles"], "%s: polygons (all triangles)" % name)
    # One slot per material of the primitives, in their order; each face in its primitive's.
    c.equal(bm["materials"], mf.slots, "%s: material slots (the primitives' materials)" % name)
    c.equal(bm["faces_by_material"], dict(mf.triangles_by_material), "%s: faces per material slot "
            "(the triangles of each primitive)" % name)
    c.equal([u["name"] for u in bm["uv_layers"]], mf.uv_names, "%s: UV maps (one per TEXCOORD_n)" % name)
    for layer, stats, by_material in zip(bm["uv_layers"], mf.uv, mf.uv_by_material):
        want = stats.as_dict()
        if not want["count"]:
            continue
        what = "%s: %s (u, 1 - v)" % (name, layer["name"])
        c.near(layer["min"] + layer["max"], want["min"] + want["max"], what + " min, max", 1e-6, 1e-5)
        c.near(layer["sum"], want["sum"], what + " sum over corners", 1e-6, 1e-6 * want["count"])
        got_by = layer.get("by_material") or {}
        want_by = {k: v for k, v in by_material.items() if v.count}
        c.equal(sorted(got_by), sorted(want_by), what + " materials with UVs")
        for material, st in want_by.items():
            got = got_by.get(material)
            if got:
                d = st.as_dict()
                c.equal(got["count"], d["count"], what + " corners of material %s" % material)
                c.near(got["sum"], d["sum"], what + " sum over corners of material %s" % material, 1e-6, 1e-6 * st.count)
    # No COLOR_0 any more: no colour attribute; Blender 3.4 imports no custom attribute
    # (_MATERIAL_ID, _PIECE_ID), so the mesh has no generic attribute but material_index.
    c.equal([a["name"] for a in bm["color_attributes"]], mf.colour_names, "%s: colour attributes (COLOR_n)" % name)
    c.equal([a for a in bm["attributes"] if a != "material_index"], mf.colour_names,
            "%s: generic attributes besides material_index" % name)
    # The file's own _MATERIAL_ID agrees with its primitives' materials (dawnforge's reader
    # and engines that read the attribute see the materials Blender shows).
    c.expect(not mf.material_id_mismatches, lambda: "%s: triangles whose first vertex's _MATERIAL_ID is not their "
             "primitive's material: %s" % (name, dict(mf.material_id_mismatches)))
    c.equal(bm["has_custom_normals"], mf.has_normals, "%s: custom normals from NORMAL" % name)
    if mf.has_normals and "normal_sum" in bm:
        corners = 3 * mf.triangles
        c.near(bm["normal_sum"], mf.normal_sum, "%s: sum of corner normals" % name, 0.0, 5e-4 * corners + 1e-6)
    c.near(bm["volume"], mf.volume, "%s: enclosed volume" % name, 1e-5, 1e-7)


def check_materials_against_file(c, report, fig):
    """Every material as the file defines it: blend mode, and a base colour that is either the
    baseColorFactor or an Image Texture node of the file's picture (its size from the PNG's own
    header, its packed bytes the embedded ones), repeated, through KHR_texture_transform's scale,
    on UVMap."""
    want_images = {}
    nodes = report.get("material_nodes", {})
    for name, want in fig.material_figures().items():
        seen = nodes.get(name)
        if not c.expect(seen is not None, "material %s: not in Blender" % name):
            continue
        c.equal(seen.get("blend_method"), want["blend_method"], "material %s: blend mode (alphaMode)" % name)
        tex = want["texture"]
        if tex is None:
            c.equal(seen.get("base_colour_from"), None, "material %s: base colour linked (the file has no texture)" % name)
            c.near(seen.get("base_colour", [])[:3], want["base_colour"][:3], "material %s: base colour (baseColorFactor RGB)"
                   % name, 0.0, 1e-6)
            c.near(seen.get("alpha", -1.0), want["base_colour"][3], "material %s: alpha (baseColorFactor A)" % name, 0.0, 1e-6)
            continue
        if not c.equal(seen.get("base_colour_from"), "TEX_IMAGE", "material %s: node feeding the base colour" % name):
            continue
        got = seen["base_colour_texture"]
        c.equal(got["image"], tex["image"], "material %s: base colour image" % name)
        c.equal(got["extension"], "REPEAT" if tex["repeat"] else "EXTEND", "material %s: image extension (wrapS, wrapT)" % name)
        # Without KHR_texture_transform (the leaf picture, once across its card) Blender adds no
        # Mapping node, and on the first UV set no UV Map node: the identity on UVMap.
        c.near((got.get("mapping_scale") or [1.0, 1.0])[:2], tex["scale"],
               "material %s: Mapping scale (KHR_texture_transform scale)" % name, 1e-6, 1e-7)
        c.equal(got.get("uv_map") or "UVMap", "UVMap" if tex["tex_coord"] == 0 else "UVMap.%03d" % tex["tex_coord"],
                "material %s: UV map of the texture" % name)
        if want["base_colour"][3] < 1.0:
            c.expect(seen.get("alpha_linked"), "material %s: alpha %g but Blender's alpha is not linked" % (
                name, want["base_colour"][3]))
        want_images[tex["image"]] = tex
    images = report.get("images", {})
    c.equal(sorted(images), sorted(want_images), "images (the textures' pictures)")
    for image, tex in want_images.items():
        got = images.get(image)
        if not got:
            continue
        c.equal(got["size"], tex["size"], "image %s: size (the embedded PNG's header)" % image)
        c.equal(got["packed_bytes"], tex["embedded_bytes"], "image %s: packed bytes (the embedded picture's)" % image)


def check_picture_format(c, report, fig, textured):
    """The file formats: city.glb and fragments.glb embed one 256x256 PNG per material, its base
    colour texture; every other GLB has plain colours and no image."""
    wants = fig.material_figures()
    nodes = report.get("material_nodes", {})
    if textured:
        for name, want in sorted(wants.items()):
            tex = want["texture"]
            c.expect(tex is not None and tex["mime_type"] == "image/png" and tex["embedded_bytes"],
                     "material %s: no embedded PNG base colour texture" % name)
            got = (nodes.get(name) or {}).get("base_colour_texture")
            image = (report.get("images") or {}).get(got["image"]) if got and got.get("image") else None
            c.expect(image is not None and image["size"] == PICTURE_SIZE,
                     "material %s: Blender's base colour is no %dx%d picture (%s)" % (
                         name, PICTURE_SIZE[0], PICTURE_SIZE[1], image["size"] if image else got))
            c.expect(got is not None and (name == "leaves" or all(0 < v < 1.0 + 1e-9 for v in got.get("mapping_scale", [0])[:2])),
                     "material %s: the picture repeats every %s of UVMap, expected 1 m or more" % (
                         name, got.get("mapping_scale") if got else None))
        c.equal(len(report.get("images", {})), len(wants), "images (one per material)")
    else:
        c.equal(len(report.get("images", {})), 0, "images (plain colours)")
        for name, want in sorted(wants.items()):
            c.equal((nodes.get(name) or {}).get("base_colour_from"), None, "material %s: base colour linked" % name)


def faces_by_id(faces_by_material):
    """{material ID: faces} from {material name: faces} (brick_0 and brick_3 both brick)."""
    out = Counter()
    for name, n in faces_by_material.items():
        out[material_id(name)] += n
    return dict(out)


# --------------------------------------------------------------------------------------------
# Blender against our reports and the file formats


def load_json(path):
    with open(path) as f:
        return json.load(f)


def uv_layer(bm, name):
    for layer in bm["uv_layers"]:
        if layer["name"] == name:
            return layer
    return None


def check_uv_points(c, bm, layer_name, expected, what, tolerance=2e-6):
    layer = uv_layer(bm, layer_name)
    if not c.expect(layer is not None, "%s: no UV map %s" % (what, layer_name)):
        return
    if not c.expect(layer.get("distinct") is not None, "%s: %s has %s distinct UVs, too many to list" % (
            what, layer_name, layer.get("distinct_count"))):
        return
    problems = match_points(layer["distinct"], expected, tolerance)
    c.expect(not problems, lambda: "%s: %s: %s%s" % (what, layer_name, "; ".join(problems[:3]),
                                                      " (and %d more)" % (len(problems) - 3) if len(problems) > 3 else ""))


def check_city(c, report, fig, work):
    city = load_json(os.path.join(work, "city", "city.json"))
    objs = report["objects"]
    # Tiles and their ground.
    nx, ny = city["tiles"]
    tiles = [(i, j) for j in range(ny) for i in range(nx)] if city["tile"] is None else [tuple(city["tile"])]
    for i, j in tiles:
        tile = objs.get("tile_%d_%d" % (i, j))
        c.expect(tile is not None and tile["type"] == "EMPTY", "tile_%d_%d: no EMPTY object" % (i, j))
        ground = objs.get("ground_%d_%d" % (i, j))
        c.expect(ground is not None and ground["parent"] == "tile_%d_%d" % (i, j),
                 "ground_%d_%d: no mesh object under its tile" % (i, j))
    # Every building: an EMPTY with its lot, floors and rooms, and two LOD meshes with the
    # triangles city.json counts; glass and wood as its window and door parts.
    tri = Counter()
    for b in city["buildings"]:
        name = b["name"]
        ob = objs.get(name)
        if not c.expect(ob is not None, "%s: no object" % name):
            continue
        c.equal(ob["type"], "EMPTY", "%s: type" % name)
        c.equal(ob["extras"].get("floors"), b["floors"], "%s: custom property floors" % name)
        c.equal(ob["extras"].get("lot"), b["lot"], "%s: custom property lot" % name)
        c.equal(ob["extras"].get("rooms"), sum(b["rooms_per_floor"]), "%s: custom property rooms" % name)
        for lod in ("lod0", "lod1"):
            child = objs.get("%s_%s" % (name, lod))
            if not c.expect(child is not None and child["parent"] == name, "%s_%s: no mesh object under %s" % (name, lod, name)):
                continue
            bm = report["meshes"][child["data"]]
            c.equal(bm["triangles"], b["triangles"][lod], "%s_%s: triangles (city.json)" % (name, lod))
            c.equal([u["name"] for u in bm["uv_layers"]], UV[:3], "%s_%s: UV maps (TEXCOORD_0..2)" % (name, lod))
            c.equal([a["name"] for a in bm["color_attributes"]], [], "%s_%s: colour attributes (none since COLOR_0 went)" % (name, lod))
            c.expect(bm["materials"] and all(material_id(m) is not None for m in bm["materials"]),
                     "%s_%s: material slots %s, expected materials named after IDs" % (name, lod, bm["materials"]))
            check_room_uvs(c, "%s_%s" % (name, lod), bm, sum(b["rooms_per_floor"]))
        lod0 = blender_mesh(report, name + "_lod0")
        if lod0:
            faces = faces_by_id(lod0["faces_by_material"])
            for kind, material in (("window", "glass"), ("door", "wood")):
                parts = sum(p[3] for p in b["parts"] if p[0] == kind)
                c.equal(3 * faces.get(MATERIALS.index(material), 0), 3 * parts,
                        "%s_lod0: corners in the %s slot (the %s parts of city.json)" % (name, material, kind))
            # Brick and plaster carry the building's colour variant, one per building.
            variants = {m for m in lod0["materials"] if material_id(m) in (2, 4)}
            c.expect(len({m.rpartition("_")[2] for m in variants}) <= 1 and all(m.rpartition("_")[2].isdigit() for m in variants),
                     "%s_lod0: walls %s, expected brick_N / plaster_N of one variant" % (name, sorted(variants)))
            c.expect(lod0["volume"] > 0, "%s_lod0: its closed parts enclose no volume (%g)" % (name, lod0["volume"]))
    winding_done = set()
    for name, ob in objs.items():
        bm = report["meshes"].get(ob["data"]) if ob["data"] else None
        if bm is None:
            continue
        if ob["data"] not in winding_done:
            winding_done.add(ob["data"])
            check_winding(c, ob["data"], bm)
        group = name.rsplit("_", 1)[1] if name.endswith(("_lod0", "_lod1")) else name.split("_")[0]
        tri[{"land": "ground", "tree": "dressing", "lamp": "dressing"}.get(group, group)] += bm["triangles"]
        if group not in ("lod0", "lod1"):
            c.equal([u["name"] for u in bm["uv_layers"]], UV[:1], "%s: UV maps (TEXCOORD_0 only)" % name)
            c.equal([a["name"] for a in bm["color_attributes"]], [], "%s: colour attributes (none since COLOR_0 went)" % name)
    for key in ("lod0", "lod1", "ground", "dressing"):
        c.equal(tri[key], city["counts"]["triangles"][key], "triangles of all %s meshes (city.json counts)" % key)
    c.equal(sum(1 for n in objs if n.endswith("_lod0")), city["counts"]["buildings"], "buildings (city.json counts)")
    check_picture_format(c, report, fig, True)
    # Trees and lamps stand where city.json says: glTF (x, h, -y) is Blender (x, y, h).
    species = {s["name"]: s for s in city["tree_species"]}
    for t in city["trees"]:
        ob = objs.get(t["name"])
        if not c.expect(ob is not None and ob["type"] == "MESH", "%s: no mesh object" % t["name"]):
            continue
        m = ob["matrix"]
        c.near([m[0][3], m[1][3], m[2][3]], [t["foot"][0], t["foot"][1], t["height"]], "%s: foot (x, y, height)" % t["name"],
               0.0, 1e-3)
        x_axis = [m[0][0], m[1][0], m[2][0]]
        length = math.sqrt(sum(v * v for v in x_axis))
        c.near(length, t["scale"], "%s: scale (length of its X axis)" % t["name"], 0.0, 1e-3)
        c.near([v / length for v in x_axis], [0.0, 0.0, 1.0], "%s: +X runs up the trunk (Blender +Z)" % t["name"], 0.0, 1e-5)
        c.equal(ob["extras"].get("species"), t["species"], "%s: custom property species" % t["name"])
        elements = species[t["species"]]["elements"]
        names = [t["name"]] + ["%s_%s" % (t["name"], e["name"]) for e in elements[1:]]
        for e, en in zip(elements[1:], names[1:]):
            child = objs.get(en)
            c.expect(child is not None and child["parent"] == names[e["parent"]],
                     "%s: no object under %s" % (en, names[e["parent"]]))
    for lamp in city["lamps"]:
        ob = objs.get(lamp["name"])
        if c.expect(ob is not None and ob["type"] == "MESH", "%s: no mesh object" % lamp["name"]):
            m = ob["matrix"]
            c.near([m[0][3], m[1][3]], lamp["foot"], "%s: foot (x, y)" % lamp["name"], 0.0, 1e-3)
    c.equal(sum(1 for n in objs if n.startswith("tree_") and n.count("_") == 1), city["counts"]["trees"], "trees")
    c.equal(sum(1 for n in objs if n.startswith("lamp_")), city["counts"]["lamps"], "lamps")
    # The ground runs `margin` metres beyond the district on every side (Blender x east, y north).
    margin = city["recipe"]["terrain"]["margin"]
    if city["tile"] is None and nx == 1 and ny == 1:
        g = objs.get("ground_0_0")
        if g:
            c.near(g["bounds"][0][:2] + g["bounds"][1][:2], [-margin, -margin, city["size"][0] + margin, city["size"][1] + margin],
                   "ground_0_0: x, y bounds (the district and its margin)", 0.0, 1e-3)


def check_room_uvs(c, name, bm, rooms):
    """TEXCOORD_1 = (room depth, room index) and TEXCOORD_2 = (width, height) on glass, (0, 0)
    elsewhere; Blender shows (u, 1 - v)."""
    for layer_name in UV[1:3]:
        layer = uv_layer(bm, layer_name)
        if layer is None or "by_material" not in layer:
            continue
        for material, s in layer["by_material"].items():
            if material_id(material) != MATERIALS.index("glass"):
                c.equal(s["min"] + s["max"], [0.0, 1.0, 0.0, 1.0], "%s: %s off the glass" % (name, layer_name))
            elif layer_name == "UVMap.001":
                c.expect(s["min"][0] > 0 and 1.0 - s["min"][1] <= rooms - 1 + 1e-6 and s["max"][1] <= 1.0,
                         "%s: %s on glass: depth %s.., room index %s..%s of %d rooms" % (
                             name, layer_name, fmt(s["min"][0]), fmt(1 - s["max"][1]), fmt(1 - s["min"][1]), rooms))
            else:
                c.expect(s["min"][0] > 0 and s["max"][1] < 1.0, "%s: %s on glass: width from %s, height from %s" % (
                    name, layer_name, fmt(s["min"][0]), fmt(1 - s["max"][1])))
    layer = uv_layer(bm, "UVMap.001")
    if layer and layer.get("distinct"):
        off = [v for _, v, _ in layer["distinct"] if abs((1 - v) - round(1 - v)) > 1e-5]
        c.expect(not off, lambda: "%s: UVMap.001 room indices that are not whole numbers: %s" % (name, fmt(off[:3])))




def check_winding(c, name, bm, flat=False):
    """Every corner's normal on the front side of its face (glTF: counter-clockwise is the
    front); with `flat`, equal to the face's normal. Procgen's tubes (trunks, branches, lamp
    poles) were wound inside out until this check found them."""
    for material, d in sorted((bm.get("normal_face_dot_by_material") or {}).items()):
        c.expect(d["opposed_corners"] == 0, "%s: %d of %d corners of material %s face against their "
                 "triangle's winding (normal . face normal down to %.3f)" % (
                     name, d["opposed_corners"], d["corners"], material, d["min"]))
        if flat:
            c.expect(d["min"] > 0.999, "%s: material %s: corner normals differ from the flat face normal "
                     "(normal . face normal down to %.4f)" % (name, material, d["min"]))


def texel_centres(n, width, height):
    return [((i % width + 0.5) / width, 1.0 - (i // width + 0.5) / height) for i in range(n)]


def check_pivot_layout(c, what, pp, n):
    width = math.ceil(math.sqrt(n))
    c.equal([pp["width"], pp["height"]], [width, math.ceil(n / width)], "%s: _pivots.json width, height for %d elements" % (what, n))
    c.equal(pp["uv_set"], 1, "%s: _pivots.json uv_set" % what)


def check_single_mesh_object(c, report, name, generator, preset):
    objs = report["objects"]
    c.equal(sorted(objs), [name], "objects")
    c.equal(report["scene_extras"].get("generator"), generator, "scene custom property generator")
    c.equal(report["scene_extras"].get("preset"), preset, "scene custom property preset")
    if name in objs:  # the mesh too is named after the file (the Pivot Painter mesh was "Mesh_0")
        c.equal(objs[name]["data"], name, "the object's mesh name")
    return blender_mesh(report, name)


def check_species(c, report, fig, work, rel):
    species = os.path.basename(rel)[:-4]
    pp = load_json(os.path.join(work, "city", "trees", species + "_pivots.json"))
    city_fig = figures(os.path.join(work, "city", "city.glb"))
    mesh_index = {m.get("name"): i for i, m in enumerate(city_fig.doc["meshes"])}
    bm = check_single_mesh_object(c, report, species, "dawnforge pivots", pp["preset"])
    if not c.expect(bm is not None, "no mesh"):
        return
    elements = pp["elements"]
    check_pivot_layout(c, species, pp, len(elements))
    c.equal([u["name"] for u in bm["uv_layers"]][:2], UV[:2], "UV maps (TEXCOORD_0, TEXCOORD_1 the texel)")
    expected = Counter()
    materials = Counter()
    triangles = 0
    for element, uv in zip(elements, texel_centres(len(elements), pp["width"], pp["height"])):
        index = mesh_index.get("tree_%s_%s" % (species, element["name"]))
        if not c.expect(index is not None, "element %s: no mesh tree_%s_%s in city.glb" % (element["name"], species, element["name"])):
            continue
        mf = city_fig.mesh(index)
        triangles += mf.triangles
        expected[uv] += 3 * mf.triangles
        materials.update(faces_by_id(mf.triangles_by_material))
    c.equal(bm["triangles"], triangles, "triangles (the species' element meshes in city.glb)")
    check_uv_points(c, bm, "UVMap.001", expected, "texels (each element's corners at its texel)")
    check_materials(c, bm, materials, "the species' element meshes in city.glb")
    check_picture_format(c, report, fig, False)
    check_winding(c, species, bm)


def check_materials(c, bm, want, source):
    """Blender's faces per material (by ID: the variants of brick and plaster may differ) against
    the triangles of each material in `source`."""
    c.equal([a["name"] for a in bm["color_attributes"]], [], "colour attributes (none since COLOR_0 went)")
    c.equal(faces_by_id(bm["faces_by_material"]), dict(want), "faces per material ID (%s)" % source)


def check_pivots(c, report, fig, work, rel):
    stem = os.path.basename(rel)[:-4]
    pp = load_json(os.path.join(work, "pivots", stem + "_pivots.json"))
    city_fig = figures(os.path.join(work, "city", "city.glb"))
    bm = check_single_mesh_object(c, report, stem, "dawnforge pivots", pp["preset"])
    if not c.expect(bm is not None, "no mesh"):
        return
    elements = pp["elements"]
    mesh_objects = [n for n in city_fig.order if city_fig.objects[n]["mesh"] is not None]
    c.equal([e["name"] for e in elements], mesh_objects, "elements (city.glb's mesh nodes, depth first)")
    check_pivot_layout(c, stem, pp, len(elements))
    c.equal([u["name"] for u in bm["uv_layers"]][:2], UV[:2], "UV maps (TEXCOORD_0, TEXCOORD_1 the texel)")
    expected = Counter()
    for element, uv in zip(elements, texel_centres(len(elements), pp["width"], pp["height"])):
        if element["name"] in city_fig.objects:
            expected[uv] += 3 * city_fig.mesh(city_fig.objects[element["name"]]["mesh"]).triangles
    check_uv_points(c, bm, "UVMap.001", expected, "texels (each element's corners at its texel)")
    c.equal(bm["triangles"], sum(city_fig.mesh(city_fig.objects[n]["mesh"]).triangles for n in mesh_objects),
            "triangles (all of city.glb's mesh nodes)")
    materials = Counter()
    for n in mesh_objects:
        materials.update(faces_by_id(city_fig.mesh(city_fig.objects[n]["mesh"]).triangles_by_material))
    check_materials(c, bm, materials, "all of city.glb's mesh nodes")
    check_picture_format(c, report, fig, False)
    # The elements keep their triangles' winding: the same corners face against it here as in
    # Blender's city.glb (none, since the tubes were fixed).
    city_report = report.get("_city_report")
    if city_report:
        inward = Counter()
        for n in mesh_objects:
            ob = city_report["objects"].get(n)
            m = city_report["meshes"].get(ob["data"]) if ob else None
            for material, d in ((m or {}).get("normal_face_dot_by_material") or {}).items():
                inward[material_id(material)] += d["opposed_corners"]
        seen = Counter()
        for material, d in (bm.get("normal_face_dot_by_material") or {}).items():
            seen[material_id(material)] += d["opposed_corners"]
        seen = {k: v for k, v in seen.items() if v}
        c.equal(seen, {k: v for k, v in inward.items() if v}, "corners facing against their winding, per material "
                "(as in Blender's city.glb)")
    lo = [math.inf] * 3
    hi = [-math.inf] * 3
    for n in mesh_objects:
        a, b = city_fig.world_bounds(n)
        lo = [min(x, y) for x, y in zip(lo, a)]
        hi = [max(x, y) for x, y in zip(hi, b)]
    ob = report["objects"].get(stem)
    if ob and "bounds" in ob:
        c.near(ob["bounds"][0] + ob["bounds"][1], lo + hi, "bounds (city.glb's mesh nodes in world space)")
    # The pivots and X axes of _pivots.json are the origins and +X of the nodes Blender made
    # from city.glb (the city's report is checked with its own file).
    if city_report:
        for e in elements:
            ob = city_report["objects"].get(e["name"])
            if not c.expect(ob is not None, "element %s: not an object of city.glb in Blender" % e["name"]):
                continue
            m = ob["matrix"]
            c.near([m[0][3], m[1][3], m[2][3]], list(to_blender(e["pivot"])), "element %s: pivot" % e["name"], 1e-6, 1e-4)
            x = [m[0][0], m[1][0], m[2][0]]
            length = math.sqrt(sum(v * v for v in x))
            c.near([v / length for v in x], list(to_blender(e["x_axis"])), "element %s: X axis" % e["name"], 0.0, 1e-5)


def check_fragments(c, report, fig, work):
    fracture = load_json(os.path.join(work, "fracture", "fracture.json"))
    pieces = fracture["pieces"]
    objs = report["objects"]
    c.equal(sorted(objs), sorted(p["name"] for p in pieces), "objects (fracture.json pieces)")
    c.equal(report["scene_extras"], {"generator": "dawnforge fracture", "pieces": len(pieces), "bonds": len(fracture["bonds"])},
            "scene custom properties")
    total = 0.0
    for p in pieces:
        ob = objs.get(p["name"])
        if not c.expect(ob is not None and ob["type"] == "MESH" and ob["parent"] is None, "%s: no root mesh object" % p["name"]):
            continue
        m = ob["matrix"]
        c.near([m[0][3], m[1][3], m[2][3]], list(to_blender(p["center_of_mass"])), "%s: origin (centre of mass)" % p["name"],
               1e-6, 1e-6)
        c.near(ob["extras"].get("mass", -1.0), p["mass"], "%s: custom property mass" % p["name"], 1e-9, 0.0)
        c.near(ob["extras"].get("volume", -1.0), p["volume"], "%s: custom property volume" % p["name"], 1e-9, 0.0)
        bm = report["meshes"].get(ob["data"])
        c.equal(bm["triangles"], p["triangles"], "%s: triangles (fracture.json)" % p["name"])
        c.near(bm["volume"], p["volume"], "%s: volume Blender's triangles enclose" % p["name"], 1e-5, 1e-7)
        total += bm["volume"]
        c.equal([u["name"] for u in bm["uv_layers"]], UV[:1], "%s: UV maps (TEXCOORD_0)" % p["name"])
        check_winding(c, p["name"], bm, flat=True)
        c.equal([a["name"] for a in bm["color_attributes"]], [], "%s: colour attributes (none since COLOR_0 went)" % p["name"])
        codes = set(faces_by_id(bm["faces_by_material"]))
        # The input (an OBJ) has no materials: outer faces material 0, cut faces the interior one.
        c.expect(codes <= {0, fracture["settings"]["interior_material"]} and fracture["settings"]["interior_material"] in codes,
                 "%s: materials %s, expected the outside's 0 and the cut faces' %d" % (
                     p["name"], sorted(codes), fracture["settings"]["interior_material"]))
    c.near(total, fracture["volume"], "volume of all pieces (fracture.json volume)", 1e-5, 0.0)
    c.near(total, fracture["input"]["volume"], "volume of all pieces (the input's)", 1e-5, 0.0)
    check_picture_format(c, report, fig, True)


def half_bits(x):
    return struct.unpack("<H", struct.pack("<e", x))[0]


def decode_very_high(u2, v2, u3, v3):
    """The pivot (Houdini axes, metres) the Labs Unreal material decodes from the "Very High"
    form, given TEXCOORD_2 = (u2, v2) and TEXCOORD_3 = (u3, v3) with glTF's (Unreal's) V: the
    two V's are halves whose 13 low bits each carry half of a float's top 26 bits ("Decode
    Magnitude"); |v3| < 2 marks (x, y, z) = (u2, that float, u3), else (u2, ., u3) is a unit
    direction and the float its length."""
    def join(hi, lo):
        h, l = half_bits(hi), half_bits(lo)
        bits = ((((h & 0x8000) | ((h << 2) & 0x7FF8)) << 16) | (((l & 0x8000) | ((l << 2) & 0x7FF8)) << 3)) & 0xFFFFFFFF
        return struct.unpack("<f", struct.pack("<I", bits))[0]
    m = join(v2, v3)
    if abs(v3) < 2.0:
        return (u2, m, u3)
    y = math.sqrt(max(0.0, 1.0 - u2 * u2 - u3 * u3))
    return (u2 * m, y * m, u3 * m)


def check_vat(c, report, fig, work, rel):
    preset = rel.split("/")[0][len("vat_"):]
    data = load_json(os.path.join(work, "vat_" + preset, "vat_%s_data.json" % preset))
    fracture = load_json(os.path.join(work, "fracture", "fracture.json"))
    fragments = figures(os.path.join(work, "fracture", "fragments.glb"))
    pieces = fracture["pieces"]
    c.equal(data["preset"], preset, "_data.json preset")
    bm = check_single_mesh_object(c, report, data["name"], "dawnforge vat", preset)
    if not c.expect(bm is not None, "no mesh"):
        return
    data_tris = 0 if preset == "native" else 2
    c.equal(data["mesh"]["data_triangles"], data_tris, "_data.json data_triangles (the Labs' two for %s)" % preset)
    c.equal(bm["triangles"], sum(p["triangles"] for p in pieces) + data_tris, "triangles (fracture.json's and the data triangles)")
    c.near(bm["volume"], fracture["volume"], "volume (the rest pose: fracture.json volume)", 1e-5, 1e-6)
    c.equal([u["name"] for u in bm["uv_layers"]], UV, "UV maps (TEXCOORD_0..3)")
    c.equal([a["name"] for a in bm["color_attributes"]], [], "colour attributes (none since COLOR_0 went)")
    # One slot: the engines' VAT shaders draw the mesh, so it keeps one primitive ("default").
    c.equal(bm["materials"], ["default"], "material slots (one primitive of the plain material)")
    check_picture_format(c, report, fig, False)
    # Flat normals facing out, but on the data triangles, which are not drawn.
    faces = bm.get("normal_face_dot_by_material") or {}
    for material, d in sorted(faces.items()):
        allowed = 3 * data_tris
        c.expect(d["unflat_corners"] <= allowed and d["opposed_corners"] <= allowed,
                 "%s: material %s: %d corners face against their triangle's winding and %d differ from the flat "
                 "face normal (normal . face normal down to %.4f); the data triangles account for %d" % (
                     data["name"], material, d["opposed_corners"], d["unflat_corners"], d["min"], allowed))
    # The material IDs stay in _MATERIAL_ID, which Blender does not import: the file's corners
    # per ID are fragments.glb's, and 0 on the data triangles.
    mesh_index = fig.objects.get(data["name"], {}).get("mesh")
    if mesh_index is not None:
        want = Counter()
        for name in fragments.order:
            want.update(fragments.mesh(fragments.objects[name]["mesh"]).material_id_corners)
        want[0] += 3 * data_tris
        c.equal(dict(fig.mesh(mesh_index).material_id_corners), dict(want),
                "the file's _MATERIAL_ID corners per ID (fragments.glb's, and 0 on the data triangles)")
    n, w, height = data["pieces"], data["W"], data["height"]
    c.equal(n, len(pieces), "_data.json pieces")
    rows = math.ceil(n / w)
    c.equal([w, data["R"], height], [min(n, w), rows, rows * data["frames"]], "_data.json W, R, height")
    check_vat_uvs(c, bm, data, pieces, preset, data_tris)
    # Bounds: the rest pose (fragments.glb's pieces); the data triangles sit at the encoded
    # bounds' corners, which _data.json gives in engine axes and units.
    lo = [math.inf] * 3
    hi = [-math.inf] * 3
    for name in fragments.order:
        a, b = fragments.world_bounds(name)
        lo = [min(x, y) for x, y in zip(lo, a)]
        hi = [max(x, y) for x, y in zip(hi, b)]
    if data_tris:
        for corner in (data["encoded_bounds"]["min"], data["encoded_bounds"]["max"]):
            x, y, z = corner
            gltf = (-x, y, z) if preset == "unity" else (x / 100.0, z / 100.0, y / 100.0)
            p = to_blender(gltf)
            lo = [min(a, b) for a, b in zip(lo, p)]
            hi = [max(a, b) for a, b in zip(hi, p)]
    ob = report["objects"].get(data["name"])
    if ob and "bounds" in ob:
        c.near(ob["bounds"][0] + ob["bounds"][1], lo + hi,
               "bounds (fragments.glb's rest pose%s)" % (" and the encoded bounds' corners" if data_tris else ""), 1e-6, 1e-5)


def check_vat_uvs(c, bm, data, pieces, preset, data_tris):
    """Each piece's corners, and only they, carry its lookup texel of frame 0 (UVMap.001; V from
    the bottom in Blender, as the Labs' uv2) and its pivot (UVMap.002, UVMap.003): the unencoded
    Labs uv3 = (px, 1), uv4 = (py, 1 - pz) in metres, or Unreal's Very High form. The data
    triangles carry (0, 0), (0, 1), (0, 1)."""
    table = bm.get("uv_rows") or {}
    if not c.expect(table.get("layers") == UV[1:] and table.get("distinct") is not None,
                    "UV maps 1..3 side by side: %s" % {k: v for k, v in table.items() if k != "distinct"}):
        return
    n, w, height = data["pieces"], data["W"], data["height"]
    very_high = "Very High" in data["mesh"]["pivot"]
    c.expect(very_high == (preset == "unreal") or not very_high, "_data.json: Very High pivots for %s" % preset)
    max_pivot_error = data.get("max_pivot_error", 0.0)
    # The unencoded form is in metres; files that say "engine units" (before Unreal's Very High
    # form) held Unreal's in centimetres.
    scale = 100.0 if preset == "unreal" and "engine units" in data["mesh"]["pivot"] else 1.0
    if very_high:
        extent = max(abs(v) for p in pieces for v in p["center_of_mass"])
        c.expect(max_pivot_error <= 1e-3 * max(1.0, extent),
                 "_data.json max_pivot_error %g m: more than half precision gives" % max_pivot_error)
    seen = Counter()
    worst = 0.0
    for u1, v1, u2, v2, u3, v3, count in table["distinct"]:
        if (u1, v1) == (0.0, 0.0):
            c.equal([u2, v2, u3, v3, count], [0.0, 1.0, 0.0, 1.0, 3 * data_tris], "data triangles' pivot UVs and corners")
            seen["data"] += count
            continue
        col, row = u1 * w - 0.5, (1.0 - v1) * height - 0.5
        if not c.expect(abs(col - round(col)) < 1e-3 and abs(row - round(row)) < 1e-3 and 0 <= round(row) < data["R"]
                        and 0 <= round(col) < w, "lookup UV (%s, %s) on %d corners: not a texel centre of frame 0" % (
                            fmt(u1), fmt(v1), count)):
            continue
        j = round(row) * w + round(col)
        if not c.expect(j < n, "lookup UV (%s, %s): piece %d of %d" % (fmt(u1), fmt(v1), j, n)):
            continue
        seen[j] += count
        p = pieces[j]["center_of_mass"]
        if very_high:
            got = decode_very_high(u2, 1.0 - v2, u3, 1.0 - v3)
            error = math.dist(got, p)
            worst = max(worst, error)
            c.expect(error <= max_pivot_error * 1.001 + 1e-7, "%s: pivot decoded from the Very High UVs %s, "
                     "fracture.json's centre of mass %s: %.3g m off (max_pivot_error %.3g)" % (
                         pieces[j]["name"], fmt(list(got)), fmt(p), error, max_pivot_error))
        else:
            p = [scale * v for v in p]
            c.near([u2, v2, u3, v3], [p[0], 1.0, p[1], 1.0 - p[2]],
                   "%s: pivot UVs (px, 1, py, 1 - pz), fracture.json's centre of mass" % pieces[j]["name"], 2e-6, 2e-6)
    for j, p in enumerate(pieces):
        c.equal(seen[j], 3 * p["triangles"], "%s: corners at its lookup texel (3 x its triangles)" % p["name"])
    c.equal(seen["data"], 3 * data_tris, "data triangles' corners at lookup UV (0, 0)")


# --------------------------------------------------------------------------------------------


def check_file(c, work, rel, glb_path, report):
    kind = kind_of(rel)
    if not c.expect(report is not None, "Blender wrote no report"):
        return
    if not c.expect(report["ok"], "Blender's import failed: %s" % report["error"]):
        return
    fig = figures(glb_path)
    check_against_file(c, report, fig)
    if kind == "city":
        check_city(c, report, fig, work)
    elif kind == "species":
        check_species(c, report, fig, work, rel)
    elif kind == "fragments":
        check_fragments(c, report, fig, work)
    elif kind == "vat":
        check_vat(c, report, fig, work, rel)
    elif kind == "pivots":
        check_pivots(c, report, fig, work, rel)


def summary_line(report):
    objs = report.get("objects", {})
    meshes = report.get("meshes", {})
    uv = sorted({u["name"] for m in meshes.values() for u in m["uv_layers"]})
    col = sorted({a["name"] for m in meshes.values() for a in m["color_attributes"]})
    return "%d objects, %d meshes, %d triangles, UV maps %s, colours %s, %d materials, %d images" % (
        len(objs), len(meshes), sum(m["triangles"] for m in meshes.values()), "/".join(uv) or "none",
        "/".join(col) or "none", len(report.get("materials", [])), len(report.get("images", {})))


def run_checks(work, report_path):
    reports = {}
    with open(report_path) as f:
        for line in f:
            r = json.loads(line)
            reports[os.path.abspath(r["file"])] = r
    c = Checker()
    failed = False
    city_report = reports.get(os.path.abspath(os.path.join(work, "city", "city.glb")))
    first = next(iter(reports.values()), {})
    print("blender %s, numpy %s%s" % (first.get("blender"), first.get("numpy"),
                                     " (np.bool alias restored for the importer)" if first.get("numpy_bool_shim") else ""))
    for rel in originals(work):
        path = os.path.abspath(os.path.join(work, rel))
        report = reports.get(path)
        if report is not None:
            report["_city_report"] = city_report
        c.begin(rel)
        check_file(c, work, rel, path, report)
        if c.failures:
            failed = True
            print("FAIL %s: %d of %d checks differ" % (rel, len(c.failures), c.checks))
            for line in c.failures[:MAX_LINES_PER_FILE]:
                print("  FAIL %s: %s" % (rel, line))
            if len(c.failures) > MAX_LINES_PER_FILE:
                print("  ... and %d more" % (len(c.failures) - MAX_LINES_PER_FILE))
        else:
            print("ok   %s: %d checks (%s)" % (rel, c.checks, summary_line(report)))
        for line in c.notes:
            print("  note %s: %s" % (rel, line))
    # Each mutant is a broken copy of a file: the same checks must fail.
    for m in mutate.manifest(work):
        path = os.path.abspath(m["file"])
        report = reports.get(path)
        if report is not None:
            report["_city_report"] = city_report
        c.begin(m["id"])
        check_file(c, work, m["original"], path, report)
        if c.failures:
            print("ok   mutant %s (%s): %d of %d checks fail, first: %s" % (
                m["id"], m["what"], len(c.failures), c.checks, c.failures[0]))
        else:
            failed = True
            print("FAIL mutant %s (%s): every check passed on the broken file" % (m["id"], m["what"]))
    return failed


def main(argv):
    if len(argv) >= 2 and argv[0] == "files":
        work = argv[1]
        for rel in originals(work):
            print(os.path.join(work, rel))
        for m in mutate.manifest(work):
            print(m["file"])
        return 0
    if len(argv) >= 2 and argv[0] == "mutate":
        mutate.write_mutants(argv[1])
        return 0
    if len(argv) >= 3 and argv[0] == "check":
        return 1 if run_checks(argv[1], argv[2]) else 0
    sys.stderr.write(__doc__)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
