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
 * Materials are Lambertian: f = albedo / π with albedo = base colour x
 * (1 - metallic) (glTF factors times their textures, texture.h), emitters
 * one-sided on the side their shading normals face. Alpha MASK cut-outs and
 * BLEND (as stochastic coverage: a ray passes with probability 1 - alpha)
 * let the ray go on through the surface without a bounce: the path keeps its
 * depth but spends one of the wave's trace iterations; shadow rays treat
 * such surfaces as opaque.
 * Environment (st_shading.env, uniform radiance): a path that leaves the
 * scene adds beta x env. Where there are no area lights it is also sampled
 * by next-event estimation: a cosine-distributed direction (dimensions 0, 1)
 * and a shadow ray to infinity, adding beta x albedo x env (f cos / pdf =
 * albedo) when unoccluded; in the path integrator that sample and the BSDF
 * sample have the same pdf, so MIS (either heuristic) weighs each 1/2. With
 * area lights too, the direct integrator picks the environment or the area
 * lights with probability 1/2 each (dimension 4) and divides by it; the path
 * integrator leaves the environment to BSDF samples (weight 1).
 * Texture level of detail: ray cones (texture.h) of the pixel's spread angle
 * 2 tan(yfov/2) / height (Akenine-Moller et al. 2019, eq. 30, small-angle
 * form), widening along the path's unfolded length, kept in ray_d.w
 * (surfaces taken as flat: no curvature or BSDF spread); an orthographic
 * camera's cone has the pixel's width and no spread.
 * Sample dimensions of vertex k: 2 + 6k + {0: light choice and first
 * coordinate on it (or the environment direction's first), 1: second
 * coordinate, 2,3: BSDF direction, 4: environment or area lights (direct
 * integrator with both), 5: Russian roulette}. BLEND coverage draws from
 * the counter hash, keyed by the triangle. */
#include "st_shared.h"
#include "rng.h"
#include "samplers.h"
#include "trace.h"
#include "texture.h"

#define ST_DIMS_PER_VERTEX 6u
#define ST_RR_START_DEPTH 3u

/* Index of the light whose CDF interval holds *u (first cdf[i] > *u), and *u
 * rescaled to [0, 1) within that interval, so that one stratified dimension
 * both chooses the light and places the point on it: a light's share of the
 * samples stays stratified (drawing the choice from a dimension of its own
 * would scatter each light's points and lose the stratification). */
static st_u32 pick_light(__global const float *cdf, st_u32 n, float *u)
{
    st_u32 lo = 0, hi = n - 1u;
    while (lo < hi) {
        st_u32 mid = (lo + hi) / 2u;
        if (cdf[mid] > *u)
            hi = mid;
        else
            lo = mid + 1u;
    }
    float c0 = lo ? cdf[lo - 1u] : 0.0f, c1 = cdf[lo];
    *u = c1 > c0 ? fmin((*u - c0) / (c1 - c0), 0.99999994f) : 0.0f;
    return lo;
}

/* Point of triangle t at barycentrics from (u1, u2), uniform in area. */
static float3 triangle_point(__global const st_triangle *tris, st_u32 t, float u1, float u2)
{
    float su = sqrt(u1);
    float b1 = 1.0f - su, b2 = u2 * su;
    float3 v0 = vload4(0, tris[t].v0).xyz;
    return v0 + b1 * vload4(0, tris[t].e1).xyz + b2 * vload4(0, tris[t].e2).xyz;
}

/* Geometric normal of triangle t, turned to the side of its shading normals
 * (precomputed: st_tri_normals). */
static float3 facing_normal(__global const st_tri_normals *normals, st_u32 t)
{
    return (float3)(normals[t].n0[3], normals[t].n1[3], normals[t].n2[3]);
}

static float power_heuristic(float a, float b)
{
    return a * a / (a * a + b * b);
}

/* Texture `tex` (ST_NO_TEXTURE: white) at uv with the ray-cone level of
 * detail of a cone of width `width` meeting the surface at cos_nd. */
static float4 tex_lookup(__global const st_texture *textures, __global const uint *texels,
                         st_u32 tex, float2 uv, float tri_lod, float width, float cos_nd,
                         st_u32 filter)
{
    if (tex == ST_NO_TEXTURE)
        return (float4)(1.0f);
    float c[4];
    float lod = st_tex_lod(tri_lod, &textures[tex], width, cos_nd);
    st_tex_sample(&textures[tex], texels, uv.x, uv.y, lod, filter, c);
    return (float4)(c[0], c[1], c[2], c[3]);
}

/* Texture coordinates at barycentrics (b1, b2) of triangle t. */
static float2 tri_uv_at(__global const st_tri_uv *tri_uv, st_u32 t, float b1, float b2)
{
    __global const float *u = tri_uv[t].uv;
    return (1.0f - b1 - b2) * (float2)(u[0], u[1]) + b1 * (float2)(u[2], u[3]) +
           b2 * (float2)(u[4], u[5]);
}

/* Emitted radiance of light triangle lt at the point triangle_point(u1, u2)
 * picks: the factor times the emissive texture's level 0. */
static float3 light_emission(__global const st_material *materials,
                             __global const uint *tri_material, __global const st_tri_uv *tri_uv,
                             __global const st_texture *textures, __global const uint *texels,
                             st_u32 lt, float u1, float u2, st_u32 filter)
{
    __global const st_material *m = &materials[tri_material[lt]];
    float3 le = vload4(0, m->emission).xyz;
    if (m->emission_tex == ST_NO_TEXTURE)
        return le;
    float su = sqrt(u1);
    float2 uv = tri_uv_at(tri_uv, lt, 1.0f - su, u2 * su);
    return le * tex_lookup(textures, texels, m->emission_tex, uv, 0.0f, 0.0f, 1.0f, filter).xyz;
}

/* Orthonormal basis around n (Duff et al., "Building an Orthonormal Basis,
 * Revisited", JCGT 6(1), 2017). */
static void basis(float3 n, float3 *t, float3 *b)
{
    float s = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (s + n.z), c = n.x * n.y * a;
    *t = (float3)(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
    *b = (float3)(c, s + n.y * n.y * a, -n.y);
}

/* Reads hit, ray, beta (w: pdf of the BSDF sample that made this ray),
 * radiance (w: rays traced so far), depth; writes radiance (emission), the shadow ray and its
 * contribution (shadow_o.w = 0: none), the next ray, beta and depth
 * (ST_PATH_DEAD when the path ends). */
__kernel void shade_hits(const st_params p, const st_shading sh,
                         __global const st_triangle *tris,
                         __global const st_tri_normals *normals,
                         __global const uint *tri_material,
                         __global const st_material *materials,
                         __global const uint *light_tri, __global const float *light_cdf,
                         __global const float *light_pdf_area,
                         __global const st_tri_uv *tri_uv, __global const st_texture *textures,
                         __global const uint *texels, __global const uint2 *sample_id,
                         __global const float4 *hit,
                         __global float4 *ray_o, __global float4 *ray_d,
                         __global float4 *beta_buf, __global float4 *radiance,
                         __global uint *depth_buf, __global float4 *shadow_o,
                         __global float4 *shadow_d, __global float4 *shadow_l)
{
    st_u32 i = get_global_id(0);
    if (i >= p.item_count)
        return;
    shadow_o[i] = (float4)(0.0f);
    st_u32 depth = depth_buf[i];
    if (depth == ST_PATH_DEAD)
        return;
    float4 h = hit[i];
    st_u32 t = as_uint(h.w);
    float4 rad = radiance[i];
    rad.w += 1.0f; /* rays traced by this sample */
    float3 env = vload4(0, sh.env).xyz;
    int has_env = env.x > 0.0f || env.y > 0.0f || env.z > 0.0f;
    int path = p.integrator == ST_INTEGRATOR_PATH;
    if (t == ST_NO_HIT) {
        if (has_env) { /* halved where NEE sampled it too (see the top) */
            float w = depth > 0u && path && p.light_count == 0u ? 0.5f : 1.0f;
            rad.xyz += beta_buf[i].xyz * env * w;
        }
        radiance[i] = rad;
        depth_buf[i] = ST_PATH_DEAD;
        return;
    }
    float4 dir = ray_d[i]; /* w: the path's length before this ray */
    float3 wo = -dir.xyz;
    float3 pos = ray_o[i].xyz - wo * h.x;
    float4 beta = beta_buf[i];
    float3 L = rad.xyz;
    float3 ng = facing_normal(normals, t);
    float3 ns = normalize((1.0f - h.y - h.z) * vload4(0, normals[t].n0).xyz +
                          h.y * vload4(0, normals[t].n1).xyz +
                          h.z * vload4(0, normals[t].n2).xyz);
    st_material m = materials[tri_material[t]];
    float4 base = vload4(0, m.base_color);
    float3 le = vload4(0, m.emission).xyz;
    float metallic = m.metallic;
    if (m.base_color_tex != ST_NO_TEXTURE || m.emission_tex != ST_NO_TEXTURE ||
        m.metallic_roughness_tex != ST_NO_TEXTURE) {
        float2 uv = tri_uv_at(tri_uv, t, h.y, h.z);
        float px = 2.0f * p.camera.origin[3] / (float)p.height; /* pixel width at distance 1 */
        float width = p.camera.forward[3] > 0.5f ? px : px * (dir.w + h.x);
        float cos_nd = dot(ng, wo), lod = tri_uv[t].lod;
        base *= tex_lookup(textures, texels, m.base_color_tex, uv, lod, width, cos_nd,
                           sh.texture_filter);
        le *= tex_lookup(textures, texels, m.emission_tex, uv, lod, width, cos_nd,
                         sh.texture_filter).xyz;
        metallic *= tex_lookup(textures, texels, m.metallic_roughness_tex, uv, lod, width,
                               cos_nd, sh.texture_filter).z;
    }
    if (m.alpha_mode != ST_ALPHA_OPAQUE) { /* cut-outs and coverage: go on through */
        uint2 cid = sample_id[i];
        float u = st_rng_unit(st_rng_key(p.seed ^ 0xa1fa0000u, cid.x, cid.y), t ^ (depth << 24));
        if (m.alpha_mode == ST_ALPHA_MASK ? base.w < m.alpha_cutoff : u >= base.w) {
            ray_o[i] = (float4)(pos - wo * p.ray_eps, INFINITY);
            ray_d[i] = (float4)(-wo, dir.w + h.x);
            radiance[i] = rad;
            return;
        }
    }
    float3 albedo = base.xyz * (1.0f - metallic);

    /* emission, one-sided */
    float cos_o = dot(ng, wo);
    if (cos_o > 0.0f && (le.x > 0.0f || le.y > 0.0f || le.z > 0.0f)) {
        float w = 1.0f;
        if (depth > 0u) { /* reached by a BSDF sample: MIS against light sampling */
            float pdf_light = light_pdf_area[t] * h.x * h.x / cos_o;
            w = power_heuristic(beta.w, pdf_light);
        }
        L += beta.xyz * le * w;
    }
    if (cos_o < 0.0f) { /* shade the side the ray arrived on */
        ng = -ng;
    }
    if (dot(ns, ng) < 0.0f)
        ns = -ns;
    radiance[i] = (float4)(L, rad.w);
    if (depth >= p.max_depth) {
        depth_buf[i] = ST_PATH_DEAD;
        return;
    }

    /* the sample's own dimensions */
    uint2 sid = sample_id[i];
    st_sample_id id = st_sample_begin(&p, sid.x % p.width, sid.x / p.width, sid.y);
    st_u32 dim = 2u + ST_DIMS_PER_VERTEX * depth;
    float3 origin = pos + ng * p.ray_eps;

    /* next-event estimation: the environment (a cosine-distributed direction)
     * or one point on one emissive triangle; `choice` is the probability of
     * the strategy taken */
    float choice = 1.0f;
    int take_env = has_env && p.light_count == 0u;
    if (has_env && p.light_count > 0u && !path) {
        take_env = st_sample_dim(&p, &id, dim + 4u) < 0.5f;
        choice = 0.5f;
    }
    if (take_env) {
        float u1 = st_sample_dim(&p, &id, dim), u2 = st_sample_dim(&p, &id, dim + 1u);
        float r = sqrt(u1), phi = 2.0f * ST_PI_F * u2, cz = sqrt(fmax(0.0f, 1.0f - u1));
        float3 tu, tv;
        basis(ns, &tu, &tv);
        float3 wi = normalize(r * native_cos(phi) * tu + r * native_sin(phi) * tv + cz * ns);
        if (cz > 0.0f && dot(wi, ng) > 0.0f) {
            float w = path ? 0.5f : 1.0f; /* MIS against the BSDF sample's miss */
            shadow_o[i] = (float4)(origin, INFINITY);
            shadow_d[i] = (float4)(wi, 0.0f);
            shadow_l[i] = (float4)(beta.xyz * albedo * env * (w / choice), 0.0f);
        }
    } else if (p.light_count > 0u) {
        float u = st_sample_dim(&p, &id, dim), u2 = st_sample_dim(&p, &id, dim + 1u);
        st_u32 lt = light_tri[pick_light(light_cdf, p.light_count, &u)];
        float3 q = triangle_point(tris, lt, u, u2);
        float3 nl = facing_normal(normals, lt);
        float3 wi = q - origin;
        float dist2 = dot(wi, wi), dist = sqrt(dist2);
        wi /= dist;
        float cos_l = -dot(nl, wi), cos_s = dot(ns, wi);
        if (cos_l > 0.0f && cos_s > 0.0f && dot(ng, wi) > 0.0f) {
            float pdf_light = light_pdf_area[lt] * dist2 / cos_l;
            float w = path ? power_heuristic(pdf_light, cos_s / ST_PI_F) : 1.0f;
            float3 lel = light_emission(materials, tri_material, tri_uv, textures, texels, lt, u,
                                        u2, sh.texture_filter);
            float3 c = beta.xyz * albedo * (1.0f / ST_PI_F) * lel * (cos_s * w / pdf_light) /
                       choice;
            shadow_o[i] = (float4)(origin, dist * (1.0f - 1e-3f) - p.ray_eps);
            shadow_d[i] = (float4)(wi, 0.0f);
            shadow_l[i] = (float4)(c, 0.0f);
        }
    }
    if (!path) {
        depth_buf[i] = ST_PATH_DEAD;
        return;
    }

    /* BSDF sample: cosine-weighted hemisphere (Malley's method) */
    float u1 = st_sample_dim(&p, &id, dim + 2u), u2 = st_sample_dim(&p, &id, dim + 3u);
    float r = sqrt(u1), phi = 2.0f * ST_PI_F * u2;
    float3 tu, tv;
    basis(ns, &tu, &tv);
    float cz = sqrt(fmax(0.0f, 1.0f - u1));
    /* native_: the device's fast sine, deterministic on one device; the
     * accurate one's argument reduction cost a tenth of the frame on PoCL */
    float3 wi = normalize(r * native_cos(phi) * tu + r * native_sin(phi) * tv + cz * ns);
    if (!(cz > 0.0f) || dot(wi, ng) <= 0.0f) {
        depth_buf[i] = ST_PATH_DEAD;
        return;
    }
    beta.xyz *= albedo; /* f cos / pdf = (albedo/π) cos / (cos/π) */
    beta.w = cz / ST_PI_F;
    if (depth + 1u >= ST_RR_START_DEPTH) {
        float q = fmax(0.05f, 1.0f - fmax(beta.x, fmax(beta.y, beta.z)));
        if (st_sample_dim(&p, &id, dim + 5u) < q) {
            depth_buf[i] = ST_PATH_DEAD;
            return;
        }
        beta.xyz /= 1.0f - q;
    }
    beta_buf[i] = beta;
    ray_o[i] = (float4)(origin, INFINITY);
    ray_d[i] = (float4)(wi, dir.w + h.x);
    depth_buf[i] = depth + 1u;
}
