#!/usr/bin/env bash
# Contact damage against the speed of the blow: a 20 t ball of radius 1.5 m thrown along +x at
# the middle of a generated building's -x face (building 2's street front; its +z face is a
# party wall), at its second storey (4.5 m above its base), at
# 5, 7.5, 10, 15, 20, 30 and 40 m/s, 150 frames each, in its city; every figure read back from
# the files as written (bench/damage_sweep.py says how).
#
#   bench/damage_sweep.sh DAWNFORGE [BUILDING [SPEEDS...]] [-- SIMULATE_OPTIONS...]
#
# BUILDING: the id of a building of the default recipe's 400 x 400 m district, seed 1 (default
# 2, 4 storeys, fractured with `fracture --building` into 400 Voronoi cells, 1,093 pieces). Keeps its folders in
# $DAMAGE_SWEEP_KEEP when that is set. DAMAGE_SWEEP_REFINE=R fractures it again with the cells
# clustered within R m of the contact (`--impact CONTACT --radius R`, as the demo fractures its
# building), the way an artist who knows where the blow lands would.
set -euo pipefail
here=$(dirname "$(realpath "$0")")
dawnforge=$(realpath "$1")
shift
building=${1:-2}
[ $# -gt 0 ] && shift
speeds=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do speeds+=("$1"); shift; done
[ $# -gt 0 ] && shift
[ ${#speeds[@]} -gt 0 ] || speeds=(5 7.5 10 15 20 30 40)
work=${DAMAGE_SWEEP_KEEP:-$(mktemp -d)}
[ -n "${DAMAGE_SWEEP_KEEP:-}" ] || trap 'rm -rf "$work"' EXIT
mkdir -p "$work"
[ -f "$work/city/city.json" ] || "$dawnforge" --quiet city -o "$work/city" --size 400x400 >/dev/null
[ -f "$work/fracture/fracture.json" ] ||
  "$dawnforge" --quiet fracture "$work/city" --building "$building" -o "$work/fracture" --pieces 400 >/dev/null

# The target: mid-depth of the -x face, 4.5 m above the base; the contact: where a ball of
# radius 1.5 m on that line first meets a piece's vertex.
aim() {
python3 - "$work/fracture/fracture.json" "$work/fracture/fragments.glb" <<'PY'
import json, struct, sys
f = json.load(open(sys.argv[1]))
data = open(sys.argv[2], "rb").read()
length, = struct.unpack_from("<I", data, 12)
gltf = json.loads(data[20:20 + length])
binary = data[20 + length + 8:]
points = []
for node in gltf["nodes"]:
    if "mesh" not in node: continue
    t = node.get("translation", [0, 0, 0])
    acc = gltf["accessors"][gltf["meshes"][node["mesh"]]["primitives"][0]["attributes"]["POSITION"]]
    view = gltf["bufferViews"][acc["bufferView"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    stride = view.get("byteStride", 12)
    for v in range(acc["count"]):
        x, y, z = struct.unpack_from("<3f", binary, start + v * stride)
        points.append((x + t[0], y + t[1], z + t[2]))
lo = [min(p[c] for p in points) for c in range(3)]
hi = [max(p[c] for p in points) for c in range(3)]
z, y = (lo[2] + hi[2]) / 2, lo[1] + 4.5
x = min(p[0] for p in points if (p[2] - z) ** 2 + (p[1] - y) ** 2 <= 1.5 ** 2)
print(f"{lo[0]},{y},{z} {x},{y},{z}")
PY
}
read -r target contact < <(aim)
if [ -n "${DAMAGE_SWEEP_REFINE:-}" ] && [ ! -f "$work/refined" ]; then
  "$dawnforge" --quiet fracture "$work/city" --building "$building" -o "$work/fracture" --pieces 400 \
    --impact "$contact" --radius "$DAMAGE_SWEEP_REFINE" >/dev/null
  touch "$work/refined"
  read -r target contact < <(aim)
fi
python3 "$here/damage_sweep.py" --header
for speed in "${speeds[@]}"; do
  out=$work/sim_$speed
  "$dawnforge" --quiet simulate "$work/fracture" -o "$out" --frames 150 --projectile "$target" --projectile-dir 1,0,0 \
    --projectile-mass 20000 --projectile-radius 1.5 --projectile-speed "$speed" "$@" >/dev/null
  python3 "$here/damage_sweep.py" "$work/fracture" "$out" "$contact"
done
echo "building $building, contact $contact, $(python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print(len(j['pieces']), 'pieces,', len(j['bonds']), 'bonds')" "$work/fracture/fracture.json")"
