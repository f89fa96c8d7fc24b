/* packet.h — packets of 8 coherent rays per work-item, lane = ray (float8):
 * closest hit (camera rays, trace_rays_packet) and any hit (shadow rays,
 * trace_shadow_rays_packet) through the wide BVH. OpenCL C only; included
 * after trace.h.
 *
 * Why: PoCL runs a group's work-items one after the other, so a single-ray
 * traversal is SIMD only across a node's 8 children; the triangle tests and
 * the traversal's bookkeeping (masks, stack, sorting) are scalar work per
 * ray. Neighbouring items of a wave are neighbouring pixels of one row
 * (generate.cl's item order), so their camera rays, and their shadow rays towards a light,
 * open mostly the same nodes: a packet walks them once, tests each
 * triangle against 8 rays at once, and shares the stack (Wald et al.,
 * "Interactive Rendering with Coherent Ray Tracing", 2001, did it with SSE).
 *
 * Exactness: a node is entered when any live lane's st_trace_box4 (the
 * single-ray test, run per lane with that lane's own closest t) enters it,
 * so each lane opens a superset of the boxes its single ray would, and the
 * box test is conservative (trace.h), so each lane still meets its closest
 * triangle. The triangle test is st_intersect_triangle's arithmetic lane by
 * lane, the same operations in the same statements, so that the compiler's
 * contraction into fma (within a statement, OpenCL's default) is the same
 * too: each lane's t, u, v are the single ray's bit for bit, and its hit is
 * the single ray's unless two triangles tie at exactly the same t (then the
 * one met first wins, as for a single ray, but the order can differ).
 * Tests: tests/test_trace_bench.c (packet_*), tests/test_render.c. */
#ifndef ST_PACKET_H
#define ST_PACKET_H

#define ST_PACKET 8

/* A packet's rays: per lane the single-ray setup (for the node test) and
 * the origins and directions as float8 (for the triangle test); live: bit j
 * set when lane j carries a ray. */
typedef struct st_packet {
    st_trace_ray r[ST_PACKET];
    float8 ox, oy, oz, dx, dy, dz;
    st_u32 live;
} st_packet;

/* Lane mask as bits (lane j -> bit j), and back. */
ST_HOT st_u32 st_packet_bits(int8 m)
{
    int8 b = m & (int8)(1, 2, 4, 8, 16, 32, 64, 128);
    int4 s = b.lo | b.hi;
    int2 t = s.lo | s.hi;
    return (st_u32)(t.x | t.y);
}
ST_HOT int8 st_packet_lanes(st_u32 bits)
{
    return ((int8)((int)bits) & (int8)(1, 2, 4, 8, 16, 32, 64, 128)) != (int8)(0);
}

/* Lane j's ray from rays o, d (3 floats each, a lane's at 3 j); lanes not
 * in live get a harmless ray (origin 0, direction +x) that nothing counts. */
ST_HOT void st_packet_setup(st_packet *pk, const st_ray *rays, st_u32 live)
{
    float o[3][ST_PACKET], d[3][ST_PACKET];
    for (int j = 0; j < ST_PACKET; ++j) {
        st_ray r = rays[j];
        if (!((live >> j) & 1u)) {
            r.o[0] = r.o[1] = r.o[2] = 0.0f;
            r.d[0] = 1.0f;
            r.d[1] = r.d[2] = 0.0f;
        }
        st_trace_setup(&pk->r[j], &r);
        for (int a = 0; a < 3; ++a) {
            o[a][j] = r.o[a];
            d[a][j] = r.d[a];
        }
    }
    pk->ox = vload8(0, o[0]);
    pk->oy = vload8(0, o[1]);
    pk->oz = vload8(0, o[2]);
    pk->dx = vload8(0, d[0]);
    pk->dy = vload8(0, d[1]);
    pk->dz = vload8(0, d[2]);
    pk->live = live;
}

/* st_intersect_triangle of triangle j of leaf block l (n triangles) for the
 * 8 lanes: the lanes where it hits at t in (0, tmax), with t, u, v (the
 * statements are st_intersect_triangle's, in its order; there the early
 * exits skip work, here no lane needs it once none has u in [0, 1]). */
ST_HOT int8 st_packet_triangle(const ST_GLOBAL st_f32 *l, st_u32 n, st_u32 j, const st_packet *pk,
                               float8 tmax, float8 *tt, float8 *uu, float8 *vv)
{
    const ST_GLOBAL st_f32 *lane = l + j;
    st_f32 e1x = lane[ST_LEAF_E1 * n], e1y = lane[(ST_LEAF_E1 + 1) * n];
    st_f32 e1z = lane[(ST_LEAF_E1 + 2) * n];
    st_f32 e2x = lane[ST_LEAF_E2 * n], e2y = lane[(ST_LEAF_E2 + 1) * n];
    st_f32 e2z = lane[(ST_LEAF_E2 + 2) * n];
    float8 dx = pk->dx, dy = pk->dy, dz = pk->dz;
    float8 px = dy * e2z - dz * e2y;
    float8 py = dz * e2x - dx * e2z;
    float8 pz = dx * e2y - dy * e2x;
    float8 det = e1x * px + e1y * py + e1z * pz;
    float8 inv_det = 1.0f / det;
    float8 sx = pk->ox - lane[ST_LEAF_V0 * n];
    float8 sy = pk->oy - lane[(ST_LEAF_V0 + 1) * n];
    float8 sz = pk->oz - lane[(ST_LEAF_V0 + 2) * n];
    float8 u = (sx * px + sy * py + sz * pz) * inv_det;
    int8 in_u = (u >= 0.0f) & (u <= 1.0f);
    if (!any(in_u))
        return (int8)(0);
    float8 qx = sy * e1z - sz * e1y;
    float8 qy = sz * e1x - sx * e1z;
    float8 qz = sx * e1y - sy * e1x;
    float8 v = (dx * qx + dy * qy + dz * qz) * inv_det;
    float8 t = (e2x * qx + e2y * qy + e2z * qz) * inv_det;
    int8 front = (det > 0.0f) | (int8)((st_leaf_sides(l, n) >> j) & 1u ? 0 : -1);
    *tt = t;
    *uu = u;
    *vv = v;
    return in_u & (v >= 0.0f) & (u + v <= 1.0f) & (t > 0.0f) & (t < tmax) & front;
}

/* The children of wide node n that some live lane enters (bit k for child
 * k; lane j with its own search bound tmax[j]), and per child the least
 * entry distance over the lanes that enter it (+inf where none does). */
ST_HOT st_u32 st_packet_node(const ST_GLOBAL st_bvh_wide_node *n, const st_packet *pk,
                             const st_f32 *tmax, st_u32 lanes, st_f32 *near)
{
    st_u32 mask = 0u;
    float8 nearest = (float8)(INFINITY);
    for (; lanes != 0u; lanes &= lanes - 1u) {
        st_u32 j = st_trace_lowest(lanes);
        st_f32 tn[ST_BVH_WIDTH];
        st_u32 m = st_trace_box4(n, &pk->r[j], tmax[j], tn);
        nearest = select(nearest, fmin(nearest, vload8(0, tn)), st_packet_lanes(m));
        mask |= m;
    }
    vstore8(nearest, 0, near);
    return mask;
}

/* Pushes interior child `first` with entry distance e above base, keeping
 * the entries above base sorted far to near (st_intersect4_closest's order). */
ST_HOT void st_packet_push(st_u32 *stack, st_f32 *entry, st_u32 base, st_u32 *sp, st_u32 first,
                           st_f32 e)
{
    st_u32 j = (*sp)++;
    for (; j > base && entry[j - 1u] < e; --j) {
        stack[j] = stack[j - 1u];
        entry[j] = entry[j - 1u];
    }
    stack[j] = first;
    entry[j] = e;
}

/* The largest of the live lanes' bounds (a popped node whose entry lies
 * beyond it is skipped for all of them). */
ST_HOT st_f32 st_packet_max(float8 t, st_u32 live)
{
    t = select((float8)(-INFINITY), t, st_packet_lanes(live));
    float4 a = fmax(t.lo, t.hi);
    float2 b = fmax(a.lo, a.hi);
    return fmax(b.x, b.y);
}

/* A packet's closest hits, lane j as st_intersect4_closest's for ray j (the
 * contract above): hit t, u, v and prim per lane; prim ST_NO_HIT and t =
 * tmax on a miss. Lanes not live come back as misses. */
typedef struct st_packet_hits {
    float8 t, u, v;
    uint8 prim;
} st_packet_hits;

ST_HOT void st_packet_closest(const ST_GLOBAL st_bvh_wide_node *nodes, const st_packet *pk,
                              float8 tmax, st_packet_hits *h)
{
    st_u32 stack[ST_BVH4_STACK];
    st_f32 entry[ST_BVH4_STACK], bound[ST_PACKET];
    st_u32 sp = 0u, node = 0u;
    h->t = tmax;
    h->u = h->v = (float8)(0.0f);
    h->prim = (uint8)(ST_NO_HIT);
    vstore8(tmax, 0, bound);
    st_f32 reach = st_packet_max(tmax, pk->live);
    for (;;) {
        const ST_GLOBAL st_bvh_wide_node *n = nodes + node;
        st_f32 near[ST_BVH_WIDTH];
        st_u32 mask = st_packet_node(n, pk, bound, pk->live, near), base = sp, leaves = 0u;
        for (; mask != 0u; mask &= mask - 1u) {
            st_u32 k = st_trace_lowest(mask);
            st_u32 first = n->child[k], count = n->count[k];
            const ST_GLOBAL st_f32 *l = st_trace_leaf(nodes, first);
            for (st_u32 j = 0u; j < count; ++j) {
                float8 t = h->t, u = h->u, v = h->v;
                int8 ok = st_packet_triangle(l, count, j, pk, h->t, &t, &u, &v);
                h->t = select(h->t, t, ok);
                h->u = select(h->u, u, ok);
                h->v = select(h->v, v, ok);
                h->prim = select(h->prim, (uint8)(st_leaf_first(l, count) + j), ok);
            }
            leaves |= count;
            if (count != 0u)
                continue;
            st_trace_prefetch_node(nodes + first);
            st_packet_push(stack, entry, base, &sp, first, near[k]);
        }
        if (leaves != 0u) {
            vstore8(h->t, 0, bound);
            reach = st_packet_max(h->t, pk->live);
        }
        for (;;) {
            if (sp == 0u)
                return;
            --sp;
            if (entry[sp] <= reach * ST_TRACE_SLAB_WIDEN)
                break;
        }
        node = stack[sp];
    }
}

/* The live lanes that some triangle blocks at t in (0, tmax) (any hit, as
 * st_intersect4_any): a lane stops taking part once blocked, the packet
 * once all are. */
ST_HOT st_u32 st_packet_occluded(const ST_GLOBAL st_bvh_wide_node *nodes, const st_packet *pk,
                                 float8 tmax)
{
    st_u32 stack[ST_BVH4_STACK];
    st_f32 bound[ST_PACKET];
    st_u32 sp = 0u, node = 0u, open = pk->live;
    vstore8(tmax, 0, bound);
    for (;;) {
        const ST_GLOBAL st_bvh_wide_node *n = nodes + node;
        st_f32 near[ST_BVH_WIDTH];
        st_u32 mask = st_packet_node(n, pk, bound, open, near);
        for (; mask != 0u; mask &= mask - 1u) {
            st_u32 k = st_trace_lowest(mask);
            st_u32 first = n->child[k], count = n->count[k];
            for (st_u32 j = 0u; j < count; ++j) {
                float8 t = tmax, u, v;
                open &= ~st_packet_bits(
                    st_packet_triangle(st_trace_leaf(nodes, first), count, j, pk, tmax, &t, &u, &v));
                if (open == 0u)
                    return pk->live;
            }
            if (count == 0u) {
                st_trace_prefetch_node(nodes + first);
                stack[sp++] = first;
            }
        }
        if (sp == 0u)
            return pk->live & ~open;
        node = stack[--sp];
    }
}

#endif
