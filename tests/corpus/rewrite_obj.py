#!/usr/bin/env python3
"""Writes an OFF mesh as OBJ the way another tool's float formatting would: every coordinate
printed with DIGITS significant digits (%.{DIGITS}g), the faces unchanged; with --jitter F,
each coordinate first moved by up to F times the bounding box's diagonal, from a fixed seed.

  rewrite_obj.py IN.off OUT.obj DIGITS [--jitter F]

Reads OFF itself (comments, 'COFF'/'NOFF' headers, colours after the indices), so that it
shares nothing with dawnforge's readers.
"""
import math
import random
import sys


def read_off(path):
    """Points and faces of an OFF file, line by line: a vertex line may carry a colour or a
    normal after its three coordinates, a face line a colour after its indices."""
    with open(path, encoding="latin-1") as f:
        lines = [l.split("#")[0].split() for l in f]
    lines = [l for l in lines if l]
    if not lines or not lines[0][0].endswith("OFF"):
        raise SystemExit(f"rewrite_obj.py: {path} is not an OFF file")
    header = lines[0][1:] or lines[1]
    body = lines[1:] if lines[0][1:] else lines[2:]
    nv, nf = int(header[0]), int(header[1])
    points = [[float(w) for w in line[:3]] for line in body[:nv]]
    faces = [[int(w) for w in line[1:1 + int(line[0])]] for line in body[nv:nv + nf]]
    return points, faces


def main():
    args = sys.argv[1:]
    jitter = 0.0
    if "--jitter" in args:
        k = args.index("--jitter")
        jitter = float(args[k + 1])
        del args[k:k + 2]
    if len(args) != 3:
        raise SystemExit(__doc__)
    source, target, digits = args[0], args[1], int(args[2])
    points, faces = read_off(source)
    if jitter and points:
        lo = [min(p[a] for p in points) for a in range(3)]
        hi = [max(p[a] for p in points) for a in range(3)]
        step = jitter * math.dist(lo, hi)
        rng = random.Random(27)
        points = [[c + step * (2.0 * rng.random() - 1.0) for c in p] for p in points]
    with open(target, "w") as f:
        for p in points:
            f.write("v " + " ".join("%.*g" % (digits, c) for c in p) + "\n")
        for face in faces:
            f.write("f " + " ".join(str(v + 1) for v in face) + "\n")


if __name__ == "__main__":
    main()
