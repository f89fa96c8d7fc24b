#!/usr/bin/env python3
"""Writes tests/scenes/edge.gltf: one emissive quad (radiance 1) covering the
left part of the view, x < 0.37, over an empty (black) background, seen
straight on by an orthogonal-looking narrow perspective camera. With
--max-depth 0 every pixel away from the quad's edge sees one constant value,
so its error estimate is 0, while pixels on the edge mix 1 and 0: the test
scene of adaptive sampling (tests/image/test_render.c). Standard library only."""
import base64, json, struct, sys

def main(out):
    x1 = 0.37
    pos = [-10, -10, 0, x1, -10, 0, x1, 10, 0, -10, 10, 0]
    nrm = [0, 0, 1] * 4
    idx = [0, 1, 2, 0, 2, 3]
    blob = struct.pack("<12f", *pos) + struct.pack("<12f", *nrm) + struct.pack("<6H", *idx)
    uri = "data:application/octet-stream;base64," + base64.b64encode(blob).decode()
    gltf = {
        "asset": {"version": "2.0", "generator": "strata tools/make_edge.py"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.0, 0.0, 4.0]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1},
                                     "indices": 2, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]},
                       "emissiveFactor": [1, 1, 1]}],
        "buffers": [{"byteLength": len(blob), "uri": uri}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 96, "byteLength": 12}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-10, -10, 0], "max": [x1, 10, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
    }
    with open(out, "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")

if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "tests/scenes/edge.gltf")
