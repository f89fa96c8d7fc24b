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
 * st_triangle: one-sided ones are culled from behind, as a rasteriser does).
 * st_intersect_wide_closest returns the smallest such t (ties: whichever
 * triangle the traversal meets first); st_intersect_wide_any returns whether
 * any exists (shadow rays). Both agree with a brute-force loop of
 * st_intersect_triangle over all triangles: the box test is conservative
 * for the rounding of the slab test and of Moller-Trumbore's t (see
 * ST_TRACE_SLAB_WIDEN). They trace the wide tree (8 children: one vector slab
 * test per node, one vector Moller-Trumbore test per leaf of up to four
 * triangles, both written once over lanes, trace_lanes.h), on the device and
 * on the host alike, the host's vectors being lanes.h's. The BVH is the one
 * st_bvh_build writes (include/st_bvh.h). On the device the compiler may
 * contract a * b + c into fma, so t, u, v can differ from the host's in the
 * last bits. Tests: tests/unit/test_bvh.c (closest_equals_brute_force_*,
 * triangle_*). */
#ifndef ST_TRACE_H
#define ST_TRACE_H

#ifndef __OPENCL_VERSION__
#include "st_shared.h"
#endif
#include "lanes.h"

/* The binary tree's deepest leaf, as st_bvh_build guarantees it; the wide
 * traversal's stack is sized from it (ST_BVH_WIDE_STACK). */
#define ST_BVH_MAX_DEPTH 64

/* Hits are st_hit (st_shared.h), as the wavefront stores them. */


/* Far-end widening of the slab interval: t0 <= t1 * (1 + 2^-12). It covers
 * the rounding of (b - o) * inv in the three slabs (1 + 2 gamma(3) would do:
 * Ize, "Robust BVH Ray Traversal", JCGT 2(2) 2013; pbrt-v3 §3.9.2) and, more
 * to the point, Moller-Trumbore's own error in t, which is relative to t and
 * grows with the triangle's condition |e1||e2| / |e1 x e2|: a hit computed up
 * to 2.4e-4 t before its box's entry (thin triangles, grazing rays) is still
 * found, so that the traversal agrees with a brute-force loop over the same
 * triangle test (tests/unit/test_bvh.c). Cost: boxes entered within that fraction
 * beyond the current closest hit are still opened. */
#define ST_TRACE_SLAB_WIDEN 1.000244140625f

/* Per-ray constants of the slab test. neg: bit a set when inv[a] < 0 (the
 * sign of 1/d, so -0 counts as negative), the near plane then being bmax.
 * plane[a], plane[3 + a]: where a wide node's near and far planes on axis a
 * start, in floats from its lo[0] (lo[a] at W a, hi[a] at 3 W + W a, W =
 * ST_BVH_WIDTH), so that the wide slab test loads them without choosing per
 * node. */
typedef struct st_slab_consts {
    st_f32 o[3], inv[3];
    st_u32 neg;
    st_u32 plane[6];
} st_slab_consts;

ST_HOT void st_trace_setup(st_slab_consts *r, const st_ray *ray)
{
    ST_UNROLL
    for (int a = 0; a < 3; ++a) {
        r->o[a] = ray->o[a];
        r->inv[a] = 1.0f / ray->d[a];
    }
    r->neg = (r->inv[0] < 0.0f ? 1u : 0u) | (r->inv[1] < 0.0f ? 2u : 0u) | (r->inv[2] < 0.0f ? 4u : 0u);
    ST_UNROLL
    for (st_u32 a = 0u; a < 3u; ++a) {
        st_u32 flip = ((r->neg >> a) & 1u) * 3u * ST_BVH_WIDTH;
        r->plane[a] = ST_BVH_WIDTH * a + flip;
        r->plane[3u + a] = ST_BVH_WIDTH * (a + 3u) - flip;
    }
}

/* The slab and triangle tests at the widths the traversals use
 * (trace_lanes.h): 1 for a single triangle, the wide node's boxes and the
 * leaf's triangles, and a packet's rays (packet.h) where ST_W is none of
 * those. */
#define ST_N 1
#include "trace_lanes.h"
#undef ST_N
#define ST_N ST_BVH_WIDTH
#include "trace_lanes.h"
#undef ST_N
#if ST_LEAF_MAX != ST_BVH_WIDTH
#define ST_N ST_LEAF_MAX
#include "trace_lanes.h"
#undef ST_N
#endif
#if ST_W != 1 && ST_W != ST_BVH_WIDTH && ST_W != ST_LEAF_MAX
#define ST_N ST_W
#include "trace_lanes.h"
#undef ST_N
#endif

/* st_triangle_test of one triangle (its one-sidedness in v0[3]): on a hit
 * at t in (0, hit->t), fills hit->t, u, v and hit->prim = prim and returns
 * 1; otherwise leaves hit unchanged and returns 0. */
ST_FN int st_intersect_triangle(const ST_GLOBAL st_triangle *tri, const st_ray *ray, st_u32 prim,
                                st_hit *hit)
{
    st_v3x1 o = {ray->o[0], ray->o[1], ray->o[2]}, d = {ray->d[0], ray->d[1], ray->d[2]};
    st_v3x1 v0 = {tri->v0[0], tri->v0[1], tri->v0[2]};
    st_v3x1 e1 = {tri->e1[0], tri->e1[1], tri->e1[2]};
    st_v3x1 e2 = {tri->e2[0], tri->e2[1], tri->e2[2]};
    st_f32 t, u, v;
    int ok = st_triangle_test1(o, d, v0, e1, e2, hit->t, 1, tri->v0[3] == 0.0f, &t, &u, &v);
    if (ok) {
        hit->t = t;
        hit->u = u;
        hit->v = v;
        hit->prim = prim;
    }
    return ok;
}

/* ---- the wide BVH (st_bvh_wide_node): what the kernels trace ----------------- */

/* Stack of the wide traversals. A node pushes at most all but one of its
 * children (it goes on with the last), so the stack holds at most (children
 * per node - 1) x depth entries. A wide tree is no deeper than the binary one
 * (ST_BVH_MAX_DEPTH), so nodes of 4 children need 3 x 64; for nodes of 8 the
 * collapse keeps 7 x depth within the same bound, or falls back to 4 children
 * (src/bvh/bvh_wide.c), so that the private memory per work-item stays that of
 * the 4-wide tree (PoCL allots it to every work-item of a group, up to 4096). */
#define ST_BVH_WIDE_STACK (3 * ST_BVH_MAX_DEPTH)

/* The slab test of a wide node's ST_BVH_WIDTH boxes for one ray: a mask,
 * bit k set when the ray meets child k's box at some t in [0, tmax], and
 * tn[k] that box's entry distance. The boxes are the lanes of one vector,
 * each axis' near and far planes loaded where the ray's setup says they
 * start. */
ST_HOT st_u32 st_trace_box4(const ST_GLOBAL st_bvh_wide_node *n, const st_slab_consts *r,
                            st_f32 tmax, st_f32 *tn)
{
    const ST_GLOBAL st_f32 *b = n->lo[0];
    ST_VEC(float, ST_BVH_WIDTH) t0;
    ST_VEC(int, ST_BVH_WIDTH) in = ST_CAT(st_slab_test, ST_BVH_WIDTH)(
        ST_VLOAD(ST_BVH_WIDTH, b + r->plane[0]), ST_VLOAD(ST_BVH_WIDTH, b + r->plane[3]),
        ST_VLOAD(ST_BVH_WIDTH, b + r->plane[1]), ST_VLOAD(ST_BVH_WIDTH, b + r->plane[4]),
        ST_VLOAD(ST_BVH_WIDTH, b + r->plane[2]), ST_VLOAD(ST_BVH_WIDTH, b + r->plane[5]), r,
        ST_SPLAT(float, ST_BVH_WIDTH, tmax), &t0);
    ST_VSTORE(ST_BVH_WIDTH, t0, tn);
    return ST_MASK_BITS(ST_BVH_WIDTH, in);
}

/* Index of the lowest set bit of m != 0. OpenCL C 1.2 has clz, not ctz:
 * where the compiler is clang for x86 (PoCL's CPU devices; lanes.h's
 * ST_MOVMSK), its ctz builtin, one tzcnt where the clz form took five
 * instructions per child visited. Oclgrind cannot run the intrinsic it
 * becomes, so elsewhere the clz form stays. */
#if defined(__OPENCL_VERSION__) && defined(ST_MOVMSK) && defined(__has_builtin)
#if __has_builtin(__builtin_ctz)
#define ST_TRACE_CTZ 1
#endif
#endif
#ifdef ST_TRACE_CTZ
ST_FN st_u32 st_trace_lowest(st_u32 m) { return (st_u32)__builtin_ctz(m); }
#elif defined(__OPENCL_VERSION__)
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

/* The wide node at unit `unit` of the array (an interior slot's child[k]). */
ST_FN const ST_GLOBAL st_bvh_wide_node *st_trace_node(const ST_GLOBAL st_bvh_wide_node *nodes, st_u32 unit)
{
    return (const ST_GLOBAL st_bvh_wide_node *)((const ST_GLOBAL char *)nodes + (size_t)unit * ST_LEAF_UNIT);
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

/* A leaf's lanes: one per triangle, ST_LEAF_MAX of them. */
typedef ST_VEC(float, ST_LEAF_MAX) st_leaf_f;
typedef ST_VEC(int, ST_LEAF_MAX) st_leaf_i;
typedef ST_CAT(st_v3x, ST_LEAF_MAX) st_leaf_v3;

/* Row r of a block of n triangles as ST_LEAF_MAX lanes: that many floats
 * from the row's start, whatever n, so one load serves every block size.
 * Its lanes past n hold the next rows' first floats, or the block's two
 * words and padding (the last row's load stays inside the block:
 * ST_LEAF_UNITS); the test drops them with `keep`, once. */
ST_HOT st_leaf_f st_leaf_row(const ST_GLOBAL st_f32 *l, st_u32 n, st_u32 r)
{
    return ST_VLOAD(ST_LEAF_MAX, l + r * n);
}

/* Row e2 + a of the block, its lanes past `keep` zero: there the rows may
 * reach the block's words (integers, so denormals as floats, slow on some
 * CPUs). */
ST_HOT st_leaf_f st_leaf_e2(const ST_GLOBAL st_f32 *l, st_u32 n, st_u32 a, st_leaf_i keep)
{
    return ST_AS_FLOAT(ST_LEAF_MAX, ST_AS_INT(ST_LEAF_MAX, st_leaf_row(l, n, ST_LEAF_E2 + a)) & keep);
}

/* The triangle test of a leaf's lanes at once (block l of n triangles),
 * lane j = triangle first + j, for one ray (broadcast to the lanes): each
 * lane's t, u, v is st_intersect_triangle's bit for bit (tests/device/test_leaf.c
 * checks it on the device). Returns the lanes that hit at t in (0, tmax) as
 * bits (lane j -> bit j), and their t, u, v. */
ST_HOT st_u32 st_leaf_test(const ST_GLOBAL st_f32 *l, st_u32 n, const st_ray *ray, st_f32 tmax,
                           st_leaf_f *tt, st_leaf_f *uu, st_leaf_f *vv)
{
    st_leaf_i keep = ST_IOTA(ST_LEAF_MAX) < ST_SPLAT(int, ST_LEAF_MAX, (int)n);
    st_leaf_v3 o = {ST_SPLAT(float, ST_LEAF_MAX, ray->o[0]), ST_SPLAT(float, ST_LEAF_MAX, ray->o[1]),
                    ST_SPLAT(float, ST_LEAF_MAX, ray->o[2])};
    st_leaf_v3 d = {ST_SPLAT(float, ST_LEAF_MAX, ray->d[0]), ST_SPLAT(float, ST_LEAF_MAX, ray->d[1]),
                    ST_SPLAT(float, ST_LEAF_MAX, ray->d[2])};
    st_leaf_v3 v0 = {st_leaf_row(l, n, ST_LEAF_V0), st_leaf_row(l, n, ST_LEAF_V0 + 1),
                     st_leaf_row(l, n, ST_LEAF_V0 + 2)};
    st_leaf_v3 e1 = {st_leaf_row(l, n, ST_LEAF_E1), st_leaf_row(l, n, ST_LEAF_E1 + 1),
                     st_leaf_row(l, n, ST_LEAF_E1 + 2)};
    st_leaf_v3 e2 = {st_leaf_e2(l, n, 0, keep), st_leaf_e2(l, n, 1, keep),
                     st_leaf_e2(l, n, 2, keep)};
    st_leaf_i two_sided = ST_BITS_MASK(ST_LEAF_MAX, st_leaf_sides(l, n)) == 0;
    st_leaf_i ok = ST_CAT(st_triangle_test, ST_LEAF_MAX)(o, d, v0, e1, e2,
                                                         ST_SPLAT(float, ST_LEAF_MAX, tmax), keep,
                                                         two_sided, tt, uu, vv);
    return ST_MASK_BITS(ST_LEAF_MAX, ok);
}

/* Lane j's hit into *hit. */
ST_HOT void st_leaf_take(const ST_GLOBAL st_f32 *l, st_u32 n, st_u32 j, st_leaf_f t, st_leaf_f u,
                         st_leaf_f v, st_hit *hit)
{
    hit->t = t[j];
    hit->u = u[j];
    hit->v = v[j];
    hit->prim = st_leaf_first(l, n) + j;
}

/* The leaf's closest hit below hit->t, as the scalar loop over its
 * triangles in order finds it: the least t among the lanes that hit and, on
 * a tie, the lowest lane (the loop's strict t < best keeps the first). */
ST_HOT void st_leaf_closest(const ST_GLOBAL st_f32 *l, st_u32 n, const st_ray *ray, st_hit *hit)
{
    /* zero only for the host's compiler, which cannot see that the test
     * sets them wherever it returns a lane (the device drops the stores) */
    st_leaf_f t = ST_SPLAT(float, ST_LEAF_MAX, 0.0f), u = t, v = t;
    st_u32 ok = st_leaf_test(l, n, ray, hit->t, &t, &u, &v);
    if (ok == 0u)
        return;
    if ((ok & (ok - 1u)) != 0u) { /* more than one lane: the least t's */
        st_leaf_f hits = ST_SELECT(ST_LEAF_MAX, ST_SPLAT(float, ST_LEAF_MAX, INFINITY), t,
                                   ST_BITS_MASK(ST_LEAF_MAX, ok)); /* hits: t < hit->t */
        ok = ST_MASK_BITS(ST_LEAF_MAX, hits == ST_HMIN(ST_LEAF_MAX, hits));
    }
    st_leaf_take(l, n, st_trace_lowest(ok), t, u, v, hit);
}

/* Whether a lane hits at t in (0, ray->tmax); the lowest such lane's hit
 * into *hit (the scalar loop stops at the first). */
ST_HOT int st_leaf_any(const ST_GLOBAL st_f32 *l, st_u32 n, const st_ray *ray, st_hit *hit)
{
    st_leaf_f t, u, v;
    st_u32 ok = st_leaf_test(l, n, ray, ray->tmax, &t, &u, &v);
    if (ok != 0u)
        st_leaf_take(l, n, st_trace_lowest(ok), t, u, v, hit);
    return ok != 0u;
}

/* Asks for a wide node's four cache lines (boxes and links), and the four
 * after them, where its first leaf blocks lie (st_shared.h; on the icosphere
 * twelve lines and four were both slower), when the traversal meets it as
 * an interior child, so that the misses of the children it takes later
 * overlap with the work on the nearer ones instead of following it. Such a
 * child is visited unless a nearer hit turns up first, so the hint is seldom
 * wasted; on the Cornell box, whose tree lives in the caches, it costs its
 * instructions alone. Lines past the array's end are only hints: a prefetch
 * does not fault. */
#define ST_TRACE_PREFETCH_LINES 8
ST_HOT void st_trace_prefetch_node(const ST_GLOBAL st_bvh_wide_node *node)
{
    const ST_GLOBAL char *b = (const ST_GLOBAL char *)node;
    ST_UNROLL
    for (int line = 0; line < ST_TRACE_PREFETCH_LINES; line++)
        ST_PREFETCH(b + 64 * line);
}

/* Pushes interior child `child` with entry distance e above base, keeping
 * the entries above base sorted far to near; of equal entries, the later
 * pushed lies nearer the top. */
ST_HOT void st_trace_push_sorted(st_u32 *stack, st_f32 *entry, st_u32 base, st_u32 *sp,
                                 st_u32 child, st_f32 e)
{
    st_u32 j = (*sp)++;
    for (; j > base && entry[j - 1u] < e; --j) {
        stack[j] = stack[j - 1u];
        entry[j] = entry[j - 1u];
    }
    stack[j] = child;
    entry[j] = e;
}

/* A node's interior child `child` (entry e) in visiting order: the nearest
 * so far stays out of the stack, in *near and *near_e (*near 0: none yet;
 * unit 0 is the root, nobody's child), and the rest are pushed sorted. The
 * nearest is the child that would be on top had all been pushed: the least
 * entry, the latest of equal ones (so e <= *near_e takes its place), and a
 * child displaced from it has a larger entry than any pushed meanwhile, so
 * the stack below holds what it would have held. The traversal then goes
 * to the nearest at once, saving its push and pop. */
ST_HOT void st_trace_order(st_u32 *stack, st_f32 *entry, st_u32 base, st_u32 *sp, st_u32 *near,
                           st_f32 *near_e, st_u32 child, st_f32 e)
{
    if (*near == 0u || e <= *near_e) {
        st_u32 c = *near;
        st_f32 ce = *near_e;
        *near = child;
        *near_e = e;
        child = c;
        e = ce;
    }
    if (child != 0u)
        st_trace_push_sorted(stack, entry, base, sp, child, e);
}

/* Closest hit through the wide tree; same contract as st_intersect_closest
 * (ties: whichever triangle the traversal meets first). At each node the
 * leaves the ray enters are tested at once; the interior children it enters
 * are visited nearest first (st_trace_order; Wald et al. 2008 order children
 * front to back the same way), the others left on the stack with their entry
 * distance; a child whose entry lies beyond the closest hit so far is
 * skipped with the same widening as the box test. */
ST_HOT int st_intersect_wide_closest(const ST_GLOBAL st_bvh_wide_node *nodes, const st_ray *ray,
                                     st_hit *hit)
{
    st_slab_consts r;
    st_u32 stack[ST_BVH_WIDE_STACK];
    st_f32 entry[ST_BVH_WIDE_STACK];
    st_u32 sp = 0u, node = 0u;
    st_trace_setup(&r, ray);
    hit->t = ray->tmax;
    hit->u = 0.0f;
    hit->v = 0.0f;
    hit->prim = ST_NO_HIT;
    for (;;) {
        const ST_GLOBAL st_bvh_wide_node *n = st_trace_node(nodes, node);
        st_f32 tn[ST_BVH_WIDTH];
        st_u32 mask = st_trace_box4(n, &r, hit->t, tn), base = sp, near = 0u;
        st_f32 near_e = 0.0f;
        for (; mask != 0u; mask &= mask - 1u) {
            st_u32 k = st_trace_lowest(mask);
            st_u32 first = n->child[k];
            if (n->count[k] != 0u) {
                st_leaf_closest(st_trace_leaf(nodes, first), n->count[k], ray, hit);
                continue;
            }
            st_trace_prefetch_node(st_trace_node(nodes, first));
            st_trace_order(stack, entry, base, &sp, &near, &near_e, first, tn[k]);
        }
        if (near != 0u && near_e <= hit->t * ST_TRACE_SLAB_WIDEN) {
            node = near;
            continue;
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
 * stops at the first, which it leaves in *hit (t, u, v, prim; unspecified
 * when there is none), so that the caller can look at what it met
 * (kernels/integrator/shadow.h: its material's alpha). Any occluder will
 * do, but the children are still visited nearest first (st_trace_order):
 * a shadow ray grazing a dense mesh meets an occluder sooner so than in
 * the order the node lists them (packet.h's st_packet_occluded alike). */
ST_HOT int st_intersect_wide_any_hit(const ST_GLOBAL st_bvh_wide_node *nodes, const st_ray *ray,
                                     st_hit *hit)
{
    st_slab_consts r;
    st_f32 entry[ST_BVH_WIDE_STACK];
    st_u32 stack[ST_BVH_WIDE_STACK];
    st_u32 sp = 0u, node = 0u;
    st_trace_setup(&r, ray);
    hit->t = ray->tmax;
    for (;;) {
        const ST_GLOBAL st_bvh_wide_node *n = st_trace_node(nodes, node);
        st_f32 tn[ST_BVH_WIDTH];
        st_u32 mask = st_trace_box4(n, &r, ray->tmax, tn), next = 0u, base = sp;
        st_f32 near_e = 0.0f;
        for (; mask != 0u; mask &= mask - 1u) {
            st_u32 k = st_trace_lowest(mask);
            st_u32 first = n->child[k];
            if (n->count[k] != 0u) {
                if (st_leaf_any(st_trace_leaf(nodes, first), n->count[k], ray, hit))
                    return 1;
                continue;
            }
            st_trace_prefetch_node(st_trace_node(nodes, first));
            st_trace_order(stack, entry, base, &sp, &next, &near_e, first, tn[k]);
        }
        if (next != 0u) {
            node = next;
            continue;
        }
        if (sp == 0u)
            return 0;
        node = stack[--sp];
    }
}

/* st_intersect_wide_any_hit without the hit. */
ST_HOT int st_intersect_wide_any(const ST_GLOBAL st_bvh_wide_node *nodes, const st_ray *ray)
{
    st_hit hit;
    return st_intersect_wide_any_hit(nodes, ray, &hit);
}

#endif
