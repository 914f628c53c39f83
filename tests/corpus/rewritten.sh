#!/usr/bin/env bash
# CGAL's test meshes as they arrive from another tool: each written as OBJ with its coordinates
# printed at 6, 7 and 9 significant digits, and at 9 after a deterministic jitter of 1e-7 of its
# size (tests/corpus/rewrite_obj.py; the faces unchanged). A mesh that passed through a studio's
# float formatting is the normal case, and it breaks what exact input never does: CGAL's
# horizons.off at %.9g crashed `fracture --repair` (issue 26).
#
#   tests/corpus/rewritten.sh DAWNFORGE FRACTURE_CHECK WORK_DIR [--sample N|all] [--fracture M] [--jobs J]
#
# Every variant goes through `inspect --repair`; M of them (horizons at 9 digits first, then
# every k-th) also through `fracture --pieces 50 --repair`, the pieces checked by fracture_check
# against inspect's repaired solid. A run passes when nothing dies of a signal or a time-out,
# every exit is 0 or 2, every refusal is one line in our words (no CGAL assertion text), and
# every fracture that succeeds is checked clean. --sample N takes every k-th mesh so that about
# N are run (default all 138; the test in ./run test takes a fixed sample). Prints a table of
# the outcomes; exits 1 when anything fails.
set -uo pipefail
dawnforge=$(realpath "$1")
checker=$(realpath "$2")
work=$3
shift 3
sample=all fractures=4 jobs=${JOBS:-2}
while (($#)); do
  case $1 in
    --sample) sample=$2; shift 2 ;;
    --fracture) fractures=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    *) echo "rewritten.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
here=$(cd "$(dirname "$0")" && pwd)
cgal_tar=/usr/share/doc/libcgal-dev/data.tar.gz
[[ -e $cgal_tar ]] || { echo "rewritten.sh: $cgal_tar is missing (./run installs libcgal-demo)" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work/cgal" "$work/variants" "$work/out"
tar xzf "$cgal_tar" -C "$work/cgal" data/meshes

meshes=()
while IFS= read -r -d '' f; do meshes+=("$(basename "$f" .off)"); done < <(find "$work/cgal/data/meshes" -name '*.off' -print0 | sort -z)
if [[ $sample != all ]] && ((${#meshes[@]} > sample)); then
  step=$(((${#meshes[@]} + sample - 1) / sample))
  picked=(horizons)
  for ((i = 0; i < ${#meshes[@]}; i += step)); do [[ ${meshes[i]} == horizons ]] || picked+=("${meshes[i]}"); done
  meshes=("${picked[@]}")
fi
variants=()
for name in "${meshes[@]}"; do
  for form in 6 7 9 9j; do
    digits=${form%j} jitter=()
    [[ $form == *j ]] && jitter=(--jitter 1e-7)
    python3 "$here/rewrite_obj.py" "$work/cgal/data/meshes/$name.off" "$work/variants/$name-$form.obj" "$digits" "${jitter[@]}" ||
      { echo "rewritten.sh: could not rewrite $name" >&2; exit 1; }
    variants+=("$name-$form")
  done
done
# Fractured: horizons at 9 digits, then every k-th variant.
fracture_list=" horizons-9 "
if ((fractures > 1)); then
  step=$(((${#variants[@]} + fractures - 2) / (fractures - 1)))
  for ((i = 1; i < ${#variants[@]}; i += step)); do fracture_list+="${variants[i]} "; done
fi

# A refusal is in our words: one line, no CGAL assertion text.
ours() { (($(wc -l <"$1") == 1)) && ! grep -qE 'CGAL|Expr:|File:|Line:|[Aa]ssertion|terminate called' "$1"; }

# One variant: prints "name outcome seconds detail".
one_variant() {
  local name=$1 dir=$work/out/$1 start=$SECONDS outcome detail
  mkdir -p "$dir"
  timeout 600 "$dawnforge" inspect "$work/variants/$name.obj" --repair "$dir/reference.glb" >/dev/null 2>"$dir/inspect.err"
  local inspect=$?
  grep -v 'repaired\|oriented' "$dir/inspect.err" >"$dir/inspect.why"
  if ((inspect == 0)); then
    outcome=repaired
  elif ((inspect == 2)) && ours "$dir/inspect.why"; then
    outcome=refused detail=$(cut -c1-120 "$dir/inspect.why")
  else
    echo "$name FAILED $((SECONDS - start)) inspect --repair: exit $inspect: $(head -c 160 "$dir/inspect.why" | tr '\n' ' ')"
    return
  fi
  if [[ $fracture_list == *" $name "* ]]; then
    timeout 900 "$dawnforge" --quiet fracture "$work/variants/$name.obj" -o "$dir/pieces" --pieces 50 --seed 1 --repair \
      >/dev/null 2>"$dir/fracture.err"
    local fracture=$?
    grep -v 'repaired\|oriented' "$dir/fracture.err" >"$dir/fracture.why"
    if ((fracture == 0)) && [[ $outcome == repaired ]]; then
      if "$checker" "$dir/pieces" "$dir/reference.glb" >"$dir/check.json" 2>&1; then
        outcome=fractured
      else
        echo "$name FAILED $((SECONDS - start)) the check: $(tr -d '\n' <"$dir/check.json" | grep -o '"failures": *\[[^]]*' | cut -c1-160)"
        return
      fi
    elif ((fracture == 2)) && ours "$dir/fracture.why"; then
      outcome=fracture-refused detail=$(cut -c1-120 "$dir/fracture.why")
    else
      echo "$name FAILED $((SECONDS - start)) fracture --repair: exit $fracture: $(head -c 160 "$dir/fracture.why" | tr '\n' ' ')"
      return
    fi
  fi
  echo "$name $outcome $((SECONDS - start)) ${detail:-}"
}
export -f one_variant ours
export work dawnforge checker fracture_list

echo "CGAL meshes: ${#meshes[@]}, each as OBJ at 6, 7, 9 digits and jittered (${#variants[@]} files) through inspect --repair;" \
  "$(wc -w <<<"$fracture_list") also fractured, $jobs at a time"
# shellcheck disable=SC2016  # $1 is the inner bash's
printf '%s\0' "${variants[@]}" | xargs -0 -P "$jobs" -I{} bash -c 'one_variant "$1"' _ {} >"$work/outcomes.txt"
sort -o "$work/outcomes.txt" "$work/outcomes.txt"
column -t -l 4 "$work/outcomes.txt" 2>/dev/null || cat "$work/outcomes.txt"
count() { grep -c " $1 " "$work/outcomes.txt"; }
echo "rewritten CGAL meshes: $(count repaired) repaired, $(count fractured) fractured and checked," \
  "$(count refused) refused by inspect, $(count fracture-refused) refused by fracture, $(count FAILED) failed"
(($(count FAILED) == 0))
