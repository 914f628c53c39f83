#!/usr/bin/env bash
# The VAT forms on the demo's building (docs/vat.md): the demo's district, its building 14
# fractured and hit by the demo's ball (as bench/demo_building.sh), then `vat` in HDR float32,
# half, Non-HDR and Non-HDR with one position texture (unity preset). Prints, per form, the
# texture files' size, the size in the engine (W × height × bytes per texel × textures) and the
# worst errors _data.json states.
# usage: bench/vat_forms.sh DAWNFORGE_EXE
set -euo pipefail
dawnforge=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
echo '{"coast": {"water": 0.3}}' >demo.json
"$dawnforge" --quiet city -o demo --size 320x280 --tile-size 160 --recipe demo.json >/dev/null
"$dawnforge" --quiet fracture demo --building 14 -o probe --pieces 12 >/dev/null
target=$(python3 "$here/demo_impact.py" probe)
"$dawnforge" --quiet fracture demo --building 14 -o fracture --pieces 120 --shard-size 0.8 --impact "$target" \
  --radius 5 >/dev/null
"$dawnforge" --quiet simulate fracture -o sim --frames 240 --projectile "$target" --projectile-dir 0,0,-1 \
  --projectile-radius 1.5 >/dev/null
"$dawnforge" --quiet vat sim -o vat --preset unity --name f32 >/dev/null
"$dawnforge" --quiet vat sim -o vat --preset unity --name half --half >/dev/null
"$dawnforge" --quiet vat sim -o vat --preset unity --name ldr --format ldr >/dev/null
"$dawnforge" --quiet vat sim -o vat --preset unity --name ldr1 --format ldr --single-position-texture >/dev/null
/usr/bin/python3 - vat <<'PY'
import glob, json, math, os, sys
d = sys.argv[1]
print(f"{'form':6} {'files MB':>9} {'engine MB':>10} {'position mm':>12} {'rotation deg':>13} {'vertex cm':>10}")
for name, bytes_per_texel in (("f32", 16), ("half", 8), ("ldr", 4), ("ldr1", 4)):
    j = json.load(open(f"{d}/{name}_data.json"))
    files = [f for f in glob.glob(f"{d}/{name}_*") if not f.endswith(("_mesh.glb", "_data.json"))]
    engine = j["W"] * j["height"] * bytes_per_texel * len(files)
    print(f"{name:6} {sum(map(os.path.getsize, files)) / 1e6:9.3f} {engine / 1e6:10.2f} "
          f"{j['max_position_error'] * 1e3:12.2f} {math.degrees(j['max_rotation_error']):13.4f} "
          f"{j['max_vertex_error'] * 1e2:10.2f}")
PY
