# Runs inside Blender: imports each GLB with Blender's own glTF importer (io_scene_gltf2, default
# options) into an empty scene, and writes one JSON line per file describing what Blender ended
# up with. It judges nothing; check.py compares the lines with figures of its own.
#
#   blender -b --factory-startup --python-exit-code 1 --python import_report.py -- OUT.jsonl A.glb B.glb ...
#
# Per file: the objects (type, parent, mesh, world matrix, world-space bounds of the mesh's
# vertices, custom properties, which is where the importer puts node extras), the meshes
# (vertex and triangle counts; material slots in order and the faces of each; UV maps in order
# with per-corner statistics, also per material slot; colour attributes; the generic
# attributes; the sum of the loop normals and how they agree with the winding, per slot), the
# materials (blend mode, base colour: its value or the image texture that feeds it, with its
# UV map and mapping), the images (size, packed bytes) and the scene's custom properties (the
# scene extras).
#
# Debian's Blender 3.4 runs its bundled importer against the system NumPy; from NumPy 1.24 on,
# `np.bool` is gone and the importer fails on every mesh (set_poly_smoothing). The alias is
# restored here, before anything is imported, exactly as it was (numpy.bool = bool).

import json
import math
import sys
import time

import numpy

NUMPY_BOOL_SHIM = False
if "bool" not in numpy.__dict__:
    numpy.bool = bool
    NUMPY_BOOL_SHIM = True

import bpy  # noqa: E402

DISTINCT_UV_CAP = 4096  # distinct UVs listed per layer up to this many (lookup and texel UVs)


def plain(value):
    """A custom property as JSON (ID properties come back as IDPropertyGroup/Array)."""
    if hasattr(value, "to_dict"):
        return {k: plain(v) for k, v in value.to_dict().items()}
    if hasattr(value, "to_list"):
        return [plain(v) for v in value.to_list()]
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, (str, int, float, bool)) or value is None:
        return value
    return str(value)


def custom_properties(idblock):
    return {k: plain(idblock[k]) for k in idblock.keys() if not k.startswith("_") and k != "cycles"}


def stats(values):
    return {"min": values.min(axis=0).tolist(), "max": values.max(axis=0).tolist(),
            "sum": values.sum(axis=0).tolist(), "count": int(len(values))}


def uv_layer_report(mesh, layer, corner_slots):
    n = len(mesh.loops)
    uv = numpy.empty(n * 2, dtype=numpy.float32)
    layer.data.foreach_get("uv", uv)
    uv = uv.reshape(n, 2)
    out = {"name": layer.name, "corners": n}
    if n:
        out.update(stats(uv.astype(numpy.float64)))
        # Distinct UVs (exact float values) with their corner counts: lookup and texel UVs.
        out.update(distinct_rows(uv))
        uv = uv.astype(numpy.float64)
        # The same statistics for the corners of each material slot (by the slot's material name).
        if corner_slots is not None:
            out["by_material"] = {slot_name(mesh, k): stats(uv[corner_slots == k]) for k in numpy.unique(corner_slots)}
    return out


def distinct_rows(values):
    keys, counts = numpy.unique(values, axis=0, return_counts=True)
    return {"distinct_count": int(len(keys)),
            "distinct": ([[float(v) for v in k] + [int(c)] for k, c in zip(keys.tolist(), counts.tolist())]
                         if len(keys) <= DISTINCT_UV_CAP else None)}


def uv_rows(mesh):
    """The distinct rows of all UV maps but the first, side by side, with their corner counts:
    per piece of a VAT its lookup texel and pivot together."""
    layers = list(mesh.uv_layers)[1:]
    n = len(mesh.loops)
    if not layers or not n:
        return None
    columns = []
    for layer in layers:
        uv = numpy.empty(n * 2, dtype=numpy.float32)
        layer.data.foreach_get("uv", uv)
        columns.append(uv.reshape(n, 2))
    return dict(distinct_rows(numpy.hstack(columns)), layers=[layer.name for layer in layers])


def slot_name(mesh, index):
    """A material slot's material name ("" for an empty slot, "#k" for a face beyond the slots)."""
    index = int(index)
    if index >= len(mesh.materials):
        return "#%d" % index
    material = mesh.materials[index]
    return material.name if material else ""


def face_loops(mesh):
    """(loops, faces): every corner's loop index and the face it belongs to, face by face."""
    count = len(mesh.polygons)
    starts = numpy.empty(count, dtype=numpy.int64)
    totals = numpy.empty(count, dtype=numpy.int64)
    mesh.polygons.foreach_get("loop_start", starts)
    mesh.polygons.foreach_get("loop_total", totals)
    loops = numpy.concatenate([numpy.arange(s, s + t) for s, t in zip(starts, totals)] or [starts]) \
        if count and not (totals == 3).all() else (starts[:, None] + numpy.arange(3)).ravel()
    return loops, numpy.repeat(numpy.arange(count), totals)


def colour_report(attribute):
    count = len(attribute.data)
    rgba = numpy.empty(count * 4, dtype=numpy.float32)
    attribute.data.foreach_get("color", rgba)
    rgba = rgba.reshape(count, 4)
    return {"name": attribute.name, "domain": attribute.domain, "data_type": attribute.data_type,
            "values": int(count), "min": rgba.min(axis=0).tolist() if count else None,
            "max": rgba.max(axis=0).tolist() if count else None}


def socket_source(socket):
    """The node that feeds an input socket (None when the socket is not linked)."""
    return socket.links[0].from_node if socket.is_linked else None


def material_report(material):
    """The blend mode and what the Principled BSDF's base colour and alpha come from: a value, or
    an image texture node (its image, extension, UV map node and Mapping node)."""
    out = {"blend_method": material.blend_method, "use_nodes": bool(material.use_nodes)}
    if not material.use_nodes or material.node_tree is None:
        return out
    bsdf = next((n for n in material.node_tree.nodes if n.type == "BSDF_PRINCIPLED"), None)
    if bsdf is None:
        return out
    base = bsdf.inputs["Base Color"]
    out["base_colour"] = [float(v) for v in base.default_value]
    out["alpha"] = float(bsdf.inputs["Alpha"].default_value)
    out["alpha_linked"] = bool(bsdf.inputs["Alpha"].is_linked)
    node = socket_source(base)
    out["base_colour_from"] = node.type if node else None
    if node is not None and node.type == "TEX_IMAGE":
        tex = {"image": node.image.name if node.image else None, "extension": node.extension,
               "interpolation": node.interpolation}
        feed = socket_source(node.inputs["Vector"])
        if feed is not None and feed.type == "MAPPING":
            tex["mapping_scale"] = [float(v) for v in feed.inputs["Scale"].default_value]
            tex["mapping_location"] = [float(v) for v in feed.inputs["Location"].default_value]
            feed = socket_source(feed.inputs["Vector"])
        tex["uv_map"] = feed.uv_map if feed is not None and feed.type == "UVMAP" else None
        out["base_colour_texture"] = tex
    return out


def image_report(image):
    return {"size": [int(v) for v in image.size], "source": image.source,
            "packed_bytes": int(image.packed_file.size) if image.packed_file else None}


def signed_volume(mesh):
    """The volume the triangles enclose, in the mesh's own space (divergence theorem)."""
    n = len(mesh.loop_triangles)
    if not n:
        return 0.0
    co = numpy.empty(len(mesh.vertices) * 3, dtype=numpy.float32)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3).astype(numpy.float64)
    tris = numpy.empty(n * 3, dtype=numpy.int64)
    mesh.loop_triangles.foreach_get("vertices", tris)
    p = co[tris.reshape(n, 3)]
    return float(numpy.einsum("ij,ij->i", p[:, 0], numpy.cross(p[:, 1], p[:, 2])).sum() / 6.0)


def mesh_report(mesh):
    mesh.calc_loop_triangles()
    colours = list(mesh.color_attributes)
    # Each corner's material slot (its face's material_index), and the faces of each slot.
    count = len(mesh.polygons)
    loops, faces = face_loops(mesh)
    material_index = numpy.empty(count, dtype=numpy.int64)
    mesh.polygons.foreach_get("material_index", material_index)
    corner_slots = numpy.empty(len(mesh.loops), dtype=numpy.int64)
    corner_slots[loops] = material_index[faces]
    slots, slot_faces = numpy.unique(material_index, return_counts=True)
    out = {
        "vertices": len(mesh.vertices),
        "polygons": count,
        "triangles": len(mesh.loop_triangles),
        "corners": len(mesh.loops),
        "volume": signed_volume(mesh),
        "uv_layers": [uv_layer_report(mesh, layer, corner_slots) for layer in mesh.uv_layers],
        "uv_rows": uv_rows(mesh),
        "color_attributes": [colour_report(a) for a in colours],
        "attributes": sorted(a.name for a in mesh.attributes if not a.name.startswith(".")),
        "materials": [m.name if m else None for m in mesh.materials],
        "faces_by_material": {slot_name(mesh, k): int(n) for k, n in zip(slots, slot_faces)},
        "has_custom_normals": bool(mesh.has_custom_normals),
    }
    if len(mesh.loops):
        mesh.calc_normals_split()
        normals = numpy.empty(len(mesh.loops) * 3, dtype=numpy.float32)
        mesh.loops.foreach_get("normal", normals)
        normals = normals.reshape(-1, 3).astype(numpy.float64)
        out["normal_sum"] = normals.sum(axis=0).tolist()
        # How each corner's normal agrees with the normal its face's winding gives (faces of
        # zero area, which have none, left out), per material slot.
        face_normals = numpy.empty(count * 3, dtype=numpy.float32)
        mesh.polygons.foreach_get("normal", face_normals)
        areas = numpy.empty(count, dtype=numpy.float32)
        mesh.polygons.foreach_get("area", areas)
        dots = numpy.einsum("ij,ij->i", normals[loops], face_normals.reshape(-1, 3)[faces].astype(numpy.float64))
        keep = areas[faces] > 1e-12
        out["normal_face_dot"] = ({"min": float(dots[keep].min()), "mean": float(dots[keep].mean())}
                                  if keep.any() else None)
        codes = corner_slots[loops]
        out["normal_face_dot_by_material"] = {
            slot_name(mesh, k): {"min": float(dots[keep & (codes == k)].min()),
                                 "mean": float(dots[keep & (codes == k)].mean()),
                                 "opposed_corners": int((dots[keep & (codes == k)] < 0).sum()),
                                 "unflat_corners": int((dots[keep & (codes == k)] < 0.999).sum()),
                                 "corners": int((keep & (codes == k)).sum())}
            for k in numpy.unique(codes[keep])}
    return out


def object_report(ob):
    world = numpy.array(ob.matrix_world, dtype=numpy.float64)
    out = {
        "type": ob.type,
        "parent": ob.parent.name if ob.parent else None,
        "data": ob.data.name if ob.data is not None else None,
        "matrix": [[round(v, 7) for v in row] for row in world.tolist()],
        "extras": custom_properties(ob),
    }
    if ob.type == "MESH" and len(ob.data.vertices):
        co = numpy.empty(len(ob.data.vertices) * 3, dtype=numpy.float32)
        ob.data.vertices.foreach_get("co", co)
        co = co.reshape(-1, 3).astype(numpy.float64) @ world[:3, :3].T + world[:3, 3]
        out["bounds"] = [co.min(axis=0).tolist(), co.max(axis=0).tolist()]
    return out


def import_one(path):
    # A fresh, empty file for each import: nothing of the last file's scene, meshes,
    # materials or scene properties is left over.
    bpy.ops.wm.read_homefile(use_empty=True)
    error = None
    start = time.perf_counter()
    try:
        result = bpy.ops.import_scene.gltf(filepath=path)
        if "FINISHED" not in result:
            error = "import_scene.gltf returned %s" % sorted(result)
    except Exception as ex:  # the operator's ERROR reports come as RuntimeError
        error = "%s: %s" % (type(ex).__name__, str(ex).strip())
    seconds = time.perf_counter() - start
    report = {
        "file": path,
        "ok": error is None,
        "error": error,
        "import_seconds": round(seconds, 3),
        "blender": bpy.app.version_string,
        "numpy": numpy.__version__,
        "numpy_bool_shim": NUMPY_BOOL_SHIM,
    }
    if error is None:
        scene = bpy.context.scene
        report["scene_extras"] = custom_properties(scene)
        report["materials"] = sorted(m.name for m in bpy.data.materials)
        report["material_nodes"] = {m.name: material_report(m) for m in bpy.data.materials}
        report["images"] = {im.name: image_report(im) for im in bpy.data.images}
        report["objects"] = {ob.name: object_report(ob) for ob in scene.objects}
        report["orphan_objects"] = len(bpy.data.objects) - len(scene.objects)
        report["meshes"] = {me.name: mesh_report(me) for me in bpy.data.meshes if me.users}
    return report


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) < 2:
        sys.stderr.write("usage: blender -b --python import_report.py -- OUT.jsonl FILE.glb ...\n")
        sys.exit(2)
    out_path, files = argv[0], argv[1:]
    failed = False
    with open(out_path, "w") as out:
        for path in files:
            report = import_one(path)
            failed |= not report["ok"]
            out.write(json.dumps(report, allow_nan=False) + "\n")
            out.flush()
            sys.stdout.write("\nimport_report: %s: %s in %.2f s\n" % (
                path, "imported" if report["ok"] else report["error"], report["import_seconds"]))
            sys.stdout.flush()
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
