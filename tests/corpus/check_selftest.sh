#!/usr/bin/env bash
# Self-test of fracture_check: it must pass a clean fracture and fail, with the right check named,
# on deliberately broken copies of it.
#
#   tests/corpus/check_selftest.sh [CHECKER] [DAWNFORGE]
#
# CHECKER defaults to a fresh build of tests/corpus/fracture_check.cpp in the work folder,
# DAWNFORGE to build/bin/dawnforge. Needs python3. Exits 0 when every case behaves.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
checker=${1:-}
dawnforge=${2:-$root/build/bin/dawnforge}
if [[ -z $checker ]]; then
  checker=$work/fracture_check
  g++ -std=c++20 -O2 -o "$checker" "$here/fracture_check.cpp"
fi

# A closed input with no flat faces meeting at edges: an icosphere (3 subdivisions, radius 2, off
# the origin so that pivots and world positions differ).
python3 - "$work/ball.obj" <<'EOF'
import math, sys
t = (1 + 5 ** 0.5) / 2
V = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
     (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
F = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
     (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
     (8, 6, 7), (9, 8, 1)]
V = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in V]
for _ in range(3):
    mid, G = {}, []
    def m(a, b):
        k = (min(a, b), max(a, b))
        if k not in mid:
            p = [(V[a][i] + V[b][i]) / 2 for i in range(3)]
            n = math.sqrt(sum(x * x for x in p))
            V.append(tuple(x / n for x in p)); mid[k] = len(V) - 1
        return mid[k]
    for a, b, c in F:
        ab, bc, ca = m(a, b), m(b, c), m(c, a)
        G += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    F = G
with open(sys.argv[1], "w") as f:
    for v in V: f.write("v %.9f %.9f %.9f\n" % (2 * v[0] + 5, 2 * v[1] - 1, 2 * v[2] + 0.5))
    for a, b, c in F: f.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))
EOF
"$dawnforge" -q inspect "$work/ball.obj" --repair "$work/ball.glb" >/dev/null
"$dawnforge" -q fracture "$work/ball.obj" -o "$work/good" --pieces 20 --seed 3 >/dev/null

# corrupt.py KIND IN_DIR OUT_DIR: a copy of a fracture folder with one defect.
cat >"$work/corrupt.py" <<'EOF'
import json, shutil, struct, sys
kind, src, dst = sys.argv[1:4]
shutil.copytree(src, dst)
glb = open(f"{dst}/fragments.glb", "rb").read()
jlen = struct.unpack_from("<I", glb, 12)[0]
doc = json.loads(glb[20:20 + jlen])
blen = struct.unpack_from("<I", glb, 20 + jlen)[0]
binary = bytearray(glb[28 + jlen:28 + jlen + blen])
frac = json.load(open(f"{dst}/fracture.json"))

def indices(piece):  # (offset in binary, format) of the index accessor of a piece's primitive
    acc = doc["accessors"][doc["meshes"][doc["nodes"][piece]["mesh"]]["primitives"][0]["indices"]]
    view = doc["bufferViews"][acc["bufferView"]]
    return acc, view.get("byteOffset", 0) + acc.get("byteOffset", 0), {5121: "B", 5123: "H", 5125: "I"}[acc["componentType"]]

def positions(piece):
    acc = doc["accessors"][doc["meshes"][doc["nodes"][piece]["mesh"]]["primitives"][0]["attributes"]["POSITION"]]
    view = doc["bufferViews"][acc["bufferView"]]
    return acc, view.get("byteOffset", 0) + acc.get("byteOffset", 0)

piece = 3
if kind == "flip":          # one triangle turned inside out
    acc, off, f = indices(piece)
    s = struct.calcsize(f)
    a, b = struct.unpack_from("<2" + f, binary, off + s)
    struct.pack_into("<2" + f, binary, off + s, b, a)
elif kind == "drop":        # the last triangle of a piece removed
    acc, off, f = indices(piece)
    acc["count"] -= 3
elif kind == "move":        # a piece moved by a fifth of its size into its neighbours
    acc, off = positions(piece)
    size = max(h - l for h, l in zip(acc["max"], acc["min"]))
    doc["nodes"][piece]["translation"][0] += 0.2 * size
elif kind == "collapse":    # one corner of a triangle moved onto another: a degenerate triangle
    acc, off, f = indices(piece)
    s = struct.calcsize(f)
    i0, i1 = struct.unpack_from("<2" + f, binary, off)
    pacc, poff = positions(piece)
    binary[poff + 12 * i1:poff + 12 * i1 + 12] = binary[poff + 12 * i0:poff + 12 * i0 + 12]
elif kind == "remove":      # a piece missing from the scene and the json
    doc["scenes"][0]["nodes"].pop()
    frac["pieces"].pop()
    n = len(frac["pieces"])
    frac["bonds"] = [b for b in frac["bonds"] if b["b"] < n]
elif kind == "volume":      # fracture.json's volume of a piece off by 1%
    frac["pieces"][piece]["volume"] *= 1.01
elif kind == "bond_normal": # a bond's normal from b to a
    frac["bonds"][0]["normal"] = [-x for x in frac["bonds"][0]["normal"]]
elif kind == "bond_drop":   # a bond between two touching pieces missing
    frac["bonds"].pop(0)
elif kind == "bond_centroid":  # a bond's centroid off the shared face
    frac["bonds"][0]["centroid"][1] += 0.1
elif kind == "truncate":    # an unreadable file
    open(f"{dst}/fragments.glb", "wb").write(glb[:len(glb) // 2])
    sys.exit(0)
else:
    sys.exit(f"unknown corruption {kind}")

jbytes = json.dumps(doc).encode()
jbytes += b" " * (-len(jbytes) % 4)
binary += b"\0" * (-len(binary) % 4)
out = struct.pack("<III", 0x46546C67, 2, 28 + len(jbytes) + len(binary))
out += struct.pack("<II", len(jbytes), 0x4E4F534A) + jbytes + struct.pack("<II", len(binary), 0x004E4942) + bytes(binary)
open(f"{dst}/fragments.glb", "wb").write(out)
json.dump(frac, open(f"{dst}/fracture.json", "w"))
EOF

failed=0
# expect NAME EXIT_CODE CHECK: run the checker on $work/NAME, expect that exit code and, for exit 1,
# that CHECK is among the failed checks.
expect() {
  local name=$1 want=$2 check=$3 rc=0
  "$checker" "$work/$name" "$work/ball.glb" >"$work/$name.json" || rc=$?
  local got
  got=$(python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(" ".join(d.get("failure_counts", {})) or d.get("error", "-"))' "$work/$name.json")
  if [[ $rc != "$want" ]] || [[ $want == 1 && " $got " != *" $check "* ]]; then
    echo "FAIL $name: exit $rc (want $want), failed checks: $got (want $check)"
    failed=1
  else
    echo "ok   $name: exit $rc, failed checks: $got"
  fi
}

expect good 0 -
for case in flip:orientation drop:not_closed move:overlap move:pivot collapse:degenerate remove:volume_sum \
            remove:coverage volume:piece_volume bond_normal:bond_normal bond_drop:missing_bond \
            bond_centroid:bond_centroid; do
  kind=${case%%:*}
  [[ -d $work/$kind ]] || python3 "$work/corrupt.py" "$kind" "$work/good" "$work/$kind"
  expect "$kind" 1 "${case#*:}"
done
python3 "$work/corrupt.py" truncate "$work/good" "$work/truncate"
expect truncate 2 -

# The reference may come as OBJ, or as a GLB whose mesh sits under node transforms.
python3 - "$work/ball.obj" "$work/ball_nodes.glb" <<'EOF'
import json, math, struct, sys
V, F = [], []
for line in open(sys.argv[1]):
    t = line.split()
    if t and t[0] == "v": V.append([float(x) for x in t[1:4]])
    if t and t[0] == "f": F += [int(x) - 1 for x in t[1:4]]
# world = P + T R S local, R = 90 degrees about z: local = S^-1 R^-1 (world - P - T)
P, T, S = (1.0, 2.0, 3.0), (0.5, -0.25, 0.125), 2.0
local = []
for x, y, z in V:
    x, y, z = x - P[0] - T[0], y - P[1] - T[1], z - P[2] - T[2]
    local.append((y / S, -x / S, z / S))
pos = b"".join(struct.pack("<3f", *p) for p in local)
idx = b"".join(struct.pack("<I", i) for i in F)
doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
       "nodes": [{"translation": list(P), "children": [1]},
                 {"translation": list(T), "rotation": [0, 0, math.sin(math.pi / 4), math.cos(math.pi / 4)],
                  "scale": [S, S, S], "mesh": 0}],
       "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}],
       "buffers": [{"byteLength": len(pos) + len(idx)}],
       "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
                       {"buffer": 0, "byteOffset": len(pos), "byteLength": len(idx)}],
       "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(local), "type": "VEC3",
                      "min": [min(p[i] for p in local) for i in range(3)], "max": [max(p[i] for p in local) for i in range(3)]},
                     {"bufferView": 1, "componentType": 5125, "count": len(F), "type": "SCALAR"}]}
j = json.dumps(doc).encode(); j += b" " * (-len(j) % 4)
b = pos + idx; b += b"\0" * (-len(b) % 4)
out = struct.pack("<III", 0x46546C67, 2, 28 + len(j) + len(b)) + struct.pack("<II", len(j), 0x4E4F534A) + j
open(sys.argv[2], "wb").write(out + struct.pack("<II", len(b), 0x004E4942) + b)
EOF
for ref in ball.obj ball_nodes.glb; do
  rc=0
  "$checker" "$work/good" "$work/$ref" >"$work/ref.json" || rc=$?
  if [[ $rc == 0 ]]; then
    echo "ok   good against $ref: exit 0"
  else
    echo "FAIL good against $ref: exit $rc"
    cat "$work/ref.json"
    failed=1
  fi
done
exit $failed
