/* shade.cl — one path vertex of ST_W items per work-item (integrator.h: the
 * vertex written once over lanes): emission (with MIS), next-event
 * estimation, and the next bounce.
 *
 * Integrators (pbrt's conventions; pbr-book 4ed §13.4):
 *  direct: the emission seen at the camera hit, and at that hit one light
 *          sample (next-event estimation) and one BSDF sample, combined by
 *          multiple importance sampling with the power heuristic (Veach &
 *          Guibas, SIGGRAPH 1995), as pbrt-v4's and Mitsuba's direct
 *          integrators do: the BSDF sample's ray adds the emission it meets
 *          (or the environment's), weighted, and ends there. So smooth
 *          surfaces, which light sampling alone cannot resolve, reflect
 *          their lights, and shadows are soft.
 *  path:   at each vertex, next-event estimation and BSDF sampling combined
 *          the same way; Russian roulette from the third vertex on
 *          (drawn with its bounce: the fourth is the first vertex a path
 *          may not reach; Mitsuba's rr_depth 3 draws on reaching it).
 *          max_depth counts the vertices at which light is gathered (pbrt's
 *          maxdepth; Mitsuba's max_depth is one more): direct is a path of
 *          max_depth 1.
 * Materials: the glTF metallic-roughness BRDF (bsdf.h; a Lambertian one,
 * specularFactor 0, takes the cheap cosine path), with transmission
 * (bsdf_dielectric.h: the path refracts and goes on from the other side;
 * KHR_materials_volume's absorption on the segments inside), a sheen
 * (bsdf_sheen.h) and a clear coat (bsdf_coat.h) where the material has them, its factors times their
 * textures (texture.h). Next-event estimation samples lights on the side
 * the ray arrived from only; a refracted BSDF sample's emission takes MIS
 * weight 1 (bsdf_pdf 0: no light sample makes it). KHR_materials_unlit shows its base colour from
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
 * unoccluded. That sample and the BSDF sample are
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
 * coordinate, 2,3: BSDF direction (2 also picks the lobe), 4: reflection or
 * refraction (read only at a transmissive surface), 5: Russian roulette}. BLEND coverage draws from
 * the counter hash, keyed by the triangle. */
#include "st_shared.h"
#include "rng.h"
#include "samplers.h"
#include "trace.h"
#include "texture.h"
#include "lights.h"
#include "bsdf.h"
#include "bsdf_dielectric.h"
#include "bsdf_sheen.h"
#include "bsdf_coat.h"
#include "integrator.h"
#include "shadow.h"

/* The ray item i follows next: from o along d, path_length along the path. */
static void ray_store(__global st_ray *r, float3 o, float3 d, float path_length)
{
    vstore3(o, 0, r->o);
    r->tmax = INFINITY;
    vstore3(d, 0, r->d);
    r->path_length = path_length;
}

/* An AOV render's value (st_params.aov; ST_AOV_* in st_shared.h) at the hit
 * h of the camera ray from o along d, travelled long from the camera: the
 * base colour a.base, the interpolated vertex normal turned, as the
 * integrator turns it (vertex_surface), to the side of the geometric
 * normal ng that faces the ray, the hit point, or its distance (in R). */
static float3 aov_value(const st_params *p, st_hit h, float3 o, float3 d, float3 ng,
                        __global const st_tri_normals *n, const st_material_at *a,
                        float travelled)
{
    if (p->aov == ST_AOV_ALBEDO)
        return a->base.xyz;
    if (p->aov == ST_AOV_POSITION)
        return o + d * h.t;
    if (p->aov == ST_AOV_DEPTH)
        return (float3)(travelled, 0.0f, 0.0f);
    float3 ns = (1.0f - h.u - h.v) * vload4(0, n->n0).xyz + h.u * vload4(0, n->n1).xyz +
                h.v * vload4(0, n->n2).xyz;
    ns = normalize(ns);
    float3 facing = dot(ng, d) > 0.0f ? -ng : ng;
    return dot(ns, facing) < 0.0f ? -ns : ns;
}

/* Lane k's sample dimensions at its depth, where the vertex reads them
 * (integrator.h's u): 0 and 1 for next-event estimation, 2 and 3 for the
 * bounce, and 5 for Russian roulette where it plays. The random sampler's
 * are made in lanes instead (dims_random). */
static void dims_gather(const st_params *p, st_sample smp, __global const st_u32 *pmj02,
                        st_u32 depth, st_u32 k, int transmissive, st_vertex_in *l)
{
    if (p->sampler == ST_SAMPLER_RANDOM || depth >= p->max_depth)
        return;
    st_sample_id id = st_sample_resume(p, smp.pixel, smp.index, smp.key, smp.word);
    id.pmj02 = pmj02;
    st_u32 dim = 2u + ST_DIMS_PER_VERTEX * depth;
    l->u[0][k] = st_sample_dim(p, &id, dim);
    l->u[1][k] = st_sample_dim(p, &id, dim + 1u);
    l->u[2][k] = st_sample_dim(p, &id, dim + 2u);
    l->u[3][k] = st_sample_dim(p, &id, dim + 3u);
    if (transmissive)
        l->u[4][k] = st_sample_dim(p, &id, dim + 4u);
    if (depth + 1u >= ST_RR_START_DEPTH)
        l->u[5][k] = st_sample_dim(p, &id, dim + 5u);
}

/* dims_gather's dimensions for the random sampler, all lanes at once (4
 * only where some lane is transmissive). */
ST_HOT void dims_random(st_vertex_in *l, int transmissive)
{
    st_lu key = ST_LV(l->key), dim = 2u + ST_DIMS_PER_VERTEX * ST_LV(l->depth);
    for (st_u32 j = 0; j < 6u; j++)
        if (j != 4u)
            ST_VSTORE(ST_W, st_rng_unit_lanes(key, dim + j), l->u[j]);
    if (transmissive)
        ST_VSTORE(ST_W, st_rng_unit_lanes(key, dim + 4u), l->u[4]);
}

/* The material of triangle prim. */
static __global const st_material *m_of(const st_scene_refs *s, st_u32 prim)
{
    return &s->materials[s->tri_material[prim]];
}

/* The key of the draw of a dispersive path's colour channel. */
#define ST_DISPERSION_KEY 0xd15e0000u

/* KHR_materials_dispersion at lane k's hit (path gp, its throughput beta
 * gathered): an RGB renderer refracts one wavelength per channel, so a
 * path that meets its first dispersive surface draws one channel c
 * uniformly (from the counter hash of the sample, keyed by the depth) and
 * carries 3 x that channel alone from then on (E[3 f_c e_c] = Σ_c f_c e_c);
 * there and at every later dispersive surface the lane refracts with c's
 * ior (st_dispersed_ior). Returns the throughput. */
static float3 dispersed(const st_params *p, st_sample smp, __global st_path *gp, float dispersion,
                        st_u32 depth, float3 beta, st_u32 k, st_vertex_in *l)
{
    st_u32 c = gp->channel;
    if (c == 0u) {
        float u = st_rng_unit(st_rng_key(p->seed ^ ST_DISPERSION_KEY, smp.pixel, smp.index), depth);
        c = 1u + min((st_u32)(3.0f * u), 2u);
        gp->channel = c;
        beta = 3.0f * (float3)(c == 1u ? 1.0f : 0.0f, c == 2u ? 1.0f : 0.0f, c == 3u ? 1.0f : 0.0f) *
               beta;
        set_lane3(l->beta, k, beta);
    }
    l->ior[k] = st_dispersed_ior(l->ior[k], dispersion, c - 1u);
    return beta;
}

/* The lanes' kinds, lane k bit k (vertex_gather sets them). */
typedef struct st_lane_bits {
    st_u32 miss, nmapped, trans, thin, coated, cmapped, sheened, aniso, dtrans, irid;
    st_u32 through; /* went on through a cut-out, not shaded */
} st_lane_bits;

/* Every row of the lanes' inputs holds a number in every lane, as if the
 * struct began zeroed: the lanes' arithmetic reads all lanes, and masks only
 * drop the results (a lane left unwritten would branch on undefined values:
 * Oclgrind reports it). Zeroing all of st_vertex_in cost each work-item a
 * memset of 72 rows, so the rows are cleared by who writes them: the rows a
 * gathered hit writes only sometimes (its sample dimensions, light sample,
 * normal map, coat) in lanes, before the gather (vertex_clear_some); the
 * rest only in the lanes no gather filled, after it (vertex_clear_lane).
 * A row added to st_vertex_in must join one of the two. */
ST_HOT void vertex_clear_some(st_vertex_in *l)
{
    st_lf z = ST_LF(0.0f);
    for (int j = 0; j < 6; j++)
        ST_VSTORE(ST_W, z, l->u[j]);
    for (int a = 0; a < 3; a++) {
        ST_VSTORE(ST_W, z, l->lp[a]);
        ST_VSTORE(ST_W, z, l->ll[a]);
        ST_VSTORE(ST_W, z, l->lnl[a]);
        ST_VSTORE(ST_W, z, l->nmap[a]);
        ST_VSTORE(ST_W, z, l->cnmap[a]);
    }
    ST_VSTORE(ST_W, z, l->lq);
    ST_VSTORE(ST_W, z, l->lco);
    ST_VSTORE(ST_W, z, l->lci);
    ST_VSTORE(ST_W, (st_li)(0), l->lkind);
    ST_VSTORE(ST_W, z, l->nscale);
    ST_VSTORE(ST_W, z, l->cnscale);
    ST_VSTORE(ST_W, z, l->coat);
    ST_VSTORE(ST_W, z, l->coat_rough);
}

/* Lane k's rows that a hit's gather writes (a miss's writes none of them);
 * with `path`, also those every gathered lane writes, hit or miss (for a
 * lane that no gather took to the end). */
ST_HOT void vertex_clear_lane(st_vertex_in *l, st_u32 k, int path)
{
    float3 z = (float3)(0.0f);
    set_lane3(l->o, k, z);
    set_lane3(l->d, k, z);
    set_lane3(l->n0, k, z);
    set_lane3(l->n1, k, z);
    set_lane3(l->n2, k, z);
    set_lane3(l->ng, k, z);
    set_lane3(l->base, k, z);
    l->t[k] = l->bu[k] = l->bv[k] = l->travelled[k] = 0.0f;
    l->metallic[k] = l->roughness[k] = l->ior[k] = l->transmission[k] = 0.0f;
    for (int j = 0; j < 4; j++)
        l->spec[j][k] = 0.0f;
    l->key[k] = l->prim[k] = 0u;
    if (!path)
        return;
    set_lane3(l->beta, k, z);
    set_lane3(l->rad, k, z);
    set_lane3(l->le, k, z);
    l->bsdf_pdf[k] = l->emit_pdf[k] = 0.0f;
    l->depth[k] = 0u;
}

/* Lane k's part of the vertex of item i: the shadow ray cleared; a dead
 * path left alone; a ray that goes on through a cut-out and a
 * KHR_materials_unlit surface (its colour, from either side, and no more)
 * done here. Otherwise the lane's inputs are gathered (bit k of b->miss set
 * for a ray that left the scene, of b->nmapped for a normal-mapped surface,
 * of b->trans for a transmissive one, of b->coated for a clear-coated one,
 * of b->sheened for one with a sheen, which sheen_gather reads, of
 * b->aniso for an anisotropic one, which aniso_gather reads, of b->dtrans
 * for one with diffuse transmission, which dtrans_gather reads, of b->irid
 * for an iridescent one, which irid_gather reads)
 * and it returns 1: the lanes do the rest. */
ST_HOT int vertex_gather(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                         st_u32 i, st_u32 k, __global const st_sample *sample,
                         __global st_ray *ray, __global const st_hit *hit,
                         __global st_path *path, __global st_shadow *shadow,
                         __global const st_u32 *pmj02, st_vertex_in *l, st_lane_bits *b)
{
    shadow[i].ray.tmax = 0.0f;
    __global st_path *gp = &path[i];
    st_u32 depth = gp->depth;
    if (depth == ST_PATH_DEAD)
        return 0;
    gp->closest_rays++;
    st_hit h = hit[i];
    __global st_ray *r = &ray[i];
    float3 o = vload3(0, r->o), d = vload3(0, r->d), beta = vload3(0, gp->beta);
    set_lane3(l->beta, k, beta);
    set_lane3(l->rad, k, vload3(0, gp->radiance));
    l->bsdf_pdf[k] = gp->bsdf_pdf;
    l->depth[k] = depth;
    if (h.prim == ST_NO_HIT && p->aov != ST_AOV_NONE) { /* an AOV of nothing: 0 */
        gp->depth = ST_PATH_DEAD;
        return 0;
    }
    if (h.prim == ST_NO_HIT) { /* the environment, weighed in lanes (seen_emission) */
        float pdf = gp->env_pdf;
        float3 le = env_lit(sh) ? env_radiance(s, sh, d, &pdf) : (float3)(0.0f);
        set_lane3(l->le, k, le);
        l->emit_pdf[k] = pdf * env_choice(sh);
        b->miss |= 1u << k;
        return 1;
    }
    float travelled = r->path_length + h.t;
    /* the ray's, the hit's and the triangle's rows first, while they are in
     * registers: stored after the material's early ends, they were kept
     * across material_at and spilled (a lane that ends below is not live,
     * and vertex_clear_lane clears its rows again) */
    set_lane3(l->o, k, o);
    set_lane3(l->d, k, d);
    l->t[k] = h.t, l->bu[k] = h.u, l->bv[k] = h.v;
    l->travelled[k] = travelled;
    l->prim[k] = h.prim;
    __global const st_tri_normals *n = &s->normals[h.prim];
    set_lane3(l->n0, k, vload4(0, n->n0).xyz);
    set_lane3(l->n1, k, vload4(0, n->n1).xyz);
    set_lane3(l->n2, k, vload4(0, n->n2).xyz);
    float3 ng = facing_normal(s->normals, h.prim), pos = o + d * h.t;
    set_lane3(l->ng, k, ng);
    st_material_at a = material_at(s, p, sh, h, dot(ng, -d), travelled);
    st_sample smp = sample[i];
    if (alpha_passes_keyed(p, &a, smp, h.prim, depth, ST_PATH_ALPHA_KEY)) { /* go on through */
        ray_store(r, pos + d * p->ray_eps, d, travelled);
        b->through |= 1u << k;
        return 0;
    }
    if (p->aov != ST_AOV_NONE) { /* what the camera ray sees, and no more */
        vstore3(aov_value(p, h, o, d, ng, n, &a, travelled), 0, gp->radiance);
        gp->depth = ST_PATH_DEAD;
        return 0;
    }
    if (a.flags & ST_MAT_UNLIT) {
        vstore3(vload3(0, gp->radiance) + beta * a.base.xyz, 0, gp->radiance);
        gp->depth = ST_PATH_DEAD;
        return 0;
    }
    if (depth >= p->max_depth && !(a.le.x > 0.0f || a.le.y > 0.0f || a.le.z > 0.0f)) {
        /* the last vertex adds what it sees emitted (seen_emission), here
         * nothing: the path ends without the lanes, as most of direct
         * lighting's BSDF samples do */
        gp->depth = ST_PATH_DEAD;
        return 0;
    }
    l->key[k] = smp.key;
    set_lane3(l->base, k, a.base.xyz);
    set_lane3(l->le, k, a.le);
    l->metallic[k] = a.metallic, l->roughness[k] = a.roughness, l->ior[k] = a.ior;
    l->spec[0][k] = a.spec.x, l->spec[1][k] = a.spec.y, l->spec[2][k] = a.spec.z;
    l->spec[3][k] = a.spec.w;
    l->emit_pdf[k] = s->light_pdf[h.prim];
    l->transmission[k] = a.transmission;
    if (a.coat > 0.0f) {
        l->coat[k] = a.coat, l->coat_rough[k] = a.coat_rough;
        b->coated |= 1u << k;
        if (a.cnmap.w > 0.0f) {
            set_lane3(l->cnmap, k, a.cnmap.xyz);
            l->cnscale[k] = a.coat_nscale;
            b->cmapped |= 1u << k;
        }
    }
    if (a.flags & ST_MAT_SHEEN) /* sheen_gather reads its sheen */
        b->sheened |= 1u << k;
    if (a.flags & ST_MAT_ANISO) /* aniso_gather reads its anisotropy */
        b->aniso |= 1u << k;
    if (a.flags & ST_MAT_DIFFUSE_TRANS) /* dtrans_gather reads its diffuse transmission */
        b->dtrans |= 1u << k;
    if (a.flags & ST_MAT_IRIDESCENT) /* irid_gather reads its thin film */
        b->irid |= 1u << k;
    if (a.flags & ST_MAT_DISPERSIVE)
        beta = dispersed(p, smp, gp, m_of(s, h.prim)->dispersion, depth, beta, k, l);
    if (a.transmission > 0.0f) {
        b->trans |= 1u << k;
        if (a.flags & ST_MAT_THIN)
            b->thin |= 1u << k;
        /* met from inside: the medium absorbed along the segment (Beer-Lambert;
         * the item's own exp, which a vector's lanes would round otherwise) */
        if (dot(ng, d) > 0.0f)
            set_lane3(l->beta, k, beta * exp(-a.absorb * h.t));
    }
    if (a.nmap.w > 0.0f) {
        set_lane3(l->nmap, k, a.nmap.xyz);
        l->nscale[k] = a.normal_scale;
        b->nmapped |= 1u << k;
    }
    dims_gather(p, smp, pmj02, depth, k, a.transmission > 0.0f, l);
    return 1;
}

/* What the lanes leave for each lane to store (vertex_store). */
typedef struct st_vertex_out {
    float rad[3][ST_W], beta[3][ST_W], origin[3][ST_W];
    float next_o[3][ST_W]; /* a refracted ray's origin, on the other side (bits `refracted`) */
    float shadow_d[3][ST_W], contribution[3][ST_W], tmax[ST_W]; /* the shadow ray */
    float next_d[3][ST_W], bsdf_pdf[ST_W], env_pdf[ST_W];      /* the next ray */
} st_vertex_out;

/* What vertex_store does for a lane (bits of its `what`). */
#define ST_STORE_SHADOWED 1u /* a shadow ray */
#define ST_STORE_GOES 2u     /* the next ray */
#define ST_STORE_REFRACTED 4u /* ..., which starts on the other side */
#define ST_STORE_DARK 8u     /* no next ray: it would see no light (dark_bounces) */

/* Lane k's results into item i: the radiance; the shadow ray (where
 * `what` has ST_STORE_SHADOWED); the next ray and the path one vertex
 * deeper (ST_STORE_GOES; from the other side with ST_STORE_REFRACTED),
 * else the path ended. */
ST_HOT void vertex_store(const st_vertex_out *o, const st_vertex_in *l, st_u32 i, st_u32 k,
                         st_u32 what, __global st_ray *ray,
                         __global st_path *path, __global st_shadow *shadow)
{
    __global st_path *gp = &path[i];
    vstore3(lane3(o->rad, k), 0, gp->radiance);
    float3 origin = lane3(o->origin, k);
    if ((what & ST_STORE_SHADOWED) && o->tmax[k] > 0.0f) {
        __global st_shadow *sr = &shadow[i];
        vstore3(origin, 0, sr->ray.o);
        sr->ray.tmax = o->tmax[k];
        vstore3(lane3(o->shadow_d, k), 0, sr->ray.d);
        vstore3(lane3(o->contribution, k), 0, sr->contribution);
    }
    if (!(what & ST_STORE_GOES)) {
        gp->closest_rays += (what & ST_STORE_DARK) ? 1u : 0u; /* as trace_rays_last counts it */
        gp->depth = ST_PATH_DEAD;
        return;
    }
    vstore3(lane3(o->beta, k), 0, gp->beta);
    gp->bsdf_pdf = o->bsdf_pdf[k];
    gp->env_pdf = o->env_pdf[k];
    gp->depth = l->depth[k] + 1u;
    float3 from = (what & ST_STORE_REFRACTED) ? lane3(o->next_o, k) : origin;
    ray_store(&ray[i], from, lane3(o->next_d, k),
              l->travelled[k]);
}

/* The lanes of `goes` whose next ray, from `from` along d, is the last
 * vertex's and meets none of the light list's triangles, where
 * trace_rays_last will trace it (p->last_lights) in a scene whose
 * environment gives no light: that ray would end its path unseen, so it is
 * not stored. The test is trace_rays_last's own, st_list_closest, at ST_W
 * lanes (each lane computes what it computes at width 1). */
ST_HOT st_u32 dark_bounces(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                           st_lv3 from, st_lv3 d, st_lu depth, st_u32 goes)
{
    st_u32 last = ST_MASK_BITS(ST_W, depth + 1u >= p->max_depth) & goes;
    if (!p->last_lights || !last || env_lit(sh))
        return 0u;
    st_lf t = ST_LF(INFINITY), u = ST_LF(0.0f), v = ST_LF(0.0f);
    st_li prim = ST_SPLAT(int, ST_W, (int)ST_NO_HIT);
    st_li seen = ST_CAT(st_list_closest, ST_W)(s->tris, s->light_tri, p->light_count, from, d,
                                               ST_BITS_MASK(ST_W, last), &t, &u, &v, &prim);
    return last & ~ST_MASK_BITS(ST_W, seen);
}

/* The vertex of the lanes in `scatters` (not all of them missed, below
 * max_depth): the surface, its emission, next-event estimation and the
 * bounce, into o. Returns the lanes whose path goes on; *refracted those
 * of them that go on from the other side; *dark those whose path ends
 * because its last ray would see no light (dark_bounces). */
ST_HOT st_u32 vertex_scatter(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                             st_vertex_in *l, const st_lane_bits *b, st_u32 scatters,
                             st_vertex_out *o, st_u32 *refracted, st_u32 *dark)
{
    st_sheen_in sn;
    if (b->sheened)
        sheen_gather(s, p, sh, l, b->sheened, &sn);
    st_more_in more;
    more.aniso_bits = b->aniso, more.dtrans_bits = b->dtrans, more.irid_bits = b->irid;
    more_gather(s, p, sh, l, &more);
    if (p->sampler == ST_SAMPLER_RANDOM)
        dims_random(l, b->trans != 0u);
    st_lf cos_o;
    st_layers lay;
    st_vertex v = vertex_surface(s, l, b->nmapped, b->trans, b->thin, b->coated, b->cmapped,
                                 b->sheened, &sn, &more, &lay,
                                 ST_BITS_MASK(ST_W, b->miss), sh, &cos_o);
    lv3_store(v.rad, o->rad);
    st_lv3 origin = st_lv3_along(v.pos, v.ng, ST_LF(p->ray_eps)), wi;
    lv3_store(origin, o->origin);
    if (p->area_lanes)
        area_lanes(s, p, sh, scatters, l);
    else
        for (st_u32 k = 0; k < ST_W; k++)
            if ((scatters >> k) & 1u)
                light_gather(s, p, sh, k, l);
    st_lf tmax, pdf, cz;
    lv3_store(light_sample(l, &v, origin, p->ray_eps, &wi, &tmax), o->contribution);
    lv3_store(wi, o->shadow_d);
    ST_VSTORE(ST_W, tmax, o->tmax);
    st_li on = vertex_bounce(&v, ST_LV(l->u[2]), ST_LV(l->u[3]), ST_LV(l->u[4]), &wi, &pdf, &cz);
    on = on && roulette(&v, ST_LV(l->depth), ST_LV(l->u[5]));
    st_u32 goes = ST_MASK_BITS(ST_W, on) & scatters;
    lv3_store(v.beta, o->beta);
    lv3_store(wi, o->next_d);
    ST_VSTORE(ST_W, pdf, o->bsdf_pdf);
    ST_VSTORE(ST_W, cz / ST_PI_F, o->env_pdf);
    *refracted = 0u;
    st_lv3 from = origin;
    if (b->trans | b->dtrans) { /* a ray into the object, or through a diffusely
                                 * transmitting surface, goes on from the other side
                                 * (the geometry's, vertex_bounce), where no uniform
                                 * environment's light sample reaches (env_pdf 0) */
        st_li below = st_lv3_dot(wi, v.ng) < 0.0f;
        *refracted = ST_MASK_BITS(ST_W, below) & goes;
        st_lv3 inside = st_lv3_along(v.pos, v.ng, ST_LF(-p->ray_eps));
        lv3_store(inside, o->next_o);
        ST_VSTORE(ST_W, ST_SELECT(ST_W, fmax(cz, 0.0f), ST_LF(0.0f), below) / ST_PI_F, o->env_pdf);
        from = st_lv3_select(origin, inside, ST_BITS_MASK(ST_W, *refracted));
    }
    *dark = dark_bounces(s, p, sh, from, wi, ST_LV(l->depth), goes);
    *refracted &= ~*dark;
    return goes & ~*dark;
}

/* One vertex of the live paths at positions first .. first + n - 1 of list
 * (n <= ST_W; st_live_item), lane k at position first + k: the gather
 * (vertex_gather), the lanes' arithmetic (integrator.h; where no lane
 * scatters, as at the last vertex, only what the lanes see) and each lane's
 * store. Lanes that shade nothing hold zeros (vertex_clear_lane): every lane holds numbers, and
 * masks keep their results. Returns the lanes whose path goes on (bounced,
 * or through a cut-out). */
ST_HOT st_u32 shade_lanes(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                          __global const st_u32 *list, st_u32 first, st_u32 n,
                          __global const st_sample *sample, __global st_ray *ray,
                          __global const st_hit *hit, __global st_path *path,
                          __global st_shadow *shadow, __global const st_u32 *pmj02)
{
    st_vertex_in l; /* cleared where no gather writes it: vertex_clear_some */
    st_u32 live = 0u, item[ST_W];
    st_lane_bits b = {0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u};
    /* two loops, not one select: vectorised, the select became a masked
     * load from the null list at vertex 0, which faults in every lane it
     * masks off, and the CPU's microcode repairs that at great cost (on
     * AMD Zen 3 it was the hottest instruction of shade_hits) */
    if (list)
        for (st_u32 k = 0; k < n; k++)
            item[k] = list[first + k];
    else
        for (st_u32 k = 0; k < n; k++)
            item[k] = first + k;
    vertex_clear_some(&l);
    for (st_u32 k = 0; k < n; k++)
        live |= (st_u32)vertex_gather(s, p, sh, item[k], k, sample, ray, hit, path, shadow,
                                      pmj02, &l, &b) << k;
    if (!live)
        return b.through;
    for (st_u32 k = 0; k < ST_W; k++)
        if (!((live >> k) & 1u) || ((b.miss >> k) & 1u))
            vertex_clear_lane(&l, k, !((live >> k) & 1u));
    st_lu depth = ST_LV(l.depth);
    st_u32 scatters = ST_MASK_BITS(ST_W, depth < p->max_depth) & live & ~b.miss;
    st_u32 goes = 0u, refracted = 0u, dark = 0u;
    st_vertex_out o;
    if (scatters) {
        goes = vertex_scatter(s, p, sh, &l, &b, scatters, &o, &refracted, &dark);
    } else {
        st_lf cos_o = st_lv3_dot(ST_LV3_OF(l.ng), st_lv3_neg(ST_LV3_OF(l.d)));
        lv3_store(vertex_radiance(&l, sh, ST_BITS_MASK(ST_W, b.miss), cos_o), o.rad);
    }
    for (st_u32 k = 0; k < n; k++)
        if ((live >> k) & 1u)
            vertex_store(&o, &l, item[k], k,
                         ((scatters >> k) & 1u) * ST_STORE_SHADOWED +
                             ((goes >> k) & 1u) * ST_STORE_GOES +
                             ((refracted >> k) & 1u) * ST_STORE_REFRACTED +
                             ((dark >> k) & 1u) * ST_STORE_DARK,
                         ray, path, shadow);
    return goes | b.through;
}

/* The stage kernels' ST_W paths per work-item: work-item g shades the live
 * paths at positions ST_W g .. ST_W g + ST_W - 1 (global size st_live_count /
 * ST_W rounded up), and sets bit k of live_bits[g] where the path at
 * position ST_W g + k goes on (live.cl lists those for the next vertex). */
#define ST_SHADE_LANES_ITEMS                                                                \
    st_u32 first = ST_W * ST_ITEM(), count = st_live_count(&p);                             \
    if (first >= count)                                                                     \
        return;                                                                             \
    st_u32 n = min((st_u32)ST_W, count - first);                                            \
    __global const st_u32 *list = st_live_list(&p, live_a, live_b);                         \
    st_scene_refs s = ST_SCENE_REFS_INIT;                                                   \
    live_bits[ST_ITEM()] =                                                                  \
        shade_lanes(&s, &p, &sh, list, first, n, sample, ray, hit, path, shadow, pmj02)

/* One vertex of every live path; its shadow ray is traced by the next
 * stage, trace_shadow_rays (the default: src/render/plan.c). */
__kernel void shade_hits(ST_STAGE_PARAMS)
{
    ST_SHADE_LANES_ITEMS;
}

/* shade_hits and trace_shadow_rays in one work-item: the shadow rays are
 * traced at once, while the vertex is fresh (only when asked: on PoCL it ran
 * more instructions than the two stages). The same floats are added in the
 * same order, so the film is the same. */
__kernel void shade_hits_shadowed(ST_STAGE_PARAMS)
{
    ST_SHADE_LANES_ITEMS;
    for (st_u32 k = 0; k < n; k++)
        trace_shadow_item(nodes, &s, &p, &sh, shadow, path, sample, st_live_item(list, first + k));
}
