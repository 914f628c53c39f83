#!/usr/bin/env bash
# consumers.pivot_painter: three.js, in Debian's chromium, reads each tree species' Pivot Painter
# 2 files the way Unreal's Pivot Painter 2 material functions do (browser/pivots.mjs), for every
# vertex of the species mesh, and what they give must match the tree's node hierarchy in city.glb:
# the element, its parent, its pivot, X axis and extent. Then files broken on purpose (V from the
# bottom, pivots left in glTF axes) must fail.
#
# usage: pivot_painter.sh DAWNFORGE_EXE WORK_DIR      (exit 77: the browser is not installed)
set -euo pipefail
exe=$1 work=$2
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=browser/common.sh
source "$here/browser/common.sh"
need_browser
enter_work "$work"

"$exe" -q city -o city --size 200x160 --seed 4 >city.log
species=$(python3 -c "import json; print(' '.join(s['name'] for s in json.load(open('city/city.json'))['tree_species']))")
[ -n "$species" ] || { echo "FAILED: the city has no tree species"; exit 1; }

read_species() {  # read_species REPORT SPECIES [MUTATION]
  local query=(--query city=city --query "species=$2")
  [ $# -lt 3 ] || query+=(--query "mutate=$3")
  run_page "$1" pivots.html "$work" "${query[@]}" || { cat "$1"; exit 1; }
}

for s in $species; do
  read_species "$s.json" "$s"
  python3 "$here/check.py" pivots "$s.json"
done

first=${species%% *}
for mutation in uv-v-from-bottom pivots-in-gltf-axes; do
  read_species broken.json "$first" "$mutation"
  if python3 "$here/check.py" pivots broken.json >broken.txt; then
    echo "FAILED: the Pivot Painter check did not notice $first's files with $mutation"
    exit 1
  fi
  echo "ok: $first with $mutation is refused: $(cut -c1-200 broken.txt)"
done
