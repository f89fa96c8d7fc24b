#!/usr/bin/env python3
"""Writes scenes/furnace.gltf: the inside of a cube whose every face emits
radiance 1 and reflects albedo 0.5 (Lambertian: KHR_materials_specular's
specularFactor 0 turns the glTF BRDF's specular lobe off), seen from its centre.

A "furnace test": the radiance along every camera ray is known in closed form,
L = sum_{k=0..D} 0.5^k for paths gathering light at D vertices (D = 1 for
direct lighting), so `strata bench` can check a device's image against an
analytic value before it reports a speed. Standard library only."""
import base64, json, struct, sys

def quad(p0, p1, p2, p3, n):
    return [p0, p1, p2, p0, p2, p3], [n] * 6

def main(out, emission=1.0):
    faces = []
    # inward normals; winding counter-clockwise seen from inside
    for axis in range(3):
        for sign in (-1.0, 1.0):
            n = [0.0, 0.0, 0.0]
            n[axis] = -sign
            u, v = (axis + 1) % 3, (axis + 2) % 3
            def pt(a, b):
                p = [0.0, 0.0, 0.0]
                p[axis], p[u], p[v] = sign, a, b
                return p
            corners = [pt(-1, -1), pt(1, -1), pt(1, 1), pt(-1, 1)]
            if sign > 0:
                corners.reverse()
            faces.append(quad(*corners, n))
    pos = [c for f in faces for p in f[0] for c in p]
    nrm = [c for f in faces for p in f[1] for c in p]
    count = len(pos) // 3
    blob = struct.pack("<%df" % len(pos), *pos) + struct.pack("<%df" % len(nrm), *nrm)
    uri = "data:application/octet-stream;base64," + base64.b64encode(blob).decode()
    gltf = {
        "asset": {"version": "2.0", "generator": "strata tools/make_furnace.py"},
        "scene": 0,
        "scenes": [{"name": "furnace", "nodes": [0, 1]}],
        "nodes": [{"name": "box", "mesh": 0},
                  {"name": "camera", "camera": 0, "translation": [0.0, 0.0, 0.0]}],
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 1.0, "znear": 0.01, "aspectRatio": 1.0}}],
        "meshes": [{"name": "box", "primitives": [
            {"attributes": {"POSITION": 0, "NORMAL": 1}, "material": 0, "mode": 4}]}],
        "materials": [{"name": "glow", "pbrMetallicRoughness": {
            "baseColorFactor": [0.5, 0.5, 0.5, 1.0], "metallicFactor": 0.0,
            "roughnessFactor": 1.0}, "emissiveFactor": [1.0, 1.0, 1.0],
            "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}],
        "extensionsUsed": ["KHR_materials_specular"] +
                          (["KHR_materials_emissive_strength"] if emission != 1.0 else []),
        "buffers": [{"byteLength": len(blob), "uri": uri}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 12 * count},
            {"buffer": 0, "byteOffset": 12 * count, "byteLength": 12 * count}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3",
             "min": [-1.0, -1.0, -1.0], "max": [1.0, 1.0, 1.0]},
            {"bufferView": 1, "componentType": 5126, "count": count, "type": "VEC3"}],
    }
    if emission != 1.0:
        gltf["materials"][0]["extensions"]["KHR_materials_emissive_strength"] = {
            "emissiveStrength": emission}
    with open(out, "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")

if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "scenes/furnace.gltf",
         float(sys.argv[2]) if len(sys.argv) > 2 else 1.0)
