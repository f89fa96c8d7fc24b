/* shadow.cl — the integrator's queries through the BVH: shadow rays (one a
 * work-item through alpha cut-outs, shadow.h, or a packet of them for an
 * opaque scene, packet.h) and the last vertex's rays, which look at the
 * lights first. They read the materials and the lights, so they sit here,
 * above the traversal (kernels/geom/) they call. */
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

/* trace_rays for the rays of the last vertex (depth max_depth), which adds
 * only the light it sees (shade.cl: an emitter's emission, or the
 * environment's), where the plan finds every emitter in the light list
 * (src/render/plan.c): the ray is tested against those triangles alone
 * (st_list_closest at width 1, the leaves' test bit for bit, and in lanes
 * shade.cl's dark_bounces), then for any
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
    st_hit h;
    if (pa->depth < p.max_depth) { /* not the last vertex: the traversal */
        if (!st_intersect_wide_closest(nodes, &r, &h))
            h.prim = ST_NO_HIT;
        hit[i] = h;
        return;
    }
    st_v3x1 o = {r.o[0], r.o[1], r.o[2]}, d = {r.d[0], r.d[1], r.d[2]};
    int prim = (int)ST_NO_HIT;
    h.t = r.tmax;
    h.u = h.v = 0.0f;
    st_list_closest1(tris, light_tri, p.light_count, o, d, 1, &h.t, &h.u, &h.v, &prim);
    h.prim = (st_u32)prim;
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
