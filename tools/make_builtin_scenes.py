#!/usr/bin/env python3
"""make_builtin_scenes.py - writes strata's built-in test scenes for textures
and lighting: scenes/checkerboard.gltf, scenes/soft-shadows.gltf and
scenes/zone-plate.gltf (cornell-box.gltf and furnace.gltf have their own
tools).

Development tool, standard library only; the .gltf files it writes are
committed, so the build never runs this. Every buffer and image is a base64
data: URI, so the scenes load from inside the binary.
Usage: python3 tools/make_builtin_scenes.py [OUT_DIR]   (default: scenes)

checkerboard  A plane y = 0 from x = -1000 to 1000 and z = -2000 to 20 (a
              16 x 16 grid of quads), textured with an 8 x 8 checker (2 x 2
              squares of 4 x 4 texels, sRGB bytes 230 and 25; NEAREST
              magnification, REPEAT), UVs (x, z) / 2 so that every square is
              one unit: a million squares, receding to the horizon under a
              camera 1 unit above the plane, pitched 8 degrees down (yfov 40).
              No emitter: the default white environment lights it, and a
              plane open to the sky gets exactly albedo x env (no noise), so
              what the image shows is texture aliasing and its filtering.
zone-plate    A 2 x 2 square facing the camera, which it fills exactly (yfov
              40 degrees at distance 1 / tan 20), textured with a 512 x 512
              zone plate, linear value 1/2 + 1/2 cos(k r^2), r in texels from
              the centre, k = pi / (2 r_c), r_c the corner's radius: the local
              frequency k r / pi cycles per texel grows linearly from 0 at
              the centre to 1/2 (the texture's Nyquist) at the corners, so
              every frequency is present at once and a render below the
              texture's resolution shows where it aliases (Moire rings).
              LINEAR filters, CLAMP_TO_EDGE; lit like the checkerboard.
soft-shadows  An 8 x 8 floor, a sphere, a box turned 30 degrees and a small
              cube, under a 2.5 x 2.5 area light 4 units up facing down
              (emission 8): penumbrae that widen with the distance from the
              occluder.
"""
import base64
import json
import math
import os
import struct
import sys
import zlib


# ---- PNG (stdlib: zlib + struct; PNG spec, W3C 2003, sections 5 and 11) ----

def png_bytes(width, height, channels, rows):
    """rows: height lists of width * channels bytes (8-bit grey, RGB or RGBA)."""
    colour = {1: 0, 3: 2, 4: 6}[channels]
    raw = b"".join(b"\x00" + bytes(r) for r in rows)  # filter type 0 per row

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xffffffff)

    ihdr = struct.pack(">IIBBBBB", width, height, 8, colour, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def srgb_byte(linear):
    """IEC 61966-2-1 sRGB encoding of a linear value in [0, 1], rounded."""
    c = min(max(linear, 0.0), 1.0)
    s = c * 12.92 if c <= 0.0031308 else 1.055 * c ** (1.0 / 2.4) - 0.055
    return int(round(255.0 * s))


# ---- glTF writing ----------------------------------------------------------

class Scene:
    """Collects meshes, materials, images and nodes; writes one glTF file
    with a single data: URI buffer."""

    def __init__(self):
        self.blob = bytearray()
        self.views, self.accessors, self.meshes, self.materials = [], [], [], []
        self.images, self.textures, self.samplers, self.nodes = [], [], [], []
        self.cameras, self.extensions = [], set()

    def _view(self, data, target=None):
        while len(self.blob) % 4:
            self.blob.append(0)
        view = {"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(data)}
        if target:
            view["target"] = target
        self.blob.extend(data)
        self.views.append(view)
        return len(self.views) - 1

    def _accessor(self, values, n, kind, component=5126, target=34962):
        fmt = "<%d%s" % (len(values), "f" if component == 5126 else "I")
        view = self._view(struct.pack(fmt, *values), target)
        acc = {"bufferView": view, "componentType": component, "count": len(values) // n,
               "type": kind}
        if kind == "VEC3":
            acc["min"] = [min(values[i::3]) for i in range(3)]
            acc["max"] = [max(values[i::3]) for i in range(3)]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def mesh(self, name, pos, nrm, idx, material, uv=None):
        attrs = {"POSITION": self._accessor(pos, 3, "VEC3"),
                 "NORMAL": self._accessor(nrm, 3, "VEC3")}
        if uv is not None:
            attrs["TEXCOORD_0"] = self._accessor(uv, 2, "VEC2")
        ind = self._accessor(idx, 1, "SCALAR", 5125, 34963)
        self.meshes.append({"name": name, "primitives": [
            {"attributes": attrs, "indices": ind, "material": material, "mode": 4}]})
        return len(self.meshes) - 1

    def texture(self, png, mag, min_filter, wrap):
        uri = "data:image/png;base64," + base64.b64encode(png).decode("ascii")
        self.images.append({"uri": uri})
        self.samplers.append({"magFilter": mag, "minFilter": min_filter, "wrapS": wrap,
                              "wrapT": wrap})
        self.textures.append({"sampler": len(self.samplers) - 1, "source": len(self.images) - 1})
        return len(self.textures) - 1

    def material(self, name, colour, texture=None, emission=None):
        pbr = {"baseColorFactor": list(colour) + [1.0], "metallicFactor": 0.0,
               "roughnessFactor": 1.0}
        if texture is not None:
            pbr["baseColorTexture"] = {"index": texture}
        # specularFactor 0: Lambertian, so that closed forms (albedo x env) hold
        m = {"name": name, "pbrMetallicRoughness": pbr,
             "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}
        self.extensions.add("KHR_materials_specular")
        if emission:
            peak = max(emission)
            m["emissiveFactor"] = [e / peak for e in emission]
            if peak != 1.0:
                m["extensions"]["KHR_materials_emissive_strength"] = {"emissiveStrength": peak}
                self.extensions.add("KHR_materials_emissive_strength")
        self.materials.append(m)
        return len(self.materials) - 1

    def node(self, **fields):
        self.nodes.append(fields)
        return len(self.nodes) - 1

    def camera(self, name, eye, target, yfov_degrees):
        self.cameras.append({"type": "perspective", "perspective": {
            "yfov": math.radians(yfov_degrees), "znear": 0.01}})
        return self.node(name=name, camera=len(self.cameras) - 1, translation=list(eye),
                         rotation=look_at_quaternion(eye, target))

    def write(self, path, generator):
        g = {"asset": {"version": "2.0", "generator": generator},
             "scene": 0, "scenes": [{"nodes": list(range(len(self.nodes)))}],
             "nodes": self.nodes, "meshes": self.meshes, "materials": self.materials,
             "accessors": self.accessors, "bufferViews": self.views,
             "buffers": [{"byteLength": len(self.blob), "uri":
                          "data:application/octet-stream;base64," +
                          base64.b64encode(bytes(self.blob)).decode("ascii")}]}
        for key in ("cameras", "images", "samplers", "textures"):
            if getattr(self, key):
                g[key] = getattr(self, key)
        if self.extensions:
            g["extensionsUsed"] = sorted(self.extensions)
        with open(path, "w", encoding="ascii") as f:
            json.dump(g, f, indent=1)
            f.write("\n")


def normalise(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def look_at_quaternion(eye, target, up=(0.0, 1.0, 0.0)):
    """Rotation (x, y, z, w) turning the camera's -Z towards target with +Y up:
    the matrix with columns right, up', back, converted by Shepperd's method
    (Shepperd, "Quaternion from rotation matrix", J. Guidance 1(3), 1978)."""
    back = normalise([e - t for e, t in zip(eye, target)])
    right = normalise(cross(up, back))
    up2 = cross(back, right)
    m = [[right[i], up2[i], back[i]] for i in range(3)]  # m[row][col]
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0:
        s = 2.0 * math.sqrt(tr + 1.0)
        q = [(m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, s / 4]
    elif m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = 2.0 * math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2])
        q = [s / 4, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s, (m[2][1] - m[1][2]) / s]
    elif m[1][1] > m[2][2]:
        s = 2.0 * math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2])
        q = [(m[0][1] + m[1][0]) / s, s / 4, (m[1][2] + m[2][1]) / s, (m[0][2] - m[2][0]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1])
        q = [(m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, s / 4, (m[1][0] - m[0][1]) / s]
    return normalise(q)


# ---- geometry ----------------------------------------------------------------

def grid(x0, x1, z0, z1, n, y=0.0, uv_scale=None):
    """An n x n grid of quads on the plane y, normals +Y, wound counter-
    clockwise seen from above; uv = (x, z) * uv_scale."""
    pos, nrm, uv, idx = [], [], [], []
    for j in range(n + 1):
        for i in range(n + 1):
            x = x0 + (x1 - x0) * i / n
            z = z0 + (z1 - z0) * j / n
            pos += [x, y, z]
            nrm += [0.0, 1.0, 0.0]
            if uv_scale:
                uv += [x * uv_scale, z * uv_scale]
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            b, c, d = a + 1, a + n + 1, a + n + 2
            idx += [a, c, b, b, c, d]  # (x, z) -> y up: a, c, b is counter-clockwise from +Y
    return pos, nrm, idx, (uv if uv_scale else None)


def box(centre, size, yaw_degrees=0.0):
    """An axis box turned about Y, normals out, 4 vertices per face."""
    c, s = math.cos(math.radians(yaw_degrees)), math.sin(math.radians(yaw_degrees))
    pos, nrm, idx = [], [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            n = [0.0, 0.0, 0.0]
            n[axis] = sign
            u, v = (axis + 1) % 3, (axis + 2) % 3
            corners = []
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis], p[u], p[v] = sign, a, b
                corners.append(p)
            if sign < 0:
                corners.reverse()  # counter-clockwise seen from outside
            base = len(pos) // 3
            for p in corners:
                q = [p[k] * size[k] / 2 for k in range(3)]
                pos += [centre[0] + c * q[0] + s * q[2], centre[1] + q[1],
                        centre[2] - s * q[0] + c * q[2]]
                nrm += [c * n[0] + s * n[2], n[1], -s * n[0] + c * n[2]]
            idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return pos, nrm, idx


def sphere(centre, radius, rings=24, segments=48):
    pos, nrm, idx = [], [], []
    for j in range(rings + 1):
        theta = math.pi * j / rings
        for i in range(segments + 1):
            phi = 2 * math.pi * i / segments
            n = [math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi)]
            pos += [centre[k] + radius * n[k] for k in range(3)]
            nrm += n
    for j in range(rings):
        for i in range(segments):
            a = j * (segments + 1) + i
            b, c, d = a + 1, a + segments + 1, a + segments + 2
            if j > 0:
                idx += [a, c, b]
            if j < rings - 1:
                idx += [b, c, d]
    return pos, nrm, idx


def flip_down(pos, nrm, idx):
    """The same quad facing -Y: normals negated, winding reversed."""
    return pos, [-x for x in nrm], [idx[i + k] for i in range(0, len(idx), 3) for k in (0, 2, 1)]


# ---- the scenes ----------------------------------------------------------------

GEN = "strata tools/make_builtin_scenes.py"
NEAREST, LINEAR, LINEAR_MIPMAP_LINEAR = 9728, 9729, 9987
REPEAT, CLAMP = 10497, 33071


def checkerboard(path):
    s = Scene()
    light, dark = 230, 25
    rows = [[light if ((x // 4) + (y // 4)) % 2 == 0 else dark for x in range(8) for _ in range(3)]
            for y in range(8)]
    tex = s.texture(png_bytes(8, 8, 3, rows), NEAREST, LINEAR_MIPMAP_LINEAR, REPEAT)
    mat = s.material("checker", (1.0, 1.0, 1.0), texture=tex)
    pos, nrm, idx, uv = grid(-1000.0, 1000.0, -2000.0, 20.0, 16, uv_scale=0.5)
    s.node(name="plane", mesh=s.mesh("plane", pos, nrm, idx, mat, uv))
    pitch = math.radians(8.0)
    s.camera("camera", (0.0, 1.0, 0.0), (0.0, 1.0 - math.sin(pitch), -math.cos(pitch)), 40.0)
    s.write(path, GEN)


def zone_plate(path):
    s = Scene()
    n = 512
    rc = math.sqrt(2.0) * n / 2  # radius of the corners, in texels
    k = math.pi / (2.0 * rc)
    rows = []
    for y in range(n):
        dy = y + 0.5 - n / 2
        rows.append([srgb_byte(0.5 + 0.5 * math.cos(k * ((x + 0.5 - n / 2) ** 2 + dy * dy)))
                     for x in range(n)])
    tex = s.texture(png_bytes(n, n, 1, rows), LINEAR, LINEAR_MIPMAP_LINEAR, CLAMP)
    mat = s.material("zone plate", (1.0, 1.0, 1.0), texture=tex)
    # the square z = 0, x, y in [-1, 1], facing +Z; uv (0, 0) at the top left
    pos = [-1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0]
    uv = [0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0]
    s.node(name="plate", mesh=s.mesh("plate", pos, [0.0, 0.0, 1.0] * 4, [0, 1, 2, 0, 2, 3], mat, uv))
    d = 1.0 / math.tan(math.radians(20.0))
    s.camera("camera", (0.0, 0.0, d), (0.0, 0.0, 0.0), 40.0)
    s.write(path, GEN)


def soft_shadows(path):
    s = Scene()
    floor = s.material("floor", (0.7, 0.7, 0.7))
    red = s.material("red", (0.7, 0.12, 0.1))
    blue = s.material("blue", (0.15, 0.3, 0.7))
    yellow = s.material("yellow", (0.75, 0.6, 0.15))
    lamp = s.material("light", (0.8, 0.8, 0.8), emission=(8.0, 8.0, 8.0))
    pos, nrm, idx, _ = grid(-4.0, 4.0, -4.0, 4.0, 1)
    s.node(name="floor", mesh=s.mesh("floor", pos, nrm, idx, floor))
    s.node(name="sphere", mesh=s.mesh("sphere", *sphere((-1.3, 0.7, 0.2), 0.7), red))
    s.node(name="box", mesh=s.mesh("box", *box((1.2, 0.75, -0.4), (1.0, 1.5, 1.0), 30.0), blue))
    s.node(name="cube", mesh=s.mesh("cube", *box((0.2, 0.25, 1.4), (0.5, 0.5, 0.5), -15.0), yellow))
    pos, nrm, idx, _ = grid(-1.25, 1.25, -1.25, 1.25, 1, y=4.0)
    s.node(name="light", mesh=s.mesh("light", *flip_down(pos, nrm, idx), lamp))
    s.camera("camera", (0.0, 3.6, 7.0), (0.0, 0.6, 0.0), 40.0)
    s.write(path, GEN)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "scenes"
    checkerboard(os.path.join(out, "checkerboard.gltf"))
    zone_plate(os.path.join(out, "zone-plate.gltf"))
    soft_shadows(os.path.join(out, "soft-shadows.gltf"))


if __name__ == "__main__":
    main()
