#!/usr/bin/env python3
"""bench_mitsuba.py - the whole-pass workload of `strata bench SCENE` rendered
by Mitsuba 3, for comparison; not a test.

  render SCENE.gltf path|direct [OUT.exr]   renders and times the scene
  compare A.exr B.exr                        says whether two renders agree

render reads the glTF scene with tools/gltf_scene.py and builds the same
scene for Mitsuba (the glTF is not Mitsuba's format): each primitive a mesh
with flat (face) normals and a `diffuse` BSDF of its base colour (the bench
scene's materials are Lambertian: specularFactor 0, roughness 1; a
transmissive one a dielectric: glass_dict; an anisotropic white metal a
rough conductor: conductor_dict), with the file's vertex normals
where it has them, an
emissive one an `area` emitter of radiance emissiveFactor x emissiveStrength
(one-sided, on the side the vertices run counter-clockwise, as glTF's and
Mitsuba's front); the camera node's `perspective` sensor of the same
vertical field of view; WIDTH x HEIGHT (512), SPP (64), the `independent`
sampler and the `box` filter, as strata's bench workload
(--sampler random --filter box). Integrators: `path` with max_depth 5
(strata's --max-depth 4 counts vertices that gather light, pbrt's
convention; Mitsuba counts one more) and Russian roulette from rr_depth 3,
which is strata's (the fourth vertex is the first a path may not reach:
strata draws at the third vertex's bounce, Mitsuba on arriving at the
fourth; survival min(0.95, max throughput) in both); `direct` with one emitter sample and one BSDF
sample weighed by MIS, as strata's direct lighting (a light sample at the
first hit, and its BSDF sample's ray, which adds the emission it meets).
It renders once untimed (Dr.Jit compiles its kernels), then RUNS
times (default 3), each timed from the call to the evaluated image, and
prints one JSON line: {"renderer", "variant", "threads", "integrator",
"samples", "seconds": [...], "samples_per_second" (of the median)}.
Variant: VARIANT (default llvm_ad_rgb; its LLVM backend needs Debian's
libllvm19: DRJIT_LIBLLVM_PATH is set to /usr/lib/x86_64-linux-gnu/libLLVM-19.so
when unset and that file exists). Threads: Dr.Jit's pool, all cores.

compare prints each image's mean per channel and their relative difference,
the RMSE of the per-pixel difference (mostly the two renders' noise), and
the RMSE of 16 x 16 block means, where the noise falls 16-fold and a bias
would remain; it exits 1 when a channel's mean differs by more than TOL
(default 0.01, 1 %: far above the noise of 2^24 samples, far below any
wrong light or material) or when the block RMSE exceeds twice the noise's
share (per-pixel RMSE / 16; a moved or mirrored camera keeps the means).
Usage: python3 tools/bench_mitsuba.py render SCENE.gltf path|direct [OUT.exr]
       python3 tools/bench_mitsuba.py compare A.exr B.exr
       (environment: WIDTH, HEIGHT, SPP, RUNS, SEED, VARIANT, TOL, MAX_DEPTH (strata's
       --max-depth, 4), ENV (R,G,B: a uniform environment, strata's --env))
"""
import json
import math
import os
import statistics
import sys
import tempfile
import time

import numpy as np

import gltf_scene

LIBLLVM = "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"


def write_ply(path, triangles, normals=None, uvs=None):
    """Binary PLY of unshared vertices (3 per triangle), with their normals
    and texture coordinates where given, as Mitsuba reads it (its tangent,
    which an anisotropic BSDF follows, is dP/du, as strata's)."""
    n = len(triangles)
    props = "property float x\nproperty float y\nproperty float z\n"
    verts = triangles.reshape(-1, 3)
    if normals is not None:
        props += "property float nx\nproperty float ny\nproperty float nz\n"
        verts = np.concatenate([verts, normals.reshape(-1, 3)], axis=1)
    if uvs is not None:
        props += "property float u\nproperty float v\n"
        verts = np.concatenate([verts, uvs.reshape(-1, 2)], axis=1)
    head = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\n%s"
            "element face %d\nproperty list uchar int vertex_indices\nend_header\n" % (
                3 * n, props, n))
    faces = np.zeros(n, dtype=[("k", "u1"), ("i", "<i4", 3)])
    faces["k"] = 3
    faces["i"] = np.arange(3 * n, dtype=np.int32).reshape(n, 3)
    with open(path, "wb") as f:
        f.write(head.encode())
        f.write(verts.astype("<f4").tobytes())
        f.write(faces.tobytes())


def glass_dict(m, rgb):
    """KHR_materials_transmission at factor 1 on a dielectric (metallic 0)
    as Mitsuba's `thindielectric` without KHR_materials_volume (thin-walled,
    smooth only), else `dielectric` (roughness 0) or `roughdielectric` (GGX, alpha
    roughness², visible normals), the ior of KHR_materials_ior (1.5), the
    base colour as the transmittance; KHR_materials_volume's attenuation as
    a purely absorbing `homogeneous` medium inside (sigma_t = -ln(colour) /
    distance), which needs the `volpath` integrator."""
    ext = m.get("extensions", {})
    pbr = m.get("pbrMetallicRoughness", {})
    if ext["KHR_materials_transmission"].get("transmissionFactor", 0.0) != 1.0 or \
            pbr.get("metallicFactor", 1.0) != 0.0:
        sys.exit("bench_mitsuba: only transmissionFactor 1 on metallic 0 has a Mitsuba match")
    r = pbr.get("roughnessFactor", 1.0)
    if "KHR_materials_volume" not in ext:  # thin-walled: Mitsuba's thindielectric
        if r > 0.0:
            sys.exit("bench_mitsuba: Mitsuba has no rough thin dielectric")
        return {"bsdf": {"type": "thindielectric",
                         "int_ior": ext.get("KHR_materials_ior", {}).get("ior", 1.5),
                         "ext_ior": 1.0,
                         "specular_transmittance": {"type": "rgb", "value": rgb}}}
    bsdf = {"type": "dielectric" if r == 0.0 else "roughdielectric",
            "int_ior": ext.get("KHR_materials_ior", {}).get("ior", 1.5), "ext_ior": 1.0,
            "specular_transmittance": {"type": "rgb", "value": rgb}}
    if r > 0.0:
        bsdf.update(distribution="ggx", alpha=r * r)
    shape = {"bsdf": bsdf}
    vol = ext.get("KHR_materials_volume")
    if vol and "attenuationDistance" in vol:
        sigma = [-math.log(max(c, 1e-30)) / vol["attenuationDistance"]
                 for c in vol.get("attenuationColor", [1, 1, 1])]
        top = max(max(sigma), 1e-30)  # an RGB value must lie in [0, 1]: scaled
        shape["interior"] = {"type": "homogeneous", "albedo": 0.0, "scale": top,
                             "sigma_t": {"type": "rgb", "value": [c / top for c in sigma]}}
    return shape


def conductor_dict(m, rgb):
    """A white metal (base colour 1, metallic 1: Fresnel 1) under
    KHR_materials_anisotropy as Mitsuba's `roughconductor` with its
    `none` material (Fresnel 1): GGX of alpha_u along the tangent and
    alpha_v across it, alpha_t = mix(roughness², 1, strength²) and
    alpha_b = roughness² (the extension's definition), swapped where
    anisotropyRotation turns the direction by 90 degrees. No texture."""
    ext = m["extensions"]["KHR_materials_anisotropy"]
    pbr = m.get("pbrMetallicRoughness", {})
    if rgb != [1, 1, 1] or pbr.get("metallicFactor", 1.0) != 1.0 or "anisotropyTexture" in ext:
        sys.exit("bench_mitsuba: only a white metal without an anisotropyTexture has a "
                 "Mitsuba match")
    r, s = pbr.get("roughnessFactor", 1.0), ext.get("anisotropyStrength", 0.0)
    ab = r * r
    at = ab + (1.0 - ab) * s * s
    quarter = ext.get("anisotropyRotation", 0.0) / (math.pi / 2)
    if abs(quarter - round(quarter)) > 1e-6:
        sys.exit("bench_mitsuba: only anisotropyRotation k x 90 degrees has a Mitsuba match")
    if round(quarter) % 2:
        at, ab = ab, at
    return {"bsdf": {"type": "roughconductor", "material": "none", "distribution": "ggx",
                     "alpha_u": at, "alpha_v": ab}}


def material_dict(m):
    """A glTF material as Mitsuba's BSDF (and area emitter, if it emits)."""
    pbr = m.get("pbrMetallicRoughness", {})
    rgb = pbr.get("baseColorFactor", [1, 1, 1, 1])[:3]
    if "KHR_materials_transmission" in m.get("extensions", {}):
        return glass_dict(m, rgb)
    if "KHR_materials_anisotropy" in m.get("extensions", {}):
        return conductor_dict(m, rgb)
    shape = {"bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": rgb}}}
    strength = m.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get(
        "emissiveStrength", 1.0)
    emit = [c * strength for c in m.get("emissiveFactor", [0, 0, 0])]
    if max(emit) > 0:
        shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": emit}}
    return shape


def sensor_dict(mi, camera, width, height, spp):
    m = camera.matrix
    origin, forward, up = m[:3, 3], -m[:3, 2], m[:3, 1]
    return {"type": "perspective", "fov_axis": "y", "fov": math.degrees(camera.yfov),
            "to_world": mi.ScalarTransform4f().look_at(origin=origin.tolist(),
                                                       target=(origin + forward).tolist(),
                                                       up=up.tolist()),
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {"type": "hdrfilm", "width": width, "height": height,
                     "pixel_format": "rgb", "rfilter": {"type": "box"}}}


def integrator_dict(kind, media):
    if kind == "path":  # MAX_DEPTH: strata's --max-depth (Mitsuba counts one more)
        return {"type": "volpath" if media else "path",
                "max_depth": int(os.environ.get("MAX_DEPTH", 4)) + 1, "rr_depth": 3}
    return {"type": "direct", "emitter_samples": 1, "bsdf_samples": 1}


def scene_dict(mi, path, kind, folder, width, height, spp):
    prims, camera = gltf_scene.load(path)
    if camera is None:
        sys.exit("bench_mitsuba: %s: no camera node" % path)
    d = {"type": "scene", "sensor": sensor_dict(mi, camera, width, height, spp)}
    media = False
    for k, p in enumerate(prims):
        ply = os.path.join(folder, "mesh%d.ply" % k)
        write_ply(ply, p.triangles, p.normals, p.uvs)
        d["mesh%d" % k] = {"type": "ply", "filename": ply, "face_normals": p.normals is None,
                           **material_dict(p.material)}
        media = media or "interior" in d["mesh%d" % k]
    d["integrator"] = integrator_dict(kind, media)
    if "ENV" in os.environ:  # strata's --env R,G,B: a uniform environment
        rgb = [float(c) for c in os.environ["ENV"].split(",")]
        d["env"] = {"type": "constant", "radiance": {"type": "rgb", "value": rgb}}
    return d


def render(a):
    if len(a) < 2 or a[1] not in ("path", "direct"):
        sys.exit(__doc__.split("Usage: ")[1])
    if "DRJIT_LIBLLVM_PATH" not in os.environ and os.path.exists(LIBLLVM):
        os.environ["DRJIT_LIBLLVM_PATH"] = LIBLLVM
    import drjit as dr
    import mitsuba as mi
    variant = os.environ.get("VARIANT", "llvm_ad_rgb")
    mi.set_variant(variant)
    width, height = int(os.environ.get("WIDTH", 512)), int(os.environ.get("HEIGHT", 512))
    spp, runs = int(os.environ.get("SPP", 64)), int(os.environ.get("RUNS", 3))
    seed = int(os.environ.get("SEED", 0))
    with tempfile.TemporaryDirectory() as folder:
        scene = mi.load_dict(scene_dict(mi, a[0], a[1], folder, width, height, spp))
    image = mi.render(scene, seed=seed)  # untimed: Dr.Jit compiles here
    dr.eval(image)
    dr.sync_thread()
    seconds = []
    for r in range(runs):
        t0 = time.perf_counter()
        image = mi.render(scene, seed=seed + 1 + r)
        dr.eval(image)
        dr.sync_thread()
        seconds.append(time.perf_counter() - t0)
    if len(a) > 2:
        mi.Bitmap(image).write(a[2])
    samples = width * height * spp
    threads = dr.thread_count() if hasattr(dr, "thread_count") else os.cpu_count()
    print(json.dumps({"renderer": "mitsuba %s" % mi.__version__, "variant": variant,
                      "threads": threads, "scene": a[0], "integrator": a[1],
                      "samples": samples, "seconds": seconds,
                      "samples_per_second": samples / statistics.median(seconds)}))


def read_exr(path):
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    b = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, False)
    return np.array(b, dtype=np.float64)


def compare(a):
    if len(a) != 2:
        sys.exit(__doc__.split("Usage: ")[1])
    x, y = read_exr(a[0]), read_exr(a[1])
    if x.shape != y.shape:
        sys.exit("bench_mitsuba: %s and %s differ in size" % (a[0], a[1]))
    tol = float(os.environ.get("TOL", 0.01))
    mx, my = x.mean(axis=(0, 1)), y.mean(axis=(0, 1))
    rel = np.abs(mx - my) / np.maximum(np.abs(my), 1e-12)
    h, w = (x.shape[0] // 16) * 16, (x.shape[1] // 16) * 16
    blocks = (x - y)[:h, :w].reshape(h // 16, 16, w // 16, 16, 3).mean(axis=(1, 3))
    print("mean A %s  B %s  relative difference %s (tolerance %g)" % (
        np.array2string(mx, precision=5), np.array2string(my, precision=5),
        np.array2string(rel, precision=5), tol))
    pixel, block = math.sqrt(np.mean((x - y) ** 2)), math.sqrt(np.mean(blocks ** 2))
    print("RMSE per pixel %.5f, of 16x16 block means %.5f (noise alone: about %.5f)" % (
        pixel, block, pixel / 16))
    # independent noise falls 16-fold over 256 pixels; twice that leaves room
    # for its spread, and a moved camera or a mirrored image exceeds it
    if np.any(rel > tol) or block > 2 * pixel / 16:
        print("bench_mitsuba: the images disagree")
        sys.exit(1)
    print("the images agree")


def main():
    a = sys.argv[1:]
    if a[:1] == ["render"]:
        render(a[1:])
    elif a[:1] == ["compare"]:
        compare(a[1:])
    else:
        sys.exit(__doc__.split("Usage: ")[1])


if __name__ == "__main__":
    main()
