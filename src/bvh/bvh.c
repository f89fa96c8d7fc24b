/* bvh.c — binned-SAH bounding volume hierarchy over triangles, built on the
 * host and flattened depth first into st_bvh_node (include/st_bvh.h lists the
 * guarantees of a built tree; kernels/geom/trace.h traverses it).
 *
 * Cost model, the surface area heuristic (MacDonald & Booth 1990; Wald,
 * "On fast Construction of SAH-based Bounding Volume Hierarchies", IEEE
 * Symposium on Interactive Ray Tracing 2007):
 *   C_split = C_trav + C_isect (N_L A(L) + N_R A(R)) / A(node);
 * the sweeps below choose the split of least N_L A(L) + N_R A(R). A leaf
 * holds at most LEAF_MAX triangles, which the kernels test together in one
 * vector test (trace.h, st_leaf_test), so C_leaf = C_isect whatever its
 * count (Embree's SAH counts leaves in such blocks too), less than the
 * C_trav = 1.5 C_isect of any split: every node of at most LEAF_MAX
 * triangles is a leaf, larger ones are split. Counting C_isect per triangle,
 * as the scalar test did, left about half again as many leaves with fewer
 * triangles each on a large mesh, and its rays were slower: each leaf costs
 * a node visit, and the block's triangles are tested together anyway.
 *
 * Three builders share the work, from the top down:
 *   - scenes of GRID_MIN_TRIS triangles or more get their top levels from a
 *     grid of clusters (HLBVH's way, see build_clustered): two passes over the
 *     input instead of a binning and a partitioning pass per level;
 *   - nodes of more than SMALL_MAX triangles: binned SAH in Wald's manner,
 *     BIN_COUNT bins over the centroid bounds along their widest axis (as
 *     pbrt does), children's bounds and centroid bounds taken from the bins,
 *     then a branch-free in-place partition;
 *   - subtrees of up to SMALL_MAX triangles: the full SAH sweep over the
 *     centroid order (small_tree), cheaper and better than bins at that size.
 * Centroids coincident on every axis fall back to an object-median split.
 *
 * Threads (st_bvh_build_threads): the passes over the input run in shares,
 * the subtrees below the top as tasks, each piece of work with its place in
 * the output fixed before it runs (see the clustered build's phases), so
 * the tree is the same, byte for byte, whatever the thread count.
 *
 * Depth invariant: a node at depth d (root = 1) holding n triangles satisfies
 *   d + levels(n) <= ST_BVH_MAX_DEPTH,  levels(n) = ceil(log2(ceil(n / 4))),
 * the levels that object-median splits need to reach leaves of <= 4. It holds
 * at the root for any n < 2^30 (levels < 29). A median split keeps it
 * (levels(ceil(n/2)) = levels(n) - 1 for n > 4); a SAH split that would break
 * it for a child is replaced by a median split. So the build recurses at most
 * ST_BVH_MAX_DEPTH deep and the traversal stack never overflows.
 *
 * Boxes are the exact bounds of their triangles (min and max of vertex
 * coordinates: no rounding). That a Moller-Trumbore hit which rounding places
 * a hair outside its triangle is still found is the traversal's business:
 * trace.h widens the slab interval relative to t. tests/unit/test_bvh.c compares
 * the traversal with a brute-force loop over the same triangle test, bit for
 * bit.
 *
 * Memory: the triangle references (32 bytes) and the subtrees' arena live in
 * the memory of the wide tree, which is written after them (build_tree);
 * the node array is allocated at its bound 2N - 1 and shrunk at the end; the
 * grid, when used, takes a few MB.
 * The per-triangle work runs on 4-wide float vectors (SSE2 where available,
 * plain C otherwise, with the same results). */
#define _DEFAULT_SOURCE /* madvise(2)'s MADV_HUGEPAGE */
#include "st_bvh.h"

#include "trace.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#define LEAF_MAX ((st_u32)ST_LEAF_MAX)
#define BIN_COUNT 16u
#define MAX_TRIANGLES 0x3fffffffu
#define SMALL_MAX 32u

/* ---- 4-wide floats ------------------------------------------------------- */

#if defined(__SSE2__) && !defined(ST_BVH_NO_SIMD)
#include <emmintrin.h>
typedef __m128 v4;
static inline v4 v4_load(const float f[4]) { return _mm_load_ps(f); }
static inline void v4_store(float f[4], v4 a) { _mm_storeu_ps(f, a); }
static inline v4 v4_splat(float x) { return _mm_set1_ps(x); }
static inline v4 v4_add(v4 a, v4 b) { return _mm_add_ps(a, b); }
static inline v4 v4_sub(v4 a, v4 b) { return _mm_sub_ps(a, b); }
/* minps/maxps: a < b ? a : b and a > b ? a : b per lane. */
static inline v4 v4_min(v4 a, v4 b) { return _mm_min_ps(a, b); }
static inline v4 v4_max(v4 a, v4 b) { return _mm_max_ps(a, b); }
#else
typedef struct v4 {
    float f[4];
} v4;
static inline v4 v4_load(const float f[4]) { v4 r; memcpy(r.f, f, sizeof r.f); return r; }
static inline void v4_store(float f[4], v4 a) { memcpy(f, a.f, sizeof a.f); }
static inline v4 v4_splat(float x) { return (v4){{x, x, x, x}}; }
#define V4_LANES(expr)                                                                         \
    v4 r;                                                                                      \
    for (int i = 0; i < 4; ++i)                                                                \
        r.f[i] = (expr);                                                                       \
    return r
static inline v4 v4_add(v4 a, v4 b) { V4_LANES(a.f[i] + b.f[i]); }
static inline v4 v4_sub(v4 a, v4 b) { V4_LANES(a.f[i] - b.f[i]); }
static inline v4 v4_min(v4 a, v4 b) { V4_LANES(a.f[i] < b.f[i] ? a.f[i] : b.f[i]); }
static inline v4 v4_max(v4 a, v4 b) { V4_LANES(a.f[i] > b.f[i] ? a.f[i] : b.f[i]); }
#undef V4_LANES
#endif

static inline float v4_lane(v4 a, st_u32 i)
{
    float f[4];
    v4_store(f, a);
    return f[i];
}

/* ---- boxes and triangle references ------------------------------------------ */

/* Boxes use lanes x, y, z; the fourth lane carries whatever it picks up. */
typedef struct box {
    v4 lo, hi;
} box;

/* A triangle's bounds. lo[3] carries its input index as float bits with bit
 * 30 set (so MAX_TRIANGLES < 2^30): a normal float, an infinity or a NaN but
 * never a denormal, which could slow the vector arithmetic the lane goes
 * through unused. hi[3] is 0. The doubled centroid lo + hi stands for the
 * centroid everywhere in the build (one add, no multiply). */
typedef struct ref {
    _Alignas(16) float lo[4];
    float hi[4];
} ref;

static inline box box_empty(void) { return (box){v4_splat(FLT_MAX), v4_splat(-FLT_MAX)}; }

static inline void box_grow(box *b, const box *c)
{
    b->lo = v4_min(b->lo, c->lo);
    b->hi = v4_max(b->hi, c->hi);
}

static inline void box_grow_point(box *b, v4 p)
{
    b->lo = v4_min(b->lo, p);
    b->hi = v4_max(b->hi, p);
}

/* Half the surface area, (dx dy + dy dz) + dz dx (only ratios matter). */
static inline float box_area(const box *b)
{
#if defined(__SSE2__) && !defined(ST_BVH_NO_SIMD)
    __m128 d = _mm_sub_ps(b->hi, b->lo);
    __m128 p = _mm_mul_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(3, 0, 2, 1)));
    __m128 sum = _mm_add_ss(_mm_add_ss(p, _mm_shuffle_ps(p, p, 1)), _mm_movehl_ps(p, p));
    return _mm_cvtss_f32(sum);
#else
    float d[4];
    v4_store(d, v4_sub(b->hi, b->lo));
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
#endif
}

static st_u32 box_widest_axis(const box *b)
{
    float d[4];
    v4_store(d, v4_sub(b->hi, b->lo));
    return d[0] >= d[1] && d[0] >= d[2] ? 0u : d[1] >= d[2] ? 1u : 2u;
}

static inline box ref_box(const ref *r) { return (box){v4_load(r->lo), v4_load(r->hi)}; }
static inline float ref_key(const ref *r, st_u32 axis) { return r->lo[axis] + r->hi[axis]; }

static inline void ref_set(ref *r, const float lo[3], const float hi[3], st_u32 id)
{
    st_u32 bits = id | 0x40000000u;
    memcpy(r->lo, lo, 3 * sizeof *lo);
    memcpy(&r->lo[3], &bits, sizeof bits);
    memcpy(r->hi, hi, 3 * sizeof *hi);
    r->hi[3] = 0.0f;
}

static inline st_u32 ref_id(const ref *r)
{
    st_u32 bits;
    memcpy(&bits, &r->lo[3], sizeof bits);
    return bits & 0x3fffffffu;
}

static inline void swap_refs(ref *refs, st_u32 i, st_u32 j)
{
    ref t = refs[i];
    refs[i] = refs[j];
    refs[j] = t;
}

/* Bounds and centroid bounds of refs [0, n). */
static void bounds_of(const ref *refs, st_u32 n, box *b, box *cb)
{
    *b = box_empty();
    *cb = box_empty();
    for (st_u32 i = 0; i < n; ++i) {
        box r = ref_box(&refs[i]);
        box_grow(b, &r);
        box_grow_point(cb, v4_add(r.lo, r.hi));
    }
}

/* A split into children [0, left_count) and [left_count, n), lower
 * coordinates on `axis` first: their bounds and centroid bounds, and
 * cost = N_L A(L) + N_R A(R). */
typedef struct split {
    st_u32 axis, left_count;
    float cost;
    box left, right, left_cb, right_cb;
} split;

/* ---- binned SAH (nodes of more than SMALL_MAX triangles) ------------------------ */

/* The bins lie along the widest axis of the centroid bounds, as in pbrt
 * (Pharr, Jakob & Humphreys, PBR 3rd ed. §4.3.2): evaluating the other two
 * axes would triple the binning work for a few percent of SAH cost. Bin of a
 * doubled centroid c: x = (c - cmin) * scale with scale = BIN_COUNT / extent,
 * bin = trunc(x) clamped to the last bin (NaN, from an infinite extent, goes
 * there too). Binning and partitioning use the same function, so they agree
 * on every triangle. */
typedef struct binning {
    st_u32 axis;
    float cmin, scale;
} binning;

static inline st_u32 bin_index(const binning *m, const ref *r)
{
    float x = (ref_key(r, m->axis) - m->cmin) * m->scale;
    x = x < (float)(BIN_COUNT - 1u) ? x : (float)(BIN_COUNT - 1u);
    return (st_u32)(int)x;
}

/* Triangle bounds, centroid bounds and count of one bin: the sweep takes the
 * children's boxes and centroid boxes from them, so no pass over the
 * children is needed before they are binned in turn. */
typedef struct bin {
    box b, c;
    st_u32 n;
} bin;

static void bins_clear(bin *bins)
{
    for (st_u32 k = 0; k < BIN_COUNT; ++k) {
        bins[k].b = box_empty();
        bins[k].c = box_empty();
        bins[k].n = 0;
    }
}

static inline void bins_add(bin *bins, const binning *m, const ref *r)
{
    bin *b = &bins[bin_index(m, r)];
    box rb = ref_box(r);
    box_grow(&b->b, &rb);
    box_grow_point(&b->c, v4_add(rb.lo, rb.hi));
    b->n++;
}

/* In large nodes, even and odd triangles go into separate bin sets, merged
 * at the end, so that runs of triangles falling into one bin do not
 * serialise on store-to-load latency; small nodes skip the second set's
 * fixed cost. */
#define BIN_TWO_SETS_MIN 512u
static void bin_refs(const ref *refs, st_u32 n, const binning *m, bin *bins)
{
    st_u32 i = 0;
    bins_clear(bins);
    if (n >= BIN_TWO_SETS_MIN) {
        bin odd[BIN_COUNT];
        bins_clear(odd);
        for (; i + 1u < n; i += 2u) {
            bins_add(bins, m, &refs[i]);
            bins_add(odd, m, &refs[i + 1u]);
        }
        for (st_u32 k = 0; k < BIN_COUNT; ++k) {
            box_grow(&bins[k].b, &odd[k].b);
            box_grow(&bins[k].c, &odd[k].c);
            bins[k].n += odd[k].n;
        }
    }
    for (; i < n; ++i)
        bins_add(bins, m, &refs[i]);
}

/* Finds the cheapest bin boundary, N_L A(L) + N_R A(R); returns it (0 for
 * none: every triangle in one bin, or areas overflowing). */
static st_u32 sweep_bins(const bin *bins, float *best_cost)
{
    float right_cost[BIN_COUNT];
    box acc = box_empty();
    st_u32 count = 0, best = 0;
    for (st_u32 k = BIN_COUNT - 1u; k > 0u; --k) {
        box_grow(&acc, &bins[k].b);
        count += bins[k].n;
        right_cost[k] = count ? (float)count * box_area(&acc) : INFINITY;
    }
    acc = box_empty();
    count = 0;
    *best_cost = INFINITY;
    for (st_u32 k = 1; k < BIN_COUNT; ++k) {
        box_grow(&acc, &bins[k - 1u].b);
        count += bins[k - 1u].n;
        float cost = count ? (float)count * box_area(&acc) + right_cost[k] : INFINITY;
        if (cost < *best_cost) {
            *best_cost = cost;
            best = k;
        }
    }
    return best;
}

/* Branch-free partition (Lomuto's scheme: every element is swapped with the
 * first right-hand one), as the sides of a split are unpredictable. */
static st_u32 partition_bins(ref *refs, st_u32 n, const binning *m, st_u32 split_bin)
{
    st_u32 p = 0;
    for (st_u32 i = 0; i < n; ++i) {
        ref r = refs[i];
        st_u32 left = bin_index(m, &r) < split_bin;
        refs[i] = refs[p];
        refs[p] = r;
        p += left;
    }
    return p;
}

/* Binned SAH split of a large node with centroid bounds cb, partitioned;
 * returns 0 when there is none (no centroid extent, areas overflowing). */
static int split_binned(ref *refs, st_u32 n, const box *cb, split *s)
{
    bin bins[BIN_COUNT];
    float lo[4], hi[4];
    binning m;
    m.axis = box_widest_axis(cb);
    v4_store(lo, cb->lo);
    v4_store(hi, cb->hi);
    float extent = hi[m.axis] - lo[m.axis];
    m.cmin = lo[m.axis];
    m.scale = (float)BIN_COUNT / extent;
    if (!(extent > 0.0f && m.scale <= FLT_MAX))
        return 0;
    bin_refs(refs, n, &m, bins);
    st_u32 k = sweep_bins(bins, &s->cost);
    if (k == 0u)
        return 0;
    s->axis = m.axis;
    s->left = s->right = s->left_cb = s->right_cb = box_empty();
    for (st_u32 j = 0; j < BIN_COUNT; ++j) {
        box_grow(j < k ? &s->left : &s->right, &bins[j].b);
        box_grow(j < k ? &s->left_cb : &s->right_cb, &bins[j].c);
    }
    s->left_count = partition_bins(refs, n, &m, k);
    return 1;
}

/* ---- median split (fallback) ----------------------------------------------- */

/* Rearranges [0, n) so that element k has the centroid it would have if
 * sorted along axis, smaller ones before it, larger after (Hoare's FIND, as
 * in Wirth, "Algorithms + Data Structures = Programs", 1976, §2.3.4). Keys
 * are never NaN (finite input), so the pivot bounds both scans. */
static void select_nth(ref *refs, st_u32 n, st_u32 k, st_u32 axis)
{
    st_i64 lo = 0, hi = (st_i64)n - 1;
    while (lo < hi) {
        float pivot = ref_key(&refs[lo + (hi - lo) / 2], axis);
        st_i64 i = lo, j = hi;
        while (i <= j) {
            while (ref_key(&refs[i], axis) < pivot)
                ++i;
            while (pivot < ref_key(&refs[j], axis))
                --j;
            if (i <= j)
                swap_refs(refs, (st_u32)i++, (st_u32)j--);
        }
        if ((st_i64)k <= j)
            hi = j;
        else if ((st_i64)k >= i)
            lo = i;
        else
            break;
    }
}

static void split_median(ref *refs, st_u32 n, const box *cb, split *s)
{
    s->axis = box_widest_axis(cb);
    s->left_count = n / 2u;
    select_nth(refs, n, s->left_count, s->axis);
    bounds_of(refs, s->left_count, &s->left, &s->left_cb);
    bounds_of(refs + s->left_count, n - s->left_count, &s->right, &s->right_cb);
}

/* ---- the tree -------------------------------------------------------------- */

typedef struct builder {
    ref *refs;          /* in BVH order once built */
    st_bvh_node *nodes;
    st_u32 node_count;
    st_u32 depth;
} builder;

static st_u32 median_levels(st_u32 n)
{
    st_u64 leaves = ((st_u64)n + LEAF_MAX - 1u) / LEAF_MAX;
    st_u32 levels = 0;
    while (((st_u64)1 << levels) < leaves)
        ++levels;
    return levels;
}

static void write_box(st_bvh_node *node, const box *b)
{
    float lo[4], hi[4];
    v4_store(lo, b->lo);
    v4_store(hi, b->hi);
    memcpy(node->bmin, lo, sizeof node->bmin);
    memcpy(node->bmax, hi, sizeof node->bmax);
}

/* ---- small subtrees (up to SMALL_MAX triangles): full-sweep SAH --------------- */

/* A subtree of at most SMALL_MAX triangles is built from a local copy, its
 * triangles named by 8-bit local indices. At each node they are sorted along
 * the widest centroid axis (insertion sort: a child mostly inherits its
 * parent's order) and every object split of that order is evaluated, the
 * full sweep of MacDonald & Booth ("Heuristics for ray tracing using space
 * subdivision", The Visual Computer 6(3), 1990): better than binning for few
 * triangles and, without per-node bins or moves of whole references, several
 * times cheaper; these nodes are most of the tree. Equal centroids are split
 * apart like any others, and the middle of the sorted order is the object
 * median the depth guard asks for. Leaves record their triangles in `out`;
 * the references are permuted once at the end. */
typedef struct small_tree {
    builder *b;
    st_u32 begin, cursor;
    box rb[SMALL_MAX];              /* triangle bounds */
    v4 c[SMALL_MAX];                /* doubled centroids */
    float key[3][SMALL_MAX];        /* the same, per axis */
    unsigned char perm[SMALL_MAX];  /* working order */
    unsigned char out[SMALL_MAX];   /* leaf order */
} small_tree;

static void sort_by_key(unsigned char *perm, st_u32 n, const float *key)
{
    for (st_u32 i = 1; i < n; ++i) {
        unsigned char v = perm[i];
        st_u32 j = i;
        for (; j > 0u && key[v] < key[perm[j - 1u]]; --j)
            perm[j] = perm[j - 1u];
        perm[j] = v;
    }
}

/* Sorts perm[0, n) along the widest centroid axis and sweeps it; returns
 * the best j (children: the first j and the rest) with its cost
 * N_L A(L) + N_R A(R) in *best (INFINITY if the areas overflow). */
static st_u32 small_sweep(small_tree *t, unsigned char *perm, st_u32 n, st_u32 *axis, float *best)
{
    float right_cost[SMALL_MAX];
    box cb = box_empty(), acc = box_empty();
    st_u32 best_j = n / 2u;
    for (st_u32 i = 0; i < n; ++i)
        box_grow_point(&cb, t->c[perm[i]]);
    *axis = box_widest_axis(&cb);
    sort_by_key(perm, n, t->key[*axis]);
    for (st_u32 j = n - 1u; j > 0u; --j) {
        box_grow(&acc, &t->rb[perm[j]]);
        right_cost[j] = (float)(n - j) * box_area(&acc);
    }
    acc = box_empty();
    *best = INFINITY;
    for (st_u32 j = 1; j < n; ++j) {
        box_grow(&acc, &t->rb[perm[j - 1u]]);
        float cost = (float)j * box_area(&acc) + right_cost[j];
        if (cost < *best) {
            *best = cost;
            best_j = j;
        }
    }
    return best_j;
}

static box small_bounds(const small_tree *t, const unsigned char *perm, st_u32 n)
{
    box b = box_empty();
    for (st_u32 i = 0; i < n; ++i)
        box_grow(&b, &t->rb[perm[i]]);
    return b;
}

static void small_node(small_tree *t, st_u32 lo, st_u32 hi, st_u32 depth, const box *bounds)
{
    builder *b = t->b;
    st_u32 n = hi - lo, index = b->node_count++, axis = 0, j = 0;
    st_bvh_node *node = &b->nodes[index];
    unsigned char *perm = t->perm + lo;
    float cost = INFINITY;
    write_box(node, bounds);
    if (depth > b->depth)
        b->depth = depth;
    if (n <= LEAF_MAX) {
        node->offset = t->begin + t->cursor;
        node->meta = n << 2;
        for (st_u32 k = 0; k < n; ++k)
            t->out[t->cursor++] = perm[k];
        return;
    }
    j = small_sweep(t, perm, n, &axis, &cost);
    if (depth + 1u + median_levels(j > n - j ? j : n - j) > ST_BVH_MAX_DEPTH)
        j = n / 2u;
    box left = small_bounds(t, perm, j), right = small_bounds(t, perm + j, n - j);
    node->meta = axis;
    small_node(t, lo, lo + j, depth + 1u, &left);
    b->nodes[index].offset = b->node_count;
    small_node(t, lo + j, hi, depth + 1u, &right);
}

static void small_subtree(builder *b, st_u32 begin, st_u32 n, st_u32 depth, const box *bounds)
{
    small_tree t;
    ref *refs = b->refs + begin, sorted[SMALL_MAX];
    t.b = b;
    t.begin = begin;
    t.cursor = 0;
    for (st_u32 i = 0; i < n; ++i) {
        float c[4];
        t.rb[i] = ref_box(&refs[i]);
        t.c[i] = v4_add(t.rb[i].lo, t.rb[i].hi);
        v4_store(c, t.c[i]);
        t.key[0][i] = c[0];
        t.key[1][i] = c[1];
        t.key[2][i] = c[2];
        t.perm[i] = (unsigned char)i;
    }
    small_node(&t, 0, n, depth, bounds);
    for (st_u32 i = 0; i < n; ++i)
        sorted[i] = refs[t.out[i]];
    memcpy(refs, sorted, n * sizeof *refs);
}

/* Builds the subtree of refs [begin, end), with bounds `bounds` and centroid
 * bounds `cb`, at depth `depth` into the next free node. Nodes of more than
 * SMALL_MAX (> LEAF_MAX) triangles are always split. */
static void build_node(builder *b, st_u32 begin, st_u32 end, st_u32 depth, const box *bounds, const box *cb)
{
    st_u32 n = end - begin;
    if (n <= SMALL_MAX) {
        small_subtree(b, begin, n, depth, bounds);
        return;
    }
    st_u32 index = b->node_count++;
    ref *refs = b->refs + begin;
    split s;
    write_box(&b->nodes[index], bounds);
    if (depth > b->depth)
        b->depth = depth;
    if (!split_binned(refs, n, cb, &s) ||
        depth + 1u + median_levels(s.left_count > n - s.left_count ? s.left_count : n - s.left_count) >
            ST_BVH_MAX_DEPTH)
        split_median(refs, n, cb, &s);
    b->nodes[index].meta = s.axis;
    build_node(b, begin, begin + s.left_count, depth + 1u, &s.left, &s.left_cb);
    b->nodes[index].offset = b->node_count;
    build_node(b, begin + s.left_count, end, depth + 1u, &s.right, &s.right_cb);
}

/* Share t of `threads` near-equal contiguous shares of [0, n). */
static void share(st_u32 n, unsigned t, unsigned threads, st_u32 *lo, st_u32 *hi)
{
    *lo = (st_u32)((st_u64)n * t / threads);
    *hi = (st_u32)((st_u64)n * (t + 1u) / threads);
}

/* Work handed out piece by piece: the next piece's index. */
static inline st_u32 take(atomic_uint *next) { return (st_u32)atomic_fetch_add(next, 1u); }

/* ---- input ------------------------------------------------------------------- */

static inline void tri_bounds(const float *p, float lo[3], float hi[3])
{
    for (int a = 0; a < 3; ++a) {
        float x = p[a], y = p[3 + a], z = p[6 + a];
        lo[a] = x < y ? (x < z ? x : z) : (y < z ? y : z);
        hi[a] = x > y ? (x > z ? x : z) : (y > z ? y : z);
    }
}

/* Triangles [lo, hi): their references into refs (in input order) and
 * their bounds and centroid bounds; returns the first triangle with a
 * non-finite coordinate, or hi. The bounds grow in locals: the threads'
 * *bounds lie side by side in one cache line (scan_job), and stores to
 * them on every triangle passed the line between the cores. */
static st_u32 scan_positions(const float *positions, st_u32 lo_i, st_u32 hi_i, ref *refs, box *bounds, box *cb)
{
    box b = box_empty(), c = box_empty();
    st_u32 i = lo_i;
    for (; i < hi_i; ++i) {
        const float *p = positions + (size_t)9 * i;
        float finite = 0.0f; /* x * 0 is 0 for finite x, NaN otherwise */
        for (int k = 0; k < 9; ++k)
            finite += p[k] * 0.0f;
        if (finite != 0.0f)
            break;
        float lo[4] = {0}, hi[4] = {0};
        tri_bounds(p, lo, hi);
        ref_set(&refs[i], lo, hi, i);
        box r = {v4_load(lo), v4_load(hi)};
        box_grow(&b, &r);
        box_grow_point(&c, v4_add(r.lo, r.hi));
    }
    *bounds = b;
    *cb = c;
    return i;
}

/* scan_positions over the threads' shares, combined in share order: the
 * same bounds as one pass (box_grow keeps the later of equal values, in
 * pieces as in one pass) and the same first bad triangle. */
typedef struct scan_job {
    const float *positions;
    ref *refs;
    st_u32 n;
    unsigned threads;
    box b[ST_BVH_MAX_THREADS], cb[ST_BVH_MAX_THREADS];
    st_u32 bad[ST_BVH_MAX_THREADS];
} scan_job;

static void scan_run(void *ctx, unsigned t)
{
    scan_job *j = ctx;
    st_u32 lo, hi;
    share(j->n, t, j->threads, &lo, &hi);
    st_u32 bad = scan_positions(j->positions, lo, hi, j->refs, &j->b[t], &j->cb[t]);
    j->bad[t] = bad < hi ? bad : j->n;
}

static st_u32 scan_parallel(const float *positions, st_u32 n, unsigned threads, ref *refs, box *bounds,
                            box *cb)
{
    scan_job j;
    j.positions = positions;
    j.refs = refs;
    j.n = n;
    j.threads = threads;
    st_bvh_parallel(threads, scan_run, &j);
    st_u32 bad = n;
    *bounds = box_empty();
    *cb = box_empty();
    for (unsigned t = 0; t < threads; ++t) {
        bad = j.bad[t] < bad ? j.bad[t] : bad;
        box_grow(bounds, &j.b[t]);
        box_grow(cb, &j.cb[t]);
    }
    return bad;
}

/* ---- the top levels of large scenes: a grid of clusters ------------------------ */

/* From GRID_MIN_TRIS triangles on, the top of the tree is built over clusters
 * rather than triangles, as HLBVH does (Pantaleoni & Luebke, "HLBVH:
 * Hierarchical LBVH Construction for Real-Time Ray Tracing of Dynamic
 * Geometry", HPG 2010; Garanzha, Pantaleoni & McAllister, "Simpler and Faster
 * HLBVH with Work Queues", HPG 2011, build their top levels with binned SAH
 * over grid cells). Triangles are counted into a uniform grid of at most
 * GRID_RES cells per axis over the centroid bounds; the non-empty cells are
 * the primitives of a binned SAH build (weighted by triangle count, over all
 * three axes: it is cheap at this scale), the plan, whose leaves are single
 * cells, or groups of cells holding at most PLAN_LEAF_TRIS triangles or
 * stopped by the depth guard. The triangles are then scattered so that every
 * plan node's triangles are contiguous, and each plan leaf is built over its
 * triangles by build_node. The top levels so cost three passes over the input
 * instead of a binning and a partitioning pass per level. */
#define GRID_MIN_TRIS 65536u
#define GRID_RES 32u
#define PLAN_LEAF_TRIS 64u

typedef struct cell {
    box b, cb;          /* bounds and centroid bounds of its triangles */
    st_u32 count, start;
} cell;

typedef struct cluster {
    box b;
    st_u32 cell, count;
} cluster;

/* A plan node: clusters [first, last) holding `tris` triangles at `depth`;
 * a leaf when right == 0, its triangles then at [start, start + tris), its
 * subtree built by tasks[task]. */
typedef struct plan {
    box b;
    st_u32 first, last, tris, start;
    st_u32 axis, left, right;
    st_u32 depth, task;
} plan;

typedef struct grid {
    float cmin[3], scale[3], last[3];
    st_u32 res[3];
    cell *cells;
    cluster *clusters;
    plan *plans;
    st_u32 cluster_count, plan_count;
} grid;

/* Resolution per axis proportional to the centroid extent (cells about
 * cubic), at most GRID_RES; an axis without extent gets one cell. */
static void grid_init(grid *g, const box *cb)
{
    float lo[4], hi[4], emax = 0.0f;
    v4_store(lo, cb->lo);
    v4_store(hi, cb->hi);
    for (int a = 0; a < 3; ++a)
        emax = hi[a] - lo[a] > emax ? hi[a] - lo[a] : emax;
    for (int a = 0; a < 3; ++a) {
        float extent = hi[a] - lo[a];
        float cells = emax > 0.0f ? ceilf((float)GRID_RES * (extent / emax)) : 1.0f;
        g->res[a] = cells >= 1.0f ? (cells <= (float)GRID_RES ? (st_u32)cells : GRID_RES) : 1u;
        g->cmin[a] = lo[a];
        g->scale[a] = extent > 0.0f && (float)g->res[a] / extent <= FLT_MAX ? (float)g->res[a] / extent : 0.0f;
        g->last[a] = (float)(g->res[a] - 1u);
    }
}

static inline st_u32 grid_cell(const grid *g, const float lo[3], const float hi[3])
{
    st_u32 k[3];
    for (int a = 0; a < 3; ++a) {
        float x = (lo[a] + hi[a] - g->cmin[a]) * g->scale[a];
        x = x < g->last[a] ? x : g->last[a];
        k[a] = (st_u32)(int)x;
    }
    return (k[0] * g->res[1] + k[1]) * g->res[2] + k[2];
}

/* Pass 1 over the references of triangles [lo, hi) (in input order): every
 * triangle's cell (into cell_of) and the count and bounds of every cell's
 * triangles among them (into cells). */
static void grid_count(const grid *g, cell *cells, const ref *input, st_u32 lo_i, st_u32 hi_i, st_u32 *cell_of)
{
    for (st_u32 i = lo_i; i < hi_i; ++i) {
        st_u32 id = grid_cell(g, input[i].lo, input[i].hi);
        cell *c = &cells[id];
        box r = ref_box(&input[i]);
        cell_of[i] = id;
        c->count++;
        box_grow(&c->b, &r);
        box_grow_point(&c->cb, v4_add(r.lo, r.hi));
    }
}

/* A plan split: clusters whose centroid bin on `axis` is below `split` go
 * left, bins as in binning. */
typedef struct plan_cut {
    st_u32 axis;
    float cmin, scale, split;
} plan_cut;

static inline float plan_bin(const plan_cut *m, const cluster *c)
{
    float x = (v4_lane(v4_add(c->b.lo, c->b.hi), m->axis) - m->cmin) * m->scale;
    x = x < (float)(BIN_COUNT - 1u) ? x : (float)(BIN_COUNT - 1u);
    return (float)(int)x;
}

/* The best binned SAH split of clusters [first, last) over the three axes;
 * returns 0 for none. */
static int plan_split(const grid *g, st_u32 first, st_u32 last, plan_cut *best)
{
    box cb = box_empty();
    float lo[4], hi[4], best_cost = INFINITY;
    for (st_u32 i = first; i < last; ++i)
        box_grow_point(&cb, v4_add(g->clusters[i].b.lo, g->clusters[i].b.hi));
    v4_store(lo, cb.lo);
    v4_store(hi, cb.hi);
    for (st_u32 a = 0; a < 3u; ++a) {
        plan_cut m = {a, lo[a], (float)BIN_COUNT / (hi[a] - lo[a]), 0.0f};
        bin bins[BIN_COUNT];
        float cost;
        if (!(hi[a] - lo[a] > 0.0f && m.scale <= FLT_MAX))
            continue;
        bins_clear(bins);
        for (st_u32 i = first; i < last; ++i) {
            bin *b = &bins[(st_u32)plan_bin(&m, &g->clusters[i])];
            box_grow(&b->b, &g->clusters[i].b);
            b->n += g->clusters[i].count;
        }
        st_u32 k = sweep_bins(bins, &cost);
        if (k != 0u && cost < best_cost) {
            best_cost = cost;
            *best = m;
            best->split = (float)k;
        }
    }
    return best_cost < INFINITY;
}

static st_u32 plan_partition(grid *g, st_u32 first, st_u32 last, const plan_cut *m)
{
    st_u32 p = first;
    for (st_u32 i = first; i < last; ++i) {
        cluster c = g->clusters[i];
        int left = plan_bin(m, &c) < m->split;
        g->clusters[i] = g->clusters[p];
        g->clusters[p] = c;
        p += (st_u32)left;
    }
    return p;
}

/* Builds the plan over clusters [first, last) at `depth`; returns its index. */
static st_u32 plan_build(grid *g, st_u32 first, st_u32 last, st_u32 depth)
{
    st_u32 index = g->plan_count++, tris = 0;
    box b = box_empty();
    plan_cut m;
    for (st_u32 i = first; i < last; ++i) {
        box_grow(&b, &g->clusters[i].b);
        tris += g->clusters[i].count;
    }
    g->plans[index] = (plan){b, first, last, tris, 0, 0, 0, 0, depth, 0};
    if (last - first < 2u || tris <= PLAN_LEAF_TRIS || !plan_split(g, first, last, &m))
        return index;
    st_u32 mid = plan_partition(g, first, last, &m), left_tris = 0;
    for (st_u32 i = first; i < mid; ++i)
        left_tris += g->clusters[i].count;
    st_u32 larger = left_tris > tris - left_tris ? left_tris : tris - left_tris;
    if (mid == first || mid == last || depth + 1u + median_levels(larger) > ST_BVH_MAX_DEPTH)
        return index;
    st_u32 left = plan_build(g, first, mid, depth + 1u);
    st_u32 right = plan_build(g, mid, last, depth + 1u);
    g->plans[index].axis = m.axis;
    g->plans[index].left = left;
    g->plans[index].right = right;
    return index;
}

/* A subtree below the plan, built by one thread: triangles [begin, end) at
 * `depth` with bounds and centroid bounds; built, `count` nodes (deepest
 * leaf at max_depth) at node `at` of the arena, and `base` the first of
 * them in the tree. */
typedef struct task {
    box bounds, cb;
    st_u32 begin, end, depth;
    st_u32 at, count, max_depth;
    st_u32 base;
} task;

/* Gives each plan leaf, in depth-first order, its range of triangles and
 * its task (*tasks counts them), and each cell its start within it. */
static st_u32 plan_layout(grid *g, st_u32 index, st_u32 cursor, task *tasks, st_u32 *task_count)
{
    plan *p = &g->plans[index];
    if (p->right != 0u) {
        cursor = plan_layout(g, p->left, cursor, tasks, task_count);
        return plan_layout(g, p->right, cursor, tasks, task_count);
    }
    task *x = &tasks[*task_count];
    p->task = (*task_count)++;
    p->start = cursor;
    x->bounds = p->b;
    x->cb = box_empty();
    x->begin = cursor;
    x->end = cursor + p->tris;
    x->depth = p->depth;
    x->count = 0;
    for (st_u32 i = p->first; i < p->last; ++i) {
        cell *c = &g->cells[g->clusters[i].cell];
        box_grow(&x->cb, &c->cb);
        c->start = cursor;
        cursor += c->count;
    }
    return cursor;
}

/* Pass 2 over triangles [lo, hi): each triangle's reference to the next
 * slot of its cell, cells[c].start. */
static void grid_scatter(cell *cells, const ref *input, st_u32 lo_i, st_u32 hi_i, const st_u32 *cell_of, ref *refs)
{
    for (st_u32 i = lo_i; i < hi_i; ++i)
        refs[cells[cell_of[i]].start++] = input[i];
}

/* The output arrays of a large scene are tens of MB, and the grid's cells
 * a few, each page of which the build is first to touch: at 4 KiB a page,
 * the faults cost about a quarter of the build. Asking for huge pages
 * (where the kernel leaves transparent huge pages to madvise) makes them a
 * few hundred. Only the whole 2 MiB pages inside an array are affected;
 * refusal changes nothing. */
#define HUGE_PAGE ((size_t)2 << 20)
static void *huge_pages(void *p, size_t bytes)
{
#if defined(MADV_HUGEPAGE)
    uintptr_t lo = ((uintptr_t)p + HUGE_PAGE - 1u) & ~(uintptr_t)(HUGE_PAGE - 1u);
    uintptr_t hi = ((uintptr_t)p + bytes) & ~(uintptr_t)(HUGE_PAGE - 1u);
    if (p && hi > lo)
        (void)madvise((void *)lo, hi - lo, MADV_HUGEPAGE);
#else
    (void)bytes;
#endif
    return p;
}

/* ---- the clustered build on threads -------------------------------------------- */

/* Every phase shares out work whose output has its place fixed in advance,
 * so the tree does not depend on the threads:
 *   - count: thread t counts share t of the triangles into its own grid,
 *     part[t] (part[0] is the grid's), then the parts are merged cell by
 *     cell in share order (bounds as one pass would find them, see
 *     scan_parallel), each part keeping in `start` how many of the cell's
 *     triangles the earlier shares hold;
 *   - the plan is built and laid out on one thread (a few thousand
 *     clusters); each cell's slots are then split between the shares in
 *     share order, so the scatter puts every triangle where one pass would;
 *   - subtrees: each plan leaf is a task, built by whichever thread takes it
 *     into that thread's buffer (reused from task to task), node offsets
 *     relative to its first node, then copied to the next free nodes of the
 *     arena shared by the threads (the wide tree's memory, which the
 *     collapse overwrites: no pages of its own); leaves name triangles,
 *     which are in place already;
 *   - stitch: one thread lays the plan's nodes and the tasks' subtrees out
 *     depth first, as one thread building them in turn would (each task's
 *     size is known now), then the threads copy the subtrees to their
 *     places, offsetting interior nodes' children by where they land. */
typedef struct cluster_job {
    grid *g;
    const float *positions;
    st_u32 n, cells;
    unsigned threads;
    cell *part[ST_BVH_MAX_THREADS];
    st_u32 *cell_of;            /* pass 1 to pass 2; then the output order */
    const ref *input;           /* the references in input order (scan_parallel's) */
    ref *refs;
    task *tasks;
    st_u32 task_count;
    st_bvh_node *arena;                      /* room for 2n - 1 nodes */
    st_bvh_node *local[ST_BVH_MAX_THREADS];  /* each thread's buffer */
    st_u32 local_cap[ST_BVH_MAX_THREADS];
    st_bvh_node *nodes;
    st_triangle *tris;
    atomic_uint next, arena_used;
} cluster_job;

static void count_run(void *ctx, unsigned t)
{
    cluster_job *j = ctx;
    st_u32 lo, hi;
    share(j->n, t, j->threads, &lo, &hi);
    for (st_u32 c = 0; c < j->cells; ++c)
        j->part[t][c] = (cell){box_empty(), box_empty(), 0, 0};
    grid_count(j->g, j->part[t], j->input, lo, hi, j->cell_of);
}

static void merge_run(void *ctx, unsigned t)
{
    cluster_job *j = ctx;
    st_u32 lo, hi;
    share(j->cells, t, j->threads, &lo, &hi);
    for (st_u32 c = lo; c < hi; ++c) {
        cell *sum = &j->part[0][c];
        st_u32 before = sum->count;
        sum->start = 0;
        for (unsigned p = 1; p < j->threads; ++p) {
            cell *x = &j->part[p][c];
            x->start = before;
            before += x->count;
            box_grow(&sum->b, &x->b);
            box_grow(&sum->cb, &x->cb);
        }
        sum->count = before;
    }
}

/* After plan_layout: the first slot of each share's triangles in a cell. */
static void offsets_run(void *ctx, unsigned t)
{
    cluster_job *j = ctx;
    st_u32 lo, hi;
    share(j->cells, t, j->threads, &lo, &hi);
    for (st_u32 c = lo; c < hi; ++c)
        for (unsigned p = 1; p < j->threads; ++p)
            j->part[p][c].start += j->part[0][c].start;
}

static void scatter_run(void *ctx, unsigned t)
{
    cluster_job *j = ctx;
    st_u32 lo, hi;
    share(j->n, t, j->threads, &lo, &hi);
    grid_scatter(j->part[t], j->input, lo, hi, j->cell_of, j->refs);
}

/* tris[i] = input triangle order[i] as (v0, v1 - v0, v2 - v0), i in
 * [lo, hi). The reads from positions are scattered over the input, so they
 * are prefetched a few triangles ahead. */
#define PREFETCH_AHEAD 16u
static void write_triangles(const float *positions, const st_u32 *order, st_u32 lo, st_u32 hi,
                            st_triangle *tris)
{
    for (st_u32 i = lo; i < hi; ++i) {
#if defined(__GNUC__)
        if (i + PREFETCH_AHEAD < hi)
            __builtin_prefetch(positions + (size_t)9 * order[i + PREFETCH_AHEAD]);
#endif
        const float *p = positions + (size_t)9 * order[i];
        st_triangle t;
        for (int a = 0; a < 3; ++a) {
            t.v0[a] = p[a];
            t.e1[a] = p[3 + a] - p[a];
            t.e2[a] = p[6 + a] - p[a];
        }
        t.v0[3] = t.e1[3] = t.e2[3] = 0.0f;
        memcpy(&tris[i], &t, sizeof t);
    }
}

/* Thread t's buffer, grown to at least `nodes` nodes; 0 if out of memory. */
static int local_room(cluster_job *j, unsigned t, st_u32 nodes)
{
    if (j->local_cap[t] >= nodes)
        return 1;
    nodes = nodes > 4096u ? nodes : 4096u;
    st_bvh_node *grown = realloc(j->local[t], (size_t)nodes * sizeof *grown);
    if (!grown)
        return 0;
    j->local[t] = grown;
    j->local_cap[t] = nodes;
    return 1;
}

/* The tasks this thread takes, each into its buffer (a subtree of m
 * triangles has at most 2m - 1 nodes) and then the arena; then, its
 * references final, its triangles' input indices into the output order and
 * the output triangles. A task left undone (count 0) is out of memory. */
static void subtree_run(void *ctx, unsigned t)
{
    cluster_job *j = ctx;
    for (st_u32 k; (k = take(&j->next)) < j->task_count;) {
        task *x = &j->tasks[k];
        if (!local_room(j, t, 2u * (x->end - x->begin) - 1u))
            continue;
        builder b = {j->refs, j->local[t], 0, 0};
        build_node(&b, x->begin, x->end, x->depth, &x->bounds, &x->cb);
        x->at = (st_u32)atomic_fetch_add(&j->arena_used, b.node_count);
        x->count = b.node_count;
        x->max_depth = b.depth;
        memcpy(j->arena + x->at, j->local[t], (size_t)b.node_count * sizeof *j->arena);
        for (st_u32 i = x->begin; i < x->end; ++i)
            j->cell_of[i] = ref_id(&j->refs[i]);
        write_triangles(j->positions, j->cell_of, x->begin, x->end, j->tris);
    }
}

/* Lays the plan out depth first from nodes[*cursor]: its interior nodes
 * written, each task given its base; returns the deepest leaf. */
static st_u32 plan_stitch(const grid *g, st_u32 index, st_bvh_node *nodes, st_u32 *cursor, task *tasks)
{
    const plan *p = &g->plans[index];
    if (p->right == 0u) {
        task *x = &tasks[p->task];
        x->base = *cursor;
        *cursor += x->count;
        return x->max_depth;
    }
    st_u32 node = (*cursor)++;
    write_box(&nodes[node], &p->b);
    nodes[node].meta = p->axis;
    st_u32 left = plan_stitch(g, p->left, nodes, cursor, tasks);
    nodes[node].offset = *cursor;
    st_u32 right = plan_stitch(g, p->right, nodes, cursor, tasks);
    return left > right ? left : right;
}

/* Each subtree to its place. */
static void place_run(void *ctx, unsigned t)
{
    cluster_job *j = ctx;
    (void)t;
    for (st_u32 k; (k = take(&j->next)) < j->task_count;) {
        const task *x = &j->tasks[k];
        const st_bvh_node *from = j->arena + x->at;
        st_bvh_node *to = j->nodes + x->base;
        memcpy(to, from, (size_t)x->count * sizeof *to);
        for (st_u32 i = 0; i < x->count; ++i)
            if ((to[i].meta >> 2) == 0u)
                to[i].offset += x->base;
    }
}

static void cluster_job_free(cluster_job *j)
{
    for (unsigned t = 0; t < j->threads; ++t) {
        free(j->local[t]);
        if (t > 0u)
            free(j->part[t]);
    }
    free(j->tasks);
}

/* The tasks under j's plan built on the threads and laid out with the
 * plan into bvh's nodes, and the output triangles written; 0 if out of
 * memory. */
static int run_tasks(cluster_job *j, st_bvh *bvh)
{
    st_u32 count = 0;
    st_bvh_parallel(j->threads, subtree_run, j);
    for (st_u32 k = 0; k < j->task_count; ++k)
        if (j->tasks[k].count == 0u)
            return 0;
    bvh->depth = plan_stitch(j->g, 0, bvh->nodes, &count, j->tasks);
    bvh->node_count = count;
    atomic_store(&j->next, 0u);
    st_bvh_parallel(j->threads, place_run, j);
    return 1;
}

/* Pass 1 on the threads: every triangle's cell and the merged cells. */
static void count_cells(cluster_job *j)
{
    grid *g = j->g;
    st_bvh_parallel(j->threads, count_run, j);
    st_bvh_parallel(j->threads, merge_run, j);
    for (st_u32 c = 0; c < j->cells; ++c)
        if (g->cells[c].count)
            g->clusters[g->cluster_count++] = (cluster){g->cells[c].b, c, g->cells[c].count};
}

/* The clustered build of n >= GRID_MIN_TRIS triangles into bvh (its order
 * array serves as scratch for the cells until it is written), with room for
 * n references and an arena of 2n - 1 nodes. */
static st_status build_clustered(st_bvh *bvh, const float *positions, const box *cb, unsigned threads,
                                 ref *refs, st_bvh_node *arena, st_error *err)
{
    st_u32 n = bvh->tri_count;
    grid g = {0};
    cluster_job j = {0};
    grid_init(&g, cb);
    j.cells = g.res[0] * g.res[1] * g.res[2];
    j.g = &g;
    j.positions = positions;
    j.n = n;
    j.threads = threads;
    j.cell_of = bvh->order;
    j.input = (const ref *)(const void *)arena; /* the arena's first use is after the scatter */
    j.refs = refs;
    j.nodes = bvh->nodes;
    j.tris = bvh->tris;
    j.arena = arena;
    g.cells = huge_pages(malloc(j.cells * sizeof *g.cells), j.cells * sizeof *g.cells);
    g.clusters = malloc(j.cells * sizeof *g.clusters);
    g.plans = malloc((2u * j.cells - 1u) * sizeof *g.plans);
    j.part[0] = g.cells;
    int ok = g.cells && g.clusters && g.plans;
    for (unsigned t = 1; t < threads; ++t)
        ok &= (j.part[t] = huge_pages(malloc(j.cells * sizeof *g.cells), j.cells * sizeof *g.cells)) != NULL;
    if (ok) {
        count_cells(&j);
        plan_build(&g, 0, g.cluster_count, 1);
        ok = (j.tasks = malloc(g.plan_count * sizeof *j.tasks)) != NULL;
    }
    if (ok) {
        plan_layout(&g, 0, 0, j.tasks, &j.task_count);
        st_bvh_parallel(threads, offsets_run, &j);
        st_bvh_parallel(threads, scatter_run, &j);
        ok = run_tasks(&j, bvh);
    }
    cluster_job_free(&j);
    free(g.cells);
    free(g.clusters);
    free(g.plans);
    if (!ok)
        return st_fail(err, ST_ERR_NOMEM, "bvh: out of memory for the cluster grid of %u triangles", n);
    return ST_OK;
}

/* ---- the direct build on threads ------------------------------------------------ */

/* Below GRID_MIN_TRIS triangles the tree is build_node's from the root. On
 * threads, its top is made by top_node on one thread down to nodes of at
 * most a sixteenth of the triangles (but more than SMALL_MAX), each of
 * those a task as the plan's leaves are above: the splits are build_node's,
 * so the tree does not depend on where the tasks begin. */
#define TOP_SHARE 16u

/* build_node's split of refs [begin, end) as plan node g->plans[plan_count]
 * (a leaf, right == 0, for a task); returns its index. */
static st_u32 top_node(cluster_job *j, st_u32 begin, st_u32 end, st_u32 depth, const box *bounds, const box *cb,
                       st_u32 cut)
{
    grid *g = j->g;
    st_u32 n = end - begin, index = g->plan_count++;
    g->plans[index] = (plan){*bounds, 0, 0, n, begin, 0, 0, 0, depth, 0};
    if (n <= cut) {
        task *x = &j->tasks[j->task_count];
        g->plans[index].task = j->task_count++;
        *x = (task){*bounds, *cb, begin, end, depth, 0, 0, 0, 0};
        return index;
    }
    split s;
    ref *refs = j->refs + begin;
    if (!split_binned(refs, n, cb, &s) ||
        depth + 1u + median_levels(s.left_count > n - s.left_count ? s.left_count : n - s.left_count) >
            ST_BVH_MAX_DEPTH)
        split_median(refs, n, cb, &s);
    g->plans[index].axis = s.axis;
    st_u32 left = top_node(j, begin, begin + s.left_count, depth + 1u, &s.left, &s.left_cb, cut);
    st_u32 right = top_node(j, begin + s.left_count, end, depth + 1u, &s.right, &s.right_cb, cut);
    g->plans[index].left = left;
    g->plans[index].right = right;
    return index;
}

static st_status build_direct(st_bvh *bvh, const float *positions, const box *bounds, const box *cb,
                              unsigned threads, ref *refs, st_bvh_node *arena, st_error *err)
{
    st_u32 n = bvh->tri_count, cut = n / TOP_SHARE > SMALL_MAX ? n / TOP_SHARE : SMALL_MAX;
    grid g = {0};
    cluster_job j = {0};
    j.g = &g;
    j.positions = positions;
    j.n = n;
    j.threads = threads;
    j.cell_of = bvh->order;
    j.refs = refs;
    j.nodes = bvh->nodes;
    j.tris = bvh->tris;
    j.arena = arena;
    /* the top's interior nodes hold more than `cut` triangles each, and
     * those at one depth are disjoint: at most n / cut + 1 a level, over at
     * most ST_BVH_MAX_DEPTH levels, and fewer than n in all; one more task */
    st_u64 levels = (st_u64)ST_BVH_MAX_DEPTH * (n / cut + 1u);
    st_u32 most = 2u * (levels < n ? (st_u32)levels : n) + 1u;
    g.plans = malloc((size_t)most * sizeof *g.plans);
    j.tasks = malloc((size_t)most * sizeof *j.tasks);
    int ok = g.plans && j.tasks;
    if (ok && threads == 1u) { /* build_node itself, as the threads' top and tasks do */
        builder b = {j.refs, bvh->nodes, 0, 0};
        build_node(&b, 0, n, 1, bounds, cb);
        for (st_u32 i = 0; i < n; ++i)
            bvh->order[i] = ref_id(&j.refs[i]);
        write_triangles(positions, bvh->order, 0, n, bvh->tris);
        bvh->node_count = b.node_count;
        bvh->depth = b.depth;
    } else if (ok) {
        top_node(&j, 0, n, 1, bounds, cb, cut);
        ok = run_tasks(&j, bvh);
    }
    cluster_job_free(&j);
    free(g.plans);
    if (!ok)
        return st_fail(err, ST_ERR_NOMEM, "bvh: out of memory for the build of %u triangles", n);
    return ST_OK;
}

/* The empty scene: one leaf whose inverted box no ray enters, holding one
 * zeroed (unhittable: det = 0) placeholder triangle. */
static void make_empty(st_bvh *bvh)
{
    st_bvh_node *root = &bvh->nodes[0];
    for (int a = 0; a < 3; ++a) {
        root->bmin[a] = FLT_MAX;
        root->bmax[a] = -FLT_MAX;
    }
    root->offset = 0;
    root->meta = 1u << 2;
    memset(bvh->tris, 0, sizeof *bvh->tris);
    bvh->order[0] = 0;
    bvh->node_count = 1;
    bvh->depth = 1;
}

/* The triangle references and then the subtrees' arena live in `room`, the
 * (16-byte aligned) memory of the wide tree, which is larger (at least two
 * wide nodes a triangle, 512 bytes, against 32 for a reference and 64 for
 * the arena's two nodes) and written after them: no extra allocation, and
 * the pages the build touches are the ones the output needs anyway. */
ST_STATIC_ASSERT(sizeof(ref) + 2u * sizeof(st_bvh_node) <= 2u * sizeof(st_bvh_wide_node) && sizeof(ref) % 16u == 0u,
                 "the references and the arena must fit in the wide tree's room");

static st_status build_tree(const float *positions, st_bvh *bvh, unsigned threads, void *room, st_error *err)
{
    st_u32 n = bvh->tri_count;
    ref *refs = room;
    st_bvh_node *arena = (st_bvh_node *)(void *)(refs + n);
    box bounds, cb;
    /* the references in input order: in place for the direct build, in the
     * arena (unused until the subtrees) for the clustered one to scatter */
    int clustered = n >= GRID_MIN_TRIS;
    st_u32 bad = scan_parallel(positions, n, threads, clustered ? (ref *)(void *)arena : refs, &bounds, &cb);
    if (bad < n)
        return st_fail(err, ST_ERR_FORMAT, "bvh: triangle %u has a non-finite vertex coordinate", bad);
    if (clustered) {
        st_status s = build_clustered(bvh, positions, &cb, threads, refs, arena, err);
        if (s != ST_OK)
            return s;
    } else {
        st_status s = build_direct(bvh, positions, &bounds, &cb, threads, refs, arena, err);
        if (s != ST_OK)
            return s;
    }
    if (bvh->depth > ST_BVH_MAX_DEPTH) /* unreachable: see the depth invariant above */
        return st_fail(err, ST_ERR_FORMAT, "bvh: depth %u exceeds %d", bvh->depth, ST_BVH_MAX_DEPTH);
    st_bvh_node *shrunk = realloc(bvh->nodes, (size_t)bvh->node_count * sizeof *bvh->nodes);
    if (shrunk)
        bvh->nodes = shrunk;
    return ST_OK;
}

st_status st_bvh_build(const float *positions, st_u32 tri_count, st_bvh **out, st_error *err)
{
    return st_bvh_build_threads(positions, tri_count, 0u, out, err);
}

st_status st_bvh_build_threads(const float *positions, st_u32 tri_count, unsigned threads, st_bvh **out,
                               st_error *err)
{
    if (!out)
        return st_fail(err, ST_ERR_USAGE, "bvh: no output handle");
    *out = NULL;
    if (!positions && tri_count > 0u)
        return st_fail(err, ST_ERR_USAGE, "bvh: %u triangles but no positions", tri_count);
    if (tri_count > MAX_TRIANGLES)
        return st_fail(err, ST_ERR_FORMAT, "bvh: %u triangles, at most %u supported", tri_count, MAX_TRIANGLES);
    size_t slots = tri_count ? tri_count : 1u;
    threads = st_bvh_threads(threads, tri_count);
    st_bvh *bvh = calloc(1, sizeof *bvh);
    if (!bvh)
        return st_fail(err, ST_ERR_NOMEM, "bvh: out of memory");
    bvh->tri_count = tri_count;
    bvh->nodes = huge_pages(malloc((2u * slots - 1u) * sizeof *bvh->nodes), (2u * slots - 1u) * sizeof *bvh->nodes);
    bvh->tris = huge_pages(aligned_alloc(16, slots * sizeof *bvh->tris), slots * sizeof *bvh->tris);
    bvh->order = malloc(slots * sizeof *bvh->order);
    /* the wide tree's room (st_bvh_collapse_wide_threads: node_count + 1
     * <= 2 slots nodes), the build's references and arena until then */
    st_bvh_wide_node *wide = huge_pages(malloc(2u * slots * sizeof *wide), 2u * slots * sizeof *wide);
    st_status s = ST_OK;
    if (!bvh->nodes || !bvh->tris || !bvh->order || !wide)
        s = st_fail(err, ST_ERR_NOMEM, "bvh: out of memory for %u triangles", tri_count);
    else if (tri_count == 0u)
        make_empty(bvh);
    else
        s = build_tree(positions, bvh, threads, wide, err);
    if (s == ST_OK)
        s = st_bvh_collapse_wide_threads(bvh, threads, 1, wide, err);
    else
        free(wide);
    if (s != ST_OK) {
        st_bvh_destroy(bvh);
        return s;
    }
    *out = bvh;
    return ST_OK;
}

void st_bvh_destroy(st_bvh *bvh)
{
    if (!bvh)
        return;
    free(bvh->nodes);
    free(bvh->wide);
    free(bvh->tris);
    free(bvh->order);
    free(bvh);
}
