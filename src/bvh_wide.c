/* bvh_wide.c — the binary BVH collapsed into an ST_BVH_WIDTH-wide one
 * (st_bvh_wide_node), as Embree and pbrt-v4's GPU path trace (Wald et al.,
 * "Getting Rid of Packets", RT 2008; Dammertz et al., "Shallow Bounding
 * Volume Hierarchies for Fast SIMD Ray Tracing of Incoherent Rays", EGSR
 * 2008): a node's boxes meet the ray in one vector slab test, and the tree is
 * a third as deep as the binary one for 8 children (half for 4). Each leaf's
 * triangles follow the nodes as one st_bvh_leaf (structure of arrays), so
 * that the kernels test them together, as Embree's Triangle4 leaves are. */
#include <float.h>
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

/* Gives every leaf slot its st_bvh_leaf, after the b->count nodes in slot
 * order: lane 0 at the slot's first triangle, the lanes zero until
 * st_bvh_pack_leaves fills them. Returns the number of leaves. */
static st_u32 place_leaves(wide_builder *b)
{
    st_u32 leaves = 0u;
    for (st_u32 w = 0u; w < b->count; w++)
        for (int k = 0; k < ST_BVH_WIDTH; k++) {
            if (b->wide[w].count[k] == 0u)
                continue;
            st_u32 at = b->count + leaves++;
            st_bvh_leaf *leaf = (st_bvh_leaf *)(void *)&b->wide[at];
            memset(leaf, 0, sizeof *leaf);
            leaf->first = b->wide[w].child[k];
            b->wide[w].child[k] = at;
        }
    return leaves;
}

void st_bvh_pack_leaves(st_bvh *bvh)
{
    for (st_u32 w = 0u; w < bvh->wide_count; w++)
        for (int k = 0; k < ST_BVH_WIDTH; k++) {
            st_u32 count = bvh->wide[w].count[k];
            if (count == 0u)
                continue;
            st_bvh_leaf *leaf = (st_bvh_leaf *)(void *)&bvh->wide[bvh->wide[w].child[k]];
            for (st_u32 j = 0u; j < 4u; j++) {
                static const st_triangle none;
                const st_triangle *t = j < count ? &bvh->tris[leaf->first + j] : &none;
                for (int a = 0; a < 3; a++) {
                    leaf->v0[a][j] = t->v0[a];
                    leaf->e1[a][j] = t->e1[a];
                    leaf->e2[a][j] = t->e2[a];
                }
                leaf->one_sided[j] = t->v0[3];
            }
        }
}

st_status st_bvh_collapse_wide(st_bvh *bvh, st_error *err)
{
    /* every wide node consumes at least one binary interior node and every
     * binary leaf becomes one st_bvh_leaf: at most node_count entries in a
     * full binary tree, one more for a leaf root (a small or empty scene),
     * which gets one wide node over it */
    size_t cap = (size_t)bvh->node_count + 1u;
    wide_builder b = {bvh->nodes, malloc(cap * sizeof *b.wide), 0u, 1u, ST_BVH_WIDTH};
    if (!b.wide)
        return st_fail(err, ST_ERR_NOMEM, "bvh: out of memory for the wide tree");
    collapse(&b);
    /* the traversal stack holds (width - 1) x depth entries at most: a tree
     * too deep for ST_BVH4_STACK at full width is made of 4-child nodes,
     * whose depth <= ST_BVH_MAX_DEPTH keeps it within (trace.h) */
    if ((st_u32)(b.width - 1) * b.depth > ST_BVH4_STACK) {
        b.width = 4;
        collapse(&b);
    }
    st_u32 leaves = place_leaves(&b);
    st_bvh_wide_node *shrunk = realloc(b.wide, (size_t)(b.count + leaves) * sizeof *b.wide);
    bvh->wide = shrunk ? shrunk : b.wide;
    bvh->wide_count = b.count;
    bvh->leaf_count = leaves;
    bvh->wide_depth = b.depth;
    return ST_OK;
}
