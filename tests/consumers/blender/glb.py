"""A minimal GLB reader for the checks: the JSON chunk, the BIN chunk and accessors, with
nothing but struct and json (it shares no code with dawnforge or with Blender's importer)."""

import json
import struct

_COMPONENTS = {5120: ("b", 1), 5121: ("B", 1), 5122: ("h", 2), 5123: ("H", 2), 5125: ("I", 4), 5126: ("f", 4)}
_WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}
_NORMALIZED_MAX = {5120: 127.0, 5121: 255.0, 5122: 32767.0, 5123: 65535.0}


class Glb:
    def __init__(self, path):
        with open(path, "rb") as f:
            data = f.read()
        magic, version, length = struct.unpack_from("<4sII", data, 0)
        if magic != b"glTF" or version != 2 or length != len(data):
            raise ValueError("%s: not a GLB 2.0 file of its stated length" % path)
        self.json = None
        self.bin = b""
        offset = 12
        while offset < length:
            chunk_length, chunk_type = struct.unpack_from("<II", data, offset)
            body = data[offset + 8: offset + 8 + chunk_length]
            if chunk_type == 0x4E4F534A:
                self.json = json.loads(body.decode("utf-8"))
            elif chunk_type == 0x004E4942:
                self.bin = body
            offset += 8 + chunk_length
        if self.json is None:
            raise ValueError("%s: no JSON chunk" % path)
        self.path = path
        self._cache = {}

    def accessor(self, index):
        """The accessor's elements as a list of tuples (a list of numbers for SCALAR)."""
        if index in self._cache:
            return self._cache[index]
        acc = self.json["accessors"][index]
        fmt, size = _COMPONENTS[acc["componentType"]]
        width = _WIDTH[acc["type"]]
        count = acc["count"]
        view = self.json["bufferViews"][acc["bufferView"]]
        if view.get("buffer", 0) != 0:
            raise ValueError("only the GLB's own buffer is read")
        start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
        stride = view.get("byteStride", size * width)
        element = struct.Struct("<%d%s" % (width, fmt))
        if stride == element.size:
            values = list(element.iter_unpack(self.bin[start: start + count * stride]))
        else:
            values = [element.unpack_from(self.bin, start + i * stride) for i in range(count)]
        if acc.get("normalized"):
            scale = _NORMALIZED_MAX[acc["componentType"]]
            values = [tuple(max(c / scale, -1.0) for c in v) for v in values]
        if width == 1:
            values = [v[0] for v in values]
        self._cache[index] = values
        return values
