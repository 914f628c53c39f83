# Runs inside Blender: imports each GLB with Blender's own glTF importer (io_scene_gltf2, default
# options) into an empty scene, and writes one JSON line per file describing what Blender ended
# up with. It judges nothing; check.py compares the lines with figures of its own.
#
#   blender -b --factory-startup --python-exit-code 1 --python import_report.py -- OUT.jsonl A.glb B.glb ...
#
# Per file: the objects (type, parent, mesh, world matrix, world-space bounds of the mesh's
# vertices, custom properties, which is where the importer puts node extras), the meshes
# (vertex and triangle counts; UV maps in order with per-corner statistics; colour attributes
# with a histogram of their corner colours, each channel rounded to 0 or 1; the sum of the
# loop normals), the materials, and the scene's custom properties (the scene extras).
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


def uv_layer_report(mesh, layer, corner_codes):
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
        # The same statistics for the corners of each colour (material ID) of the first colour
        # attribute, when there is one on the corners.
        if corner_codes is not None:
            out["by_colour"] = {str(int(code)): stats(uv[corner_codes == code])
                                for code in numpy.unique(corner_codes)}
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


def colour_codes(attribute):
    """Each value's colour as a 4-bit code, each channel rounded to 0 or 1: R + 2G + 4B + 8A."""
    count = len(attribute.data)
    rgba = numpy.empty(count * 4, dtype=numpy.float32)
    attribute.data.foreach_get("color", rgba)
    rgba = rgba.reshape(count, 4)
    bits = (rgba > 0.5).astype(numpy.int64)
    return rgba, bits[:, 0] + 2 * bits[:, 1] + 4 * bits[:, 2] + 8 * bits[:, 3]


def colour_report(attribute):
    rgba, codes = colour_codes(attribute)
    values, counts = numpy.unique(codes, return_counts=True)
    # How far any channel is from 0 or 1 (our COLOR_0 holds only 0 and 255).
    off = float(numpy.abs(rgba - numpy.round(rgba)).max()) if len(rgba) else 0.0
    return {"name": attribute.name, "domain": attribute.domain, "data_type": attribute.data_type,
            "values": int(len(rgba)), "histogram": {str(int(v)): int(c) for v, c in zip(values, counts)},
            "max_off_binary": off}


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
    corner_codes = None
    if colours and colours[0].domain == "CORNER":
        corner_codes = colour_codes(colours[0])[1]
    out = {
        "vertices": len(mesh.vertices),
        "polygons": len(mesh.polygons),
        "triangles": len(mesh.loop_triangles),
        "corners": len(mesh.loops),
        "volume": signed_volume(mesh),
        "uv_layers": [uv_layer_report(mesh, layer, corner_codes) for layer in mesh.uv_layers],
        "uv_rows": uv_rows(mesh),
        "color_attributes": [colour_report(a) for a in colours],
        "attributes": sorted(a.name for a in mesh.attributes if not a.name.startswith(".")),
        "materials": [m.name if m else None for m in mesh.materials],
        "has_custom_normals": bool(mesh.has_custom_normals),
    }
    if len(mesh.loops):
        mesh.calc_normals_split()
        normals = numpy.empty(len(mesh.loops) * 3, dtype=numpy.float32)
        mesh.loops.foreach_get("normal", normals)
        normals = normals.reshape(-1, 3).astype(numpy.float64)
        out["normal_sum"] = normals.sum(axis=0).tolist()
        # How each corner's normal agrees with the normal its face's winding gives (faces of
        # zero area, which have none, left out), over all corners and per colour.
        count = len(mesh.polygons)
        face_normals = numpy.empty(count * 3, dtype=numpy.float32)
        mesh.polygons.foreach_get("normal", face_normals)
        areas = numpy.empty(count, dtype=numpy.float32)
        mesh.polygons.foreach_get("area", areas)
        starts = numpy.empty(count, dtype=numpy.int64)
        totals = numpy.empty(count, dtype=numpy.int64)
        mesh.polygons.foreach_get("loop_start", starts)
        mesh.polygons.foreach_get("loop_total", totals)
        loops = numpy.concatenate([numpy.arange(s, s + t) for s, t in zip(starts, totals)] or [starts]) \
            if count and not (totals == 3).all() else (starts[:, None] + numpy.arange(3)).ravel()
        faces = numpy.repeat(numpy.arange(count), totals)
        dots = numpy.einsum("ij,ij->i", normals[loops], face_normals.reshape(-1, 3)[faces].astype(numpy.float64))
        keep = areas[faces] > 1e-12
        out["normal_face_dot"] = ({"min": float(dots[keep].min()), "mean": float(dots[keep].mean())}
                                  if keep.any() else None)
        if corner_codes is not None:
            codes = corner_codes[loops]
            out["normal_face_dot_by_colour"] = {
                str(int(code)): {"min": float(dots[keep & (codes == code)].min()),
                                 "mean": float(dots[keep & (codes == code)].mean()),
                                 "opposed_corners": int((dots[keep & (codes == code)] < 0).sum()),
                                 "unflat_corners": int((dots[keep & (codes == code)] < 0.999).sum()),
                                 "corners": int((keep & (codes == code)).sum())}
                for code in numpy.unique(codes[keep])}
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
        report["images"] = len(bpy.data.images)
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
