/* bvh_wide.c — the binary BVH collapsed into an ST_BVH_WIDTH-wide one
 * (st_bvh_wide_node), as Embree and pbrt-v4's GPU path trace (Wald et al.,
 * "Getting Rid of Packets", RT 2008; Dammertz et al., "Shallow Bounding
 * Volume Hierarchies for Fast SIMD Ray Tracing of Incoherent Rays", EGSR
 * 2008): a node's boxes meet the ray in one vector slab test, and the tree is
 * a third as deep as the binary one for 8 children (half for 4). Which
 * binary nodes become wide nodes is chosen for the least total area (below).
 * Each leaf's
 * triangles follow its node as one leaf block (structure of arrays, as
 * Embree's Triangle4 leaves are, but sized to the leaf: st_shared.h), so
 * that the kernels test them together and find them near the node. */
#include <float.h>
#include <stdatomic.h>
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

/* The greedy choice, which the four-child fallback keeps (its depth bound
 * holds for it): the binary nodes that become the children of a wide node
 * made from interior node i are its two children, then, while fewer than
 * `width`, the interior one of largest area replaced by its own two (the
 * first of equal areas, so the result is a function of the tree). Returns
 * their number. Each kid's area is computed once (-1 for a leaf: never
 * opened). */
static float open_area(const st_bvh_node *n) { return is_leaf(n) ? -1.0f : half_area(n); }

static int gather_greedy(const st_bvh_node *nodes, st_u32 i, int width, st_u32 kids[ST_BVH_WIDTH])
{
    float area[ST_BVH_WIDTH];
    int c = 2;
    kids[0] = i + 1u;
    kids[1] = nodes[i].offset;
    area[0] = open_area(&nodes[kids[0]]);
    area[1] = open_area(&nodes[kids[1]]);
    while (c < width) {
        int best = -1;
        float most = -1.0f;
        for (int k = 0; k < c; k++)
            if (area[k] > most) {
                most = area[k];
                best = k;
            }
        if (best < 0)
            break;
        st_u32 open = kids[best];
        kids[best] = open + 1u;
        kids[c] = nodes[open].offset;
        area[best] = open_area(&nodes[kids[best]]);
        area[c] = open_area(&nodes[kids[c]]);
        c++;
    }
    return c;
}

typedef struct wide_builder {
    const st_bvh_node *nodes;
    st_bvh_wide_node *wide;
    st_u32 count, depth;
    int width; /* children per node: ST_BVH_WIDTH, or 4 (see collapse) */
    const float *cost; /* plan_costs' table at width ST_BVH_WIDTH; NULL: gather_greedy */
} wide_builder;

/* ---- the SAH-optimal choice of wide nodes ----
 * Which binary nodes become wide nodes, chosen to minimise the sum of the
 * wide nodes' surface areas (a ray's expected node visits; every binary
 * leaf is a leaf slot whatever the choice, so the leaves' own cost does not
 * enter), by dynamic programming over the binary tree (Ylitie, Karras and
 * Laine, "Efficient Incoherent Ray Traversal on GPUs Through Compressed
 * Wide BVHs", HPG 2017): C(n, i) is the least cost of binary subtree n
 * placed in at most i slots of its parent,
 *   C(leaf, i) = 0,
 *   C(n, 1) = A(n) + D(n, W)   (n a wide node of W slots),
 *   C(n, i) = min(C(n, i - 1), D(n, i)),
 *   D(n, j) = min over k in 1..j-1 of C(left, k) + C(right, j - k).
 * cost[n W + i - 1] holds C(n, i). The greedy collapse (open the largest
 * child) leaves many nodes of two or three leaves below full parents. */

/* D(n, j) for interior n, and in *k the least k that reaches it. */
static float split_cost(const wide_builder *b, st_u32 n, int j, int *k)
{
    const float *l = b->cost + (size_t)(n + 1u) * ST_BVH_WIDTH;
    const float *r = b->cost + (size_t)b->nodes[n].offset * ST_BVH_WIDTH;
    float best = INFINITY;
    for (int a = 1; a < j; a++) {
        float c = l[a - 1] + r[j - a - 1];
        if (c < best) {
            best = c;
            *k = a;
        }
    }
    return best;
}

/* Node n's row of the table from its children's. */
static void plan_node(const wide_builder *b, st_u32 n, float *cost)
{
    float *c = cost + (size_t)n * ST_BVH_WIDTH;
    if (is_leaf(&b->nodes[n])) {
        for (int i = 0; i < ST_BVH_WIDTH; i++)
            c[i] = 0.0f;
        return;
    }
    int k;
    float area = half_area(&b->nodes[n]);
    area = area <= FLT_MAX ? area : FLT_MAX; /* no NaN (inf - inf, 0 inf) in the sums */
    c[0] = area + split_cost(b, n, ST_BVH_WIDTH, &k);
    for (int i = 2; i <= ST_BVH_WIDTH; i++) {
        float d = split_cost(b, n, i, &k);
        c[i - 1] = d < c[i - 2] ? d : c[i - 2];
    }
}

/* The table for binary subtree n, children before their parent. */
static void plan_costs(const wide_builder *b, st_u32 n, float *cost)
{
    if (!is_leaf(&b->nodes[n])) {
        plan_costs(b, n + 1u, cost);
        plan_costs(b, b->nodes[n].offset, cost);
    }
    plan_node(b, n, cost);
}

/* The table on threads: the subtrees PLAN_DEPTH levels down (or leaves
 * above that) are tasks, the levels above them done after, on one thread.
 * Each row is a function of the subtree alone, so the table is the same
 * whatever the threads. */
#define PLAN_DEPTH 6u

typedef struct plan_job {
    const wide_builder *b;
    float *cost;
    st_u32 task[1u << PLAN_DEPTH], count;
    atomic_uint next;
} plan_job;

static void plan_tasks(plan_job *j, st_u32 n, st_u32 depth)
{
    if (depth == PLAN_DEPTH || is_leaf(&j->b->nodes[n])) {
        j->task[j->count++] = n;
        return;
    }
    plan_tasks(j, n + 1u, depth + 1u);
    plan_tasks(j, j->b->nodes[n].offset, depth + 1u);
}

static void plan_run(void *ctx, unsigned t)
{
    plan_job *j = ctx;
    (void)t;
    for (st_u32 k; (k = (st_u32)atomic_fetch_add(&j->next, 1u)) < j->count;)
        plan_costs(j->b, j->task[k], j->cost);
}

/* The rows above the tasks, children before their parent. */
static void plan_top(const wide_builder *b, st_u32 n, st_u32 depth, float *cost)
{
    if (depth == PLAN_DEPTH || is_leaf(&b->nodes[n]))
        return;
    plan_top(b, n + 1u, depth + 1u, cost);
    plan_top(b, b->nodes[n].offset, depth + 1u, cost);
    plan_node(b, n, cost);
}

static void plan_costs_threads(const wide_builder *b, unsigned threads, float *cost)
{
    plan_job j = {b, cost, {0u}, 0u, 0u};
    plan_tasks(&j, 0u, 0u);
    atomic_init(&j.next, 0u);
    st_bvh_parallel(threads, plan_run, &j);
    plan_top(b, 0u, 0u, cost);
}

/* Binary subtree n into at most j slots, kids[*c ..], as the table chose:
 * its children's slots (the least split that reaches C(n, j), also on a
 * tie with one slot, so that boxes of no area still fill nodes), else one
 * slot (a leaf, or a wide node of its own). */
static void take(const wide_builder *b, st_u32 n, int j, st_u32 kids[ST_BVH_WIDTH], int *c)
{
    const float *cn = b->cost + (size_t)n * ST_BVH_WIDTH;
    if (!is_leaf(&b->nodes[n]))
        for (int i = 2; i <= j; i++) {
            int k = 1;
            if (split_cost(b, n, i, &k) == cn[j - 1]) {
                take(b, n + 1u, k, kids, c);
                take(b, b->nodes[n].offset, i - k, kids, c);
                return;
            }
        }
    kids[(*c)++] = n;
}

/* The binary nodes that become the children of the wide node made from
 * interior node i (at most b->width). */
static int gather(const wide_builder *b, st_u32 i, st_u32 kids[ST_BVH_WIDTH])
{
    if (!b->cost)
        return gather_greedy(b->nodes, i, b->width, kids);
    int c = 0, k = 1;
    split_cost(b, i, ST_BVH_WIDTH, &k);
    take(b, i + 1u, k, kids, &c);
    take(b, b->nodes[i].offset, ST_BVH_WIDTH - k, kids, &c);
    return c;
}

/* Child slot k of wide node w: binary node `child`'s box and count; its
 * child[k] is the leaf's first triangle (0 for an interior child, set by
 * the caller). */
static void set_slot(wide_builder *b, st_u32 w, int k, st_u32 child)
{
    const st_bvh_node *n = &b->nodes[child];
    for (int a = 0; a < 3; a++) {
        b->wide[w].lo[a][k] = n->bmin[a];
        b->wide[w].hi[a][k] = n->bmax[a];
    }
    b->wide[w].count[k] = n->meta >> 2;
    b->wide[w].child[k] = is_leaf(n) ? n->offset : 0u;
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

/* Wide node for binary interior node i, depth first from b->count; returns
 * its index. */
static st_u32 emit(wide_builder *b, st_u32 i, st_u32 depth)
{
    st_u32 w = b->count++;
    b->depth = depth > b->depth ? depth : b->depth;
    clear_slots(&b->wide[w]);
    st_u32 kids[ST_BVH_WIDTH];
    int c = gather(b, i, kids);
    for (int k = 0; k < c; k++) {
        set_slot(b, w, k, kids[k]);
        if (!is_leaf(&b->nodes[kids[k]])) {
            st_u32 child = emit(b, kids[k], depth + 1u);
            b->wide[w].child[k] = child;
        }
    }
    return w;
}

/* The wide nodes emit would make from binary interior node i; *depth
 * becomes the deepest of them if deeper. */
static st_u32 count_wide(const wide_builder *b, st_u32 i, st_u32 at, st_u32 *depth)
{
    st_u32 kids[ST_BVH_WIDTH], total = 1u;
    int c = gather(b, i, kids);
    *depth = at > *depth ? at : *depth;
    for (int k = 0; k < c; k++)
        if (!is_leaf(&b->nodes[kids[k]]))
            total += count_wide(b, kids[k], at + 1u, depth);
    return total;
}

/* ---- the collapse on threads ----
 * The top TASK_DEPTH - 1 levels of wide nodes are made on one thread; each
 * interior child below them is a task: its wide subtree is counted by
 * whichever thread takes it, the top levels are then emitted depth first
 * with each task's subtree given its range of indices, and the threads
 * emit the subtrees into them: the nodes emit alone would make, where it
 * would put them. */
#define TASK_DEPTH 3u
#define MAX_TASKS (ST_BVH_WIDTH * ST_BVH_WIDTH) /* interior children at TASK_DEPTH */

typedef struct wide_task {
    st_u32 node, depth, base, count, max_depth;
} wide_task;

typedef struct collapse_job {
    wide_builder *b;
    wide_task task[MAX_TASKS];
    st_u32 task_count, next_task; /* next_task: while the top levels are emitted */
    atomic_uint next;
} collapse_job;

/* The tasks below binary interior node i, which would be the wide node at
 * `depth`, in depth-first order. */
static void list_tasks(collapse_job *j, st_u32 i, st_u32 depth)
{
    st_u32 kids[ST_BVH_WIDTH];
    int c = gather(j->b, i, kids);
    for (int k = 0; k < c; k++) {
        if (is_leaf(&j->b->nodes[kids[k]]))
            continue;
        if (depth + 1u >= TASK_DEPTH)
            j->task[j->task_count++] = (wide_task){kids[k], depth + 1u, 0u, 0u, 0u};
        else
            list_tasks(j, kids[k], depth + 1u);
    }
}

/* emit over the top levels: a task's subtree is skipped over, its nodes
 * left to emit_tasks. */
static st_u32 emit_top(collapse_job *j, st_u32 i, st_u32 depth)
{
    wide_builder *b = j->b;
    st_u32 w = b->count++;
    b->depth = depth > b->depth ? depth : b->depth;
    clear_slots(&b->wide[w]);
    st_u32 kids[ST_BVH_WIDTH];
    int c = gather(b, i, kids);
    for (int k = 0; k < c; k++) {
        set_slot(b, w, k, kids[k]);
        if (is_leaf(&b->nodes[kids[k]]))
            continue;
        st_u32 child;
        if (depth + 1u >= TASK_DEPTH) {
            wide_task *x = &j->task[j->next_task++];
            x->base = child = b->count;
            b->count += x->count;
        } else {
            child = emit_top(j, kids[k], depth + 1u);
        }
        b->wide[w].child[k] = child;
    }
    return w;
}

static void count_tasks(void *ctx, unsigned t)
{
    collapse_job *j = ctx;
    (void)t;
    for (st_u32 k; (k = (st_u32)atomic_fetch_add(&j->next, 1u)) < j->task_count;) {
        wide_task *x = &j->task[k];
        x->count = count_wide(j->b, x->node, x->depth, &x->max_depth);
    }
}

static void emit_tasks(void *ctx, unsigned t)
{
    collapse_job *j = ctx;
    (void)t;
    for (st_u32 k; (k = (st_u32)atomic_fetch_add(&j->next, 1u)) < j->task_count;) {
        wide_task *x = &j->task[k];
        wide_builder b = *j->b;
        b.count = x->base;
        emit(&b, x->node, x->depth);
    }
}

/* The wide tree of nodes of up to b->width children into b->wide. */
static void collapse(wide_builder *b, unsigned threads)
{
    b->count = 0u;
    b->depth = 1u;
    if (is_leaf(&b->nodes[0])) {
        b->count = 1u;
        clear_slots(&b->wide[0]);
        set_slot(b, 0u, 0, 0u);
        return;
    }
    collapse_job *j = malloc(sizeof *j);
    if (!j) { /* one thread needs no task list */
        emit(b, 0u, 1u);
        return;
    }
    j->b = b;
    j->task_count = j->next_task = 0u;
    list_tasks(j, 0u, 1u);
    atomic_init(&j->next, 0u);
    st_bvh_parallel(threads, count_tasks, j);
    emit_top(j, 0u, 1u);
    atomic_store(&j->next, 0u);
    st_bvh_parallel(threads, emit_tasks, j);
    for (st_u32 k = 0; k < j->task_count; k++)
        b->depth = j->task[k].max_depth > b->depth ? j->task[k].max_depth : b->depth;
    free(j);
}

/* ---- the array: each node followed by its leaf blocks ---- */

/* Wide nodes a piece of the layout's work. */
#define NODE_PIECE 256u
#define NODE_UNITS ((st_u32)(sizeof(st_bvh_wide_node) / ST_LEAF_UNIT))
#define LINE_UNITS (64u / ST_LEAF_UNIT)

st_u32 st_bvh_wide_span(const st_bvh_wide_node *node)
{
    st_u32 units = NODE_UNITS;
    for (int k = 0; k < ST_BVH_WIDTH; k++)
        units += node->count[k] ? ST_LEAF_UNITS(node->count[k]) : 0u;
    return (units + LINE_UNITS - 1u) / LINE_UNITS * LINE_UNITS;
}

static st_bvh_wide_node *node_at(st_bvh_wide_node *wide, size_t unit)
{
    return (st_bvh_wide_node *)(void *)((char *)wide + unit * ST_LEAF_UNIT);
}

static st_f32 *rows_at(st_bvh_wide_node *wide, size_t unit)
{
    return (st_f32 *)(void *)((char *)wide + unit * ST_LEAF_UNIT);
}

static void pack_block(const st_bvh *bvh, st_f32 *rows, st_u32 n)
{
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

/* The leaf blocks of the node at unit `at`, spanning `span` units: in slot
 * order right after it, each ST_LEAF_UNITS(count) units; child[k] becomes
 * the block's unit and the block's first word the leaf's first triangle;
 * the rest zero, or packed from bvh->tris when `pack`. */
static void place_blocks(const st_bvh *bvh, st_bvh_wide_node *wide, size_t at, st_u32 span, int pack)
{
    st_bvh_wide_node *node = node_at(wide, at);
    size_t unit = at + NODE_UNITS;
    memset(rows_at(wide, unit), 0, (span - NODE_UNITS) * (size_t)ST_LEAF_UNIT);
    for (int k = 0; k < ST_BVH_WIDTH; k++) {
        st_u32 count = node->count[k];
        if (count == 0u)
            continue;
        st_f32 *rows = rows_at(wide, unit);
        ((st_u32 *)(void *)rows)[ST_LEAF_ROWS * count] = node->child[k];
        node->child[k] = (st_u32)unit;
        if (pack)
            pack_block(bvh, rows, count);
        unit += ST_LEAF_UNITS(count);
    }
}

/* The layout's pieces on threads, NODE_PIECE nodes each, node w at unit
 * at[w] (at[count]: the end). */
typedef struct layout_job {
    const st_bvh *bvh;
    st_bvh_wide_node *wide;
    const size_t *at;
    st_u32 count, pieces;
    int pack;
    atomic_uint next;
} layout_job;

static void place_run(void *ctx, unsigned t)
{
    layout_job *j = ctx;
    (void)t;
    for (st_u32 p; (p = (st_u32)atomic_fetch_add(&j->next, 1u)) < j->pieces;) {
        st_u32 lo = p * NODE_PIECE, hi = j->count - lo < NODE_PIECE ? j->count : lo + NODE_PIECE;
        for (st_u32 w = lo; w < hi; w++)
            place_blocks(j->bvh, j->wide, j->at[w], (st_u32)(j->at[w + 1u] - j->at[w]), j->pack);
    }
}

/* Lays the b->count nodes, numbered depth first, out as the kernels read
 * them: node w at unit at[w], the sum of the spans before it, followed by
 * its leaf blocks; interior children named by their units. Returns the
 * units in all (more than UINT32_MAX: not laid out), or SIZE_MAX when out
 * of memory. The array (node_count + 1 slots) has room: a wide node takes
 * its binary interior node's NODE_UNITS, a leaf block fewer than its binary
 * leaf's by at least the LINE_UNITS - 1 of padding a node may add, and
 * there are fewer wide nodes than leaves. */
ST_STATIC_ASSERT(ST_LEAF_UNITS(ST_LEAF_MAX) + LINE_UNITS - 1u <= NODE_UNITS,
               "a leaf block and a node's padding fit in a binary leaf's slot");
static size_t lay_out(const st_bvh *bvh, wide_builder *b, unsigned threads, int pack)
{
    size_t *at = malloc(((size_t)b->count + 1u) * sizeof *at), units = 0u;
    if (!at)
        return SIZE_MAX;
    for (st_u32 w = 0; w < b->count; w++) {
        at[w] = units;
        units += st_bvh_wide_span(&b->wide[w]);
    }
    at[b->count] = units;
    if (units > UINT32_MAX) {
        free(at);
        return units;
    }
    /* from the last node back: node w's unit at[w] >= NODE_UNITS w lies past
     * every node not yet moved, which are below it */
    for (st_u32 w = b->count; w-- > 0u;) {
        st_bvh_wide_node node = b->wide[w];
        for (int k = 0; k < ST_BVH_WIDTH; k++)
            if (node.count[k] == 0u)
                node.child[k] = (st_u32)at[node.child[k]];
        *node_at(b->wide, at[w]) = node;
    }
    layout_job j = {bvh, b->wide, at, b->count, (b->count + NODE_PIECE - 1u) / NODE_PIECE, pack, 0u};
    atomic_init(&j.next, 0u);
    st_bvh_parallel(threads, place_run, &j);
    free(at);
    return units;
}

/* ---- every leaf block, on threads ---- */

typedef void leaf_fn(void *ctx, st_f32 *rows, st_u32 n);

typedef struct leaf_walk {
    st_bvh *bvh;
    leaf_fn *fn;
    void *ctx;
    const size_t *start; /* per piece: its first node's unit */
    st_u32 pieces, per_piece;
    atomic_uint next;
} leaf_walk;

static void walk_run(void *ctx, unsigned t)
{
    leaf_walk *j = ctx;
    st_u32 count = j->bvh->wide_count;
    (void)t;
    for (st_u32 p; (p = (st_u32)atomic_fetch_add(&j->next, 1u)) < j->pieces;) {
        st_u32 lo = p * j->per_piece, hi = count - lo < j->per_piece ? count : lo + j->per_piece;
        size_t unit = j->start[p];
        for (st_u32 w = lo; w < hi; w++) {
            st_bvh_wide_node *node = node_at(j->bvh->wide, unit);
            for (int k = 0; k < ST_BVH_WIDTH; k++)
                if (node->count[k] != 0u)
                    j->fn(j->ctx, rows_at(j->bvh->wide, node->child[k]), node->count[k]);
            unit += st_bvh_wide_span(node);
        }
    }
}

/* fn(ctx, rows, n) for every leaf block (n triangles), pieces of nodes on
 * threads: the pieces' first units found by a walk over the nodes (one
 * piece on one thread where memory for them is short). */
static void each_leaf(st_bvh *bvh, unsigned threads, leaf_fn *fn, void *ctx)
{
    st_u32 pieces = (bvh->wide_count + NODE_PIECE - 1u) / NODE_PIECE;
    size_t *start = malloc((pieces ? pieces : 1u) * sizeof *start), whole = 0u;
    leaf_walk j = {bvh, fn, ctx, start, pieces, NODE_PIECE, 0u};
    if (!start) {
        j.start = &whole;
        j.pieces = 1u;
        j.per_piece = bvh->wide_count;
        threads = 1u;
    } else {
        size_t unit = 0u;
        for (st_u32 w = 0; w < bvh->wide_count; w++) {
            if (w % NODE_PIECE == 0u)
                start[w / NODE_PIECE] = unit;
            unit += st_bvh_wide_span(node_at(bvh->wide, unit));
        }
    }
    atomic_init(&j.next, 0u);
    st_bvh_parallel(threads, walk_run, &j);
    free(start);
}

static void pack_one(void *ctx, st_f32 *rows, st_u32 n) { pack_block(ctx, rows, n); }

void st_bvh_pack_leaves(st_bvh *bvh)
{
    each_leaf(bvh, st_bvh_threads(0u, bvh->tri_count), pack_one, bvh);
}

st_status st_bvh_collapse_wide(st_bvh *bvh, st_error *err)
{
    return st_bvh_collapse_wide_threads(bvh, st_bvh_threads(0u, bvh->node_count), 0, NULL, err);
}

st_status st_bvh_collapse_wide_threads(st_bvh *bvh, unsigned threads, int pack, st_bvh_wide_node *room,
                                       st_error *err)
{
    /* every wide node consumes at least one binary interior node and every
     * binary leaf becomes one leaf block, smaller than a node: at most
     * node_count entries in a full binary tree, one more for a leaf root (a
     * small or empty scene), which gets one wide node over it */
    size_t cap = (size_t)bvh->node_count + 1u;
    wide_builder b = {bvh->nodes, room ? room : malloc(cap * sizeof *b.wide), 0u, 1u, ST_BVH_WIDTH, NULL};
    float *cost = malloc(cap * ST_BVH_WIDTH * sizeof *cost);
    if (!b.wide || !cost) {
        free(b.wide);
        free(cost);
        return st_fail(err, ST_ERR_NOMEM, "bvh: out of memory for the wide tree");
    }
    b.cost = cost;
    plan_costs_threads(&b, threads, cost);
    collapse(&b, threads);
    /* the traversal stack holds (width - 1) x depth entries at most: a tree
     * too deep for ST_BVH_WIDE_STACK at full width is made of 4-child nodes
     * by the greedy collapse, whose depth <= ST_BVH_MAX_DEPTH keeps it
     * within (trace.h) */
    if ((st_u32)(b.width - 1) * b.depth > ST_BVH_WIDE_STACK) {
        b.width = 4;
        b.cost = NULL;
        collapse(&b, threads);
    }
    free(cost);
    size_t units = lay_out(bvh, &b, threads, pack);
    if (units == SIZE_MAX) {
        free(b.wide);
        return st_fail(err, ST_ERR_NOMEM, "bvh: out of memory for the leaf blocks");
    }
    if (units > UINT32_MAX) { /* child[k] could not name every node and block */
        free(b.wide);
        return st_fail(err, ST_ERR_NOMEM, "bvh: the wide tree exceeds 2^32 leaf units");
    }
    st_u32 slots = (st_u32)((units + NODE_UNITS - 1u) / NODE_UNITS);
    st_bvh_wide_node *shrunk = realloc(b.wide, (size_t)slots * sizeof *b.wide);
    bvh->wide = shrunk ? shrunk : b.wide;
    /* the last slot's rest: zero, so that the array is a function of the tree */
    memset((char *)bvh->wide + units * ST_LEAF_UNIT, 0, (size_t)slots * sizeof *b.wide - units * ST_LEAF_UNIT);
    bvh->wide_count = b.count;
    bvh->leaf_slots = slots - b.count;
    bvh->wide_depth = b.depth;
    return ST_OK;
}

/* One pass over the leaf blocks: each triangle's side rule into its
 * st_triangle and its block's sides word (every triangle is in one block;
 * the rows do not depend on the sides). */
typedef struct sides_ctx {
    st_bvh *bvh;
    const st_u32 *tri_material;
    const st_material *materials;
} sides_ctx;

static void sides_one(void *ctx, st_f32 *rows, st_u32 n)
{
    sides_ctx *c = ctx;
    st_u32 *words = (st_u32 *)(void *)(rows + ST_LEAF_ROWS * n), sides = 0u;
    for (st_u32 i = 0u; i < n; i++) {
        st_u32 tri = words[0] + i;
        st_u32 flags = c->materials[c->tri_material[c->bvh->order[tri]]].flags;
        c->bvh->tris[tri].v0[3] = (flags & ST_MAT_DOUBLE_SIDED) ? 0.0f : ST_TRI_ONE_SIDED;
        sides |= (c->bvh->tris[tri].v0[3] != 0.0f ? 1u : 0u) << i;
    }
    words[1] = sides;
}

void st_bvh_set_sides(st_bvh *bvh, const st_u32 *tri_material, const st_material *materials)
{
    if (bvh->tri_count == 0u) /* the empty scene's placeholder has no material */
        return;
    sides_ctx c = {bvh, tri_material, materials};
    each_leaf(bvh, st_bvh_threads(0u, bvh->tri_count), sides_one, &c);
}
