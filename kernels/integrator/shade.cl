/* shade.cl — one path vertex per work-item: emission (with MIS), next-event
 * estimation towards the emissive triangles, and the next bounce.
 *
 * Integrators (pbrt's conventions; pbr-book 4ed §13.4):
 *  direct: the emission seen at the camera hit plus area-light sampling at
 *          that hit (no bounce), so shadows are soft.
 *  path:   at each vertex, next-event estimation and cosine-weighted BSDF
 *          sampling combined by multiple importance sampling with the power
 *          heuristic (Veach & Guibas, SIGGRAPH 1995); Russian roulette from
 *          the fourth vertex on. max_depth counts the vertices at which light
 *          is gathered (pbrt's maxdepth; Mitsuba's max_depth is one more).
 * Materials: the glTF metallic-roughness BRDF (bsdf.h; a Lambertian one,
 * specularFactor 0, takes the cheap cosine path), its factors times their
 * textures (texture.h); KHR_materials_unlit shows its base colour from
 * either side and ends the path; emitters are one-sided on the side their
 * shading normals face. Alpha MASK cut-outs and
 * BLEND (as stochastic coverage: a ray passes with probability 1 - alpha)
 * let the ray go on through the surface without a bounce: the path keeps its
 * depth but spends one of the wave's trace iterations; shadow rays treat
 * such surfaces as opaque.
 * Environment (st_shading.env: a uniform radiance, or a map, --env FILE:
 * envmap.h): a path that leaves the scene adds beta x its radiance. Next-
 * event estimation samples it too, choosing between it and the area lights
 * by power (st_shading.env_pick; dimension 0 rescaled): a uniform one by a
 * cosine-distributed direction, a map by its luminance (envmap.h), and a
 * shadow ray to infinity adds beta x f cos / (pdf x choice) x radiance when
 * unoccluded. In the path integrator that sample and the BSDF sample are
 * weighted by the power heuristic (at a miss the map gives its pdf of the
 * ray's direction; for a uniform one st_path.env_pdf keeps the cosine pdf
 * of the BSDF sample's direction); the area-light samples likewise.
 * Punctual lights (KHR_lights_punctual; st_shading.punct_count): with
 * probability punct_share next-event estimation takes one of them instead
 * (chosen by power from punct_cdf, dimension 0 rescaled), as a delta light
 * without MIS; the environment and area-light pdfs that MIS weighs are then
 * scaled by 1 - punct_share, the probability of the strategies that make them.
 * Texture level of detail: ray cones (texture.h) of the pixel's spread angle
 * 2 tan(yfov/2) / height (Akenine-Moller et al. 2019, eq. 30, small-angle
 * form), widening along the path's unfolded length, kept as the ray's
 * path_length (surfaces taken as flat: no curvature or BSDF spread); an orthographic
 * camera's cone has the pixel's width and no spread.
 * Sample dimensions of vertex k: 2 + 6k + {0: light choice and first
 * coordinate on it (or the environment direction's first), 1: second
 * coordinate, 2,3: BSDF direction (2 also picks the lobe), 4: unused,
 * 5: Russian roulette}. BLEND coverage draws from
 * the counter hash, keyed by the triangle. */
#include "st_shared.h"
#include "rng.h"
#include "samplers.h"
#include "trace.h"
#include "texture.h"
#include "lights.h"
#include "bsdf.h"
#include "integrator.h"
#include "shadow.h"
#include "shade_lanes.h"

/* A path that left the scene along d sees the environment, weighted by MIS
 * where next-event estimation samples it too (see the top). */
static void shade_miss(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                       st_walk *pa, float3 d)
{
    float3 env = vload4(0, sh->env).xyz;
    if (env.x > 0.0f || env.y > 0.0f || env.z > 0.0f) {
        float pdf_env = pa->env_pdf, choice = env_choice(sh);
        float3 le = env_radiance(s, sh, d, &pdf_env);
        float w = pa->depth > 0u && p->integrator == ST_INTEGRATOR_PATH && choice > 0.0f
                      ? power_heuristic(pa->bsdf_pdf, pdf_env * choice)
                      : 1.0f;
        pa->radiance = pa->radiance + pa->beta * le * w;
    }
    pa->depth = ST_PATH_DEAD;
}

/* The ray item i follows next: from o along d, path_length along the path. */
static void ray_store(__global st_wave_ray *r, float3 o, float3 d, float path_length)
{
    vstore3(o, 0, r->o);
    r->tmax = INFINITY;
    vstore3(d, 0, r->d);
    r->path_length = path_length;
}

/* The rest of a vertex on surface v after emission, alpha and unlit (see
 * shade_item): next-event estimation's shadow ray and the bounce, or the
 * path's end. */
static void shade_scatter(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                          st_surface *v, st_walk *pa, __global const st_sample *smp,
                          __global const st_u32 *pmj02, __global st_shadow_ray *shadow,
                          __global st_wave_ray *ray)
{
    if (pa->depth >= p->max_depth) {
        pa->depth = ST_PATH_DEAD;
        return;
    }
    surface_frame(v);
    st_sample_id id = st_sample_resume(p, smp->pixel, smp->index, smp->key, smp->word);
    id.pmj02 = pmj02;
    st_u32 dim = 2u + ST_DIMS_PER_VERTEX * pa->depth;
    float3 origin = v->pos + v->ng * p->ray_eps, wi;
    next_event(s, p, sh, v, pa, origin, &id, dim, shadow);
    if (p->integrator != ST_INTEGRATOR_PATH || !bsdf_bounce(p, v, pa, &id, dim, &wi) ||
        !roulette(p, pa, &id, dim)) {
        pa->depth = ST_PATH_DEAD;
    } else {
        ray_store(ray, origin, wi, v->travelled);
        pa->depth++;
    }
}

/* One vertex of item i's path, if live: reads hit, ray, path and sample;
 * adds the emission it sees to the path's radiance, writes the shadow ray of
 * next-event estimation (tmax 0: none) and the next ray, or ends the path
 * (depth ST_PATH_DEAD). Forced inline; the values p and sh by pointer: as
 * by-value parameters PoCL copied them for every work-item (callgrind). The
 * path, ray and sample are read field by field where used, never copied
 * whole into private structs (see st_walk). */
ST_HOT void shade_item(st_u32 i, const st_params *p,
                       const st_shading *sh ST_SCENE_BUFFERS(ST_SCENE_PARAM)
                           ST_WAVE_BUFFERS(ST_WAVE_PARAM))
{
    shadow[i].tmax = 0.0f;
    __global st_path *gp = &path[i];
    if (gp->depth == ST_PATH_DEAD)
        return;
    gp->closest_rays++;
    st_walk pa = walk_load(gp);
    st_hit h = hit[i];
    st_scene_refs s = ST_SCENE_REFS_INIT;
    __global st_wave_ray *r = &ray[i];
    float3 d = vload3(0, r->d);
    if (h.prim == ST_NO_HIT) {
        shade_miss(&s, p, sh, &pa, d);
        walk_store(gp, &pa);
        return;
    }
    st_sample smp = sample[i];
    st_surface v = surface_at_ray(&s, p, sh, vload3(0, r->o), d, r->path_length, h);
    if (alpha_passes(&s, p, &v, smp, h.prim, pa.depth)) { /* go on through */
        ray_store(r, v.pos - v.wo * p->ray_eps, -v.wo, v.travelled);
        return;
    }
    if (v.unlit) { /* KHR_materials_unlit: its colour, from either side, and no more */
        pa.radiance = pa.radiance + pa.beta * v.base.xyz;
        pa.depth = ST_PATH_DEAD;
        walk_store(gp, &pa);
        return;
    }
    float cos_o = dot(v.ng, v.wo);
    float we = emission_weight(&s, sh, &v, &pa, h, cos_o);
    if (we > 0.0f)
        pa.radiance = pa.radiance + pa.beta * v.le * we;
    if (cos_o < 0.0f) /* shade the side the ray arrived on */
        v.ng = -v.ng;
    if (dot(v.ns, v.ng) < 0.0f)
        v.ns = -v.ns;
    shade_scatter(&s, p, sh, &v, &pa, &sample[i], pmj02, &shadow[i], r);
    walk_store(gp, &pa);
}

/* The stage's arguments, passed on to shade_item. */
#define ST_ARG(name, ...) , name
#define ST_STAGE_ARGS &p, &sh ST_SCENE_BUFFERS(ST_ARG) ST_WAVE_BUFFERS(ST_ARG)

/* One vertex of every live path (shade_item); its shadow ray is traced by
 * the next stage, trace_shadow_rays (the default: render.c). */
__kernel void shade_hits(ST_STAGE_PARAMS)
{
    st_u32 i = get_global_id(0);
    if (i < p.item_count)
        shade_item(i, ST_STAGE_ARGS);
}

/* shade_hits and trace_shadow_rays in one work-item: the shadow ray is
 * traced at once, while the vertex is fresh (only when asked: on PoCL it ran
 * more instructions than the two stages; render.c). The same floats
 * are added in the same order, so the film is the same. */
__kernel void shade_hits_shadowed(ST_STAGE_PARAMS)
{
    st_u32 i = get_global_id(0);
    if (i >= p.item_count)
        return;
    shade_item(i, ST_STAGE_ARGS);
    st_scene_refs sc = ST_SCENE_REFS_INIT;
    trace_shadow_item(nodes, &sc, &p, &sh, shadow, path, sample, i);
}

/* Fast lane k's results into item i: what shade_item leaves at a direct
 * render's first vertex (the shadow ray or none, the radiance, the path
 * ended, one more closest ray). */
ST_HOT void shade_lanes_store(st_u32 i, st_u32 k, float (*rad)[ST_W], float (*org)[ST_W],
                              float (*dir)[ST_W], float (*con)[ST_W], const float *tmax,
                              __global st_shadow_ray *shadow, __global st_path *path)
{
    __global st_shadow_ray *sr = &shadow[i];
    sr->tmax = 0.0f;
    if (tmax[k] > 0.0f) {
        vstore3((float3)(org[0][k], org[1][k], org[2][k]), 0, sr->o);
        sr->tmax = tmax[k];
        vstore3((float3)(dir[0][k], dir[1][k], dir[2][k]), 0, sr->d);
        vstore3((float3)(con[0][k], con[1][k], con[2][k]), 0, sr->contribution);
    }
    __global st_path *gp = &path[i];
    gp->closest_rays++;
    vstore3((float3)(rad[0][k], rad[1][k], rad[2][k]), 0, gp->radiance);
    gp->depth = ST_PATH_DEAD;
}

/* A 3-vector of lanes into three arrays of ST_W floats. */
ST_HOT void lv3_store(st_lv3 v, float (*out)[ST_W])
{
    ST_VSTORE(ST_W, v.x, out[0]);
    ST_VSTORE(ST_W, v.y, out[1]);
    ST_VSTORE(ST_W, v.z, out[2]);
}

/* The fast lanes (bit k of `fast`: item first + k) of one work-item of
 * shade_hits_lanes (shade_lanes.h); returns the lanes it shaded (those whose
 * normal PoCL's normalize would not rescale). */
ST_HOT st_u32 shade_lanes_run(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                              st_u32 first, st_u32 n, st_u32 fast,
                              __global const st_sample *sample, __global const st_wave_ray *ray,
                              __global const st_hit *hit, __global st_path *path,
                              __global st_shadow_ray *shadow, __global const st_u32 *pmj02)
{
    st_shade_lanes l;
    for (st_u32 k = 0; k < ST_W; k++)
        shade_lanes_gather(s, p, first + (k < n ? k : 0u), (fast >> k) & 1u, k, sample, ray, hit,
                           path, pmj02, &l);
    if (p->sampler == ST_SAMPLER_RANDOM) { /* dimensions 2 and 3: vertex 0's light sample */
        st_lu key = ST_VLOAD(ST_W, l.key);
        ST_VSTORE(ST_W, rng_unit_lanes(key, 2u), l.u);
        ST_VSTORE(ST_W, rng_unit_lanes(key, 3u), l.u2);
    }
    for (st_u32 k = 0; k < ST_W; k++)
        shade_lanes_gather_light(s, p, sh, k, &l);
    st_shade_lanes_out o;
    st_lv3 ns, ng;
    shade_lanes_surface(&l, p->ray_eps, &ns, &ng, &o);
    shade_lanes_light(&l, p, sh, ns, ng, &o);
    float rad[3][ST_W], org[3][ST_W], dir[3][ST_W], con[3][ST_W], tmax[ST_W];
    int ok[ST_W];
    lv3_store(o.radiance, rad);
    lv3_store(o.origin, org);
    lv3_store(o.wi, dir);
    lv3_store(o.contribution, con);
    ST_VSTORE(ST_W, o.tmax, tmax);
    ST_VSTORE(ST_W, o.fast, ok);
    for (st_u32 k = 0; k < ST_W; k++) {
        if (!ok[k])
            fast &= ~(1u << k);
        if ((fast >> k) & 1u)
            shade_lanes_store(first + k, k, rad, org, dir, con, tmax, shadow, path);
    }
    return fast;
}

/* shade_hits for ST_W items per work-item (global size item_count / ST_W
 * rounded up): work-item g shades items W g .. W g + W - 1, the fast lanes
 * in lanes (shade_lanes.h), every other by shade_item, so the film is
 * shade_hits' at every width (the plan chooses, src/plan.c; test
 * shade_lanes_equal_shade_hits in tests/test_render_paths.c). */
__kernel void shade_hits_lanes(ST_STAGE_PARAMS)
{
    st_u32 first = ST_W * get_global_id(0);
    if (first >= p.item_count)
        return;
    st_u32 n = min((st_u32)ST_W, p.item_count - first), fast = 0u;
    st_scene_refs s = ST_SCENE_REFS_INIT;
    if (st_shade_lanes_render_fast(&p, &sh))
        for (st_u32 k = 0; k < n; k++)
            fast |= (st_u32)shade_lanes_item_fast(&s, first + k, path, hit) << k;
    if (fast)
        fast = shade_lanes_run(&s, &p, &sh, first, n, fast, sample, ray, hit, path, shadow, pmj02);
    for (st_u32 k = 0; k < n; k++)
        if (!((fast >> k) & 1u))
            shade_item(first + k, ST_STAGE_ARGS);
}
