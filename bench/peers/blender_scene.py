"""Shared by the Blender peer scripts: prints the result as one JSON line (on a line of its own,
since Blender's operator reports may leave stdout mid-line) and writes it to OUT_JSON unless "-"."""
import json
import sys


def report(out, out_json):
    line = json.dumps(out)
    if out_json and out_json != "-":
        with open(out_json, "w") as f:
            f.write(line + "\n")
    sys.stdout.write("\n")
    sys.stderr.flush()
    sys.stdout.flush()
    print(line)
    sys.stdout.flush()
