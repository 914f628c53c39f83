#!/usr/bin/env bash
# consumers.vat: three.js, in Debian's chromium, plays dawnforge's VATs with the SideFX Labs
# decoders of Unity and of Unreal written in GLSL ES (browser/vat.mjs), and every decoded vertex,
# at whole frames and between two (the Labs interframe slerp), must land where transforms.bin and
# turns.bin put it: within 1 mm for float32 textures, within the
# max_vertex_error that _data.json declares for half floats, for the Labs Non-HDR form (8-bit PNGs,
# with and without the second position texture) and for Unreal's default pivots far from the
# origin. Then the same check on files broken on purpose (pivot UV sets swapped, lookup V from
# the bottom, Y and Z swapped, the rotation alpha's sign flipped, a Non-HDR VAT without its
# second position texture) must fail.
#
# usage: vat.sh DAWNFORGE_EXE WORK_DIR      (exit 77: the browser is not installed)
set -euo pipefail
exe=$1 work=$2
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=browser/common.sh
source "$here/browser/common.sh"
need_browser
enter_work "$work"

# The inputs; what the commands print goes to inputs.log.
{
  # CGAL's elephant in 29 pieces, blown apart: pieces that turn up to half a turn per frame. A
  # width of 7 texels makes 5 rows per frame, so the row arithmetic is exercised.
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz --strip-components=2 data/meshes/elephant.off
  "$exe" -q fracture elephant.off -o fracture --pieces 24 --seed 3
  "$exe" -q simulate fracture -o sim --frames 24 --explosion 0,-0.3,0 --explosion-speed 78 --explosion-radius 2 \
    --trigger-time 0.1
  for preset in unity unreal; do
    "$exe" -q vat sim -o vat --preset "$preset" --name "$preset" --max-width 7
    "$exe" -q vat sim -o vat --preset "$preset" --name "${preset}_half" --half --max-width 7
    "$exe" -q vat sim -o vat --preset "$preset" --name "${preset}_ldr" --format ldr --max-width 7
    "$exe" -q vat sim -o vat --preset "$preset" --name "${preset}_ldr1" --format ldr --single-position-texture --max-width 7
  done

  # A building of a generated city hit by a ball, as the demo's destruction: 880 pieces some
  # 90 m from the origin, where Unreal's default "Very High" pivots cost centimetres
  # (max_pivot_error) and --full-precision-uvs none.
  "$exe" -q city -o city --size 120x100 --seed 3
  target=$(python3 "$here/aim.py" city/city.json 1)
  "$exe" -q fracture city --building 1 -o building_fracture --pieces 40
  "$exe" -q simulate building_fracture -o building_sim --frames 40 --projectile "$target" --projectile-radius 1.5
  "$exe" -q vat building_sim -o vat --preset unity --name building_unity
  "$exe" -q vat building_sim -o vat --preset unreal --name building_unreal
  "$exe" -q vat building_sim -o vat --preset unreal --name building_unreal_full --full-precision-uvs
  "$exe" -q vat building_sim -o vat --preset unity --name building_unity_ldr --format ldr
  "$exe" -q vat building_sim -o vat --preset unreal --name building_unreal_ldr --format ldr
} >inputs.log

frames=0,1,4.5,9,16.25,22.5
play() {  # play REPORT NAME DECODER [MUTATION]
  local query=(--query vat=vat --query "name=$2" --query "decoder=$3" --query "sim=${sim:-sim}" --query "frames=$frames")
  [ $# -lt 4 ] || query+=(--query "mutate=$4")
  run_page "$1" vat.html "$work" "${query[@]}" || { cat "$1"; exit 1; }
}
declared() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['max_vertex_error'] * 1.01 + 1e-5)" "$1"; }

for preset in unity unreal; do
  play "$preset.json" "$preset" "$preset"
  python3 "$here/check.py" vat "$preset.json" 0.001
  play "${preset}_half.json" "${preset}_half" "$preset"
  python3 "$here/check.py" vat "${preset}_half.json" "$(declared "vat/${preset}_half_data.json")"
  for form in ldr ldr1; do
    play "${preset}_$form.json" "${preset}_$form" "$preset"
    python3 "$here/check.py" vat "${preset}_$form.json" "$(declared "vat/${preset}_${form}_data.json")"
  done
done

sim=building_sim frames=0,8,20.5,39
play building_unity.json building_unity unity
python3 "$here/check.py" vat building_unity.json 0.001
play building_unreal.json building_unreal unreal
python3 "$here/check.py" vat building_unreal.json "$(declared vat/building_unreal_data.json)"
play building_unreal_full.json building_unreal_full unreal
python3 "$here/check.py" vat building_unreal_full.json 0.001
for preset in unity unreal; do
  play "building_${preset}_ldr.json" "building_${preset}_ldr" "$preset"
  python3 "$here/check.py" vat "building_${preset}_ldr.json" "$(declared "vat/building_${preset}_ldr_data.json")"
done
unset sim
frames=0,1,4.5,9,16.25,22.5

# The check must see a broken file.
for mutation in swap-pivot-uvs lookup-v-from-bottom swap-y-z rotation-alpha-negated; do
  for preset in unity unreal; do
    play "broken.json" "$preset" "$preset" "$mutation"
    if python3 "$here/check.py" vat broken.json 0.001 >broken.txt; then
      echo "FAILED: the $preset decoder did not notice a file with $mutation"
      exit 1
    fi
    echo "ok: $preset with $mutation is refused: $(cut -c1-160 broken.txt)"
  done
done
# Non-HDR without its second texture: the 8-bit positions alone are 1/510 of the bounds off.
for preset in unity unreal; do
  play "broken.json" "${preset}_ldr" "$preset" no-second-position-texture
  if python3 "$here/check.py" vat broken.json "$(declared "vat/${preset}_ldr_data.json")" >broken.txt; then
    echo "FAILED: the $preset decoder did not notice a Non-HDR VAT played without its second position texture"
    exit 1
  fi
  echo "ok: ${preset}_ldr without _pos2 is refused: $(cut -c1-160 broken.txt)"
done
