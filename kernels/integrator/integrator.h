/* integrator.h — one path vertex of ST_W paths at once, one path per lane
 * (lanes.h), the steps shade.cl's shade_hits runs in order: each lane
 * gathers its item (the ray, the hit, the material times its textures, the
 * path, the sample's dimensions, the light it samples), the arithmetic is
 * done once for all lanes (the surface, emission with MIS, next-event
 * estimation, the BSDF bounce, Russian roulette), and each lane stores its
 * own results. The same text runs at every width: 1 on a GPU (one item per
 * work-item, its SIMT hardware making the lanes) and 4, 8 or 16 on a CPU,
 * where PoCL keeps the lanes in SSE, AVX2 or AVX-512 registers (it widens
 * none of a single item's float3 arithmetic itself). A lane computes at
 * every width what it computes at width 1, bit for bit (tests/
 * test_render_paths.c, shade_at_every_width): lanes never mix, a branch
 * taken only where some lane needs it changes no lane's value, and the
 * statements are the same.
 *
 * What is one item's by nature stays one item's, in the gather: memory
 * reads, texture lookups (each lane its own texture and footprint), the
 * choice of a light from a CDF, the sampler's dimensions (but the random
 * sampler's hashes, made in lanes), alpha cut-outs, KHR_materials_unlit
 * and a path that ends at a cut-out. OpenCL only. The conventions
 * (integrators, sample dimensions, MIS) are described at the top of
 * shade.cl. */
#ifndef ST_INTEGRATOR_H
#define ST_INTEGRATOR_H

#define ST_DIMS_PER_VERTEX 6u
#define ST_RR_START_DEPTH 3u

/* Next-event estimation's kinds of light sample (st_vertex_in.lkind). */
#define ST_LIGHT_NONE 0
#define ST_LIGHT_AREA 1      /* a point on an emissive triangle */
#define ST_LIGHT_ENV 2       /* a direction from the environment map */
#define ST_LIGHT_ENV_LOCAL 3 /* a uniform environment's cosine direction about the shading normal */
#define ST_LIGHT_POINT 4     /* a point or spot light */
#define ST_LIGHT_DISTANT 5   /* a directional light */

/* What a vertex gathers per lane: an array of ST_W per value, lane k at
 * index k, read as lanes by ST_VLOAD. */
typedef struct st_vertex_in {
    float o[3][ST_W], d[3][ST_W];          /* the ray */
    float t[ST_W], bu[ST_W], bv[ST_W];     /* the hit */
    float travelled[ST_W];                 /* the path's length at the hit (ray cones) */
    float n0[3][ST_W], n1[3][ST_W], n2[3][ST_W]; /* the triangle's vertex normals */
    float ng[3][ST_W];                     /* its geometric normal, on their side */
    float base[3][ST_W], le[3][ST_W];      /* base colour and emission, textured */
    float metallic[ST_W], roughness[ST_W], spec[4][ST_W], ior[ST_W];
    float beta[3][ST_W], rad[3][ST_W], bsdf_pdf[ST_W];
    float emit_pdf[ST_W]; /* a hit: light_pdf of its triangle; a miss: the environment's
                             sampling density of the ray's direction (emission_weight) */
    st_u32 depth[ST_W];
    st_u32 key[ST_W], prim[ST_W];
    float u[6][ST_W]; /* the vertex's sample dimensions 2 + 6 depth + j */
    /* next-event estimation's light sample (light_gather): a point (area,
     * point) or direction (distant, environment), its radiance or
     * intensity, an area light's normal or a spot's axis, the density to
     * divide by, a spot's cone (cos outer, cos inner) */
    float lp[3][ST_W], ll[3][ST_W], lnl[3][ST_W], lq[ST_W], lco[ST_W], lci[ST_W];
    int lkind[ST_W];
    float nmap[3][ST_W], nscale[ST_W]; /* the normal map's texel and scale */
    float transmission[ST_W]; /* KHR_materials_transmission */
    float coat[ST_W], coat_rough[ST_W]; /* KHR_materials_clearcoat */
    float cnmap[3][ST_W], cnscale[ST_W]; /* its normal map's texel and scale */
} st_vertex_in;

/* KHR_materials_sheen's colour and roughness per lane, apart from
 * st_vertex_in so that a vertex without a sheen neither clears nor reads
 * them (vertex_gather clears them when it meets the first sheen). */
typedef struct st_sheen_in {
    float colour[3][ST_W], rough[ST_W];
} st_sheen_in;

/* KHR_materials_anisotropy's direction in world space (not yet orthogonal
 * to the shading normal) and strength per lane, apart for the same reason
 * (aniso_gather clears them). */
typedef struct st_aniso_in {
    float dir[3][ST_W], strength[ST_W];
} st_aniso_in;

/* KHR_materials_diffuse_transmission's colour and share per lane, apart
 * for the same reason (dtrans_gather clears them). */
typedef struct st_dtrans_in {
    float colour[3][ST_W], share[ST_W];
} st_dtrans_in;

/* KHR_materials_iridescence's film per lane: its weight, ior and thickness
 * (nm), apart for the same reason (irid_gather clears them). */
typedef struct st_irid_in {
    float weight[ST_W], ior[ST_W], nm[ST_W];
} st_irid_in;

/* The extensions' inputs gathered out of line, with the lanes that have
 * each (lane k bit k): only those lanes' rows are read. */
typedef struct st_more_in {
    st_u32 aniso_bits, dtrans_bits, irid_bits;
    st_aniso_in aniso;
    st_dtrans_in dtrans;
    st_irid_in irid;
} st_more_in;

#define ST_LV(a) ST_VLOAD(ST_W, a)
#define ST_LV3_OF(a) st_lv3_make(ST_VLOAD(ST_W, (a)[0]), ST_VLOAD(ST_W, (a)[1]), ST_VLOAD(ST_W, (a)[2]))

/* Lanes of a 3-vector into three arrays of ST_W floats, and back. */
ST_HOT void lv3_store(st_lv3 v, float (*out)[ST_W])
{
    ST_VSTORE(ST_W, v.x, out[0]);
    ST_VSTORE(ST_W, v.y, out[1]);
    ST_VSTORE(ST_W, v.z, out[2]);
}

/* Lane k of three arrays as a float3, and a float3 into lane k. */
static float3 lane3(const float (*a)[ST_W], st_u32 k)
{
    return (float3)(a[0][k], a[1][k], a[2][k]);
}

static void set_lane3(float (*a)[ST_W], st_u32 k, float3 v)
{
    a[0][k] = v.x;
    a[1][k] = v.y;
    a[2][k] = v.z;
}

/* ---- one item's parts: the gather ----------------------------------------- */

/* The material of the triangle hit at h, its factors times their textures
 * (looked up with the ray cone's footprint: width at the hit, cos_nd its
 * slant), and vertex colours; the normal map's texel in nmap, the clear
 * coat's in cnmap (their w: 0 without a map). */
typedef struct st_material_at {
    float4 base, spec, nmap, cnmap;
    float3 le, absorb;
    float metallic, roughness, ior, normal_scale, transmission, coat, coat_rough, coat_nscale;
    st_u32 flags, alpha_mode;
    float alpha_cutoff;
} st_material_at;

static st_material_at material_at(const st_scene_refs *s, const st_params *p,
                                  const st_shading *sh, st_hit h, float cos_nd, float travelled)
{
    st_u32 t = h.prim;
    __global const st_material *m = &s->materials[s->tri_material[t]]; /* fields as needed */
    st_material_at a;
    a.spec = vload4(0, m->specular);
    a.metallic = m->metallic;
    a.roughness = m->roughness;
    a.ior = m->ior;
    a.base = vload4(0, m->base_color);
    a.le = vload4(0, m->emission).xyz;
    a.flags = m->flags;
    a.alpha_mode = m->alpha_mode;
    a.alpha_cutoff = m->alpha_cutoff;
    a.normal_scale = m->normal_scale;
    a.transmission = m->transmission;
    a.absorb = a.transmission > 0.0f ? vload3(0, m->absorption) : (float3)(0.0f);
    a.coat = m->clearcoat;
    a.coat_rough = m->clearcoat_roughness;
    a.coat_nscale = m->clearcoat_normal_scale;
    a.nmap = a.cnmap = (float4)(0.0f);
    if (m->flags & ST_MAT_VERTEX_COLOR) { /* COLOR_0 multiplies the base colour */
        __global const st_tri_colors *c = &s->colors[t];
        a.base *= (1.0f - h.u - h.v) * vload4(0, c->c0) + h.u * vload4(0, c->c1) +
                  h.v * vload4(0, c->c2);
    }
    if (m->flags & ST_MAT_TEXTURED) { /* st_material_reads_textures */
        float px = 2.0f * p->camera.origin[3] / (float)p->height; /* pixel width at distance 1 */
        float width = p->camera.forward[3] > 0.5f ? px : px * travelled;
        float b1 = h.u, b2 = h.v;
        st_u32 f = sh->texture_filter;
        st_tex_refs x = tex_refs(s);
        a.base *= tex_lookup(x, m->base_color_tex, t, b1, b2, width, cos_nd, f);
        a.le *= tex_lookup(x, m->emission_tex, t, b1, b2, width, cos_nd, f).xyz;
        float4 mr = tex_lookup(x, m->metallic_roughness_tex, t, b1, b2, width, cos_nd, f);
        a.metallic *= mr.z;
        a.roughness *= mr.y;
        a.spec.w *= tex_lookup(x, m->specular_tex, t, b1, b2, width, cos_nd, f).w;
        a.spec.xyz *= tex_lookup(x, m->specular_color_tex, t, b1, b2, width, cos_nd, f).xyz;
        a.transmission *= tex_lookup(x, m->transmission_tex, t, b1, b2, width, cos_nd, f).x;
        a.coat *= tex_lookup(x, m->clearcoat_tex, t, b1, b2, width, cos_nd, f).x;
        a.coat_rough *= tex_lookup(x, m->clearcoat_roughness_tex, t, b1, b2, width, cos_nd, f).y;
        if (m->normal_tex != ST_NO_TEXTURE)
            a.nmap = (float4)(tex_lookup(x, m->normal_tex, t, b1, b2, width, cos_nd, f).xyz, 1.0f);
        if (m->clearcoat_normal_tex != ST_NO_TEXTURE)
            a.cnmap = (float4)(
                tex_lookup(x, m->clearcoat_normal_tex, t, b1, b2, width, cos_nd, f).xyz, 1.0f);
    }
    return a;
}

/* The sheen (KHR_materials_sheen) of the lanes in `bits`, whose materials
 * have ST_MAT_SHEEN, into sn (the other lanes' cleared): sheenColorFactor x
 * texture RGB and sheenRoughnessFactor x texture alpha, looked up with
 * material_at's footprint from what vertex_gather left in l. Done after
 * the gather and out of line, so that a vertex without a sheen pays one
 * bit test per lane. */
ST_COLD void sheen_gather(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                          const st_vertex_in *l, st_u32 bits, st_sheen_in *sn)
{
    *sn = (st_sheen_in){{{0.0f}}, {0.0f}};
    float px = 2.0f * p->camera.origin[3] / (float)p->height; /* pixel width at distance 1 */
    st_tex_refs x = tex_refs(s);
    for (st_u32 k = 0; k < ST_W; k++) {
        if (!((bits >> k) & 1u))
            continue;
        st_u32 t = l->prim[k];
        __global const st_material *m = &s->materials[s->tri_material[t]];
        float3 c = vload3(0, m->sheen_color);
        float r = m->sheen_roughness;
        if (m->sheen_color_tex != ST_NO_TEXTURE || m->sheen_roughness_tex != ST_NO_TEXTURE) {
            float width = p->camera.forward[3] > 0.5f ? px : px * l->travelled[k];
            float cos_nd = -dot(lane3(l->ng, k), lane3(l->d, k));
            float u = l->bu[k], v = l->bv[k];
            st_u32 f = sh->texture_filter;
            c *= tex_lookup(x, m->sheen_color_tex, t, u, v, width, cos_nd, f).xyz;
            r *= tex_lookup(x, m->sheen_roughness_tex, t, u, v, width, cos_nd, f).w;
        }
        set_lane3(sn->colour, k, c);
        sn->rough[k] = r;
    }
}

/* Whether a ray goes on through the surface of material a: an alpha MASK
 * cut-out, or BLEND coverage (passes with probability 1 - alpha, drawn from
 * the counter hash keyed by the seed ^ key, the sample, the triangle and
 * depth). */
static int alpha_passes_keyed(const st_params *p, const st_material_at *a, st_sample smp,
                              st_u32 prim, st_u32 depth, st_u32 key)
{
    if (a->alpha_mode == ST_ALPHA_OPAQUE)
        return 0;
    float u = st_rng_unit(st_rng_key(p->seed ^ key, smp.pixel, smp.index), prim ^ (depth << 24));
    return a->alpha_mode == ST_ALPHA_MASK ? a->base.w < a->alpha_cutoff : u >= a->base.w;
}

/* The key of the rays a path follows (shadow rays: shadow.h). */
#define ST_PATH_ALPHA_KEY 0xa1fa0000u

/* Texture tex at lane k's hit, looked up with material_at's footprint
 * from what vertex_gather left in l (white where tex is ST_NO_TEXTURE). */
static float4 lane_texel(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                         const st_vertex_in *l, st_u32 k, st_u32 tex)
{
    float px = 2.0f * p->camera.origin[3] / (float)p->height; /* pixel width at distance 1 */
    float width = p->camera.forward[3] > 0.5f ? px : px * l->travelled[k];
    float cos_nd = -dot(lane3(l->ng, k), lane3(l->d, k));
    return tex_lookup(tex_refs(s), tex, l->prim[k], l->bu[k], l->bv[k], width, cos_nd,
                      sh->texture_filter);
}

/* The diffuse transmission (KHR_materials_diffuse_transmission) of the
 * lanes in `bits`, whose materials have ST_MAT_DIFFUSE_TRANS, into dt (the
 * other lanes' cleared): the share, diffuseTransmissionFactor x texture A,
 * and the colour, diffuseTransmissionColorFactor x texture RGB. Out of
 * line, as sheen_gather. */
ST_COLD void dtrans_gather(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                           const st_vertex_in *l, st_u32 bits, st_dtrans_in *dt)
{
    *dt = (st_dtrans_in){{{0.0f}}, {0.0f}};
    for (st_u32 k = 0; k < ST_W; k++) {
        if (!((bits >> k) & 1u))
            continue;
        __global const st_material *m = &s->materials[s->tri_material[l->prim[k]]];
        float4 f = vload4(0, m->diffuse_trans);
        if (m->diffuse_trans_tex != ST_NO_TEXTURE)
            f.w *= lane_texel(s, p, sh, l, k, m->diffuse_trans_tex).w;
        if (m->diffuse_trans_color_tex != ST_NO_TEXTURE)
            f.xyz *= lane_texel(s, p, sh, l, k, m->diffuse_trans_color_tex).xyz;
        set_lane3(dt->colour, k, f.xyz);
        dt->share[k] = f.w;
    }
}

/* The thin film (KHR_materials_iridescence) of the lanes in `bits`, whose
 * materials have ST_MAT_IRIDESCENT, into ir (the other lanes' cleared):
 * its weight, iridescenceFactor x texture R, its ior, and its thickness,
 * mix(minimum, maximum, thickness texture G), the maximum without that
 * texture. Out of line, as sheen_gather. */
ST_COLD void irid_gather(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                         const st_vertex_in *l, st_u32 bits, st_irid_in *ir)
{
    *ir = (st_irid_in){{0.0f}, {0.0f}, {0.0f}};
    for (st_u32 k = 0; k < ST_W; k++) {
        if (!((bits >> k) & 1u))
            continue;
        __global const st_material *m = &s->materials[s->tri_material[l->prim[k]]];
        float4 f = vload4(0, m->iridescence);
        float w = f.x, nm = f.w;
        if (m->iridescence_tex != ST_NO_TEXTURE)
            w *= lane_texel(s, p, sh, l, k, m->iridescence_tex).x;
        if (m->iridescence_thickness_tex != ST_NO_TEXTURE)
            nm = mix(f.z, f.w, lane_texel(s, p, sh, l, k, m->iridescence_thickness_tex).y);
        ir->weight[k] = w;
        ir->ior[k] = f.y;
        ir->nm[k] = nm;
    }
}

/* The tangent of triangle prim interpolated at (bu, bv), and in *w its
 * handedness (0: the triangle has no tangents). */
static float3 interpolated_tangent(const st_scene_refs *s, st_u32 prim, float bu, float bv,
                                   float *w)
{
    __global const st_tri_tangents *tt = &s->tangents[prim];
    *w = tt->t0[3];
    return (1.0f - bu - bv) * vload4(0, tt->t0).xyz + bu * vload4(0, tt->t1).xyz +
           bv * vload4(0, tt->t2).xyz;
}

/* The anisotropy (KHR_materials_anisotropy) of the lanes in `bits`, whose
 * materials have ST_MAT_ANISO, into an (the other lanes' cleared): the
 * strength, anisotropyStrength x texture B, and the direction, texture RG
 * as 2 c - 1 ((1, 0) without a texture) turned counter-clockwise by
 * anisotropyRotation in the frame of the tangent and the bitangent w x
 * cross(n, tangent) (the normal map's frame), in world space. A triangle
 * without tangents (no texture coordinates), or a texel of no direction,
 * gets strength 0: the isotropic lobe. Out of line, as sheen_gather. */
ST_COLD void aniso_gather(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                          const st_vertex_in *l, st_u32 bits, st_aniso_in *an)
{
    *an = (st_aniso_in){{{0.0f}}, {0.0f}};
    for (st_u32 k = 0; k < ST_W; k++) {
        if (!((bits >> k) & 1u))
            continue;
        st_u32 t = l->prim[k];
        __global const st_material *m = &s->materials[s->tri_material[t]];
        float strength = m->anisotropy[0];
        float2 d = (float2)(1.0f, 0.0f);
        if (m->anisotropy_tex != ST_NO_TEXTURE) {
            float3 c = lane_texel(s, p, sh, l, k, m->anisotropy_tex).xyz;
            d = 2.0f * c.xy - 1.0f;
            strength *= c.z;
        }
        float cr = m->anisotropy[1], sr = m->anisotropy[2], bu = l->bu[k], bv = l->bv[k], w;
        d = (float2)(cr * d.x - sr * d.y, sr * d.x + cr * d.y);
        float3 tg = interpolated_tangent(s, t, bu, bv, &w);
        float3 n = (1.0f - bu - bv) * lane3(l->n0, k) + bu * lane3(l->n1, k) + bv * lane3(l->n2, k);
        float3 dir = d.x * tg + d.y * w * cross(n, tg);
        if (w == 0.0f || !(dot(dir, dir) > 1e-12f))
            strength = 0.0f;
        set_lane3(an->dir, k, dir);
        an->strength[k] = strength;
    }
}

/* The inputs of more->*_bits' lanes (the bits set by the caller). */
ST_HOT void more_gather(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                        const st_vertex_in *l, st_more_in *more)
{
    if (more->aniso_bits)
        aniso_gather(s, p, sh, l, more->aniso_bits, &more->aniso);
    if (more->dtrans_bits)
        dtrans_gather(s, p, sh, l, more->dtrans_bits, &more->dtrans);
    if (more->irid_bits)
        irid_gather(s, p, sh, l, more->irid_bits, &more->irid);
}

/* The shading normal ns bent by a normal map's texel c (tangent-space
 * normal 2 c - 1, x and y times normalTexture.scale) in the frame of the
 * interpolated tangent, made orthogonal to ns, and the bitangent w x
 * cross(ns, tangent). Kept at least a little above the geometric surface
 * ng, so that a map cannot turn the shading side over; ns stays where the
 * triangle has no tangent (no texture coordinates). */
static float3 normal_mapped(const st_scene_refs *s, st_u32 prim, float bu, float bv, float3 ns,
                            float3 ng, float3 c, float scale)
{
    float w;
    float3 tg = interpolated_tangent(s, prim, bu, bv, &w);
    tg -= ns * dot(ns, tg);
    float len = length(tg);
    if (!(len > 1e-6f) || w == 0.0f)
        return ns;
    tg /= len;
    float3 t = 2.0f * c - 1.0f;
    float3 n = t.x * scale * tg + t.y * scale * w * cross(ns, tg) + t.z * ns;
    float up = dot(n, ng);
    if (up < 0.01f)
        n += (0.01f - up) * ng;
    len = length(n);
    return len > 0.0f ? n / len : ns;
}

/* The probabilities with which next-event estimation samples the
 * environment and the area lights (light_gather): both take what the
 * punctual lights leave, split by power (st_shading.env_pick). The MIS
 * weights at an emitter and at a miss use these same numbers. */
static float env_choice(const st_shading *sh)
{
    return (1.0f - sh->punct_share) * sh->env_pick;
}

static float area_choice(const st_shading *sh)
{
    return (1.0f - sh->punct_share) * (1.0f - sh->env_pick);
}

/* The environment map's radiance at map coordinates (u, v) (nearest
 * texel: kernels/integrator/envmap.h) times the env factor, and in *pdf the density in
 * solid angle with which env_gather picks that direction. */
static float3 env_map_at(__global const float *env_cdf, __global const float *env_texels,
                         const st_shading *sh, float u, float v, float *pdf)
{
    st_u32 w = sh->env_size[0], h = sh->env_size[1], i, j;
    st_env_texel(w, h, u, v, &i, &j);
    *pdf = st_env_solid_angle_pdf(st_env_texel_pdf(env_cdf, w, h, i, j), v);
    return vload4(0, sh->env).xyz * vload4(j * w + i, env_texels).xyz;
}

/* Whether the environment gives light (a uniform one's radiance, or a map's
 * factor, above 0): a ray that leaves the scene sees it. */
static int env_lit(const st_shading *sh)
{
    float3 env = vload4(0, sh->env).xyz;
    return env.x > 0.0f || env.y > 0.0f || env.z > 0.0f;
}

/* The environment's radiance arriving against the world direction d; with a
 * map, *pdf becomes env_gather's density of d (a uniform environment leaves
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

/* Lane k's environment sample from (u1, u2): the map's importance sampling
 * by luminance (a world direction, its radiance and density x choice), or
 * for a uniform environment (u1, u2) themselves, which light_sample turns
 * into a cosine-distributed direction about the shading normal in lanes. */
static void env_gather(const st_scene_refs *s, const st_shading *sh, float u1, float u2, st_u32 k,
                       st_vertex_in *l)
{
    float choice = env_choice(sh), pdf;
    if (sh->env_size[0] == 0u) { /* the direction is made in lanes (light_sample) */
        set_lane3(l->lp, k, (float3)(u1, u2, 0.0f));
        set_lane3(l->ll, k, vload4(0, sh->env).xyz);
        l->lq[k] = choice;
        l->lkind[k] = ST_LIGHT_ENV_LOCAL;
        return;
    }
    float u, w, dm[3], dw[3];
    st_env_sample(s->env_cdf, sh->env_size[0], sh->env_size[1], u1, u2, &u, &w);
    st_env_direction(u, w, dm);
    st_env_rotate(sh->env_rot, 1, dm, dw);
    set_lane3(l->lp, k, (float3)(dw[0], dw[1], dw[2]));
    set_lane3(l->ll, k, env_map_at(s->env_cdf, s->env_texels, sh, u, w, &pdf));
    l->lq[k] = pdf * choice;
    l->lkind[k] = ST_LIGHT_ENV;
}

/* Lane k's punctual light, picked by power with u (probability punct_share
 * x its share of their power): a delta light, which no BSDF sample can
 * hit, so its sample takes weight 1 (no MIS). A spot's cone goes to the
 * lanes, which weigh its intensity (punctual_intensity); other lights get a
 * cone that passes everything. */
static void punctual_gather(const st_scene_refs *s, const st_shading *sh, float u, st_u32 k,
                            st_vertex_in *l)
{
    st_u32 j = pick_light(s->punct_cdf, sh->punct_count, &u);
    __global const st_punctual *pl = &s->punctual[j];
    st_u32 kind = (st_u32)pl->pos[3];
    l->lq[k] = sh->punct_share * st_cdf_prob(s->punct_cdf, j);
    set_lane3(l->ll, k, vload4(0, pl->intensity).xyz);
    if (kind == ST_PUNCT_DIRECTIONAL) {
        set_lane3(l->lp, k, -vload4(0, pl->dir).xyz);
        l->lkind[k] = ST_LIGHT_DISTANT;
        return;
    }
    set_lane3(l->lp, k, vload4(0, pl->pos).xyz);
    l->lkind[k] = ST_LIGHT_POINT;
    if (kind == ST_PUNCT_SPOT) {
        set_lane3(l->lnl, k, vload4(0, pl->dir).xyz);
        l->lco[k] = pl->dir[3];
        l->lci[k] = pl->intensity[3];
    }
}

/* Lane k's sample of light triangle lt at (u1, u2), whose barycentrics
 * are b1 = 1 - sqrt(u1), b2 = u2 sqrt(u1) (uniform in its area: the
 * caller's, in lanes or not): the point, its facing normal, emission and
 * density per area x choice. One body for area_gather and area_lanes. */
ST_HOT void area_at(const st_scene_refs *s, const st_shading *sh, st_u32 lt, float u1, float u2,
                    float b1, float b2, st_u32 k, st_vertex_in *l)
{
    set_lane3(l->lp, k, triangle_at(s->tris, lt, b1, b2));
    set_lane3(l->lnl, k, facing_normal(s->normals, lt));
    set_lane3(l->ll, k, light_emission(s, lt, u1, u2, sh->texture_filter));
    l->lq[k] = s->light_pdf[lt] * area_choice(sh);
}

/* Lane k's area-light sample: the triangle picked by power with u, the
 * point uniform in its area (area_at). */
static void area_gather(const st_scene_refs *s, const st_params *p, const st_shading *sh, float u,
                        float u2, st_u32 k, st_vertex_in *l)
{
    st_u32 lt = s->light_tri[pick_light(s->light_cdf, p->light_count, &u)];
    float su = sqrt(u);
    area_at(s, sh, lt, u, u2, 1.0f - su, u2 * su, k, l);
    l->lkind[k] = ST_LIGHT_AREA;
}

/* Lane k's light sample for next-event estimation: a punctual light (with
 * probability punct_share), else the environment or one point on one
 * emissive triangle, chosen by power (env_pick). One stratified dimension
 * makes each choice and then the sample's first coordinate (pick_light). */
static void light_gather(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                         st_u32 k, st_vertex_in *l)
{
    float u = l->u[0][k], u2 = l->u[1][k], pe = sh->env_pick;
    l->lkind[k] = ST_LIGHT_NONE;
    l->lco[k] = -1.0f; /* a cone that passes every direction (punctual_gather) */
    l->lci[k] = 0.0f;
    set_lane3(l->lnl, k, (float3)(0.0f));
    if (sh->punct_count > 0u) { /* u both chooses and stays stratified (pick_light) */
        if (u < sh->punct_share) {
            punctual_gather(s, sh, u / sh->punct_share, k, l);
            return;
        }
        u = fmin((u - sh->punct_share) / (1.0f - sh->punct_share), 0.99999994f);
    }
    int take_env = u < pe;
    if (pe > 0.0f && pe < 1.0f)
        u = take_env ? u / pe : fmin((u - pe) / (1.0f - pe), 0.99999994f);
    if (take_env)
        env_gather(s, sh, u, u2, k, l);
    else if (p->light_count > 0u)
        area_gather(s, p, sh, u, u2, k, l);
}

/* light_gather for the lanes in `bits` where the plan picks area lights
 * in lanes (p->area_lanes: area lights alone, from a short list), its
 * choice in lanes: each lane's triangle picked from the CDF with dimension
 * 0 rescaled, as st_cdf_pick picks and rescales (the entries at or below u
 * among all but the last, counted, are its binary search's index in a CDF
 * that never decreases), and the point's barycentrics; the triangle's
 * point, normal, emission and density gathered lane by lane (area_at, as
 * area_gather gathers them). The other lanes keep what vertex_clear_some
 * left. */
ST_HOT void area_lanes(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                       st_u32 bits, st_vertex_in *l)
{
    st_lf u = ST_LV(l->u[0]), c0 = ST_LF(0.0f), c1 = ST_LF(0.0f);
    st_li below = (st_li)(0), found = (st_li)(0);
    st_u32 n = p->light_count;
    for (st_u32 j = 0; j < n; j++) {
        st_lf c = ST_LF(s->light_cdf[j]);
        st_li le = j + 1u < n ? c <= u : (st_li)(0);
        st_li take = !found & !le; /* the first entry above u, or the last */
        below += ST_SELECT(ST_W, (st_li)(0), (st_li)(1), le);
        c0 = ST_SELECT(ST_W, c0, c, le);
        c1 = ST_SELECT(ST_W, c1, c, take);
        found |= take;
    }
    u = ST_SELECT(ST_W, ST_LF(0.0f), fmin((u - c0) / (c1 - c0), 0.99999994f), c1 > c0);
    st_lf su = sqrt(u);
    float u1[ST_W], b1[ST_W], b2[ST_W];
    int pick[ST_W];
    ST_VSTORE(ST_W, u, u1);
    ST_VSTORE(ST_W, 1.0f - su, b1);
    ST_VSTORE(ST_W, ST_LV(l->u[1]) * su, b2);
    ST_VSTORE(ST_W, below, pick);
    for (st_u32 k = 0; k < ST_W; k++)
        if ((bits >> k) & 1u)
            area_at(s, sh, s->light_tri[pick[k]], u1[k], l->u[1][k], b1[k], b2[k], k, l);
    st_li on = ST_BITS_MASK(ST_W, bits);
    ST_VSTORE(ST_W, ST_SELECT(ST_W, ST_LV(l->lkind), (st_li)(ST_LIGHT_AREA), on), l->lkind);
    ST_VSTORE(ST_W, ST_SELECT(ST_W, ST_LV(l->lco), ST_LF(-1.0f), on), l->lco);
}

/* ---- the lanes' arithmetic ------------------------------------------------ */

/* The layers of ST_W surface points, where some lane has them (kept out of
 * st_vertex, so that a vertex without them stays as small as before). */
typedef struct st_layers {
    st_dielectric diel; /* the transmission lobe (bsdf_dielectric.h) */
    st_sheen sheen;     /* the sheen (bsdf_sheen.h) */
    st_coat coat;       /* the clear coat (bsdf_coat.h) */
} st_layers;

/* What the steps know of ST_W surface points. */
typedef struct st_vertex {
    st_lv3 pos, wo;     /* the points, and the directions back along the rays */
    st_lv3 ng, ns;      /* geometric and shading normals, turned to the ray's side */
    st_lv3 tu, tv;      /* the shading frame's tangents */
    st_lv3 albedo;      /* the Lambertian part's albedo ((1 - metallic) x base colour) */
    st_brdf brdf;       /* the glTF BRDF (bsdf.h), where glossy */
    st_layers *lay;     /* the layers, where layered (layer_bits) */
    st_dir wo_local;    /* wo in the shading frame, where glossy */
    st_li glossy;       /* the lanes with a specular lobe (metallic, specular or transmission > 0) */
    st_u32 trans_bits;  /* the lanes with transmission > 0, lane k bit k (0: no work) */
    st_u32 pass_bits;   /* those and the lanes with diffuse transmission: light passes */
    st_u32 layer_bits;  /* the lanes with transmission, a sheen or a clear coat (of glossy) */
    st_u32 sheen_bits;  /* the lanes with a sheen (of layer_bits) */
    st_lv3 beta, rad;   /* the paths' throughput and radiance */
} st_vertex;

/* The normal interpolated from the vertex normals. */
ST_HOT st_lv3 interpolated_normal(const st_vertex_in *l)
{
    st_lf bu = ST_LV(l->bu), bv = ST_LV(l->bv), w0 = 1.0f - bu - bv;
    st_lv3 n0 = ST_LV3_OF(l->n0), n1 = ST_LV3_OF(l->n1), n2 = ST_LV3_OF(l->n2);
    st_lv3 sum = st_lv3_make(w0 * n0.x + bu * n1.x + bv * n2.x, w0 * n0.y + bu * n1.y + bv * n2.y,
                             w0 * n0.z + bu * n1.z + bv * n2.z);
    return st_lv3_div(sum, sqrt(st_lv3_dot(sum, sum)));
}

/* ns bent by the normal map (texels map, scales scale) in the lanes of
 * `bits` (one lane at a time: normal_mapped reads the triangle's
 * tangents): the base's, or the clear coat's. */
ST_HOT st_lv3 mapped_normal(const st_scene_refs *s, const st_vertex_in *l, st_u32 bits,
                            const float (*map)[ST_W], const float *scale, st_lv3 ns, st_lv3 ng)
{
    float nsa[3][ST_W], nga[3][ST_W];
    lv3_store(ns, nsa);
    lv3_store(ng, nga);
    for (st_u32 k = 0; k < ST_W; k++)
        if ((bits >> k) & 1u)
            set_lane3(nsa, k, normal_mapped(s, l->prim[k], l->bu[k], l->bv[k], lane3(nsa, k),
                                            lane3(nga, k), lane3(map, k), scale[k]));
    return ST_LV3_OF(nsa);
}

/* The clear coat's own normal where a lane has its normal map (the lanes
 * of cmapped), in the base's shading frame of v and turned to its side. */
ST_COLD void coat_normal(const st_scene_refs *s, const st_vertex_in *l, st_u32 cmapped,
                         const st_vertex *v, st_coat *c)
{
    st_lv3 nc = mapped_normal(s, l, cmapped, l->cnmap, l->cnscale, interpolated_normal(l), v->ng);
    nc = st_lv3_select(nc, st_lv3_neg(nc), st_lv3_dot(nc, v->ng) < 0.0f);
    st_lv3 nl = st_lv3_make(st_lv3_dot(nc, v->tu), st_lv3_dot(nc, v->tv),
                          fmax(st_lv3_dot(nc, v->ns), 0.01f));
    nl = st_lv3_div(nl, sqrt(st_lv3_dot(nl, nl)));
    st_coat tilted = *c;
    st_coat_tilt(&tilted, nl);
    st_li mapped = ST_BITS_MASK(ST_W, cmapped);
    c->tu = st_lv3_select(c->tu, tilted.tu, mapped);
    c->tv = st_lv3_select(c->tv, tilted.tv, mapped);
    c->n = st_lv3_select(c->n, tilted.n, mapped);
}

/* The shading normal interpolated from the vertex normals, bent by the
 * normal map where a lane has one. */
ST_HOT st_lv3 shading_normal(const st_scene_refs *s, st_vertex_in *l, st_u32 nmapped, st_lv3 ng)
{
    st_lv3 ns = interpolated_normal(l);
    return nmapped ? mapped_normal(s, l, nmapped, l->nmap, l->nscale, ns, ng) : ns;
}

/* The emission seen along each lane's ray, weighted: 1 for a camera ray,
 * and for a ray made by a BSDF sample (depth > 0, not a refraction) the MIS weight against
 * sampling the same light (an emitter's density per area turned to solid
 * angle, t² / cos; the environment's as gathered). Emitters are one-sided. */
ST_HOT st_lv3 seen_emission(const st_vertex_in *l, const st_shading *sh, st_li miss, st_lf cos_o)
{
    st_lv3 le = ST_LV3_OF(l->le);
    st_lf t = ST_LV(l->t), q = ST_LV(l->emit_pdf);
    q = ST_SELECT(ST_W, q * area_choice(sh) * t * t / cos_o, q, miss);
    st_li seen = (miss || cos_o > 0.0f) && (le.x > 0.0f || le.y > 0.0f || le.z > 0.0f);
    st_lf pb = ST_LV(l->bsdf_pdf); /* 0 after a refraction: no light sample makes that ray */
    st_lf w = ST_SELECT(ST_W, ST_LF(1.0f), st_power_heuristic(pb, q),
                        ST_LV(l->depth) > 0u && pb > 0.0f);
    return st_lv3_scale(le, ST_SELECT(ST_W, ST_LF(0.0f), w, seen));
}

/* The path's radiance with what the vertex's lanes see added (seen_emission), cos_o the
 * cosine of wo to the geometric normal: all a vertex does where no lane scatters. */
ST_HOT st_lv3 vertex_radiance(const st_vertex_in *l, const st_shading *sh, st_li miss,
                              st_lf cos_o)
{
    st_lv3 beta = ST_LV3_OF(l->beta);
    return st_lv3_add(ST_LV3_OF(l->rad), st_lv3_mul(beta, seen_emission(l, sh, miss, cos_o)));
}

/* Where a glossy lane's mirror direction of wo about the shading normal
 * falls below the geometric surface (an interpolated or normal-mapped ns
 * tilted far from ng), ns bent towards ng: to the half vector of wo and
 * that mirror direction lifted just above the surface (the shading normal
 * adaptation of Keller et al., "The Iray Light Transport Simulation and
 * Rendering System", 2017). The specular lobe then reflects into the
 * upper hemisphere instead of losing its energy through the surface, which
 * rendered black rims on glossy normal-mapped surfaces. Lambertian lanes
 * keep their normal, and so do transmissive ones: there the interpolated
 * normal is taken as it is and a sample's side is the geometry's
 * (vertex_bounce), Mitsuba 3's convention for its dielectrics, which keeps
 * a smooth glass object's energy at its outline (test_render.c
 * glass_furnace_coarse_keeps_the_outline, test_mitsuba_glass.sh). */
ST_HOT st_lv3 adapted_normal(st_lv3 ns, st_lv3 ng, st_lv3 wo, st_li glossy)
{
    st_lf c = 2.0f * st_lv3_dot(wo, ns);
    st_lv3 r = st_lv3_make(c * ns.x - wo.x, c * ns.y - wo.y, c * ns.z - wo.z);
    st_lf below = 0.01f - st_lv3_dot(r, ng);
    st_lv3 lifted = st_lv3_along(r, ng, below);
    lifted = st_lv3_div(lifted, sqrt(st_lv3_dot(lifted, lifted)));
    st_lv3 h = st_lv3_add(wo, lifted);
    h = st_lv3_div(h, sqrt(st_lv3_dot(h, h)));
    return st_lv3_select(ns, h, glossy && below > 0.0f);
}

/* The sheen of the lanes sheen_gather filled (black elsewhere). Out of
 * line (ST_COLD), as every step of a sheen (sheen_gather, sheened_f_pdf,
 * sheened_sample), to keep the vertex's inlined code, which every vertex
 * runs, close to what it is without a sheen; coated and transmissive lanes
 * without a sheen run bsdf_coat.h's plain forms. */
ST_COLD void sheen_layer(const st_sheen_in *shn, st_layers *lay)
{
    st_lf sc[3] = {ST_LV(shn->colour[0]), ST_LV(shn->colour[1]), ST_LV(shn->colour[2])};
    lay->sheen = st_sheen_make(sc, ST_LV(shn->rough));
}

/* Where a lane is anisotropic (the lanes of aniso_bits, directions and
 * strengths in an), the shading frame turned about ns so that tu runs
 * along the anisotropy direction made orthogonal to ns; returns the
 * strengths (0 where the direction lies along ns, whose lanes keep their
 * frame, and in the other lanes). */
ST_COLD st_lf aniso_frame(st_vertex *v, const st_aniso_in *an, st_u32 aniso_bits)
{
    st_lv3 d = ST_LV3_OF(an->dir), n = v->ns;
    d = st_lv3_along(d, n, -st_lv3_dot(d, n));
    st_lf len = sqrt(st_lv3_dot(d, d));
    st_li on = ST_BITS_MASK(ST_W, aniso_bits) && len > 1e-6f;
    st_lv3 t = st_lv3_div(d, ST_SELECT(ST_W, ST_LF(1.0f), len, on));
    st_lv3 b = st_lv3_make(n.y * t.z - n.z * t.y, n.z * t.x - n.x * t.z, n.x * t.y - n.y * t.x);
    v->tu = st_lv3_select(v->tu, t, on);
    v->tv = st_lv3_select(v->tv, b, on);
    return ST_SELECT(ST_W, ST_LF(0.0f), ST_LV(an->strength), on);
}

/* The Lambertian part's transmission where a lane has it (dtrans_gather's
 * share 0 elsewhere, which changes nothing). */
ST_COLD void dtrans_layer(const st_dtrans_in *dt, st_lf metallic, st_lf tr, st_brdf *b)
{
    st_lf c[3] = {ST_LV(dt->colour[0]), ST_LV(dt->colour[1]), ST_LV(dt->colour[2])};
    st_brdf_diffuse_transmission(b, metallic, tr, ST_LV(dt->share), c);
}

/* The thin film where a lane has it (weight 0 elsewhere: no film). */
ST_COLD void irid_layer(const st_irid_in *ir, st_brdf *b)
{
    st_brdf_iridescent(b, ST_LV(ir->weight), ST_LV(ir->ior), ST_LV(ir->nm));
}

/* The surface at each lane's hit: position, normals (turned to the side
 * the ray arrived on), the shading frame and the BRDF where glossy, with
 * the transmission lobe where bit k of trans_bits is set (lane k has
 * transmission > 0: vertex_gather; thin-walled where thin_bits' is), the
 * clear coat where coat_bits' is (about its own normal where cmapped's is),
 * the sheen where sheen_bits' is, and where more's bits say so the
 * anisotropic specular lobe (in a frame along its direction), the diffuse
 * transmission and the thin film. */
ST_HOT st_vertex vertex_surface(const st_scene_refs *s, st_vertex_in *l, st_u32 nmapped,
                                st_u32 trans_bits, st_u32 thin_bits, st_u32 coat_bits,
                                st_u32 cmapped, st_u32 sheen_bits,
                                const st_sheen_in *shn, const st_more_in *more,
                                st_layers *lay, st_li miss, const st_shading *sh, st_lf *cos_o)
{
    st_u32 dtrans_bits = more->dtrans_bits, aniso_bits = more->aniso_bits;
    st_vertex v;
    st_lv3 d = ST_LV3_OF(l->d);
    v.wo = st_lv3_neg(d);
    v.pos = st_lv3_along(ST_LV3_OF(l->o), d, ST_LV(l->t));
    v.ng = ST_LV3_OF(l->ng);
    v.ns = shading_normal(s, l, nmapped, v.ng);
    *cos_o = st_lv3_dot(v.ng, v.wo);
    v.beta = ST_LV3_OF(l->beta);
    v.lay = lay;
    v.trans_bits = trans_bits;
    v.pass_bits = trans_bits | dtrans_bits;
    v.layer_bits = trans_bits | coat_bits | sheen_bits;
    v.sheen_bits = sheen_bits;
    st_lf tr = trans_bits ? ST_LV(l->transmission) : ST_LF(0.0f);
    v.rad = vertex_radiance(l, sh, miss, *cos_o);
    v.ng = st_lv3_select(v.ng, st_lv3_neg(v.ng), *cos_o < 0.0f);
    v.ns = st_lv3_select(v.ns, st_lv3_neg(v.ns), st_lv3_dot(v.ns, v.ng) < 0.0f);
    st_lf metallic = ST_LV(l->metallic), specular = ST_LV(l->spec[3]);
    v.glossy = (metallic > 0.0f || specular > 0.0f) && !miss;
    if (v.layer_bits | dtrans_bits)
        v.glossy = v.glossy || ST_BITS_MASK(ST_W, v.layer_bits | dtrans_bits);
    if (ST_ANY(ST_W, v.glossy))
        v.ns = adapted_normal(v.ns, v.ng, v.wo, v.glossy && !ST_BITS_MASK(ST_W, v.pass_bits));
    st_basis(v.ns, &v.tu, &v.tv);
    st_lf strength = aniso_bits ? aniso_frame(&v, &more->aniso, aniso_bits) : ST_LF(0.0f);
    v.albedo = ST_LV3_OF(l->base);
    if (ST_ANY(ST_W, v.glossy)) {
        st_lf c[3] = {v.albedo.x, v.albedo.y, v.albedo.z};
        st_lf sc[3] = {ST_LV(l->spec[0]), ST_LV(l->spec[1]), ST_LV(l->spec[2])};
        v.brdf = st_brdf_make(c, metallic, ST_LV(l->roughness), specular, sc, ST_LV(l->ior), tr);
        if (aniso_bits)
            st_brdf_anisotropic(&v.brdf, strength);
        if (dtrans_bits)
            dtrans_layer(&more->dtrans, metallic, tr, &v.brdf);
        if (more->irid_bits)
            irid_layer(&more->irid, &v.brdf);
        if (v.layer_bits) { /* entering where the ray meets the front */
            lay->diel = st_dielectric_make(tr, metallic, c, ST_LV(l->ior), *cos_o >= 0.0f,
                                           ST_BITS_MASK(ST_W, thin_bits));
            lay->coat = st_coat_make(ST_LV(l->coat), ST_LV(l->coat_rough));
            if (cmapped)
                coat_normal(s, l, cmapped, &v, &lay->coat);
            if (sheen_bits)
                sheen_layer(shn, lay);
        }
        v.albedo = st_lv3_select(
            v.albedo, st_lv3_make(v.brdf.diffuse[0], v.brdf.diffuse[1], v.brdf.diffuse[2]),
            v.glossy);
        /* wo below the shading normal's horizon (interpolated normals at a
         * silhouette) is lifted just above it, so the BRDF does not go
         * black there */
        st_lf z = fmax(st_lv3_dot(v.wo, v.ns), 1e-4f);
        v.wo_local = st_dir_normalize(st_lv3_make(st_lv3_dot(v.wo, v.tu), st_lv3_dot(v.wo, v.tv), z));
    }
    return v;
}

/* The direction with local coordinates w (in the frame tu, tv, ns). */
ST_HOT st_lv3 vertex_world(const st_vertex *v, st_dir w)
{
    st_lv3 d = st_lv3_make(w.x * v->tu.x + w.y * v->tv.x + w.z * v->ns.x,
                           w.x * v->tu.y + w.y * v->tv.y + w.z * v->ns.y,
                           w.x * v->tu.z + w.y * v->tv.z + w.z * v->ns.z);
    return st_lv3_div(d, sqrt(st_lv3_dot(d, d)));
}

/* The whole material with its sheen (bsdf_coat.h's _sheened forms): f[3]
 * and *pdf at li, and a direction from (u1, u2, u3). */
ST_COLD void sheened_f_pdf(const st_vertex *v, st_dir li, st_lf *f, st_lf *pdf)
{
    const st_layers *y = v->lay;
    st_coated_sheened_eval(&v->brdf, &y->diel, &y->sheen, &y->coat, v->wo_local, li, f);
    *pdf = st_coated_sheened_pdf(&v->brdf, &y->diel, &y->sheen, &y->coat, v->wo_local, li);
}

ST_COLD st_dir sheened_sample(const st_vertex *v, st_lf u1, st_lf u2, st_lf u3)
{
    const st_layers *y = v->lay;
    return st_coated_sheened_sample(&v->brdf, &y->diel, &y->sheen, &y->coat, v->wo_local, u1, u2,
                                    u3);
}

/* Where a lane is layered (transmissive, sheened or coated), f[3] and
 * *pdf (the BRDF's at li) become the whole material's (bsdf_coat.h: the
 * coat over bsdf_sheen.h's sheen over bsdf_dielectric.h's material); the
 * other lanes keep theirs bit for bit. */
ST_HOT void bsdf_with_layers(const st_vertex *v, st_dir li, st_lf *f, st_lf *pdf)
{
    st_lf ft[3];
    st_lf pt;
    if (v->sheen_bits) {
        sheened_f_pdf(v, li, ft, &pt);
    } else {
        st_coated_eval(&v->brdf, &v->lay->diel, &v->lay->coat, v->wo_local, li, ft);
        pt = st_coated_pdf(&v->brdf, &v->lay->diel, &v->lay->coat, v->wo_local, li);
    }
    st_li layered = ST_BITS_MASK(ST_W, v->layer_bits);
    for (int k = 0; k < 3; k++)
        f[k] = ST_SELECT(ST_W, f[k], ft[k], layered);
    *pdf = ST_SELECT(ST_W, *pdf, pt, layered);
}

/* f(wo, wi) cos θi for directions wi above the surface, and in *pdf the
 * density with which vertex_bounce would choose wi. */
ST_HOT st_lv3 surface_f_cos(const st_vertex *v, st_lv3 wi, st_lf *pdf)
{
    st_lf c = st_lv3_dot(v->ns, wi);
    *pdf = c / ST_PI_F;
    st_lv3 f = st_lv3_scale(v->albedo, *pdf);
    if (ST_ANY(ST_W, v->glossy)) {
        st_dir li = st_lv3_make(st_lv3_dot(wi, v->tu), st_lv3_dot(wi, v->tv), c);
        st_lf fk[3];
        st_brdf_eval(&v->brdf, v->wo_local, li, fk);
        st_lf gp = st_brdf_pdf(&v->brdf, v->wo_local, li);
        if (v->layer_bits)
            bsdf_with_layers(v, li, fk, &gp);
        *pdf = ST_SELECT(ST_W, *pdf, gp, v->glossy);
        f = st_lv3_select(f, st_lv3_scale(st_lv3_make(fk[0], fk[1], fk[2]), c), v->glossy);
    }
    return f;
}

/* Next-event estimation's shadow rays, from the light samples gathered:
 * the direction and distance to the light, the cosines it needs, and what
 * the ray adds when unoccluded, beta f cos L w / q, with q the sample's
 * density in solid angle (x its choice) and w the power heuristic's weight
 * against the BSDF sample (1 for a delta light, which no BSDF sample hits).
 * *tmax: the ray's length; 0 where none. */
ST_HOT st_lv3 light_sample(const st_vertex_in *l, const st_vertex *v, st_lv3 origin, float eps,
                           st_lv3 *wi, st_lf *tmax)
{
    st_li kind = ST_LV(l->lkind);
    st_li at_point = kind == ST_LIGHT_AREA || kind == ST_LIGHT_POINT;
    st_li in_frame = kind == ST_LIGHT_ENV_LOCAL, area = kind == ST_LIGHT_AREA;
    st_lv3 lp = ST_LV3_OF(l->lp);
    st_dir wl = lp;
    *wi = lp;
    if (ST_ANY(ST_W, in_frame)) {
        wl = st_cosine_sample(lp.x, lp.y);
        *wi = st_lv3_select(*wi, vertex_world(v, wl), in_frame);
    }
    st_lv3 to = st_lv3_sub(lp, origin);
    st_lf dist2 = st_lv3_dot(to, to), dist = sqrt(dist2);
    *wi = st_lv3_select(*wi, st_lv3_div(to, dist), at_point);
    dist2 = ST_SELECT(ST_W, ST_LF(1.0f), dist2, at_point);
    *tmax = ST_SELECT(ST_W, ST_LF(INFINITY), dist * (1.0f - 1e-3f) - eps, at_point);
    st_lf cos_l = -st_lv3_dot(ST_LV3_OF(l->lnl), *wi);
    st_lf q = ST_LV(l->lq) * dist2 * ST_SELECT(ST_W, ST_LF(1.0f), wl.z / ST_PI_F, in_frame) /
              ST_SELECT(ST_W, ST_LF(1.0f), cos_l, area);
    /* a spot's falloff, t² with t = (cos - cos_outer) / max(1e-3, cos_inner
     * - cos_outer) clamped to [0, 1] (KHR_lights_punctual); 1 elsewhere */
    st_lf co = ST_LV(l->lco), tc = (cos_l - co) / fmax(1e-3f, ST_LV(l->lci) - co);
    tc = st_clamp01(ST_SELECT(ST_W, ST_LF(1.0f), tc, kind == ST_LIGHT_POINT));
    st_li ok = kind != ST_LIGHT_NONE && st_lv3_dot(v->ns, *wi) > 0.0f &&
               st_lv3_dot(v->ng, *wi) > 0.0f && (!area || cos_l > 0.0f) && *tmax > 0.0f &&
               q > 0.0f;
    st_lf pdf_bsdf;
    st_lv3 fc = surface_f_cos(v, *wi, &pdf_bsdf);
    st_li weigh = kind == ST_LIGHT_AREA || kind == ST_LIGHT_ENV || in_frame; /* not delta */
    st_lf w = ST_SELECT(ST_W, ST_LF(1.0f), st_power_heuristic(q, pdf_bsdf), weigh);
    *tmax = ST_SELECT(ST_W, ST_LF(0.0f), *tmax, ok);
    st_lv3 c = st_lv3_mul(st_lv3_mul(v->beta, fc), ST_LV3_OF(l->ll));
    return st_lv3_scale(c, tc * tc * (w / q));
}

/* The BSDF sample: a cosine-weighted direction where Lambertian, else one
 * from the BRDF's mixture (bsdf.h), or where transmissive from the whole
 * material's (bsdf_dielectric.h, u3 choosing reflection or refraction);
 * beta *= f |cos| / pdf. *pdf: its density (for MIS where the ray ends;
 * 0 for a direction next-event estimation cannot make, which samples only
 * above both surfaces: its emission then takes weight 1), *cz its cosine
 * about the shading normal. An opaque lane's direction must lie above both
 * the shading and the geometric surface (the others' paths end). A
 * transmissive lane's goes on wherever it points, its side (into the
 * object or back out) the geometry's, as in Mitsuba 3: where the shading
 * normal strays from the facet's, a refraction may leave on the side it
 * came from and a reflection enter, and ending those paths darkened the
 * outlines of smooth-normal glass. */
ST_HOT st_li vertex_bounce(st_vertex *v, st_lf u1, st_lf u2, st_lf u3, st_lv3 *wi, st_lf *pdf,
                           st_lf *cz)
{
    st_dir w = st_cosine_sample(u1, u2);
    *pdf = w.z / ST_PI_F;
    st_lv3 weight = v->albedo;
    if (ST_ANY(ST_W, v->glossy)) {
        st_dir g = st_brdf_sample(&v->brdf, v->wo_local, u1, u2);
        if (v->layer_bits) {
            st_dir c = v->sheen_bits ? sheened_sample(v, u1, u2, u3)
                                     : st_coated_sample(&v->brdf, &v->lay->diel, &v->lay->coat,
                                                        v->wo_local, u1, u2, u3);
            g = st_lv3_select(g, c, ST_BITS_MASK(ST_W, v->layer_bits));
        }
        st_lf f[3], gp = st_brdf_pdf(&v->brdf, v->wo_local, g);
        st_brdf_eval(&v->brdf, v->wo_local, g, f);
        if (v->layer_bits)
            bsdf_with_layers(v, g, f, &gp);
        w = st_lv3_select(w, g, v->glossy);
        *pdf = ST_SELECT(ST_W, *pdf, gp, v->glossy);
        st_lf gz = ST_SELECT(ST_W, g.z, -g.z, g.z < 0.0f); /* refracted (transmissive lanes) */
        weight = st_lv3_select(weight, st_lv3_scale(st_lv3_make(f[0], f[1], f[2]), gz / gp),
                               v->glossy);
    }
    *cz = w.z;
    *wi = vertex_world(v, w);
    st_li ok = *cz > 0.0f && *pdf > 0.0f && st_lv3_dot(*wi, v->ng) > 0.0f;
    if (v->pass_bits) {
        st_li trans = ST_BITS_MASK(ST_W, v->pass_bits) && *pdf > 0.0f;
        st_li through = trans && st_lv3_dot(*wi, v->ng) < 0.0f; /* into the object */
        st_li back = trans && *cz < 0.0f && st_lv3_dot(*wi, v->ng) > 0.0f;
        ok = ok || through || back;
        *pdf = ST_SELECT(ST_W, *pdf, ST_LF(0.0f), through || back);
    }
    v->beta = st_lv3_select(v->beta, st_lv3_mul(v->beta, weight), ok);
    return ok;
}

/* Russian roulette from the ST_RR_START_DEPTH-th vertex on: the path ends
 * with probability q = max(0.05, 1 - max beta) (u below q) and survivors
 * divide by 1 - q. Returns the lanes that go on. */
ST_HOT st_li roulette(st_vertex *v, st_lu depth, st_lf u)
{
    st_li play = depth + 1u >= ST_RR_START_DEPTH;
    st_lv3 b = v->beta;
    st_lf q = fmax(0.05f, 1.0f - fmax(b.x, fmax(b.y, b.z)));
    st_li ends = play && u < q;
    v->beta = st_lv3_select(b, st_lv3_div(b, 1.0f - q), play && !ends);
    return !ends;
}

#endif
