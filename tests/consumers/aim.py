#!/usr/bin/env python3
"""Where the consumers' tests aim a ball at a building of a generated city: the footprint's
centre, 0.4 of the building's height, in dawnforge's axes (plan y becomes -z).

    aim.py CITY_JSON BUILDING_ID      prints X,Y,Z
"""
import json
import sys

city, wanted = sys.argv[1], int(sys.argv[2])
b = next(b for b in json.load(open(city))["buildings"] if b["id"] == wanted)
f = b["footprint"]
print("%.2f,%.2f,%.2f" % (sum(p[0] for p in f) / len(f), 0.4 * b["height"], -sum(p[1] for p in f) / len(f)))
