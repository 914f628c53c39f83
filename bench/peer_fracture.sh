#!/usr/bin/env bash
# Fracture speed against Blender 3.4's Cell Fracture, measured in one run on the same inputs.
#
#   bench/peer_fracture.sh DAWNFORGE [PEERS_DIR]
#
# Inputs: an icosphere of 20,480 triangles (made here) at 100 and 500 pieces, and CGAL's
# armadillo.off (52,000 triangles; Debian libcgal-demo) at 50 and 100 pieces. Blender times
# its operator alone (peers/blender_cellfracture.py); dawnforge is timed as a whole process
# (reading, checks, fracture, writing the GLB and JSON). Prints one line per case with both
# times and the ratio. Needs `blender` (Debian package; benchmarks only, not CI).
set -euo pipefail
dawnforge=$(realpath "$1")
peers=${2:-$(dirname "$0")/../../shared/peers}
command -v blender >/dev/null || { echo "peer_fracture.sh: blender is not installed (apt-get install blender)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

python3 "$(dirname "$0")/peers/icosphere.py" "$work/sphere.obj"
tar xzf /usr/share/doc/libcgal-dev/data.tar.gz -C "$work" data/meshes/armadillo.off
awk 'NR == 1 { next } NR == 2 { nv = $1; next } NF == 0 { next }
     ++i <= nv { print "v", $1, $2, $3; next } { print "f", $2 + 1, $3 + 1, $4 + 1 }' \
  "$work/data/meshes/armadillo.off" >"$work/armadillo.obj"

printf '%-22s %8s %10s %10s %7s\n' input pieces blender_s dawnforge_s ratio
for case in "sphere 100" "sphere 500" "armadillo 50" "armadillo 100"; do
  read -r name pieces <<<"$case"
  blender_s=$(blender -b --factory-startup --python-exit-code 1 --python "$peers/blender_cellfracture.py" -- \
    "$work/$name.obj" "$pieces" 1 - 2>/dev/null | grep "^{\"tool\"" | python3 -c 'import json,sys; print(json.load(sys.stdin)["seconds"])')
  ours=$(python3 -c 'import subprocess, sys, time
t = time.monotonic(); subprocess.run(sys.argv[1:], check=True, stdout=subprocess.DEVNULL); print(time.monotonic() - t)' \
    "$dawnforge" --quiet fracture "$work/$name.obj" -o "$work/out-$name-$pieces" --pieces "$pieces")
  python3 -c 'import sys; n, p, b, o = sys.argv[1:]; print(f"{n:<22} {p:>8} {float(b):10.2f} {float(o):10.2f} {float(b) / float(o):6.1f}x")' \
    "$name" "$pieces" "$blender_s" "$ours"
done
