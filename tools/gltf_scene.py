"""gltf_scene.py - the little of glTF 2.0 that the peer benchmark needs
(tools/bench_mitsuba.py): the triangle primitives
under the default scene's nodes, in world space (translation/rotation/scale
or matrix; buffers as data: URIs or files beside the .gltf), each with its
material, and the first camera node. Not strata's importer (src/scene/scene.c):
an independent reading, so that a peer sees the scene as the file says.
"""
import base64
import json
import os
from collections import namedtuple

import numpy as np

# triangles: float64, n x 3 x 3 (world space); material: the glTF material
# object (a dict, {} when the primitive has none); normals: the NORMAL of
# each triangle corner in world space (n x 3 x 3, unit), None without;
# uvs: the TEXCOORD_0 of each corner (n x 3 x 2), None without.
Primitive = namedtuple("Primitive", "name triangles material normals uvs", defaults=(None, None))
# matrix: the camera node's 4x4 world matrix (the camera looks down its -z);
# yfov in radians.
Camera = namedtuple("Camera", "matrix yfov")


def quat_matrix(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def node_matrix(n):
    if "matrix" in n:
        return np.array(n["matrix"], dtype=np.float64).reshape(4, 4).T
    m = np.eye(4)
    m[:3, :3] = quat_matrix(n.get("rotation", [0, 0, 0, 1])) * np.array(n.get("scale", [1, 1, 1]))
    m[:3, 3] = n.get("translation", [0, 0, 0])
    return m


def load(path):
    """(list of Primitive in node order, depth first; Camera or None)."""
    g = json.load(open(path))
    folder = os.path.dirname(path)
    bufs = []
    for b in g["buffers"]:
        uri = b["uri"]
        bufs.append(base64.b64decode(uri.split(",", 1)[1]) if uri.startswith("data:")
                    else open(os.path.join(folder, uri), "rb").read())

    def accessor(i):
        a = g["accessors"][i]
        v = g["bufferViews"][a["bufferView"]]
        dt = {5126: np.float32, 5125: np.uint32, 5123: np.uint16, 5121: np.uint8}[a["componentType"]]
        k = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}[a["type"]]
        off = v.get("byteOffset", 0) + a.get("byteOffset", 0)
        return np.frombuffer(bufs[v["buffer"]], dt, a["count"] * k, off).reshape(-1, k)

    prims, camera = [], None
    stack = [(n, np.eye(4)) for n in g["scenes"][g.get("scene", 0)]["nodes"]]
    while stack:
        i, parent = stack.pop()
        n = g["nodes"][i]
        m = parent @ node_matrix(n)
        for c in n.get("children", []):
            stack.append((c, m))
        if "camera" in n and camera is None:
            camera = Camera(m, g["cameras"][n["camera"]]["perspective"]["yfov"])
        mesh = g["meshes"][n["mesh"]] if "mesh" in n else {"primitives": []}
        for p in mesh["primitives"]:
            pos = accessor(p["attributes"]["POSITION"]).astype(np.float64)
            pos = pos @ m[:3, :3].T + m[:3, 3]
            idx = accessor(p["indices"]).ravel() if "indices" in p else np.arange(len(pos))
            material = g["materials"][p["material"]] if "material" in p else {}
            normals = None
            if "NORMAL" in p["attributes"]:  # normals go by the inverse transpose
                nrm = accessor(p["attributes"]["NORMAL"]).astype(np.float64)
                nrm = nrm @ np.linalg.inv(m[:3, :3])
                nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
                normals = nrm[idx].reshape(-1, 3, 3)
            uvs = None
            if "TEXCOORD_0" in p["attributes"]:
                uvs = accessor(p["attributes"]["TEXCOORD_0"]).astype(np.float64)[idx]
                uvs = uvs.reshape(-1, 3, 2)
            prims.append(Primitive(n.get("name", mesh.get("name", "mesh%d" % i)),
                                   pos[idx].reshape(-1, 3, 3), material, normals, uvs))
    return prims, camera
