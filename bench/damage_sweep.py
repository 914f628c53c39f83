#!/usr/bin/env python3
"""Visible damage of one simulation, read from the files as written (fracture.json, sim.json,
transforms.bin), sharing no code with the simulation.

    damage_sweep.py FRACTURE_DIR SIM_DIR CONTACT_X,Y,Z [--header]

A bond is separated from the first frame where the point it joined, carried by each of its two
pieces, is more than 2 cm apart. Prints one line: bonds separated, pieces moved more than 1 m,
how many of those lie more than 12 m (horizontally) from the contact, the largest move of a
piece within 3 m of the contact, the share of the pieces more than 12 m away that stayed within
5 cm, and the share of the bonds separated in the first 0.25 s after the first that lie within
6 m of the contact.
"""
import json
import math
import struct
import sys
from array import array

SEPARATED = 0.02  # m


def rotate(q, v):
    x, y, z, w = q
    # v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z)
    cx, cy, cz = y * v[2] - z * v[1], z * v[0] - x * v[2], x * v[1] - y * v[0]
    ccx, ccy, ccz = y * cz - z * cy, z * cx - x * cz, x * cy - y * cx
    return (v[0] + 2 * (w * cx + ccx), v[1] + 2 * (w * cy + ccy), v[2] + 2 * (w * cz + ccz))


def main():
    if "--header" in sys.argv:
        print(f"{'speed':>6} {'energy_MJ':>9} {'separated':>9} {'moved>1m':>8} {'of_them>12m':>11} "
              f"{'near_move_m':>11} {'far_still':>9} {'early_near':>10} {'broken':>7}")
        return
    frac_dir, sim_dir, contact = sys.argv[1], sys.argv[2], [float(c) for c in sys.argv[3].split(",")]
    fracture = json.load(open(f"{frac_dir}/fracture.json"))
    sim = json.load(open(f"{sim_dir}/sim.json"))
    n, frames, fps = sim["pieces"], sim["frames"], sim["fps"]
    t = array("f")
    with open(f"{sim_dir}/transforms.bin", "rb") as f:
        t.frombytes(f.read())
    assert len(t) == frames * n * 7, "transforms.bin does not match sim.json"
    rest = [fracture["pieces"][i]["center_of_mass"] for i in range(n)]

    def pose(k, i):
        o = (k * n + i) * 7
        return (t[o], t[o + 1], t[o + 2]), (t[o + 3], t[o + 4], t[o + 5], t[o + 6])

    def carried(k, i, point):  # a rest-pose point, carried by piece i to frame k
        x, q = pose(k, i)
        r = rotate(q, [point[c] - rest[i][c] for c in range(3)])
        return [x[c] + r[c] for c in range(3)]

    first = {}  # bond -> first frame it is separated
    for bi, b in enumerate(fracture["bonds"]):
        a, c, p = b["a"], b["b"], b["centroid"]
        for k in range(1, frames):
            if math.dist(carried(k, a, p), carried(k, c, p)) > SEPARATED:
                first[bi] = k
                break
    moves = [max(math.dist(pose(k, i)[0], pose(0, i)[0]) for k in range(frames)) for i in range(n)]
    horizontal = [math.hypot(rest[i][0] - contact[0], rest[i][2] - contact[2]) for i in range(n)]
    moved = [i for i in range(n) if moves[i] > 1.0]
    far = [i for i in range(n) if horizontal[i] > 12.0]
    near = [moves[i] for i in range(n) if math.dist(rest[i], contact) <= 3.0]
    early_near = "-"
    if first:
        start = min(first.values())
        early = [bi for bi, k in first.items() if (k - start) / fps <= 0.25]
        inside = sum(math.dist(fracture["bonds"][bi]["centroid"], contact) <= 6.0 for bi in early)
        early_near = f"{inside / len(early):.2f}"
    far_still = sum(moves[i] <= 0.05 for i in far) / len(far) if far else float("nan")
    projectile = next((x for x in sim["triggers"] if x["type"] == "projectile"), None)
    speed = projectile["speed"] if projectile else 0.0
    energy = 0.5 * projectile["mass"] * speed * speed / 1e6 if projectile else 0.0
    print(f"{speed:6g} {energy:9.2f} {len(first):9d} {len(moved):8d} {sum(horizontal[i] > 12.0 for i in moved):11d} "
          f"{max(near, default=0.0):11.2f} {far_still:9.3f} {early_near:>10} {sim['glue']['broken']:7d}")


main()
