/* st_bvh.h — bounding volume hierarchy over a triangle soup, built on the host
 * with binned SAH and flattened depth first for the kernels.
 *
 * The layout (st_bvh_node, st_bvh_wide_node, st_triangle) is kernels/shared/st_shared.h's;
 * the traversal that reads it is kernels/geom/trace.h's, shared by host and device:
 * st_intersect_wide_closest and st_intersect_wide_any on the tree collapsed
 * ST_BVH_WIDTH-wide (the binary nodes are the build's and the collapse's).
 * Guarantees of a built tree:
 *   - nodes[0] is the root; an interior node's first child is the next node,
 *     its second child is nodes[offset]; meta = count << 2 | split axis;
 *   - a leaf holds 1..4 triangles, tris[offset .. offset + count);
 *   - order is a permutation of 0 .. tri_count - 1 (tris[i] is input triangle
 *     order[i]; hits report BVH-order indices);
 *   - every box is the exact bounds of its subtree's triangles;
 *   - depth <= ST_BVH_MAX_DEPTH (trace.h's stack size).
 * An empty scene (tri_count == 0) has a single leaf root (count 1, since
 * count 0 marks an interior node) with an inverted (empty) box that no ray
 * enters, over one zeroed placeholder triangle that no ray can hit (det = 0);
 * tris and order then hold that one entry, so that device buffers made from
 * them are never empty. */
#ifndef ST_BVH_H
#define ST_BVH_H

#include "st_error.h"
#include "st_shared.h"

typedef struct st_bvh {
    st_u32 node_count;
    st_bvh_node *nodes;     /* depth first; nodes[0] is the root */
    st_u32 tri_count;
    st_triangle *tris;      /* triangles in BVH order, prepared for Moller-Trumbore (v0, e1, e2) */
    st_u32 *order;          /* order[i] = index in the input of BVH triangle i */
    st_u32 depth;           /* deepest leaf, root = 1 */
    /* The same tree collapsed ST_BVH_WIDTH-wide (st_bvh_wide_node; what the kernels trace):
     * the root at the start, the nodes depth first, each followed by its
     * leaf blocks (st_shared.h); every binary interior node is either a wide
     * node or opened into its parent; leaves and triangles as above. */
    st_u32 wide_count;
    st_bvh_wide_node *wide; /* wide_count + leaf_slots node-sized slots */
    st_u32 wide_depth;      /* deepest wide node, root = 1 */
    st_u32 leaf_slots;      /* the slots the leaf blocks and the padding take
                               beyond the nodes' own (st_bvh_pack_leaves) */
} st_bvh;

/* positions: 9 floats per triangle (v0 v1 v2). tri_count may be 0 (an empty leaf root: no hits). Returns ST_ERR_NOMEM on
   allocation failure, ST_ERR_FORMAT if the tree would exceed ST_BVH_MAX_DEPTH. */
/* The depth bound is kept by construction (median splits near the limit), so
 * the ST_ERR_FORMAT for depth is a safety net that does not fire.
 * Also: ST_ERR_USAGE when out is NULL or positions is NULL with tri_count > 0;
 * ST_ERR_FORMAT when a coordinate is not finite (the message names the
 * triangle) or tri_count > 2^30 - 1. The build reads positions only during the
 * call. On success *out is owned by the caller (st_bvh_destroy); on failure
 * *out is NULL. */
st_status st_bvh_build(const float *positions, st_u32 tri_count, st_bvh **out, st_error *err);

/* st_bvh_build on `threads` threads: 0 chooses (one per online processor,
 * one for scenes too small to gain), any other count is used as given, at
 * most ST_BVH_MAX_THREADS. The tree is the same, array for array, whatever
 * the count and however the threads are scheduled: every piece of work has
 * its place in the output fixed before it runs, and bounds gathered in
 * pieces are combined in input order (min and max keep the later of equal
 * values, so the grouping does not change even the sign of a zero).
 * st_bvh_build is st_bvh_build_threads with 0. */
#define ST_BVH_MAX_THREADS 16u
st_status st_bvh_build_threads(const float *positions, st_u32 tri_count, unsigned threads, st_bvh **out,
                               st_error *err);

/* Marks each triangle one-sided (st_triangle.v0[3] = ST_TRI_ONE_SIDED) or
 * two-sided from its material's ST_MAT_DOUBLE_SIDED flag: tri_material[i]
 * is input triangle i's index into materials. st_bvh_build leaves every
 * triangle two-sided; every traversal of a scene's triangles (the renderer's
 * and the host's references) marks them so, to cull alike. Updates the
 * leaf blocks' sides words to match (their rows do not change), as
 * st_bvh_pack_leaves would. */
void st_bvh_set_sides(st_bvh *bvh, const st_u32 *tri_material, const st_material *materials);

/* Collapses bvh->nodes into bvh->wide (src/bvh/bvh_wide.c; st_bvh_build calls
 * it): the binary nodes that become wide nodes, and the ones each takes as
 * its up to ST_BVH_WIDTH children, are those of the least total surface
 * area of the wide nodes (a ray's expected node visits; dynamic programming,
 * Ylitie et al. 2017). A tree so deep that the traversal stack could
 * overflow at that width (7 x depth > ST_BVH_WIDE_STACK, depth > 27) is made
 * of nodes of at most four children instead, each taking its binary node's
 * two children and, while it has fewer than four, opening the interior child
 * of largest surface area. Each node's leaf blocks
 * follow it (st_shared.h; their rows left zero, see
 * st_bvh_pack_leaves). ST_ERR_NOMEM on allocation failure. */
st_status st_bvh_collapse_wide(st_bvh *bvh, st_error *err);

/* For src/bvh*.c. st_bvh_collapse_wide on `threads` threads (as
 * st_bvh_build_threads counts them), filling the leaf blocks as well when
 * `pack` (st_bvh_pack_leaves' rows, from bvh->tris), in `room` (room for
 * node_count + 1 wide nodes, owned by the call from then on) or, when NULL,
 * memory of its own. */
st_status st_bvh_collapse_wide_threads(st_bvh *bvh, unsigned threads, int pack, st_bvh_wide_node *room,
                                       st_error *err);

/* For src/bvh*.c: the thread count for `work` items (triangles, nodes) from
 * a requested count (0: one per online processor, one below a size where
 * threads do not pay), at most ST_BVH_MAX_THREADS. */
unsigned st_bvh_threads(unsigned threads, st_u64 work);

/* For src/bvh*.c: runs job(ctx, t) once for every t < threads and returns
 * when all have: t = 0 on the calling thread, each other on a thread of its
 * own, or on the calling thread after t = 0 where a thread cannot be
 * started (so a job may own a share of the work by its t). */
typedef void st_bvh_job(void *ctx, unsigned t);
void st_bvh_parallel(unsigned threads, st_bvh_job *job, void *ctx);

/* Fills every leaf block of bvh->wide from bvh->tris (their first
 * triangles and counts as the collapse placed them; st_bvh_build fills
 * them so); whoever changes bvh->tris after (tests) calls it before tracing
 * the wide tree. */
void st_bvh_pack_leaves(st_bvh *bvh);

/* Units (ST_LEAF_UNIT bytes) from the start of a node of bvh->wide to the
 * next node's: the node, its leaf blocks, and padding to a 64-byte line. A
 * walk over the nodes in order: node 0 at unit 0, each next at the last
 * one's unit plus its span. */
st_u32 st_bvh_wide_span(const st_bvh_wide_node *node);

/* Frees the tree and its arrays. NULL is a no-op. */
void st_bvh_destroy(st_bvh *bvh);

#endif
