#!/usr/bin/env python3
"""make_cornell_box.py - writes scenes/cornell-box.gltf, strata's default scene,
or with --bench the bench's Cornell box (build/scenes/cornell-bench.gltf).

Standard library only. The default scene it writes is committed; the bench's
is made by the build where tests and benchmarks need it (make, the Makefile's
BENCH_SCENE). Usage: python3 tools/make_cornell_box.py [--bench] [OUT.gltf]

The bench's box (--bench) is the one strata is compared on with other
renderers (tools/bench_peers.sh): the same geometry in units of 100 mm, the
light 0.5 mm below the ceiling, and the reflectances and emission of the
Cornell box scene of Mitsuba's scene collection (the measured spectra as
linear RGB: white (0.885809, 0.698859, 0.666422), red (0.570068, 0.0430135,
0.0443706), green (0.105421, 0.37798, 0.076425), light (18.387, 13.9873,
6.75357)), so that a peer reads the very values strata renders.

Geometry: the Cornell box as measured by the Cornell Program of Computer
Graphics ("Cornell Box Data", https://www.graphics.cornell.edu/online/box/data.html),
converted from millimetres to metres. The walls are not quite planar or
rectangular in that data, so every quad is two triangles with their own
vertices and flat normals. Every face is wound counter-clockwise as seen
from the side its normal faces (glTF front faces), and the normals face into
the box (walls, floor, ceiling), out of the blocks, and down (the light).
The bottoms of the blocks rest on the floor and are left out.

Materials (linear RGB, diffuse: KHR_materials_specular's specularFactor 0
leaves the glTF BRDF Lambertian, as the Cornell box is): white 0.73, red (0.63, 0.065, 0.05), green
(0.14, 0.45, 0.09), values close to the measured reflectances used by many
renderers' Cornell boxes. The light is a quad 1 mm below the ceiling, facing
down, emitting (17, 12, 4): emissiveFactor (1, 12/17, 4/17) times
KHR_materials_emissive_strength 17.

Camera: at (278, 273, -800) mm looking along +Z (the glTF camera looks along
its local -Z, so the node turns 180 degrees about Y), focal length 35 mm on a
25 mm film: yfov = 2 atan(12.5 / 35).

One buffer, embedded as a base64 data: URI, with three bufferViews:
positions, normals (float VEC3) and indices (unsigned short).
"""
import base64
import json
import math
import os
import struct
import sys

MM = 0.001  # millimetres to metres

# name, material, quads (corners in mm, in the published order), which way
# the normals face: 'in' (towards the box centre), 'out' (away from the
# block's centre) or 'down'.
PARTS = [
    ("floor", "white", "in", [[(552.8, 0, 0), (0, 0, 0), (0, 0, 559.2), (549.6, 0, 559.2)]]),
    ("ceiling", "white", "in",
     [[(556.0, 548.8, 0), (556.0, 548.8, 559.2), (0, 548.8, 559.2), (0, 548.8, 0)]]),
    ("back_wall", "white", "in",
     [[(549.6, 0, 559.2), (0, 0, 559.2), (0, 548.8, 559.2), (556.0, 548.8, 559.2)]]),
    ("red_wall", "red", "in",
     [[(552.8, 0, 0), (549.6, 0, 559.2), (556.0, 548.8, 559.2), (556.0, 548.8, 0)]]),
    ("green_wall", "green", "in",
     [[(0, 0, 559.2), (0, 0, 0), (0, 548.8, 0), (0, 548.8, 559.2)]]),
    ("short_block", "white", "out", [
        [(130.0, 165.0, 65.0), (82.0, 165.0, 225.0), (240.0, 165.0, 272.0), (290.0, 165.0, 114.0)],
        [(290.0, 0, 114.0), (290.0, 165.0, 114.0), (240.0, 165.0, 272.0), (240.0, 0, 272.0)],
        [(130.0, 0, 65.0), (130.0, 165.0, 65.0), (290.0, 165.0, 114.0), (290.0, 0, 114.0)],
        [(82.0, 0, 225.0), (82.0, 165.0, 225.0), (130.0, 165.0, 65.0), (130.0, 0, 65.0)],
        [(240.0, 0, 272.0), (240.0, 165.0, 272.0), (82.0, 165.0, 225.0), (82.0, 0, 225.0)],
    ]),
    ("tall_block", "white", "out", [
        [(423.0, 330.0, 247.0), (265.0, 330.0, 296.0), (314.0, 330.0, 456.0),
         (472.0, 330.0, 406.0)],
        [(423.0, 0, 247.0), (423.0, 330.0, 247.0), (472.0, 330.0, 406.0), (472.0, 0, 406.0)],
        [(472.0, 0, 406.0), (472.0, 330.0, 406.0), (314.0, 330.0, 456.0), (314.0, 0, 456.0)],
        [(314.0, 0, 456.0), (314.0, 330.0, 456.0), (265.0, 330.0, 296.0), (265.0, 0, 296.0)],
        [(265.0, 0, 296.0), (265.0, 330.0, 296.0), (423.0, 330.0, 247.0), (423.0, 0, 247.0)],
    ]),
    # The published light sits in the ceiling plane (y = 548.8); ours hangs
    # 1 mm lower so that it does not coincide with the ceiling.
    ("light", "light", "down",
     [[(343.0, 547.8, 227.0), (343.0, 547.8, 332.0), (213.0, 547.8, 332.0),
       (213.0, 547.8, 227.0)]]),
]

MATERIALS = [
    ("white", (0.73, 0.73, 0.73), None),
    ("red", (0.63, 0.065, 0.05), None),
    ("green", (0.14, 0.45, 0.09), None),
    ("light", (0.78, 0.78, 0.78), (17.0, 12.0, 4.0)),
]

# The bench's variant (--bench): scale, light height (mm), materials.
BENCH = {
    "scale": 0.01,
    "light_y": 548.3,
    "materials": [
        ("white", (0.885809, 0.698859, 0.666422), None),
        ("red", (0.570068, 0.0430135, 0.0443706), None),
        ("green", (0.105421, 0.37798, 0.076425), None),
        ("light", (0.0, 0.0, 0.0), (18.387, 13.9873, 6.75357)),
    ],
}

BOX_CENTRE = (278.0, 274.4, 279.6)  # mm, the middle of the room


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def unit(v):
    n = math.sqrt(dot(v, v))
    return [x / n for x in v]


def centroid(points):
    return [sum(p[i] for p in points) / len(points) for i in range(3)]


def wanted_direction(facing, quad, part_quads):
    """The direction the quad's normal should point to."""
    c = centroid(quad)
    if facing == "in":
        return sub(BOX_CENTRE, c)
    if facing == "out":
        return sub(c, centroid([p for q in part_quads for p in q]))
    return [0.0, -1.0, 0.0]


def triangles(facing, quads):
    """Each quad as two triangles (a, b, c) and (a, c, d), reversed where the
    Newell normal of the quad points the wrong way."""
    out = []
    for quad in quads:
        newell = [0.0, 0.0, 0.0]
        for i in range(4):
            p, q = quad[i], quad[(i + 1) % 4]
            newell[0] += (p[1] - q[1]) * (p[2] + q[2])
            newell[1] += (p[2] - q[2]) * (p[0] + q[0])
            newell[2] += (p[0] - q[0]) * (p[1] + q[1])
        if dot(newell, wanted_direction(facing, quad, quads)) < 0:
            quad = quad[::-1]
        a, b, c, d = quad
        out += [(a, b, c), (a, c, d)]
    return out


def bench_parts():
    """PARTS with the light at the bench's height."""
    out = []
    for name, material, facing, quads in PARTS:
        if name == "light":
            quads = [[(x, BENCH["light_y"], z) for x, _, z in q] for q in quads]
        out.append((name, material, facing, quads))
    return out


def build(bench=False):
    scale = BENCH["scale"] if bench else MM
    parts = bench_parts() if bench else PARTS
    mats = BENCH["materials"] if bench else MATERIALS
    blob = bytearray()
    positions, normals, indices = bytearray(), bytearray(), bytearray()
    accessors, meshes, nodes = [], [], []
    mat_index = {name: i for i, (name, _, _) in enumerate(mats)}
    for name, material, facing, quads in parts:
        tris = triangles(facing, quads)
        pos_off, nrm_off, idx_off = len(positions), len(normals), len(indices)
        verts = []
        for tri in tris:
            n = unit(cross(sub(tri[1], tri[0]), sub(tri[2], tri[0])))
            for p in tri:
                q = [x * scale for x in p]
                verts.append(q)
                positions += struct.pack("<3f", *q)
                normals += struct.pack("<3f", *n)
        for i in range(len(verts)):
            indices += struct.pack("<H", i)
        first = len(accessors)
        # glTF requires min/max on POSITION; they must bound the float32 values.
        f32 = [struct.unpack("<3f", struct.pack("<3f", *v)) for v in verts]
        accessors += [
            {"bufferView": 0, "byteOffset": pos_off, "componentType": 5126,
             "count": len(verts), "type": "VEC3",
             "min": [min(v[i] for v in f32) for i in range(3)],
             "max": [max(v[i] for v in f32) for i in range(3)]},
            {"bufferView": 1, "byteOffset": nrm_off, "componentType": 5126,
             "count": len(verts), "type": "VEC3"},
            {"bufferView": 2, "byteOffset": idx_off, "componentType": 5123,
             "count": len(verts), "type": "SCALAR"},
        ]
        meshes.append({"name": name, "primitives": [{
            "attributes": {"POSITION": first, "NORMAL": first + 1},
            "indices": first + 2, "material": mat_index[material], "mode": 4}]})
        nodes.append({"name": name, "mesh": len(meshes) - 1})
    while len(indices) % 4:
        indices += b"\0"
    views = []
    for data, target in ((positions, 34962), (normals, 34962), (indices, 34963)):
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data),
                      "target": target})
        blob += data
    yfov = 2.0 * math.atan(12.5 / 35.0)
    nodes.append({"name": "camera", "camera": 0,
                  "translation": [278.0 * scale, 273.0 * scale, -800.0 * scale],
                  "rotation": [0.0, 1.0, 0.0, 0.0]})
    materials = []
    for name, albedo, emission in mats:
        m = {"name": name,
             "pbrMetallicRoughness": {"baseColorFactor": list(albedo) + [1.0],
                                      "metallicFactor": 0.0, "roughnessFactor": 1.0},
             "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}
        if emission:
            strength = max(emission)
            m["emissiveFactor"] = [e / strength for e in emission]
            m["extensions"]["KHR_materials_emissive_strength"] = {"emissiveStrength": strength}
        materials.append(m)
    return {
        "asset": {"version": "2.0", "generator": "strata tools/make_cornell_box.py",
                  "copyright": "geometry: Cornell Program of Computer Graphics, Cornell Box Data"},
        "extensionsUsed": ["KHR_materials_emissive_strength", "KHR_materials_specular"],
        "scene": 0,
        "scenes": [{"name": "cornell-bench" if bench else "cornell-box",
                    "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "cameras": [{"name": "front", "type": "perspective",
                     "perspective": {"yfov": yfov, "aspectRatio": 1.0, "znear": 0.01}}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64,"
                            + base64.b64encode(bytes(blob)).decode("ascii")}],
    }


def main(argv):
    bench = "--bench" in argv[1:]
    args = [a for a in argv[1:] if a != "--bench"]
    out = args[0] if args else "scenes/cornell-box.gltf"
    with open(out + ".tmp", "w", encoding="ascii") as f:
        json.dump(build(bench), f, indent=1)
        f.write("\n")
    os.replace(out + ".tmp", out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
