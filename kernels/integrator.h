/* integrator.h — one path vertex as a sequence of named steps, which
 * shade.cl runs in order: the surface at the hit, alpha cut-outs, emission
 * with MIS, next-event estimation, the BSDF bounce and Russian roulette.
 * OpenCL only. The conventions (integrators, sample dimensions, MIS) are
 * described at the top of shade.cl. */
#ifndef ST_INTEGRATOR_H
#define ST_INTEGRATOR_H

#define ST_DIMS_PER_VERTEX 6u
#define ST_RR_START_DEPTH 3u

/* What the steps know of the surface point a ray reached. */
typedef struct st_surface {
    float3 pos, wo;  /* the point, and the direction back along the ray */
    float3 ng, ns;   /* geometric and shading normals */
    float4 base;     /* base colour (RGB) and alpha, textured */
    float3 le;       /* emitted radiance, textured */
    float metallic;
    float travelled; /* path length at the point (ray-cone width) */
} st_surface;

/* The surface at hit h of ray r: position, normals (ng on the side its
 * shading normals face), and the material's factors times their textures,
 * looked up with the ray cone's footprint. */
static st_surface surface_at(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                             const st_wave_ray *r, st_hit h)
{
    st_surface v;
    st_u32 t = h.prim;
    v.wo = -vload3(0, r->d);
    v.pos = vload3(0, r->o) - v.wo * h.t;
    v.travelled = r->path_length + h.t;
    v.ng = facing_normal(s->normals, t);
    v.ns = normalize((1.0f - h.u - h.v) * vload4(0, s->normals[t].n0).xyz +
                     h.u * vload4(0, s->normals[t].n1).xyz + h.v * vload4(0, s->normals[t].n2).xyz);
    st_material m = s->materials[s->tri_material[t]];
    v.base = vload4(0, m.base_color);
    v.le = vload4(0, m.emission).xyz;
    v.metallic = m.metallic;
    if (m.base_color_tex != ST_NO_TEXTURE || m.emission_tex != ST_NO_TEXTURE ||
        m.metallic_roughness_tex != ST_NO_TEXTURE) {
        float2 uv = tri_uv_at(s->tri_uv, t, h.u, h.v);
        float px = 2.0f * p->camera.origin[3] / (float)p->height; /* pixel width at distance 1 */
        float width = p->camera.forward[3] > 0.5f ? px : px * v.travelled;
        float cos_nd = dot(v.ng, v.wo), lod = s->tri_uv[t].lod;
        st_u32 f = sh->texture_filter;
        v.base *= tex_lookup(s, m.base_color_tex, uv, lod, width, cos_nd, f);
        v.le *= tex_lookup(s, m.emission_tex, uv, lod, width, cos_nd, f).xyz;
        v.metallic *= tex_lookup(s, m.metallic_roughness_tex, uv, lod, width, cos_nd, f).z;
    }
    return v;
}

/* Whether the ray goes on through the surface: an alpha MASK cut-out, or
 * BLEND coverage (passes with probability 1 - alpha, drawn from the counter
 * hash keyed by the triangle and depth). */
static int alpha_passes(const st_scene_refs *s, const st_params *p, const st_surface *v,
                        st_sample smp, st_u32 prim, st_u32 depth)
{
    __global const st_material *m = &s->materials[s->tri_material[prim]];
    if (m->alpha_mode == ST_ALPHA_OPAQUE)
        return 0;
    float u = st_rng_unit(st_rng_key(p->seed ^ 0xa1fa0000u, smp.pixel, smp.index),
                          prim ^ (depth << 24));
    return m->alpha_mode == ST_ALPHA_MASK ? v->base.w < m->alpha_cutoff : u >= v->base.w;
}

/* The weight of the emission seen along the ray (one-sided; 0: none): 1
 * for a camera ray, and for a ray made by a BSDF sample (depth > 0) the MIS
 * weight against sampling the same light. The caller adds beta x le x w in
 * one expression, as the compiler may fuse it. */
static float emission_weight(const st_scene_refs *s, const st_surface *v, const st_path *pa,
                             st_hit h, float cos_o)
{
    float3 le = v->le;
    if (!(cos_o > 0.0f && (le.x > 0.0f || le.y > 0.0f || le.z > 0.0f)))
        return 0.0f;
    if (pa->depth == 0u)
        return 1.0f;
    float pdf_light = s->light_pdf[h.prim] * h.t * h.t / cos_o;
    return power_heuristic(pa->bsdf_pdf, pdf_light);
}

/* Next-event estimation: the environment (a cosine-distributed direction)
 * or one point on one emissive triangle, as a shadow ray with what it adds
 * when unoccluded; tmax stays 0 when the sample cannot contribute.
 * `choice` is the probability of the strategy taken. */
static st_shadow_ray next_event(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                                const st_surface *v, const st_path *pa, float3 albedo,
                                float3 origin, st_sample_id *id, st_u32 dim)
{
    st_shadow_ray out = {{0.0f, 0.0f, 0.0f}, 0.0f, {0.0f, 0.0f, 0.0f}, 0.0f,
                         {0.0f, 0.0f, 0.0f}, 0.0f};
    float3 env = vload4(0, sh->env).xyz, beta = vload3(0, pa->beta);
    int has_env = env.x > 0.0f || env.y > 0.0f || env.z > 0.0f;
    int path = p->integrator == ST_INTEGRATOR_PATH;
    float choice = 1.0f, w = 1.0f;
    int take_env = has_env && p->light_count == 0u;
    if (has_env && p->light_count > 0u && !path) {
        take_env = st_sample_dim(p, id, dim + 4u) < 0.5f;
        choice = 0.5f;
    }
    float3 wi, c;
    float tmax;
    if (take_env) {
        float cz, u1 = st_sample_dim(p, id, dim), u2 = st_sample_dim(p, id, dim + 1u);
        wi = cosine_direction(v->ns, u1, u2, &cz);
        if (!(cz > 0.0f && dot(wi, v->ng) > 0.0f))
            return out;
        w = path ? 0.5f : 1.0f; /* MIS against the BSDF sample's miss */
        c = beta * albedo * env * (w / choice);
        tmax = INFINITY;
    } else if (p->light_count > 0u) {
        float u = st_sample_dim(p, id, dim), u2 = st_sample_dim(p, id, dim + 1u);
        st_u32 lt = s->light_tri[pick_light(s->light_cdf, p->light_count, &u)];
        float3 q = triangle_point(s->tris, lt, u, u2), nl = facing_normal(s->normals, lt);
        wi = q - origin;
        float dist2 = dot(wi, wi), dist = sqrt(dist2);
        wi /= dist;
        float cos_l = -dot(nl, wi), cos_s = dot(v->ns, wi);
        if (!(cos_l > 0.0f && cos_s > 0.0f && dot(v->ng, wi) > 0.0f))
            return out;
        float pdf_light = s->light_pdf[lt] * dist2 / cos_l;
        w = path ? power_heuristic(pdf_light, cos_s / ST_PI_F) : 1.0f;
        float3 lel = light_emission(s, lt, u, u2, sh->texture_filter);
        c = beta * albedo * (1.0f / ST_PI_F) * lel * (cos_s * w / pdf_light) / choice;
        tmax = dist * (1.0f - 1e-3f) - p->ray_eps;
    } else {
        return out;
    }
    vstore3(origin, 0, out.o);
    out.tmax = tmax;
    vstore3(wi, 0, out.d);
    vstore3(c, 0, out.contribution);
    return out;
}

/* The BSDF sample: a cosine-weighted direction; beta *= f cos / pdf =
 * albedo and bsdf_pdf = cos / π. Returns 0 when the direction is below the
 * geometric surface (the path ends). */
static int bsdf_bounce(const st_params *p, const st_surface *v, float3 albedo, st_path *pa,
                       st_sample_id *id, st_u32 dim, float3 *wi)
{
    float cz, u1 = st_sample_dim(p, id, dim + 2u), u2 = st_sample_dim(p, id, dim + 3u);
    *wi = cosine_direction(v->ns, u1, u2, &cz);
    if (!(cz > 0.0f) || dot(*wi, v->ng) <= 0.0f)
        return 0;
    vstore3(vload3(0, pa->beta) * albedo, 0, pa->beta);
    pa->bsdf_pdf = cz / ST_PI_F;
    return 1;
}

/* Russian roulette from the ST_RR_START_DEPTH-th vertex on: the path ends
 * with probability q = max(0.05, 1 - max beta) and survivors divide by
 * 1 - q. Returns 0 when it ends. */
static int roulette(const st_params *p, st_path *pa, st_sample_id *id, st_u32 dim)
{
    if (pa->depth + 1u < ST_RR_START_DEPTH)
        return 1;
    float3 beta = vload3(0, pa->beta);
    float q = fmax(0.05f, 1.0f - fmax(beta.x, fmax(beta.y, beta.z)));
    if (st_sample_dim(p, id, dim + 5u) < q)
        return 0;
    vstore3(beta / (1.0f - q), 0, pa->beta);
    return 1;
}

#endif
