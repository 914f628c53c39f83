#!/usr/bin/env bash
# consumers.animation: three.js, in Debian's chromium, plays what `dawnforge anim` writes with
# its own GLTFLoader and AnimationMixer (browser/animation.mjs), and every piece at every frame
# must stand where transforms.bin puts it: within 1 mm and 0.1 degrees (check.py anim). The
# same check on a copy whose keys were moved 5 mm must fail. Blender plays the same files in
# consumers.blender.
#
# usage: animation.sh DAWNFORGE_EXE WORK_DIR      (exit 77: the browser is not installed)
set -euo pipefail
exe=$1 work=$2
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=browser/common.sh
source "$here/browser/common.sh"
need_browser
enter_work "$work"

# The inputs (what the commands print goes to inputs.log): CGAL's elephant blown apart (pieces
# in flight: a key at nearly every frame), and a building of a generated city hit by a ball
# (most pieces rest: two keys a channel).
{
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz --strip-components=2 data/meshes/elephant.off
  "$exe" -q fracture elephant.off -o fracture --pieces 24 --seed 3
  "$exe" -q simulate fracture -o sim --frames 24 --explosion 0,-0.3,0 --explosion-speed 78 --explosion-radius 2 \
    --trigger-time 0.1
  "$exe" -q anim sim -o elephant.glb
  "$exe" -q city -o city --size 120x100 --seed 3
  target=$(python3 "$here/aim.py" city/city.json 1)
  "$exe" -q fracture city --building 1 -o building_fracture --pieces 40
  "$exe" -q simulate building_fracture -o building_sim --frames 40 --projectile "$target" --projectile-radius 1.5
  "$exe" -q anim building_sim -o building.glb
  python3 "$here/blender/anim_compare.py" --mutate building.glb mutant.glb
} >inputs.log 2>&1

play() {  # play REPORT GLB SIM_DIR
  local frames fps
  read -r frames fps < <(python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print(j['frames'], j['fps'])" "$3/sim.json")
  run_page "$1" animation.html "$work" --query "glb=$2" --query "fps=$fps" --query "frames=$frames" || { cat "$1"; exit 1; }
}
play elephant.json elephant.glb sim
python3 "$here/check.py" anim elephant.json sim
play building.json building.glb building_sim
python3 "$here/check.py" anim building.json building_sim
play mutant.json mutant.glb building_sim
if python3 "$here/check.py" anim mutant.json building_sim >mutant.txt; then
  echo "FAILED: the check did not notice keys moved 5 mm: $(cat mutant.txt)"
  exit 1
fi
echo "ok: keys moved 5 mm are caught: $(cut -c1-160 mutant.txt)"
