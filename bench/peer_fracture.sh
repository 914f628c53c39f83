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

python3 - "$work/sphere.obj" <<'PY'
import math, sys
# An icosphere, subdivided 5 times: 20 * 4^5 = 20,480 triangles, radius 1 m.
t = (1 + 5 ** 0.5) / 2
v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
     (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
     (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7),
     (9, 8, 1)]
for _ in range(5):
    mid, g = {}, []
    def m(a, b):
        k = (min(a, b), max(a, b))
        if k not in mid:
            p = [(x + y) / 2 for x, y in zip(v[a], v[b])]
            n = math.sqrt(sum(x * x for x in p))
            v.append(tuple(x / n for x in p))
            mid[k] = len(v) - 1
        return mid[k]
    for a, b, c in f:
        ab, bc, ca = m(a, b), m(b, c), m(c, a)
        g += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    f = g
with open(sys.argv[1], "w") as out:
    out.writelines(f"v {x:.9f} {y:.9f} {z:.9f}\n" for x, y, z in v)
    out.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in f)
PY
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
