"""What Blender should show for a GLB, worked out from the file itself with glb.py (no Blender,
no dawnforge code): the objects of the scene's node tree, their world matrices, and for every
mesh its vertex and triangle counts, material slots and the triangles of each, per-corner UV
statistics (also per material), normal sum and volume, all in Blender's terms; and for every
material what its base colour should come from (a value, or an embedded picture of a size read
from the PNG's own header).

Blender's glTF importer (io_scene_gltf2, Blender 3.4, default options) is assumed to:
- make one object per node of the scene (a node without a mesh becomes an EMPTY), named like
  the node, parented like the node; one Blender mesh per glTF mesh, shared by its instances;
- turn glTF's +Y up into Blender's +Z up: a point (x, y, z) becomes (x, -z, y), a world matrix
  W becomes C W C^-1 with C that rotation;
- keep, per primitive, the vertices that the indices use, unmerged (merge_vertices is off);
  one face per index triple, in index order (so corners follow the index buffer);
- make a UV map per TEXCOORD_n, n = 0, 1, ... while the set exists, named UVMap, UVMap.001, ...
  and holding (u, 1 - v);
- make a colour attribute "Col" on the face corners from COLOR_0 (dawnforge writes none since
  the material ID became the custom attribute _MATERIAL_ID: no colour attribute is expected);
- leave out attributes whose names start with "_" (_MATERIAL_ID, _PIECE_ID): Blender 3.4 imports
  no custom attributes;
- give a mesh one material slot per distinct material of its primitives, in primitive order,
  and each face the slot of its primitive's material;
- set the normals as custom split normals;
- make each material a Principled BSDF whose base colour is baseColorFactor, or, with a
  baseColorTexture, an Image Texture node of image "Image_<source>" (the images have no names)
  fed through a Mapping node with KHR_texture_transform's scale.
"""

import math
import struct
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


MATERIALS = ["asphalt", "paving", "brick", "concrete", "plaster", "glass", "metal", "trim", "roof_tiles",
             "roof_flat", "wood", "interior_wall", "floor", "ground", "sand", "rubble"]


def material_id(name):
    """The material ID (0..15) a glTF material's name stands for ("brick_2": brick, 2; "leaves": a
    tree's ground cards, 13), or None ("default", or no name)."""
    if not name:
        return None
    if name == "leaves":
        return MATERIALS.index("ground")
    base, _, suffix = name.rpartition("_")
    if base and suffix.isdigit():
        name = base
    return MATERIALS.index(name) if name in MATERIALS else None


def png_size(data):
    """(width, height) from a PNG's IHDR chunk, or None when the bytes are no PNG."""
    if len(data) < 24 or data[:8] != b"\x89PNG\r\n\x1a\n" or data[12:16] != b"IHDR":
        return None
    return list(struct.unpack(">II", data[16:24]))


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
        self.primitives = len(prims)
        num_uvs = max((self._count_sets(p, "TEXCOORD_") for p in prims), default=0)
        num_cols = max((self._count_sets(p, "COLOR_") for p in prims), default=0)
        self.uv_names = ["UVMap" if i == 0 else "UVMap.%03d" % i for i in range(num_uvs)]
        self.colour_names = ["Col" if i == 0 else "Col.%03d" % i for i in range(num_cols)]
        self.uv = [Stats() for _ in range(num_uvs)]
        self.uv_by_material = [{} for _ in range(num_uvs)]
        self.normal_sum = [0.0, 0.0, 0.0]
        self.volume = 0.0
        self.has_normals = any("NORMAL" in p["attributes"] for p in prims)
        # Material slots: each distinct material of the primitives, in primitive order (None for
        # a primitive without one); the faces Blender keeps of each.
        self.slots = []
        self.triangles_by_material = Counter()
        # From _MATERIAL_ID, which Blender does not import: the IDs per corner, and the triangles
        # whose first vertex's ID is not the ID their primitive's material is named after.
        self.material_id_corners = Counter()
        self.material_id_mismatches = Counter()
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
            material = glb.json["materials"][prim["material"]].get("name") if "material" in prim else None
            if material not in self.slots:
                self.slots.append(material)
            ids = glb.accessor(attrs["_MATERIAL_ID"]) if "_MATERIAL_ID" in attrs else None
            want_id = material_id(material)
            for t in range(0, len(idx), 3):
                a, b, c = idx[t], idx[t + 1], idx[t + 2]
                if a == b or b == c or a == c:
                    self.degenerate_index_triangles += 1
                else:
                    self.triangles_by_material[material] += 1
                if ids is not None and want_id is not None and ids[a] != want_id:
                    self.material_id_mismatches[material] += 1
                p0, p1, p2 = pos[a], pos[b], pos[c]
                self.volume += (p0[0] * (p1[1] * p2[2] - p1[2] * p2[1]) - p0[1] * (p1[0] * p2[2] - p1[2] * p2[0])
                                + p0[2] * (p1[0] * p2[1] - p1[1] * p2[0])) / 6.0
            # Every per-vertex value counts once per corner that uses the vertex.
            uses = Counter(idx)
            if ids is not None:
                for i, k in uses.items():
                    self.material_id_corners[ids[i]] += k
            for n in range(num_uvs):
                key = "TEXCOORD_%d" % n
                values = glb.accessor(attrs[key]) if key in attrs else None
                by_material = self.uv_by_material[n].setdefault(material, Stats())
                stats = self.uv[n]
                for i, k in uses.items():
                    u, v = values[i] if values else (0.0, 0.0)
                    v = 1.0 - v
                    stats.add(u, v, k)
                    by_material.add(u, v, k)
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

    def material_figures(self):
        """name -> what Blender's material of that name should show: blend_method, and either
        base_colour (RGBA) or texture: image name, PNG size, embedded bytes, mapping scale."""
        out = {}
        for m in self.doc.get("materials", []):
            pbr = m.get("pbrMetallicRoughness", {})
            want = {"blend_method": {"BLEND": "BLEND", "MASK": "CLIP"}.get(m.get("alphaMode"), "OPAQUE"),
                    "base_colour": list(pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0])), "texture": None}
            info = pbr.get("baseColorTexture")
            if info is not None:
                source = self.doc["textures"][info["index"]]["source"]
                image = self.doc["images"][source]
                data = b""
                if "bufferView" in image:
                    view = self.doc["bufferViews"][image["bufferView"]]
                    data = self.glb.bin[view.get("byteOffset", 0): view.get("byteOffset", 0) + view["byteLength"]]
                transform = info.get("extensions", {}).get("KHR_texture_transform", {})
                sampler = self.doc["samplers"][self.doc["textures"][info["index"]]["sampler"]] \
                    if "sampler" in self.doc["textures"][info["index"]] else {}
                want["texture"] = {
                    "image": image.get("name") or "Image_%d" % source,
                    "mime_type": image.get("mimeType"),
                    "embedded_bytes": len(data) if "bufferView" in image else None,
                    "size": png_size(data),
                    "scale": list(transform.get("scale", [1.0, 1.0])),
                    "tex_coord": info.get("texCoord", 0),
                    "repeat": sampler.get("wrapS", 10497) == 10497 and sampler.get("wrapT", 10497) == 10497,
                }
            out[m.get("name")] = want
        return out

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
