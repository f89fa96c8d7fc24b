#!/usr/bin/env python3
"""bench_embree.py - the trace benchmark of `strata bench SCENE --rays KIND`
with Embree (pip install embreex numpy), for comparison; not a test.

It reads the glTF scene with tools/gltf_scene.py, makes the same rays as
strata's src/trace_bench.c (the same hash, lowbias32, of the seed and the
ray's index; camera: the first camera node, through uniformly random points
of the WIDTH x HEIGHT image; random: origins uniform in the bounding box of
the vertices, directions uniform on the sphere), builds Embree's BVH (timed,
alone, on Embree's own threads) and traces the rays with embreex's
EmbreeScene.run (rtcIntersect1 per ray) in THREADS processes at once
(default 2, the cores strata's PoCL uses), each pinned to one CPU over its
share of the rays on a BVH of its own, started together at a barrier; the
time is from the first start to the last end (embreex holds the GIL, so
threads would take turns). It prints one JSON line with strata's keys, so
the hit fraction can be checked against strata's (it should agree to about
1e-3).
Usage: python3 tools/bench_embree.py SCENE.gltf camera|random [COUNT] [WIDTH HEIGHT] [SEED]
       (environment: THREADS, default 2)
"""
import json
import math
import multiprocessing
import os
import sys
import time

import numpy as np
from embreex import rtcore_scene
from embreex.mesh_construction import TriangleMesh

import gltf_scene

M32 = np.uint32(0xFFFFFFFF)


def h32(x):
    x = x.astype(np.uint64)
    x ^= x >> np.uint64(16)
    x = (x * np.uint64(0x7FEB352D)) & np.uint64(0xFFFFFFFF)
    x ^= x >> np.uint64(15)
    x = (x * np.uint64(0x846CA68B)) & np.uint64(0xFFFFFFFF)
    x ^= x >> np.uint64(16)
    return x


def unit(key, dim):
    """st_rng_unit(key, dim): top 24 bits of st_rng_u32 as a float in [0, 1)."""
    d = h32(np.uint64(dim + 0x9E3779B9) & np.uint64(0xFFFFFFFF))
    return ((h32(key ^ d) >> np.uint64(8)).astype(np.float32) * np.float32(2.0 ** -24))


def ray_keys(seed, kind, n):
    """ray_key of trace_bench.c: st_rng_key(seed ^ set * 0x68bc21eb, i, i >> 32)."""
    s = (seed ^ (kind * 0x68BC21EB)) & 0xFFFFFFFF
    i = np.arange(n, dtype=np.uint64)
    inner = h32(np.uint64(s ^ 0x5BD1E995))
    return h32((i >> np.uint64(32)) ^ h32((i & np.uint64(0xFFFFFFFF)) ^ inner))


def load(path):
    """All triangles of the scene, world space (float32, n x 3 x 3), and its camera."""
    prims, camera = gltf_scene.load(path)
    return np.concatenate([p.triangles for p in prims]).astype(np.float32), camera


def make_rays(kind, n, tris, camera, width, height, seed):
    key = ray_keys(seed, kind, n)
    if kind == 1:  # random
        lo, hi = tris.reshape(-1, 3).min(0), tris.reshape(-1, 3).max(0)
        o = np.stack([lo[a] + unit(key, a) * (hi[a] - lo[a]) for a in range(3)], 1)
        z = 1 - 2 * unit(key, 3)
        phi = np.float32(2 * math.pi) * unit(key, 4)
        r = np.sqrt(np.maximum(0, 1 - z * z))
        return o.astype(np.float32), np.stack([r * np.cos(phi), r * np.sin(phi), z], 1).astype(np.float32)
    m, yfov = camera
    fwd, up, right = -m[:3, 2], m[:3, 1], np.cross(-m[:3, 2], m[:3, 1])
    th, aspect = math.tan(yfov / 2), width / height
    fx, fy = unit(key, 0) * width, unit(key, 1) * height
    sx = (2 * fx / width - 1) * th * aspect
    sy = (1 - 2 * fy / height) * th
    d = fwd + sx[:, None] * right + sy[:, None] * up
    d /= np.linalg.norm(d, axis=1)[:, None]
    return np.repeat(m[None, :3, 3], n, 0).astype(np.float32), d.astype(np.float32)


def build(tris):
    """An Embree scene of the triangles, committed; returns it and the seconds."""
    scene = rtcore_scene.EmbreeScene()
    t0 = time.perf_counter()
    TriangleMesh(scene, tris)
    z = np.zeros((1, 3), np.float32)
    scene.run(z, z + np.float32(1))  # embreex commits the scene (builds the BVH) at the first query
    return scene, time.perf_counter() - t0


def trace_share(cpu, tris, o, d, barrier, out):
    """One process, pinned to one CPU (so that Embree's task scheduler starts
    no worker threads to spin beside the others): its own BVH, then, once all
    are ready, its rays (timed)."""
    os.sched_setaffinity(0, {cpu})
    scene, _ = build(tris)
    barrier.wait()
    t0 = time.perf_counter()
    prim = scene.run(o, d)
    out.put((t0, time.perf_counter(), int(np.count_nonzero(prim >= 0))))


def trace_parallel(tris, o, d, threads):
    """Seconds from the first process's start to the last one's end, hits."""
    ctx = multiprocessing.get_context("fork")
    barrier, out = ctx.Barrier(threads), ctx.Queue()
    cpus = sorted(os.sched_getaffinity(0))
    parts = np.array_split(np.arange(len(o)), threads)
    procs = [ctx.Process(target=trace_share, args=(cpus[k % len(cpus)], tris, o[p], d[p], barrier, out))
             for k, p in enumerate(parts)]
    for p in procs:
        p.start()
    res = [out.get() for _ in procs]
    for p in procs:
        p.join()
    if any(p.exitcode != 0 for p in procs):
        sys.exit("bench_embree: a tracing process failed")
    return max(r[1] for r in res) - min(r[0] for r in res), sum(r[2] for r in res)


def main():
    a = sys.argv[1:]
    if len(a) < 2 or a[1] not in ("camera", "random"):
        sys.exit(__doc__.split("Usage: ")[1])
    count = int(a[2]) if len(a) > 2 else 1 << 21
    width, height = (int(a[3]), int(a[4])) if len(a) > 4 else (512, 512)
    seed = int(a[5]) if len(a) > 5 else 0
    threads = int(os.environ.get("THREADS", "2"))
    kind = 1 if a[1] == "random" else 0
    tris, camera = load(a[0])
    o, d = make_rays(kind, count, tris, camera, width, height, seed)
    seconds, hits = trace_parallel(tris, o, d, threads)
    _, build_seconds = build(tris)  # after the tracers, so it has the cores alone
    print(json.dumps({"device": "embree (embreex, %d processes)" % threads, "scene": a[0],
                      "rays": {"kind": a[1], "count": count, "seconds": seconds,
                               "rays_per_second": count / seconds,
                               "hit_fraction": hits / count},
                      "bvh": {"triangles": len(tris), "seconds": build_seconds,
                              "triangles_per_second": len(tris) / build_seconds}}))


if __name__ == "__main__":
    main()
