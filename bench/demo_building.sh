#!/usr/bin/env bash
# The demo's destruction, timed: a building fractured as the demo fractures it and hit by the
# demo's ball (20 t at 40 m/s along -z, radius 1.5 m, at mid-width, 0.45 of the height, on its
# +z face), 240 frames in its city.
#
#   bench/demo_building.sh DAWNFORGE
#
# Buildings: the demo's (14 of its 320 x 280 m district: the same city.json as `dawnforge demo`),
# and a 4-storey (2) and a 13-storey (50) building of the default recipe's 400 x 400 m district,
# seed 1. Prints one line per building: pieces, bonds broken, bodies, chips and puffs of dust,
# the simulation's wall time (the whole `simulate` process, debris and dust included) and its
# peak memory.
set -euo pipefail
dawnforge=$(realpath "$1")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo '{"coast": {"water": 0.3}}' >"$work/demo.json"
"$dawnforge" --quiet city -o "$work/demo" --size 320x280 --tile-size 160 --recipe "$work/demo.json" >/dev/null
"$dawnforge" --quiet city -o "$work/large" --size 400x400 >/dev/null

# impact FRACTURE_DIR: the demo's impact point from the pieces' bounds in fragments.glb
impact() { python3 "$(dirname "$0")/demo_impact.py" "$1"; }

printf '%-22s %7s %13s %7s %6s %6s %8s %8s\n' building pieces broken bodies chips puffs seconds peak_MB
for case in "demo 14" "large 2" "large 50"; do
  read -r city id <<<"$case"
  dir=$work/$city-$id
  "$dawnforge" --quiet fracture "$work/$city" --building "$id" -o "$dir/probe" --pieces 12 >/dev/null
  target=$(impact "$dir/probe")
  "$dawnforge" --quiet fracture "$work/$city" --building "$id" -o "$dir/fracture" --pieces 120 --shard-size 0.8 \
    --impact "$target" --radius 5 >/dev/null
  /usr/bin/time -f "%e %M" -o "$dir/time" "$dawnforge" --quiet simulate "$dir/fracture" -o "$dir/sim" --frames 240 \
    --projectile "$target" --projectile-dir 0,0,-1 --projectile-radius 1.5 >/dev/null
  python3 - "$dir" "$city $id" <<'PY'
import json, sys
d, name = sys.argv[1:]
sim = json.load(open(f"{d}/sim/sim.json"))
glue, debris = sim["glue"], sim.get("debris", {})
seconds, kb = open(f"{d}/time").read().split()
chips, puffs = debris.get("chips", 0), debris.get("dust", {}).get("puffs", 0)
print(f"{name:<22} {sim['pieces'] - chips:7} {glue['broken']:6} of {glue['bonds']:<5} {glue.get('bodies', '-'):>6} "
      f"{chips:6} {puffs:6} {float(seconds):8.2f} {int(kb) / 1024:8.0f}")
PY
done
