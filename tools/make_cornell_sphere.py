#!/usr/bin/env python3
"""make_cornell_sphere.py - the whole-pass benchmark's large scene: the bench
Cornell box with the trace benchmark's icosphere (327,680 triangles, from
tools/make_icosphere.c) standing on its floor, so that most rays traverse a
large tree; tools/bench_peers.sh renders it with strata and Mitsuba.

The sphere gets the box's "white" material (Lambertian, one-sided, as every
surface of the box; the icosphere's triangles run counter-clockwise seen
from outside) and a node that scales it to radius RADIUS and sets it on the
floor at (CENTRE_X, RADIUS, CENTRE_Z): in front of the tall block and to the
right of the short one (x 3.0 .. 5.3, z 0.1 .. 2.4 against the blocks'
x <= 2.9 and z >= 2.47), so it cuts neither. The box's own buffer is
embedded as it was (a data: URI, or the file's bytes re-encoded); the
icosphere's .bin is referenced by its path relative to OUT (not copied).
Usage: python3 tools/make_cornell_sphere.py CORNELL.gltf ICOSPHERE.gltf OUT.gltf
"""
import base64
import json
import os
import sys

RADIUS = 1.15
CENTRE_X, CENTRE_Z = 4.15, 1.25


def embedded(uri, folder):
    """A buffer's URI as a data: URI (a file beside the .gltf read in)."""
    if uri.startswith("data:"):
        return uri
    with open(os.path.join(folder, uri), "rb") as f:
        return "data:application/octet-stream;base64," + base64.b64encode(f.read()).decode()


def add_sphere(box, sphere, bin_uri):
    """Appends the icosphere's one POSITION accessor (with its buffer and
    view), a mesh of it with the box's white material, and its node."""
    white = [m.get("name") for m in box["materials"]].index("white")
    acc = sphere["accessors"][sphere["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
    view = dict(sphere["bufferViews"][acc["bufferView"]], buffer=len(box["buffers"]))
    box["buffers"].append({"uri": bin_uri, "byteLength": sphere["buffers"][0]["byteLength"]})
    box["bufferViews"].append(view)
    box["accessors"].append(dict(acc, bufferView=len(box["bufferViews"]) - 1))
    box["meshes"].append({"name": "icosphere", "primitives": [
        {"attributes": {"POSITION": len(box["accessors"]) - 1}, "material": white}]})
    box["nodes"].append({"name": "icosphere", "mesh": len(box["meshes"]) - 1,
                         "translation": [CENTRE_X, RADIUS, CENTRE_Z], "scale": [RADIUS] * 3})
    box["scenes"][box.get("scene", 0)]["nodes"].append(len(box["nodes"]) - 1)


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__.split("Usage: ")[1])
    box_path, sphere_path, out = sys.argv[1:]
    with open(box_path) as f:
        box = json.load(f)
    with open(sphere_path) as f:
        sphere = json.load(f)
    if len(sphere["buffers"]) != 1:
        sys.exit("make_cornell_sphere: %s: expected one buffer (tools/make_icosphere.c's)" % sphere_path)
    for b in box["buffers"]:
        b["uri"] = embedded(b["uri"], os.path.dirname(box_path))
    sphere_bin = os.path.join(os.path.dirname(sphere_path), sphere["buffers"][0]["uri"])
    add_sphere(box, sphere, os.path.relpath(sphere_bin, os.path.dirname(os.path.abspath(out))))
    box["asset"]["generator"] = "strata tools/make_cornell_sphere.py"
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(box, f)
    os.replace(tmp, out)  # no half-written scene


if __name__ == "__main__":
    main()
