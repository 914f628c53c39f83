#!/usr/bin/env bash
# consumers.cesium: CesiumJS (npm cesium, in Debian's chromium, headless, WebGL 2 on SwiftShader)
# loads a world that `dawnforge world build` wrote, placed on the globe by its plan's --origin
# (browser/cesium.mjs): the plan's origin must land where plan.json says in Cesium's own WGS84
# arithmetic, a far camera must draw the HLOD alone, a near one every tile, and every content
# must load, and a building picked from above must carry its city.json properties (check.py
# cesium). Then a copy of the world whose tileset.json has no root transform
# (the world at the Earth's centre, as before the georeference) must fail the same check.
#
# usage: cesium.sh DAWNFORGE_EXE WORK_DIR      (exit 77: the browser or cesium is not installed)
set -euo pipefail
exe=$1 work=$2
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=browser/common.sh
source "$here/browser/common.sh"
need_browser
[ -f "$BROWSER_DIR/node_modules/cesium/Build/Cesium/Cesium.js" ] || {
  echo "skipped: npm package cesium not installed (./run installs it with npm ci in tests/consumers/browser)"
  exit 77
}
enter_work "$work"

# A 256 m world in 2 x 2 tiles of 128 m on the Golden Gate's south end, 20 m up: not the default.
{
  "$exe" -q world plan world --size 256x256 --tile-size 128 --seed 5 --origin -122.4783,37.8080,20
  "$exe" -q world build world --stages city,hlod
} >inputs.log 2>&1 || { tail -n 3 inputs.log; exit 1; }

run_page cesium.json cesium.html world --timeout 300 --screenshot near.png || { cat cesium.json; exit 1; }
python3 "$here/check.py" cesium cesium.json world/plan.json

# The check must see a world that is not on the globe.
mkdir -p flat
ln -s "$work/world/hlod" flat/hlod
ln -s "$work/world/tiles" flat/tiles
ln -s "$work/world/textures" flat/textures
cp world/plan.json flat/plan.json
python3 - world/tileset.json flat/tileset.json <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))
del t["root"]["transform"]
json.dump(t, open(sys.argv[2], "w"))
PY
if run_page flat.json cesium.html flat --timeout 300 && python3 "$here/check.py" cesium flat.json flat/plan.json >flat.txt; then
  echo "FAILED: the check passed a world without its root transform"
  exit 1
fi
echo "ok: a world without its root transform is refused: $(cut -c1-200 flat.txt 2>/dev/null || head -c 200 flat.json)"
