/* trace.cl — closest-hit and any-hit queries through the BVH (trace.h holds
 * the traversal, shared with the host's reference tests). */
#include "st_shared.h"
#include "trace.h"

/* Reads ray_o (w = tmax), ray_d, depth (ST_PATH_DEAD: skip); writes hit =
 * (t, u, v, triangle as bits), triangle ST_NO_HIT on a miss. */
__kernel void trace_rays(const st_params p, __global const st_bvh_node *nodes,
                         __global const st_triangle *tris, __global const float4 *ray_o,
                         __global const float4 *ray_d, __global const uint *depth,
                         __global float4 *hit)
{
    st_u32 i = get_global_id(0);
    if (i >= p.item_count || depth[i] == ST_PATH_DEAD)
        return;
    float4 o = ray_o[i], d = ray_d[i];
    st_ray r;
    r.o[0] = o.x; r.o[1] = o.y; r.o[2] = o.z;
    r.d[0] = d.x; r.d[1] = d.y; r.d[2] = d.z;
    r.tmax = o.w;
    st_hit h;
    if (!st_intersect_closest(nodes, tris, &r, &h))
        h.prim = ST_NO_HIT;
    hit[i] = (float4)(h.t, h.u, h.v, as_float(h.prim));
}

/* Reads the shadow ray (shadow_o.w = tmax, 0: none) and its unoccluded
 * contribution; adds that to radiance when nothing blocks the ray. */
__kernel void trace_shadow_rays(const st_params p, __global const st_bvh_node *nodes,
                                __global const st_triangle *tris,
                                __global const float4 *shadow_o,
                                __global const float4 *shadow_d,
                                __global const float4 *shadow_l, __global float4 *radiance)
{
    st_u32 i = get_global_id(0);
    if (i >= p.item_count)
        return;
    float4 o = shadow_o[i];
    if (!(o.w > 0.0f))
        return;
    float4 d = shadow_d[i];
    st_ray r;
    r.o[0] = o.x; r.o[1] = o.y; r.o[2] = o.z;
    r.d[0] = d.x; r.d[1] = d.y; r.d[2] = d.z;
    r.tmax = o.w;
    float3 l = st_intersect_any(nodes, tris, &r) ? (float3)(0.0f) : shadow_l[i].xyz;
    radiance[i] += (float4)(l, ST_SHADOW_RAY_UNIT); /* w counts rays traced */
}
