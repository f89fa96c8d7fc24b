/* trace.cl — closest-hit queries through the BVH, one ray a work-item or a
 * packet of them (trace.h holds the traversal, shared with the host's
 * reference tests; packet.h the packets'). The queries that need shading's
 * state (shadow rays through alpha cut-outs, the last vertex's look at the
 * lights) are the integrator's: kernels/integrator/shadow.cl. */
#include "st_shared.h"
#include "trace.h"
#include "packet.h"

/* How far ahead of its own item a work-item of a sorted trace asks for the
 * hit record of a later one: sorted, the items lie anywhere in the wave, and
 * each hit would be a miss to wait for (their rays are in order_ray, in
 * the trace's order, and a dead path is marked in `order`, so that the
 * trace does not read the paths). */
#define ST_ORDER_AHEAD 16u

/* Work-item g: the live path at position g of the vertex's list (st_live_item),
 * or of the rays sorted by order.cl (p.ordered: its ray from order_ray).
 * Reads ray, and path where there is no list (depth ST_PATH_DEAD: skip; a
 * list, live.cl's, holds live paths alone, and sorted, ST_ORDER_DEAD marks
 * the dead); writes hit (prim ST_NO_HIT on a miss). */
__kernel void trace_rays(ST_STAGE_PARAMS)
{
    st_u32 g = ST_ITEM(), n = st_live_count(&p);
    if (g >= n)
        return;
    st_u32 i;
    st_ray r;
    if (p.ordered) {
        if (g + ST_ORDER_AHEAD < n)
            ST_PREFETCH(&hit[order[g + ST_ORDER_AHEAD] & ~ST_ORDER_DEAD]);
        i = order[g];
        if (i & ST_ORDER_DEAD)
            return;
        r = order_ray[g];
    } else {
        __global const st_u32 *list = st_live_list(&p, live_a, live_b);
        i = st_live_item(list, g);
        if (!list && path[i].depth == ST_PATH_DEAD)
            return;
        r = ray[i];
    }
    st_hit h;
    if (!st_intersect_wide_closest(nodes, &r, &h))
        h.prim = ST_NO_HIT;
    hit[i] = h;
}

/* trace_rays over a packet: the same hits, written for the same items (the
 * live ones: below item_count, path alive). */
__kernel void trace_rays_packet(ST_STAGE_PARAMS)
{
    st_u32 first = packet_first(), live = 0u, item[ST_PACKET];
    st_ray r[ST_PACKET];
    float tmax[ST_PACKET];
    packet_items(&p, live_a, live_b, first, item);
    ST_UNROLL
    for (st_u32 j = 0u; j < ST_PACKET; ++j) {
        st_u32 i = item[j];
        int take = i != ST_NO_ITEM && path[i].depth != ST_PATH_DEAD;
        __global const st_ray *w = &ray[take ? i : 0u];
        live |= packet_lane(&r[j], &tmax[j], w, take) << j;
    }
    if (live == 0u)
        return;
    st_packet pk;
    st_packet_hits h;
    st_packet_setup(&pk, r, live);
    st_packet_closest(nodes, &pk, ST_VLOAD(ST_W, tmax), &h);
    float t[ST_PACKET], u[ST_PACKET], v[ST_PACKET];
    uint prim[ST_PACKET];
    ST_VSTORE(ST_W, h.t, t);
    ST_VSTORE(ST_W, h.u, u);
    ST_VSTORE(ST_W, h.v, v);
    ST_VSTORE(ST_W, h.prim, prim);
    ST_UNROLL
    for (st_u32 j = 0u; j < ST_PACKET; ++j)
        if ((live >> j) & 1u) {
            st_hit o = {t[j], u[j], v[j], prim[j]};
            hit[item[j]] = o;
        }
}
