#!/usr/bin/env python3
"""make_test_scenes.py - writes the small glTF files that tests/unit/test_scene.c loads.

Development tool, standard library only; its output is committed next to it.
Run from the repository root: python3 tests/scenes/make_test_scenes.py

layout_*      one pyramid (5 vertices, 4 triangles) stored every way the loader
              must read: u8/u16/u32 indices, interleaved with byteStride, no
              indices, external .bin, data: URI, .glb. test_scene.c expects the
              same triangles from each, from its own copy of PYRAMID.
trs_nested    a mesh under nested TRS and matrix nodes (one mirrored), in a
              non-default scene; trs_baked holds the same triangles with the
              transforms applied here, in Python, as plain vertices.
camera_pick   cameras in a hierarchy, listed depth first: an orthographic one,
              then perspective ones (the first under a rotated node, one in a
              later subtree, one in a later root).
materials_flat  no normals (flat normals expected), a zero-area and a
              collinear triangle (dropped), an emissive material with
              KHR_materials_emissive_strength, a primitive without material
              (default appended), a POINTS primitive (skipped).
textures      texture coordinates and materials: TEXCOORD_0 as float,
              normalised unsigned byte and unsigned short; a 4 x 2 PNG (data:
              URI) and a 2 x 2 PNG stored in a bufferView; materials with a
              base colour texture (NEAREST magnification, MIRRORED_REPEAT x
              CLAMP_TO_EDGE), an emissive texture with KHR_texture_transform,
              a metallic-roughness texture on the same image (a second, linear
              chain), a texture on TEXCOORD_1 (ignored, a warning), alpha MASK
              (cutoff 0.3) and BLEND; a LINES primitive (skipped, a warning).
textured_quad a 2 x 2 quad filling an orthographic view, its material's every
              factor multiplied by a constant texture (base colour sRGB 188,
              metallic-roughness G = 255, B = 0, emissive sRGB 64), Lambertian
              (KHR_materials_specular's specularFactor 0, metallic 0.2 x 0): a
              render must give emission + albedo x environment in every pixel.
textured.glb  a quad with a 4 x 4 RGBA texture stored in the GLB's BIN chunk
              (for byte mutation tests: the image decoder meets damaged PNGs).
cutout        two quads seen by an orthographic camera: the front one red,
              alpha MASK with its left half at alpha 0; the back one green
              (both Lambertian: specularFactor 0).
image_*       textured_quad with an image that cannot be decoded or read: a
              warning, and a white texture in its place.
uses_variants textured_quad using (not requiring) KHR_materials_variants: a
              warning.
quad_strip, quad_fan  the quad as a TRIANGLE_STRIP and as a TRIANGLE_FAN.
quad_sparse   the quad with vertex 2 moved to (2, 3, 0) by a sparse accessor
              (quad_sparse_zeros: over zeros, every vertex sparse).
black_emitter textured_quad with a black emissive texture (emissiveFactor > 0):
              nothing emits.
vertex_color  a white Lambertian quad with COLOR_0 (bytes 128, 64, 255, 255).
unlit         the quad with KHR_materials_unlit, base colour (0.3, 0.6, 0.9).
material_extensions  the quad with KHR_materials_specular (factor 0.5, colour
              (1, 0.5, 0.25), a specularTexture), KHR_materials_ior 1.4 and a
              normalTexture of scale 0.5.
normal_tilt   textured_quad as a white Lambertian plane whose constant normal
              map tilts the shading normal by about 60 degrees.
normal_missing  normal_tilt with its normal map's file missing.
coat_normal   normal_tilt's map at scale 1/3 as the clearcoatNormalTexture of a
              rough clear coat over the white plane, lit by a directional
              light at the view's mirror direction about the coat's normal;
              coat_normal_missing, the same with that map's file missing.
glass_panes   a lamp seen through four glass panes (eight interfaces).
glass_mitsuba_coarse  glass_mitsuba with the spheres of glass_furnace_coarse.
glass_mitsuba_thin  glass_mitsuba with its spheres smooth and thin-walled.
thin_pane     a smooth thin-walled glass quad (no KHR_materials_volume) before
              a lamp quad; thin_pane_white, a white one and no lamp.
glass_furnace_coarse  glass_furnace's spheres with 6 rings and 8 segments, smooth
              normals (far from the facets' at the outline).
sided_one, sided_two  a 2 x 2 x 2 cube about the origin, counter-clockwise
              seen from outside (its fronts face out), KHR_materials_unlit
              (0.3, 0.6, 0.9), doubleSided false / true; camera 0 perspective
              at the centre looking down -Z, camera 1 orthographic outside on +Z.
quantized, quantized_float  a pyramid under a scaled node, once with
              KHR_mesh_quantization (positions as plain shorts; normals as normalised bytes; tangents as normalised
              shorts; texcoords as plain unsigned bytes) and once as floats holding the values the extension's
              decoding gives (c, max(c / 127, -1), max(c / 32767, -1), ...).
shadow_*      a grey (0.5) Lambertian ground at z = -1 under a black occluder at
              z = 0 facing down (one-sided: the camera above sees through it to
              the ground; shadow rays meet it), orthographic: shadow_cutout's occluder is
              the 2 x 2 quad, alpha MASK with its left half (x < 0) at alpha 0;
              shadow_half's is only the right half, opaque; shadow_opaque's the
              whole quad, opaque; shadow_blend's the whole quad, BLEND alpha 0.5.
two_uv        the quad, unlit white, seen as textured_quad is: TEXCOORD_0 constant
              (0.25, 0.5), TEXCOORD_1 the quad's own uv as normalised unsigned
              shorts; its base colour texture, a 2 x 1 PNG (red | blue, NEAREST
              magnification), and its normal map (flat) read TEXCOORD_1, so the
              view's left half (x < 0, u < 0.5) is red and its right half blue,
              where TEXCOORD_0 would make all of it red; tangents generated from
              TEXCOORD_1 are +x (u grows with x) with w = +1 (v falls with y,
              so -dP/dv = +y = n x t).
              two_uv_transform names texCoord 0 and KHR_texture_transform's
              texCoord 1 (identity transform); two_uv_coord2 names texCoord 2.
              two_uv_light: a white Lambertian ground (the quad, z = 0) under a
              one-sided emitter (the quad turned to face -z at z = 1, so the
              camera above sees through its back): emissiveFactor 1 times a
              2 x 1 texture black | white (NEAREST) on TEXCOORD_1 (its own uv;
              TEXCOORD_0 constant on the white texel), so only its half x > 0
              emits; half_light: the same with that half alone as the emitter,
              untextured.
shade_mix     six 1 x 1 quads of a 3 x 2 ground (z = 0) under two one-sided
              emitters facing down at z = 1.5 (the camera above, orthographic and
              wider than the ground, sees through their backs and past the
              ground's edges): white and red Lambertian quads beside a
              textured, an alpha MASK, a vertex-coloured and a metallic one,
              so that shade's lanes mix them; the emitter over x > 0 has an
              emissive texture (grey | white), the one over x < 0 none.
tangent_ramp  the quad (u along +x, v along -y, as glTF's v runs down the
              image), white and Lambertian, without TANGENT, whose constant
              normal map (bytes 128, 64, 238: n = (0, -0.5, 0.87) in tangent
              space) tilts the normal towards +v, the way a height ramp
              rising towards -v does; tangent_ramp_mirrored: its u mirrored
              (u along -x); tangent_ramp_given: tangent_ramp with the TANGENT
              (1, 0, 0, 1) that glTF's definition gives (bitangent
              w cross(n, t) = +y, towards -v).
glow_box      sided_one's closed cube, double-sided, its inside emitting
              radiance 1 (a dim emitter: emissiveFactor 1, no strength), camera 0
              at its centre; glow_box_open: the same without its +z face;
              glow_box_one_sided: one-sided, so the camera inside sees through
              the backs of its outward-facing walls. dark_box: the same cube
              grey (0.5) and emitting nothing: no sky reaches its camera.
lamp_and_glow the quad emitting radiance 1 (power 4 pi: area 4) and, in front
              of it, the quad scaled by 0.25 (area 0.25) as a lamp of
              emissiveStrength 4 (power pi): the lamp carries less than half
              of the power; lamp_over_glow: strength 32 (power 8 pi), more.
instancing    the triangle (0, 0, 0), (1, 0, 0), (0, 1, 0) (normal +z) on a node at
              (10, 0, 0) with EXT_mesh_gpu_instancing (required): three
              instances, T (0, 0, 0), R identity, S 1; T (1, 0, 0), R 90
              degrees about +z, S 1; T (0, 2, 0), R identity, S 2.
              instancing_huge: 2^20 triangles (a sparse POSITION accessor over
              zeros) in 65 instances: more than 2^26, the triangle cap.
morph         that triangle with two morph targets moving vertex 2 by
              (0, 0, 1) and by (0, 1, 0) (target 0 also turns every normal by
              (1, 0, 0)), mesh weights (0.5, 0.25); node 0 draws it with the
              mesh's weights, node 1, at (5, 0, 0), with its own (1, 0).
skin          a four-vertex fan, v0 (0, 0, 0) and v1 (1, 0, 0) on joint 0, v2
              (0, 2, 0) on joint 1, v3 (0.5, 1, 0) half on each, skinned by
              joint 0 (the root, identity) and joint 1 (its child, at (0, 1, 0),
              turned 90 degrees about +z in its default transform; bound
              unturned: inverseBindMatrices identity and T(0, -1, 0)); the
              mesh's node (at (100, 0, 0), a child of joint 1: its transform
              must be ignored) and one animation (not played).
specgloss     the quad with KHR_materials_pbrSpecularGlossiness (required) in two
              materials on two primitives: factors only (diffuse (0.5, 0.25, 1,
              1), specular (0.2, 0.3, 0.4), glossiness 0.75), and glossiness 0.5
              with a 2 x 1 RGBA specularGlossinessTexture (RGB (10, 20, 30) A
              64 | RGB (200, 100, 50) A 255) and a diffuseTexture.
glass_slab    a unit glass cube (KHR_materials_transmission 1, ior 1.5,
              KHR_materials_volume attenuationColor 0.5 after 1) face-on to an
              orthographic camera; glass_furnace: a smooth and a rough (0.5)
              glass sphere side by side, nothing else; glass: a Lambertian
              floor and wall under a quad light, a smooth glass sphere, a rough
              one that absorbs and a half-transmissive tinted one of ior 1.33;
              glass_mitsuba: the same without the light, the third sphere fully
              transmissive and smooth (what Mitsuba's dielectrics match).
coat_quad     two quads face-on to an orthographic camera, Lambertian black
              (left) and white (right) under a full smooth clear coat; coat:
              glass's floor, wall and light with a coated red Lambertian
              sphere, a coated rough gold one and coated glass.
sheen_quad    two Lambertian quads (specularFactor 0) side by side, turned 60
              degrees about x, seen by an orthographic camera at cos 0.5: black
              under a sheen of colour (1, 0.5, 0.25) x a white sheenColorTexture
              and roughness 1 x a sheenRoughnessTexture of alpha 128 (left),
              white under a sheen of colour 0.8 and roughness 0.5 (right);
              sheen: glass's floor, wall and light with a red velvet sphere
              (sheen 0.9, roughness 0.3), a rough gold one under sheen and coat
              and glass under a sheen.
aniso_mitsuba glass_mitsuba's floor and wall with three white metal spheres
              (roughness 0.2; 32 rings and 48 segments with texture
              coordinates, so tangents run along the latitudes) under
              KHR_materials_anisotropy: strength 0, 0.5 along the tangent and
              0.5 turned by 90 degrees (what Mitsuba's roughconductor with
              alpha_u, alpha_v matches).
aniso_quad    sheen_quad's two tilted quads (texture coordinates: u along x),
              white metals: left of roughness 0.4 under anisotropy 0.8 turned
              by 0.5 radians x an anisotropyTexture of direction (1, 1) and
              strength 128 / 255 (texel (255, 255, 128)), right of roughness
              0.3 with strength 0 (isotropic).
dtrans_lamp   a white Lambertian sheet (specularFactor 0, [-1, 1]² at z = 0,
              facing +Z, filling an orthographic view from z = 5) under
              KHR_materials_diffuse_transmission: factor 0.75 x a texture of
              A 204 (0.6), colour (1, 0.5, 1) x an sRGB texture (255, 255,
              128); behind it, at z = -0.5, a lamp [-1.5, 1.5]² facing it
              (emission 1, black).
irid_quad     sheen_quad's two tilted quads, smooth (roughness 0): left a black
              dielectric under KHR_materials_iridescence (factor 1 x texture R
              191, ior 1.3, thickness 200 .. 600 nm by texture G 128), right a
              metal of base colour (0.9, 0.6, 0.3) under a film of factor 0.5
              and ior 1.8 (thickness: the default maximum, 400 nm).
dispersion_slab  a smooth glass slab (a solid: KHR_materials_volume) 1 thick,
              turned 45 degrees about y, between an orthographic camera looking
              down -z (view [-1, 1] x [-0.5, 0.5]) and a thin emissive line (0.06
              wide, emission 10) at z = -4: KHR_materials_dispersion 5 (V_d 4);
              dispersion_slab_zero with dispersion 0; clear_slab without the
              extension.
bad_*         malformed files, each wrong in one way (named by the file).
markers       two small unlit cubes (half side 0.01), white at (1, 2, -3) and red
              at (1.5, 2.25, -3.5), no camera: --look-at puts them where the
              pinhole projection says (tests/device/test_view.c).
aov_plane     a Lambertian quad of base colour (0.2, 0.5, 0.8) at z = -1.5, facing
              +Z, filling an orthographic view from z = 2: albedo, normal (0, 0, 1),
              depth 3.5 and position (x, y, -1.5) in every pixel.
aov_sphere    a UV sphere (48 x 24 segments) of radius 1 about (0.5, -0.25, -1)
              with its exact normals at the vertices, seen from (0.5, -0.25, 3).
"""
import base64
import json
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))

# The pyramid: a unit square base at z = 0 (left open), apex above its centre.
PYRAMID_V = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 1.0, 0.0), (0.0, 1.0, 0.0), (0.5, 0.5, 1.0)]
PYRAMID_T = [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)]


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def pyramid_normal(v):
    """Vertex normal: away from (0.5, 0.5, -0.5), below the base's centre."""
    return unit([v[0] - 0.5, v[1] - 0.5, v[2] + 0.5])


def f32(values):
    return struct.pack("<%df" % len(values), *values)


def data_uri(blob):
    return "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode("ascii")


def doc(meshes, accessors, views, buffers, nodes=None, scenes=None, scene=0, **extra):
    g = {"asset": {"version": "2.0", "generator": "strata tests/scenes/make_test_scenes.py"}}
    g["scene"] = scene
    g["scenes"] = scenes if scenes is not None else [{"nodes": [0]}]
    g["nodes"] = nodes if nodes is not None else [{"mesh": 0}]
    g["meshes"] = meshes
    g["accessors"] = accessors
    g["bufferViews"] = views
    g["buffers"] = buffers
    g.update(extra)
    return g


def png(width, height, channels, rows):
    """PNG (W3C 2003 spec, sections 5, 11) of 8-bit rows (grey, RGB or RGBA)."""
    raw = b"".join(b"\x00" + bytes(r) for r in rows)

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xffffffff)

    ihdr = struct.pack(">IIBBBBB", width, height, 8, {1: 0, 3: 2, 4: 6}[channels], 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) +
            chunk(b"IEND", b""))


def png_uri(data):
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


def write_json(name, g):
    with open(os.path.join(HERE, name), "w", encoding="ascii") as f:
        json.dump(g, f, indent=1)
        f.write("\n")


def write_bytes(name, data):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


def vec3_accessor(view, offset, count, values=None):
    a = {"bufferView": view, "byteOffset": offset, "componentType": 5126, "count": count,
         "type": "VEC3"}
    if values is not None:
        a["min"] = [min(v[i] for v in values) for i in range(3)]
        a["max"] = [max(v[i] for v in values) for i in range(3)]
    return a


def pyramid_arrays():
    pos = [x for v in PYRAMID_V for x in v]
    nrm = [x for v in PYRAMID_V for x in pyramid_normal(v)]
    idx = [i for t in PYRAMID_T for i in t]
    return pos, nrm, idx


def prim(pos, nrm, ind=None):
    p = {"attributes": {"POSITION": pos, "NORMAL": nrm}}
    if ind is not None:
        p["indices"] = ind
    return p


def layout_indexed(component, fmt, size, index_offset):
    """Separate views for positions, normals, indices; the index accessor
    starts index_offset bytes into its view."""
    pos, nrm, idx = pyramid_arrays()
    blob = bytearray(f32(pos) + f32(nrm))
    iview = len(blob)
    blob += b"\xee" * index_offset + struct.pack("<%d%s" % (len(idx), fmt), *idx)
    while len(blob) % 4:
        blob += b"\0"
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 60, "target": 34962},
             {"buffer": 0, "byteOffset": 60, "byteLength": 60, "target": 34962},
             {"buffer": 0, "byteOffset": iview, "byteLength": index_offset + size * len(idx),
              "target": 34963}]
    accessors = [vec3_accessor(0, 0, 5, PYRAMID_V), vec3_accessor(1, 0, 5),
                 {"bufferView": 2, "byteOffset": index_offset, "componentType": component,
                  "count": len(idx), "type": "SCALAR"}]
    return [{"primitives": [prim(0, 1, 2)]}], accessors, views, bytes(blob)


def write_layouts():
    # u8 indices, external .bin
    meshes, acc, views, blob = layout_indexed(5121, "B", 1, 0)
    write_bytes("layout_u8.bin", blob)
    write_json("layout_u8.gltf",
               doc(meshes, acc, views, [{"byteLength": len(blob), "uri": "layout_u8.bin"}]))
    # u16 indices at byte 2 of their view, data: URI
    meshes, acc, views, blob = layout_indexed(5123, "H", 2, 2)
    write_json("layout_u16.gltf",
               doc(meshes, acc, views, [{"byteLength": len(blob), "uri": data_uri(blob)}]))
    # u32 indices at byte 4 of their view, data: URI
    meshes, acc, views, blob = layout_indexed(5125, "I", 4, 4)
    write_json("layout_u32.gltf",
               doc(meshes, acc, views, [{"byteLength": len(blob), "uri": data_uri(blob)}]))
    # the same u16 layout as a .glb
    meshes, acc, views, blob = layout_indexed(5123, "H", 2, 2)
    write_bytes("layout.glb", glb(doc(meshes, acc, views, [{"byteLength": len(blob)}]), blob))

    # interleaved: per vertex [position 12][pad 4][normal 12][pad 4], stride 32,
    # the view 8 bytes into the buffer; u16 indices after it; external .bin
    pos, nrm, idx = pyramid_arrays()
    blob = bytearray(b"\xab" * 8)
    for v in range(5):
        blob += f32(pos[3 * v:3 * v + 3]) + b"\xcd" * 4 + f32(nrm[3 * v:3 * v + 3]) + b"\xcd" * 4
    iview = len(blob)
    blob += struct.pack("<%dH" % len(idx), *idx)
    while len(blob) % 4:
        blob += b"\0"
    views = [{"buffer": 0, "byteOffset": 8, "byteLength": 160, "byteStride": 32, "target": 34962},
             {"buffer": 0, "byteOffset": iview, "byteLength": 2 * len(idx), "target": 34963}]
    acc = [vec3_accessor(0, 0, 5, PYRAMID_V), vec3_accessor(0, 16, 5),
           {"bufferView": 1, "componentType": 5123, "count": len(idx), "type": "SCALAR"}]
    write_bytes("layout_interleaved.bin", bytes(blob))
    write_json("layout_interleaved.gltf",
               doc([{"primitives": [prim(0, 1, 2)]}], acc, views,
                   [{"byteLength": len(blob), "uri": "layout_interleaved.bin"}]))

    # non-indexed: the 12 corners written out
    corners = [PYRAMID_V[i] for t in PYRAMID_T for i in t]
    blob = f32([x for v in corners for x in v]) + \
        f32([x for v in corners for x in pyramid_normal(v)])
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 144, "target": 34962},
             {"buffer": 0, "byteOffset": 144, "byteLength": 144, "target": 34962}]
    acc = [vec3_accessor(0, 0, 12, corners), vec3_accessor(1, 0, 12)]
    write_json("layout_nonindexed.gltf",
               doc([{"primitives": [prim(0, 1)]}], acc, views,
                   [{"byteLength": len(blob), "uri": data_uri(blob)}]))


def glb(g, blob):
    """GLB container (glTF 2.0 §4.4): header, JSON chunk, BIN chunk."""
    js = json.dumps(g, separators=(",", ":")).encode("ascii")
    js += b" " * (-len(js) % 4)
    blob = bytes(blob) + b"\0" * (-len(blob) % 4)
    total = 12 + 8 + len(js) + 8 + len(blob)
    return (struct.pack("<4sII", b"glTF", 2, total) + struct.pack("<II", len(js), 0x4E4F534A)
            + js + struct.pack("<II", len(blob), 0x004E4942) + blob)


# ---- transforms, in plain Python (row-major 4x4 lists) ---------------------

def mat_mul(a, b):
    return [[sum(a[r][k] * b[k][c] for k in range(4)) for c in range(4)] for r in range(4)]


def trs(t=(0, 0, 0), q=(0, 0, 0, 1), s=(1, 1, 1)):
    x, y, z, w = q
    r = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    return [[r[i][0] * s[0], r[i][1] * s[1], r[i][2] * s[2], t[i]] for i in range(3)] + \
        [[0, 0, 0, 1]]


def axis_angle(axis, degrees):
    a = unit(axis)
    h = math.radians(degrees) / 2
    return (a[0] * math.sin(h), a[1] * math.sin(h), a[2] * math.sin(h), math.cos(h))


def column_major(m):
    return [m[r][c] for c in range(4) for r in range(4)]


def det3(a):
    return (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))


def inverse3(a):
    """Inverse by Gauss-Jordan elimination with partial pivoting."""
    m = [list(a[r][:3]) + [1.0 if r == c else 0.0 for c in range(3)] for r in range(3)]
    for c in range(3):
        p = max(range(c, 3), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        piv = m[c][c]
        m[c] = [x / piv for x in m[c]]
        for r in range(3):
            if r != c:
                f = m[r][c]
                m[r] = [m[r][k] - f * m[c][k] for k in range(6)]
    return [row[3:] for row in m]


def apply_point(m, p):
    return [sum(m[r][k] * p[k] for k in range(3)) + m[r][3] for r in range(3)]


def apply_normal(m, n):
    inv = inverse3(m)  # normal' = (A^-1)^T n
    return unit([sum(inv[k][r] * n[k] for k in range(3)) for r in range(3)])


# A bent quad: two triangles with their own vertices and face normals.
BENT_TRIS = [[(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(1, 0, 0), (1, 1, 0.5), (0, 1, 0)]]


def face_normal(t):
    e1 = [t[1][i] - t[0][i] for i in range(3)]
    e2 = [t[2][i] - t[0][i] for i in range(3)]
    return unit([e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                 e1[0] * e2[1] - e1[1] * e2[0]])


def write_trs():
    verts = [v for t in BENT_TRIS for v in t]
    nrms = [face_normal(t) for t in BENT_TRIS for _ in range(3)]
    blob = f32([x for v in verts for x in v]) + f32([x for n in nrms for x in n])
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 72, "target": 34962},
             {"buffer": 0, "byteOffset": 72, "byteLength": 72, "target": 34962}]
    acc = [vec3_accessor(0, 0, 6, verts), vec3_accessor(1, 0, 6)]

    root = trs((1, 2, 3), axis_angle((1, 1, 0), 30), (2, 0.5, 1.5))
    child = trs((0.5, 0, 1), axis_angle((0, 0, 1), 90), (1, 2, 1))
    mirror_t, mirror_q, mirror_s = (0, 0, -2), axis_angle((1, 0, 0), 45), (-1, 1, 1)
    mirror = trs(mirror_t, mirror_q, mirror_s)
    side = trs((0, -1, 0))
    nodes = [
        {"name": "root", "mesh": 0, "translation": [1, 2, 3],
         "rotation": list(axis_angle((1, 1, 0), 30)), "scale": [2, 0.5, 1.5], "children": [1, 3]},
        {"name": "matrix_child", "mesh": 0, "matrix": column_major(child), "children": [2]},
        {"name": "mirrored", "mesh": 0, "translation": list(mirror_t),
         "rotation": list(mirror_q), "scale": list(mirror_s)},
        {"name": "side", "mesh": 0, "translation": [0, -1, 0]},
        {"name": "other_scene_only", "mesh": 0, "translation": [100, 0, 0]},
    ]
    # scene 0 is a decoy; "scene": 1 must be the one loaded.
    write_json("trs_nested.gltf",
               doc([{"primitives": [prim(0, 1)]}], acc, views,
                   [{"byteLength": len(blob), "uri": data_uri(blob)}],
                   nodes=nodes, scenes=[{"nodes": [4]}, {"nodes": [0]}], scene=1))

    # Depth-first order: root, matrix_child, mirrored, side.
    worlds = [root, mat_mul(root, child), mat_mul(mat_mul(root, child), mirror),
              mat_mul(root, side)]
    bp, bn = [], []
    for w in worlds:
        flip = det3(w) < 0
        for t in BENT_TRIS:
            n = face_normal(t)
            corners = [apply_point(w, p) for p in t]
            normals = [apply_normal(w, n)] * 3
            if flip:
                corners = [corners[0], corners[2], corners[1]]
            bp += corners
            bn += normals
    blob = f32([x for v in bp for x in v]) + f32([x for n in bn for x in n])
    nb = 12 * len(bp)
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": nb, "target": 34962},
             {"buffer": 0, "byteOffset": nb, "byteLength": nb, "target": 34962}]
    acc = [vec3_accessor(0, 0, len(bp), bp), vec3_accessor(1, 0, len(bp))]
    write_json("trs_baked.gltf",
               doc([{"primitives": [prim(0, 1)]}], acc, views,
                   [{"byteLength": len(blob), "uri": data_uri(blob)}]))


def write_camera_pick():
    pos, nrm, idx = pyramid_arrays()
    blob = f32(pos) + f32(nrm)
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 60, "target": 34962},
             {"buffer": 0, "byteOffset": 60, "byteLength": 60, "target": 34962}]
    acc = [vec3_accessor(0, 0, 5, PYRAMID_V), vec3_accessor(1, 0, 5)]
    nodes = [
        {"name": "rig", "translation": [1, 0, 0], "scale": [2, 2, 2], "children": [1, 2, 3]},
        {"name": "ortho", "camera": 2},
        {"name": "arm", "children": [4]},
        {"name": "late", "camera": 1, "translation": [0, 0, 9]},
        {"name": "picked", "camera": 0, "translation": [0, 1, 0],
         "rotation": list(axis_angle((0, 1, 0), 90))},
        {"name": "geometry", "mesh": 0},
        {"name": "later_root", "camera": 1, "translation": [0, 0, 5]},
    ]
    cameras = [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}},
               {"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.1}},
               {"type": "orthographic",
                "orthographic": {"xmag": 1, "ymag": 1, "zfar": 10, "znear": 0.1}}]
    write_json("camera_pick.gltf",
               doc([{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1},
                                     "mode": 0}, prim(0, 1)]}], acc, views,
                   [{"byteLength": len(blob), "uri": data_uri(blob)}],
                   nodes=nodes, scenes=[{"nodes": [5, 0, 6]}], cameras=cameras))


def write_materials_flat():
    # primitive 0 (material 0): a counter-clockwise and a clockwise triangle
    # in the z = 0 plane; primitive 1 (no material): one good triangle, one
    # with a repeated vertex and one with collinear vertices; primitive 2:
    # POINTS.
    p0 = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (2, 0, 0), (2, 1, 0), (3, 0, 0)]
    p1 = [(0, 0, 1), (0, 1, 1), (0, 0, 2), (5, 5, 5), (5, 5, 5), (6, 5, 5),
          (0, 0, 0), (1, 1, 1), (3, 3, 3)]
    blob = f32([x for v in p0 + p1 for x in v])
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": len(blob), "target": 34962}]
    acc = [vec3_accessor(0, 0, len(p0), p0), vec3_accessor(0, 12 * len(p0), len(p1), p1)]
    meshes = [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0},
                              {"attributes": {"POSITION": 1}},
                              {"attributes": {"POSITION": 1}, "mode": 0, "material": 0}]}]
    materials = [{"name": "glow",
                  "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.3, 0.4, 0.5]},
                  "emissiveFactor": [1.0, 0.5, 0.25],
                  "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}}}]
    write_json("materials_flat.gltf",
               doc(meshes, acc, views, [{"byteLength": len(blob), "uri": data_uri(blob)}],
                   materials=materials, extensionsUsed=["KHR_materials_emissive_strength"]))


QUAD_POS = [-1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0]
QUAD_UV = [0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0]


class Blob:
    """One buffer built view by view (4-byte aligned)."""

    def __init__(self):
        self.data, self.views, self.accessors = bytearray(), [], []

    def view(self, data):
        while len(self.data) % 4:
            self.data.append(0)
        self.views.append({"buffer": 0, "byteOffset": len(self.data), "byteLength": len(data)})
        self.data += data
        return len(self.views) - 1

    def accessor(self, data, component, count, kind, **extra):
        a = {"bufferView": self.view(data), "componentType": component, "count": count,
             "type": kind}
        a.update(extra)
        self.accessors.append(a)
        return len(self.accessors) - 1

    def quad(self, z=0.0, uv=None, uv_component=5126, uv_fmt="f"):
        pos = list(QUAD_POS)
        for k in range(2, 12, 3):
            pos[k] = z
        attrs = {"POSITION": self.accessor(f32(pos), 5126, 4, "VEC3",
                                           min=[-1.0, -1.0, z], max=[1.0, 1.0, z]),
                 "NORMAL": self.accessor(f32([0.0, 0.0, 1.0] * 4), 5126, 4, "VEC3")}
        if uv is not None:
            extra = {"normalized": True} if uv_component != 5126 else {}
            attrs["TEXCOORD_0"] = self.accessor(struct.pack("<8" + uv_fmt, *uv), uv_component, 4,
                                                "VEC2", **extra)
        ind = self.accessor(struct.pack("<6H", 0, 1, 2, 0, 2, 3), 5123, 6, "SCALAR")
        return {"attributes": attrs, "indices": ind}

    def buffers(self):
        return [{"byteLength": len(self.data), "uri": data_uri(bytes(self.data))}]


def ortho_camera_node(z=5.0):
    return {"name": "camera", "camera": 0, "translation": [0.0, 0.0, z]}


ORTHO = [{"type": "orthographic", "orthographic": {"xmag": 0.4, "ymag": 0.4, "zfar": 100.0,
                                                   "znear": 0.01}}]


def constant_png(rgb, size=4):
    return png(size, size, 3, [list(rgb) * size] * size)


def write_textures():
    b = Blob()
    # uv: float (the quad's own), normalised u8 (x 255) and u16 (x 65535)
    p_float = b.quad(0.0, QUAD_UV)
    p_u8 = b.quad(1.0, [0, 255, 255, 255, 255, 0, 0, 0], 5121, "B")
    p_u16 = b.quad(2.0, [0, 65535, 32768, 65535, 32768, 0, 0, 0], 5123, "H")
    p_u8["material"], p_u16["material"], p_float["material"] = 0, 1, 2
    lines = {"attributes": {"POSITION": p_float["attributes"]["POSITION"]}, "mode": 1}
    # image 0: 4 x 2 RGBA, data: URI; image 1: 2 x 2 RGB in a bufferView
    img0 = png(4, 2, 4, [[10, 20, 30, 255, 40, 50, 60, 128, 70, 80, 90, 0, 100, 110, 120, 64],
                          [130, 140, 150, 255, 160, 170, 180, 255, 190, 200, 210, 255,
                           220, 230, 240, 255]])
    img1 = png(2, 2, 3, [[255, 0, 0, 0, 255, 0], [0, 0, 255, 255, 255, 255]])
    images = [{"uri": png_uri(img0)}, {"bufferView": b.view(img1), "mimeType": "image/png"}]
    samplers = [{"magFilter": 9728, "wrapS": 33648, "wrapT": 33071}, {}]
    textures = [{"sampler": 0, "source": 0}, {"sampler": 1, "source": 1}, {"source": 0}]
    transform = {"KHR_texture_transform": {"offset": [0.5, 0.25], "rotation": math.pi / 2,
                                           "scale": [2.0, 3.0]}}
    materials = [
        {"name": "textured", "alphaMode": "MASK", "alphaCutoff": 0.3,
         "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1.0],
                                  "baseColorTexture": {"index": 0},
                                  "metallicFactor": 0.5,
                                  "metallicRoughnessTexture": {"index": 2}},
         "emissiveFactor": [1.0, 1.0, 1.0],
         "emissiveTexture": {"index": 1, "extensions": transform}},
        {"name": "second uv set", "alphaMode": "BLEND",
         "pbrMetallicRoughness": {"baseColorTexture": {"index": 1, "texCoord": 1},
                                  "metallicFactor": 0.0}},
        {"name": "shared", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                                    "metallicFactor": 0.0}},
    ]
    g = doc([{"name": "quads", "primitives": [p_float, p_u8, p_u16, lines]}], b.accessors,
            b.views, b.buffers(), materials=materials, images=images, samplers=samplers,
            textures=textures, extensionsUsed=["KHR_texture_transform"])
    write_json("textures.gltf", g)


def write_textured_quad():
    b = Blob()
    p = b.quad(0.0, QUAD_UV)
    p["material"] = 0
    images = [{"uri": png_uri(constant_png((188, 188, 188)))},
              {"uri": png_uri(constant_png((0, 255, 0)))},
              {"uri": png_uri(constant_png((64, 64, 64)))}]
    materials = [{"name": "constant textures",
                  "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.5, 0.25, 1.0],
                                           "baseColorTexture": {"index": 0},
                                           "metallicFactor": 0.2,
                                           "metallicRoughnessTexture": {"index": 1}},
                  "emissiveFactor": [0.5, 1.0, 0.0], "emissiveTexture": {"index": 2},
                  "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}]
    g = doc([{"primitives": [p]}], b.accessors, b.views, b.buffers(),
            nodes=[{"mesh": 0}, ortho_camera_node()], scenes=[{"nodes": [0, 1]}],
            cameras=ORTHO, materials=materials, images=images,
            textures=[{"source": 0}, {"source": 1}, {"source": 2}])
    write_json("textured_quad.gltf", g)


def write_textured_glb():
    b = Blob()
    p = b.quad(0.0, QUAD_UV)
    p["material"] = 0
    image = png(4, 4, 4, [[v for x in range(4) for v in (x * 60, y * 60, 200, 255)]
                          for y in range(4)])
    view = b.view(image)
    g = doc([{"primitives": [p]}], b.accessors, b.views, [{"byteLength": len(b.data)}],
            materials=[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                                 "metallicFactor": 0.0}}],
            images=[{"bufferView": view, "mimeType": "image/png"}], textures=[{"source": 0}])
    write_bytes("textured.glb", glb(g, b.data))


def write_cutout():
    b = Blob()
    front, back = b.quad(0.0, QUAD_UV), b.quad(-1.0, QUAD_UV)
    front["material"], back["material"] = 0, 1
    half = [[0, 0, 0, 0] * 2 + [255, 255, 255, 255] * 2] * 4  # left half alpha 0
    materials = [{"name": "front", "alphaMode": "MASK",
                  "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.0, 0.0, 1.0],
                                           "baseColorTexture": {"index": 0},
                                           "metallicFactor": 0.0},
                  "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}},
                 {"name": "back", "pbrMetallicRoughness": {"baseColorFactor": [0.0, 1.0, 0.0, 1.0],
                                                           "metallicFactor": 0.0},
                  "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}]
    g = doc([{"primitives": [front, back]}], b.accessors, b.views, b.buffers(),
            nodes=[{"mesh": 0}, ortho_camera_node()], scenes=[{"nodes": [0, 1]}],
            cameras=ORTHO, materials=materials, images=[{"uri": png_uri(png(4, 4, 4, half))}],
            samplers=[{"magFilter": 9728}], textures=[{"source": 0, "sampler": 0}])
    write_json("cutout.gltf", g)


def write_strip_fan():
    # the quad (vertices 0 1 2 3, triangles 0 1 2 and 0 2 3) as a strip
    # (1 2 0 3) and as a fan (0 1 2 3): the same two triangles, same winding
    for name, mode, order in (("quad_strip.gltf", 5, (1, 2, 0, 3)),
                              ("quad_fan.gltf", 6, (0, 1, 2, 3))):
        b = Blob()
        p = b.quad(0.0, QUAD_UV)
        b.views[b.accessors[p["indices"]]["bufferView"]]["byteLength"] = 8
        b.accessors[p["indices"]]["count"] = 4
        p["indices"] = b.accessor(struct.pack("<4H", *order), 5123, 4, "SCALAR")
        p["mode"] = mode
        write_json(name, doc([{"primitives": [p]}], b.accessors, b.views, b.buffers()))


def write_sparse():
    # the quad with vertex 2 moved to (2, 3, 0) by a sparse POSITION accessor:
    # over the quad's own positions, and over zeros (no bufferView) with
    # every vertex given sparsely
    for name, base in (("quad_sparse.gltf", True), ("quad_sparse_zeros.gltf", False)):
        b = Blob()
        p = b.quad(0.0, QUAD_UV)
        acc = b.accessors[p["attributes"]["POSITION"]]
        moved = list(QUAD_POS)
        moved[6:9] = [2.0, 3.0, 0.0]
        idx = [2] if base else [0, 1, 2, 3]
        vals = moved[6:9] if base else moved
        acc["sparse"] = {"count": len(idx),
                         "indices": {"bufferView": b.view(bytes(idx)), "componentType": 5121},
                         "values": {"bufferView": b.view(f32(vals))}}
        acc["max"] = [2.0, 3.0, 0.0]
        if not base:
            del acc["bufferView"]
        write_json(name, doc([{"primitives": [p]}], b.accessors, b.views, b.buffers()))


def write_lighting():
    # textured_quad whose emissive texture is black: emissiveFactor > 0, yet
    # nothing emits, so the white environment must light it
    with open(os.path.join(HERE, "textured_quad.gltf"), encoding="ascii") as f:
        g = json.load(f)
    g["images"][2]["uri"] = png_uri(constant_png((0, 0, 0)))
    write_json("black_emitter.gltf", g)
    # textured_quad as a white Lambertian plane with a constant normal map
    # tilting the normal about 60 degrees (bytes 238, 128, 191)
    g["images"].append({"uri": png_uri(constant_png((238, 128, 191)))})
    g["textures"].append({"source": len(g["images"]) - 1})
    g["materials"] = [{"name": "tilted", "pbrMetallicRoughness": {"metallicFactor": 0.0},
                       "normalTexture": {"index": len(g["textures"]) - 1},
                       "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}]
    write_json("normal_tilt.gltf", g)
    # the same with its normal map's file missing: the map is left out (a
    # white texel would tilt the normal by some 55 degrees), not made white
    g["images"][-1] = {"uri": "no_such_normal_map.png"}
    write_json("normal_missing.gltf", g)
    # normal_tilt's map (scale 1/3: some 30 degrees) moved to a clear coat
    # (factor 1, roughness 0.5) over the white Lambertian plane, lit by a
    # directional light of irradiance 1 from the coat normal's mirror
    # direction of the view (the tilt's y ignored): the coat's highlight
    # peaks there, the base keeps the plane's normal
    g["images"][-1] = {"uri": png_uri(constant_png((238, 128, 191)))}
    tilt = math.atan2((238 / 255 * 2 - 1) / 3, 191 / 255 * 2 - 1)
    g["materials"] = [{"name": "coat_tilted", "pbrMetallicRoughness": {"metallicFactor": 0.0},
                       "extensions": {
                           "KHR_materials_specular": {"specularFactor": 0.0},
                           "KHR_materials_clearcoat": {
                               "clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.5,
                               "clearcoatNormalTexture": {"index": len(g["textures"]) - 1,
                                                          "scale": 1.0 / 3.0}}}}]
    g["nodes"].append({"name": "sun", "rotation": [0.0, math.sin(tilt), 0.0, math.cos(tilt)],
                       "extensions": {"KHR_lights_punctual": {"light": 0}}})
    g["scenes"][0]["nodes"].append(len(g["nodes"]) - 1)
    g["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "directional",
                                                            "intensity": 1.0}]}}
    g["extensionsUsed"] = sorted(set(g.get("extensionsUsed", [])) |
                                 {"KHR_lights_punctual", "KHR_materials_clearcoat",
                                  "KHR_materials_specular"})
    write_json("coat_normal.gltf", g)
    # the same with the coat's normal map's file missing: left out
    g["images"][-1] = {"uri": "no_such_coat_normal_map.png"}
    write_json("coat_normal_missing.gltf", g)

    # the quad, white and Lambertian, with COLOR_0 (normalised bytes 128, 64,
    # 255, 255 at every vertex)
    b = Blob()
    p = b.quad(0.0, QUAD_UV)
    p["attributes"]["COLOR_0"] = b.accessor(bytes([128, 64, 255, 255] * 4), 5121, 4, "VEC4",
                                            normalized=True)
    p["material"] = 0
    g = doc([{"primitives": [p]}], b.accessors, b.views, b.buffers(),
            nodes=[{"mesh": 0}, ortho_camera_node()], scenes=[{"nodes": [0, 1]}],
            cameras=ORTHO, materials=[{"pbrMetallicRoughness": {"metallicFactor": 0.0},
                                       "extensions": {"KHR_materials_specular":
                                                      {"specularFactor": 0.0}}}])
    write_json("vertex_color.gltf", g)
    g["materials"] = [{"pbrMetallicRoughness": {"baseColorFactor": [0.3, 0.6, 0.9, 1.0]},
                       "extensions": {"KHR_materials_unlit": {}}}]
    g["extensionsUsed"] = ["KHR_materials_unlit"]
    del g["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"]
    write_json("unlit.gltf", g)
    g["materials"] = [{"pbrMetallicRoughness": {"baseColorFactor": [0.3, 0.6, 0.9, 1.0]},
                       "normalTexture": {"index": 0, "scale": 0.5},
                       "extensions": {"KHR_materials_specular": {
                           "specularFactor": 0.5, "specularColorFactor": [1.0, 0.5, 0.25],
                           "specularTexture": {"index": 0}},
                                      "KHR_materials_ior": {"ior": 1.4}}}]
    g["extensionsUsed"] = ["KHR_materials_specular", "KHR_materials_ior"]
    g["images"] = [{"uri": png_uri(constant_png((128, 128, 255)))}]
    g["textures"] = [{"source": 0}]
    write_json("material_extensions.gltf", g)


# tangent space normal of tangent_ramp's map, as bytes (n + 1) / 2 x 255
RAMP_TEXEL = (128, 64, 238)


def write_tangent_ramp():
    for name, mirrored, given in (("tangent_ramp.gltf", False, False),
                                  ("tangent_ramp_mirrored.gltf", True, False),
                                  ("tangent_ramp_given.gltf", False, True)):
        b = Blob()
        uv = list(QUAD_UV)
        if mirrored:
            uv[0::2] = [1.0 - u for u in uv[0::2]]
        p = b.quad(0.0, uv)
        if given:
            p["attributes"]["TANGENT"] = b.accessor(f32([1.0, 0.0, 0.0, 1.0] * 4), 5126, 4,
                                                    "VEC4")
        p["material"] = 0
        g = doc([{"primitives": [p]}], b.accessors, b.views, b.buffers(),
                nodes=[{"mesh": 0}, ortho_camera_node()], scenes=[{"nodes": [0, 1]}],
                cameras=ORTHO, images=[{"uri": png_uri(constant_png(RAMP_TEXEL))}],
                textures=[{"source": 0}],
                materials=[{"name": "ramp", "pbrMetallicRoughness": {"metallicFactor": 0.0},
                            "normalTexture": {"index": 0},
                            "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}])
        write_json(name, g)


def write_two_uv():
    b = Blob()
    p = b.quad(0.0, [0.25, 0.5] * 4)
    uv1 = [round(x * 65535) for x in QUAD_UV]
    p["attributes"]["TEXCOORD_1"] = b.accessor(struct.pack("<8H", *uv1), 5123, 4, "VEC2",
                                               normalized=True)
    p["material"] = 0
    images = [{"uri": png_uri(png(2, 1, 3, [[255, 0, 0, 0, 0, 255]]))},
              {"uri": png_uri(constant_png((128, 128, 255)))}]
    material = {"name": "second set",
                "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1}},
                "normalTexture": {"index": 1, "texCoord": 1},
                "extensions": {"KHR_materials_unlit": {}}}
    g = doc([{"primitives": [p]}], b.accessors, b.views, b.buffers(),
            nodes=[{"mesh": 0}, ortho_camera_node()], scenes=[{"nodes": [0, 1]}],
            cameras=ORTHO, materials=[material], images=images,
            samplers=[{"magFilter": 9728}], textures=[{"source": 0, "sampler": 0},
                                                      {"source": 1}],
            extensionsUsed=["KHR_materials_unlit"])
    write_json("two_uv.gltf", g)
    base = g["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]
    base["texCoord"] = 0
    base["extensions"] = {"KHR_texture_transform": {"texCoord": 1}}
    g["extensionsUsed"] = ["KHR_materials_unlit", "KHR_texture_transform"]
    write_json("two_uv_transform.gltf", g)
    del base["extensions"]
    base["texCoord"] = 2
    g["extensionsUsed"] = ["KHR_materials_unlit"]
    write_json("two_uv_coord2.gltf", g)


def write_two_uv_light():
    lambert = {"pbrMetallicRoughness": {"metallicFactor": 0.0},
               "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}
    emitter = {"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0],
                                        "metallicFactor": 0.0},
               "emissiveFactor": [1.0, 1.0, 1.0],
               "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}
    nodes = [{"mesh": 0}, {"mesh": 1, "translation": [0.0, 0.0, 1.0],
                           "rotation": [1.0, 0.0, 0.0, 0.0]}, ortho_camera_node()]
    for name in ("two_uv_light.gltf", "half_light.gltf"):
        b = Blob()
        ground = b.quad(0.0, QUAD_UV)
        ground["material"] = 0
        light = b.quad(0.0, [0.75, 0.5] * 4)
        light["material"] = 1
        extra = {}
        if name == "two_uv_light.gltf":
            light["attributes"]["TEXCOORD_1"] = b.accessor(f32(QUAD_UV), 5126, 4, "VEC2")
            emitter["emissiveTexture"] = {"index": 0, "texCoord": 1}
            extra = {"images": [{"uri": png_uri(png(2, 1, 3, [[0, 0, 0, 255, 255, 255]]))}],
                     "samplers": [{"magFilter": 9728}],
                     "textures": [{"source": 0, "sampler": 0}]}
        else:  # the emitter's half x > 0 alone
            half = [0.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0]
            light["attributes"]["POSITION"] = b.accessor(f32(half), 5126, 4, "VEC3",
                                                         min=[0.0, -1.0, 0.0],
                                                         max=[1.0, 1.0, 0.0])
            emitter.pop("emissiveTexture")
        g = doc([{"primitives": [ground]}, {"primitives": [light]}], b.accessors, b.views,
                b.buffers(), nodes=nodes, scenes=[{"nodes": [0, 1, 2]}], cameras=ORTHO,
                materials=[lambert, emitter], **extra)
        write_json(name, g)


def write_sided():
    # face (axis a, sign sg): corners c -+ u -+ v with u x v = the outward normal
    pos, ind = [], []
    for a in range(3):
        for sg in (1.0, -1.0):
            c = [0.0, 0.0, 0.0]
            c[a] = sg
            u, v = [0.0] * 3, [0.0] * 3
            u[(a + 1) % 3], v[(a + 2) % 3] = 1.0, 1.0
            if sg < 0:
                u, v = v, u
            base = len(pos) // 3
            for du, dv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                pos += [c[k] + du * u[k] + dv * v[k] for k in range(3)]
            ind += [base, base + 1, base + 2, base, base + 2, base + 3]
    b = Blob()
    p = {"attributes": {"POSITION": b.accessor(f32(pos), 5126, 24, "VEC3",
                                               min=[-1.0] * 3, max=[1.0] * 3)},
         "indices": b.accessor(struct.pack("<36H", *ind), 5123, 36, "SCALAR"), "material": 0}
    cameras = [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.01}}, ORTHO[0]]
    for name, two in (("sided_one.gltf", False), ("sided_two.gltf", True)):
        mat = {"pbrMetallicRoughness": {"baseColorFactor": [0.3, 0.6, 0.9, 1.0]},
               "doubleSided": two, "extensions": {"KHR_materials_unlit": {}}}
        g = doc([{"primitives": [p]}], b.accessors, b.views, b.buffers(),
                nodes=[{"mesh": 0}, {"camera": 0}, dict(ortho_camera_node(), camera=1)],
                scenes=[{"nodes": [0, 1, 2]}], cameras=cameras, materials=[mat],
                extensionsUsed=["KHR_materials_unlit"])
        write_json(name, g)


def write_lighting_default():
    with open(os.path.join(HERE, "sided_one.gltf"), encoding="ascii") as f:
        g = json.load(f)
    g["materials"] = [{"emissiveFactor": [1.0, 1.0, 1.0], "doubleSided": True,
                       "pbrMetallicRoughness": {"metallicFactor": 0.0}}]
    del g["extensionsUsed"]
    write_json("glow_box.gltf", g)
    dark = dict(g, materials=[{"doubleSided": True, "pbrMetallicRoughness": {
        "baseColorFactor": [0.5, 0.5, 0.5, 1.0], "metallicFactor": 0.0}}])
    write_json("dark_box.gltf", dark)
    g["materials"][0]["doubleSided"] = False
    write_json("glow_box_one_sided.gltf", g)
    g["materials"][0]["doubleSided"] = True
    b = Blob()
    # the cube's +z face (axis 2, sign +1) is its fifth: indices 24..29 dropped
    ind = [i for k, i in enumerate(struct.unpack_from("<36H", base64.b64decode(
        g["buffers"][0]["uri"].split(",", 1)[1]), g["bufferViews"][1]["byteOffset"]))
           if not 24 <= k < 30]
    b.data = bytearray(base64.b64decode(g["buffers"][0]["uri"].split(",", 1)[1]))
    b.views, b.accessors = g["bufferViews"], g["accessors"]
    g["meshes"][0]["primitives"][0]["indices"] = b.accessor(
        struct.pack("<30H", *ind), 5123, 30, "SCALAR")
    g["bufferViews"], g["accessors"], g["buffers"] = b.views, b.accessors, b.buffers()
    write_json("glow_box_open.gltf", g)
    for name, strength in (("lamp_and_glow.gltf", 4.0), ("lamp_over_glow.gltf", 32.0)):
        b = Blob()
        p = b.quad(0.0)
        p["material"] = 0
        lamp = dict(p, material=1)
        materials = [{"name": "glow", "emissiveFactor": [1.0, 1.0, 1.0]},
                     {"name": "lamp", "emissiveFactor": [1.0, 1.0, 1.0],
                      "extensions": {"KHR_materials_emissive_strength":
                                     {"emissiveStrength": strength}}}]
        g = doc([{"primitives": [p]}, {"primitives": [lamp]}], b.accessors, b.views,
                b.buffers(), nodes=[{"mesh": 0}, {"mesh": 1, "translation": [0.0, 0.0, 0.5],
                                                  "scale": [0.25, 0.25, 1.0]},
                                    ortho_camera_node()],
                scenes=[{"nodes": [0, 1, 2]}], cameras=ORTHO, materials=materials,
                extensionsUsed=["KHR_materials_emissive_strength"])
        write_json(name, g)


TRIANGLE = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
Z_ROT_90 = [0.0, 0.0, math.sqrt(0.5), math.sqrt(0.5)]  # (x, y, z, w)


def triangle_prim(b):
    return {"attributes": {"POSITION": b.accessor(f32(TRIANGLE), 5126, 3, "VEC3",
                                                  min=[0.0] * 3, max=[1.0, 1.0, 0.0]),
                           "NORMAL": b.accessor(f32([0.0, 0.0, 1.0] * 3), 5126, 3, "VEC3")}}


def write_structure():
    ext = ["EXT_mesh_gpu_instancing"]
    b = Blob()
    p = triangle_prim(b)
    attrs = {"TRANSLATION": b.accessor(f32([0, 0, 0, 1, 0, 0, 0, 2, 0]), 5126, 3, "VEC3"),
             "ROTATION": b.accessor(f32([0, 0, 0, 1] + Z_ROT_90 + [0, 0, 0, 1]), 5126, 3, "VEC4"),
             "SCALE": b.accessor(f32([1, 1, 1, 1, 1, 1, 2, 2, 2]), 5126, 3, "VEC3")}
    node = {"mesh": 0, "translation": [10.0, 0.0, 0.0],
            "extensions": {"EXT_mesh_gpu_instancing": {"attributes": attrs}}}
    write_json("instancing.gltf", doc([{"primitives": [p]}], b.accessors, b.views, b.buffers(),
                                      nodes=[node], extensionsUsed=ext, extensionsRequired=ext))
    b = Blob()
    b.accessors.append({"componentType": 5126, "count": 3 << 20, "type": "VEC3",
                        "sparse": {"count": 1, "indices": {"bufferView": b.view(struct.pack("<I", 0)),
                                                           "componentType": 5125},
                                   "values": {"bufferView": b.view(f32([0.0] * 3))}}})
    p = {"attributes": {"POSITION": 0}}
    attrs = {"TRANSLATION": b.accessor(f32([0.0] * 3 * 65), 5126, 65, "VEC3")}
    node = {"mesh": 0, "extensions": {"EXT_mesh_gpu_instancing": {"attributes": attrs}}}
    write_json("instancing_huge.gltf", doc([{"primitives": [p]}], b.accessors, b.views,
                                           b.buffers(), nodes=[node], extensionsUsed=ext,
                                           extensionsRequired=ext))
    b = Blob()
    p = triangle_prim(b)
    p["targets"] = [{"POSITION": b.accessor(f32([0, 0, 0, 0, 0, 0, 0, 0, 1]), 5126, 3, "VEC3",
                                            min=[0.0] * 3, max=[0.0, 0.0, 1.0]),
                     "NORMAL": b.accessor(f32([1, 0, 0] * 3), 5126, 3, "VEC3")},
                    {"POSITION": b.accessor(f32([0, 0, 0, 0, 0, 0, 0, 1, 0]), 5126, 3, "VEC3",
                                            min=[0.0] * 3, max=[0.0, 1.0, 0.0])}]
    write_json("morph.gltf", doc([{"primitives": [p], "weights": [0.5, 0.25]}], b.accessors,
                                 b.views, b.buffers(),
                                 nodes=[{"mesh": 0},
                                        {"mesh": 0, "translation": [5.0, 0.0, 0.0],
                                         "weights": [1.0, 0.0]}],
                                 scenes=[{"nodes": [0, 1]}]))
    b = Blob()
    pos = [0, 0, 0, 1, 0, 0, 0, 2, 0, 0.5, 1, 0]
    p = {"attributes": {"POSITION": b.accessor(f32(pos), 5126, 4, "VEC3", min=[0.0] * 3,
                                               max=[1.0, 2.0, 0.0]),
                        "NORMAL": b.accessor(f32([0.0, 0.0, 1.0] * 4), 5126, 4, "VEC3"),
                        "JOINTS_0": b.accessor(bytes([0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0,
                                                      0, 1, 0, 0]), 5121, 4, "VEC4"),
                        "WEIGHTS_0": b.accessor(f32([1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0,
                                                     0.5, 0.5, 0, 0]), 5126, 4, "VEC4")},
         "indices": b.accessor(struct.pack("<6H", 0, 1, 3, 0, 3, 2), 5123, 6, "SCALAR")}
    ibm = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,
           1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1]  # column-major: T(0, -1, 0)
    skins = [{"joints": [0, 1], "inverseBindMatrices": b.accessor(f32(ibm), 5126, 2, "MAT4")}]
    times = b.accessor(f32([0.0, 1.0]), 5126, 2, "SCALAR", min=[0.0], max=[1.0])
    turns = b.accessor(f32(Z_ROT_90 + [0, 0, 0, 1]), 5126, 2, "VEC4")
    animations = [{"channels": [{"sampler": 0, "target": {"node": 1, "path": "rotation"}}],
                   "samplers": [{"input": times, "output": turns}]}]
    nodes = [{"name": "joint 0", "children": [1]},
             {"name": "joint 1", "translation": [0.0, 1.0, 0.0], "rotation": Z_ROT_90,
              "children": [2]},
             {"name": "skinned", "mesh": 0, "skin": 0, "translation": [100.0, 0.0, 0.0]}]
    write_json("skin.gltf", doc([{"primitives": [p]}], b.accessors, b.views, b.buffers(),
                                nodes=nodes, skins=skins, animations=animations))


def write_specgloss():
    ext = ["KHR_materials_pbrSpecularGlossiness"]
    b = Blob()
    p0, p1 = b.quad(0.0, QUAD_UV), b.quad(1.0, QUAD_UV)
    p0["material"], p1["material"] = 0, 1
    sg = png(2, 1, 4, [[10, 20, 30, 64, 200, 100, 50, 255]])
    materials = [{"name": "factors", "extensions": {ext[0]: {
                      "diffuseFactor": [0.5, 0.25, 1.0, 1.0], "specularFactor": [0.2, 0.3, 0.4],
                      "glossinessFactor": 0.75}}},
                 {"name": "textured", "extensions": {ext[0]: {
                      "glossinessFactor": 0.5, "specularGlossinessTexture": {"index": 0},
                      "diffuseTexture": {"index": 1}}}}]
    g = doc([{"primitives": [p0, p1]}], b.accessors, b.views, b.buffers(), materials=materials,
            images=[{"uri": png_uri(sg)}, {"uri": png_uri(constant_png((90, 90, 90)))}],
            textures=[{"source": 0}, {"source": 1}], extensionsUsed=ext, extensionsRequired=ext)
    write_json("specgloss.gltf", g)


def write_quantized():
    pos = [(-2, -2, 0), (2, -2, 0), (2, 2, 0), (-2, 2, 0), (0, 0, 3)]
    nrm = [(0, -127, 0), (127, 0, 0), (0, 127, 0), (-128, 0, 0), (0, 0, 127)]  # -128: -1
    tan = [(32767, 0, 0, 32767), (0, 32767, 0, -32767), (-32768, 0, 0, 32767),
           (0, -32767, 0, 32767), (16384, 0, 0, 32767)]
    uv = [(0, 0), (1, 0), (2, 1), (0, 3), (255, 7)]
    ind = [0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4]

    def sn(c, m):
        return max(c / m, -1.0)
    variants = [  # (attribute, float values, packed element, stride, componentType, normalized)
        ("POSITION", pos, lambda e: struct.pack("<3hxx", *e), 8, 5122, False, "VEC3"),
        ("NORMAL", [[sn(c, 127) for c in e] for e in nrm], lambda e: struct.pack("<3bx", *e),
         4, 5120, True, "VEC3"),
        ("TANGENT", [[sn(c, 32767) for c in e] for e in tan], lambda e: struct.pack("<4h", *e),
         8, 5122, True, "VEC4"),
        ("TEXCOORD_0", uv, lambda e: struct.pack("<2Bxx", *e), 4, 5121, False, "VEC2"),
    ]
    quant_src = {"POSITION": pos, "NORMAL": nrm, "TANGENT": tan, "TEXCOORD_0": uv}
    for name, quantized in (("quantized.gltf", True), ("quantized_float.gltf", False)):
        blob, views, accessors, attrs = bytearray(), [], [], {}
        for attr, floats, pack, stride, ct, normalized, kind in variants:
            n = {"VEC2": 2, "VEC3": 3, "VEC4": 4}[kind]
            if quantized:
                data = b"".join(pack(e) for e in quant_src[attr])
                view = {"buffer": 0, "byteOffset": len(blob), "byteLength": len(data),
                        "byteStride": stride}
                acc = {"componentType": ct, "count": 5, "type": kind}
                if normalized:
                    acc["normalized"] = True
            else:
                data = struct.pack("<%df" % (5 * n), *[float(c) for e in floats for c in e])
                view = {"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)}
                acc = {"componentType": 5126, "count": 5, "type": kind}
            if attr == "POSITION":
                acc["min"], acc["max"] = [-2, -2, 0], [2, 2, 3]
            blob += data
            views.append(view)
            acc["bufferView"] = len(views) - 1
            accessors.append(acc)
            attrs[attr] = len(accessors) - 1
        data = struct.pack("<12H", *ind)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
        blob += data
        accessors.append({"bufferView": len(views) - 1, "componentType": 5123, "count": 12,
                          "type": "SCALAR"})
        g = doc([{"primitives": [{"attributes": attrs, "indices": len(accessors) - 1}]}],
                accessors, views, [{"byteLength": len(blob), "uri": data_uri(bytes(blob))}],
                nodes=[{"mesh": 0, "scale": [0.25, 0.5, 0.125], "translation": [1.0, 0.0, 0.0]}])
        if quantized:
            write_json("bad_quantized_undeclared.gltf", g)  # the types, without the extension
            g["extensionsUsed"] = g["extensionsRequired"] = ["KHR_mesh_quantization"]
        write_json(name, g)


def cube_prim(b, half):
    """A cube of side 2 half about the origin, flat normals, faces outwards."""
    pos, nrm, ind = [], [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            n = [0.0, 0.0, 0.0]
            n[axis] = sign
            u, v = [0.0] * 3, [0.0] * 3
            u[(axis + 1) % 3], v[(axis + 2) % 3] = 1.0, 1.0
            if sign < 0:
                u, v = v, u
            base = len(pos) // 3
            for a, c in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                pos += [half * (n[k] + a * u[k] + c * v[k]) for k in range(3)]
                nrm += n
            ind += [base, base + 1, base + 2, base, base + 2, base + 3]
    lo, hi = [-half] * 3, [half] * 3
    return {"attributes": {"POSITION": b.accessor(f32(pos), 5126, 24, "VEC3", min=lo, max=hi),
                           "NORMAL": b.accessor(f32(nrm), 5126, 24, "VEC3")},
            "indices": b.accessor(struct.pack("<36H", *ind), 5123, 36, "SCALAR")}


def sphere_prim(b, radius, rings=16, segments=24, uv=False):
    """A UV sphere with smooth normals, outwards; with `uv`, TEXCOORD_0 u
    along the segments (east, about +y) and v along the rings (north to
    south)."""
    pos, nrm, ind, tex = [], [], [], []
    for i in range(rings + 1):
        th = math.pi * i / rings
        for j in range(segments + 1):
            ph = 2.0 * math.pi * j / segments
            n = [math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph)]
            nrm += n
            pos += [radius * c for c in n]
            tex += [j / segments, i / rings]
    for i in range(rings):
        for j in range(segments):
            a, c = i * (segments + 1) + j, (i + 1) * (segments + 1) + j
            if i > 0:
                ind += [a, c, a + 1]
            if i < rings - 1:
                ind += [a + 1, c, c + 1]
    count = len(pos) // 3
    p = {"attributes": {"POSITION": b.accessor(f32(pos), 5126, count, "VEC3",
                                               min=[-radius] * 3, max=[radius] * 3),
                        "NORMAL": b.accessor(f32(nrm), 5126, count, "VEC3")},
         "indices": b.accessor(struct.pack("<%dH" % len(ind), *ind), 5123, len(ind), "SCALAR")}
    if uv:
        p["attributes"]["TEXCOORD_0"] = b.accessor(f32(tex), 5126, count, "VEC2")
    return p


# KHR_materials_volume with a thickness: the mesh bounds a solid (without
# it, transmission is thin-walled)
SOLID = {"thicknessFactor": 1.0}


def glass_material(roughness=0.0, base=(1.0, 1.0, 1.0), transmission=1.0, metallic=0.0,
                   attenuation=None):
    ext = {"KHR_materials_transmission": {"transmissionFactor": transmission},
           "KHR_materials_volume": dict(SOLID)}
    if attenuation is not None:
        ext["KHR_materials_volume"].update({"attenuationColor": list(attenuation[0]),
                                            "attenuationDistance": attenuation[1]})
    return {"pbrMetallicRoughness": {"baseColorFactor": list(base) + [1.0],
                                     "metallicFactor": metallic, "roughnessFactor": roughness},
            "extensions": ext}


GLASS_EXTENSIONS = ["KHR_materials_transmission", "KHR_materials_volume",
                    "KHR_materials_specular"]


def write_glass():
    """glass_slab: a unit glass cube face-on to an orthographic camera
    (attenuationColor 0.5 after 1, the cube's depth); glass_furnace: a
    smooth and a rough glass sphere side by side, nothing else; glass: a
    scene for the lanes and for Mitsuba, a Lambertian floor and back wall
    under a quad light, a smooth glass sphere, a rough one with absorption
    and a half-transmissive tinted one."""
    b = Blob()
    cube = cube_prim(b, 0.5)
    cube["material"] = 0
    g = doc([{"primitives": [cube]}], b.accessors, b.views, b.buffers(),
            nodes=[{"mesh": 0}, ortho_camera_node()], scenes=[{"nodes": [0, 1]}],
            cameras=[{"type": "orthographic", "orthographic": {"xmag": 1.0, "ymag": 1.0,
                                                               "zfar": 100.0, "znear": 0.01}}],
            materials=[glass_material(attenuation=((0.5, 0.5, 0.5), 1.0))],
            extensionsUsed=GLASS_EXTENSIONS[:2])
    write_json("glass_slab.gltf", g)

    b = Blob()
    spheres = [sphere_prim(b, 0.8), sphere_prim(b, 0.8)]
    spheres[0]["material"], spheres[1]["material"] = 0, 1
    g = doc([{"primitives": [spheres[0]]}, {"primitives": [spheres[1]]}], b.accessors, b.views,
            b.buffers(),
            nodes=[{"mesh": 0, "translation": [-1.0, 0.0, 0.0]},
                   {"mesh": 1, "translation": [1.0, 0.0, 0.0]}, ortho_camera_node()],
            scenes=[{"nodes": [0, 1, 2]}],
            cameras=[{"type": "orthographic", "orthographic": {"xmag": 2.0, "ymag": 1.0,
                                                               "zfar": 100.0, "znear": 0.01}}],
            materials=[glass_material(), glass_material(roughness=0.5)],
            extensionsUsed=GLASS_EXTENSIONS[:1])
    write_json("glass_furnace.gltf", g)
    # the same two spheres coarse (6 rings, 8 segments) with their smooth
    # normals: the shading normals stray far from the facets' at the outline
    b = Blob()
    spheres = [sphere_prim(b, 0.8, 6, 8), sphere_prim(b, 0.8, 6, 8)]
    spheres[0]["material"], spheres[1]["material"] = 0, 1
    g["meshes"] = [{"primitives": [spheres[0]]}, {"primitives": [spheres[1]]}]
    g["accessors"], g["bufferViews"], g["buffers"] = b.accessors, b.views, b.buffers()
    write_json("glass_furnace_coarse.gltf", g)

    tinted = dict(glass_material(roughness=0.2, base=(0.9, 0.7, 0.3), transmission=0.5),
                  extensions={"KHR_materials_transmission": {"transmissionFactor": 0.5},
                              "KHR_materials_volume": SOLID,
                              "KHR_materials_ior": {"ior": 1.33}})
    write_json("glass.gltf", glass_scene(tinted, light=True))
    # what Mitsuba's dielectric and roughdielectric match: transmission 1, metallic 0
    tinted = dict(glass_material(base=(0.9, 0.7, 0.3)),
                  extensions={"KHR_materials_transmission": {"transmissionFactor": 1.0},
                              "KHR_materials_volume": SOLID,
                              "KHR_materials_ior": {"ior": 1.33}})
    write_json("glass_mitsuba.gltf", glass_scene(tinted, light=False))
    write_json("glass_mitsuba_coarse.gltf", glass_scene(tinted, light=False, size=(6, 8)))
    # glass_mitsuba with its three spheres smooth and thin-walled (no
    # KHR_materials_volume): what Mitsuba's thindielectric matches
    g = glass_scene(tinted, light=False)
    for m in g["materials"][3:]:
        m["extensions"].pop("KHR_materials_volume")
        m["pbrMetallicRoughness"]["roughnessFactor"] = 0.0
    write_json("glass_mitsuba_thin.gltf", g)
    # thin_pane: a smooth thin-walled quad (transmission 1, ior 1.5, base
    # colour 0.9, 0.7, 0.3; no KHR_materials_volume) face-on to an
    # orthographic camera, before a lamp quad (emission 1) that fills the
    # view; thin_pane_white, the same pane white and without the lamp
    b = Blob()
    lamp, pane = b.quad(0.0), b.quad(0.0)
    lamp["material"], pane["material"] = 0, 1
    glass = glass_material(base=(0.9, 0.7, 0.3))
    glass["extensions"].pop("KHR_materials_volume")
    materials = [{"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0],
                                           "metallicFactor": 0.0},
                  "emissiveFactor": [1.0, 1.0, 1.0],
                  "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}, glass]
    nodes = [{"mesh": 0, "translation": [0.0, 0.0, -1.0], "scale": [3.0, 3.0, 1.0]},
             {"mesh": 1, "scale": [2.0, 2.0, 1.0]}, ortho_camera_node()]
    cameras = [{"type": "orthographic", "orthographic": {"xmag": 0.8, "ymag": 0.6,
                                                         "zfar": 100.0, "znear": 0.01}}]
    used = ["KHR_materials_transmission", "KHR_materials_specular"]
    write_json("thin_pane.gltf", doc([{"primitives": [lamp]}, {"primitives": [pane]}],
                                     b.accessors, b.views, b.buffers(), nodes=nodes,
                                     scenes=[{"nodes": [0, 1, 2]}], cameras=cameras,
                                     materials=materials, extensionsUsed=used))
    white = glass_material()
    white["extensions"].pop("KHR_materials_volume")
    write_json("thin_pane_white.gltf", doc([{"primitives": [lamp]}, {"primitives": [pane]}],
                                           b.accessors, b.views, b.buffers(),
                                           nodes=nodes[1:], scenes=[{"nodes": [0, 1]}],
                                           cameras=cameras, materials=[materials[0], white],
                                           extensionsUsed=used))


def write_coat():
    """coat_quad: two quads side by side face-on to an orthographic camera,
    both Lambertian (specularFactor 0) under a full smooth clear coat: black
    (left) and white (right). coat: glass.gltf's floor, wall and light with
    three coated spheres: a red Lambertian base (coat 1, roughness 0), a
    rough gold metal (coat 0.7, roughness 0.3) and glass (coat 0.5, 0.1)."""
    b = Blob()
    left, right = b.quad(0.0), b.quad(0.0)
    left["material"], right["material"] = 0, 1

    def coated(rgb, coat=1.0, rough=0.0, metallic=0.0, roughness=1.0, extra=None):
        ext = {"KHR_materials_clearcoat": {"clearcoatFactor": coat,
                                           "clearcoatRoughnessFactor": rough}}
        if metallic == 0.0 and extra is None:
            ext["KHR_materials_specular"] = {"specularFactor": 0.0}
        ext.update(extra or {})
        return {"pbrMetallicRoughness": {"baseColorFactor": list(rgb) + [1.0],
                                         "metallicFactor": metallic,
                                         "roughnessFactor": roughness},
                "extensions": ext}
    g = doc([{"primitives": [left]}, {"primitives": [right]}], b.accessors, b.views,
            b.buffers(),
            nodes=[{"mesh": 0, "translation": [-1.0, 0.0, 0.0]},
                   {"mesh": 1, "translation": [1.0, 0.0, 0.0]}, ortho_camera_node()],
            scenes=[{"nodes": [0, 1, 2]}],
            cameras=[{"type": "orthographic", "orthographic": {"xmag": 2.0, "ymag": 1.0,
                                                               "zfar": 100.0, "znear": 0.01}}],
            materials=[coated((0.0, 0.0, 0.0)), coated((1.0, 1.0, 1.0))],
            extensionsUsed=["KHR_materials_clearcoat", "KHR_materials_specular"])
    write_json("coat_quad.gltf", g)
    glass = coated((1.0, 1.0, 1.0), 0.5, 0.1, roughness=0.0,
                   extra={"KHR_materials_transmission": {"transmissionFactor": 1.0},
                          "KHR_materials_volume": SOLID})
    g = glass_scene(glass, light=True)
    g["materials"][3] = coated((0.8, 0.1, 0.1))
    g["materials"][4] = coated((1.0, 0.8, 0.4), 0.7, 0.3, metallic=1.0, roughness=0.5)
    g["extensionsUsed"].append("KHR_materials_clearcoat")
    write_json("coat.gltf", g)


def write_sheen():
    """sheen_quad and sheen (see the top)."""
    b = Blob()
    left, right = b.quad(0.0, QUAD_UV), b.quad(0.0, QUAD_UV)
    left["material"], right["material"] = 0, 1

    def sheened(rgb, colour, rough, metallic=0.0, roughness=1.0, extra=None, textures=None):
        sheen = {"sheenColorFactor": list(colour), "sheenRoughnessFactor": rough}
        sheen.update(textures or {})
        ext = {"KHR_materials_sheen": sheen}
        if metallic == 0.0 and extra is None:
            ext["KHR_materials_specular"] = {"specularFactor": 0.0}
        ext.update(extra or {})
        return {"pbrMetallicRoughness": {"baseColorFactor": list(rgb) + [1.0],
                                         "metallicFactor": metallic,
                                         "roughnessFactor": roughness},
                "extensions": ext}
    tilt = [math.sin(math.radians(-30.0)), 0.0, 0.0, math.cos(math.radians(-30.0))]
    images = [{"uri": png_uri(constant_png((255, 255, 255)))},
              {"uri": png_uri(png(4, 4, 4, [[0, 0, 0, 128] * 4] * 4))}]
    g = doc([{"primitives": [left]}, {"primitives": [right]}], b.accessors, b.views,
            b.buffers(),
            nodes=[{"mesh": 0, "translation": [-1.0, 0.0, 0.0], "rotation": tilt},
                   {"mesh": 1, "translation": [1.0, 0.0, 0.0], "rotation": tilt},
                   ortho_camera_node()],
            scenes=[{"nodes": [0, 1, 2]}],
            cameras=[{"type": "orthographic", "orthographic": {"xmag": 2.0, "ymag": 1.0,
                                                               "zfar": 100.0, "znear": 0.01}}],
            materials=[sheened((0.0, 0.0, 0.0), (1.0, 0.5, 0.25), 1.0,
                               textures={"sheenColorTexture": {"index": 0},
                                         "sheenRoughnessTexture": {"index": 1}}),
                       sheened((1.0, 1.0, 1.0), (0.8, 0.8, 0.8), 0.5)],
            images=images, textures=[{"source": 0}, {"source": 1}],
            extensionsUsed=["KHR_materials_sheen", "KHR_materials_specular"])
    write_json("sheen_quad.gltf", g)
    glass = sheened((1.0, 1.0, 1.0), (0.6, 0.7, 0.9), 0.2, roughness=0.0,
                    extra={"KHR_materials_transmission": {"transmissionFactor": 1.0},
                           "KHR_materials_volume": SOLID})
    g = glass_scene(glass, light=True)
    g["materials"][3] = sheened((0.5, 0.05, 0.05), (0.9, 0.9, 0.9), 0.3)
    g["materials"][4] = sheened((1.0, 0.8, 0.4), (0.3, 0.5, 1.0), 0.7, metallic=1.0,
                                roughness=0.5,
                                extra={"KHR_materials_clearcoat": {"clearcoatFactor": 0.7,
                                                                   "clearcoatRoughnessFactor": 0.3}})
    g["extensionsUsed"] += ["KHR_materials_sheen", "KHR_materials_clearcoat"]
    write_json("sheen.gltf", g)


def anisotropic(strength, rotation=0.0, roughness=0.3, texture=None):
    """A white metal (F = 1) of `roughness` under KHR_materials_anisotropy."""
    ext = {"anisotropyStrength": strength, "anisotropyRotation": rotation}
    if texture is not None:
        ext["anisotropyTexture"] = {"index": texture}
    return {"pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                                     "metallicFactor": 1.0, "roughnessFactor": roughness},
            "extensions": {"KHR_materials_anisotropy": ext}}


def write_anisotropy():
    """aniso_mitsuba and aniso_quad (see the top)."""
    # fine spheres: where smooth normals stray from coarse facets at the
    # outline, strata and Mitsuba treat a glossy lobe below the facet
    # differently (integrator.h adapted_normal), which is not anisotropy
    g = glass_scene(anisotropic(0.5, math.pi / 2, roughness=0.2), light=False, size=(32, 48),
                    uv=True)
    g["materials"][3] = anisotropic(0.0, roughness=0.2)
    g["materials"][4] = anisotropic(0.5, roughness=0.2)
    g["extensionsUsed"].append("KHR_materials_anisotropy")
    write_json("aniso_mitsuba.gltf", g)
    b = Blob()
    left, right = b.quad(0.0, QUAD_UV), b.quad(0.0, QUAD_UV)
    left["material"], right["material"] = 0, 1
    tilt = [math.sin(math.radians(-30.0)), 0.0, 0.0, math.cos(math.radians(-30.0))]
    # the texel: direction (1, 1) as RG (255, 255), strength 128 / 255 as B
    g = doc([{"primitives": [left]}, {"primitives": [right]}], b.accessors, b.views,
            b.buffers(),
            nodes=[{"mesh": 0, "translation": [-1.0, 0.0, 0.0], "rotation": tilt},
                   {"mesh": 1, "translation": [1.0, 0.0, 0.0], "rotation": tilt},
                   ortho_camera_node()],
            scenes=[{"nodes": [0, 1, 2]}],
            cameras=[{"type": "orthographic", "orthographic": {"xmag": 2.0, "ymag": 1.0,
                                                               "zfar": 100.0, "znear": 0.01}}],
            materials=[anisotropic(0.8, 0.5, roughness=0.4, texture=0), anisotropic(0.0)],
            images=[{"uri": png_uri(constant_png((255, 255, 128)))}],
            textures=[{"source": 0}], extensionsUsed=["KHR_materials_anisotropy"])
    write_json("aniso_quad.gltf", g)


def write_diffuse_transmission():
    """dtrans_lamp (see the top)."""
    b = Blob()
    sheet, lamp = b.quad(0.0, QUAD_UV), b.quad(0.0)
    sheet["material"], lamp["material"] = 0, 1
    spec0 = {"KHR_materials_specular": {"specularFactor": 0.0}}
    dt = {"diffuseTransmissionFactor": 0.75, "diffuseTransmissionTexture": {"index": 0},
          "diffuseTransmissionColorFactor": [1.0, 0.5, 1.0],
          "diffuseTransmissionColorTexture": {"index": 1}}
    materials = [{"pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                                           "metallicFactor": 0.0},
                  "extensions": dict(spec0, KHR_materials_diffuse_transmission=dt)},
                 {"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0],
                                           "metallicFactor": 0.0},
                  "emissiveFactor": [1.0, 1.0, 1.0], "extensions": spec0}]
    images = [{"uri": png_uri(png(4, 4, 4, [[255, 255, 255, 204] * 4] * 4))},
              {"uri": png_uri(constant_png((255, 255, 128)))}]
    g = doc([{"primitives": [sheet]}, {"primitives": [lamp]}], b.accessors, b.views,
            b.buffers(),
            nodes=[{"mesh": 0}, {"mesh": 1, "translation": [0.0, 0.0, -0.5],
                                 "scale": [1.5, 1.5, 1.0]},
                   ortho_camera_node()],
            scenes=[{"nodes": [0, 1, 2]}],
            cameras=[{"type": "orthographic", "orthographic": {"xmag": 1.0, "ymag": 1.0,
                                                               "zfar": 100.0, "znear": 0.01}}],
            materials=materials, images=images, textures=[{"source": 0}, {"source": 1}],
            extensionsUsed=["KHR_materials_diffuse_transmission", "KHR_materials_specular"])
    write_json("dtrans_lamp.gltf", g)


def write_iridescence():
    """irid_quad (see the top)."""
    b = Blob()
    left, right = b.quad(0.0, QUAD_UV), b.quad(0.0, QUAD_UV)
    left["material"], right["material"] = 0, 1
    tilt = [math.sin(math.radians(-30.0)), 0.0, 0.0, math.cos(math.radians(-30.0))]
    film = {"iridescenceFactor": 1.0, "iridescenceIor": 1.3, "iridescenceTexture": {"index": 0},
            "iridescenceThicknessMinimum": 200.0, "iridescenceThicknessMaximum": 600.0,
            "iridescenceThicknessTexture": {"index": 0}}
    materials = [{"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0],
                                           "metallicFactor": 0.0, "roughnessFactor": 0.0},
                  "extensions": {"KHR_materials_iridescence": film}},
                 {"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.6, 0.3, 1.0],
                                           "metallicFactor": 1.0, "roughnessFactor": 0.0},
                  "extensions": {"KHR_materials_iridescence": {"iridescenceFactor": 0.5,
                                                               "iridescenceIor": 1.8}}}]
    g = doc([{"primitives": [left]}, {"primitives": [right]}], b.accessors, b.views,
            b.buffers(),
            nodes=[{"mesh": 0, "translation": [-1.0, 0.0, 0.0], "rotation": tilt},
                   {"mesh": 1, "translation": [1.0, 0.0, 0.0], "rotation": tilt},
                   ortho_camera_node()],
            scenes=[{"nodes": [0, 1, 2]}],
            cameras=[{"type": "orthographic", "orthographic": {"xmag": 2.0, "ymag": 1.0,
                                                               "zfar": 100.0, "znear": 0.01}}],
            materials=materials,
            images=[{"uri": png_uri(png(4, 4, 4, [[191, 128, 0, 255] * 4] * 4))}],
            textures=[{"source": 0}], extensionsUsed=["KHR_materials_iridescence"])
    write_json("irid_quad.gltf", g)


def write_dispersion():
    """dispersion_slab, _zero and clear_slab (see the top)."""
    for name, dispersion in (("dispersion_slab", 5.0), ("dispersion_slab_zero", 0.0),
                             ("clear_slab", None)):
        b = Blob()
        slab, line = cube_prim(b, 0.5), b.quad(0.0)
        slab["material"], line["material"] = 0, 1
        glass = glass_material()
        if dispersion is not None:
            glass["extensions"]["KHR_materials_dispersion"] = {"dispersion": dispersion}
        lamp = {"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0],
                                         "metallicFactor": 0.0},
                "emissiveFactor": [1.0, 1.0, 1.0],
                "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 10.0}}}
        turn = [0.0, math.sin(math.radians(22.5)), 0.0, math.cos(math.radians(22.5))]
        used = GLASS_EXTENSIONS + ["KHR_materials_emissive_strength"]
        if dispersion is not None:
            used.append("KHR_materials_dispersion")
        g = doc([{"primitives": [slab]}, {"primitives": [line]}], b.accessors, b.views,
                b.buffers(),
                nodes=[{"mesh": 0, "rotation": turn, "scale": [1.0, 4.0, 4.0]},
                       {"mesh": 1, "translation": [0.0, 0.0, -4.0], "scale": [0.03, 2.0, 1.0]},
                       ortho_camera_node()],
                scenes=[{"nodes": [0, 1, 2]}],
                cameras=[{"type": "orthographic",
                          "orthographic": {"xmag": 1.0, "ymag": 0.5, "zfar": 100.0,
                                           "znear": 0.01}}],
                materials=[glass, lamp], extensionsUsed=used)
        write_json(name + ".gltf", g)


def glass_scene(third, light, size=(16, 24), uv=False):
    """A Lambertian floor and back wall, a quad light above (where `light`),
    a smooth glass sphere, a rough one with absorption and `third` (of the
    rings and segments `size` gives, with smooth normals; with texture
    coordinates where `uv`)."""
    b = Blob()
    lambert = {"KHR_materials_specular": {"specularFactor": 0.0}}
    floor, wall, lamp = b.quad(0.0), b.quad(0.0), b.quad(0.0)
    prims = [floor, wall, lamp] + [sphere_prim(b, 0.45, *size, uv=uv) for _ in range(3)]
    for k, p in enumerate(prims):
        p["material"] = k
    materials = [
        {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0},
         "extensions": lambert},
        {"pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.3, 0.2, 1.0], "metallicFactor": 0.0},
         "extensions": lambert},
        {"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0},
         "emissiveFactor": [1.0, 1.0, 1.0],
         "extensions": dict(lambert, KHR_materials_emissive_strength={"emissiveStrength": 6.0})},
        glass_material(),
        glass_material(roughness=0.3, attenuation=((0.3, 0.6, 0.9), 0.5)), third]
    r90 = [-math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)]  # +z normal to +y
    nodes = [{"mesh": 0, "rotation": r90, "scale": [2.0, 2.0, 1.0]},
             {"mesh": 1, "translation": [0.0, 1.0, -1.5], "scale": [2.0, 1.0, 1.0]},
             {"mesh": 2, "translation": [0.0, 2.5, 0.0], "rotation": [math.sqrt(0.5), 0.0, 0.0,
                                                                      math.sqrt(0.5)],
              "scale": [0.6, 0.6, 1.0]},
             {"mesh": 3, "translation": [-1.0, 0.45, 0.0]},
             {"mesh": 4, "translation": [0.0, 0.45, 0.3]},
             {"mesh": 5, "translation": [1.0, 0.45, 0.0]},
             {"name": "camera", "camera": 0, "translation": [0.0, 1.2, 4.0],
              "rotation": [-0.0998, 0.0, 0.0, 0.995]}]
    if not light:
        del nodes[2]
    meshes = [{"primitives": [p]} for p in prims]
    return doc(meshes, b.accessors, b.views, b.buffers(), nodes=nodes,
               scenes=[{"nodes": list(range(len(nodes)))}],
               cameras=[{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.01}}],
               materials=materials,
               extensionsUsed=GLASS_EXTENSIONS + ["KHR_materials_ior",
                                                  "KHR_materials_emissive_strength"])


def write_shade_mix():
    spec0 = {"KHR_materials_specular": {"specularFactor": 0.0}}

    def lambert(rgb, **extra):
        m = {"pbrMetallicRoughness": {"baseColorFactor": list(rgb) + [1.0], "metallicFactor": 0.0},
             "extensions": spec0}
        m.update(extra)
        return m
    materials = [lambert((0.8, 0.8, 0.8)), lambert((0.8, 0.2, 0.1)),
                 lambert((1.0, 1.0, 1.0)), lambert((0.2, 0.8, 0.2), alphaMode="MASK",
                                                   alphaCutoff=0.5),
                 lambert((1.0, 1.0, 1.0)), {"pbrMetallicRoughness": {"metallicFactor": 0.5}},
                 lambert((0.0, 0.0, 0.0), emissiveFactor=[4.0, 4.0, 4.0]),
                 lambert((0.0, 0.0, 0.0), emissiveFactor=[4.0, 3.0, 2.0],
                         emissiveTexture={"index": 1})]
    materials[2]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
    b = Blob()
    meshes, nodes = [], []
    for k in range(6):
        p = b.quad(0.0, QUAD_UV)
        p["material"] = k
        if k == 4:
            p["attributes"]["COLOR_0"] = b.accessor(bytes([255, 128, 64, 255] * 4), 5121, 4,
                                                    "VEC4", normalized=True)
        meshes.append({"primitives": [p]})
        nodes.append({"mesh": k, "translation": [k % 3 - 1.0, k // 3 - 0.5, 0.0],
                      "scale": [0.5, 0.5, 1.0]})
    for k, x in ((6, -0.75), (7, 0.75)):
        p = b.quad(0.0, QUAD_UV)
        p["material"] = k
        meshes.append({"primitives": [p]})
        nodes.append({"mesh": k, "translation": [x, 0.0, 1.5], "scale": [0.5, 0.5, 1.0],
                      "rotation": [1.0, 0.0, 0.0, 0.0]})
    nodes.append(ortho_camera_node())
    camera = [{"type": "orthographic", "orthographic": {"xmag": 2.0, "ymag": 1.4,
                                                        "zfar": 100.0, "znear": 0.01}}]
    images = [{"uri": png_uri(png(2, 2, 3, [[255, 0, 0, 0, 255, 0], [0, 0, 255, 255, 255, 255]]))},
              {"uri": png_uri(png(2, 1, 3, [[128, 128, 128, 255, 255, 255]]))}]
    g = doc(meshes, b.accessors, b.views, b.buffers(), nodes=nodes,
            scenes=[{"nodes": list(range(len(nodes)))}], cameras=camera, materials=materials,
            images=images, textures=[{"source": 0}, {"source": 1}],
            extensionsUsed=["KHR_materials_specular"])
    write_json("shade_mix.gltf", g)


def write_shadows():
    half = [[0, 0, 0, 0] * 2 + [255, 255, 255, 255] * 2] * 4  # left half alpha 0
    lambert = {"extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}
    black = [0.0, 0.0, 0.0, 1.0]  # the occluder reflects nothing onto the ground
    variants = {
        "shadow_cutout.gltf": (-1.0, {"alphaMode": "MASK", "pbrMetallicRoughness": {
            "baseColorFactor": black, "baseColorTexture": {"index": 0}, "metallicFactor": 0.0}}),
        "shadow_half.gltf": (0.0, {"pbrMetallicRoughness": {"baseColorFactor": black,
                                                            "metallicFactor": 0.0}}),
        "shadow_opaque.gltf": (-1.0, {"pbrMetallicRoughness": {"baseColorFactor": black,
                                                               "metallicFactor": 0.0}}),
        "shadow_blend.gltf": (-1.0, {"alphaMode": "BLEND", "pbrMetallicRoughness": {
            "baseColorFactor": [0.0, 0.0, 0.0, 0.5], "metallicFactor": 0.0}}),
    }
    for name, (left, occluder) in variants.items():
        b = Blob()
        ground, top = b.quad(-1.0), b.quad(0.0, QUAD_UV)
        if left != -1.0:  # only x in [left, 1]
            pos = list(QUAD_POS)
            pos[0] = pos[9] = left
            top["attributes"]["POSITION"] = b.accessor(f32(pos), 5126, 4, "VEC3",
                                                       min=[left, -1.0, 0.0], max=[1.0, 1.0, 0.0])
        # the occluder faces down (one-sided): shadow rays from the ground meet
        # its front, camera rays from above pass through its back
        top["indices"] = b.accessor(struct.pack("<6H", 0, 2, 1, 0, 3, 2), 5123, 6, "SCALAR")
        top["attributes"]["NORMAL"] = b.accessor(f32([0.0, 0.0, -1.0] * 4), 5126, 4, "VEC3")
        ground["material"], top["material"] = 0, 1
        occluder = dict(occluder, **lambert)
        g = doc([{"primitives": [ground, top]}], b.accessors, b.views, b.buffers(),
                nodes=[{"mesh": 0}, ortho_camera_node()], scenes=[{"nodes": [0, 1]}],
                cameras=ORTHO, materials=[dict(lambert, pbrMetallicRoughness={
                    "baseColorFactor": [0.5, 0.5, 0.5, 1.0], "metallicFactor": 0.0}),
                                          occluder],
                images=[{"uri": png_uri(png(4, 4, 4, half))}],
                samplers=[{"magFilter": 9728}], textures=[{"source": 0, "sampler": 0}])
        write_json(name, g)


def write_bad():
    # One valid base (u16 layout with a data: URI), then one fault per file.
    def base():
        meshes, acc, views, blob = layout_indexed(5123, "H", 2, 0)
        return doc(meshes, acc, views, [{"byteLength": len(blob), "uri": data_uri(blob)}]), blob

    g, _ = base()
    text = json.dumps(g, indent=1)
    write_bytes("bad_truncated.gltf", text[:len(text) * 3 // 5].encode("ascii"))
    write_bytes("bad_not_gltf.gltf", b"this is not a glTF file\n")

    g, blob = base()  # an index of 812 with 5 vertices
    idx = [i for t in PYRAMID_T for i in t]
    idx[7] = 812
    blob = blob[:120] + struct.pack("<%dH" % len(idx), *idx)
    g["buffers"] = [{"byteLength": len(blob), "uri": data_uri(blob)}]
    write_json("bad_index.gltf", g)

    g, blob = base()
    g["bufferViews"][1]["byteLength"] = 64 + len(blob)  # past the buffer's end
    write_json("bad_view_past_buffer.gltf", g)

    g, blob = base()
    g["accessors"][0]["count"] = 6  # 72 bytes in a 60-byte view
    write_json("bad_accessor_past_view.gltf", g)

    g, blob = base()
    g["buffers"] = [{"byteLength": len(blob), "uri": "bad_missing_bin.bin"}]
    write_json("bad_missing_bin.gltf", g)

    g, blob = base()
    blob = bytearray(blob)
    blob[16:20] = struct.pack("<f", float("nan"))  # vertex 1, y
    g["buffers"] = [{"byteLength": len(blob), "uri": data_uri(blob)}]
    del g["accessors"][0]["min"], g["accessors"][0]["max"]
    write_json("bad_nonfinite.gltf", g)

    g, _ = base()
    g["nodes"] = [{"children": [1]}, {"mesh": 0, "children": [0]}]
    write_json("bad_node_cycle.gltf", g)

    g, _ = base()
    g["nodes"] = [{"mesh": 5}]
    write_json("bad_mesh_index.gltf", g)

    g, _ = base()
    g["accessors"][0]["type"] = "VEC2"
    g["accessors"][0]["min"] = g["accessors"][0]["min"][:2]
    g["accessors"][0]["max"] = g["accessors"][0]["max"][:2]
    write_json("bad_position_type.gltf", g)

    g, _ = base()
    g["bufferViews"][0]["byteStride"] = 8  # smaller than a float VEC3
    write_json("bad_stride.gltf", g)

    g, _ = base()
    g["meshes"][0]["primitives"][0]["mode"] = 0  # POINTS only: nothing to render
    write_json("bad_no_triangles.gltf", g)

    # GLB whose BIN chunk claims 8 bytes more than the file holds.
    meshes, acc, views, blob = layout_indexed(5123, "H", 2, 2)
    data = bytearray(glb(doc(meshes, acc, views, [{"byteLength": len(blob)}]), blob))
    json_len = struct.unpack("<I", data[12:16])[0]
    bin_at = 20 + json_len
    struct.pack_into("<I", data, bin_at, struct.unpack("<I", data[bin_at:bin_at + 4])[0] + 8)
    write_bytes("bad_glb_chunk.glb", bytes(data))

    # texture faults, on a copy of textured_quad
    with open(os.path.join(HERE, "textured_quad.gltf"), encoding="ascii") as f:
        quad = json.load(f)

    def variant(name, change):
        g = json.loads(json.dumps(quad))
        change(g)
        write_json(name, g)

    def not_png(g):
        g["images"][0]["uri"] = "data:image/png;base64," + base64.b64encode(b"not a png").decode()
    # unreadable images are warnings (a white texture replaces them), not faults
    variant("image_undecodable.gltf", not_png)
    variant("image_missing.gltf", lambda g: g["images"][0].update(uri="no_such_image.png"))

    def draco(g):  # required and not supported; its bufferView is broken too
        g["extensionsUsed"] = g["extensionsRequired"] = ["KHR_draco_mesh_compression"]
        g["accessors"][0]["bufferView"] = 99
    variant("bad_requires_draco.gltf", draco)
    # occlusionTexture is not read: one warning
    variant("occlusion.gltf",
            lambda g: g["materials"][0].update(occlusionTexture={"index": 0}))
    variant("uses_variants.gltf",
            lambda g: g.update(extensionsUsed=["KHR_materials_variants"]))
    variant("bad_texture_index.gltf", lambda g: g["materials"][0]["pbrMetallicRoughness"]
            ["baseColorTexture"].update(index=7))
    variant("bad_image_index.gltf", lambda g: g["textures"][1].update(source=9))

    def bad_wrap(g):
        g["samplers"] = [{"wrapS": 1234}]
        g["textures"][0]["sampler"] = 0
    variant("bad_sampler_wrap.gltf", bad_wrap)

    def bad_uv(g):
        g["accessors"][2]["type"] = "VEC3"
    variant("bad_texcoord_type.gltf", bad_uv)

    def bad_uv1(g):  # TEXCOORD_1 (read: a texture names it) is the VEC3 POSITION accessor
        g["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] = 0
        g["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 1
    variant("bad_texcoord1_type.gltf", bad_uv1)
    variant("bad_alpha_mode.gltf", lambda g: g["materials"][0].update(alphaMode="SOMETIMES"))
    variant("bad_camera_ymag.gltf", lambda g: g["cameras"][0]["orthographic"].update(ymag=0.0))


def unlit_cube(b, centre, half):
    """A cube of half side `half` about centre, its faces wound outwards (as write_sided's)."""
    pos, ind = [], []
    for a in range(3):
        for sg in (1.0, -1.0):
            c = [0.0, 0.0, 0.0]
            c[a] = sg
            u, v = [0.0] * 3, [0.0] * 3
            u[(a + 1) % 3], v[(a + 2) % 3] = 1.0, 1.0
            if sg < 0:
                u, v = v, u
            base = len(pos) // 3
            for du, dv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                pos += [centre[k] + half * (c[k] + du * u[k] + dv * v[k]) for k in range(3)]
            ind += [base, base + 1, base + 2, base, base + 2, base + 3]
    return {"attributes": {"POSITION": b.accessor(
                f32(pos), 5126, 24, "VEC3", min=[centre[k] - half for k in range(3)],
                max=[centre[k] + half for k in range(3)])},
            "indices": b.accessor(struct.pack("<36H", *ind), 5123, 36, "SCALAR")}


def write_view_scenes():
    b = Blob()
    white = dict(unlit_cube(b, (1.0, 2.0, -3.0), 0.01), material=0)
    red = dict(unlit_cube(b, (1.5, 2.25, -3.5), 0.01), material=1)
    mats = [{"pbrMetallicRoughness": {"baseColorFactor": c}, "doubleSided": True,
             "extensions": {"KHR_materials_unlit": {}}}
            for c in ([1.0, 1.0, 1.0, 1.0], [1.0, 0.0, 0.0, 1.0])]
    write_json("markers.gltf", doc([{"primitives": [white, red]}], b.accessors, b.views,
                                   b.buffers(), materials=mats,
                                   extensionsUsed=["KHR_materials_unlit"]))
    lambert = {"extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}
    b = Blob()
    p = dict(b.quad(-1.5), material=0)
    mat = dict(lambert, pbrMetallicRoughness={"baseColorFactor": [0.2, 0.5, 0.8, 1.0],
                                              "metallicFactor": 0.0})
    write_json("aov_plane.gltf", doc([{"primitives": [p]}], b.accessors, b.views, b.buffers(),
                                     nodes=[{"mesh": 0}, ortho_camera_node(2.0)],
                                     scenes=[{"nodes": [0, 1]}], cameras=ORTHO, materials=[mat],
                                     extensionsUsed=["KHR_materials_specular"]))
    c, seg, rings = (0.5, -0.25, -1.0), 48, 24
    pos, nrm, ind = [], [], []
    for i in range(rings + 1):
        th = math.pi * i / rings
        for j in range(seg + 1):
            ph = 2.0 * math.pi * j / seg
            n = [math.sin(th) * math.sin(ph), math.cos(th), math.sin(th) * math.cos(ph)]
            nrm += n
            pos += [c[k] + n[k] for k in range(3)]
    for i in range(rings):
        for j in range(seg):
            a, d = i * (seg + 1) + j, (i + 1) * (seg + 1) + j
            if i + 1 < rings:  # at the bottom pole d = d + 1
                ind += [a, d, d + 1]
            if i > 0:  # at the top pole a = a + 1
                ind += [a, d + 1, a + 1]
    b = Blob()
    nv = len(pos) // 3
    p = {"attributes": {"POSITION": b.accessor(f32(pos), 5126, nv, "VEC3",
                                               min=[c[k] - 1.0 for k in range(3)],
                                               max=[c[k] + 1.0 for k in range(3)]),
                        "NORMAL": b.accessor(f32(nrm), 5126, nv, "VEC3")},
         "indices": b.accessor(struct.pack("<%dH" % len(ind), *ind), 5123, len(ind), "SCALAR"),
         "material": 0}
    cam = [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.01}}]
    write_json("aov_sphere.gltf", doc([{"primitives": [p]}], b.accessors, b.views, b.buffers(),
                                      nodes=[{"mesh": 0}, {"camera": 0, "translation": [0.5, -0.25, 3.0]}],
                                      scenes=[{"nodes": [0, 1]}], cameras=cam, materials=[mat],
                                      extensionsUsed=["KHR_materials_specular"]))


def write_glass_panes():
    """glass_panes: a lamp quad (emission 4) seen head-on through four smooth
    glass panes (cubes flattened to 0.1 thick) by an orthographic camera: a
    camera path meets eight glass interfaces before the lamp, so it needs a
    max depth of 8 at least."""
    b = Blob()
    lamp = b.quad(0.0)
    lamp["material"] = 0
    pane = cube_prim(b, 1.0)
    pane["material"] = 1
    g = doc([{"primitives": [lamp]}, {"primitives": [pane]}], b.accessors, b.views, b.buffers(),
            nodes=[{"mesh": 0, "translation": [0.0, 0.0, -1.0], "scale": [2.0, 2.0, 1.0]}] +
                  [{"mesh": 1, "translation": [0.0, 0.0, 0.4 * k], "scale": [1.5, 1.5, 0.05]}
                   for k in range(4)] + [ortho_camera_node()],
            scenes=[{"nodes": list(range(6))}],
            cameras=[{"type": "orthographic", "orthographic": {"xmag": 0.8, "ymag": 0.8,
                                                               "zfar": 100.0, "znear": 0.01}}],
            materials=[{"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0],
                                                 "metallicFactor": 0.0},
                        "emissiveFactor": [1.0, 1.0, 1.0],
                        "extensions": {"KHR_materials_emissive_strength":
                                       {"emissiveStrength": 4.0}}},
                       glass_material()],
            extensionsUsed=["KHR_materials_transmission", "KHR_materials_volume",
                            "KHR_materials_emissive_strength"])
    write_json("glass_panes.gltf", g)


def write_dark_views():
    """Scenes whose own lights carry the power but would leave most of the
    default view black (st_scene.h ST_ENV_DARK_VIEW), and one they light:
    lamp_in_glass, a Lambertian floor under a closed smooth glass sphere
    holding a small lamp (emission 20), which next-event estimation cannot
    reach; sun_behind, a white quad filling an orthographic view, lit by a
    directional light from behind; sun_front, the same light from the
    front."""
    b = Blob()
    lambert = {"KHR_materials_specular": {"specularFactor": 0.0}}
    floor, bulb, lamp = b.quad(0.0), sphere_prim(b, 0.45), cube_prim(b, 0.1)
    for k, p in enumerate((floor, bulb, lamp)):
        p["material"] = k
    materials = [
        {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0},
         "extensions": lambert},
        glass_material(),
        {"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0},
         "emissiveFactor": [1.0, 1.0, 1.0],
         "extensions": dict(lambert, KHR_materials_emissive_strength={"emissiveStrength": 20.0})}]
    r90 = [-math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)]  # +z normal to +y
    nodes = [{"mesh": 0, "rotation": r90, "scale": [2.0, 2.0, 1.0]},
             {"mesh": 1, "translation": [0.0, 0.5, 0.0]},
             {"mesh": 2, "translation": [0.0, 0.5, 0.0]},
             {"name": "camera", "camera": 0, "translation": [0.0, 1.2, 4.0],
              "rotation": [-0.0998, 0.0, 0.0, 0.995]}]
    write_json("lamp_in_glass.gltf",
               doc([{"primitives": [p]} for p in (floor, bulb, lamp)], b.accessors, b.views,
                   b.buffers(), nodes=nodes, scenes=[{"nodes": [0, 1, 2, 3]}],
                   cameras=[{"type": "perspective", "perspective": {"yfov": 0.7,
                                                                    "znear": 0.01}}],
                   materials=materials,
                   extensionsUsed=["KHR_materials_transmission", "KHR_materials_volume",
                                   "KHR_materials_specular", "KHR_materials_emissive_strength"]))
    for name, rotation in (("sun_behind.gltf", [0.0, 1.0, 0.0, 0.0]),
                           ("sun_front.gltf", [0.0, 0.0, 0.0, 1.0])):
        b = Blob()
        p = b.quad(0.0)
        p["material"] = 0
        write_json(name, doc(
            [{"primitives": [p]}], b.accessors, b.views, b.buffers(),
            nodes=[{"mesh": 0}, ortho_camera_node(),
                   {"name": "sun", "rotation": rotation,
                    "extensions": {"KHR_lights_punctual": {"light": 0}}}],
            scenes=[{"nodes": [0, 1, 2]}],
            cameras=[{"type": "orthographic", "orthographic": {"xmag": 0.9, "ymag": 0.9,
                                                               "zfar": 100.0, "znear": 0.01}}],
            materials=[{"pbrMetallicRoughness": {"metallicFactor": 0.0}, "extensions": lambert}],
            extensions={"KHR_lights_punctual": {"lights": [{"type": "directional",
                                                             "intensity": 2.0}]}},
            extensionsUsed=["KHR_lights_punctual", "KHR_materials_specular"]))


def main():
    write_layouts()
    write_trs()
    write_camera_pick()
    write_materials_flat()
    write_textures()
    write_textured_quad()
    write_textured_glb()
    write_cutout()
    write_lighting()
    write_strip_fan()
    write_sparse()
    write_sided()
    write_two_uv()
    write_two_uv_light()
    write_tangent_ramp()
    write_lighting_default()
    write_structure()
    write_specgloss()
    write_shadows()
    write_shade_mix()
    write_glass()
    write_coat()
    write_sheen()
    write_anisotropy()
    write_diffuse_transmission()
    write_iridescence()
    write_dispersion()
    write_dark_views()
    write_glass_panes()
    write_quantized()
    write_bad()
    write_view_scenes()


if __name__ == "__main__":
    main()
