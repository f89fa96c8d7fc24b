/* trace.h — ray/triangle and ray/BVH intersection: the renderer's hot path.
 *
 * Compiled twice from this one text: as C11 on the host (tests, reference
 * renders) and as OpenCL C 1.2 in the kernels, so the host tests run the
 * device's own code. It is included after st_shared.h (ST_FN, ST_GLOBAL,
 * st_u32, st_bvh_node, st_triangle). Scalar floats only, no recursion, no
 * dynamic indexing of private arrays except the traversal stack.
 *
 * Contract: a hit is a triangle crossing at t in (0, tmax), t > 0 strictly,
 * from its front, or from either side where the triangle is two-sided (see
 * st_triangle: one-sided ones are culled from behind, as a rasteriser does). st_intersect_closest returns the smallest such t
 * (ties: whichever triangle the traversal meets first); st_intersect_any
 * returns whether any exists (shadow rays). Both agree with a brute-force loop
 * of st_intersect_triangle over all triangles: the box test is conservative
 * for the rounding of the slab test and of Moller-Trumbore's t (see
 * ST_TRACE_SLAB_WIDEN). The kernels trace the wide tree (8 children)
 * (st_intersect4_closest, st_intersect4_any: one float8 slab test per node,
 * one float4 Moller-Trumbore test per leaf of up to four triangles);
 * the binary tree's traversal stays as the host's reference, and both are
 * tested against brute force. The BVH is the one st_bvh_build writes
 * (include/st_bvh.h): depth first, leaf depth <= ST_BVH_MAX_DEPTH. On the
 * device the compiler may contract a * b + c into fma, so t, u, v can differ
 * from the host's in the last bits. Tests: tests/test_bvh.c
 * (closest_equals_brute_force_*, triangle_*). */
#ifndef ST_TRACE_H
#define ST_TRACE_H

#ifndef __OPENCL_VERSION__
#include "st_shared.h"
#endif

/* Traversal stack size. The pbrt-style loop below holds at most one pending
 * sibling per level of the current path, i.e. depth - 1 entries, and
 * st_bvh_build guarantees depth <= ST_BVH_MAX_DEPTH. */
#define ST_BVH_MAX_DEPTH 64

typedef struct st_ray {
    st_f32 o[3], d[3], tmax;
} st_ray;

/* Hits are st_hit (st_shared.h), as the wavefront stores them. */

#ifndef __OPENCL_VERSION__
ST_STATIC_ASSERT(sizeof(st_ray) == 28, "st_ray: 7 floats");
#endif

/* Far-end widening of the slab interval: t0 <= t1 * (1 + 2^-12). It covers
 * the rounding of (b - o) * inv in the three slabs (1 + 2 gamma(3) would do:
 * Ize, "Robust BVH Ray Traversal", JCGT 2(2) 2013; pbrt-v3 §3.9.2) and, more
 * to the point, Moller-Trumbore's own error in t, which is relative to t and
 * grows with the triangle's condition |e1||e2| / |e1 x e2|: a hit computed up
 * to 2.4e-4 t before its box's entry (thin triangles, grazing rays) is still
 * found, so that the traversal agrees with a brute-force loop over the same
 * triangle test (tests/test_bvh.c). Cost: boxes entered within that fraction
 * beyond the current closest hit are still opened. */
#define ST_TRACE_SLAB_WIDEN 1.000244140625f

/* Running max and min of the slab test, t > acc ? t : acc and t < acc ? t :
 * acc: a NaN t leaves acc as it is. NaN comes only from a zero direction
 * component (1/d = inf) on a ray starting exactly in that slab's plane,
 * 0 * inf; ignoring the slab then counts the plane as inside, which it is
 * (boxes are closed). Any other zero component gives inv = +-inf and slab
 * times of +-inf, exact. On x86 (host, PoCL) each is one maxss/minss. */
ST_FN st_f32 st_trace_near(st_f32 t, st_f32 acc) { return t > acc ? t : acc; }
ST_FN st_f32 st_trace_far(st_f32 t, st_f32 acc) { return t < acc ? t : acc; }

/* Per-ray constants of the slab test. neg: bit a set when inv[a] < 0 (the
 * sign of 1/d, so -0 counts as negative), the near plane then being bmax.
 * plane[a], plane[3 + a]: where a wide node's near and far planes on axis a
 * start, in floats from its lo[0] (lo[a] at W a, hi[a] at 3 W + W a, W =
 * ST_BVH_WIDTH), so that the wide slab test loads them without choosing per
 * node. */
typedef struct st_trace_ray {
    st_f32 o[3], inv[3];
    st_u32 neg;
    st_u32 plane[6];
} st_trace_ray;

ST_FN void st_trace_setup(st_trace_ray *r, const st_ray *ray)
{
    for (int a = 0; a < 3; ++a) {
        r->o[a] = ray->o[a];
        r->inv[a] = 1.0f / ray->d[a];
    }
    r->neg = (r->inv[0] < 0.0f ? 1u : 0u) | (r->inv[1] < 0.0f ? 2u : 0u) | (r->inv[2] < 0.0f ? 4u : 0u);
    for (st_u32 a = 0u; a < 3u; ++a) {
        st_u32 flip = ((r->neg >> a) & 1u) * 3u * ST_BVH_WIDTH;
        r->plane[a] = ST_BVH_WIDTH * a + flip;
        r->plane[3u + a] = ST_BVH_WIDTH * (a + 3u) - flip;
    }
}

/* Slab test (Kay & Kajiya, "Ray Tracing Complex Scenes", SIGGRAPH 1986) in
 * Williams et al.'s form ("An Efficient and Robust Ray-Box Intersection
 * Algorithm", JGT 2005): the ray's direction signs pick the near and far plane
 * of each axis, so no per-axis min/max swap is needed, and a box with
 * inverted bounds (bmin > bmax, the empty scene's root) is never entered.
 * Returns whether the ray meets the box at some t in [0, tmax]. */
ST_FN int st_trace_box(const ST_GLOBAL st_bvh_node *n, const st_trace_ray *r, st_f32 tmax)
{
    st_u32 neg = r->neg;
    st_f32 nx = (neg & 1u) ? n->bmax[0] : n->bmin[0];
    st_f32 fx = (neg & 1u) ? n->bmin[0] : n->bmax[0];
    st_f32 ny = (neg & 2u) ? n->bmax[1] : n->bmin[1];
    st_f32 fy = (neg & 2u) ? n->bmin[1] : n->bmax[1];
    st_f32 nz = (neg & 4u) ? n->bmax[2] : n->bmin[2];
    st_f32 fz = (neg & 4u) ? n->bmin[2] : n->bmax[2];
    st_f32 t0 = st_trace_near((nx - r->o[0]) * r->inv[0], 0.0f);
    st_f32 t1 = st_trace_far((fx - r->o[0]) * r->inv[0], tmax);
    t0 = st_trace_near((ny - r->o[1]) * r->inv[1], t0);
    t1 = st_trace_far((fy - r->o[1]) * r->inv[1], t1);
    t0 = st_trace_near((nz - r->o[2]) * r->inv[2], t0);
    t1 = st_trace_far((fz - r->o[2]) * r->inv[2], t1);
    return t0 <= t1 * ST_TRACE_SLAB_WIDEN;
}

/* Moller-Trumbore ray/triangle test (Moller & Trumbore, "Fast, Minimum Storage
 * Ray/Triangle Intersection", JGT 2(1) 1997):
 *   p = d x e2, det = e1 . p, s = o - v0, q = s x e1,
 *   u = (s . p) / det, v = (d . q) / det, t = (e2 . q) / det,
 *   hit iff u >= 0, v >= 0, u + v <= 1 and 0 < t < hit->t, and, for a
 *   one-sided triangle (v0[3] != 0), det > 0.
 * det = e1 . (d x e2) = -d . (e1 x e2): positive when the ray meets the
 * front, the side from which v0, v1, v2 run counter-clockwise (glTF's front
 * face, §3.7.2.1); so culling costs one compare, no extra arithmetic.
 * det = 0 (ray parallel to the plane, or a degenerate triangle) needs no test
 * of its own: 1/det is infinite, so u and v are infinite or NaN and fail the
 * barycentric tests. A u outside [0, 1] (or NaN) is a miss whatever v is
 * (v >= 0 makes u + v >= u > 1 in floats too), so the test stops there, and
 * again after v when v or u + v fails: the result is the full test's, without
 * q, v and t (or t) for such triangles. On a hit, fills hit->t, u, v and
 * hit->prim = prim and returns 1; otherwise leaves hit unchanged and returns
 * 0. */
ST_FN int st_intersect_triangle(const ST_GLOBAL st_triangle *tri, const st_ray *ray, st_u32 prim,
                                st_hit *hit)
{
    st_f32 e1x = tri->e1[0], e1y = tri->e1[1], e1z = tri->e1[2];
    st_f32 e2x = tri->e2[0], e2y = tri->e2[1], e2z = tri->e2[2];
    st_f32 dx = ray->d[0], dy = ray->d[1], dz = ray->d[2];
    st_f32 px = dy * e2z - dz * e2y;
    st_f32 py = dz * e2x - dx * e2z;
    st_f32 pz = dx * e2y - dy * e2x;
    st_f32 det = e1x * px + e1y * py + e1z * pz;
    st_f32 inv_det = 1.0f / det;
    st_f32 sx = ray->o[0] - tri->v0[0];
    st_f32 sy = ray->o[1] - tri->v0[1];
    st_f32 sz = ray->o[2] - tri->v0[2];
    st_f32 u = (sx * px + sy * py + sz * pz) * inv_det;
    if (!(u >= 0.0f && u <= 1.0f))
        return 0;
    st_f32 qx = sy * e1z - sz * e1y;
    st_f32 qy = sz * e1x - sx * e1z;
    st_f32 qz = sx * e1y - sy * e1x;
    st_f32 v = (dx * qx + dy * qy + dz * qz) * inv_det;
    if (!(v >= 0.0f && u + v <= 1.0f))
        return 0;
    st_f32 t = (e2x * qx + e2y * qy + e2z * qz) * inv_det;
    int ok = (u >= 0.0f) & (v >= 0.0f) & (u + v <= 1.0f) & (t > 0.0f) & (t < hit->t) &
             ((det > 0.0f) | (tri->v0[3] == 0.0f));
    if (ok) {
        hit->t = t;
        hit->u = u;
        hit->v = v;
        hit->prim = prim;
    }
    return ok;
}

/* Both queries walk the tree depth first (pbrt-v3 §4.4.3,
 * BVHAccel::Intersect): at an interior node the child on the near side of the
 * split plane (split axis from meta, side from the ray's sign on that axis) is
 * visited first and the other is pushed. */
ST_FN st_u32 st_trace_descend(const ST_GLOBAL st_bvh_node *n, st_u32 node, st_u32 neg,
                              st_u32 *stack, st_u32 *sp)
{
    st_u32 far_first = (neg >> (n->meta & 3u)) & 1u;
    stack[(*sp)++] = far_first ? node + 1u : n->offset;
    return far_first ? n->offset : node + 1u;
}

/* Closest hit with t in (0, ray->tmax); the search interval shrinks to the
 * best t found so far. Returns 1 on a hit; hit->prim is ST_NO_HIT and
 * hit->t = ray->tmax otherwise. */
ST_FN int st_intersect_closest(const ST_GLOBAL st_bvh_node *nodes, const ST_GLOBAL st_triangle *tris,
                               const st_ray *ray, st_hit *hit)
{
    st_trace_ray r;
    st_u32 stack[ST_BVH_MAX_DEPTH];
    st_u32 sp = 0u, node = 0u;
    st_trace_setup(&r, ray);
    hit->t = ray->tmax;
    hit->u = 0.0f;
    hit->v = 0.0f;
    hit->prim = ST_NO_HIT;
    for (;;) {
        const ST_GLOBAL st_bvh_node *n = nodes + node;
        if (st_trace_box(n, &r, hit->t)) {
            st_u32 count = n->meta >> 2;
            if (count == 0u) {
                node = st_trace_descend(n, node, r.neg, stack, &sp);
                continue;
            }
            st_u32 first = n->offset;
            for (st_u32 i = first; i < first + count; ++i)
                st_intersect_triangle(tris + i, ray, i, hit);
        }
        if (sp == 0u)
            break;
        node = stack[--sp];
    }
    return hit->prim != ST_NO_HIT;
}

/* Whether any triangle is hit at t in (0, ray->tmax): stops at the first. */
ST_FN int st_intersect_any(const ST_GLOBAL st_bvh_node *nodes, const ST_GLOBAL st_triangle *tris,
                           const st_ray *ray)
{
    st_trace_ray r;
    st_hit hit;
    st_u32 stack[ST_BVH_MAX_DEPTH];
    st_u32 sp = 0u, node = 0u;
    st_trace_setup(&r, ray);
    hit.t = ray->tmax;
    for (;;) {
        const ST_GLOBAL st_bvh_node *n = nodes + node;
        if (st_trace_box(n, &r, ray->tmax)) {
            st_u32 count = n->meta >> 2;
            if (count == 0u) {
                node = st_trace_descend(n, node, r.neg, stack, &sp);
                continue;
            }
            st_u32 first = n->offset;
            for (st_u32 i = first; i < first + count; ++i)
                if (st_intersect_triangle(tris + i, ray, i, &hit))
                    return 1;
        }
        if (sp == 0u)
            return 0;
        node = stack[--sp];
    }
}

/* ---- the wide BVH (st_bvh_wide_node): what the kernels trace ----------------- */

/* Stack of the wide traversals. A node pushes at most all but one of its
 * children (it goes on with the last), so the stack holds at most (children
 * per node - 1) x depth entries. A wide tree is no deeper than the binary one
 * (ST_BVH_MAX_DEPTH), so nodes of 4 children need 3 x 64; for nodes of 8 the
 * collapse keeps 7 x depth within the same bound, or falls back to 4 children
 * (src/bvh_wide.c), so that the private memory per work-item stays that of
 * the 4-wide tree (PoCL allots it to every work-item of a group, up to 4096). */
#define ST_BVH4_STACK (3 * ST_BVH_MAX_DEPTH)

/* The slab test of st_trace_box for a wide node's ST_BVH_WIDTH boxes at
 * once, lane k computed with the same operations in the same order as
 * st_trace_box would for child k (so host and device agree to the bit).
 * Returns a mask, bit k set when the ray meets child k's box at some t in
 * [0, tmax]; tn[k] is that box's entry distance. In OpenCL C an explicit
 * float8 (or float4) test: one AVX (SSE) instruction per step on PoCL, native
 * on GPUs; on the host a loop over the lanes, which gcc vectorises. */
#ifdef __OPENCL_VERSION__
#if ST_BVH_WIDTH == 8
typedef float8 st_wfloat;
typedef int8 st_wint;
#define st_wload vload8
#define st_wstore vstore8
#define ST_WMASK(in)                                                                            \
    ((st_u32)(((in).s0 & 1) | ((in).s1 & 2) | ((in).s2 & 4) | ((in).s3 & 8) | ((in).s4 & 16) |   \
              ((in).s5 & 32) | ((in).s6 & 64) | ((in).s7 & 128)))
#else
typedef float4 st_wfloat;
typedef int4 st_wint;
#define st_wload vload4
#define st_wstore vstore4
#define ST_WMASK(in) ((st_u32)(((in).s0 & 1) | ((in).s1 & 2) | ((in).s2 & 4) | ((in).s3 & 8)))
#endif
ST_FN st_u32 st_trace_box4(const ST_GLOBAL st_bvh_wide_node *n, const st_trace_ray *r, st_f32 tmax,
                           st_f32 *tn)
{
    const ST_GLOBAL st_f32 *b = n->lo[0];
    st_wfloat nx = st_wload(0, b + r->plane[0]);
    st_wfloat fx = st_wload(0, b + r->plane[3]);
    st_wfloat ny = st_wload(0, b + r->plane[1]);
    st_wfloat fy = st_wload(0, b + r->plane[4]);
    st_wfloat nz = st_wload(0, b + r->plane[2]);
    st_wfloat fz = st_wload(0, b + r->plane[5]);
    st_wfloat t, t0 = (st_wfloat)(0.0f), t1 = (st_wfloat)(tmax);
    /* select(acc, t, t > acc): st_trace_near, lane-wise (NaN t keeps acc) */
    t = (nx - r->o[0]) * r->inv[0];
    t0 = select(t0, t, t > t0);
    t = (fx - r->o[0]) * r->inv[0];
    t1 = select(t1, t, t < t1);
    t = (ny - r->o[1]) * r->inv[1];
    t0 = select(t0, t, t > t0);
    t = (fy - r->o[1]) * r->inv[1];
    t1 = select(t1, t, t < t1);
    t = (nz - r->o[2]) * r->inv[2];
    t0 = select(t0, t, t > t0);
    t = (fz - r->o[2]) * r->inv[2];
    t1 = select(t1, t, t < t1);
    st_wstore(t0, 0, tn);
    st_wint in = t0 <= t1 * ST_TRACE_SLAB_WIDEN;
    return ST_WMASK(in);
}
#else
ST_FN st_u32 st_trace_box4(const st_bvh_wide_node *n, const st_trace_ray *r, st_f32 tmax,
                           st_f32 *tn)
{
    st_u32 mask = 0u;
    for (int k = 0; k < ST_BVH_WIDTH; ++k) {
        st_f32 t0 = 0.0f, t1 = tmax;
        for (int a = 0; a < 3; ++a) {
            int flip = (r->neg >> a) & 1u;
            st_f32 near_plane = flip ? n->hi[a][k] : n->lo[a][k];
            st_f32 far_plane = flip ? n->lo[a][k] : n->hi[a][k];
            t0 = st_trace_near((near_plane - r->o[a]) * r->inv[a], t0);
            t1 = st_trace_far((far_plane - r->o[a]) * r->inv[a], t1);
        }
        tn[k] = t0;
        mask |= (st_u32)(t0 <= t1 * ST_TRACE_SLAB_WIDEN) << k;
    }
    return mask;
}
#endif

/* A hint that `p` will be read soon, so that its cache line is on its way
 * while the traversal works elsewhere: the wide nodes and triangles of a big
 * mesh do not fit in the caches, and a random ray waits on memory more than
 * it computes (perf on the 327,680-triangle icosphere: over half of
 * trace_rays' samples on the first load of a node and of a leaf's first
 * triangle). OpenCL's own prefetch() is a no-op on PoCL, so a kernel uses
 * clang's __builtin_prefetch, but only where the host asks for it with
 * -DST_PREFETCH_HINTS (device.c: PoCL's CPU devices, where it was measured):
 * other OpenCL compilers need not know it, and Oclgrind cannot run the
 * llvm.prefetch clang makes of it. The host's gcc has it too. Elsewhere
 * nothing. */
#if defined(__OPENCL_VERSION__) && defined(ST_PREFETCH_HINTS) && defined(__has_builtin)
#if __has_builtin(__builtin_prefetch)
#define ST_PREFETCH(p) __builtin_prefetch(p)
#endif
#endif
#if !defined(ST_PREFETCH) && defined(__GNUC__) && !defined(__OPENCL_VERSION__)
#define ST_PREFETCH(p) __builtin_prefetch(p)
#endif
#ifndef ST_PREFETCH
#define ST_PREFETCH(p) ((void)0)
#endif

/* Index of the lowest set bit of m != 0 (OpenCL C 1.2 has clz, not ctz). */
#ifdef __OPENCL_VERSION__
ST_FN st_u32 st_trace_lowest(st_u32 m) { return 31u - clz(m & (0u - m)); }
#else
ST_FN st_u32 st_trace_lowest(st_u32 m) { return (st_u32)__builtin_ctz(m); }
#endif

/* ---- a leaf's triangles together (the leaf block, st_shared.h) --------------- */

/* The rows of the leaf block a leaf slot's child index names (count[k] != 0). */
ST_FN const ST_GLOBAL st_f32 *st_trace_leaf(const ST_GLOBAL st_bvh_wide_node *nodes, st_u32 child)
{
    return (const ST_GLOBAL st_f32 *)((const ST_GLOBAL char *)nodes + (size_t)child * ST_LEAF_UNIT);
}

/* Block l's first triangle (lane 0's, in BVH order) and its one-sided lanes
 * as bits; n: its triangles. */
ST_FN st_u32 st_leaf_first(const ST_GLOBAL st_f32 *l, st_u32 n)
{
    return ((const ST_GLOBAL st_u32 *)l)[ST_LEAF_ROWS * n];
}
ST_FN st_u32 st_leaf_sides(const ST_GLOBAL st_f32 *l, st_u32 n)
{
    return ((const ST_GLOBAL st_u32 *)l)[ST_LEAF_ROWS * n + 1u];
}

#ifdef __OPENCL_VERSION__
/* Lane mask as bits (lane j -> bit j), and back. */
ST_HOT st_u32 st_leaf_bits(int4 m)
{
    int4 b = m & (int4)(1, 2, 4, 8);
    int2 o = b.lo | b.hi;
    return (st_u32)(o.x | o.y);
}
ST_HOT int4 st_leaf_lanes(st_u32 bits)
{
    return ((int4)((int)bits) & (int4)(1, 2, 4, 8)) != (int4)(0);
}

/* Row r of a block of n triangles as float4: four floats from the row's
 * start, whatever n, so one load serves every block size. Its lanes past n
 * hold the next rows' first floats, or the block's two words and padding
 * (the last row's load stays inside the block: ST_LEAF_UNITS); the test
 * computes them like the others and drops them with `keep`, once. */
ST_HOT float4 st_leaf_row(const ST_GLOBAL st_f32 *l, st_u32 n, st_u32 r)
{
    return vload4(0, l + r * n);
}

/* st_intersect_triangle on a leaf's lanes at once (block l of n triangles),
 * lane j = triangle first + j: the same operations in the same statements,
 * so that the compiler contracts them into fma alike (OpenCL contracts
 * within a statement) and each lane's t, u, v is the scalar test's bit for
 * bit (tests/test_leaf.c checks it on the device). Returns the lanes that
 * hit at t in (0, tmax) as bits (lane j -> bit j), and their t, u, v. The
 * scalar test's early exits become one: when no lane has u in [0, 1], q, v
 * and t are not computed (and the callers, seeing 0, exit at once). */
ST_HOT st_u32 st_leaf_test(const ST_GLOBAL st_f32 *l, st_u32 n, const st_ray *ray, st_f32 tmax,
                           float4 *tt, float4 *uu, float4 *vv)
{
    /* past lane n the e2 rows may reach the block's words (integers, so
     * denormals as floats, slow on some CPUs): those lanes zero */
    int4 keep = (int4)(0, 1, 2, 3) < (int4)((int)n);
    float4 e1x = st_leaf_row(l, n, ST_LEAF_E1), e1y = st_leaf_row(l, n, ST_LEAF_E1 + 1);
    float4 e1z = st_leaf_row(l, n, ST_LEAF_E1 + 2);
    float4 e2x = as_float4(as_int4(st_leaf_row(l, n, ST_LEAF_E2)) & keep);
    float4 e2y = as_float4(as_int4(st_leaf_row(l, n, ST_LEAF_E2 + 1)) & keep);
    float4 e2z = as_float4(as_int4(st_leaf_row(l, n, ST_LEAF_E2 + 2)) & keep);
    st_f32 dx = ray->d[0], dy = ray->d[1], dz = ray->d[2];
    float4 px = dy * e2z - dz * e2y;
    float4 py = dz * e2x - dx * e2z;
    float4 pz = dx * e2y - dy * e2x;
    float4 det = e1x * px + e1y * py + e1z * pz;
    float4 inv_det = 1.0f / det;
    float4 sx = ray->o[0] - st_leaf_row(l, n, ST_LEAF_V0);
    float4 sy = ray->o[1] - st_leaf_row(l, n, ST_LEAF_V0 + 1);
    float4 sz = ray->o[2] - st_leaf_row(l, n, ST_LEAF_V0 + 2);
    float4 u = (sx * px + sy * py + sz * pz) * inv_det;
    int4 in_u = (u >= 0.0f) & (u <= 1.0f) & keep;
    if (!any(in_u))
        return 0u;
    float4 qx = sy * e1z - sz * e1y;
    float4 qy = sz * e1x - sx * e1z;
    float4 qz = sx * e1y - sy * e1x;
    float4 v = (dx * qx + dy * qy + dz * qz) * inv_det;
    float4 t = (e2x * qx + e2y * qy + e2z * qz) * inv_det;
    int4 front = (det > 0.0f) | ~st_leaf_lanes(st_leaf_sides(l, n));
    *tt = t;
    *uu = u;
    *vv = v;
    return st_leaf_bits(in_u & (v >= 0.0f) & (u + v <= 1.0f) & (t > 0.0f) & (t < tmax) & front);
}

/* Lane j's hit into *hit. */
ST_HOT void st_leaf_take(const ST_GLOBAL st_f32 *l, st_u32 n, st_u32 j, float4 t, float4 u,
                         float4 v, st_hit *hit)
{
    st_f32 tj[4], uj[4], vj[4];
    vstore4(t, 0, tj);
    vstore4(u, 0, uj);
    vstore4(v, 0, vj);
    hit->t = tj[j];
    hit->u = uj[j];
    hit->v = vj[j];
    hit->prim = st_leaf_first(l, n) + j;
}

/* The leaf's closest hit below hit->t, as the scalar loop over its
 * triangles in order finds it: the least t among the lanes that hit and, on
 * a tie, the lowest lane (the loop's strict t < best keeps the first). */
ST_HOT void st_leaf_closest(const ST_GLOBAL st_f32 *l, st_u32 n, const st_ray *ray, st_hit *hit)
{
    float4 t, u, v;
    st_u32 ok = st_leaf_test(l, n, ray, hit->t, &t, &u, &v);
    if (ok == 0u)
        return;
    if ((ok & (ok - 1u)) != 0u) { /* more than one lane: the least t's */
        float4 hits = select((float4)(INFINITY), t, st_leaf_lanes(ok)); /* hits: t < hit->t */
        float2 m = fmin(hits.lo, hits.hi);
        ok = st_leaf_bits(hits == fmin(m.x, m.y));
    }
    st_leaf_take(l, n, st_trace_lowest(ok), t, u, v, hit);
}

/* Whether a lane hits at t in (0, ray->tmax); the lowest such lane's hit
 * into *hit (the scalar loop stops at the first). */
ST_HOT int st_leaf_any(const ST_GLOBAL st_f32 *l, st_u32 n, const st_ray *ray, st_hit *hit)
{
    float4 t, u, v;
    st_u32 ok = st_leaf_test(l, n, ray, ray->tmax, &t, &u, &v);
    if (ok != 0u)
        st_leaf_take(l, n, st_trace_lowest(ok), t, u, v, hit);
    return ok != 0u;
}
#else
/* On the host, the scalar loop itself: st_intersect_triangle lane by lane,
 * in order, which the device's vector test matches. Lane j (< n) of block
 * l as the st_triangle it was packed from (padding zero). */
ST_FN st_triangle st_leaf_lane(const st_f32 *l, st_u32 n, st_u32 j)
{
    st_triangle tri = {{0}, {0}, {0}};
    for (st_u32 a = 0u; a < 3u; ++a) {
        tri.v0[a] = l[(ST_LEAF_V0 + a) * n + j];
        tri.e1[a] = l[(ST_LEAF_E1 + a) * n + j];
        tri.e2[a] = l[(ST_LEAF_E2 + a) * n + j];
    }
    tri.v0[3] = (st_leaf_sides(l, n) >> j) & 1u ? ST_TRI_ONE_SIDED : 0.0f;
    return tri;
}

ST_FN void st_leaf_closest(const st_f32 *l, st_u32 n, const st_ray *ray, st_hit *hit)
{
    for (st_u32 j = 0u; j < n; ++j) {
        st_triangle tri = st_leaf_lane(l, n, j);
        st_intersect_triangle(&tri, ray, st_leaf_first(l, n) + j, hit);
    }
}

/* hit->t is ray->tmax on entry (st_intersect4_any_hit). */
ST_FN int st_leaf_any(const st_f32 *l, st_u32 n, const st_ray *ray, st_hit *hit)
{
    for (st_u32 j = 0u; j < n; ++j) {
        st_triangle tri = st_leaf_lane(l, n, j);
        if (st_intersect_triangle(&tri, ray, st_leaf_first(l, n) + j, hit))
            return 1;
    }
    return 0;
}
#endif

/* Asks for a wide node's four cache lines (boxes and links) when the
 * traversal pushes it, so that the misses of the children it takes later
 * overlap with the work on the nearer ones instead of following it. A pushed
 * child is visited unless a nearer hit turns up first, so the hint is seldom
 * wasted; on the Cornell box, whose tree lives in the caches, it costs its
 * instructions alone. */
ST_HOT void st_trace_prefetch_node(const ST_GLOBAL st_bvh_wide_node *node)
{
    const ST_GLOBAL char *b = (const ST_GLOBAL char *)node;
    ST_PREFETCH(b);
    ST_PREFETCH(b + 64);
    ST_PREFETCH(b + 128);
    ST_PREFETCH(b + 192);
}

/* Closest hit through the wide tree; same contract as st_intersect_closest
 * (ties: whichever triangle the traversal meets first). At each node the
 * leaves the ray enters are tested at once; the interior children it enters
 * go on the stack with their entry distance, sorted so that the nearest is
 * visited next (Wald et al. 2008 order children front to back the same way);
 * a popped child whose entry lies beyond the closest hit so far is skipped
 * with the same widening as the box test. */
ST_FN int st_intersect4_closest(const ST_GLOBAL st_bvh_wide_node *nodes, const st_ray *ray,
                                st_hit *hit)
{
    st_trace_ray r;
    st_u32 stack[ST_BVH4_STACK];
    st_f32 entry[ST_BVH4_STACK];
    st_u32 sp = 0u, node = 0u;
    st_trace_setup(&r, ray);
    hit->t = ray->tmax;
    hit->u = 0.0f;
    hit->v = 0.0f;
    hit->prim = ST_NO_HIT;
    for (;;) {
        const ST_GLOBAL st_bvh_wide_node *n = nodes + node;
        st_f32 tn[ST_BVH_WIDTH];
        st_u32 mask = st_trace_box4(n, &r, hit->t, tn), base = sp;
        for (; mask != 0u; mask &= mask - 1u) {
            st_u32 k = st_trace_lowest(mask);
            st_u32 first = n->child[k];
            if (n->count[k] != 0u) {
                st_leaf_closest(st_trace_leaf(nodes, first), n->count[k], ray, hit);
                continue;
            }
            st_trace_prefetch_node(nodes + first);
            /* insertion: entries above base stay sorted far to near */
            st_u32 j = sp++;
            for (; j > base && entry[j - 1u] < tn[k]; --j) {
                stack[j] = stack[j - 1u];
                entry[j] = entry[j - 1u];
            }
            stack[j] = first;
            entry[j] = tn[k];
        }
        for (;;) {
            if (sp == 0u)
                return hit->prim != ST_NO_HIT;
            --sp;
            if (entry[sp] <= hit->t * ST_TRACE_SLAB_WIDEN)
                break;
        }
        node = stack[sp];
    }
}

/* Whether any triangle is hit at t in (0, ray->tmax) through the wide tree:
 * stops at the first (no ordering: any occluder will do), which it leaves in
 * *hit (t, u, v, prim; unspecified when there is none), so that the caller
 * can look at what it met (kernels/shadow.h: its material's alpha). */
ST_FN int st_intersect4_any_hit(const ST_GLOBAL st_bvh_wide_node *nodes, const st_ray *ray,
                                st_hit *hit)
{
    st_trace_ray r;
    st_u32 stack[ST_BVH4_STACK];
    st_u32 sp = 0u, node = 0u;
    st_trace_setup(&r, ray);
    hit->t = ray->tmax;
    for (;;) {
        const ST_GLOBAL st_bvh_wide_node *n = nodes + node;
        st_f32 tn[ST_BVH_WIDTH];
        st_u32 mask = st_trace_box4(n, &r, ray->tmax, tn);
        for (; mask != 0u; mask &= mask - 1u) {
            st_u32 k = st_trace_lowest(mask);
            st_u32 first = n->child[k];
            if (n->count[k] != 0u) {
                if (st_leaf_any(st_trace_leaf(nodes, first), n->count[k], ray, hit))
                    return 1;
                continue;
            }
            st_trace_prefetch_node(nodes + first);
            stack[sp++] = first;
        }
        if (sp == 0u)
            return 0;
        node = stack[--sp];
    }
}

/* st_intersect4_any_hit without the hit. */
ST_FN int st_intersect4_any(const ST_GLOBAL st_bvh_wide_node *nodes, const st_ray *ray)
{
    st_hit hit;
    return st_intersect4_any_hit(nodes, ray, &hit);
}

#endif
