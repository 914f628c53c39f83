"""What Blender should show for a GLB, worked out from the file itself with glb.py (no Blender,
no dawnforge code): the objects of the scene's node tree, their world matrices, and for every
mesh its vertex and triangle counts, per-corner UV statistics, colour histogram, normal sum and
volume, all in Blender's terms.

Blender's glTF importer (io_scene_gltf2, Blender 3.4, default options) is assumed to:
- make one object per node of the scene (a node without a mesh becomes an EMPTY), named like
  the node, parented like the node; one Blender mesh per glTF mesh, shared by its instances;
- turn glTF's +Y up into Blender's +Z up: a point (x, y, z) becomes (x, -z, y), a world matrix
  W becomes C W C^-1 with C that rotation;
- keep, per primitive, the vertices that the indices use, unmerged (merge_vertices is off);
  one face per index triple, in index order (so corners follow the index buffer);
- make a UV map per TEXCOORD_n, n = 0, 1, ... while the set exists, named UVMap, UVMap.001, ...
  and holding (u, 1 - v);
- make a colour attribute "Col" on the face corners from COLOR_0;
- set the normals as custom split normals.
"""

import math
from collections import Counter

from glb import Glb

# glTF -> Blender axes: (x, y, z) -> (x, -z, y).
AXES = ((1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (0.0, 1.0, 0.0))


def to_blender(p):
    return (p[0], -p[2], p[1])


def bounds_to_blender(lo, hi):
    a, b = to_blender(lo), to_blender(hi)
    return [min(x, y) for x, y in zip(a, b)], [max(x, y) for x, y in zip(a, b)]


def identity():
    return [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def node_matrix(node):
    if "matrix" in node:
        m = node["matrix"]  # column-major
        return [[m[c * 4 + r] for c in range(4)] for r in range(4)]
    tx, ty, tz = node.get("translation", (0.0, 0.0, 0.0))
    qx, qy, qz, qw = node.get("rotation", (0.0, 0.0, 0.0, 1.0))
    sx, sy, sz = node.get("scale", (1.0, 1.0, 1.0))
    r = [[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
         [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
         [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]]
    s = (sx, sy, sz)
    return [[r[i][0] * s[0], r[i][1] * s[1], r[i][2] * s[2], (tx, ty, tz)[i]] for i in range(3)] + [[0.0, 0.0, 0.0, 1.0]]


def matrix_to_blender(m):
    c = [list(row) + [0.0] for row in AXES] + [[0.0, 0.0, 0.0, 1.0]]
    ct = [[c[j][i] for j in range(4)] for i in range(4)]
    return matmul(matmul(c, m), ct)


def transform(m, p):
    return tuple(m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3] for i in range(3))


def det3(m):
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


_CODES = {}


def colour_code(rgba):
    """The material ID a colour carries: R + 2G + 4B + 8A, each channel thresholded at 0.5."""
    code = _CODES.get(rgba)
    if code is None:
        code = _CODES[rgba] = sum(1 << i for i in range(4) if rgba[i] > 0.5)
    return code


class Stats:
    """min, max, sum and count of 2D values, as import_report.py reports them."""

    __slots__ = ("lo_u", "lo_v", "hi_u", "hi_v", "sum_u", "sum_v", "count")

    def __init__(self):
        self.lo_u = self.lo_v = math.inf
        self.hi_u = self.hi_v = -math.inf
        self.sum_u = self.sum_v = 0.0
        self.count = 0

    def add(self, u, v, times=1):
        if u < self.lo_u:
            self.lo_u = u
        if u > self.hi_u:
            self.hi_u = u
        if v < self.lo_v:
            self.lo_v = v
        if v > self.hi_v:
            self.hi_v = v
        self.sum_u += times * u
        self.sum_v += times * v
        self.count += times

    def as_dict(self):
        return {"min": [self.lo_u, self.lo_v], "max": [self.hi_u, self.hi_v],
                "sum": [self.sum_u, self.sum_v], "count": self.count}


class MeshFigures:
    """Blender's view of one glTF mesh, from the file."""

    def __init__(self, glb, mesh_index):
        mesh = glb.json["meshes"][mesh_index]
        self.name = mesh.get("name")
        self.vertices = 0
        self.triangles = 0
        self.degenerate_index_triangles = 0  # a repeated index: Blender's validate() drops them
        self.positions = []  # the positions the indices use (glTF axes, the mesh's own space)
        prims = [p for p in mesh["primitives"] if "POSITION" in p["attributes"]]
        num_uvs = max((self._count_sets(p, "TEXCOORD_") for p in prims), default=0)
        num_cols = max((self._count_sets(p, "COLOR_") for p in prims), default=0)
        self.uv_names = ["UVMap" if i == 0 else "UVMap.%03d" % i for i in range(num_uvs)]
        self.colour_names = ["Col" if i == 0 else "Col.%03d" % i for i in range(num_cols)]
        self.uv = [Stats() for _ in range(num_uvs)]
        self.uv_by_colour = [{} for _ in range(num_uvs)]
        self.histograms = [Counter() for _ in range(num_cols)]
        self.normal_sum = [0.0, 0.0, 0.0]
        self.volume = 0.0
        self.has_normals = any("NORMAL" in p["attributes"] for p in prims)
        self.materials = set()
        for prim in prims:
            if prim.get("mode", 4) != 4:
                raise ValueError("%s: mesh %d: only triangle primitives are expected" % (glb.path, mesh_index))
            attrs = prim["attributes"]
            pos = glb.accessor(attrs["POSITION"])
            idx = glb.accessor(prim["indices"]) if "indices" in prim else list(range(len(pos)))
            used = sorted(set(idx))
            self.vertices += len(used)
            self.positions.extend(pos[i] for i in used)
            self.triangles += len(idx) // 3
            if "material" in prim:
                self.materials.add(glb.json["materials"][prim["material"]].get("name"))
            for t in range(0, len(idx), 3):
                a, b, c = idx[t], idx[t + 1], idx[t + 2]
                if a == b or b == c or a == c:
                    self.degenerate_index_triangles += 1
                p0, p1, p2 = pos[a], pos[b], pos[c]
                self.volume += (p0[0] * (p1[1] * p2[2] - p1[2] * p2[1]) - p0[1] * (p1[0] * p2[2] - p1[2] * p2[0])
                                + p0[2] * (p1[0] * p2[1] - p1[1] * p2[0])) / 6.0
            # Every per-vertex value counts once per corner that uses the vertex.
            uses = Counter(idx)
            codes = None
            if num_cols:
                colours = glb.accessor(attrs["COLOR_0"]) if "COLOR_0" in attrs else None
                codes = {i: colour_code(colours[i]) if colours else 15 for i in uses}
            for n in range(num_cols):
                key = "COLOR_%d" % n
                if key in attrs:
                    values = glb.accessor(attrs[key])
                    for i, k in uses.items():
                        self.histograms[n][colour_code(values[i])] += k
                else:
                    self.histograms[n][15] += len(idx)  # Blender fills a missing set with white
            for n in range(num_uvs):
                key = "TEXCOORD_%d" % n
                values = glb.accessor(attrs[key]) if key in attrs else None
                by_colour = self.uv_by_colour[n]
                stats = self.uv[n]
                for i, k in uses.items():
                    u, v = values[i] if values else (0.0, 0.0)
                    v = 1.0 - v
                    stats.add(u, v, k)
                    if codes is not None:
                        code = codes[i]
                        if code not in by_colour:
                            by_colour[code] = Stats()
                        by_colour[code].add(u, v, k)
            if "NORMAL" in attrs:
                normals = glb.accessor(attrs["NORMAL"])
                for i, k in uses.items():
                    x, y, z = normals[i]
                    self.normal_sum[0] += k * x
                    self.normal_sum[1] -= k * z
                    self.normal_sum[2] += k * y

    @staticmethod
    def _count_sets(prim, prefix):
        n = 0
        while n < 8 and ("%s%d" % (prefix, n)) in prim["attributes"]:
            n += 1
        return n


class FileFigures:
    """Blender's view of a whole GLB: objects (by node name) and meshes (by glTF index)."""

    def __init__(self, path):
        self.glb = Glb(path)
        doc = self.glb.json
        self.doc = doc
        scene = doc["scenes"][doc.get("scene", 0)]
        self.scene_extras = scene.get("extras", {})
        self.objects = {}  # name -> dict(type, parent, mesh, matrix (Blender), glTF world matrix)
        self.order = []
        self._meshes = {}

        def visit(index, parent_name, parent_world):
            node = doc["nodes"][index]
            world = matmul(parent_world, node_matrix(node))
            name = node.get("name", "Node_%d" % index)
            self.objects[name] = {
                "type": "MESH" if "mesh" in node else "EMPTY",
                "parent": parent_name,
                "mesh": node.get("mesh"),
                "world": world,
                "matrix": matrix_to_blender(world),
                "extras": node.get("extras", {}),
            }
            self.order.append(name)
            for child in node.get("children", []):
                visit(child, name, world)

        for root in scene.get("nodes", []):
            visit(root, None, identity())

    def mesh(self, index):
        if index not in self._meshes:
            self._meshes[index] = MeshFigures(self.glb, index)
        return self._meshes[index]

    def world_bounds(self, name):
        """The Blender-axes world bounds of a mesh object's vertices."""
        obj = self.objects[name]
        m = obj["world"]
        points = self.mesh(obj["mesh"]).positions
        if m != identity():
            points = [transform(m, p) for p in points]
        if not points:
            return [math.inf] * 3, [-math.inf] * 3
        lo = [min(p[k] for p in points) for k in range(3)]
        hi = [max(p[k] for p in points) for k in range(3)]
        return bounds_to_blender(lo, hi)

    def world_volume(self, name):
        obj = self.objects[name]
        return self.mesh(obj["mesh"]).volume * det3(obj["world"])
