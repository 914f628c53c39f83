#!/usr/bin/env bash
# Fracture speed against Blender 3.4's Cell Fracture, measured in one run on the same inputs.
#
#   bench/peer_fracture.sh DAWNFORGE [PEERS_DIR]
#
# Inputs: an icosphere of 20,480 triangles (made here) at 100 and 500 pieces, and CGAL's
# armadillo.off (52,000 triangles; Debian libcgal-demo) at 50, 100 and 500 pieces. Blender times
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

# One dawnforge run: "seconds peak_MB" of the whole process.
ours() {
  python3 -c 'import resource, subprocess, sys, time
t = time.monotonic(); subprocess.run(sys.argv[1:], check=True, stdout=subprocess.DEVNULL)
print(time.monotonic() - t, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024)' \
    "$dawnforge" --quiet fracture "$@"
}

# Per case: Blender's time; dawnforge's on 2 threads (the default method, the restricted Voronoi
# diagram), on 1 thread, and with --method corefine (one corefinement per cell, the old core);
# each with its ratio against Blender and its peak memory.
printf '%-10s %6s %9s %18s %18s %18s %14s\n' input pieces blender_s "rvd 2 threads" "rvd 1 thread" "corefine 2 thr." "peak MB r/c"
for case in "sphere 100" "sphere 500" "armadillo 50" "armadillo 100" "armadillo 500"; do
  read -r name pieces <<<"$case"
  blender_s=$(blender -b --factory-startup --python-exit-code 1 --python "$peers/blender_cellfracture.py" -- \
    "$work/$name.obj" "$pieces" 1 - 2>/dev/null | grep "^{\"tool\"" | python3 -c 'import json,sys; print(json.load(sys.stdin)["seconds"])')
  read -r rvd2 rvd_mb < <(ours "$work/$name.obj" -o "$work/out-$name-$pieces" --pieces "$pieces")
  read -r rvd1 _ < <(ours "$work/$name.obj" -o "$work/out1-$name-$pieces" --pieces "$pieces" --threads 1)
  read -r core2 core_mb < <(ours "$work/$name.obj" -o "$work/outc-$name-$pieces" --pieces "$pieces" --method corefine)
  python3 -c 'import sys
n, p, b, r2, r1, c2, rm, cm = sys.argv[1:]; b = float(b)
cell = lambda s: f"{float(s):6.2f} s {b / float(s):6.1f}x"
print(f"{n:<10} {p:>6} {b:9.2f} {cell(r2):>18} {cell(r1):>18} {cell(c2):>18} {float(rm):6.0f}/{float(cm):<6.0f}")' \
    "$name" "$pieces" "$blender_s" "$rvd2" "$rvd1" "$core2" "$rvd_mb" "$core_mb"
done
