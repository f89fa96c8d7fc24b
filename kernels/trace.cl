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

/* Reads ray and path (depth ST_PATH_DEAD: skip); writes hit (prim ST_NO_HIT
 * on a miss). */
__kernel void trace_rays(ST_STAGE_PARAMS)
{
    st_u32 i = get_global_id(0);
    if (i >= p.item_count || path[i].depth == ST_PATH_DEAD)
        return;
    st_wave_ray w = ray[i];
    st_ray r;
    r.o[0] = w.o[0]; r.o[1] = w.o[1]; r.o[2] = w.o[2];
    r.d[0] = w.d[0]; r.d[1] = w.d[1]; r.d[2] = w.d[2];
    r.tmax = w.tmax;
    st_hit h;
    if (!st_intersect4_closest(nodes, tris, &r, &h))
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
