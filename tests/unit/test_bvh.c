/* test_bvh.c — the BVH (src/bvh/bvh.c) and the shared traversal (kernels/geom/trace.h)
 * against their definitions:
 *   - closest hit through the tree = closest hit of a brute-force loop over
 *     every input triangle (same t to the bit; same triangle, or one at the
 *     same t), for random rays on random soups of 1 .. 100000 triangles and
 *     degenerate ones (coincident centroids, axis-aligned flat triangles,
 *     triangle sizes spanning 36 orders of magnitude, duplicated triangles,
 *     axis-aligned rays starting on box planes, where 0 * inf meets the slab
 *     test); scenes above 65536 triangles take the builder's cluster-grid path;
 *   - any hit = existence of a closest hit, for random tmax, and false/true
 *     with tmax at/just past the closest t;
 *   - through the wide tree, by the kernels' own traversal and tests
 *     (st_intersect_wide_*, their vectors as the host's lanes), the tree
 *     checked as well;
 *   - the flattened tree is what st_bvh.h promises: preorder numbering, boxes
 *     containing children and triangles, leaves of 1..4 covering every BVH
 *     slot once, order a permutation, tris[i] = input triangle order[i];
 *   - the ray/triangle test against an independent construction (points built
 *     from chosen barycentrics);
 *   - overflow: coordinates near 1e36 (infinite areas) still give valid trees;
 *   - errors: no output handle, missing positions, non-finite coordinates.
 * The 1M-triangle test also prints the build speed (a TAP comment, never an
 * assertion: speed is measured by strata bench). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "st_bvh.h"
#include "trace.h"

/* ---- deterministic random numbers (xorshift64*, Vigna 2016) ---------------- */

typedef struct rng {
    uint64_t s;
} rng;

static uint32_t rng_u32(rng *r)
{
    r->s ^= r->s >> 12;
    r->s ^= r->s << 25;
    r->s ^= r->s >> 27;
    return (uint32_t)((r->s * 2685821657736338717ull) >> 32);
}

/* Uniform in [0, 1). */
static float rng_float(rng *r) { return (float)(rng_u32(r) >> 8) / 16777216.0f; }
static float rng_range(rng *r, float a, float b) { return a + (b - a) * rng_float(r); }

/* ---- scenes ------------------------------------------------------------------ */

/* Triangles of size ~size around centres uniform in [-1, 1]^3. */
static float *soup(rng *r, uint32_t n, float size)
{
    float *p = malloc((size_t)n * 9 * sizeof *p);
    assert_non_null(p);
    for (uint32_t i = 0; i < n; ++i) {
        float c[3] = {rng_range(r, -1, 1), rng_range(r, -1, 1), rng_range(r, -1, 1)};
        for (int v = 0; v < 3; ++v)
            for (int a = 0; a < 3; ++a)
                p[9 * i + 3 * v + a] = c[a] + rng_range(r, -size, size);
    }
    return p;
}

/* Triangles of random shapes and sizes whose bounding boxes all have their
 * centre at c = (0.25, 0.5, 0.75), the centroid the builder bins: v0 = c - h,
 * v1 = c + h, v2 = c + s * h with |s| < 1 per axis. Coordinates are
 * multiples of 2^-16 below 2, so c +- h is exact and the centres coincide
 * bit for bit. */
static float *coincident(rng *r, uint32_t n)
{
    const float c[3] = {0.25f, 0.5f, 0.75f};
    float *p = malloc((size_t)n * 9 * sizeof *p);
    assert_non_null(p);
    for (uint32_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            float h = (float)(1 + rng_u32(r) % 256) / 1024.0f;
            float s = (float)((int)(rng_u32(r) % 63) - 31) / 32.0f;
            p[9 * i + a] = c[a] - h;
            p[9 * i + 3 + a] = c[a] + h;
            p[9 * i + 6 + a] = c[a] + s * h;
        }
    return p;
}

/* Axis-aligned flat triangles: each lies in a plane x, y or z = k/4, so many
 * boxes have zero thickness and many triangles share planes. */
static float *flat(rng *r, uint32_t n)
{
    float *p = malloc((size_t)n * 9 * sizeof *p);
    assert_non_null(p);
    for (uint32_t i = 0; i < n; ++i) {
        uint32_t axis = rng_u32(r) % 3;
        float plane = (float)((int)(rng_u32(r) % 9) - 4) / 4.0f;
        float c[3] = {rng_range(r, -1, 1), rng_range(r, -1, 1), rng_range(r, -1, 1)};
        for (int v = 0; v < 3; ++v)
            for (int a = 0; a < 3; ++a)
                p[9 * i + 3 * v + a] = (uint32_t)a == axis ? plane : c[a] + rng_range(r, -0.2f, 0.2f);
    }
    return p;
}

/* Triangle i spans [2^(i-60), 2^(i-59)]: sizes over 36 orders of magnitude,
 * an unbalanced tree (depth about n / 3) and rays from far away. */
static float *geometric(uint32_t n)
{
    float *p = malloc((size_t)n * 9 * sizeof *p);
    assert_non_null(p);
    for (uint32_t i = 0; i < n; ++i) {
        float x0 = ldexpf(1.0f, (int)i - 60), x1 = 2.0f * x0;
        float tri[9] = {x0, -x0, -x0, x1, x0, -x0, x0, x0, x1};
        memcpy(&p[9 * i], tri, sizeof tri);
    }
    return p;
}

/* ---- references -------------------------------------------------------------- */

/* Input triangles prepared as st_bvh_build documents: (v0, v1 - v0, v2 - v0). */
static st_triangle *prepare(const float *p, uint32_t n)
{
    st_triangle *t = calloc(n ? n : 1, sizeof *t);
    assert_non_null(t);
    for (uint32_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            t[i].v0[a] = p[9 * i + a];
            t[i].e1[a] = p[9 * i + 3 + a] - p[9 * i + a];
            t[i].e2[a] = p[9 * i + 6 + a] - p[9 * i + a];
        }
    return t;
}

/* Whether a one-sided triangle turns its back to the ray: d . (e1 x e2) >= 0
 * (glTF's front is where v0, v1, v2 run counter-clockwise), computed here in
 * double, apart from trace.h's sign of Moller-Trumbore's determinant. */
static int culled(const st_triangle *t, const st_ray *ray)
{
    if (t->v0[3] == 0.0f)
        return 0;
    double n[3] = {(double)t->e1[1] * t->e2[2] - (double)t->e1[2] * t->e2[1],
                   (double)t->e1[2] * t->e2[0] - (double)t->e1[0] * t->e2[2],
                   (double)t->e1[0] * t->e2[1] - (double)t->e1[1] * t->e2[0]};
    return ray->d[0] * n[0] + ray->d[1] * n[1] + ray->d[2] * n[2] >= 0.0;
}

/* The definition: the smallest t over all input triangles that face the ray
 * or are two-sided (each tested as two-sided once it passes the cull). */
static int brute_closest(const st_triangle *tris, uint32_t n, const st_ray *ray, st_hit *hit)
{
    hit->t = ray->tmax;
    hit->prim = ST_NO_HIT;
    for (uint32_t i = 0; i < n; ++i) {
        st_triangle two_sided = tris[i];
        two_sided.v0[3] = 0.0f;
        if (!culled(&tris[i], ray))
            st_intersect_triangle(&two_sided, ray, i, hit);
    }
    return hit->prim != ST_NO_HIT;
}

/* Random rays: origins in the scene box grown by half, directions unnormalised
 * and sometimes axis-aligned (exact zeros, -0 too), half aimed at a point on a
 * random triangle; tmax infinite or random. */
static st_ray random_ray(rng *r, const float *p, uint32_t n, const float lo[3], const float hi[3])
{
    st_ray ray;
    for (int a = 0; a < 3; ++a) {
        float m = 0.5f * (hi[a] - lo[a]) + 1e-3f;
        ray.o[a] = rng_range(r, lo[a] - m, hi[a] + m);
        ray.d[a] = rng_range(r, -1, 1);
    }
    uint32_t kind = rng_u32(r) % 8;
    if (kind < 4 && n > 0) {
        uint32_t i = rng_u32(r) % n;
        float u = rng_float(r), v = rng_float(r);
        if (u + v > 1) {
            u = 1 - u;
            v = 1 - v;
        }
        for (int a = 0; a < 3; ++a) {
            float x = p[9 * i + a] + u * (p[9 * i + 3 + a] - p[9 * i + a]) + v * (p[9 * i + 6 + a] - p[9 * i + a]);
            ray.d[a] = x - ray.o[a];
        }
    } else if (kind == 4) {
        int axis = (int)(rng_u32(r) % 3);
        for (int a = 0; a < 3; ++a)
            ray.d[a] = a == axis ? (rng_u32(r) & 1 ? 1.0f : -1.0f) : (rng_u32(r) & 1 ? 0.0f : -0.0f);
    }
    ray.tmax = rng_u32(r) % 4 == 0 ? rng_range(r, 0.0f, 3.0f) : INFINITY;
    return ray;
}

/* The 12 triangles of each unit cube [x, x+1] x [y, y+1] x [z, z+1] of a
 * k x k x k grid with gaps (cubes at even coordinates): many boxes share
 * planes with integer coordinates. Returns the triangle count. */
static float *cubes(uint32_t k, uint32_t *count)
{
    static const int quad[6][4][3] = {
        {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}, {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}},
        {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}, {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}},
        {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};
    float *p = malloc((size_t)k * k * k * 12 * 9 * sizeof *p);
    uint32_t t = 0;
    assert_non_null(p);
    for (uint32_t c = 0; c < k * k * k; ++c) {
        int base[3] = {2 * (int)(c % k), 2 * (int)(c / k % k), 2 * (int)(c / (k * k))};
        for (int f = 0; f < 6; ++f)
            for (int half = 0; half < 2; ++half) {
                const int *v[3] = {quad[f][0], quad[f][1 + half], quad[f][2 + half]};
                for (int i = 0; i < 3; ++i)
                    for (int a = 0; a < 3; ++a)
                        p[9 * t + 3 * i + a] = (float)(base[a] + v[i][a]);
                t++;
            }
    }
    *count = t;
    return p;
}

/* ---- structural checks --------------------------------------------------------- */

static int box_contains(const st_bvh_node *outer, const float lo[3], const float hi[3])
{
    for (int a = 0; a < 3; ++a)
        if (!(outer->bmin[a] <= lo[a] && hi[a] <= outer->bmax[a]))
            return 0;
    return 1;
}

/* The wide tree's array, in ST_LEAF_UNIT units. */
static size_t wide_units(const st_bvh *bvh)
{
    return (bvh->wide_count + (size_t)bvh->leaf_slots) * (sizeof(st_bvh_wide_node) / ST_LEAF_UNIT);
}

static const st_bvh_wide_node *wide_at(const st_bvh *bvh, size_t unit)
{
    return (const st_bvh_wide_node *)(const void *)((const char *)bvh->wide + unit * ST_LEAF_UNIT);
}

/* Lane j (< n) of leaf block l as the st_triangle it was packed from
 * (padding zero): the block's rows read back as st_shared.h lays them out. */
static st_triangle leaf_lane(const float *l, uint32_t n, uint32_t j)
{
    st_triangle tri = {{0}, {0}, {0}};
    for (uint32_t a = 0u; a < 3u; ++a) {
        tri.v0[a] = l[(ST_LEAF_V0 + a) * n + j];
        tri.e1[a] = l[(ST_LEAF_E1 + a) * n + j];
        tri.e2[a] = l[(ST_LEAF_E2 + a) * n + j];
    }
    tri.v0[3] = (st_leaf_sides(l, n) >> j) & 1u ? ST_TRI_ONE_SIDED : 0.0f;
    return tri;
}

/* Leaf slot child (count c) of the wide tree: its block lies inside the
 * array, and lane j holds triangle first + j exactly (st_triangle's floats,
 * v0[3] as the sides bit j). Returns first. */
static uint32_t check_leaf(const st_bvh *bvh, uint32_t child, uint32_t c)
{
    assert_true(child + ST_LEAF_UNITS(c) <= wide_units(bvh));
    const float *l = st_trace_leaf(bvh->wide, child);
    uint32_t first = st_leaf_first(l, c);
    assert_true(first + c <= (bvh->tri_count ? bvh->tri_count : 1u));
    assert_true(st_leaf_sides(l, c) >> c == 0u);
    for (uint32_t j = 0; j < c; ++j) {
        st_triangle want = bvh->tris[first + j], got = leaf_lane(l, c, j);
        want.e1[3] = want.e2[3] = 0.0f; /* padding, not packed */
        assert_memory_equal(&got, &want, sizeof got);
    }
    return first;
}

static int is_node_start(const size_t *start, uint32_t n, size_t unit)
{
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (start[mid] < unit)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < n && start[lo] == unit;
}

/* The array: node 0 at unit 0; each node's leaf blocks of mixed sizes
 * right after it in slot order, each starting where the one before ends
 * and ST_LEAF_UNITS(count) units long; the next node at the first 64-byte
 * line after them, as st_bvh_wide_span says; every interior child a later
 * node's unit; the padding between and the last slot's rest zero, and
 * leaf_slots no more than they need. Returns the sizes met, bit c for
 * blocks of c triangles. */
static uint32_t check_layout(const st_bvh *bvh)
{
    const size_t per_node = sizeof(st_bvh_wide_node) / ST_LEAF_UNIT, line = 64 / ST_LEAF_UNIT;
    const size_t end = wide_units(bvh);
    const unsigned char *bytes = (const unsigned char *)bvh->wide;
    size_t *start = malloc(bvh->wide_count * sizeof *start), unit = 0;
    uint32_t sizes = 0;
    assert_non_null(start);
    for (uint32_t w = 0; w < bvh->wide_count; ++w) {
        const st_bvh_wide_node *node = wide_at(bvh, unit);
        size_t next = unit + per_node;
        start[w] = unit;
        for (int k = 0; k < ST_BVH_WIDTH; ++k) {
            uint32_t c = node->count[k];
            if (c == 0)
                continue;
            assert_int_equal(node->child[k], next);
            for (size_t b = 4 * (ST_LEAF_ROWS * c + 2); b < ST_LEAF_UNITS(c) * ST_LEAF_UNIT; ++b)
                assert_int_equal(bytes[next * ST_LEAF_UNIT + b], 0);
            next += ST_LEAF_UNITS(c);
            sizes |= 1u << c;
        }
        size_t span = (next - unit + line - 1) / line * line;
        assert_int_equal(st_bvh_wide_span(node), span);
        for (size_t b = next * ST_LEAF_UNIT; b < (unit + span) * ST_LEAF_UNIT; ++b)
            assert_int_equal(bytes[b], 0);
        unit += span;
    }
    assert_true(unit <= end && end - unit < per_node);
    for (size_t b = unit * ST_LEAF_UNIT; b < end * ST_LEAF_UNIT; ++b)
        assert_int_equal(bytes[b], 0);
    for (uint32_t w = 0; w < bvh->wide_count; ++w) {
        const st_bvh_wide_node *node = wide_at(bvh, start[w]);
        for (int k = 0; k < ST_BVH_WIDTH; ++k)
            if (node->count[k] == 0 && node->lo[0][k] <= node->hi[0][k]) {
                assert_true(node->child[k] > start[w]);
                assert_true(is_node_start(start, bvh->wide_count, node->child[k]));
            }
    }
    free(start);
    return sizes;
}

/* The wide tree (st_bvh_wide_node) from the node at `unit`: nodes depth
 * first (a child after its parent), each used slot's box containing its subtree's triangles,
 * unused slots inverted, leaves of 1..4 covering every triangle once, no
 * deeper than the binary tree. Recursive: returns the subtree's depth. */
static uint32_t check_wide_node(const st_bvh *bvh, const float *p, uint32_t unit, const float *plo,
                                const float *phi, uint32_t *covered)
{
    const st_bvh_wide_node *node = wide_at(bvh, unit);
    uint32_t deepest = 1, used = 0;
    for (int k = 0; k < ST_BVH_WIDTH; ++k) {
        float lo[3] = {node->lo[0][k], node->lo[1][k], node->lo[2][k]};
        float hi[3] = {node->hi[0][k], node->hi[1][k], node->hi[2][k]};
        uint32_t c = node->count[k], first = node->child[k];
        if (lo[0] > hi[0]) { /* unused slot (or the empty scene's leaf) */
            for (int a = 0; a < 3; ++a)
                assert_true(lo[a] == FLT_MAX && hi[a] == -FLT_MAX);
            assert_true(bvh->tri_count == 0 || (c == 0 && first == 0));
            continue;
        }
        used++;
        for (int a = 0; a < 3; ++a)
            assert_true(plo[a] <= lo[a] && hi[a] <= phi[a]);
        if (c == 0) {
            assert_true(first > unit && first < wide_units(bvh));
            uint32_t d = 1 + check_wide_node(bvh, p, first, lo, hi, covered);
            deepest = d > deepest ? d : deepest;
            continue;
        }
        assert_true(c <= 4);
        first = check_leaf(bvh, first, c);
        for (uint32_t t = first; t < first + c; ++t) {
            covered[t]++;
            for (int v = 0; v < 3; ++v)
                for (int a = 0; a < 3; ++a) {
                    float x = p[9 * (size_t)bvh->order[t] + 3 * v + a];
                    assert_true(lo[a] <= x && x <= hi[a]);
                }
        }
    }
    assert_true(used >= 2 || unit == 0); /* a root may hold one leaf, or none (empty scene) */
    return deepest;
}

/* The most children (used slots) of any wide node. */
static uint32_t wide_children_max(const st_bvh *bvh)
{
    uint32_t most = 0;
    size_t unit = 0;
    for (uint32_t w = 0; w < bvh->wide_count; ++w) {
        const st_bvh_wide_node *node = wide_at(bvh, unit);
        uint32_t used = 0;
        for (int k = 0; k < ST_BVH_WIDTH; ++k)
            used += node->lo[0][k] <= node->hi[0][k];
        most = used > most ? used : most;
        unit += st_bvh_wide_span(node);
    }
    return most;
}

static void check_wide_structure(const st_bvh *bvh, const float *p, uint32_t n)
{
    uint32_t *covered = calloc(n ? n : 1, sizeof *covered);
    float lo[3] = {-INFINITY, -INFINITY, -INFINITY}, hi[3] = {INFINITY, INFINITY, INFINITY};
    assert_non_null(covered);
    assert_true(bvh->wide_count >= 1 && bvh->wide_count <= bvh->node_count);
    uint32_t depth = check_wide_node(bvh, p, 0, lo, hi, covered);
    assert_int_equal(depth, bvh->wide_depth);
    assert_true(depth <= bvh->depth);
    /* the traversal's stack bound: all but one child pushed per level */
    uint32_t most = wide_children_max(bvh);
    assert_true(most <= ST_BVH_WIDTH);
    assert_true((most ? most - 1 : 0) * depth <= ST_BVH_WIDE_STACK);
    for (uint32_t k = 0; k < n; ++k)
        assert_int_equal(covered[k], 1);
    check_layout(bvh);
    free(covered);
}

/* Walks the tree from the root in preorder and checks every promise of
 * st_bvh.h; returns the number of leaves. */
static uint32_t check_structure(const st_bvh *bvh, const float *p, uint32_t n)
{
    uint32_t *covered = calloc(n ? n : 1, sizeof *covered), *seen = calloc(n ? n : 1, sizeof *seen);
    uint32_t stack[2 * ST_BVH_MAX_DEPTH + 2], depth_of[2 * ST_BVH_MAX_DEPTH + 2];
    uint32_t sp = 0, visited = 0, leaves = 0, deepest = 0;
    assert_non_null(covered);
    assert_non_null(seen);
    assert_int_equal(bvh->tri_count, n);
    assert_true(bvh->node_count >= 1 && bvh->node_count <= (n ? 2 * n - 1 : 1));
    stack[sp] = 0;
    depth_of[sp++] = 1;
    while (sp > 0) {
        uint32_t i = stack[--sp], depth = depth_of[sp];
        const st_bvh_node *node = &bvh->nodes[i];
        uint32_t count = node->meta >> 2;
        assert_int_equal(i, visited); /* depth first: preorder numbering */
        visited++;
        assert_true(depth <= ST_BVH_MAX_DEPTH);
        deepest = depth > deepest ? depth : deepest;
        if (count == 0) {
            const st_bvh_node *l = &bvh->nodes[i + 1], *r = &bvh->nodes[node->offset];
            assert_true((node->meta & 3u) < 3u);
            assert_true(node->offset > i + 1 && node->offset < bvh->node_count);
            assert_true(box_contains(node, l->bmin, l->bmax));
            assert_true(box_contains(node, r->bmin, r->bmax));
            assert_true(sp + 2 <= 2 * ST_BVH_MAX_DEPTH + 2);
            stack[sp] = node->offset;
            depth_of[sp++] = depth + 1;
            stack[sp] = i + 1;
            depth_of[sp++] = depth + 1;
            continue;
        }
        leaves++;
        assert_true(count >= 1 && count <= 4);
        assert_true(node->offset + count <= n);
        for (uint32_t k = node->offset; k < node->offset + count; ++k) {
            covered[k]++;
            for (int v = 0; v < 3; ++v) {
                const float *x = &p[9 * (size_t)bvh->order[k] + 3 * v];
                assert_true(box_contains(node, x, x));
            }
        }
    }
    assert_int_equal(visited, bvh->node_count);
    assert_int_equal(deepest, bvh->depth);
    for (uint32_t k = 0; k < n; ++k) {
        assert_int_equal(covered[k], 1);
        assert_true(bvh->order[k] < n);
        seen[bvh->order[k]]++;
    }
    for (uint32_t k = 0; k < n; ++k)
        assert_int_equal(seen[k], 1);
    free(covered);
    free(seen);
    check_wide_structure(bvh, p, n);
    return leaves;
}

static void check_tris_match_order(const st_bvh *bvh, const st_triangle *input)
{
    for (uint32_t i = 0; i < bvh->tri_count; ++i)
        assert_memory_equal(&bvh->tris[i], &input[bvh->order[i]], sizeof(st_triangle));
}

static void scene_bounds(const float *p, uint32_t n, float lo[3], float hi[3])
{
    for (int a = 0; a < 3; ++a) {
        lo[a] = n ? INFINITY : -1.0f;
        hi[a] = n ? -INFINITY : 1.0f;
    }
    for (uint32_t i = 0; i < 3 * n; ++i)
        for (int a = 0; a < 3; ++a) {
            lo[a] = fminf(lo[a], p[3 * i + a]);
            hi[a] = fmaxf(hi[a], p[3 * i + a]);
        }
}

/* The wide traversal (what the kernels run, here on the host's lanes)
 * against the brute force's closest hit want (exists: whether there is
 * one): same t to the bit, the same triangle (then the same u, v) or one
 * hit at that t; any-hit agrees, also with tmax at and just past the
 * closest t. */
static void check_wide_ray(const st_bvh *bvh, const st_triangle *input, const st_ray *ray,
                           int exists, const st_hit *want)
{
    st_hit got;
    assert_int_equal(st_intersect_wide_closest(bvh->wide, ray, &got), exists);
    assert_int_equal(st_intersect_wide_any(bvh->wide, ray), exists);
    if (!exists) {
        assert_int_equal(got.prim, ST_NO_HIT);
        return;
    }
    assert_true(got.prim < bvh->tri_count);
    assert_memory_equal(&got.t, &want->t, sizeof got.t);
    if (bvh->order[got.prim] != want->prim) { /* a tie: that triangle is hit at the same t */
        st_hit tie = {INFINITY, 0, 0, ST_NO_HIT};
        assert_true(st_intersect_triangle(&input[bvh->order[got.prim]], ray, 0, &tie));
        assert_memory_equal(&tie.t, &want->t, sizeof tie.t);
    } else {
        assert_memory_equal(&got.u, &want->u, sizeof got.u);
        assert_memory_equal(&got.v, &want->v, sizeof got.v);
    }
    st_ray shorter = *ray;
    shorter.tmax = want->t;
    assert_false(st_intersect_wide_any(bvh->wide, &shorter));
    shorter.tmax = nextafterf(want->t, INFINITY);
    assert_true(st_intersect_wide_any(bvh->wide, &shorter));
}

/* Builds, checks the structure, then compares `rays` random rays with the
 * brute-force closest hit, and any-hit with the closest hit's existence.
 * Returns the number of rays that hit (to check the test is not vacuous). */
static uint32_t check_scene_sided(const float *p, uint32_t n, uint32_t rays, uint64_t seed,
                                  int one_sided)
{
    st_bvh *bvh = NULL;
    st_error err = {0};
    rng r = {seed};
    float lo[3], hi[3];
    uint32_t hits = 0;
    assert_int_equal(st_bvh_build(p, n, &bvh, &err), ST_OK);
    assert_non_null(bvh);
    st_triangle *input = prepare(p, n);
    check_structure(bvh, p, n);
    check_tris_match_order(bvh, input);
    for (uint32_t i = 0; one_sided && i < bvh->tri_count; ++i) { /* every other one-sided */
        input[i].v0[3] = (i & 1u) ? ST_TRI_ONE_SIDED : 0.0f;
        bvh->tris[i].v0[3] = (bvh->order[i] & 1u) ? ST_TRI_ONE_SIDED : 0.0f;
    }
    st_bvh_pack_leaves(bvh);
    scene_bounds(p, n, lo, hi);
    for (uint32_t k = 0; k < rays; ++k) {
        st_ray ray = random_ray(&r, p, n, lo, hi);
        st_hit want;
        int exists = brute_closest(input, n, &ray, &want);
        check_wide_ray(bvh, input, &ray, exists, &want);
        hits += (uint32_t)exists;
    }
    free(input);
    st_bvh_destroy(bvh);
    return hits;
}

static uint32_t check_scene(const float *p, uint32_t n, uint32_t rays, uint64_t seed)
{
    return check_scene_sided(p, n, rays, seed, 0);
}

/* ---- tests: closest hit = brute force ---------------------------------------- */

static void closest_equals_brute_force_1(void **state)
{
    (void)state;
    rng r = {1};
    float *p = soup(&r, 1, 0.8f);
    assert_true(check_scene(p, 1, 20000, 11) > 1000);
    free(p);
}

static void closest_equals_brute_force_2(void **state)
{
    (void)state;
    rng r = {2};
    float *p = soup(&r, 2, 0.8f);
    assert_true(check_scene(p, 2, 20000, 12) > 1000);
    free(p);
}

static void closest_equals_brute_force_100(void **state)
{
    (void)state;
    rng r = {3};
    float *p = soup(&r, 100, 0.3f);
    assert_true(check_scene(p, 100, 20000, 13) > 5000);
    free(p);
}

static void closest_equals_brute_force_10000(void **state)
{
    (void)state;
    rng r = {4};
    float *p = soup(&r, 10000, 0.05f);
    assert_true(check_scene(p, 10000, 5000, 14) > 2000);
    free(p);
}

/* Half the triangles one-sided: every traversal culls as the definition
 * does (brute_closest's own test of the facing); fewer hits than two-sided. */
static void closest_equals_brute_force_one_sided(void **state)
{
    (void)state;
    rng r = {4};
    float *p = soup(&r, 10000, 0.05f);
    uint32_t culled_hits = check_scene_sided(p, 10000, 5000, 14, 1);
    assert_true(culled_hits > 1000);
    assert_true(culled_hits < check_scene(p, 10000, 5000, 14));
    free(p);
}

/* Large enough for the builder's grid of clusters (its top levels). */
static void closest_equals_brute_force_100000(void **state)
{
    (void)state;
    rng r = {5};
    float *p = soup(&r, 100000, 0.02f);
    assert_true(check_scene(p, 100000, 400, 15) > 150);
    free(p);
}

static void closest_equals_brute_force_coincident_centroids(void **state)
{
    (void)state;
    rng r = {6};
    float *p = coincident(&r, 1000);
    assert_true(check_scene(p, 1000, 20000, 16) > 5000);
    free(p);
}

static void closest_equals_brute_force_flat_axis_aligned(void **state)
{
    (void)state;
    rng r = {7};
    float *p = flat(&r, 2000);
    assert_true(check_scene(p, 2000, 20000, 17) > 5000);
    free(p);
}

/* Two copies of one soup: every triangle has a twin, so every hit is a tie. */
static void closest_equals_brute_force_duplicates(void **state)
{
    (void)state;
    rng r = {8};
    float *p = soup(&r, 500, 0.2f);
    float *twice = malloc(1000 * 9 * sizeof *twice);
    assert_non_null(twice);
    memcpy(twice, p, 500 * 9 * sizeof *p);
    memcpy(twice + 500 * 9, p, 500 * 9 * sizeof *p);
    assert_true(check_scene(twice, 1000, 20000, 18) > 5000);
    free(twice);
    free(p);
}

/* Axis-aligned rays (direction components exactly 0, +-1) from origins on
 * the cubes' face planes and edges: zero components meet box faces at
 * 0 * inf, and hits land on triangle edges. */
static void closest_equals_brute_force_rays_in_box_planes(void **state)
{
    (void)state;
    uint32_t n, hits = 0;
    float *p = cubes(3, &n);
    st_bvh *bvh = NULL;
    st_error err = {0};
    rng r = {30};
    assert_int_equal(st_bvh_build(p, n, &bvh, &err), ST_OK);
    st_triangle *input = prepare(p, n);
    for (int k = 0; k < 20000; ++k) {
        st_ray ray;
        do {
            for (int a = 0; a < 3; ++a)
                ray.d[a] = (float)((int)(rng_u32(&r) % 3) - 1);
        } while (ray.d[0] == 0 && ray.d[1] == 0 && ray.d[2] == 0);
        for (int a = 0; a < 3; ++a) {
            ray.o[a] = (float)((int)(rng_u32(&r) % 13) - 1) * 0.5f; /* -0.5 .. 5.5 in halves */
            if (ray.d[a] == 0 && rng_u32(&r) & 1)
                ray.d[a] = -0.0f;
        }
        ray.tmax = INFINITY;
        st_hit want;
        int found = brute_closest(input, n, &ray, &want);
        check_wide_ray(bvh, input, &ray, found, &want);
        hits += (uint32_t)found;
    }
    assert_true(hits > 5000);
    free(input);
    st_bvh_destroy(bvh);
    free(p);
}

static void closest_equals_brute_force_unbalanced_geometric(void **state)
{
    (void)state;
    float *p = geometric(120);
    st_bvh *bvh = NULL;
    st_error err = {0};
    assert_int_equal(st_bvh_build(p, 120, &bvh, &err), ST_OK);
    assert_true(bvh->depth > 20 && bvh->depth <= ST_BVH_MAX_DEPTH); /* unbalanced, yet bounded */
    st_bvh_destroy(bvh);
    assert_true(check_scene(p, 120, 20000, 19) > 1000);
    free(p);
}

/* ---- tests: structure and the empty scene ------------------------------------- */

/* A binary node of box [0, size]^3 at nodes[*n]: a leaf of one triangle
 * (numbered by *leaves), or interior with its first child next. */
static uint32_t add_node(st_bvh_node *nodes, uint32_t *n, uint32_t *leaves, float size, int leaf)
{
    uint32_t i = (*n)++;
    for (int a = 0; a < 3; ++a) {
        nodes[i].bmin[a] = 0.0f;
        nodes[i].bmax[a] = size;
    }
    nodes[i].offset = leaf ? (*leaves)++ : 0u;
    nodes[i].meta = leaf ? 1u << 2 : 0u;
    return i;
}

/* A complete binary subtree of `levels` interior levels over big boxes. */
static void add_bushy(st_bvh_node *nodes, uint32_t *n, uint32_t *leaves, int levels)
{
    uint32_t i = add_node(nodes, n, leaves, 10.0f, levels == 0);
    if (levels == 0)
        return;
    add_bushy(nodes, n, leaves, levels - 1);
    nodes[i].offset = *n;
    add_bushy(nodes, n, leaves, levels - 1);
}

/* A subtree of seven leaves over big boxes: four below one child, three
 * below the other. */
static void add_seven(st_bvh_node *nodes, uint32_t *n, uint32_t *leaves)
{
    uint32_t i = add_node(nodes, n, leaves, 10.0f, 0);
    add_bushy(nodes, n, leaves, 2);
    nodes[i].offset = *n;
    uint32_t j = add_node(nodes, n, leaves, 10.0f, 0);
    add_bushy(nodes, n, leaves, 1);
    nodes[j].offset = *n;
    add_node(nodes, n, leaves, 10.0f, 1);
}

/* A chain whose every node has a small interior child (the chain goes on)
 * and a sibling of seven leaves over big boxes: the cheapest wide tree
 * opens each sibling into its chain node's seven slots (no node of its
 * own), which leaves the eighth to the chain's next node, so at full width
 * the wide tree is as deep as the chain: 7 x 40 > ST_BVH_WIDE_STACK. It must
 * fall back to nodes of four children, whose stack bound 3 x depth holds. */
static void collapse_keeps_stack_bound_on_a_deep_chain(void **state)
{
    (void)state;
    enum { CHAIN = 40, BUSHY = 3 };
    st_bvh *bvh = calloc(1, sizeof *bvh);
    assert_non_null(bvh);
    bvh->nodes = calloc(CHAIN * (2u << BUSHY) + 1, sizeof *bvh->nodes);
    assert_non_null(bvh->nodes);
    /* depth first: the spine (each node's first child is the next), the
     * chain's end leaf, then the bushy second children, deepest first */
    uint32_t n = 0, leaves = 0;
    uint32_t spine[CHAIN];
    for (int level = 0; level < CHAIN; ++level)
        spine[level] = add_node(bvh->nodes, &n, &leaves, 1.0f, 0);
    add_node(bvh->nodes, &n, &leaves, 1.0f, 1);
    for (int level = CHAIN - 1; level >= 0; --level) {
        bvh->nodes[spine[level]].offset = n;
        add_seven(bvh->nodes, &n, &leaves);
    }
    bvh->node_count = n;
    bvh->depth = CHAIN + BUSHY + 1; /* the deepest bushy subtree's leaves */
    st_error err = {0};
    assert_int_equal(st_bvh_collapse_wide(bvh, &err), ST_OK);
    uint32_t most = wide_children_max(bvh);
    assert_true(most >= 2 && most <= 4);
    assert_true(bvh->wide_depth >= CHAIN && bvh->wide_depth <= bvh->depth);
    assert_true((most - 1) * bvh->wide_depth <= ST_BVH_WIDE_STACK);
    st_bvh_destroy(bvh);
}

/* ---- the collapse's choice against enumeration --------------------------------
 * The wide tree should be the one of least total wide-node area (the sum of
 * A(node) over its nodes: a ray's expected node visits, bvh_wide.c). Here
 * the least is found by listing every way each binary subtree can fill the
 * slots of the wide node above it, as (slots, cost) pairs, and trying every
 * pair of the two children's ways: no recurrence of the builder's. */

typedef struct way {
    int slots;
    double cost;
} way;

static double node_area(const st_bvh_node *n)
{
    double dx = (double)n->bmax[0] - n->bmin[0], dy = (double)n->bmax[1] - n->bmin[1];
    double dz = (double)n->bmax[2] - n->bmin[2];
    return dx * dy + dy * dz + dz * dx;
}

static double least_wide(const st_bvh_node *nodes, uint32_t n, double *memo);

/* Every way binary subtree n takes at most ST_BVH_WIDTH slots: one slot
 * (a leaf, cost 0; an interior node, a wide node of its own), or any way of
 * its first child beside any way of its second. Returns their number. */
static int ways_of(const st_bvh_node *nodes, uint32_t n, double *memo, way **out)
{
    way *w = malloc(sizeof *w);
    assert_non_null(w);
    if (nodes[n].meta >> 2) {
        w[0] = (way){1, 0.0};
        *out = w;
        return 1;
    }
    w[0] = (way){1, least_wide(nodes, n, memo)};
    way *a, *b;
    int na = ways_of(nodes, n + 1u, memo, &a), nb = ways_of(nodes, nodes[n].offset, memo, &b);
    int count = 1;
    for (int i = 0; i < na; i++)
        for (int j = 0; j < nb; j++)
            if (a[i].slots + b[j].slots <= ST_BVH_WIDTH) {
                w = realloc(w, (size_t)(count + 1) * sizeof *w);
                assert_non_null(w);
                w[count++] = (way){a[i].slots + b[j].slots, a[i].cost + b[j].cost};
            }
    free(a);
    free(b);
    *out = w;
    return count;
}

/* The least cost of binary node n made a wide node: its area and the
 * cheapest of its children's ways that fit its slots. */
static double least_wide(const st_bvh_node *nodes, uint32_t n, double *memo)
{
    if (memo[n] >= 0.0)
        return memo[n];
    way *a, *b;
    int na = ways_of(nodes, n + 1u, memo, &a), nb = ways_of(nodes, nodes[n].offset, memo, &b);
    double least = INFINITY;
    for (int i = 0; i < na; i++)
        for (int j = 0; j < nb; j++)
            if (a[i].slots + b[j].slots <= ST_BVH_WIDTH && a[i].cost + b[j].cost < least)
                least = a[i].cost + b[j].cost;
    free(a);
    free(b);
    return memo[n] = node_area(&nodes[n]) + least;
}

/* The wide tree's cost: the area of the box around each wide node's slots. */
static double wide_cost(const st_bvh *bvh)
{
    double sum = 0.0;
    size_t unit = 0;
    for (uint32_t w = 0; w < bvh->wide_count; ++w) {
        const st_bvh_wide_node *node = wide_at(bvh, unit);
        st_bvh_node box = {{INFINITY, INFINITY, INFINITY}, 0u, {-INFINITY, -INFINITY, -INFINITY}, 0u};
        for (int k = 0; k < ST_BVH_WIDTH; ++k)
            for (int a = 0; a < 3 && node->lo[0][k] <= node->hi[0][k]; ++a) {
                box.bmin[a] = fminf(box.bmin[a], node->lo[a][k]);
                box.bmax[a] = fmaxf(box.bmax[a], node->hi[a][k]);
            }
        sum += node_area(&box);
        unit += st_bvh_wide_span(node);
    }
    return sum;
}

/* On random soups, and on a grid of cubes, whose many boxes share planes:
 * the built wide tree costs the least that enumeration finds (to float
 * rounding). */
static void collapse_has_least_area(void **state)
{
    (void)state;
    const uint32_t sizes[] = {9, 24, 48, 96};
    rng r = {0x5eedu};
    for (size_t t = 0; t < 5; t++) {
        uint32_t n = t < 4 ? sizes[t] : 0u;
        float *p = t < 4 ? soup(&r, n, 0.3f) : cubes(2, &n);
        st_bvh *bvh = NULL;
        st_error err = {0};
        assert_int_equal(st_bvh_build(p, n, &bvh, &err), ST_OK);
        double *memo = malloc(bvh->node_count * sizeof *memo);
        assert_non_null(memo);
        for (uint32_t i = 0; i < bvh->node_count; i++)
            memo[i] = -1.0;
        double least = least_wide(bvh->nodes, 0u, memo), got = wide_cost(bvh);
        assert_true(fabs(got - least) <= 1e-5 * least);
        free(memo);
        st_bvh_destroy(bvh);
        free(p);
    }
}

static void build_empty_scene_has_no_hits(void **state)
{
    (void)state;
    st_bvh *bvh = NULL;
    st_error err = {0};
    rng r = {9};
    float lo[3] = {-1, -1, -1}, hi[3] = {1, 1, 1};
    assert_int_equal(st_bvh_build(NULL, 0, &bvh, &err), ST_OK);
    assert_int_equal(bvh->tri_count, 0);
    assert_int_equal(bvh->node_count, 1);
    assert_int_equal(bvh->depth, 1);
    assert_non_null(bvh->tris);   /* never-empty device buffers */
    assert_non_null(bvh->order);
    for (int k = 0; k < 20000; ++k) {
        st_ray ray = random_ray(&r, NULL, 0, lo, hi);
        st_hit hit;
        assert_false(st_intersect_wide_closest(bvh->wide, &ray, &hit));
        assert_int_equal(hit.prim, ST_NO_HIT);
        assert_false(st_intersect_wide_any(bvh->wide, &ray));
    }
    check_wide_structure(bvh, NULL, 0);
    st_bvh_destroy(bvh);
}

static void build_leaves_hold_at_most_four_and_order_is_permutation(void **state)
{
    (void)state;
    rng r = {10};
    for (uint32_t n = 1; n <= 40; ++n) {
        float *p = soup(&r, n, 0.5f);
        st_bvh *bvh = NULL;
        st_error err = {0};
        assert_int_equal(st_bvh_build(p, n, &bvh, &err), ST_OK);
        check_structure(bvh, p, n);
        st_bvh_destroy(bvh);
        free(p);
    }
}

static void build_is_deterministic(void **state)
{
    (void)state;
    rng r = {11};
    float *p = soup(&r, 70000, 0.02f);
    st_bvh *a = NULL, *b = NULL;
    st_error err = {0};
    assert_int_equal(st_bvh_build(p, 70000, &a, &err), ST_OK);
    assert_int_equal(st_bvh_build(p, 70000, &b, &err), ST_OK);
    assert_int_equal(a->node_count, b->node_count);
    assert_memory_equal(a->nodes, b->nodes, a->node_count * sizeof *a->nodes);
    assert_memory_equal(a->order, b->order, a->tri_count * sizeof *a->order);
    assert_int_equal(a->wide_count, b->wide_count);
    assert_int_equal(a->leaf_slots, b->leaf_slots);
    assert_memory_equal(a->wide, b->wide, (a->wide_count + a->leaf_slots) * sizeof *a->wide);
    st_bvh_destroy(a);
    st_bvh_destroy(b);
    free(p);
}

/* Every array of two trees the same, byte for byte. */
static void assert_same_tree(const st_bvh *a, const st_bvh *b)
{
    assert_int_equal(a->tri_count, b->tri_count);
    assert_int_equal(a->node_count, b->node_count);
    assert_int_equal(a->depth, b->depth);
    assert_memory_equal(a->nodes, b->nodes, a->node_count * sizeof *a->nodes);
    assert_memory_equal(a->order, b->order, a->tri_count * sizeof *a->order);
    assert_memory_equal(a->tris, b->tris, a->tri_count * sizeof *a->tris);
    assert_int_equal(a->wide_count, b->wide_count);
    assert_int_equal(a->wide_depth, b->wide_depth);
    assert_int_equal(a->leaf_slots, b->leaf_slots);
    assert_memory_equal(a->wide, b->wide, (a->wide_count + a->leaf_slots) * sizeof *a->wide);
}

/* Triangles in the plane z = 0, each z coordinate +0 or -0 at random: the
 * boxes' z bounds are zeros of either sign, which keep the sign one pass
 * would give them only if bounds gathered in pieces are combined in input
 * order (min and max keep the later of equal values). */
static float *signed_zeros(rng *r, uint32_t n)
{
    float *p = soup(r, n, 0.02f);
    for (uint32_t i = 0; i < 3 * n; ++i)
        p[3 * i + 2] = rng_u32(r) & 1u ? 0.0f : -0.0f;
    return p;
}

/* The tree is the same whatever the thread count (st_bvh_build_threads):
 * 1, 2, 3, 7 and 16 threads, on scenes of both builders (below and above
 * the cluster grid's threshold; below it, one thread is build_node alone,
 * more share out its subtrees), an unbalanced one (a long chain at the
 * top), with many equal centroids (one grid cell) and with zeros of both
 * signs; and st_bvh_build's own choice. The one-thread build is also
 * checked against the definitions. */
static void build_same_tree_whatever_the_threads(void **state)
{
    (void)state;
    rng r = {31};
    const uint32_t sizes[5] = {120, 3000, 70000, 70000, 70000};
    for (int k = 0; k < 5; ++k) {
        uint32_t n = sizes[k];
        float *p = k == 0 ? geometric(n) : k == 1 ? soup(&r, n, 0.05f) : k == 2 ? soup(&r, n, 0.02f)
                 : k == 3 ? coincident(&r, n) : signed_zeros(&r, n);
        st_bvh *one = NULL, *other = NULL;
        st_error err = {0};
        assert_int_equal(st_bvh_build_threads(p, n, 1, &one, &err), ST_OK);
        check_structure(one, p, n);
        const unsigned threads[5] = {2, 3, 7, ST_BVH_MAX_THREADS, 0};
        for (int t = 0; t < 5; ++t) {
            assert_int_equal(st_bvh_build_threads(p, n, threads[t], &other, &err), ST_OK);
            assert_same_tree(one, other);
            st_bvh_destroy(other);
        }
        assert_int_equal(st_bvh_build(p, n, &other, &err), ST_OK);
        assert_same_tree(one, other);
        st_bvh_destroy(other);
        st_bvh_destroy(one);
        free(p);
    }
}

/* st_bvh_set_sides = its definition: each triangle's st_triangle.v0[3]
 * from its material's ST_MAT_DOUBLE_SIDED flag, then the leaves repacked
 * (st_bvh_pack_leaves); every array equal, with materials of both kinds
 * (and a second call turning every triangle back two-sided). */
static void set_sides_equals_marking_and_repacking(void **state)
{
    (void)state;
    rng r = {32};
    const uint32_t n = 70000;
    float *p = soup(&r, n, 0.02f);
    uint32_t *tri_material = malloc(n * sizeof *tri_material);
    assert_non_null(tri_material);
    st_material materials[3];
    memset(materials, 0, sizeof materials);
    materials[1].flags = ST_MAT_DOUBLE_SIDED;
    for (uint32_t i = 0; i < n; ++i)
        tri_material[i] = rng_u32(&r) % 3u;
    st_bvh *got = NULL, *want = NULL;
    st_error err = {0};
    assert_int_equal(st_bvh_build(p, n, &got, &err), ST_OK);
    assert_int_equal(st_bvh_build(p, n, &want, &err), ST_OK);
    for (int pass = 0; pass < 2; ++pass) {
        st_bvh_set_sides(got, tri_material, materials);
        uint32_t one_sided = 0;
        for (uint32_t i = 0; i < n; ++i) {
            int two = (materials[tri_material[want->order[i]]].flags & ST_MAT_DOUBLE_SIDED) != 0;
            want->tris[i].v0[3] = two ? 0.0f : ST_TRI_ONE_SIDED;
            one_sided += !two;
        }
        st_bvh_pack_leaves(want);
        assert_true(pass == 1 ? one_sided == 0 : one_sided > n / 2 && one_sided < n);
        assert_same_tree(got, want);
        for (int m = 0; m < 3; ++m)
            materials[m].flags = ST_MAT_DOUBLE_SIDED;
    }
    st_bvh_destroy(got);
    st_bvh_destroy(want);
    free(tri_material);
    free(p);
}

/* 1M random triangles: structure checked; speed printed as a TAP comment. */
static void build_million_triangles_structure(void **state)
{
    (void)state;
    const uint32_t n = 1000000;
    rng r = {12};
    float *p = soup(&r, n, 0.01f);
    st_bvh *bvh = NULL;
    st_error err = {0};
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    assert_int_equal(st_bvh_build(p, n, &bvh, &err), ST_OK);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double s = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    print_message("# bvh build: %u triangles in %.3f s = %.2f M triangles/s (%u nodes, depth %u)\n", n, s,
                  n / s / 1e6, bvh->node_count, bvh->depth);
    check_structure(bvh, p, n);
    assert_int_equal(check_layout(bvh), 0x1e); /* blocks of 1, 2, 3 and 4 triangles */
    st_bvh_destroy(bvh);
    free(p);
}

/* Coordinates near 1e36: box areas and Moller-Trumbore's products overflow
 * to infinity, so the SAH finds no finite cost and the builder falls back to
 * median splits; the tree must still be valid and agree with brute force. */
static void build_overflowing_areas_keeps_structure(void **state)
{
    (void)state;
    const uint32_t sizes[2] = {3000, 70000}; /* below and above the cluster grid's threshold */
    for (int k = 0; k < 2; ++k) {
        rng r = {20u + (uint64_t)k};
        float *p = soup(&r, sizes[k], 0.05f);
        for (uint32_t i = 0; i < 9 * sizes[k]; ++i)
            p[i] *= 1e36f;
        check_scene(p, sizes[k], 200, 22);
        free(p);
    }
}

/* ---- tests: the ray/triangle test against an independent construction --------- */

/* A ray aimed at the point with barycentrics (u, v) from distance t along d
 * must report that t, u and v (tolerance 1e-4 relative: the construction
 * rounds); points with u < 0, v < 0 or u + v > 1 by a margin are missed,
 * as are hits behind the origin and beyond tmax; back faces are hit. */
static void triangle_hit_matches_barycentric_construction(void **state)
{
    (void)state;
    rng r = {13};
    for (int k = 0; k < 20000; ++k) {
        st_triangle tri;
        memset(&tri, 0, sizeof tri);
        for (int a = 0; a < 3; ++a) {
            tri.v0[a] = rng_range(&r, -1, 1);
            tri.e1[a] = rng_range(&r, -1, 1);
            tri.e2[a] = rng_range(&r, -1, 1);
        }
        float u = rng_range(&r, 0.01f, 0.98f), v = rng_range(&r, 0.01f, 0.99f - u), t = rng_range(&r, 0.5f, 2.0f);
        st_ray ray;
        float n[3] = {tri.e1[1] * tri.e2[2] - tri.e1[2] * tri.e2[1], tri.e1[2] * tri.e2[0] - tri.e1[0] * tri.e2[2],
                      tri.e1[0] * tri.e2[1] - tri.e1[1] * tri.e2[0]};
        float sign = rng_u32(&r) & 1 ? 1.0f : -1.0f; /* front or back face */
        float dn = 0;
        for (int a = 0; a < 3; ++a) {
            ray.d[a] = sign * n[a] + rng_range(&r, -0.3f, 0.3f);
            dn += ray.d[a] * n[a];
        }
        if (fabsf(dn) < 0.05f * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]))
            continue; /* nearly parallel: ill-conditioned, skip */
        for (int a = 0; a < 3; ++a)
            ray.o[a] = tri.v0[a] + u * tri.e1[a] + v * tri.e2[a] - t * ray.d[a];
        ray.tmax = INFINITY;
        st_hit hit = {INFINITY, 0, 0, ST_NO_HIT};
        assert_true(st_intersect_triangle(&tri, &ray, 7, &hit));
        assert_int_equal(hit.prim, 7);
        assert_true(fabsf(hit.t - t) <= 1e-4f * t);
        assert_true(fabsf(hit.u - u) <= 1e-4f);
        assert_true(fabsf(hit.v - v) <= 1e-4f);
        st_hit miss = {t * 0.999f, 0, 0, ST_NO_HIT}; /* tmax before the hit */
        assert_false(st_intersect_triangle(&tri, &ray, 7, &miss));
        st_ray behind = ray; /* origin past the triangle: t < 0 */
        for (int a = 0; a < 3; ++a)
            behind.o[a] = ray.o[a] + 2.0f * t * ray.d[a];
        miss.t = INFINITY;
        assert_false(st_intersect_triangle(&tri, &behind, 7, &miss));
        st_ray outside = ray; /* aimed at u + v = 1.2 */
        for (int a = 0; a < 3; ++a)
            outside.o[a] = tri.v0[a] + (u + 0.6f) * tri.e1[a] + (v + 0.6f) * tri.e2[a] - t * ray.d[a];
        assert_false(st_intersect_triangle(&tri, &outside, 7, &miss));
        for (int a = 0; a < 3; ++a) /* aimed at u = -0.1 */
            outside.o[a] = tri.v0[a] - 0.1f * tri.e1[a] + v * tri.e2[a] - t * ray.d[a];
        assert_false(st_intersect_triangle(&tri, &outside, 7, &miss));
        assert_int_equal(miss.prim, ST_NO_HIT);
    }
}

/* t = 0 exactly (origin on the triangle) is not a hit: t > 0 strictly. */
static void triangle_hit_excludes_t_zero(void **state)
{
    (void)state;
    st_triangle tri = {{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}};
    st_ray ray = {{0.25f, 0.25f, 0.0f}, INFINITY, {0, 0, 1}, 0.0f};
    st_hit hit = {INFINITY, 0, 0, ST_NO_HIT};
    assert_false(st_intersect_triangle(&tri, &ray, 0, &hit));
    ray.o[2] = -1.0f;
    assert_true(st_intersect_triangle(&tri, &ray, 0, &hit));
    assert_true(hit.t == 1.0f && hit.u == 0.25f && hit.v == 0.25f);
    st_triangle one_sided = tri; /* e1 x e2 = +z: its front faces +z */
    one_sided.v0[3] = ST_TRI_ONE_SIDED;
    hit.t = INFINITY;
    assert_false(st_intersect_triangle(&one_sided, &ray, 0, &hit)); /* from behind (-z) */
    st_ray front = {{0.25f, 0.25f, 1.0f}, INFINITY, {0, 0, -1}, 0.0f};
    assert_true(st_intersect_triangle(&one_sided, &front, 0, &hit));
    assert_true(hit.t == 1.0f);
    st_triangle degenerate = {{0, 0, 0, 0}, {1, 0, 0, 0}, {2, 0, 0, 0}};
    hit.t = INFINITY;
    hit.prim = ST_NO_HIT;
    assert_false(st_intersect_triangle(&degenerate, &ray, 0, &hit));
}

/* ---- tests: errors -------------------------------------------------------------- */

static void build_rejects_missing_output_and_positions(void **state)
{
    (void)state;
    st_error err = {0};
    st_bvh *bvh = (st_bvh *)&err;
    float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    assert_int_equal(st_bvh_build(tri, 1, NULL, &err), ST_ERR_USAGE);
    assert_int_equal(err.status, ST_ERR_USAGE);
    st_error_clear(&err);
    assert_int_equal(st_bvh_build(NULL, 3, &bvh, &err), ST_ERR_USAGE);
    assert_null(bvh);
    assert_non_null(strstr(err.msg, "3 triangles"));
    st_bvh_destroy(NULL); /* harmless */
}

static void build_rejects_non_finite_coordinates(void **state)
{
    (void)state;
    rng r = {14};
    const float bad[3] = {NAN, INFINITY, -INFINITY};
    for (int k = 0; k < 3; ++k) {
        float *p = soup(&r, 50, 0.1f);
        p[9 * 37 + 4] = bad[k];
        st_error err = {0};
        st_bvh *bvh = (st_bvh *)&err;
        assert_int_equal(st_bvh_build(p, 50, &bvh, &err), ST_ERR_FORMAT);
        assert_null(bvh);
        assert_non_null(strstr(err.msg, "triangle 37"));
        free(p);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(closest_equals_brute_force_1),
        cmocka_unit_test(closest_equals_brute_force_2),
        cmocka_unit_test(closest_equals_brute_force_100),
        cmocka_unit_test(closest_equals_brute_force_10000),
        cmocka_unit_test(closest_equals_brute_force_one_sided),
        cmocka_unit_test(closest_equals_brute_force_100000),
        cmocka_unit_test(closest_equals_brute_force_coincident_centroids),
        cmocka_unit_test(closest_equals_brute_force_flat_axis_aligned),
        cmocka_unit_test(closest_equals_brute_force_duplicates),
        cmocka_unit_test(closest_equals_brute_force_rays_in_box_planes),
        cmocka_unit_test(closest_equals_brute_force_unbalanced_geometric),
        cmocka_unit_test(collapse_keeps_stack_bound_on_a_deep_chain),
        cmocka_unit_test(collapse_has_least_area),
        cmocka_unit_test(build_empty_scene_has_no_hits),
        cmocka_unit_test(build_leaves_hold_at_most_four_and_order_is_permutation),
        cmocka_unit_test(build_is_deterministic),
        cmocka_unit_test(build_same_tree_whatever_the_threads),
        cmocka_unit_test(set_sides_equals_marking_and_repacking),
        cmocka_unit_test(build_million_triangles_structure),
        cmocka_unit_test(build_overflowing_areas_keeps_structure),
        cmocka_unit_test(triangle_hit_matches_barycentric_construction),
        cmocka_unit_test(triangle_hit_excludes_t_zero),
        cmocka_unit_test(build_rejects_missing_output_and_positions),
        cmocka_unit_test(build_rejects_non_finite_coordinates),
    };
    return cmocka_run_group_tests_name("bvh", tests, NULL, NULL);
}
