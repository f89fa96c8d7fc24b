/* packet.h — packets of ST_W coherent rays per work-item, lane = ray
 * (lanes.h): closest hit (camera rays, trace_rays_packet) and any hit
 * (shadow rays, trace_shadow_rays_packet) through the wide BVH. OpenCL C
 * only; included after trace.h. ST_W is the device's lane width (the host
 * chooses it: st_device_lanes), so the same text makes packets of 4, 8 or 16
 * rays, and of 1 where a GPU's work-items make the lanes.
 *
 * Why: PoCL runs a group's work-items one after the other, so a single-ray
 * traversal is SIMD only across a node's 8 children; the triangle tests and
 * the traversal's bookkeeping (masks, stack, sorting) are scalar work per
 * ray. Neighbouring items of a wave are neighbouring pixels of one row, so
 * their camera rays, and their shadow rays towards a light, open mostly the
 * same nodes: a packet walks them once, tests each triangle against all its
 * rays at once, and shares the stack (Wald et al., "Interactive Rendering
 * with Coherent Ray Tracing", 2001, did it with SSE).
 *
 * Exactness: a node is entered when any live lane's st_trace_box4 (the
 * single-ray test, run per lane with that lane's own closest t) enters it,
 * so each lane opens a superset of the boxes its single ray would, and the
 * box test is conservative (trace.h), so each lane still meets its closest
 * triangle. The triangle test is trace_lanes.h's, the one the leaf test and
 * the host's reference run, at ST_W lanes: each lane's t, u, v are the
 * single ray's bit for bit, and its hit is the single ray's unless two
 * triangles tie at exactly the same t (then the one met first wins, as for
 * a single ray, but the order can differ).
 * Tests: tests/device/test_packet.c, tests/image/test_render.c. */
#ifndef ST_PACKET_H
#define ST_PACKET_H

#define ST_PACKET ST_W

/* A packet's rays (lanes.h's st_lf, st_li, st_lv3 per ray): per lane the
 * single-ray setup (for the node test) and the origins and directions as
 * lanes (for the triangle test); live: bit j set when lane j carries a ray. */
typedef struct st_packet {
    st_slab_consts r[ST_PACKET];
    st_lv3 o, d;
    st_u32 live;
} st_packet;

/* Lane j's ray from rays o, d (3 floats each, a lane's at 3 j); lanes not
 * in live get a harmless ray (origin 0, direction +x) that nothing counts. */
ST_HOT void st_packet_setup(st_packet *pk, const st_ray *rays, st_u32 live)
{
    float o[3][ST_PACKET], d[3][ST_PACKET];
    ST_UNROLL
    for (int j = 0; j < ST_PACKET; ++j) {
        st_ray r = rays[j];
        if (!((live >> j) & 1u)) {
            r.o[0] = r.o[1] = r.o[2] = 0.0f;
            r.d[0] = 1.0f;
            r.d[1] = r.d[2] = 0.0f;
        }
        st_trace_setup(&pk->r[j], &r);
        ST_UNROLL
        for (int a = 0; a < 3; ++a) {
            o[a][j] = r.o[a];
            d[a][j] = r.d[a];
        }
    }
    st_lv3 po = {ST_VLOAD(ST_W, o[0]), ST_VLOAD(ST_W, o[1]), ST_VLOAD(ST_W, o[2])};
    st_lv3 pd = {ST_VLOAD(ST_W, d[0]), ST_VLOAD(ST_W, d[1]), ST_VLOAD(ST_W, d[2])};
    pk->o = po;
    pk->d = pd;
    pk->live = live;
}

/* The triangle test of triangle j of leaf block l (n triangles) against
 * the packet's lanes: the lanes where it hits at t in (0, tmax), with t, u,
 * v. */
ST_HOT st_li st_packet_triangle(const ST_GLOBAL st_f32 *l, st_u32 n, st_u32 j, const st_packet *pk,
                                st_lf tmax, st_lf *tt, st_lf *uu, st_lf *vv)
{
    const ST_GLOBAL st_f32 *lane = l + j;
    st_lv3 v0 = {(st_lf)(lane[ST_LEAF_V0 * n]), (st_lf)(lane[(ST_LEAF_V0 + 1) * n]),
                 (st_lf)(lane[(ST_LEAF_V0 + 2) * n])};
    st_lv3 e1 = {(st_lf)(lane[ST_LEAF_E1 * n]), (st_lf)(lane[(ST_LEAF_E1 + 1) * n]),
                 (st_lf)(lane[(ST_LEAF_E1 + 2) * n])};
    st_lv3 e2 = {(st_lf)(lane[ST_LEAF_E2 * n]), (st_lf)(lane[(ST_LEAF_E2 + 1) * n]),
                 (st_lf)(lane[(ST_LEAF_E2 + 2) * n])};
    st_li two_sided = (st_li)((st_leaf_sides(l, n) >> j) & 1u ? 0 : -1);
    return ST_CAT(st_triangle_test, ST_W)(pk->o, pk->d, v0, e1, e2, tmax, (st_li)(-1), two_sided,
                                          tt, uu, vv);
}

/* The children of wide node n that some live lane enters (bit k for child
 * k; lane j with its own search bound tmax[j]), and per child the least
 * entry distance over the lanes that enter it (+inf where none does). */
ST_HOT st_u32 st_packet_node(const ST_GLOBAL st_bvh_wide_node *n, const st_packet *pk,
                             const st_f32 *tmax, st_u32 lanes, st_f32 *near)
{
    st_u32 mask = 0u;
    ST_VEC(float, ST_BVH_WIDTH) nearest = (ST_VEC(float, ST_BVH_WIDTH))(INFINITY);
    for (; lanes != 0u; lanes &= lanes - 1u) {
        st_u32 j = st_trace_lowest(lanes);
        st_f32 tn[ST_BVH_WIDTH];
        st_u32 m = st_trace_box4(n, &pk->r[j], tmax[j], tn);
        nearest = ST_SELECT(ST_BVH_WIDTH, nearest, fmin(nearest, ST_VLOAD(ST_BVH_WIDTH, tn)),
                            ST_BITS_MASK(ST_BVH_WIDTH, m));
        mask |= m;
    }
    ST_VSTORE(ST_BVH_WIDTH, nearest, near);
    return mask;
}

/* The largest of the live lanes' bounds (a popped node whose entry lies
 * beyond it is skipped for all of them). */
ST_HOT st_f32 st_packet_max(st_lf t, st_u32 live)
{
    return ST_HMAX(ST_W, ST_SELECT(ST_W, (st_lf)(-INFINITY), t, ST_BITS_MASK(ST_W, live)));
}

/* A packet's closest hits, lane j as st_intersect_wide_closest's for ray j (the
 * contract above): hit t, u, v and prim per lane; prim ST_NO_HIT and t =
 * tmax on a miss. Lanes not live come back as misses. */
typedef struct st_packet_hits {
    st_lf t, u, v;
    st_lu prim;
} st_packet_hits;

ST_HOT void st_packet_closest(const ST_GLOBAL st_bvh_wide_node *nodes, const st_packet *pk,
                              st_lf tmax, st_packet_hits *h)
{
    st_u32 stack[ST_BVH_WIDE_STACK];
    st_f32 entry[ST_BVH_WIDE_STACK], bound[ST_PACKET];
    st_u32 sp = 0u, node = 0u;
    h->t = tmax;
    h->u = h->v = (st_lf)(0.0f);
    h->prim = (st_lu)(ST_NO_HIT);
    ST_VSTORE(ST_W, tmax, bound);
    st_f32 reach = st_packet_max(tmax, pk->live);
    for (;;) {
        const ST_GLOBAL st_bvh_wide_node *n = st_trace_node(nodes, node);
        st_f32 near[ST_BVH_WIDTH];
        st_u32 mask = st_packet_node(n, pk, bound, pk->live, near), base = sp, leaves = 0u;
        st_u32 next = 0u;
        st_f32 next_e = 0.0f;
        for (; mask != 0u; mask &= mask - 1u) {
            st_u32 k = st_trace_lowest(mask);
            st_u32 first = n->child[k], count = n->count[k];
            const ST_GLOBAL st_f32 *l = st_trace_leaf(nodes, first);
            for (st_u32 j = 0u; j < count; ++j) {
                st_lf t = h->t, u = h->u, v = h->v;
                st_li ok = st_packet_triangle(l, count, j, pk, h->t, &t, &u, &v);
                h->t = ST_SELECT(ST_W, h->t, t, ok);
                h->u = ST_SELECT(ST_W, h->u, u, ok);
                h->v = ST_SELECT(ST_W, h->v, v, ok);
                h->prim = ST_SELECT(ST_W, h->prim, (st_lu)(st_leaf_first(l, count) + j), ok);
            }
            leaves |= count;
            if (count != 0u)
                continue;
            st_trace_prefetch_node(st_trace_node(nodes, first));
            st_trace_order(stack, entry, base, &sp, &next, &next_e, first, near[k]);
        }
        if (leaves != 0u) {
            ST_VSTORE(ST_W, h->t, bound);
            reach = st_packet_max(h->t, pk->live);
        }
        if (next != 0u && next_e <= reach * ST_TRACE_SLAB_WIDEN) {
            node = next;
            continue;
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
 * st_intersect_wide_any): a lane stops taking part once blocked, the packet
 * once all are. Children nearest first (by the packet's nearest entry), as
 * the closest-hit walk takes them: the shadow rays of camera hits on the
 * icosphere inside the Cornell box took about a quarter less time than in
 * the order the node lists them. */
ST_HOT st_u32 st_packet_occluded(const ST_GLOBAL st_bvh_wide_node *nodes, const st_packet *pk,
                                 st_lf tmax)
{
    st_u32 stack[ST_BVH_WIDE_STACK];
    st_f32 entry[ST_BVH_WIDE_STACK], bound[ST_PACKET];
    st_u32 sp = 0u, node = 0u, open = pk->live;
    ST_VSTORE(ST_W, tmax, bound);
    for (;;) {
        const ST_GLOBAL st_bvh_wide_node *n = st_trace_node(nodes, node);
        st_f32 near[ST_BVH_WIDTH];
        st_u32 mask = st_packet_node(n, pk, bound, open, near), next = 0u, base = sp;
        st_f32 next_e = 0.0f;
        for (; mask != 0u; mask &= mask - 1u) {
            st_u32 k = st_trace_lowest(mask);
            st_u32 first = n->child[k], count = n->count[k];
            for (st_u32 j = 0u; j < count; ++j) {
                st_lf t = tmax, u, v;
                open &= ~ST_MASK_BITS(ST_W, st_packet_triangle(st_trace_leaf(nodes, first), count,
                                                               j, pk, tmax, &t, &u, &v));
                if (open == 0u)
                    return pk->live;
            }
            if (count == 0u) {
                st_trace_prefetch_node(st_trace_node(nodes, first));
                st_trace_order(stack, entry, base, &sp, &next, &next_e, first, near[k]);
            }
        }
        if (next != 0u) {
            node = next;
            continue;
        }
        if (sp == 0u)
            return pk->live & ~open;
        node = stack[--sp];
    }
}

/* The packet kernels (trace_rays_packet in trace.cl,
 * trace_shadow_rays_packet in kernels/integrator/shadow.cl): work-item g takes positions W g .. W g + W - 1 of the
 * vertex's live paths (W = ST_W), lane j the item at position W g + j; the
 * host launches ceil(st_live_count / W) work-items (src/render/render.c), so
 * the last packet's lanes past the count are masked. */
static st_u32 packet_first(void) { return ST_ITEM() * ST_PACKET; }

#define ST_NO_ITEM 0xffffffffu /* a packet lane past the live paths */

/* The items of the packet at positions first .. first + ST_PACKET - 1. */
static void packet_items(const st_params *p, __global const st_u32 *live_a,
                         __global const st_u32 *live_b, st_u32 first, st_u32 item[ST_PACKET])
{
    __global const st_u32 *list = st_live_list(p, live_a, live_b);
    st_u32 n = st_live_count(p);
    /* two loops, not st_live_item's select: see shade_lanes (shade.cl) on
     * the masked load from the null list that the select became */
    if (list) {
        ST_UNROLL
        for (st_u32 j = 0u; j < ST_PACKET; ++j)
            item[j] = first + j < n ? list[first + j] : ST_NO_ITEM;
    } else {
        ST_UNROLL
        for (st_u32 j = 0u; j < ST_PACKET; ++j)
            item[j] = first + j < n ? first + j : ST_NO_ITEM;
    }
}

/* Lane j's ray *r, a copy of *w, and its bound *tmax (-1, below every hit,
 * for a lane not taken); returns take as the lane's bit. */
ST_HOT st_u32 packet_lane(st_ray *r, float *tmax, __global const st_ray *w, int take)
{
    *r = *w;
    r->tmax = *tmax = take ? w->tmax : -1.0f;
    return take ? 1u : 0u;
}

#endif
