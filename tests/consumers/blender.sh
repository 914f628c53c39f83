#!/usr/bin/env bash
# consumers.blender: Blender's own glTF importer reads every kind of GLB dawnforge writes, and
# what it ends up with (objects, meshes, UV maps, materials, pictures, triangles, bounds, ...) is
# checked against figures that share nothing with the product: the GLB read with Python's struct
# and json, and the JSON reports dawnforge writes beside it (tests/consumers/blender/README.md).
#
#   bash tests/consumers/blender.sh DAWNFORGE_EXE WORK_DIR
#
# Exit 0: every check passed and every broken copy (mutant) was caught; 1: a check failed
# (the lines starting with FAIL say what differed); 77: Blender, or the NumPy its glTF
# importer needs, is not installed.
set -euo pipefail

if [ $# -ne 2 ]; then
  echo "usage: $0 DAWNFORGE_EXE WORK_DIR" >&2
  exit 2
fi
exe=$(realpath "$1")
work=$(realpath -m "$2")
here=$(cd "$(dirname "$0")/blender" && pwd)
case "$work" in
  / | "$HOME" | "$(realpath -m .)") echo "$0: refusing to empty $work" >&2; exit 2 ;;
esac

if ! command -v blender >/dev/null 2>&1; then
  echo "consumers.blender: skipped: blender is not installed (Debian: apt-get install blender python3-numpy)"
  exit 77
fi
if ! command -v python3 >/dev/null 2>&1; then
  echo "consumers.blender: skipped: python3 is not installed"
  exit 77
fi
start=$(date +%s)
export PYTHONDONTWRITEBYTECODE=1  # nothing written into the source tree

rm -rf "$work"
mkdir -p "$work"
cd "$work"

# The inputs: a small district (one tile, its trees and lamps), a fracture of the U prism of
# tests/data into 20 cells (21 pieces: a cell across the notch makes two), 12 frames of it
# falling apart as VATs in every preset (native one row per frame, unity and unreal several),
# and the Pivot Painter files of the city's node hierarchy.
df() {
  if ! "$exe" --quiet "$@" >/dev/null; then
    echo "FAIL: dawnforge $* failed (see its message above)"
    exit 1
  fi
}
data=$(cd "$here/../../data" && pwd)
df city -o city --size 120x100 --seed 3 --threads 2
df fracture "$data/u_prism.obj" -o fracture --pieces 20 --seed 2 --threads 2
# Without debris or dust: the VATs below are checked piece by piece against fracture.json (the
# building's animation further down carries its chips).
df simulate fracture -o sim --frames 12 --collapse --no-debris --no-dust --threads 2
df vat sim -o vat_native --preset native --name vat_native
df vat sim -o vat_unity --preset unity --name vat_unity --max-width 8
df vat sim -o vat_unreal --preset unreal --name vat_unreal --max-width 6
df pivots city/city.glb -o pivots --name city_pivots

# Broken copies, which the checks must catch.
python3 "$here/check.py" mutate "$work"
mapfile -t files < <(python3 "$here/check.py" files "$work")

# One Blender process imports them all, each into an empty file.
set +e
blender -b --factory-startup --python-exit-code 1 --python "$here/import_report.py" -- \
  "$work/report.jsonl" "${files[@]}" >"$work/blender.log" 2>&1
status=$?
set -e
if grep -q "No module named 'numpy'" "$work/blender.log"; then
  echo "consumers.blender: skipped: Blender's Python has no NumPy, which its glTF importer needs (Debian: apt-get install python3-numpy)"
  exit 77
fi
if [ ! -s "$work/report.jsonl" ]; then
  echo "FAIL blender exited $status and reported nothing; the end of $work/blender.log:"
  tail -n 20 "$work/blender.log"
  exit 1
fi
[ $status -eq 0 ] || echo "blender exited $status (an import failed; see below and $work/blender.log)"

set +e
python3 "$here/check.py" check "$work" "$work/report.jsonl"
result=$?
set -e
# The simulation as a glTF animation (dawnforge anim), played by Blender frame by frame: every
# piece within 1 mm and 0.1 degrees of transforms.bin (blender/anim_compare.py); a building hit by
# a ball, whose resting pieces keep two keys a channel; and a copy with one piece's keys moved
# 5 mm, which must be caught.
target=$(python3 "$here/../aim.py" city/city.json 1)
df fracture city --building 1 -o building_fracture --pieces 40 --threads 2
df simulate building_fracture -o building_sim --frames 40 --projectile "$target" --projectile-radius 1.5 --threads 2
df anim sim -o anim_u_prism.glb
df anim building_sim -o anim_building.glb
python3 "$here/anim_compare.py" --mutate anim_building.glb anim_mutant.glb
play() {  # play GLB SIM_DIR: Blender's matrices at every frame, in GLB.json
  local frames fps
  read -r frames fps < <(python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print(j['frames'], j['fps'])" "$2/sim.json")
  blender -b --factory-startup --python-exit-code 1 --python "$here/anim_play.py" -- "$1" "$fps" "$frames" "$1.json" \
    >>"$work/blender_anim.log" 2>&1 || { echo "FAIL blender could not play $1 (see $work/blender_anim.log)"; result=1; }
}
play anim_u_prism.glb sim
play anim_building.glb building_sim
play anim_mutant.glb building_sim
python3 "$here/anim_compare.py" sim anim_u_prism.glb.json || result=1
python3 "$here/anim_compare.py" building_sim anim_building.glb.json || result=1
if python3 "$here/anim_compare.py" building_sim anim_mutant.glb.json >mutant.txt; then
  echo "FAIL the animation check did not notice keys moved 5 mm: $(cat mutant.txt)"
  result=1
else
  echo "ok: keys moved 5 mm are caught: $(head -c 160 mutant.txt)"
fi

echo "consumers.blender: ${#files[@]} files imported, $(( $(date +%s) - start )) s"
if [ $result -ne 0 ] || [ $status -ne 0 ]; then
  echo "consumers.blender: FAILED (the FAIL lines above say what Blender saw and what was expected)"
  exit 1
fi
echo "consumers.blender: passed"
