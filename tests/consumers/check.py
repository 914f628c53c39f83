#!/usr/bin/env python3
"""Checks a browser consumer's report (run-page.mjs's JSON) against stated bounds.

  check.py vat REPORT.json BOUND_M      every piece vertex of every frame within BOUND_M metres of
                                        transforms.bin (the report's units converted); the data
                                        triangles' vertices all at the origin
  check.py pivots REPORT.json           every vertex's element, parent, pivot (within the rounding
                                        of a half float), X axis (within 1/255) and extent (within
                                        half of the 8-bit step of 2048/255 cm)
  check.py anim REPORT.json SIM_DIR     every piece (a node named as sim.json's piece_names) at
                                        every frame within 1 mm and 0.1 degrees of transforms.bin
  check.py cesium REPORT.json PLAN      CesiumJS put the plan's origin where plan.json says (1e-9
                                        degrees, 1 cm), drew only HLOD contents from afar, refined to
                                        every tile near, loaded every content and none failed, and
                                        picked a building whose properties are city.json's

Prints one line per report; exits 1 with the reason when a bound does not hold.
"""
import json
import math
import struct
import sys


def fail(message):
    print(f"FAILED: {message}")
    sys.exit(1)


def check_vat(report, bound_m):
    r = report["result"]
    scale = 100.0 if r["units"] == "centimetres" else 1.0
    worst = max((f["max_error"] if f["max_error"] is not None else float("inf")) for f in r["frames"]) / scale
    label = f'{r["name"]} ({r["engine"]} decoder, {r["precision"]}, {r["vertices"]} vertices, frames ' \
            f'{",".join(str(f["frame"]) for f in r["frames"])})'
    if r["data_vertices"] != 6:
        fail(f"{label}: {r['data_vertices']} data-triangle vertices, expected 6")
    if r["data_vertices_off_origin"]:
        fail(f"{label}: {r['data_vertices_off_origin']} data-triangle vertices not hidden at the origin")
    if not worst <= bound_m:
        frame = max(r["frames"], key=lambda f: f["max_error"] if f["max_error"] is not None else float("inf"))
        fail(f"{label}: a vertex is {worst:.3g} m from the simulation (frame {frame['frame']}, vertex "
             f"{frame['worst_vertex']}); the bound is {bound_m:.3g} m")
    print(f"ok: {label}: worst {worst:.3g} m (bound {bound_m:.3g} m)")


def check_pivots(report):
    r = report["result"]
    w = r["worst"]
    label = f'{r["species"]} ({r["elements"]} elements, {r["levels"]} levels, {r["vertices"]} vertices)'
    problems = []
    if r["vertex_count_mismatches"]:
        problems.append(f"vertices per element differ from city.glb: {r['vertex_count_mismatches'][:3]}")
    if w["index_out_of_range"]:
        problems.append(f"{w['index_out_of_range']} vertices address no element")
    if w["parent_mismatches"]:
        problems.append(f"{w['parent_mismatches']} vertices decode the wrong parent index")
    if not w["pivot_over_half_step"] <= 1.1:
        problems.append(f"a pivot is {w['pivot_cm']:.3g} cm off ({w['pivot_over_half_step']:.3g} x the half-float rounding)")
    if not w["axis"] <= 1 / 255 + 1e-4:
        problems.append(f"an X axis component is {w['axis']:.3g} off (bound 1/255)")
    if not w["extent_cm"] <= 1024 / 255 + 0.1:
        problems.append(f"an extent is {w['extent_cm']:.3g} cm off (bound {1024 / 255 + 0.1:.3g} cm)")
    if problems:
        fail(f"{label}: " + "; ".join(problems))
    print(f"ok: {label}: pivot within {w['pivot_cm']:.3g} cm, axis {w['axis']:.4f}, extent {w['extent_cm']:.3g} cm")


def check_anim(report, sim_dir):
    r = report["result"]
    sim = json.load(open(f"{sim_dir}/sim.json"))
    n, frames, names = sim["pieces"], sim["frames"], sim["piece_names"]
    data = open(f"{sim_dir}/transforms.bin", "rb").read()
    label = f'{sim_dir} ({n} pieces, {frames} frames, clip "{r["clip"]}" with {r["tracks"]} tracks)'
    missing = [name for name in names if len(r["poses"].get(name, [])) != frames]
    if missing:
        fail(f"{label}: {len(missing)} pieces not played at every frame (first: {missing[0]})")
    worst_p, worst_d, where = 0.0, 0.0, ""
    for i, name in enumerate(names):
        for k, got in enumerate(r["poses"][name]):
            if any(v is None or not math.isfinite(v) for v in got):  # NaN arrives as null
                fail(f"{label}: {name} at frame {k} is not a number: {got}")
            want = struct.unpack_from("<7f", data, (k * n + i) * 28)
            worst_p = max(worst_p, math.dist(got[:3], want[:3]))
            # the angle between two unit quaternions, either sign: 4 atan2(|a - b|, |a + b|)
            b = want[3:] if sum(x * y for x, y in zip(got[3:], want[3:])) >= 0 else [-x for x in want[3:]]
            d = math.degrees(4 * math.atan2(math.dist(got[3:], b), math.hypot(*[x + y for x, y in zip(got[3:], b)])))
            if d > worst_d:
                worst_d, where = d, f"{name} at frame {k}"
    if not (worst_p <= 0.001 and worst_d <= 0.1):
        fail(f"{label}: a piece is {worst_p * 1000:.3g} mm and {worst_d:.3g} degrees from the simulation ({where}); "
             f"the bounds are 1 mm and 0.1 degrees")
    print(f"ok: {label}: worst {worst_p * 1000:.3g} mm, {worst_d:.3g} degrees")


def check_cesium(report, plan_path):
    r = report["result"]
    want = json.load(open(plan_path))["origin"]
    got = r["origin"]
    label = f'CesiumJS {r["cesium"]} ({len(r["contents"])} contents)'
    if got is None:
        fail(f"{label}: Cesium puts the plan's origin at ECEF {r['ecef_origin']}, which is no place on the globe")
    if not (abs(got["longitude"] - want["longitude"]) < 1e-9 and abs(got["latitude"] - want["latitude"]) < 1e-9
            and abs(got["height"] - want["height"]) < 0.01):
        fail(f"{label}: the plan's origin lands at {got}, not at plan.json's {want}")
    views = {v["name"]: v for v in r["views"]}
    leaves = [c for c in r["contents"] if c.endswith("/city.glb")]
    hlods = [c for c in r["contents"] if c.startswith("hlod/")]
    for v in views.values():
        if not v["settled"]:
            fail(f"{label}: the {v['name']} view did not settle (tilesLoaded never held)")
        if v["failed"]:
            fail(f"{label}: the {v['name']} view failed to load {v['failed']}")
    far, near = views["far"], views["near"]
    if not far["visible"] or any(c not in hlods for c in far["visible"]):
        fail(f"{label}: from {far['height']} m Cesium drew {far['visible']}, not HLOD contents alone")
    if sorted(near["visible"]) != sorted(leaves):
        fail(f"{label}: from {near['height']} m Cesium drew {near['visible']}, not every tile {leaves}")
    loaded = set(far["loaded"]) | set(near["loaded"])
    if loaded != set(r["contents"]):
        fail(f"{label}: Cesium loaded {sorted(loaded)}, not every content {r['contents']}")
    pick = r["pick"]
    want_b, got_b = pick["expected"], pick["got"]
    if want_b is None:
        fail(f"{label}: tile 0_0 has no building to pick")
    if got_b is None:
        fail(f"{label}: picking building {want_b['id']} from above gave {pick['picked']}, not a feature")
    for key in ("id", "floors", "roof", "wall_material"):
        if got_b[key] != want_b[key]:
            fail(f"{label}: the picked feature's {key} is {got_b[key]!r}, city.json says {want_b[key]!r} (building {want_b['id']})")
    if not abs(got_b["height"] - want_b["height"]) < 0.01:
        fail(f"{label}: the picked feature's height is {got_b['height']}, city.json says {want_b['height']}")
    print(f"ok: {label}: the origin at {got['longitude']:.9f}, {got['latitude']:.9f}, {got['height']:.3g} m; "
          f"far: {far['visible']}; near: {len(near['visible'])} tiles; picked building {got_b['id']} "
          f"({got_b['floors']} floors, {got_b['height']:.2f} m, {got_b['roof']} roof, {got_b['wall_material']})")


def main():
    kind, path = sys.argv[1], sys.argv[2]
    with open(path) as f:
        report = json.load(f)
    if not report.get("ok"):
        fail(f"the page did not finish: {report}")
    if kind == "vat":
        check_vat(report, float(sys.argv[3]))
    elif kind == "pivots":
        check_pivots(report)
    elif kind == "anim":
        check_anim(report, sys.argv[3])
    elif kind == "cesium":
        check_cesium(report, sys.argv[3])
    else:
        fail(f"unknown kind {kind}")


if __name__ == "__main__":
    main()
