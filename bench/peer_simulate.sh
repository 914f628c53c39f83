#!/usr/bin/env bash
# Rigid-body simulation speed against Blender 3.4's rigid-body bake (Bullet), measured in one run
# on the same bodies.
#
#   bench/peer_simulate.sh DAWNFORGE
#
# Cases, each run on Blender and then on dawnforge:
# - glued sphere: the icosphere of 20,480 triangles (peers/icosphere.py) fractured by
#   `dawnforge fracture --pieces 500 --seed 1`, 240 frames, 20 solver iterations, 4 substeps.
#   Blender bakes the same pieces and bonds (peers/blender_glued.py: one body per piece with
#   dawnforge's hull, margin, mass, friction and damping; one breakable FIXED constraint per
#   bond); dawnforge runs `simulate DIR --frames 240 --iterations 20 --substeps 4`, and again
#   with `--no-anchor` (the glued sphere as one moving body resting on the ground, not fixed).
# - loose cubes: 500 0.5 m cubes settling, 120 frames, 10 iterations, 4 substeps
#   (peers/blender_cubes.py; dawnforge on the same cubes as a fracture folder made by
#   peers/cube_stack_fracture_dir.py, with --ground-height 0), and again with --no-sleep (every
#   body simulated to the last frame, as Blender does).
# Blender times its bake operator alone; dawnforge is timed as a whole process (reading, hulls,
# simulation, writing). Prints the binary it ran, one line per case with both times and the ratio,
# then sanity figures: bonds broken (dawnforge's count, and for both sides the bonds whose anchors
# ended more than 5 mm or 2 degrees apart) and the mean drop of the pieces' centres.
# Needs `blender` (Debian package; benchmarks only, not CI).
set -euo pipefail
command -v blender >/dev/null || { echo "peer_simulate.sh: blender is not installed (apt-get install blender)" >&2; exit 2; }
peers=$(cd "$(dirname "$0")" && pwd)/peers
dawnforge=$(realpath "$1")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The binary as it is now, so that a rebuild during the run does not change what is measured.
cp "$dawnforge" "$work/dawnforge"
df=$work/dawnforge
repo=$(dirname "$dawnforge")/../..
commit=$(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown)
[ -n "$(git -C "$repo" status --porcelain --untracked-files=no 2>/dev/null)" ] && commit="$commit + uncommitted changes"
echo "dawnforge $("$df" --version) ($commit), $1 built $(date -r "$dawnforge" '+%F %T'), sha256 $(sha256sum "$df" | cut -c1-12)"
echo "$(blender --version 2>/dev/null | head -1)"

python3 "$peers/icosphere.py" "$work/sphere.obj"
"$df" --quiet fracture "$work/sphere.obj" -o "$work/sphere-500" --pieces 500 --seed 1 >/dev/null
python3 "$peers/cube_stack_fracture_dir.py" 500 "$work/cubes-500"

# blender_seconds SCRIPT ARGS...: runs a peer script, leaves its JSON line in $work/blender.json
blender_seconds() {
  local script=$1
  shift
  # Blender 3.4 sometimes crashes on its way out after printing the result: the JSON line decides.
  { blender -b --factory-startup --python-exit-code 1 --python "$peers/$script" -- "$@" 2>/dev/null || true; } |
    grep '^{"tool"' | tee "$work/blender.json" | python3 -c 'import json,sys; print(json.load(sys.stdin)["seconds"])'
}
# dawnforge_seconds ARGS...: the whole dawnforge process
dawnforge_seconds() {
  python3 -c 'import subprocess, sys, time
t = time.monotonic(); subprocess.run(sys.argv[1:], check=True, stdout=subprocess.DEVNULL); print(time.monotonic() - t)' \
    "$df" --quiet "$@"
}
row() {
  python3 -c 'import sys; n, p, b, f, bl, o = sys.argv[1:]
print(f"{n:<16} {p:>6} {b:>6} {f:>6} {float(bl):10.2f} {float(o):11.2f} {float(bl) / float(o):6.1f}x")' "$@"
}

printf '%-16s %6s %6s %6s %10s %11s %7s\n' case pieces bonds frames blender_s dawnforge_s ratio
bonds=$(python3 -c 'import json, sys; print(len(json.load(open(sys.argv[1]))["bonds"]))' "$work/sphere-500/fracture.json")
b=$(blender_seconds blender_glued.py "$work/sphere-500" 240 20 4 -)
cp "$work/blender.json" "$work/blender-glued.json"
o=$(dawnforge_seconds simulate "$work/sphere-500" -o "$work/sim-sphere" --frames 240 --iterations 20 --substeps 4)
row "glued sphere" 500 "$bonds" 240 "$b" "$o"
# The same sphere not fixed where it rests (--no-anchor): one moving compound body on the ground,
# against the same Blender bake.
o=$(dawnforge_seconds simulate "$work/sphere-500" -o "$work/sim-sphere-free" --frames 240 --iterations 20 --substeps 4 --no-anchor)
row "  --no-anchor" 500 "$bonds" 240 "$b" "$o"
b=$(blender_seconds blender_cubes.py 500 120 -)
cp "$work/blender.json" "$work/blender-cubes.json"
o=$(dawnforge_seconds simulate "$work/cubes-500" -o "$work/sim-cubes" --frames 120 --iterations 10 --substeps 4 --ground-height 0)
row "loose cubes" 500 0 120 "$b" "$o"
o0=$o
# The same cubes with every body kept awake to the last frame, as Blender's bake keeps them
# (its rigid-body world does not deactivate bodies by default): the cost of a frame of the same
# work on both sides.
o=$(dawnforge_seconds simulate "$work/cubes-500" -o "$work/sim-cubes-awake" --frames 120 --iterations 10 --substeps 4 --ground-height 0 --no-sleep)
row "  --no-sleep" 500 0 120 "$b" "$o"
# And Blender with its bodies deactivating, at Bullet's default thresholds (after Bullet's 2 s).
b=$(blender_seconds blender_cubes.py 500 120 - sleep)
row "  Blender asleep" 500 0 120 "$b" "$o0"

# Sanity: what each side's bodies did. dawnforge's transforms.bin is frames x pieces x
# (px py pz qx qy qz qw) float32, Y up; frame 0 is the rest pose (ARCHITECTURE.md 4.3).
python3 - "$work" <<'PY'
import json, math, struct, sys
work = sys.argv[1]

def dawnforge_side(sim_dir, frac_dir):
    sim = json.load(open(f"{sim_dir}/sim.json"))
    frac = json.load(open(f"{frac_dir}/fracture.json"))
    frames, n = sim["frames"], sim["pieces"]
    with open(f"{sim_dir}/transforms.bin", "rb") as f:
        first = struct.unpack(f"<{7 * n}f", f.read(28 * n))
        f.seek(28 * n * (frames - 1))
        last = struct.unpack(f"<{7 * n}f", f.read(28 * n))
    pose = lambda t, i: (t[7 * i:7 * i + 3], t[7 * i + 3:7 * i + 7])
    drops = [pose(first, i)[0][1] - pose(last, i)[0][1] for i in range(n)]

    def rotate(q, v):  # q = (x, y, z, w)
        x, y, z, w = q
        tx, ty, tz = 2 * (y * v[2] - z * v[1]), 2 * (z * v[0] - x * v[2]), 2 * (x * v[1] - y * v[0])
        return (v[0] + w * tx + y * tz - z * ty, v[1] + w * ty + z * tx - x * tz, v[2] + w * tz + x * ty - y * tx)

    apart = 0
    for bond in frac["bonds"]:
        ends = []
        for i in (bond["a"], bond["b"]):
            p0, _ = pose(first, i)
            p, q = pose(last, i)
            local = [c - o for c, o in zip(bond["centroid"], p0)]
            ends.append(([a + r for a, r in zip(p, rotate(q, local))], q))
        (pa, qa), (pb, qb) = ends
        turn = math.degrees(2 * math.acos(min(1.0, abs(sum(x * y for x, y in zip(qa, qb))))))
        if math.dist(pa, pb) > 0.005 or turn > 2.0:
            apart += 1
    return sim, sum(drops) / n, max(drops), apart

def m(x):
    return f"{x:.3f}".replace("-0.000", "0.000")

def bodies(glue):
    return f"; dawnforge ran {glue['bodies']} bodies ({glue.get('fixed_bodies', 0)} fixed where they stood)" if "bodies" in glue else ""

print("(apart: a bond's two anchor points ended more than 5 mm apart or turned more than 2 degrees against each other; "
      "Blender does not say which constraints broke)")
glued = json.loads(open(f"{work}/blender-glued.json").read())
sim, mean, top, apart = dawnforge_side(f"{work}/sim-sphere", f"{work}/sphere-500")
glue = sim.get("glue", {})
print(f"glued sphere: bonds broken: dawnforge {glue.get('broken', 0)} of {glue.get('bonds', 0)} ({apart} apart), "
      f"Blender {glued['bonds_apart']} apart; mean drop of the centres: Blender {m(glued['mean_drop_m'])} m "
      f"(max {m(glued['max_drop_m'])}), dawnforge {m(mean)} m (max {m(top)}){bodies(glue)}")
cubes = json.loads(open(f"{work}/blender-cubes.json").read())
sim, mean, top, apart = dawnforge_side(f"{work}/sim-cubes", f"{work}/cubes-500")
print(f"loose cubes: mean drop of the centres: Blender {m(cubes['mean_drop_m'])} m, dawnforge {m(mean)} m "
      f"(max {m(top)}){bodies(sim.get('glue', {}))}")
PY
