/* bsdf.h — the surface's scattering: the glTF 2.0 metallic-roughness BRDF
 * (glTF 2.0 specification, appendix B) with KHR_materials_specular and
 * KHR_materials_ior, in the local shading frame (z along the shading
 * normal). The part above `#ifdef __OPENCL_VERSION__` compiles as C11 too,
 * so tests/test_bsdf.c runs the device's own code.
 *
 *   f = (1 - m) c / π (1 - max3 F_d)  +  F D V
 * with m the metallic factor, c the base colour and, with s = (1 - |v.h|)^5,
 *   dielectric Fresnel F_d = f0_d + (f90_d - f0_d) s,
 *     f0_d = min(((ior - 1) / (ior + 1))^2 x specularColour, 1) x specular,
 *     f90_d = specular (KHR_materials_specular; 0.04 and 1 without it);
 *   the specular lobe's Fresnel F = (1 - m) F_d + m (c + (1 - c) s), which
 *     is again Schlick's form with F0 = (1 - m) f0_d + m c and
 *     F90 = (1 - m) f90_d + m;
 *   D the Trowbridge-Reitz (GGX) distribution with α = roughness²,
 *   V the height-correlated Smith visibility G2 / (4 |n.l| |n.v|)
 *     (Heitz, "Understanding the Masking-Shadowing Function", JCGT 3(2), 2014).
 * specularFactor 0 leaves the Lambertian (1 - m) c / π alone.
 *
 * Sampling: a mixture of the cosine-weighted diffuse lobe and the specular
 * lobe by its distribution of visible normals (Heitz, "Sampling the GGX
 * Distribution of Visible Normals", JCGT 7(4), 2018); the specular lobe is
 * chosen with probability st_brdf_spec_prob (an estimate of the lobes'
 * reflectance towards v), and the pdf is the mixture's, so f cos / pdf is
 * exact whichever lobe made the direction. */
#ifndef ST_BSDF_H
#define ST_BSDF_H

#ifndef __OPENCL_VERSION__
#include "st_shared.h"
#define ST_SQRTF(x) sqrtf(x)
#define ST_COSF(x) cosf(x)
#define ST_SINF(x) sinf(x)
#define ST_FMAXF(a, b) fmaxf(a, b)
#define ST_FMINF(a, b) fminf(a, b)
#else
#define ST_SQRTF(x) sqrt(x)
/* native_: the device's fast sine, deterministic on one device; the
 * accurate one's argument reduction cost a tenth of the frame on PoCL */
#define ST_COSF(x) native_cos(x)
#define ST_SINF(x) native_sin(x)
#define ST_FMAXF(a, b) fmax(a, b)
#define ST_FMINF(a, b) fmin(a, b)
#endif

/* The smallest α: below it D's peak (1 / (π α²)) and the sampling pdf
 * grow past what the MIS weights can square in single precision. */
#define ST_BRDF_MIN_ALPHA 1e-3f

/* A direction in the local shading frame. */
typedef struct st_dir {
    float x, y, z;
} st_dir;

/* The BRDF at one point, from the material's factors times their textures. */
typedef struct st_brdf {
    float diffuse[3];  /* (1 - m) c: the Lambertian part's albedo before Fresnel */
    float f0[3], f90[3]; /* the specular lobe's Schlick Fresnel */
    float fd0, fd90;   /* max3 f0_d and f90_d: the diffuse part's loss to F_d */
    float alpha;
} st_brdf;

ST_FN float st_max3(const float *c)
{
    return ST_FMAXF(c[0], ST_FMAXF(c[1], c[2]));
}

/* The BRDF of a material: base colour c, metallic m, roughness, specular
 * (KHR_materials_specular's specularFactor x texture A) and specular colour
 * (factor x texture RGB), index of refraction (KHR_materials_ior, 1.5). */
ST_FN st_brdf st_brdf_make(const float *c, float m, float roughness, float specular,
                           const float *specular_colour, float ior)
{
    st_brdf b;
    m = ST_FMINF(ST_FMAXF(m, 0.0f), 1.0f);
    specular = ST_FMINF(ST_FMAXF(specular, 0.0f), 1.0f);
    float r = ST_FMINF(ST_FMAXF(roughness, 0.0f), 1.0f);
    float q = (ior - 1.0f) / (ior + 1.0f);
    b.fd0 = 0.0f;
    for (int k = 0; k < 3; k++) {
        float f0d = ST_FMINF(q * q * specular_colour[k], 1.0f) * specular;
        b.fd0 = ST_FMAXF(b.fd0, f0d);
        b.diffuse[k] = (1.0f - m) * c[k];
        b.f0[k] = (1.0f - m) * f0d + m * c[k];
        b.f90[k] = (1.0f - m) * specular + m;
    }
    b.fd90 = specular;
    b.alpha = ST_FMAXF(r * r, ST_BRDF_MIN_ALPHA);
    return b;
}

/* Whether the BRDF is Lambertian only (no specular lobe at all). */
ST_FN int st_brdf_is_lambert(const st_brdf *b)
{
    return st_max3(b->f0) <= 0.0f && st_max3(b->f90) <= 0.0f;
}

/* GGX D(h) for a unit h: α² / (π ((h.x² + h.y²) + α² h.z²)²), the form of
 * α² / (π ((n.h)² (α² - 1) + 1)²) that keeps its precision near the peak. */
ST_FN float st_ggx_d(float alpha, st_dir h)
{
    float a2 = alpha * alpha, t = h.x * h.x + h.y * h.y + a2 * h.z * h.z;
    return h.z > 0.0f ? a2 / (ST_PI_F * t * t) : 0.0f;
}

/* Smith's Λ(w) for GGX times 2 plus 1: sqrt(1 + α² tan² θ), written with
 * the components so that it holds at grazing angles. Returns z sqrt(...)
 * (= sqrt(z² + α² (x² + y²))), the term of the height-correlated form. */
ST_FN float st_ggx_lambda_term(float alpha, st_dir w)
{
    return ST_SQRTF(w.z * w.z + alpha * alpha * (w.x * w.x + w.y * w.y));
}

/* The height-correlated visibility G2 / (4 |n.l| |n.v|)
 *   = 1 / (2 (|n.l| a(v) + |n.v| a(l))), a(w) = sqrt(z² + α² (x² + y²)) / |w.z|. */
ST_FN float st_ggx_v(float alpha, st_dir wo, st_dir wi)
{
    float lo = st_ggx_lambda_term(alpha, wo), li = st_ggx_lambda_term(alpha, wi);
    return 0.5f / (wi.z * lo + wo.z * li);
}

/* Smith's masking G1(w) = 2 z / (z + sqrt(z² + α² (x² + y²))). */
ST_FN float st_ggx_g1(float alpha, st_dir w)
{
    return 2.0f * w.z / (w.z + st_ggx_lambda_term(alpha, w));
}

ST_FN st_dir st_dir_normalize(st_dir d)
{
    float n = ST_SQRTF(d.x * d.x + d.y * d.y + d.z * d.z);
    st_dir o = {d.x / n, d.y / n, d.z / n};
    return o;
}

ST_FN st_dir st_half_vector(st_dir wo, st_dir wi)
{
    st_dir h = {wo.x + wi.x, wo.y + wi.y, wo.z + wi.z};
    return st_dir_normalize(h);
}

/* Schlick's weight (1 - x)^5. */
ST_FN float st_schlick(float x)
{
    float a = 1.0f - ST_FMINF(ST_FMAXF(x, 0.0f), 1.0f), a2 = a * a;
    return a2 * a2 * a;
}

/* f(wo, wi) per channel into f[3]; 0 unless both lie above the surface. */
ST_FN void st_brdf_eval(const st_brdf *b, st_dir wo, st_dir wi, float *f)
{
    f[0] = f[1] = f[2] = 0.0f;
    if (!(wo.z > 0.0f && wi.z > 0.0f))
        return;
    st_dir h = st_half_vector(wo, wi);
    float s = st_schlick(wo.x * h.x + wo.y * h.y + wo.z * h.z);
    float dv = st_ggx_d(b->alpha, h) * st_ggx_v(b->alpha, wo, wi);
    float kd = (1.0f - (b->fd0 + (b->fd90 - b->fd0) * s)) / ST_PI_F;
    for (int k = 0; k < 3; k++)
        f[k] = b->diffuse[k] * kd + (b->f0[k] + (b->f90[k] - b->f0[k]) * s) * dv;
}

/* The probability of sampling the specular lobe towards wo: its Fresnel
 * reflectance against the diffuse part's, at n.v (kept inside [0.05, 0.95]
 * in s, so that a lobe that is nonzero anywhere gets a share). */
ST_FN float st_brdf_spec_prob(const st_brdf *b, st_dir wo)
{
    float s = ST_FMINF(ST_FMAXF(st_schlick(wo.z), 0.05f), 0.95f), ws = 0.0f;
    for (int k = 0; k < 3; k++)
        ws = ST_FMAXF(ws, b->f0[k] + (b->f90[k] - b->f0[k]) * s);
    float wd = st_max3(b->diffuse) * (1.0f - (b->fd0 + (b->fd90 - b->fd0) * s));
    return ws + wd > 0.0f ? ws / (ws + wd) : 0.0f;
}

/* The pdf (solid angle) of st_brdf_sample choosing wi: the mixture of
 * cos / π and the visible-normal density G1(wo) D(h) / (4 wo.z). */
ST_FN float st_brdf_pdf(const st_brdf *b, st_dir wo, st_dir wi)
{
    if (!(wo.z > 0.0f && wi.z > 0.0f))
        return 0.0f;
    float ps = st_brdf_spec_prob(b, wo), spec = 0.0f;
    if (ps > 0.0f) {
        st_dir h = st_half_vector(wo, wi);
        spec = st_ggx_g1(b->alpha, wo) * st_ggx_d(b->alpha, h) / (4.0f * wo.z);
    }
    return ps * spec + (1.0f - ps) * wi.z / ST_PI_F;
}

/* A visible normal of GGX towards wo (wo.z > 0) from (u1, u2) (Heitz 2018,
 * listing 1, isotropic α): stretch wo to the hemisphere configuration, take
 * a point on the projected disk whose lower half is squashed by the
 * hemisphere's foreshortening, lift it onto the hemisphere and unstretch. */
ST_FN st_dir st_ggx_visible_normal(float alpha, st_dir wo, float u1, float u2)
{
    st_dir vh = st_dir_normalize((st_dir){alpha * wo.x, alpha * wo.y, wo.z});
    float len2 = vh.x * vh.x + vh.y * vh.y;
    st_dir t1 = {1.0f, 0.0f, 0.0f};
    if (len2 > 0.0f) {
        float inv = 1.0f / ST_SQRTF(len2);
        t1 = (st_dir){-vh.y * inv, vh.x * inv, 0.0f};
    }
    st_dir t2 = {vh.y * t1.z - vh.z * t1.y, vh.z * t1.x - vh.x * t1.z, vh.x * t1.y - vh.y * t1.x};
    float r = ST_SQRTF(u1), phi = 2.0f * ST_PI_F * u2;
    float p1 = r * ST_COSF(phi), p2 = r * ST_SINF(phi), s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * ST_SQRTF(ST_FMAXF(0.0f, 1.0f - p1 * p1)) + s * p2;
    float p3 = ST_SQRTF(ST_FMAXF(0.0f, 1.0f - p1 * p1 - p2 * p2));
    st_dir nh = {p1 * t1.x + p2 * t2.x + p3 * vh.x, p1 * t1.y + p2 * t2.y + p3 * vh.y,
                 p1 * t1.z + p2 * t2.z + p3 * vh.z};
    return st_dir_normalize((st_dir){alpha * nh.x, alpha * nh.y, ST_FMAXF(0.0f, nh.z)});
}

/* A direction from the mixture: u1 below st_brdf_spec_prob picks the
 * specular lobe (u1 rescaled to [0, 1) for it, so one dimension both
 * chooses and places), else the cosine lobe. The result may point below
 * the surface (z <= 0): then the sample is lost. */
ST_FN st_dir st_brdf_sample(const st_brdf *b, st_dir wo, float u1, float u2)
{
    float ps = st_brdf_spec_prob(b, wo);
    if (u1 < ps) {
        st_dir h = st_ggx_visible_normal(b->alpha, wo, ST_FMINF(u1 / ps, 0.99999994f), u2);
        float d = 2.0f * (wo.x * h.x + wo.y * h.y + wo.z * h.z);
        st_dir wi = {d * h.x - wo.x, d * h.y - wo.y, d * h.z - wo.z};
        return wi;
    }
    u1 = ST_FMINF((u1 - ps) / (1.0f - ps), 0.99999994f);
    float r = ST_SQRTF(u1), phi = 2.0f * ST_PI_F * u2;
    st_dir wi = {r * ST_COSF(phi), r * ST_SINF(phi), ST_SQRTF(ST_FMAXF(0.0f, 1.0f - u1))};
    return wi;
}

#ifdef __OPENCL_VERSION__
/* Orthonormal basis around n (Duff et al., "Building an Orthonormal Basis,
 * Revisited", JCGT 6(1), 2017). */
static void basis(float3 n, float3 *t, float3 *b)
{
    float s = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (s + n.z), c = n.x * n.y * a;
    *t = (float3)(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
    *b = (float3)(c, s + n.y * n.y * a, -n.y);
}

/* A cosine-distributed direction around ns from (u1, u2); *cos_theta gets
 * its cosine to ns (pdf = cos_theta / π): the Lambertian lobe alone. */
static float3 cosine_direction(float3 ns, float u1, float u2, float *cos_theta)
{
    float r = sqrt(u1), phi = 2.0f * ST_PI_F * u2;
    float3 tu, tv;
    basis(ns, &tu, &tv);
    float cz = sqrt(fmax(0.0f, 1.0f - u1));
    *cos_theta = cz;
    return normalize(r * native_cos(phi) * tu + r * native_sin(phi) * tv + cz * ns);
}

static float power_heuristic(float a, float b)
{
    return a * a / (a * a + b * b);
}
#endif

#endif
