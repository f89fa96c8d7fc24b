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

/* Reads ray and path (depth ST_PATH_DEAD: skip); writes hit (prim ST_NO_HIT
 * on a miss). */
__kernel void trace_rays(ST_STAGE_PARAMS)
{
    st_u32 i = get_global_id(0);
    if (i >= p.item_count || path[i].depth == ST_PATH_DEAD)
        return;
    st_ray r = ray[i];
    st_hit h;
    if (!st_intersect_wide_closest(nodes, &r, &h))
        h.prim = ST_NO_HIT;
    hit[i] = h;
}

/* Reads the shadow ray (tmax 0: none); adds its contribution to the path's
 * radiance when nothing blocks it (shadow_blocked: alpha lets it through
 * cut-outs), and counts the ray. */
__kernel void trace_shadow_rays(ST_STAGE_PARAMS)
{
    st_u32 i = get_global_id(0);
    if (i >= p.item_count)
        return;
    st_scene_refs sc = ST_SCENE_REFS_INIT;
    trace_shadow_item(nodes, &sc, &p, &sh, shadow, path, sample, i);
}

/* Packets (packet.h): work-item g takes items W g .. W g + W - 1 of the
 * wave (W = ST_W), lane j item W g + j; the host launches ceil(item_count /
 * W) work-items (src/render/render.c), so the last packet's lanes past item_count
 * are masked. */
static st_u32 packet_first(void) { return (st_u32)get_global_id(0) * ST_PACKET; }

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
    st_u32 first = packet_first(), live = 0u;
    st_ray r[ST_PACKET];
    float tmax[ST_PACKET];
    for (st_u32 j = 0u; j < ST_PACKET; ++j) {
        st_u32 i = first + j;
        int take = i < p.item_count && path[i].depth != ST_PATH_DEAD;
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
    for (st_u32 j = 0u; j < ST_PACKET; ++j)
        if ((live >> j) & 1u) {
            st_hit o = {t[j], u[j], v[j], prim[j]};
            hit[first + j] = o;
        }
}

/* trace_shadow_rays over a packet, for scenes whose materials are all
 * opaque (the host's choice: any hit then blocks, so no lane needs
 * shadow_blocked's walk through alpha): the same radiance and counts as
 * trace_shadow_item, lane by lane. */
__kernel void trace_shadow_rays_packet(ST_STAGE_PARAMS)
{
    st_u32 first = packet_first(), live = 0u;
    st_ray r[ST_PACKET];
    float tmax[ST_PACKET];
    for (st_u32 j = 0u; j < ST_PACKET; ++j) {
        st_u32 i = first + j;
        __global const st_shadow *s = &shadow[i < p.item_count ? i : 0u];
        int take = i < p.item_count && s->ray.tmax > 0.0f;
        live |= packet_lane(&r[j], &tmax[j], &s->ray, take) << j;
    }
    if (live == 0u)
        return;
    st_packet pk;
    st_packet_setup(&pk, r, live);
    st_u32 blocked = st_packet_occluded(nodes, &pk, ST_VLOAD(ST_W, tmax));
    for (st_u32 j = 0u; j < ST_PACKET; ++j) {
        if (!((live >> j) & 1u))
            continue;
        __global st_path *pa = &path[first + j];
        float3 l = (blocked >> j) & 1u ? (float3)(0.0f) : vload3(0, shadow[first + j].contribution);
        vstore3(vload3(0, pa->radiance) + l, 0, pa->radiance);
        pa->shadow_rays++;
    }
}
