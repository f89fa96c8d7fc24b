/* bsdf.h — the surface's scattering: the glTF 2.0 metallic-roughness BRDF
 * (glTF 2.0 specification, appendix B) with KHR_materials_specular and
 * KHR_materials_ior, in the local shading frame (z along the shading
 * normal). The part above `#ifdef __OPENCL_VERSION__` compiles as C11 too,
 * so tests/unit/test_bsdf.c runs the device's own code.
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
 * KHR_materials_diffuse_transmission splits the Lambertian part, as the
 * specification's mix: (1 - t) of it reflects the base colour and t passes
 * into the other hemisphere as a Lambertian transmission of its colour c_t,
 *   f = (1 - m) c_t t / π (1 - max3 F_d)        (wi below; F_d at the half
 *                                                 vector of wo and wi mirrored)
 * (st_brdf_diffuse_transmission).
 * KHR_materials_iridescence mixes, with its factor ι, the Schlick Fresnel
 * of the dielectric part (F0 f0_d) and of the metal (F0 c) each with the
 * thin film's over that F0 (thin_film.h) at wo.h, in the specular lobe and
 * in the diffuse part's loss (st_brdf_fresnel).
 * KHR_materials_anisotropy stretches D and V along the frame's x axis (the
 * anisotropy direction): α_t = mix(α, 1, strength²) there, α across it
 * (st_brdf_anisotropic).
 *
 * Sampling: a mixture of the cosine-weighted diffuse lobe and the specular
 * lobe by its distribution of visible normals (Heitz, "Sampling the GGX
 * Distribution of Visible Normals", JCGT 7(4), 2018); the specular lobe is
 * chosen with probability st_brdf_spec_prob (an estimate of the lobes'
 * reflectance towards v), and the pdf is the mixture's, so f cos / pdf is
 * exact whichever lobe made the direction.
 *
 * Written once over lanes (lanes.h): every value is an st_lf, ST_W
 * materials at once in the kernels (integrator.h), one float on the host,
 * where tests/unit/test_bsdf.c runs this very code; a branch is a mask and a
 * select, so that every lane computes what width 1 computes. */
#ifndef ST_BSDF_H
#define ST_BSDF_H

#ifndef __OPENCL_VERSION__
#include "st_shared.h"
#endif
#include "lanes.h"
#include "thin_film.h"

/* The smallest α: below it D's peak (1 / (π α²)) and the sampling pdf
 * grow past what the MIS weights can square in single precision. */
#define ST_BRDF_MIN_ALPHA 1e-3f

/* A direction in the local shading frame (z along the shading normal). */
typedef st_lv3 st_dir;

/* The BRDF at one point, from the material's factors times their textures. */
typedef struct st_brdf {
    st_lf diffuse[3];    /* (1 - m) c: the Lambertian part's albedo before Fresnel */
    st_lf dtrans[3];     /* (1 - m) t c_t: its diffuse transmission's (0: none) */
    st_lf f0[3], f90[3]; /* the specular lobe's Schlick Fresnel */
    st_lf fd0, fd90;     /* max3 f0_d and f90_d: the diffuse part's loss to F_d */
    st_lf alpha;   /* roughness²: the specular lobe's α across the tangent (and the
                      transmission lobe's, bsdf_dielectric.h) */
    st_lf alpha_t; /* its α along the tangent, the frame's x: alpha unless
                      anisotropic (st_brdf_anisotropic) */
    st_lf wd, wm;        /* the opaque dielectric's and the metal's weights */
    st_lf f0d[3], f0m[3]; /* their own F0s: f0_d and the base colour */
    st_lf irid;          /* the thin film's weight ι (0: none; st_brdf_iridescent) */
    st_lf film_ior, film_nm; /* its ior and thickness (nm) */
} st_brdf;

ST_FN st_lf st_max3(const st_lf *c)
{
    return ST_FMAXF(c[0], ST_FMAXF(c[1], c[2]));
}

ST_FN st_lf st_clamp01(st_lf x)
{
    return ST_FMINF(ST_FMAXF(x, 0.0f), 1.0f);
}

/* The BRDF of a material: base colour c, metallic m, roughness, specular
 * (KHR_materials_specular's specularFactor x texture A) and specular colour
 * (factor x texture RGB), index of refraction (KHR_materials_ior, 1.5),
 * transmission (KHR_materials_transmission, 0): the opaque dielectric
 * parts keep 1 - transmission of their weight, the rest being
 * bsdf_dielectric.h's lobe. */
ST_FN st_brdf st_brdf_make(const st_lf *c, st_lf m, st_lf roughness, st_lf specular,
                           const st_lf *specular_colour, st_lf ior, st_lf transmission)
{
    st_brdf b;
    m = st_clamp01(m);
    st_lf dm = (1.0f - m) * (1.0f - st_clamp01(transmission)); /* the opaque dielectric's */
    specular = st_clamp01(specular);
    st_lf r = st_clamp01(roughness);
    st_lf q = (ior - 1.0f) / (ior + 1.0f);
    b.fd0 = ST_LF(0.0f);
    for (int k = 0; k < 3; k++) {
        st_lf f0d = ST_FMINF(q * q * specular_colour[k], 1.0f) * specular;
        b.fd0 = ST_FMAXF(b.fd0, f0d);
        b.diffuse[k] = dm * c[k];
        b.dtrans[k] = ST_LF(0.0f);
        b.f0d[k] = f0d;
        b.f0m[k] = c[k];
        b.f0[k] = dm * f0d + m * c[k];
        b.f90[k] = dm * specular + m;
    }
    b.fd90 = specular;
    b.alpha = ST_FMAXF(r * r, ST_BRDF_MIN_ALPHA);
    b.alpha_t = b.alpha;
    b.wd = dm;
    b.wm = m;
    b.irid = b.film_ior = b.film_nm = ST_LF(0.0f);
    return b;
}

/* KHR_materials_iridescence: a thin film of weight ι in [0, 1], ior n and
 * thickness d nm over the specular lobe (ι = 0 changes nothing). */
ST_FN void st_brdf_iridescent(st_brdf *b, st_lf iota, st_lf n, st_lf d)
{
    b->irid = st_clamp01(iota);
    b->film_ior = n;
    b->film_nm = ST_FMAXF(d, 0.0f);
}

/* The specular lobe's Fresnel per channel into F[3], at Schlick's weight
 * s of wo.h = cos_vh, and the diffuse part's loss to the dielectric's
 * Fresnel (returned); with the thin film mixed in where a lane has one. */
ST_FN st_lf st_brdf_fresnel(const st_brdf *b, st_lf s, st_lf cos_vh, st_lf *F)
{
    for (int k = 0; k < 3; k++)
        F[k] = b->f0[k] + (b->f90[k] - b->f0[k]) * s;
    st_lf loss = b->fd0 + (b->fd90 - b->fd0) * s;
    st_li on = b->irid > 0.0f;
    if (ST_ANY(ST_W, on)) {
        st_lf id[3], im[3], ld = ST_LF(0.0f);
        st_lf c = st_clamp01(cos_vh);
        st_thin_film(b->film_ior, b->film_nm, c, b->f0d, id);
        st_thin_film(b->film_ior, b->film_nm, c, b->f0m, im);
        for (int k = 0; k < 3; k++) {
            st_lf fd = b->f0d[k] + (b->fd90 - b->f0d[k]) * s;
            st_lf fm = b->f0m[k] + (1.0f - b->f0m[k]) * s;
            st_lf fi = F[k] + b->irid * (b->wd * (id[k] - fd) + b->wm * (im[k] - fm));
            F[k] = ST_SELECT(ST_W, F[k], fi, on);
            ld = ST_FMAXF(ld, fd + b->irid * (id[k] - fd));
        }
        loss = ST_SELECT(ST_W, loss, ld, on);
    }
    return loss;
}

/* KHR_materials_diffuse_transmission's share t in [0, 1] of the Lambertian
 * part (of a material with metallic m and transmission tr, as made by
 * st_brdf_make) passed into the other hemisphere, tinted by colour: the
 * reflection keeps (1 - t) of it. t = 0 changes nothing. */
ST_FN void st_brdf_diffuse_transmission(st_brdf *b, st_lf m, st_lf transmission, st_lf t,
                                        const st_lf *colour)
{
    st_lf dm = (1.0f - st_clamp01(m)) * (1.0f - st_clamp01(transmission));
    t = st_clamp01(t);
    for (int k = 0; k < 3; k++) {
        b->dtrans[k] = dm * t * colour[k];
        b->diffuse[k] = b->diffuse[k] * (1.0f - t);
    }
}

/* The lanes whose Lambertian part transmits. */
ST_FN st_li st_brdf_transmits(const st_brdf *b)
{
    return st_max3(b->dtrans) > 0.0f;
}

/* KHR_materials_anisotropy's stretch of the specular lobe along the
 * tangent (the frame's x axis) by strength s in [0, 1]: α_t = mix(α, 1, s²),
 * α_b = α (the extension's definition). s = 0 leaves α_t = α exactly,
 * so that the lobe stays isotropic, bit for bit. */
ST_FN void st_brdf_anisotropic(st_brdf *b, st_lf s)
{
    s = st_clamp01(s);
    b->alpha_t = b->alpha + (1.0f - b->alpha) * (s * s);
}

/* GGX D(h) for a unit h: α² / (π ((h.x² + h.y²) + α² h.z²)²), the form of
 * α² / (π ((n.h)² (α² - 1) + 1)²) that keeps its precision near the peak. */
ST_FN st_lf st_ggx_d(st_lf alpha, st_dir h)
{
    st_lf a2 = alpha * alpha, t = h.x * h.x + h.y * h.y + a2 * h.z * h.z;
    return ST_SELECT(ST_W, ST_LF(0.0f), a2 / (ST_PI_F * t * t), h.z > 0.0f);
}

/* Smith's Λ(w) for GGX times 2 plus 1: sqrt(1 + α² tan² θ), written with
 * the components so that it holds at grazing angles. Returns z sqrt(...)
 * (= sqrt(z² + α² (x² + y²))), the term of the height-correlated form. */
ST_FN st_lf st_ggx_lambda_term(st_lf alpha, st_dir w)
{
    return ST_SQRTF(w.z * w.z + alpha * alpha * (w.x * w.x + w.y * w.y));
}

/* The height-correlated visibility G2 / (4 |n.l| |n.v|)
 *   = 1 / (2 (|n.l| a(v) + |n.v| a(l))), a(w) = sqrt(z² + α² (x² + y²)) / |w.z|. */
ST_FN st_lf st_ggx_v(st_lf alpha, st_dir wo, st_dir wi)
{
    st_lf lo = st_ggx_lambda_term(alpha, wo), li = st_ggx_lambda_term(alpha, wi);
    return 0.5f / (wi.z * lo + wo.z * li);
}

/* Smith's masking G1(w) = 2 z / (z + sqrt(z² + α² (x² + y²))). */
ST_FN st_lf st_ggx_g1(st_lf alpha, st_dir w)
{
    return 2.0f * w.z / (w.z + st_ggx_lambda_term(alpha, w));
}

/* The anisotropic forms, α_x along x and α_y along y (Heitz 2014, eqs. 85
 * and 86; the KHR_materials_anisotropy definition with α_x = α_t):
 *   D(h) = 1 / (π α_x α_y ((h.x / α_x)² + (h.y / α_y)² + h.z²)²),
 *   the term sqrt(z² + (α_x x)² + (α_y y)²) of Λ as st_ggx_lambda_term's. */
ST_FN st_lf st_ggx_d_aniso(st_lf ax, st_lf ay, st_dir h)
{
    st_lf x = h.x / ax, y = h.y / ay, t = x * x + y * y + h.z * h.z;
    return ST_SELECT(ST_W, ST_LF(0.0f), 1.0f / (ST_PI_F * ax * ay * t * t), h.z > 0.0f);
}

ST_FN st_lf st_ggx_lambda_term_aniso(st_lf ax, st_lf ay, st_dir w)
{
    st_lf x = ax * w.x, y = ay * w.y;
    return ST_SQRTF(w.z * w.z + (x * x + y * y));
}

/* The specular lobe's D and Λ term: the isotropic forms, and the
 * anisotropic ones in the lanes whose α_t differs from α (computed only
 * where some lane needs them), so that an isotropic material computes
 * exactly what it computed before anisotropy was added. */
ST_FN st_lf st_brdf_d(const st_brdf *b, st_dir h)
{
    st_lf d = st_ggx_d(b->alpha, h);
    st_li aniso = b->alpha_t != b->alpha;
    if (ST_ANY(ST_W, aniso))
        d = ST_SELECT(ST_W, d, st_ggx_d_aniso(b->alpha_t, b->alpha, h), aniso);
    return d;
}

ST_FN st_lf st_brdf_lambda_term(const st_brdf *b, st_dir w)
{
    st_lf l = st_ggx_lambda_term(b->alpha, w);
    st_li aniso = b->alpha_t != b->alpha;
    if (ST_ANY(ST_W, aniso))
        l = ST_SELECT(ST_W, l, st_ggx_lambda_term_aniso(b->alpha_t, b->alpha, w), aniso);
    return l;
}

/* st_ggx_v and st_ggx_g1 of the specular lobe (with st_brdf_lambda_term). */
ST_FN st_lf st_brdf_v(const st_brdf *b, st_dir wo, st_dir wi)
{
    st_lf lo = st_brdf_lambda_term(b, wo), li = st_brdf_lambda_term(b, wi);
    return 0.5f / (wi.z * lo + wo.z * li);
}

ST_FN st_lf st_brdf_g1(const st_brdf *b, st_dir w)
{
    return 2.0f * w.z / (w.z + st_brdf_lambda_term(b, w));
}

ST_FN st_dir st_dir_normalize(st_dir d)
{
    st_lf n = ST_SQRTF(d.x * d.x + d.y * d.y + d.z * d.z);
    return st_lv3_make(d.x / n, d.y / n, d.z / n);
}

ST_FN st_dir st_half_vector(st_dir wo, st_dir wi)
{
    return st_dir_normalize(st_lv3_add(wo, wi));
}

/* Schlick's weight (1 - x)^5. */
ST_FN st_lf st_schlick(st_lf x)
{
    st_lf a = 1.0f - st_clamp01(x), a2 = a * a;
    return a2 * a2 * a;
}

/* f(wo, wi) per channel into f[3]; 0 unless both lie above the surface,
 * or wi below it where the Lambertian part transmits. */
ST_FN void st_brdf_eval(const st_brdf *b, st_dir wo, st_dir wi, st_lf *f)
{
    st_li above = wo.z > 0.0f && wi.z > 0.0f;
    st_dir h = st_half_vector(wo, wi);
    st_lf vh = wo.x * h.x + wo.y * h.y + wo.z * h.z, s = st_schlick(vh), fr[3];
    st_lf dv = st_brdf_d(b, h) * st_brdf_v(b, wo, wi);
    st_lf kd = (1.0f - st_brdf_fresnel(b, s, vh, fr)) / ST_PI_F;
    for (int k = 0; k < 3; k++) {
        st_lf fk = b->diffuse[k] * kd + fr[k] * dv;
        f[k] = ST_SELECT(ST_W, ST_LF(0.0f), fk, above);
    }
    st_li through = wo.z > 0.0f && wi.z < 0.0f && st_brdf_transmits(b);
    if (ST_ANY(ST_W, through)) {
        h = st_half_vector(wo, st_lv3_make(wi.x, wi.y, -wi.z));
        s = st_schlick(wo.x * h.x + wo.y * h.y + wo.z * h.z);
        kd = (1.0f - (b->fd0 + (b->fd90 - b->fd0) * s)) / ST_PI_F;
        for (int k = 0; k < 3; k++)
            f[k] = ST_SELECT(ST_W, f[k], b->dtrans[k] * kd, through);
    }
}

/* The probability of sampling the specular lobe towards wo: its Fresnel
 * reflectance against the diffuse part's, at n.v (kept inside [0.05, 0.95]
 * in s, so that a lobe that is nonzero anywhere gets a share). */
ST_FN st_lf st_brdf_spec_prob(const st_brdf *b, st_dir wo)
{
    st_lf s = ST_FMINF(ST_FMAXF(st_schlick(wo.z), 0.05f), 0.95f), ws = ST_LF(0.0f);
    for (int k = 0; k < 3; k++)
        ws = ST_FMAXF(ws, b->f0[k] + (b->f90[k] - b->f0[k]) * s);
    st_lf wd = (st_max3(b->diffuse) + st_max3(b->dtrans)) *
               (1.0f - (b->fd0 + (b->fd90 - b->fd0) * s));
    return ST_SELECT(ST_W, ST_LF(0.0f), ws / (ws + wd), ws + wd > 0.0f);
}

/* The probability that the Lambertian part's sample transmits: its
 * transmission's share of it (0 where it does not transmit). */
ST_FN st_lf st_brdf_trans_prob(const st_brdf *b)
{
    st_lf t = st_max3(b->dtrans), r = st_max3(b->diffuse);
    return ST_SELECT(ST_W, ST_LF(0.0f), t / (t + r), t > 0.0f);
}

/* The pdf (solid angle) of st_brdf_sample choosing wi: the mixture of
 * cos / π and the visible-normal density G1(wo) D(h) / (4 wo.z), the
 * cosine lobe split by st_brdf_trans_prob into the two hemispheres. */
ST_FN st_lf st_brdf_pdf(const st_brdf *b, st_dir wo, st_dir wi)
{
    st_li above = wo.z > 0.0f && wi.z > 0.0f;
    st_lf ps = st_brdf_spec_prob(b, wo), pt = st_brdf_trans_prob(b);
    st_dir h = st_half_vector(wo, wi);
    st_lf spec = st_brdf_g1(b, wo) * st_brdf_d(b, h) / (4.0f * wo.z);
    spec = ST_SELECT(ST_W, ST_LF(0.0f), spec, ps > 0.0f);
    st_lf p = ps * spec + (1.0f - ps) * (1.0f - pt) * wi.z / ST_PI_F;
    st_li through = wo.z > 0.0f && wi.z < 0.0f && pt > 0.0f;
    p = ST_SELECT(ST_W, p, (1.0f - ps) * pt * -wi.z / ST_PI_F, through);
    return ST_SELECT(ST_W, ST_LF(0.0f), p, above || through);
}

/* A visible normal of GGX (α_x along x, α_y along y; equal: isotropic)
 * towards wo (wo.z > 0) from (u1, u2) (Heitz 2018, listing 1): stretch wo
 * to the hemisphere configuration, take a point on the projected disk whose
 * lower half is squashed by the hemisphere's foreshortening, lift it onto
 * the hemisphere and unstretch. */
ST_FN st_dir st_ggx_visible_normal(st_lf ax, st_lf ay, st_dir wo, st_lf u1, st_lf u2)
{
    st_dir vh = st_dir_normalize(st_lv3_make(ax * wo.x, ay * wo.y, wo.z));
    st_lf len2 = vh.x * vh.x + vh.y * vh.y, inv = 1.0f / ST_SQRTF(len2);
    st_li tilted = len2 > 0.0f;
    st_dir t1 = st_lv3_make(ST_SELECT(ST_W, ST_LF(1.0f), -vh.y * inv, tilted),
                            ST_SELECT(ST_W, ST_LF(0.0f), vh.x * inv, tilted), ST_LF(0.0f));
    st_dir t2 = st_lv3_make(vh.y * t1.z - vh.z * t1.y, vh.z * t1.x - vh.x * t1.z,
                            vh.x * t1.y - vh.y * t1.x);
    st_lf r = ST_SQRTF(u1), phi = 2.0f * ST_PI_F * u2;
    st_lf p1 = r * ST_COSF(phi), p2 = r * ST_SINF(phi), s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * ST_SQRTF(ST_FMAXF(0.0f, 1.0f - p1 * p1)) + s * p2;
    st_lf p3 = ST_SQRTF(ST_FMAXF(0.0f, 1.0f - p1 * p1 - p2 * p2));
    st_dir nh = st_lv3_make(p1 * t1.x + p2 * t2.x + p3 * vh.x, p1 * t1.y + p2 * t2.y + p3 * vh.y,
                            p1 * t1.z + p2 * t2.z + p3 * vh.z);
    return st_dir_normalize(st_lv3_make(ax * nh.x, ay * nh.y, ST_FMAXF(0.0f, nh.z)));
}

/* A cosine-distributed direction about z from (u1, u2): the Lambertian
 * lobe's sample, with pdf z / π. */
ST_FN st_dir st_cosine_sample(st_lf u1, st_lf u2)
{
    st_lf r = ST_SQRTF(u1), phi = 2.0f * ST_PI_F * u2;
    return st_lv3_make(r * ST_COSF(phi), r * ST_SINF(phi), ST_SQRTF(ST_FMAXF(0.0f, 1.0f - u1)));
}

/* A direction from the mixture: u1 below st_brdf_spec_prob picks the
 * specular lobe (u1 rescaled to [0, 1) for it, so one dimension both
 * chooses and places), else the cosine lobe, whose rescaled u1 below
 * st_brdf_trans_prob turns it into the lower hemisphere (rescaled again).
 * A specular sample may point below the surface (z <= 0): then it is lost
 * (as (0, 0, 0) where the Lambertian part transmits).
 * Each lobe is computed only where some lane takes it. */
ST_FN st_dir st_brdf_sample(const st_brdf *b, st_dir wo, st_lf u1, st_lf u2)
{
    st_lf ps = st_brdf_spec_prob(b, wo);
    st_li spec = u1 < ps;
    st_dir wi = wo;
    if (ST_ANY(ST_W, !spec)) {
        st_lf v = ST_FMINF((u1 - ps) / (1.0f - ps), 0.99999994f), pt = st_brdf_trans_prob(b);
        st_li through = v < pt;
        v = ST_SELECT(ST_W, (v - pt) / (1.0f - pt), v / pt, through);
        wi = st_cosine_sample(ST_FMINF(v, 0.99999994f), u2);
        wi.z = ST_SELECT(ST_W, wi.z, -wi.z, through);
    }
    if (ST_ANY(ST_W, spec)) {
        st_dir h = st_ggx_visible_normal(b->alpha_t, b->alpha, wo, ST_FMINF(u1 / ps, 0.99999994f),
                                         u2);
        st_lf d = 2.0f * (wo.x * h.x + wo.y * h.y + wo.z * h.z);
        st_dir r = st_lv3_make(d * h.x - wo.x, d * h.y - wo.y, d * h.z - wo.z);
        /* below the surface a transmitting lane would take it for the
         * Lambertian part's: lost there as (0, 0, 0) */
        st_li lost = r.z <= 0.0f && st_brdf_transmits(b);
        r = st_lv3_select(r, st_lv3_make(ST_LF(0.0f), ST_LF(0.0f), ST_LF(0.0f)), lost);
        wi = st_lv3_select(wi, r, spec);
    }
    return wi;
}

/* The power heuristic's weight of a sample with density a against one with
 * density b (β = 2; Veach & Guibas 1995). */
ST_FN st_lf st_power_heuristic(st_lf a, st_lf b)
{
    return a * a / (a * a + b * b);
}

/* Orthonormal basis around n in lanes (Duff et al., "Building an
 * Orthonormal Basis, Revisited", JCGT 6(1), 2017). */
ST_FN void st_basis(st_lv3 n, st_lv3 *t, st_lv3 *b)
{
    st_lf s = ST_SELECT(ST_W, ST_LF(-1.0f), ST_LF(1.0f), n.z >= 0.0f);
    st_lf a = -1.0f / (s + n.z), c = n.x * n.y * a;
    *t = st_lv3_make(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
    *b = st_lv3_make(c, s + n.y * n.y * a, -n.y);
}

#endif
