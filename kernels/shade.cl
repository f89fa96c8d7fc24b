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
 * Materials are Lambertian: f = albedo / π, emitters one-sided on the side
 * their shading normals face.
 * Sample dimensions of vertex k: 2 + 6k + {0: light choice and first
 * coordinate on it, 1: second coordinate, 2,3: BSDF direction, 4: unused,
 * 5: Russian roulette}. */
#include "st_shared.h"
#include "rng.h"
#include "samplers.h"
#include "trace.h"

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
__kernel void shade_hits(const st_params p, __global const st_triangle *tris,
                         __global const st_tri_normals *normals,
                         __global const uint *tri_material,
                         __global const st_material *materials,
                         __global const uint *light_tri, __global const float *light_cdf,
                         __global const float *light_pdf_area, __global const uint2 *sample_id,
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
    if (t == ST_NO_HIT) {
        radiance[i] = rad;
        depth_buf[i] = ST_PATH_DEAD;
        return;
    }
    float3 wo = -ray_d[i].xyz;
    float3 pos = ray_o[i].xyz - wo * h.x;
    float4 beta = beta_buf[i];
    float3 L = rad.xyz;
    float3 ng = facing_normal(normals, t);
    float3 ns = normalize((1.0f - h.y - h.z) * vload4(0, normals[t].n0).xyz +
                          h.y * vload4(0, normals[t].n1).xyz +
                          h.z * vload4(0, normals[t].n2).xyz);
    st_material m = materials[tri_material[t]];
    float3 albedo = vload4(0, m.base_color).xyz, le = vload4(0, m.emission).xyz;

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
    int path = p.integrator == ST_INTEGRATOR_PATH;

    /* next-event estimation: one point on one emissive triangle */
    if (p.light_count > 0u) {
        float u = st_sample_dim(&p, &id, dim);
        st_u32 lt = light_tri[pick_light(light_cdf, p.light_count, &u)];
        float3 q = triangle_point(tris, lt, u, st_sample_dim(&p, &id, dim + 1u));
        float3 nl = facing_normal(normals, lt);
        float3 wi = q - origin;
        float dist2 = dot(wi, wi), dist = sqrt(dist2);
        wi /= dist;
        float cos_l = -dot(nl, wi), cos_s = dot(ns, wi);
        if (cos_l > 0.0f && cos_s > 0.0f && dot(ng, wi) > 0.0f) {
            float pdf_light = light_pdf_area[lt] * dist2 / cos_l;
            float w = path ? power_heuristic(pdf_light, cos_s / ST_PI_F) : 1.0f;
            float3 lel = vload4(0, materials[tri_material[lt]].emission).xyz;
            float3 c = beta.xyz * albedo * (1.0f / ST_PI_F) * lel * (cos_s * w / pdf_light);
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
    ray_d[i] = (float4)(wi, 0.0f);
    depth_buf[i] = depth + 1u;
}
