/* trace.cl — closest-hit and any-hit queries through the BVH (trace.h holds
 * the traversal, shared with the host's reference tests; shadow.h lets
 * shadow rays through alpha cut-outs). */
#include "st_shared.h"
#include "rng.h"
#include "samplers.h"
#include "trace.h"
#include "texture.h"
#include "lights.h"
#include "bsdf.h"
#include "integrator.h"
#include "shadow.h"
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

/* trace_rays for the rays of the last vertex (depth max_depth), which adds
 * only the light it sees (shade.cl: an emitter's emission, or the
 * environment's), where the plan finds every emitter in the light list
 * (src/render/plan.c): the ray is tested against those triangles alone
 * (st_intersect_triangle, the leaves' test bit for bit), then for any
 * occluder before the nearest of them, or before the environment. Where
 * it sees light, the hit is the traversal's (that emitter's, or a miss);
 * where it sees none, shade would add nothing, so the path ends here (its
 * ray counted, as shade counts it). */
__kernel void trace_rays_last(ST_STAGE_PARAMS)
{
    st_u32 g = ST_ITEM();
    if (g >= st_live_count(&p))
        return;
    st_u32 i = st_live_item(st_live_list(&p, live_a, live_b), g);
    __global st_path *pa = &path[i];
    if (pa->depth == ST_PATH_DEAD)
        return;
    st_ray r = ray[i];
    st_hit h = {r.tmax, 0.0f, 0.0f, ST_NO_HIT};
    if (pa->depth < p.max_depth) { /* not the last vertex: the traversal */
        if (!st_intersect_wide_closest(nodes, &r, &h))
            h.prim = ST_NO_HIT;
        hit[i] = h;
        return;
    }
    for (st_u32 k = 0u; k < p.light_count; k++)
        st_intersect_triangle(&tris[light_tri[k]], &r, light_tri[k], &h);
    int lit = h.prim != ST_NO_HIT || env_lit(&sh);
    r.tmax = h.t;
    if (lit && !st_intersect_wide_any(nodes, &r)) {
        hit[i] = h;
        return;
    }
    pa->closest_rays++;
    pa->depth = ST_PATH_DEAD;
}

/* Reads the shadow ray (tmax 0: none); adds its contribution to the path's
 * radiance when nothing blocks it (shadow_blocked: alpha lets it through
 * cut-outs), and counts the ray. */
__kernel void trace_shadow_rays(ST_STAGE_PARAMS)
{
    st_u32 g = ST_ITEM();
    if (g >= st_live_count(&p))
        return;
    st_scene_refs sc = ST_SCENE_REFS_INIT;
    trace_shadow_item(nodes, &sc, &p, &sh, shadow, path, sample,
                      st_live_item(st_live_list(&p, live_a, live_b), g));
}

/* Packets (packet.h): work-item g takes positions W g .. W g + W - 1 of the
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

/* trace_shadow_rays over a packet, for scenes whose materials are all
 * opaque (the host's choice: any hit then blocks, so no lane needs
 * shadow_blocked's walk through alpha): the same radiance and counts as
 * trace_shadow_item, lane by lane. */
__kernel void trace_shadow_rays_packet(ST_STAGE_PARAMS)
{
    st_u32 first = packet_first(), live = 0u, item[ST_PACKET];
    st_ray r[ST_PACKET];
    float tmax[ST_PACKET];
    packet_items(&p, live_a, live_b, first, item);
    ST_UNROLL
    for (st_u32 j = 0u; j < ST_PACKET; ++j) {
        st_u32 i = item[j];
        __global const st_shadow *s = &shadow[i != ST_NO_ITEM ? i : 0u];
        int take = i != ST_NO_ITEM && s->ray.tmax > 0.0f;
        live |= packet_lane(&r[j], &tmax[j], &s->ray, take) << j;
    }
    if (live == 0u)
        return;
    st_packet pk;
    st_packet_setup(&pk, r, live);
    st_u32 blocked = st_packet_occluded(nodes, &pk, ST_VLOAD(ST_W, tmax));
    ST_UNROLL
    for (st_u32 j = 0u; j < ST_PACKET; ++j) {
        if (!((live >> j) & 1u))
            continue;
        __global st_path *pa = &path[item[j]];
        float3 l = (blocked >> j) & 1u ? (float3)(0.0f) : vload3(0, shadow[item[j]].contribution);
        vstore3(vload3(0, pa->radiance) + l, 0, pa->radiance);
        pa->shadow_rays++;
    }
}
