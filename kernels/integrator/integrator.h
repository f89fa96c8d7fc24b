/* integrator.h — one path vertex as a sequence of named steps, which
 * shade.cl runs in order: the surface at the hit, alpha cut-outs, emission
 * with MIS, next-event estimation, the BSDF bounce and Russian roulette.
 * OpenCL only. The conventions (integrators, sample dimensions, MIS) are
 * described at the top of shade.cl. */
#ifndef ST_INTEGRATOR_H
#define ST_INTEGRATOR_H

#define ST_DIMS_PER_VERTEX 6u
#define ST_RR_START_DEPTH 3u

/* The part of a path (st_path) that a vertex reads and changes, held in
 * private values for the vertex: PoCL kept a private st_path, whose fields
 * are arrays that vload3 and vstore3 address, in an array with one slot per
 * work-item (with the copied ray, many loads and stores per hit). */
typedef struct st_walk {
    float3 beta, radiance;
    float bsdf_pdf, env_pdf;
    st_u32 depth;
} st_walk;

/* Path gp's st_walk. */
static st_walk walk_load(__global const st_path *gp)
{
    st_walk w = {vload3(0, gp->beta), vload3(0, gp->radiance), gp->bsdf_pdf, gp->env_pdf,
                 gp->depth};
    return w;
}

/* Writes w back to path gp. */
static void walk_store(__global st_path *gp, const st_walk *w)
{
    vstore3(w->beta, 0, gp->beta);
    vstore3(w->radiance, 0, gp->radiance);
    gp->bsdf_pdf = w->bsdf_pdf;
    gp->env_pdf = w->env_pdf;
    gp->depth = w->depth;
}

/* What the steps know of the surface point a ray reached. */
typedef struct st_surface {
    float3 pos, wo;  /* the point, and the direction back along the ray */
    float3 ng, ns;   /* geometric and shading normals */
    float3 tu, tv;   /* the shading frame's tangents (surface_frame; not for Lambert) */
    float4 base;     /* base colour (RGB) and alpha, textured */
    float3 le;       /* emitted radiance, textured */
    float3 albedo;   /* the Lambertian part's albedo, (1 - metallic) x base colour */
    st_brdf brdf;    /* the glTF BRDF (bsdf.h) */
    st_dir wo_local; /* wo in the shading frame (surface_frame) */
    int lambert;     /* no specular lobe (metallic and specularFactor 0): the cheap path,
                        albedo = base colour; brdf is then not made */
    int unlit;       /* KHR_materials_unlit */
    float travelled; /* path length at the point (ray-cone width) */
} st_surface;

/* The shading normal ns bent by a normal map's texel c (tangent-space
 * normal 2 c - 1, x and y times normalTexture.scale) in the frame of the
 * interpolated tangent, made orthogonal to ns, and the bitangent w x
 * cross(ns, tangent). Kept at least a little above the geometric surface
 * ng, so that a map cannot turn the shading side over; ns stays where the
 * triangle has no tangent (no texture coordinates). */
static float3 normal_mapped(const st_scene_refs *s, st_hit h, float3 ns, float3 ng, float4 c,
                            float scale)
{
    __global const st_tri_tangents *tt = &s->tangents[h.prim];
    float3 tg = (1.0f - h.u - h.v) * vload4(0, tt->t0).xyz + h.u * vload4(0, tt->t1).xyz +
                h.v * vload4(0, tt->t2).xyz;
    float w = tt->t0[3];
    tg -= ns * dot(ns, tg);
    float len = length(tg);
    if (!(len > 1e-6f) || w == 0.0f)
        return ns;
    tg /= len;
    float3 t = 2.0f * c.xyz - 1.0f;
    float3 n = t.x * scale * tg + t.y * scale * w * cross(ns, tg) + t.z * ns;
    float up = dot(n, ng);
    if (up < 0.01f)
        n += (0.01f - up) * ng;
    len = length(n);
    return len > 0.0f ? n / len : ns;
}

/* The material's factors at hit h times their textures, looked up with the
 * ray cone's footprint; the BRDF made from them; the normal map. */
static void surface_material(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                             st_hit h, st_surface *v)
{
    st_u32 t = h.prim;
    __global const st_material *m = &s->materials[s->tri_material[t]]; /* fields as needed */
    float4 spec = vload4(0, m->specular);
    float metallic = m->metallic, roughness = m->roughness;
    v->base = vload4(0, m->base_color);
    v->le = vload4(0, m->emission).xyz;
    if (m->flags & ST_MAT_VERTEX_COLOR) { /* COLOR_0 multiplies the base colour */
        __global const st_tri_colors *c = &s->colors[t];
        v->base *= (1.0f - h.u - h.v) * vload4(0, c->c0) + h.u * vload4(0, c->c1) +
                   h.v * vload4(0, c->c2);
    }
    if (m->base_color_tex != ST_NO_TEXTURE || m->emission_tex != ST_NO_TEXTURE ||
        m->metallic_roughness_tex != ST_NO_TEXTURE || m->specular_tex != ST_NO_TEXTURE ||
        m->specular_color_tex != ST_NO_TEXTURE || m->normal_tex != ST_NO_TEXTURE) {
        float px = 2.0f * p->camera.origin[3] / (float)p->height; /* pixel width at distance 1 */
        float width = p->camera.forward[3] > 0.5f ? px : px * v->travelled;
        float cos_nd = dot(v->ng, v->wo), b1 = h.u, b2 = h.v;
        st_u32 f = sh->texture_filter;
        st_tex_refs x = tex_refs(s);
        v->base *= tex_lookup(x, m->base_color_tex, t, b1, b2, width, cos_nd, f);
        v->le *= tex_lookup(x, m->emission_tex, t, b1, b2, width, cos_nd, f).xyz;
        float4 mr = tex_lookup(x, m->metallic_roughness_tex, t, b1, b2, width, cos_nd, f);
        metallic *= mr.z;
        roughness *= mr.y;
        spec.w *= tex_lookup(x, m->specular_tex, t, b1, b2, width, cos_nd, f).w;
        spec.xyz *= tex_lookup(x, m->specular_color_tex, t, b1, b2, width, cos_nd, f).xyz;
        if (m->normal_tex != ST_NO_TEXTURE)
            v->ns = normal_mapped(s, h, v->ns, v->ng,
                                  tex_lookup(x, m->normal_tex, t, b1, b2, width, cos_nd, f),
                                  m->normal_scale);
    }
    v->lambert = !(metallic > 0.0f || spec.w > 0.0f); /* no specular lobe: the cheap path */
    v->albedo = v->base.xyz;
    if (!v->lambert) {
        float c[3] = {v->base.x, v->base.y, v->base.z}, sc[3] = {spec.x, spec.y, spec.z};
        v->brdf = st_brdf_make(c, metallic, roughness, spec.w, sc, m->ior);
        v->albedo = (float3)(v->brdf.diffuse[0], v->brdf.diffuse[1], v->brdf.diffuse[2]);
    }
    v->unlit = (m->flags & ST_MAT_UNLIT) != 0u;
}

/* The surface at hit h of the ray from o along d, which starts path_length
 * along the path: position, normals (ng on the side its shading normals
 * face) and the material (surface_material). Forced inline: as a call it
 * kept the caller's st_surface and st_scene_refs in memory per work-item. */
ST_HOT st_surface surface_at_ray(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                                 float3 o, float3 d, float path_length, st_hit h)
{
    st_surface v;
    st_u32 t = h.prim;
    v.wo = -d;
    v.pos = o - v.wo * h.t;
    v.travelled = path_length + h.t;
    v.ng = facing_normal(s->normals, t);
    v.ns = normalize((1.0f - h.u - h.v) * vload4(0, s->normals[t].n0).xyz +
                     h.u * vload4(0, s->normals[t].n1).xyz + h.v * vload4(0, s->normals[t].n2).xyz);
    surface_material(s, p, sh, h, &v);
    return v;
}

/* surface_at_ray for the ray r. */
static st_surface surface_at(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                             const st_wave_ray *r, st_hit h)
{
    return surface_at_ray(s, p, sh, vload3(0, r->o), vload3(0, r->d), r->path_length, h);
}

/* The shading frame around ns (once ns faces the ray's side) and wo in it;
 * wo below the shading normal's horizon (interpolated normals at a
 * silhouette) is lifted just above it, so the BRDF does not go black there. */
static void surface_frame(st_surface *v)
{
    if (v->lambert)
        return;
    basis(v->ns, &v->tu, &v->tv);
    float z = fmax(dot(v->wo, v->ns), 1e-4f);
    st_dir w = {dot(v->wo, v->tu), dot(v->wo, v->tv), z};
    v->wo_local = st_dir_normalize(w);
}

/* f(wo, wi) cos θi at the surface for a direction wi above it, and in *pdf
 * the density with which bsdf_bounce would choose wi. */
static float3 surface_f_cos(const st_surface *v, float3 wi, float *pdf)
{
    float c = dot(v->ns, wi);
    if (v->lambert) {
        *pdf = c / ST_PI_F;
        return v->albedo * *pdf;
    }
    st_dir li = {dot(wi, v->tu), dot(wi, v->tv), c};
    float f[3];
    st_brdf b = v->brdf; /* the calls get a copy: with v's own, v would live in memory */
    st_brdf_eval(&b, v->wo_local, li, f);
    *pdf = st_brdf_pdf(&b, v->wo_local, li);
    return (float3)(f[0], f[1], f[2]) * c;
}

/* Whether the ray goes on through the surface: an alpha MASK cut-out, or
 * BLEND coverage (passes with probability 1 - alpha, drawn from the counter
 * hash keyed by the seed ^ key, the sample, the triangle and depth).
 * Forced inline, as surface_at_ray. */
ST_HOT int alpha_passes_keyed(const st_scene_refs *s, const st_params *p, const st_surface *v,
                              st_sample smp, st_u32 prim, st_u32 depth, st_u32 key)
{
    __global const st_material *m = &s->materials[s->tri_material[prim]];
    if (m->alpha_mode == ST_ALPHA_OPAQUE)
        return 0;
    float u = st_rng_unit(st_rng_key(p->seed ^ key, smp.pixel, smp.index), prim ^ (depth << 24));
    return m->alpha_mode == ST_ALPHA_MASK ? v->base.w < m->alpha_cutoff : u >= v->base.w;
}

/* alpha_passes_keyed for the rays the path follows (shadow rays: shadow.h). */
static int alpha_passes(const st_scene_refs *s, const st_params *p, const st_surface *v,
                        st_sample smp, st_u32 prim, st_u32 depth)
{
    return alpha_passes_keyed(s, p, v, smp, prim, depth, 0xa1fa0000u);
}

/* The probabilities with which next-event estimation samples the
 * environment and the area lights (next_event): both take what the punctual
 * lights leave, split by power (st_shading.env_pick). The MIS weights at an
 * emitter and at a miss use these same numbers. */
static float env_choice(const st_shading *sh)
{
    return (1.0f - sh->punct_share) * sh->env_pick;
}

static float area_choice(const st_shading *sh)
{
    return (1.0f - sh->punct_share) * (1.0f - sh->env_pick);
}

/* The environment map's radiance at map coordinates (u, v) (nearest
 * texel: kernels/envmap.h) times the env factor, and in *pdf the density in
 * solid angle with which env_sample picks that direction. */
static float3 env_map_at(__global const float *env_cdf, __global const float *env_texels,
                         const st_shading *sh, float u, float v, float *pdf)
{
    st_u32 w = sh->env_size[0], h = sh->env_size[1], i, j;
    st_env_texel(w, h, u, v, &i, &j);
    *pdf = st_env_solid_angle_pdf(st_env_texel_pdf(env_cdf, w, h, i, j), v);
    return vload4(0, sh->env).xyz * vload4(j * w + i, env_texels).xyz;
}

/* The environment's radiance arriving against the world direction d; with a
 * map, *pdf becomes env_sample's density of d (a uniform environment leaves
 * *pdf alone: its density depends on the surface, st_path.env_pdf). */
static float3 env_radiance(const st_scene_refs *s, const st_shading *sh, float3 d, float *pdf)
{
    if (sh->env_size[0] == 0u)
        return vload4(0, sh->env).xyz;
    float dw[3] = {d.x, d.y, d.z}, dm[3], u, v;
    st_env_rotate(sh->env_rot, 0, dw, dm);
    st_env_coords(dm, &u, &v);
    return env_map_at(s->env_cdf, s->env_texels, sh, u, v, pdf);
}

/* A direction *wi towards the environment from (u1, u2), its density *pdf
 * in solid angle (0: none usable) and the radiance along it: the map's
 * importance sampling by luminance, or for a uniform environment a
 * cosine-distributed direction about the shading normal. */
static float3 env_sample(const st_scene_refs *s, const st_shading *sh, const st_surface *v,
                         float u1, float u2, float3 *wi, float *pdf)
{
    if (sh->env_size[0] == 0u) {
        float cz;
        *wi = cosine_direction(v->ns, u1, u2, &cz);
        *pdf = cz > 0.0f ? cz / ST_PI_F : 0.0f;
        return vload4(0, sh->env).xyz;
    }
    float u, w, dm[3], dw[3];
    st_env_sample(s->env_cdf, sh->env_size[0], sh->env_size[1], u1, u2, &u, &w);
    st_env_direction(u, w, dm);
    st_env_rotate(sh->env_rot, 1, dm, dw);
    *wi = (float3)(dw[0], dw[1], dw[2]);
    float3 le = env_map_at(s->env_cdf, s->env_texels, sh, u, w, pdf);
    if (!(dot(*wi, v->ns) > 0.0f))
        *pdf = 0.0f;
    return le;
}

/* The weight of the emission seen along the ray (one-sided; 0: none): 1
 * for a camera ray, and for a ray made by a BSDF sample (depth > 0) the MIS
 * weight against sampling the same light. The caller adds beta x le x w in
 * one expression, as the compiler may fuse it. */
static float emission_weight(const st_scene_refs *s, const st_shading *sh, const st_surface *v,
                             const st_walk *pa, st_hit h, float cos_o)
{
    float3 le = v->le;
    if (!(cos_o > 0.0f && (le.x > 0.0f || le.y > 0.0f || le.z > 0.0f)))
        return 0.0f;
    if (pa->depth == 0u)
        return 1.0f;
    float pdf_light = s->light_pdf[h.prim] * area_choice(sh) * h.t * h.t / cos_o;
    return power_heuristic(pa->bsdf_pdf, pdf_light);
}

/* Writes the shadow ray *out towards the point (origin, wi, tmax), adding c
 * when unoccluded; none (*out left alone) unless tmax > 0. Straight to the
 * wave's buffer: a private st_shadow_ray returned by value stayed in memory
 * per work-item on PoCL. */
static void shadow_towards(__global st_shadow_ray *out, float3 origin, float3 wi, float tmax,
                           float3 c)
{
    if (!(tmax > 0.0f))
        return;
    vstore3(origin, 0, out->o);
    out->tmax = tmax;
    vstore3(wi, 0, out->d);
    vstore3(c, 0, out->contribution);
}

/* Next-event estimation towards a punctual light, picked by power with u
 * (probability punct_share x its share of their power): a delta light,
 * which no BSDF sample can hit, so its sample takes weight 1 (no MIS). The
 * shadow ray ends at the light, or for a directional one goes to infinity
 * against its direction; it adds beta f cos I / (d² P(pick)) (d = 1 and I
 * the irradiance for a directional light). */
static void punctual_event(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                           const st_surface *v, float3 beta, float3 origin, float u,
                           __global st_shadow_ray *out)
{
    st_u32 k = pick_light(s->punct_cdf, sh->punct_count, &u);
    float prob = sh->punct_share * (s->punct_cdf[k] - (k ? s->punct_cdf[k - 1u] : 0.0f));
    __global const st_punctual *l = &s->punctual[k];
    float3 wi;
    float tmax = INFINITY, dist2 = 1.0f, pdf_bsdf;
    if ((st_u32)l->pos[3] == ST_PUNCT_DIRECTIONAL) {
        wi = -vload4(0, l->dir).xyz;
    } else {
        wi = vload4(0, l->pos).xyz - origin;
        dist2 = dot(wi, wi);
        float dist = sqrt(dist2);
        wi /= dist;
        tmax = dist * (1.0f - 1e-3f) - p->ray_eps;
    }
    if (!(prob > 0.0f && tmax > 0.0f && dot(v->ns, wi) > 0.0f && dot(v->ng, wi) > 0.0f))
        return;
    float3 fc = surface_f_cos(v, wi, &pdf_bsdf);
    shadow_towards(out, origin, wi, tmax, beta * fc * punctual_intensity(l, wi) / (dist2 * prob));
}

/* Next-event estimation: a punctual light (with probability punct_share:
 * punctual_event), else the environment (env_sample) or one point on one
 * emissive triangle, chosen by power (env_choice, area_choice), as a
 * shadow ray *out with what it adds when unoccluded; *out is left alone
 * (tmax 0) when the sample cannot contribute. One stratified dimension makes each choice
 * and then the sample's first coordinate (pick_light). In the path
 * integrator the environment and area samples are weighted by the power
 * heuristic against the BSDF sample (surface_f_cos's pdf). */
static void next_event(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                       const st_surface *v, const st_walk *pa, float3 origin, st_sample_id *id,
                       st_u32 dim, __global st_shadow_ray *out)
{
    float3 beta = pa->beta;
    int path = p->integrator == ST_INTEGRATOR_PATH;
    float w = 1.0f, pdf_bsdf, u = st_sample_dim(p, id, dim), pe = sh->env_pick;
    if (sh->punct_count > 0u) { /* u both chooses and stays stratified (pick_light) */
        if (u < sh->punct_share) {
            punctual_event(s, p, sh, v, beta, origin, u / sh->punct_share, out);
            return;
        }
        u = fmin((u - sh->punct_share) / (1.0f - sh->punct_share), 0.99999994f);
    }
    int take_env = u < pe;
    if (pe > 0.0f && pe < 1.0f)
        u = take_env ? u / pe : fmin((u - pe) / (1.0f - pe), 0.99999994f);
    float3 wi, c;
    float tmax, u2 = st_sample_dim(p, id, dim + 1u);
    if (take_env) {
        float pdf_env, choice = env_choice(sh);
        float3 le = env_sample(s, sh, v, u, u2, &wi, &pdf_env);
        if (!(pdf_env > 0.0f && dot(wi, v->ng) > 0.0f))
            return;
        float3 fc = surface_f_cos(v, wi, &pdf_bsdf);
        w = path ? power_heuristic(pdf_env * choice, pdf_bsdf) : 1.0f;
        c = beta * fc * le * (w / (pdf_env * choice));
        tmax = INFINITY;
    } else if (p->light_count > 0u) {
        float choice = area_choice(sh);
        st_u32 lt = s->light_tri[pick_light(s->light_cdf, p->light_count, &u)];
        float3 q = triangle_point(s->tris, lt, u, u2), nl = facing_normal(s->normals, lt);
        wi = q - origin;
        float dist2 = dot(wi, wi), dist = sqrt(dist2);
        wi /= dist;
        float cos_l = -dot(nl, wi), cos_s = dot(v->ns, wi);
        if (!(cos_l > 0.0f && cos_s > 0.0f && dot(v->ng, wi) > 0.0f))
            return;
        float pdf_light = s->light_pdf[lt] * dist2 / cos_l;
        float3 fc = surface_f_cos(v, wi, &pdf_bsdf);
        w = path ? power_heuristic(pdf_light * choice, pdf_bsdf) : 1.0f;
        float3 lel = light_emission(s, lt, u, u2, sh->texture_filter);
        c = beta * fc * lel * (w / pdf_light) / choice;
        tmax = dist * (1.0f - 1e-3f) - p->ray_eps;
    } else {
        return;
    }
    shadow_towards(out, origin, wi, tmax, c);
}

/* The BSDF sample: a cosine-weighted direction for a Lambertian surface,
 * else one from the BRDF's mixture (bsdf.h); beta *= f cos / pdf, bsdf_pdf
 * = pdf and env_pdf = cos / π for MIS where the ray ends. Returns 0 when the
 * direction is below the geometric surface (the path ends). */
static int bsdf_bounce(const st_params *p, const st_surface *v, st_walk *pa, st_sample_id *id,
                       st_u32 dim, float3 *wi)
{
    float cz, u1 = st_sample_dim(p, id, dim + 2u), u2 = st_sample_dim(p, id, dim + 3u);
    float3 weight;
    if (v->lambert) {
        *wi = cosine_direction(v->ns, u1, u2, &cz);
        weight = v->albedo;
        pa->bsdf_pdf = cz / ST_PI_F;
    } else {
        st_brdf b = v->brdf; /* a copy, as in surface_f_cos */
        st_dir li = st_brdf_sample(&b, v->wo_local, u1, u2);
        cz = li.z;
        *wi = normalize(li.x * v->tu + li.y * v->tv + li.z * v->ns);
        float f[3], pdf = st_brdf_pdf(&b, v->wo_local, li);
        st_brdf_eval(&b, v->wo_local, li, f);
        if (!(pdf > 0.0f))
            return 0;
        weight = (float3)(f[0], f[1], f[2]) * (cz / pdf);
        pa->bsdf_pdf = pdf;
    }
    if (!(cz > 0.0f) || dot(*wi, v->ng) <= 0.0f)
        return 0;
    pa->beta *= weight;
    pa->env_pdf = cz / ST_PI_F;
    return 1;
}

/* Russian roulette from the ST_RR_START_DEPTH-th vertex on: the path ends
 * with probability q = max(0.05, 1 - max beta) and survivors divide by
 * 1 - q. Returns 0 when it ends. */
static int roulette(const st_params *p, st_walk *pa, st_sample_id *id, st_u32 dim)
{
    if (pa->depth + 1u < ST_RR_START_DEPTH)
        return 1;
    float3 beta = pa->beta;
    float q = fmax(0.05f, 1.0f - fmax(beta.x, fmax(beta.y, beta.z)));
    if (st_sample_dim(p, id, dim + 5u) < q)
        return 0;
    pa->beta = beta / (1.0f - q);
    return 1;
}

#endif
