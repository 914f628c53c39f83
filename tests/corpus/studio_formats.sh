#!/usr/bin/env bash
# Studio formats end to end: FBX, STL, PLY and OFF files that ship with Assimp (Debian
# assimp-testmodels), fractured as a user would, each output checked by fracture_check
# (which shares no code with the fracture) against `inspect --repair`'s solid.
#
#   tests/corpus/studio_formats.sh DAWNFORGE FRACTURE_CHECK WORK_DIR
#
# The scanned spider has holes and crossing legs: it needs --repair; the rest fracture as
# they are (attributes kept). Exits 1 when anything fails; 77 (skipped) without the models.
set -uo pipefail
dawnforge=$(realpath "$1")
checker=$(realpath "$2")
work=$3
models=/usr/share/assimp/models
[[ -d $models ]] || { echo "studio_formats.sh: $models is missing (./run installs assimp-testmodels)"; exit 77; }
rm -rf "$work"
mkdir -p "$work"
failed=0
for spec in FBX/box.fbx "FBX/spider.fbx --repair" "STL/Spider_binary.stl --repair" PLY/cube.ply OFF/Cube.off; do
  read -r file repair <<<"$spec"
  out=$work/$(basename "$file")
  "$dawnforge" inspect "$models/$file" --repair "$out.reference.glb" >/dev/null 2>"$out.inspect.err" &&
    "$dawnforge" --quiet fracture "$models/$file" -o "$out" --pieces 12 $repair >/dev/null 2>"$out.err"
  code=$?
  if ((code != 0)); then
    echo "$file: FAILED, exit $code: $(cat "$out.inspect.err" "$out.err" | head -1)"
    failed=1
  elif "$checker" "$out" "$out.reference.glb" >"$out.check.json" 2>&1; then
    echo "$file: $(grep -c '"name"' "$out/fracture.json") pieces, checked"
  else
    echo "$file: FAILED the check: $(tr -d '\n' <"$out.check.json" | grep -o '"failures": *\[[^]]*' | cut -c1-200)"
    failed=1
  fi
done
exit $failed
