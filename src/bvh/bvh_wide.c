/* bvh_wide.c — the binary BVH collapsed into an ST_BVH_WIDTH-wide one
 * (st_bvh_wide_node), as Embree and pbrt-v4's GPU path trace (Wald et al.,
 * "Getting Rid of Packets", RT 2008; Dammertz et al., "Shallow Bounding
 * Volume Hierarchies for Fast SIMD Ray Tracing of Incoherent Rays", EGSR
 * 2008): a node's boxes meet the ray in one vector slab test, and the tree is
 * a third as deep as the binary one for 8 children (half for 4). Each leaf's
 * triangles follow the nodes as one leaf block (structure of arrays, as
 * Embree's Triangle4 leaves are, but sized to the leaf: st_shared.h), so
 * that the kernels test them together. */
#include <float.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "st_bvh.h"
#include "trace.h"

static int is_leaf(const st_bvh_node *n) { return (n->meta >> 2) != 0u; }

static float half_area(const st_bvh_node *n)
{
    float dx = n->bmax[0] - n->bmin[0], dy = n->bmax[1] - n->bmin[1], dz = n->bmax[2] - n->bmin[2];
    return dx * dy + dy * dz + dz * dx;
}

/* The binary nodes that become the children of a wide node made from
 * interior node i: its two children, then, while fewer than ST_BVH_WIDTH, the
 * interior one of largest area replaced by its own two (the first of equal
 * areas, so the result is a function of the tree). Returns their number. */
static int gather(const st_bvh_node *nodes, st_u32 i, int width, st_u32 kids[ST_BVH_WIDTH])
{
    int c = 2;
    kids[0] = i + 1u;
    kids[1] = nodes[i].offset;
    while (c < width) {
        int best = -1;
        float area = -1.0f;
        for (int k = 0; k < c; k++)
            if (!is_leaf(&nodes[kids[k]]) && half_area(&nodes[kids[k]]) > area) {
                area = half_area(&nodes[kids[k]]);
                best = k;
            }
        if (best < 0)
            break;
        st_u32 open = kids[best];
        kids[best] = open + 1u;
        kids[c++] = nodes[open].offset;
    }
    return c;
}

typedef struct wide_builder {
    const st_bvh_node *nodes;
    st_bvh_wide_node *wide;
    st_u32 count, depth;
    int width; /* children per node: ST_BVH_WIDTH, or 4 (see collapse) */
} wide_builder;

static st_u32 emit(wide_builder *b, st_u32 i, st_u32 depth);

/* Child slot k of wide node w: binary node `child`'s box, and the node
 * itself as a leaf or as the wide node made from it (emit). */
static void set_slot(wide_builder *b, st_u32 w, int k, st_u32 child, st_u32 depth)
{
    const st_bvh_node *n = &b->nodes[child];
    for (int a = 0; a < 3; a++) {
        b->wide[w].lo[a][k] = n->bmin[a];
        b->wide[w].hi[a][k] = n->bmax[a];
    }
    b->wide[w].count[k] = n->meta >> 2;
    b->wide[w].child[k] = is_leaf(n) ? n->offset : 0u;
    if (!is_leaf(n)) {
        st_u32 c = emit(b, child, depth + 1u);
        b->wide[w].child[k] = c;
    }
}

static void clear_slots(st_bvh_wide_node *w)
{
    for (int k = 0; k < ST_BVH_WIDTH; k++) {
        for (int a = 0; a < 3; a++) {
            w->lo[a][k] = FLT_MAX;
            w->hi[a][k] = -FLT_MAX;
        }
        w->child[k] = 0u;
        w->count[k] = 0u;
    }
}

/* Wide node for binary interior node i, depth first; returns its index. */
static st_u32 emit(wide_builder *b, st_u32 i, st_u32 depth)
{
    st_u32 w = b->count++;
    b->depth = depth > b->depth ? depth : b->depth;
    clear_slots(&b->wide[w]);
    st_u32 kids[ST_BVH_WIDTH];
    int c = gather(b->nodes, i, b->width, kids);
    for (int k = 0; k < c; k++)
        set_slot(b, w, k, kids[k], depth);
    return w;
}

/* The wide tree of nodes of up to b->width children into b->wide. */
static void collapse(wide_builder *b)
{
    b->count = 0u;
    b->depth = 1u;
    if (is_leaf(&b->nodes[0])) {
        b->count = 1u;
        clear_slots(&b->wide[0]);
        set_slot(b, 0u, 0, 0u, 1u);
    } else {
        emit(b, 0u, 1u);
    }
}

/* Gives every leaf slot its leaf block, after the b->count nodes in slot
 * order, each ST_LEAF_UNITS(count) units long: child[k] becomes the block's
 * unit, and the block's first word the leaf's first triangle (rows and
 * sides are st_bvh_pack_leaves'). Returns the units of all blocks. */
static size_t place_leaves(wide_builder *b)
{
    const size_t node_units = sizeof(st_bvh_wide_node) / ST_LEAF_UNIT;
    size_t used = 0u;
    for (st_u32 w = 0u; w < b->count; w++)
        for (int k = 0; k < ST_BVH_WIDTH; k++) {
            st_u32 count = b->wide[w].count[k];
            if (count == 0u)
                continue;
            size_t at = b->count * node_units + used;
            st_u32 *words = (st_u32 *)(void *)((char *)b->wide + at * ST_LEAF_UNIT);
            memset(words, 0, ST_LEAF_UNITS(count) * ST_LEAF_UNIT);
            words[ST_LEAF_ROWS * count] = b->wide[w].child[k];
            b->wide[w].child[k] = (st_u32)at;
            used += ST_LEAF_UNITS(count);
        }
    return used;
}

void st_bvh_pack_leaves(st_bvh *bvh)
{
    for (st_u32 w = 0u; w < bvh->wide_count; w++)
        for (int k = 0; k < ST_BVH_WIDTH; k++) {
            st_u32 n = bvh->wide[w].count[k];
            if (n == 0u)
                continue;
            st_f32 *rows = (st_f32 *)(void *)((char *)bvh->wide +
                                              (size_t)bvh->wide[w].child[k] * ST_LEAF_UNIT);
            st_u32 *words = (st_u32 *)(void *)(rows + ST_LEAF_ROWS * n);
            st_u32 sides = 0u;
            for (st_u32 j = 0u; j < n; j++) {
                const st_triangle *t = &bvh->tris[words[0] + j];
                for (st_u32 a = 0u; a < 3u; a++) {
                    rows[(ST_LEAF_V0 + a) * n + j] = t->v0[a];
                    rows[(ST_LEAF_E1 + a) * n + j] = t->e1[a];
                    rows[(ST_LEAF_E2 + a) * n + j] = t->e2[a];
                }
                sides |= (t->v0[3] != 0.0f ? 1u : 0u) << j;
            }
            words[1] = sides;
        }
}

st_status st_bvh_collapse_wide(st_bvh *bvh, st_error *err)
{
    /* every wide node consumes at least one binary interior node and every
     * binary leaf becomes one leaf block, smaller than a node: at most
     * node_count entries in a full binary tree, one more for a leaf root (a
     * small or empty scene), which gets one wide node over it */
    size_t cap = (size_t)bvh->node_count + 1u;
    wide_builder b = {bvh->nodes, malloc(cap * sizeof *b.wide), 0u, 1u, ST_BVH_WIDTH};
    if (!b.wide)
        return st_fail(err, ST_ERR_NOMEM, "bvh: out of memory for the wide tree");
    collapse(&b);
    /* the traversal stack holds (width - 1) x depth entries at most: a tree
     * too deep for ST_BVH_WIDE_STACK at full width is made of 4-child nodes,
     * whose depth <= ST_BVH_MAX_DEPTH keeps it within (trace.h) */
    if ((st_u32)(b.width - 1) * b.depth > ST_BVH_WIDE_STACK) {
        b.width = 4;
        collapse(&b);
    }
    size_t units = place_leaves(&b), per_node = sizeof *b.wide / ST_LEAF_UNIT;
    if (b.count * per_node + units > UINT32_MAX) { /* child[k] could not name every block */
        free(b.wide);
        return st_fail(err, ST_ERR_NOMEM, "bvh: the wide tree exceeds 2^32 leaf units");
    }
    st_u32 slots = (st_u32)((units + per_node - 1u) / per_node);
    st_bvh_wide_node *shrunk = realloc(b.wide, (size_t)(b.count + slots) * sizeof *b.wide);
    bvh->wide = shrunk ? shrunk : b.wide;
    /* the last slot's rest: zero, so that the array is a function of the tree */
    memset((char *)(bvh->wide + b.count) + units * ST_LEAF_UNIT, 0,
           (size_t)slots * sizeof *b.wide - units * ST_LEAF_UNIT);
    bvh->wide_count = b.count;
    bvh->leaf_slots = slots;
    bvh->wide_depth = b.depth;
    return ST_OK;
}
