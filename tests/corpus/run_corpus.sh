#!/usr/bin/env bash
# The real-mesh corpus: meshes nobody here made, through the commands as a user runs them.
#
#   tests/corpus/run_corpus.sh DAWNFORGE FRACTURE_CHECK WORK_DIR [--subset N] [--jobs J]
#
# - CGAL's own test meshes (Debian libcgal-demo: /usr/share/doc/libcgal-dev/data.tar.gz,
#   data/meshes/*.off: scanned statues, animals, CAD parts, broken meshes): each through
#   `inspect --repair` (the reference solid) and `fracture --pieces 50 --repair`, the output
#   checked by fracture_check (tests/corpus/fracture_check.cpp, which shares no code with the
#   fracture). A mesh passes when it fractures and every check holds, or when both commands
#   refuse it with exit 2 and one line saying that it has no volume. Three meshes are also
#   fractured on 1 and 2 threads: the files must be the same bytes.
# - Assimp's test models (Debian assimp-testmodels: /usr/share/assimp/models, valid and
#   malformed FBX, glTF, OBJ, PLY, STL, ...): each through `inspect`, which must exit 0 or 2
#   (one line on stderr), never die of a signal or hang.
# Prints a table and the counts; exits 1 when anything fails. --subset N takes every k-th
# mesh so that about N are run (the sanitizer build does that).
set -uo pipefail
dawnforge=$(realpath "$1")
checker=$(realpath "$2")
work=$3
shift 3
subset=0
jobs=${JOBS:-2}
while (($#)); do
  case $1 in
    --subset) subset=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    *) echo "run_corpus.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
cgal_tar=/usr/share/doc/libcgal-dev/data.tar.gz
assimp_models=/usr/share/assimp/models
for need in "$cgal_tar" "$assimp_models"; do
  [[ -e $need ]] || { echo "run_corpus.sh: $need is missing (./run installs libcgal-demo and assimp-testmodels)" >&2; exit 1; }
done
rm -rf "$work"
mkdir -p "$work/cgal" "$work/out"
tar xzf "$cgal_tar" -C "$work/cgal" data/meshes

meshes=()
while IFS= read -r -d '' f; do meshes+=("$f"); done < <(find "$work/cgal/data/meshes" -name '*.off' -print0 | sort -z)
if ((subset > 0 && ${#meshes[@]} > subset)); then
  step=$(((${#meshes[@]} + subset - 1) / subset))
  picked=()
  for ((i = 0; i < ${#meshes[@]}; i += step)); do picked+=("${meshes[i]}"); done
  meshes=("${picked[@]}")
fi

# One mesh: prints "name status seconds detail" (status: fractured, no-volume, FAILED; the
# detail of a fractured mesh: how many of its cells fell back to corefinement).
one_mesh() {
  local mesh=$1 dawnforge=$2 checker=$3 out=$4
  local name
  name=$(basename "$mesh" .off)
  local dir=$out/$name start=$SECONDS
  mkdir -p "$dir"
  timeout 900 "$dawnforge" inspect "$mesh" --repair "$dir/reference.glb" >"$dir/inspect.json" 2>"$dir/inspect.err"
  local inspect=$?
  timeout 900 "$dawnforge" --quiet fracture "$mesh" -o "$dir/pieces" --pieces 50 --repair >"$dir/fracture.out" 2>"$dir/fracture.err"
  local fracture=$?
  local seconds=$((SECONDS - start)) why
  why=$(grep -v 'repaired\|oriented' "$dir/fracture.err" | head -1 | cut -c1-160)
  if ((fracture == 0)); then
    local cells
    cells=$(python3 -c 'import json, sys; c = json.load(open(sys.argv[1]))["cells"]; print(c["by_corefinement"], "of", c["cut"], "cells by corefinement")' \
      "$dir/pieces/fracture.json" 2>/dev/null)
    if "$checker" "$dir/pieces" "$dir/reference.glb" >"$dir/check.json" 2>&1; then
      echo "$name fractured $seconds $cells"
    else
      echo "$name FAILED $seconds the check: $(tr -d '\n' <"$dir/check.json" | grep -o '"failures": *\[[^]]*' | cut -c1-200)"
    fi
  elif ((fracture == 2 && inspect == 2)) && [[ $why == *"no volume"* ]] &&
    (($(grep -vc 'repaired\|oriented' "$dir/fracture.err") == 1)); then
    echo "$name no-volume $seconds $why"
  else
    echo "$name FAILED $seconds exit $fracture (inspect $inspect): $why"
  fi
}
export -f one_mesh

echo "CGAL meshes: ${#meshes[@]}, fractured into 50 pieces with --repair, $jobs at a time"
printf '%s\0' "${meshes[@]}" | xargs -0 -P "$jobs" -I{} bash -c 'one_mesh "$@"' _ {} "$dawnforge" "$checker" "$work/out" \
  >"$work/cgal.txt"
sort -o "$work/cgal.txt" "$work/cgal.txt"
column -t -l 4 "$work/cgal.txt" 2>/dev/null || cat "$work/cgal.txt"
fractured=$(grep -c ' fractured ' "$work/cgal.txt")
novolume=$(grep -c ' no-volume ' "$work/cgal.txt")
failed=$(grep -c ' FAILED ' "$work/cgal.txt")
seconds=$(awk '{s += $3} END {print s}' "$work/cgal.txt")
fallback=$(awk '$2 == "fractured" {f += $4; c += $6} END {printf "%d of %d", f, c}' "$work/cgal.txt")
echo "CGAL meshes: $fractured fractured and checked, $novolume refused for having no volume, $failed failed ($seconds s of work)"
echo "CGAL meshes: $fallback cells cut by corefinement where the restricted Voronoi diagram could not close them"

# The same bytes on 1 and 2 threads, on meshes of three kinds.
determinism=0
for name in elephant joint cheese; do
  mesh=$work/cgal/data/meshes/$name.off
  [[ -f $mesh ]] || continue
  for threads in 1 2; do
    "$dawnforge" --quiet fracture "$mesh" -o "$work/threads/$name-$threads" --pieces 50 --repair --threads "$threads" \
      >/dev/null 2>&1
  done
  if ! cmp -s "$work/threads/$name-1/fragments.glb" "$work/threads/$name-2/fragments.glb" ||
    ! cmp -s "$work/threads/$name-1/fracture.json" "$work/threads/$name-2/fracture.json"; then
    echo "FAILED: $name gives different files on 1 and 2 threads"
    determinism=1
  fi
done

# Assimp's models: inspect must answer, never crash.
models=()
while IFS= read -r -d '' f; do models+=("$f"); done < <(find "$assimp_models" -type f -size -64M -print0 | sort -z)
if ((subset > 0 && ${#models[@]} > 4 * subset)); then
  step=$(((${#models[@]} + 4 * subset - 1) / (4 * subset)))
  picked=()
  for ((i = 0; i < ${#models[@]}; i += step)); do picked+=("${models[i]}"); done
  models=("${picked[@]}")
fi
ok=0 refused=0 crashed=0
for model in "${models[@]}"; do
  timeout 120 "$dawnforge" inspect "$model" >/dev/null 2>"$work/assimp.err"
  code=$?
  if ((code == 0)); then
    ok=$((ok + 1))
  elif ((code == 2)) && (($(wc -l <"$work/assimp.err") == 1)); then
    refused=$((refused + 1))
  else
    crashed=$((crashed + 1))
    echo "FAILED: inspect $model: exit $code: $(head -c 200 "$work/assimp.err")"
  fi
done
echo "Assimp models: ${#models[@]} inspected: $ok read, $refused refused with one line, $crashed failed"

((failed == 0 && determinism == 0 && crashed == 0))
