#!/usr/bin/env bash
# tiles.sh DAWNFORGE_EXE WORK_DIR   (CTest: consumers.tiles)
#
# A public OGC 3D Tiles reader nobody here wrote, NASA-AMMOS' 3d-tiles-renderer (three.js,
# WebGL 2 on SwiftShader in Debian's chromium, headless), loads a world that `dawnforge world
# build` wrote and shows it:
#   1. plans and builds a 256 m world in 2 x 2 tiles of 128 m, stages city and hlod: four
#      tiles/I_J/city.glb under one HLOD root, hlod/1_0_0.glb (no bake: the HLOD's GLB has the
#      same attributes and bytes without one, and the bake's files are nothing a reader loads)
#   2. opens browser/tiles.html (run-page.mjs) for a far view (the reader must stop at the HLOD
#      root) and a street view over tile 1_1 (its city.glb must replace the HLOD), each with a
#      screenshot, and checks each report with browser/tiles-check.mjs: no load error, what the
#      view needs loaded and visible, every bounding volume the reader computed equal to
#      tileset.json's box composed with the transforms (composed there, not by the reader), every
#      loaded content inside its box and its ancestors' (a leaf's box tight), the screenshot a
#      picture (not the clear colour, many colours)
#   3. self-test: the same check must fail on broken copies of the world (tileset.json edited, the
#      GLBs linked): a content uri naming a missing file; the HLOD's box moved 5 m east; a leaf
#      box's x and y extents swapped, another 0.5 m taller, a third tile's transform moved 3 m;
#      and on a report checked against a tileset it was not made from, and on a screenshot of
#      the clear colour alone
# Exit 0 when all holds; 1 with a one-line reason; 77 (skip) when node, chromium or the
# browser folder's node_modules are missing (./run installs them).
# shellcheck disable=SC2016  # the node -e scripts are JavaScript, in single quotes on purpose
set -uo pipefail

if [[ $# -ne 2 ]]; then
  echo "usage: tiles.sh DAWNFORGE_EXE WORK_DIR" >&2
  exit 2
fi
exe=$1
work=$2
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source=browser/common.sh
source "$here/browser/common.sh"
browser_dir=$BROWSER_DIR
clear=203040
started=$SECONDS

die() { echo "tiles.sh: FAIL: $*" >&2; exit 1; }

need_browser
[[ -x $exe ]] || die "$exe is not an executable"

rm -rf "$work"
mkdir -p "$work" || die "cannot make $work"
world=$work/world

# ---- 1. the world
t=$SECONDS
"$exe" -q world plan "$world" --size 256x256 --tile-size 128 --seed 5 >"$work/plan.log" 2>&1 ||
  die "world plan failed: $(tail -n 1 "$work/plan.log")"
"$exe" -q world build "$world" --stages city,hlod >"$work/build.log" 2>&1 ||
  die "world build failed: $(tail -n 1 "$work/build.log")"
[[ -f $world/tileset.json ]] || die "world build wrote no tileset.json"
echo "consumers.tiles: built a 2 x 2 tile world in $((SECONDS - t)) s: $world"

# view NAME DIR VIEW [TILE]: runs the page on DIR; its report goes to $work/NAME.json, its picture to $work/NAME.png
view() {
  local name=$1 dir=$2 v=$3 tile=${4:-}
  local q=(--query "view=$v" --query "clear=$clear" --query timeout=90)
  [[ -n $tile ]] && q+=(--query "tile=$tile")
  # run-page exits 1 when the page logged an error (a load error does): the check reads why
  node "$browser_dir/run-page.mjs" tiles.html "$dir" "${q[@]}" --size 640x480 --timeout 150 \
    --screenshot "$work/$name.png" >"$work/$name.json" 2>"$work/$name.err"
  local rc=$?
  if [[ ! -s $work/$name.json ]]; then
    die "$name view: run-page.mjs printed no report (exit $rc): $(tail -n 1 "$work/$name.err")"
  fi
}
# check NAME TILESET VIEW [TILE] [PNG]: the check of a report; its JSON goes to $work/NAME.check.json
check() {
  local name=$1 tileset=$2 v=$3 tile=${4:-} png=${5-$work/$1.png}
  local a=("$work/$name.json" "$tileset" --view "$v" --clear "$clear")
  [[ -n $tile ]] && a+=(--tile "$tile")
  [[ -n $png ]] && a+=(--screenshot "$png")
  node "$browser_dir/tiles-check.mjs" "${a[@]}" >"$work/$name.check.json" 2>"$work/$name.check.err"
}
summary() {   # one line of what a passing check saw
  node -e '
    const c = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
    const s = c.screenshot;
    console.log(`loaded ${c.loaded.join(" ")}; visible ${c.visible.join(" ")}; ${c.volumes.tiles} bounding volumes agree ` +
      `(worst ${c.volumes.worst_m} m); screenshot ${(100 * s.not_clear).toFixed(0)} % drawn, ${s.colours} colours; page ${c.page_s} s`);
  ' "$work/$1.check.json"
}

# ---- 2. the views
for spec in "far far" "street street 1_1"; do
  read -r name v tile <<<"$spec"
  t=$SECONDS
  view "$name" "$world" "$v" "$tile"
  check "$name" "$world/tileset.json" "$v" "$tile" || die "$(tail -n 1 "$work/$name.check.err")"
  echo "consumers.tiles: $name view ok in $((SECONDS - t)) s: $(summary "$name"); picture $work/$name.png"
done

# ---- 3. self-test: broken copies must fail the check, each for its own reason
# mutant NAME JS: a copy of the world whose tileset.json is `ts` after JS (the GLBs linked, not copied)
mutant() {
  local dir=$work/mutants/$1
  mkdir -p "$dir" || die "cannot make $dir"
  local part
  for part in hlod tiles textures; do  # textures/: the materials' pictures the GLBs link to
    ln -s "$world/$part" "$dir/$part" || die "cannot link the world into $dir"
  done
  node -e '
    const fs = require("fs");
    const ts = JSON.parse(fs.readFileSync(process.argv[1], "utf8"));
    const hlod = ts.root.children[0];
    const leaf = (name) => hlod.children.find((c) => c.content.uri === `tiles/${name}/city.glb`);
    eval(process.argv[3]);
    fs.writeFileSync(process.argv[2], JSON.stringify(ts));
  ' "$world/tileset.json" "$dir/tileset.json" "$2" || die "cannot write the $1 mutant"
}
# expect_fail NAME PATTERN...: the check of NAME must have failed, with a problem matching each PATTERN
expect_fail() {
  local name=$1 reason problems p
  shift
  [[ -s $work/$name.check.err ]] || die "self-test: the check passed the broken world '$name'"
  reason=$(tail -n 1 "$work/$name.check.err")
  problems=$(node -e '
    const c = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
    console.log((c.problems ?? [c.reason]).join("\n"));
  ' "$work/$name.check.json" 2>/dev/null) || problems=$reason
  for p in "$@"; do
    grep -Eq -- "$p" <<<"$problems" || die "self-test: the check failed the broken world '$name', but not with /$p/: $reason"
  done
  echo "consumers.tiles: self-test $name: fails as it should ($# of $# expected problems): $reason"
}

t=$SECONDS
mutant missing 'hlod.content.uri = "hlod/1_0_0.missing.glb"'
view missing "$work/mutants/missing" far
check missing "$work/mutants/missing/tileset.json" far "" && die "self-test: the check passed a tileset whose HLOD content is missing"
expect_fail missing 'failed to load .*1_0_0\.missing\.glb'

mutant moved 'hlod.boundingVolume.box[0] += 5'
view moved "$work/mutants/moved" far
check moved "$work/mutants/moved/tileset.json" far "" && die "self-test: the check passed a tileset whose HLOD box is moved 5 m"
expect_fail moved 'places hlod/1_0_0\.glb up to 5\.0[0-9]* m outside its boundingVolume'

# three leaf tiles broken at once (the street view loads all four): 1_0's box with its x and y
# extents swapped (it is 2 m longer north-south than east-west), 0_1's box 0.5 m taller, 0_0's
# transform 3 m east (its box moves with it; its extras.origin does not)
mutant leaves 'const b = leaf("1_0").boundingVolume.box; [b[3], b[7]] = [b[7], b[3]];
  const c = leaf("0_1").boundingVolume.box; c[2] += 0.25; c[11] += 0.25;
  leaf("0_0").transform[12] += 3'
view leaves "$work/mutants/leaves" street 1_1
check leaves "$work/mutants/leaves/tileset.json" street 1_1 && die "self-test: the check passed a tileset with broken leaf tiles"
expect_fail leaves 'places tiles/1_0/city\.glb up to 2\.0[0-9]* m outside its boundingVolume' \
  'tiles/0_1/city\.glb.s boundingVolume\.box is 0\.5[0-9]* m larger' \
  'puts tiles/0_0/city\.glb.s frame origin at \[3, 0, 0\], not at its extras\.origin'

# the reader's volumes are checked against tileset.json: the good far report against the moved tileset
cp "$work/far.json" "$work/volumes.json"
check volumes "$work/mutants/moved/tileset.json" far "" "$work/far.png" && die "self-test: the check took the reader's boxes for another tileset's"
expect_fail volumes "the reader's box of hlod/1_0_0\.glb .* is not tileset\.json's"

# the screenshot is checked: the good far report with a picture of the clear colour alone
node "$browser_dir/tiles-check.mjs" --solid-png "$work/blank.png" 640x480 "$clear" || die "cannot write blank.png"
cp "$work/far.json" "$work/blank.json"
check blank "$world/tileset.json" far "" "$work/blank.png" && die "self-test: the check passed a blank screenshot"
expect_fail blank 'differ from the clear colour'
echo "consumers.tiles: self-test done in $((SECONDS - t)) s"

echo "consumers.tiles: ok in $((SECONDS - started)) s"
