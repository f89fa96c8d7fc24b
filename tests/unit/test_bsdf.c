/* test_bsdf.c — the glTF metallic-roughness BRDF of kernels/integrator/bsdf.h, run
 * here on the host (the device's own code).
 *
 * Expected values come from definitions, not from the code under test:
 * GGX's D integrates to 1 against n.h over the hemisphere of normals, and
 * the visible normals' density G1(v) max(0, v.h) D(h) / v.z to 1 (Heitz
 * 2014, eq. 17); a BRDF is reciprocal; a Lambertian surface (specularFactor
 * 0) reflects its base colour; a smooth white metal reflects everything.
 * The sampler is checked against its pdf by a chi-square test over equal
 * solid-angle bins (z, φ), and Monte Carlo albedos (f cos / pdf) against
 * midpoint quadrature of f cos over the hemisphere. The same checks run on
 * anisotropic lobes (KHR_materials_anisotropy: α_t = mix(α, 1, s²) along
 * x), whose D is also checked against its textbook form. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>

#include "bsdf.h"
#include "bsdf_dielectric.h"
#include "bsdf_sheen.h"
#include "bsdf_coat.h"

#define PI 3.14159265358979323846

/* splitmix64: the test's own uniform numbers in [0, 1). */
static double next_unit(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

static st_dir dir_from(double z, double phi)
{
    double r = sqrt(fmax(0.0, 1.0 - z * z));
    st_dir d = {(float)(r * cos(phi)), (float)(r * sin(phi)), (float)z};
    return d;
}

static st_brdf material(float c, float metallic, float roughness, float specular)
{
    const float base[3] = {c, c, c}, white[3] = {1.0f, 1.0f, 1.0f};
    return st_brdf_make(base, metallic, roughness, specular, white, 1.5f, 0.0f);
}

/* ... with KHR_materials_anisotropy's strength s (the tangent along x). */
static st_brdf aniso_material(float c, float metallic, float roughness, float specular, float s)
{
    st_brdf b = material(c, metallic, roughness, specular);
    st_brdf_anisotropic(&b, s);
    return b;
}

/* ∫ g(w) dω over the upper hemisphere by the midpoint rule in (z, φ)
 * (dω = dz dφ); `which` selects the integrand. */
enum integrand { D_COS, VNDF, F_COS, PDF };
static double hemisphere(const st_brdf *b, st_dir wo, enum integrand which, int nz, int nphi)
{
    double sum = 0.0;
    for (int i = 0; i < nz; i++)
        for (int j = 0; j < nphi; j++) {
            st_dir w = dir_from((i + 0.5) / nz, 2.0 * PI * (j + 0.5) / nphi);
            float f[3];
            double g = 0.0;
            if (which == D_COS)
                g = st_brdf_d(b, w) * w.z;
            else if (which == VNDF) {
                double vh = wo.x * w.x + wo.y * w.y + wo.z * w.z;
                g = st_brdf_g1(b, wo) * fmax(0.0, vh) * st_brdf_d(b, w) / wo.z;
            } else if (which == F_COS) {
                st_brdf_eval(b, wo, w, f);
                g = f[0] * w.z;
            } else {
                g = st_brdf_pdf(b, wo, w);
            }
            sum += g;
        }
    return sum * 2.0 * PI / ((double)nz * nphi);
}

static void ggx_and_visible_normals_are_normalised(void **state)
{
    (void)state;
    const float rough[][2] = {/* roughness, anisotropy strength */
                              {0.3f, 0.0f}, {0.5f, 0.0f}, {0.8f, 0.0f}, {1.0f, 0.0f},
                              {0.3f, 0.5f}, {0.4f, 0.9f}, {0.6f, 0.7f}};
    for (int r = 0; r < 7; r++) {
        st_brdf b = aniso_material(1.0f, 1.0f, rough[r][0], 1.0f, rough[r][1]);
        double d = hemisphere(&b, dir_from(1.0, 0.0), D_COS, 2000, 256);
        if (fabs(d - 1.0) > 2e-3)
            fail_msg("roughness %g, anisotropy %g: ∫ D n.h dω = %.6f, want 1", rough[r][0],
                     rough[r][1], d);
        const double zs[] = {1.0, 0.7, 0.3};
        for (int k = 0; k < 3; k++) {
            double v = hemisphere(&b, dir_from(zs[k], 0.4), VNDF, 2000, 256);
            if (fabs(v - 1.0) > 3e-3)
                fail_msg("roughness %g, anisotropy %g, v.z %g: ∫ D_v dω = %.6f, want 1",
                         rough[r][0], rough[r][1], zs[k], v);
        }
    }
}

/* The anisotropic D and V against the extension's definition, in double:
 * α_t = mix(roughness², 1, s²), α_b = roughness², along x and y;
 * D = 1 / (π α_t α_b ((h.x / α_t)² + (h.y / α_b)² + h.z²)²);
 * V = 1 / (2 (n.l sqrt((α_t v.x)² + (α_b v.y)² + v.z²) + n.v (... l ...))). */
static void anisotropic_terms_match_their_definitions(void **state)
{
    (void)state;
    uint64_t s = 19;
    for (int i = 0; i < 1000; i++) {
        double r = 0.1 + 0.9 * next_unit(&s), st = next_unit(&s);
        double ab = r * r, at = ab + (1.0 - ab) * st * st;
        st_brdf b = aniso_material(1.0f, 1.0f, (float)r, 1.0f, (float)st);
        st_dir h = dir_from(0.05 + 0.95 * next_unit(&s), 2 * PI * next_unit(&s));
        st_dir v = dir_from(0.05 + 0.95 * next_unit(&s), 2 * PI * next_unit(&s));
        double x = h.x / at, y = h.y / ab, t = x * x + y * y + (double)h.z * h.z;
        double d = 1.0 / (PI * at * ab * t * t);
        if (fabs(st_brdf_d(&b, h) - d) > 1e-4 * d)
            fail_msg("D: %g, definition %g (α_t %g, α_b %g)", st_brdf_d(&b, h), d, at, ab);
        double lv = sqrt(at * at * v.x * v.x + ab * ab * v.y * v.y + (double)v.z * v.z);
        double lh = sqrt(at * at * h.x * h.x + ab * ab * h.y * h.y + (double)h.z * h.z);
        double vis = 0.5 / (h.z * lv + v.z * lh);
        if (fabs(st_brdf_v(&b, v, h) - vis) > 1e-4 * vis)
            fail_msg("V: %g, definition %g", st_brdf_v(&b, v, h), vis);
    }
}

/* Strength 0 is the isotropic lobe, bit for bit: the same f and pdf. */
static void anisotropy_zero_is_isotropic(void **state)
{
    (void)state;
    uint64_t s = 23;
    for (int i = 0; i < 1000; i++) {
        float c = (float)next_unit(&s), m = (float)next_unit(&s), r = (float)next_unit(&s);
        st_brdf a = material(c, m, r, 1.0f), b = aniso_material(c, m, r, 1.0f, 0.0f);
        st_dir wo = dir_from(next_unit(&s), 2 * PI * next_unit(&s));
        st_dir wi = dir_from(next_unit(&s), 2 * PI * next_unit(&s));
        float fa[3], fb[3];
        st_brdf_eval(&a, wo, wi, fa);
        st_brdf_eval(&b, wo, wi, fb);
        assert_memory_equal(fa, fb, sizeof fa);
        assert_true(st_brdf_pdf(&a, wo, wi) == st_brdf_pdf(&b, wo, wi));
    }
}

/* D and V against their textbook forms, in double: D = α² / (π ((n.h)²
 * (α² - 1) + 1)²); V = G2 / (4 n.l n.v), G2 = 1 / (1 + Λ(v) + Λ(l)),
 * Λ(w) = (sqrt(1 + α² tan² θ) - 1) / 2 (Heitz 2014, eqs. 72, 99). */
static void ggx_terms_match_their_definitions(void **state)
{
    (void)state;
    uint64_t s = 9;
    for (int i = 0; i < 1000; i++) {
        double r = 0.1 + 0.9 * next_unit(&s), a = r * r;
        st_brdf b = material(1.0f, 1.0f, (float)r, 1.0f);
        st_dir h = dir_from(0.05 + 0.95 * next_unit(&s), 2 * PI * next_unit(&s));
        st_dir v = dir_from(0.05 + 0.95 * next_unit(&s), 2 * PI * next_unit(&s));
        double c = h.z, t = c * c * (a * a - 1.0) + 1.0, d = a * a / (PI * t * t);
        if (fabs(st_ggx_d(b.alpha, h) - d) > 1e-4 * d)
            fail_msg("D: %g, definition %g", st_ggx_d(b.alpha, h), d);
        double lv = (sqrt(1.0 + a * a * (1.0 - v.z * v.z) / (v.z * v.z)) - 1.0) / 2.0;
        double lh = (sqrt(1.0 + a * a * (1.0 - h.z * h.z) / (h.z * h.z)) - 1.0) / 2.0;
        double vis = 1.0 / (1.0 + lv + lh) / (4.0 * v.z * h.z);
        if (fabs(st_ggx_v(b.alpha, v, h) - vis) > 1e-4 * vis)
            fail_msg("V: %g, definition %g", st_ggx_v(b.alpha, v, h), vis);
    }
}

static void brdf_is_reciprocal(void **state)
{
    (void)state;
    uint64_t s = 1;
    for (int i = 0; i < 2000; i++) {
        st_brdf b = material((float)next_unit(&s), (float)next_unit(&s),
                             (float)(0.05 + next_unit(&s)), (float)next_unit(&s));
        if (i % 2) /* half of them anisotropic */
            st_brdf_anisotropic(&b, (float)next_unit(&s));
        st_dir a = dir_from(next_unit(&s), 2 * PI * next_unit(&s));
        st_dir c = dir_from(next_unit(&s), 2 * PI * next_unit(&s));
        float fac[3], fca[3];
        st_brdf_eval(&b, a, c, fac);
        st_brdf_eval(&b, c, a, fca);
        for (int k = 0; k < 3; k++)
            if (fabsf(fac[k] - fca[k]) > 1e-5f * fmaxf(1.0f, fabsf(fac[k])))
                fail_msg("f(a, c) = %g but f(c, a) = %g", fac[k], fca[k]);
    }
}

/* Monte Carlo albedo E[f cos / pdf] with its standard error. */
static double sampled_albedo(const st_brdf *b, st_dir wo, int n, double *stderr_out)
{
    uint64_t s = 7;
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; i++) {
        st_dir wi = st_brdf_sample(b, wo, (float)next_unit(&s), (float)next_unit(&s));
        double w = 0.0;
        if (wi.z > 0.0f) {
            float f[3], pdf = st_brdf_pdf(b, wo, wi);
            st_brdf_eval(b, wo, wi, f);
            w = pdf > 0.0f ? f[0] * wi.z / pdf : 0.0;
        }
        sum += w;
        sum2 += w * w;
    }
    double mean = sum / n;
    *stderr_out = sqrt(fmax(0.0, sum2 / n - mean * mean) / n);
    return mean;
}

static void albedo_matches_quadrature(void **state)
{
    (void)state;
    const float params[][5] = {/* base, metallic, roughness, specular, anisotropy */
                               {0.8f, 0.0f, 1.0f, 1.0f, 0.0f}, {0.8f, 0.0f, 0.5f, 1.0f, 0.0f},
                               {0.5f, 1.0f, 0.6f, 1.0f, 0.0f}, {0.9f, 0.5f, 0.4f, 0.7f, 0.0f},
                               {0.2f, 0.0f, 0.3f, 1.0f, 0.0f}, {0.5f, 1.0f, 0.4f, 1.0f, 0.8f},
                               {0.8f, 0.0f, 0.5f, 1.0f, 0.6f}};
    const double zs[] = {0.95, 0.5, 0.15};
    for (int p = 0; p < 7; p++)
        for (int k = 0; k < 3; k++) {
            st_brdf b = aniso_material(params[p][0], params[p][1], params[p][2], params[p][3],
                                       params[p][4]);
            st_dir wo = dir_from(zs[k], 1.0);
            double quad = hemisphere(&b, wo, F_COS, 2000, 512), se;
            double mc = sampled_albedo(&b, wo, 400000, &se);
            if (!(quad <= 1.0 + 1e-3) || fabs(mc - quad) > 5.0 * se + 2e-3)
                fail_msg("material %d, v.z %g: sampled albedo %.5f +- %.5f, quadrature %.5f", p,
                         zs[k], mc, se, quad);
        }
}

/* specularFactor 0 is Lambert: f = c / π whatever the directions. */
static void specular_zero_is_lambert(void **state)
{
    (void)state;
    st_brdf b = material(0.6f, 0.0f, 0.3f, 0.0f), d = material(0.6f, 0.0f, 0.3f, 1.0f);
    uint64_t s = 3;
    int differs = 0;
    for (int i = 0; i < 100; i++) {
        float f[3], g[3];
        st_dir wo = dir_from(next_unit(&s), 1.0), wi = dir_from(next_unit(&s), 2.0);
        st_brdf_eval(&b, wo, wi, f);
        assert_float_equal(f[1], 0.6f / ST_PI_F, 1e-7f);
        st_brdf_eval(&d, wo, wi, g);
        differs += fabsf(g[1] - 0.6f / ST_PI_F) > 1e-4f;
    }
    assert_true(differs > 50); /* with specularFactor 1 the lobe is there */
}

/* A white metal reflects all light as roughness goes to 0; rougher ones lose
 * some (single scattering) but never reflect more than they receive. */
static void white_metal_albedo(void **state)
{
    (void)state;
    const float rough[] = {0.0f, 0.02f, 0.3f, 0.7f, 1.0f};
    for (int r = 0; r < 5; r++) {
        st_brdf b = material(1.0f, 1.0f, rough[r], 1.0f);
        double se, a = sampled_albedo(&b, dir_from(0.8, 0.3), 200000, &se);
        if (!(a <= 1.0 + 5.0 * se + 1e-4))
            fail_msg("roughness %g: albedo %.5f above 1", rough[r], a);
        if (rough[r] <= 0.02f && fabs(a - 1.0) > 1e-3)
            fail_msg("roughness %g: albedo %.5f, want 1", rough[r], a);
    }
}

/* The same furnace for anisotropic white metals (F = 1): never above 1,
 * at any azimuth of wo about the tangent; a smooth one stretched only a
 * little along the tangent keeps nearly all. */
static void anisotropic_white_metal_albedo(void **state)
{
    (void)state;
    const float cases[][2] = {{0.0f, 0.1f}, {0.2f, 0.5f}, {0.4f, 0.8f}, {0.6f, 1.0f},
                              {1.0f, 1.0f}};
    for (int c = 0; c < 5; c++)
        for (int a = 0; a < 4; a++) {
            st_brdf b = aniso_material(1.0f, 1.0f, cases[c][0], 1.0f, cases[c][1]);
            double se, e = sampled_albedo(&b, dir_from(0.7, a * PI / 4), 200000, &se);
            if (!(e <= 1.0 + 5.0 * se + 1e-4))
                fail_msg("roughness %g, anisotropy %g: albedo %.5f above 1", cases[c][0],
                         cases[c][1], e);
            if (c == 0 && fabs(e - 1.0) > 1e-2)
                fail_msg("roughness 0, anisotropy 0.1: albedo %.5f, want about 1", e);
        }
}

/* The pdf integrates to one: ∫ pdf dω over the hemisphere plus the share
 * of samples lost below the surface (counted) is 1. */
static void pdf_integrates_to_one(void **state)
{
    (void)state;
    const float params[][4] = {{0.8f, 0.0f, 1.0f, 0.0f}, {0.8f, 0.0f, 0.5f, 1.0f},
                               {0.5f, 1.0f, 0.4f, 1.0f}, {0.5f, 1.0f, 1.0f, 1.0f}};
    for (int p = 0; p < 4; p++) {
        st_brdf b = material(params[p][0], params[p][1], params[p][2], params[p][3]);
        st_dir wo = dir_from(0.6, 0.2);
        double integral = hemisphere(&b, wo, PDF, 2000, 512);
        uint64_t s = 5;
        int lost = 0, n = 400000;
        for (int i = 0; i < n; i++)
            lost += st_brdf_sample(&b, wo, (float)next_unit(&s), (float)next_unit(&s)).z <= 0.0f;
        double want = 1.0 - (double)lost / n, se = sqrt(want * (1.0 - want) / n);
        if (fabs(integral - want) > 5.0 * se + 2e-3)
            fail_msg("material %d: ∫ pdf dω = %.5f, samples kept %.5f", p, integral, want);
    }
}

/* Chi-square of st_brdf_sample against st_brdf_pdf: nz x nphi bins of
 * equal solid angle, expected counts from the pdf by quadrature inside each
 * bin, plus one bin for samples lost below the surface (expected: what the
 * pdf leaves of 1); bins expecting under 5 merged. The threshold is the
 * chi-square quantile at significance 1e-4 by Wilson-Hilferty's
 * approximation, z = 3.719. */
#define NZ 16
#define NPHI 32
static void sampler_passes_chi_square(void **state)
{
    (void)state;
    const float params[][5] = {/* base, metallic, roughness, specular, anisotropy */
                               {0.8f, 0.0f, 0.5f, 1.0f, 0.0f}, {0.5f, 1.0f, 0.3f, 1.0f, 0.0f},
                               {0.9f, 0.5f, 0.6f, 0.7f, 0.0f}, {0.5f, 1.0f, 0.8f, 1.0f, 0.0f},
                               {0.5f, 1.0f, 0.3f, 1.0f, 0.7f}, {0.9f, 0.5f, 0.5f, 1.0f, 0.9f}};
    const double zs[] = {0.9, 0.4};
    const int n = 1000000;
    static double obs[NZ * NPHI + 1], expct[NZ * NPHI + 1];
    for (int p = 0; p < 6; p++)
        for (int k = 0; k < 2; k++) {
            st_brdf b = aniso_material(params[p][0], params[p][1], params[p][2], params[p][3],
                                       params[p][4]);
            st_dir wo = dir_from(zs[k], 0.5);
            double total = 0.0;
            for (int i = 0; i < NZ; i++)
                for (int j = 0; j < NPHI; j++) {
                    double e = 0.0;
                    for (int a = 0; a < 8; a++)
                        for (int c = 0; c < 8; c++)
                            e += st_brdf_pdf(&b, wo,
                                             dir_from((i + (a + 0.5) / 8) / NZ,
                                                      2 * PI * (j + (c + 0.5) / 8) / NPHI));
                    expct[i * NPHI + j] = e / 64.0 * 2 * PI / (NZ * NPHI) * n;
                    obs[i * NPHI + j] = 0.0;
                    total += expct[i * NPHI + j];
                }
            expct[NZ * NPHI] = fmax(0.0, n - total);
            obs[NZ * NPHI] = 0.0;
            uint64_t s = 11 + (uint64_t)p;
            for (int i = 0; i < n; i++) {
                st_dir wi = st_brdf_sample(&b, wo, (float)next_unit(&s), (float)next_unit(&s));
                int bin = NZ * NPHI;
                if (wi.z > 0.0f) {
                    double phi = atan2(wi.y, wi.x);
                    int iz = (int)(wi.z * NZ), ip = (int)((phi < 0 ? phi + 2 * PI : phi) /
                                                          (2 * PI) * NPHI);
                    bin = (iz < NZ ? iz : NZ - 1) * NPHI + (ip < NPHI ? ip : NPHI - 1);
                }
                obs[bin] += 1.0;
            }
            double chi2 = 0.0, eo = 0.0, oo = 0.0;
            int dof = -1;
            for (int i = 0; i <= NZ * NPHI; i++) {
                eo += expct[i];
                oo += obs[i];
                if (eo >= 5.0) {
                    chi2 += (oo - eo) * (oo - eo) / eo;
                    dof++;
                    eo = oo = 0.0;
                }
            }
            double h = 2.0 / (9.0 * dof), limit = dof * pow(1.0 - h + 3.719 * sqrt(h), 3.0);
            if (!(chi2 < limit))
                fail_msg("material %d, v.z %g: chi-square %.1f over %d dof, limit %.1f", p,
                         zs[k], chi2, dof, limit);
        }
}

/* ---- transmission (bsdf_dielectric.h) -------------------------------------- */

/* A material with transmission tr, metallic m, base colour c, roughness r
 * and the relative ior eta (wi's side over wo's) in *d. */
static st_brdf glass(float c, float m, float r, float tr, float eta, st_dielectric *d)
{
    const float base[3] = {c, c, c}, white[3] = {1.0f, 1.0f, 1.0f};
    float ior = eta >= 1.0f ? eta : 1.0f / eta;
    *d = st_dielectric_make(tr, m, base, ior, eta >= 1.0f, 0);
    return st_brdf_make(base, m, r, 1.0f, white, ior, tr);
}

/* Monte Carlo energy of the material towards wo: E[f |cos| / pdf] over the
 * whole sphere, the transmitted samples times η² (the radiance BTDF's
 * 1 / η² undone: what is left is the share of power that goes on). */
static const st_coat no_coat = {0.0f, 0.5f, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f},
                                {0.0f, 0.0f, 1.0f}};
static const st_sheen no_sheen = {{0.0f, 0.0f, 0.0f}, 0.0f, 0.5f, 0.25f};

/* ... of channel `ch` under a sheen and a coat. */
static double sampled_energy_layered(const st_brdf *b, const st_dielectric *d, const st_sheen *sh,
                                     const st_coat *c, st_dir wo, int ch, int n, double *se)
{
    uint64_t s = 21;
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; i++) {
        float u1 = (float)next_unit(&s), u2 = (float)next_unit(&s), u3 = (float)next_unit(&s);
        st_dir wi = st_coated_sheened_sample(b, d, sh, c, wo, u1, u2, u3);
        float f[3], pdf = st_coated_sheened_pdf(b, d, sh, c, wo, wi);
        st_coated_sheened_eval(b, d, sh, c, wo, wi, f);
        double w = pdf > 0.0f && wi.z != 0.0f ? f[ch] * fabs(wi.z) / pdf : 0.0;
        if (wi.z < 0.0f && !d->thin) /* a thin wall has the same medium on both sides */
            w *= (double)d->eta * d->eta;
        sum += w;
        sum2 += w * w;
    }
    double mean = sum / n;
    *se = sqrt(fmax(0.0, sum2 / n - mean * mean) / n);
    return mean;
}

static double sampled_energy_coated(const st_brdf *b, const st_dielectric *d, const st_coat *c,
                                    st_dir wo, int n, double *se)
{
    return sampled_energy_layered(b, d, &no_sheen, c, wo, 0, n, se);
}

static double sampled_energy(const st_brdf *b, const st_dielectric *d, st_dir wo, int n,
                             double *se)
{
    return sampled_energy_coated(b, d, &no_coat, wo, n, se);
}

/* A smooth white dielectric loses nothing: R + T = 1 from either side,
 * total internal reflection included (leaving at 0.3 is past the critical
 * angle of 1.5); rough ones lose only what single scattering loses (<= 1;
 * from inside at α = 1 microfacet total internal reflection sends over half
 * below the surface, so the floor is 0.3). */
static void dielectric_furnace(void **state)
{
    (void)state;
    const float etas[] = {1.5f, 1.0f / 1.5f, 1.33f};
    const double zs[] = {0.95, 0.6, 0.3};
    for (int e = 0; e < 3; e++)
        for (int k = 0; k < 3; k++) {
            st_dielectric d;
            st_brdf b = glass(1.0f, 0.0f, 0.0f, 1.0f, etas[e], &d);
            double se, a = sampled_energy(&b, &d, dir_from(zs[k], 0.7), 200000, &se);
            if (fabs(a - 1.0) > 5.0 * se + 2e-3)
                fail_msg("smooth, η %g, wo.z %g: R + T = %.5f +- %.5f, want 1", etas[e], zs[k],
                         a, se);
            const float rough[] = {0.3f, 0.7f, 1.0f};
            for (int r = 0; r < 3; r++) {
                b = glass(1.0f, 0.0f, rough[r], 1.0f, etas[e], &d);
                a = sampled_energy(&b, &d, dir_from(zs[k], 0.7), 100000, &se);
                if (!(a <= 1.0 + 5.0 * se + 1e-3) || !(a > 0.3))
                    fail_msg("roughness %g, η %g, wo.z %g: energy %.5f +- %.5f", rough[r],
                             etas[e], zs[k], a, se);
            }
        }
}

/* Half transmissive, half opaque, partly metal: the energy is the mixture's
 * and still at most 1; a white smooth one with transmission 1 and metallic
 * 0 keeps everything, one of base colour 0.5 transmits half as much. */
static void transmission_mixture_energy(void **state)
{
    (void)state;
    st_dielectric d;
    st_brdf b = glass(0.9f, 0.3f, 0.4f, 0.5f, 1.5f, &d);
    double se, a = sampled_energy(&b, &d, dir_from(0.7, 0.1), 200000, &se);
    if (!(a <= 1.0 + 5.0 * se) || !(a > 0.5))
        fail_msg("mixture: energy %.5f +- %.5f", a, se);
    /* smooth, base colour 0.5: R + 0.5 T with R the Fresnel reflectance at normal incidence */
    b = glass(0.5f, 0.0f, 0.0f, 1.0f, 1.5f, &d);
    double r = st_fresnel_dielectric(1.0f, 1.5f), want = r + 0.5 * (1.0 - r);
    a = sampled_energy(&b, &d, dir_from(1.0, 0.0), 200000, &se);
    if (fabs(a - want) > 5.0 * se + 2e-3)
        fail_msg("tinted: energy %.5f +- %.5f, want %.5f", a, se, want);
}

/* The Fresnel reflectance against its definition in double, (rs² + rp²) / 2
 * with Snell's cos_t, 1 past the critical angle; 0.04 at normal incidence
 * for 1.5. */
static void fresnel_matches_definition(void **state)
{
    (void)state;
    assert_float_equal(st_fresnel_dielectric(1.0f, 1.5f), 0.04f, 1e-6f);
    const double etas[] = {1.5, 1.0 / 1.5, 2.4, 1.0 / 1.33};
    for (int e = 0; e < 4; e++)
        for (int i = 0; i <= 100; i++) {
            double c = i / 100.0, eta = etas[e], s2 = (1.0 - c * c) / (eta * eta), want = 1.0;
            if (s2 < 1.0) {
                double ct = sqrt(1.0 - s2), rs = (c - eta * ct) / (c + eta * ct),
                       rp = (eta * c - ct) / (eta * c + ct);
                want = 0.5 * (rs * rs + rp * rp);
            }
            double got = st_fresnel_dielectric((float)c, (float)eta);
            if (fabs(got - want) > 1e-5)
                fail_msg("η %g, cos %g: F %.7f, definition %.7f", eta, c, got, want);
        }
}

/* The direction mirrored in the surface's plane (z -> -z): an isotropic
 * BSDF is the same seen from below, so the reverse of a pair with wo above
 * and wi below is (mirror(wi), mirror(wo)) with η inverted. */
static st_dir mirror(st_dir w)
{
    st_dir m = {w.x, w.y, -w.z};
    return m;
}

/* Reciprocity, bare and under a clear coat (tilted by its own normal map
 * or not) and a sheen: reflections f(wo, wi) =
 * f(wi, wo); refractions, the generalised form f(wo, wi) / η(wo)² = f(wi, wo) / η(wi)², i.e. with wo's
 * side at 1, f(wo, wi; η) = f(mirror wi, mirror wo; 1 / η) / η². */
static void dielectric_is_reciprocal(void **state)
{
    (void)state;
    uint64_t s = 13;
    int refractions = 0;
    for (int i = 0; i < 4000; i++) {
        float eta = next_unit(&s) < 0.5 ? 1.5f : 1.0f / 1.5f;
        st_dielectric d, dr;
        float r = (float)(0.1 + 0.9 * next_unit(&s)), c = (float)next_unit(&s);
        st_brdf b = glass(c, 0.0f, r, 1.0f, eta, &d);
        st_brdf br = glass(c, 0.0f, r, 1.0f, 1.0f / eta, &dr);
        st_dir wo = dir_from(0.01 + 0.99 * next_unit(&s), 2 * PI * next_unit(&s));
        st_dir wi = dir_from(-1.0 + 2.0 * next_unit(&s), 2 * PI * next_unit(&s));
        /* half of them under a clear coat (bsdf_coat.h) */
        st_coat cc = st_coat_make(i % 2 ? (float)next_unit(&s) : 0.0f,
                                  (float)(0.05 + next_unit(&s)));
        /* and a third under a sheen (bsdf_sheen.h) */
        const float sc[3] = {(float)next_unit(&s), (float)next_unit(&s), (float)next_unit(&s)};
        st_sheen sh = i % 3 ? no_sheen : st_sheen_make(sc, (float)next_unit(&s));
        /* and, for reflections, a quarter about a tilted coat normal */
        if (i % 4 == 1 && wi.z > 0.0f)
            st_coat_tilt(&cc, dir_from(0.3 + 0.7 * next_unit(&s), 2 * PI * next_unit(&s)));
        float f[3], g[3];
        st_coated_sheened_eval(&b, &d, &sh, &cc, wo, wi, f);
        if (wi.z > 0.0f) {
            st_coated_sheened_eval(&b, &d, &sh, &cc, wi, wo, g);
        } else {
            st_coated_sheened_eval(&br, &dr, &sh, &cc, mirror(wi), mirror(wo), g);
            for (int k = 0; k < 3; k++)
                g[k] /= eta * eta;
            refractions += f[0] > 0.0f;
        }
        for (int k = 0; k < 3; k++)
            if (fabsf(f[k] - g[k]) > 2e-3f * fmaxf(1e-2f, fabsf(f[k])))
                fail_msg("η %g, roughness %g, wi.z %g: f %g, reversed %g", eta, r, wi.z, f[k],
                         g[k]);
    }
    if (refractions < 300)
        fail_msg("only %d refractions with f > 0", refractions);
}

/* A thin wall (bsdf_dielectric.h): smooth and white, it keeps all of the
 * energy at every angle, passing T' = 1 - 2R / (1 + R) of it (R the
 * exact Fresnel reflectance of one face at wo's angle) straight through,
 * wi = -wo (all but GGX's far tail at the least α); at any roughness f
 * is reciprocal, f(wo, wi) = f(wi, wo) for a reflection and f(wo, wi) =
 * f(mirror wi, mirror wo) for a transmission (the wall is the same from
 * both sides, no 1 / η²). */
static void thin_wall_passes_straight_through(void **state)
{
    (void)state;
    const float one[3] = {1.0f, 1.0f, 1.0f};
    const double zs[] = {0.95, 0.6, 0.3};
    for (int k = 0; k < 3; k++) {
        st_brdf b = st_brdf_make(one, 0.0f, 0.0f, 1.0f, one, 1.5f, 1.0f);
        st_dielectric d = st_dielectric_make(1.0f, 0.0f, one, 1.5f, 1, 1);
        st_dir wo = dir_from(zs[k], 0.7);
        uint64_t s = 3;
        const int n = 200000;
        double sum = 0.0, through = 0.0, along = 0.0;
        for (int i = 0; i < n; i++) {
            float u1 = (float)next_unit(&s), u2 = (float)next_unit(&s), u3 = (float)next_unit(&s);
            st_dir wi = st_bsdf_sample(&b, &d, wo, u1, u2, u3);
            float f[3], pdf = st_bsdf_pdf(&b, &d, wo, wi);
            st_bsdf_eval(&b, &d, wo, wi, f);
            double w = pdf > 0.0f ? f[0] * fabs(wi.z) / pdf : 0.0;
            sum += w / n;
            if (wi.z < 0.0f) {
                through += w / n;
                if (fabs(wi.x + wo.x) + fabs(wi.y + wo.y) + fabs(wi.z + wo.z) < 0.1)
                    along += w / n;
            }
        }
        double r = st_fresnel_dielectric((float)zs[k], 1.5f), t = 1.0 - 2.0 * r / (1.0 + r);
        print_message("thin wall at cos %.2f: energy %.6f, through %.6f (T' %.6f), %.6f of it "
                      "within 0.1 of -wo\n", zs[k], sum, through, t, along / through);
        if (fabs(sum - 1.0) > 2e-3 || fabs(through - t) > 2e-3 || along < 0.99 * through)
            fail_msg("cos %g: energy %.6f, through %.6f (T' %.6f), along -wo %.6f", zs[k], sum,
                     through, t, along);
    }
    uint64_t s = 17;
    for (int i = 0; i < 4000; i++) {
        float r = (float)(0.1 + 0.9 * next_unit(&s)), c = (float)next_unit(&s);
        const float base[3] = {c, c, c};
        st_brdf b = st_brdf_make(base, 0.0f, r, 1.0f, one, 1.5f, 1.0f);
        st_dielectric d = st_dielectric_make(1.0f, 0.0f, base, 1.5f, next_unit(&s) < 0.5, 1);
        st_dir wo = dir_from(0.01 + 0.99 * next_unit(&s), 2 * PI * next_unit(&s));
        st_dir wi = dir_from(-1.0 + 2.0 * next_unit(&s), 2 * PI * next_unit(&s));
        float f[3], g[3];
        st_bsdf_eval(&b, &d, wo, wi, f);
        if (wi.z > 0.0f)
            st_bsdf_eval(&b, &d, wi, wo, g);
        else
            st_bsdf_eval(&b, &d, mirror(wi), mirror(wo), g);
        if (fabsf(f[0] - g[0]) > 2e-3f * fmaxf(1e-2f, fabsf(f[0])))
            fail_msg("roughness %g, wi.z %g: f %g, reversed %g", r, wi.z, f[0], g[0]);
    }
}

/* The mixture's pdf over the whole sphere (z in [-1, 1]) by the midpoint
 * rule: 1 less the share of samples lost (none for these). */
static double sphere_pdf(const st_brdf *b, const st_dielectric *d, const st_sheen *sh,
                         const st_coat *c, st_dir wo, int nz, int nphi)
{
    double sum = 0.0;
    for (int i = 0; i < nz; i++)
        for (int j = 0; j < nphi; j++)
            sum += st_coated_sheened_pdf(b, d, sh, c, wo,
                               dir_from(-1.0 + 2.0 * (i + 0.5) / nz, 2 * PI * (j + 0.5) / nphi));
    return sum * 4.0 * PI / ((double)nz * nphi);
}

/* Chi-square of st_coated_sample against st_coated_pdf (bare, coated,
 * the coat about its own normal or not, sheened, with and without
 * transmission, solid or thin-walled, with diffuse transmission, over an
 * anisotropic lobe) over the sphere: SZ x
 * SPHI bins of equal solid angle in (cos θ in [-1, 1], φ), expected counts
 * from the pdf by SQ x SQ midpoint quadrature inside each bin (the refracted
 * peak is narrow), one more bin
 * for samples lost (expected: what the pdf leaves of 1), bins expecting
 * under 5 merged. Significance 1e-4 (Wilson-Hilferty, z = 3.719), as the
 * BRDF's test. The pdf is checked to integrate to the samples kept. */
#define SZ 32
#define SPHI 32
#define SQ 24
static void transmission_sampler_passes_chi_square(void **state)
{
    (void)state;
    /* base, metallic, roughness, transmission, η, coat, its roughness, sheen colour, sheen
     * roughness, the coat's normal's z (tilted towards φ = 1: st_coat_tilt), thin-walled,
     * diffuse transmission (KHR_materials_diffuse_transmission, colour (1, 0.6, 0.3)),
     * anisotropy strength (KHR_materials_anisotropy, along x) */
    const float params[][13] = {
        {1.0f, 0.0f, 0.3f, 1.0f, 1.5f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f},
        {1.0f, 0.0f, 0.5f, 1.0f, 1.0f / 1.5f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f},
        {0.7f, 0.2f, 0.6f, 0.6f, 1.33f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f},
        {0.9f, 0.0f, 0.8f, 1.0f, 2.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f},
        {0.8f, 0.0f, 0.7f, 0.0f, 1.5f, 1.0f, 0.3f, 0.0f, 0.0f, 1.0f, 0.0f},
        {0.6f, 1.0f, 0.5f, 0.0f, 1.5f, 0.7f, 0.4f, 0.0f, 0.0f, 1.0f, 0.0f},
        {0.9f, 0.0f, 0.4f, 1.0f, 1.5f, 0.5f, 0.5f, 0.0f, 0.0f, 1.0f, 0.0f},
        {0.8f, 0.0f, 0.7f, 0.0f, 1.5f, 0.0f, 0.0f, 1.0f, 0.5f, 1.0f, 0.0f},
        {0.5f, 1.0f, 0.3f, 0.0f, 1.5f, 0.0f, 0.0f, 0.6f, 0.2f, 1.0f, 0.0f},
        {0.9f, 0.0f, 0.4f, 1.0f, 1.5f, 0.6f, 0.3f, 0.8f, 0.9f, 1.0f, 0.0f},
        {0.8f, 0.0f, 0.7f, 0.0f, 1.5f, 1.0f, 0.3f, 0.0f, 0.0f, 0.8f, 0.0f},
        {0.9f, 0.0f, 0.4f, 1.0f, 1.5f, 0.5f, 0.2f, 0.0f, 0.0f, 0.9f, 0.0f},
        {1.0f, 0.0f, 0.2f, 1.0f, 1.5f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 1.0f},
        {0.9f, 0.0f, 0.5f, 1.0f, 1.5f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 1.0f},
        {0.8f, 0.0f, 0.3f, 0.6f, 1.33f, 0.5f, 0.2f, 0.0f, 0.0f, 1.0f, 1.0f},
        {0.8f, 0.0f, 0.5f, 0.0f, 1.5f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.5f},
        {0.2f, 0.0f, 0.6f, 0.0f, 1.5f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 1.0f},
        {0.9f, 0.3f, 0.4f, 0.5f, 1.5f, 0.5f, 0.3f, 0.0f, 0.0f, 1.0f, 0.0f, 0.7f},
        {0.7f, 0.0f, 0.6f, 0.0f, 1.5f, 0.0f, 0.0f, 0.6f, 0.4f, 1.0f, 0.0f, 0.6f},
        {0.6f, 1.0f, 0.3f, 0.0f, 1.5f, 0.7f, 0.4f, 0.0f, 0.0f, 0.9f, 0.0f, 0.0f, 0.8f},
        {0.9f, 0.2f, 0.4f, 0.6f, 1.5f, 0.0f, 0.0f, 0.5f, 0.3f, 1.0f, 0.0f, 0.0f, 0.7f}};
    const int nmat = (int)(sizeof params / sizeof params[0]);
    const double zs[] = {0.9, 0.35};
    const int n = 1000000;
    static double obs[SZ * SPHI + 1], expct[SZ * SPHI + 1];
    for (int p = 0; p < nmat; p++)
        for (int k = 0; k < 2; k++) {
            st_dielectric d;
            st_brdf b = glass(params[p][0], params[p][1], params[p][2], params[p][3],
                              params[p][4], &d);
            d.thin = params[p][10] > 0.0f; /* its η: the ior, from either side */
            const float dtc[3] = {1.0f, 0.6f, 0.3f};
            st_brdf_diffuse_transmission(&b, params[p][1], params[p][3], params[p][11], dtc);
            st_brdf_anisotropic(&b, params[p][12]);
            st_coat cc = st_coat_make(params[p][5], params[p][6]);
            if (params[p][9] < 1.0f)
                st_coat_tilt(&cc, dir_from(params[p][9], 1.0));
            const float sc[3] = {params[p][7], 0.8f * params[p][7], 0.5f * params[p][7]};
            st_sheen sh = st_sheen_make(sc, params[p][8]);
            st_dir wo = dir_from(zs[k], 0.5);
            double integral = sphere_pdf(&b, &d, &sh, &cc, wo, 4000, 512);
            double total = 0.0;
            for (int i = 0; i < SZ; i++)
                for (int j = 0; j < SPHI; j++) {
                    double e = 0.0;
                    for (int a = 0; a < SQ; a++)
                        for (int c = 0; c < SQ; c++)
                            e += st_coated_sheened_pdf(&b, &d, &sh, &cc, wo,
                                               dir_from(-1.0 + 2.0 * (i + (a + 0.5) / SQ) / SZ,
                                                      2 * PI * (j + (c + 0.5) / SQ) / SPHI));
                    expct[i * SPHI + j] = e / (SQ * SQ) * 4 * PI / (SZ * SPHI) * n;
                    obs[i * SPHI + j] = 0.0;
                    total += expct[i * SPHI + j];
                }
            expct[SZ * SPHI] = fmax(0.0, n - total);
            obs[SZ * SPHI] = 0.0;
            uint64_t s = 31 + (uint64_t)p;
            int lost = 0;
            for (int i = 0; i < n; i++) {
                float u1 = (float)next_unit(&s), u2 = (float)next_unit(&s),
                      u3 = (float)next_unit(&s);
                st_dir wi = st_coated_sheened_sample(&b, &d, &sh, &cc, wo, u1, u2, u3);
                int bin = SZ * SPHI;
                if (st_coated_sheened_pdf(&b, &d, &sh, &cc, wo, wi) > 0.0f) {
                    double phi = atan2(wi.y, wi.x);
                    int iz = (int)((wi.z + 1.0) / 2.0 * SZ),
                        ip = (int)((phi < 0 ? phi + 2 * PI : phi) / (2 * PI) * SPHI);
                    bin = (iz < SZ ? (iz < 0 ? 0 : iz) : SZ - 1) * SPHI +
                          (ip < SPHI ? ip : SPHI - 1);
                } else {
                    lost++;
                }
                obs[bin] += 1.0;
            }
            double kept = 1.0 - (double)lost / n;
            if (fabs(integral - kept) > 5.0 * sqrt(kept * (1.0 - kept) / n) + 3e-3)
                fail_msg("material %d, wo.z %g: ∫ pdf dω = %.5f, samples kept %.5f", p, zs[k],
                         integral, kept);
            double chi2 = 0.0, eo = 0.0, oo = 0.0;
            int dof = -1;
            for (int i = 0; i <= SZ * SPHI; i++) {
                eo += expct[i];
                oo += obs[i];
                if (eo >= 5.0) {
                    chi2 += (oo - eo) * (oo - eo) / eo;
                    dof++;
                    eo = oo = 0.0;
                }
            }
            double h = 2.0 / (9.0 * dof), limit = dof * pow(1.0 - h + 3.719 * sqrt(h), 3.0);
            if (!(chi2 < limit))
                fail_msg("material %d, wo.z %g: chi-square %.1f over %d dof, limit %.1f", p,
                         zs[k], chi2, dof, limit);
        }
}

/* ---- diffuse transmission (KHR_materials_diffuse_transmission) ---------- */

/* ∫ f |cos| dω of channel ch over the upper (sign 1) or lower (-1)
 * hemisphere by the midpoint rule in (z, φ). */
static double hemisphere_f_cos(const st_brdf *b, st_dir wo, int ch, double sign)
{
    const int nz = 1000, nphi = 256;
    double sum = 0.0;
    for (int i = 0; i < nz; i++)
        for (int j = 0; j < nphi; j++) {
            st_dir w = dir_from(sign * (i + 0.5) / nz, 2.0 * PI * (j + 0.5) / nphi);
            float f[3];
            st_brdf_eval(b, wo, w, f);
            sum += f[ch] * fabs(w.z);
        }
    return sum * 2.0 * PI / ((double)nz * nphi);
}

/* A white Lambertian material (specularFactor 0) whose diffuse part
 * transmits t of colour c keeps all the energy when c is white: the upper
 * hemisphere's ∫ f |cos| dω is 1 - t and the lower one's t c (the
 * specification's mix), by quadrature of st_brdf_eval; sampled, f |cos| /
 * pdf over the sphere gives the same split, and the pdf integrates to 1. */
static void diffuse_transmission_furnace(void **state)
{
    (void)state;
    const float ts[] = {0.0f, 0.3f, 0.75f, 1.0f}, white[3] = {1.0f, 1.0f, 1.0f};
    const float tint[3] = {1.0f, 0.5f, 0.2f};
    for (int i = 0; i < 4; i++)
        for (int w = 0; w < 2; w++) {
            const float *c = w ? tint : white;
            st_brdf b = material(1.0f, 0.0f, 0.5f, 0.0f);
            st_brdf_diffuse_transmission(&b, 0.0f, 0.0f, ts[i], c);
            st_dir wo = dir_from(0.6, 0.3);
            for (int k = 0; k < 3; k++) {
                double up = hemisphere_f_cos(&b, wo, k, 1.0), down = hemisphere_f_cos(&b, wo, k, -1.0);
                if (fabs(up - (1.0 - ts[i])) > 1e-4 || fabs(down - ts[i] * c[k]) > 1e-4)
                    fail_msg("t %g, channel %d: reflected %.5f (want %.5f), transmitted %.5f "
                             "(want %.5f)", ts[i], k, up, 1.0 - ts[i], down, ts[i] * c[k]);
            }
            uint64_t s = 41;
            double r = 0.0, t = 0.0, r2 = 0.0, t2 = 0.0, pdf_sum = 0.0;
            const int n = 200000;
            for (int j = 0; j < n; j++) {
                st_dir wi = st_brdf_sample(&b, wo, (float)next_unit(&s), (float)next_unit(&s));
                float f[3], pdf = st_brdf_pdf(&b, wo, wi);
                st_brdf_eval(&b, wo, wi, f);
                double e = pdf > 0.0f ? f[1] * fabs(wi.z) / pdf : 0.0;
                if (wi.z > 0.0f)
                    r += e / n, r2 += e * e / n;
                else
                    t += e / n, t2 += e * e / n;
            }
            /* five standard errors of each mean (the split is binomial) */
            double sr = 5.0 * sqrt(fmax(0.0, r2 - r * r) / n) + 1e-6;
            double st = 5.0 * sqrt(fmax(0.0, t2 - t * t) / n) + 1e-6;
            for (int a = 0; a < 1000; a++)
                for (int q = 0; q < 256; q++)
                    pdf_sum += st_brdf_pdf(&b, wo, dir_from(-1.0 + 2.0 * (a + 0.5) / 1000,
                                                            2 * PI * (q + 0.5) / 256));
            pdf_sum *= 4.0 * PI / (1000.0 * 256);
            if (fabs(r - (1.0 - ts[i])) > sr || fabs(t - ts[i] * c[1]) > st ||
                fabs(pdf_sum - 1.0) > 1e-3)
                fail_msg("t %g: sampled reflection %.5f, transmission %.5f, ∫ pdf %.5f", ts[i],
                         r, t, pdf_sum);
        }
}

/* Diffuse transmission is reciprocal across the surface: seen from the
 * other side the frame turns over, (x, y, z) -> (x, -y, -z), and f(wo, wi)
 * = f(wi', wo') with the primes turned; with a specular lobe above (its
 * Fresnel, at the half vector of wo and the mirrored wi, is symmetric). */
static void diffuse_transmission_is_reciprocal(void **state)
{
    (void)state;
    uint64_t s = 43;
    const float c[3] = {0.9f, 0.4f, 0.7f};
    for (int i = 0; i < 2000; i++) {
        st_brdf b = material((float)next_unit(&s), (float)next_unit(&s),
                             (float)(0.05 + next_unit(&s)), (float)next_unit(&s));
        st_brdf_diffuse_transmission(&b, 0.0f, 0.0f, (float)next_unit(&s), c);
        st_dir wo = dir_from(next_unit(&s), 2 * PI * next_unit(&s));
        st_dir wi = dir_from(-next_unit(&s), 2 * PI * next_unit(&s));
        st_dir wo2 = {wi.x, -wi.y, -wi.z}, wi2 = {wo.x, -wo.y, -wo.z};
        float f[3], g[3];
        st_brdf_eval(&b, wo, wi, f);
        st_brdf_eval(&b, wo2, wi2, g);
        for (int k = 0; k < 3; k++)
            if (fabsf(f[k] - g[k]) > 1e-5f * fmaxf(1.0f, fabsf(f[k])) || !(f[k] >= 0.0f))
                fail_msg("f(wo, wi) = %g but f(wi', wo') = %g", f[k], g[k]);
    }
}

/* Transmission 0 changes nothing, bit for bit: f, pdf and the samples. */
static void diffuse_transmission_zero_changes_nothing(void **state)
{
    (void)state;
    uint64_t s = 47;
    const float c[3] = {1.0f, 1.0f, 1.0f};
    for (int i = 0; i < 1000; i++) {
        st_brdf a = material((float)next_unit(&s), (float)next_unit(&s), (float)next_unit(&s),
                             (float)next_unit(&s)),
                b = a;
        st_brdf_diffuse_transmission(&b, 0.0f, 0.0f, 0.0f, c);
        st_dir wo = dir_from(next_unit(&s), 2 * PI * next_unit(&s));
        st_dir wi = dir_from(2.0 * next_unit(&s) - 1.0, 2 * PI * next_unit(&s));
        float fa[3], fb[3], u1 = (float)next_unit(&s), u2 = (float)next_unit(&s);
        st_brdf_eval(&a, wo, wi, fa);
        st_brdf_eval(&b, wo, wi, fb);
        assert_memory_equal(fa, fb, sizeof fa);
        assert_true(st_brdf_pdf(&a, wo, wi) == st_brdf_pdf(&b, wo, wi));
        st_dir sa = st_brdf_sample(&a, wo, u1, u2), sb = st_brdf_sample(&b, wo, u1, u2);
        assert_memory_equal(&sa, &sb, sizeof sa);
    }
}

/* ---- dispersion (KHR_materials_dispersion, st_shared.h) ------------------ */

/* st_dispersed_ior against Cauchy's n(λ) = A + B / λ² as the specification
 * derives it, in double: B = (n_d - 1) / (V_d (λ_F^-2 - λ_C^-2)), A = n_d -
 * B / λ_d², with V_d = 20 / dispersion and Fraunhofer's F, C and d lines
 * (486.1, 656.3, 587.56 nm), at the channels' wavelengths (R the C line, G
 * the d line, B the F line); to 2e-4 (n_d - 1) dispersion (the
 * specification's constants 523655 and 1.5168 are rounded). The Abbe
 * number's definition then holds: n_F - n_C = (n_d - 1) / V_d, to 0.1 %.
 * Dispersion 0 leaves n_d exactly; the ior never falls below 1. */
static void dispersed_ior_matches_cauchy(void **state)
{
    (void)state;
    const double nds[] = {1.33, 1.5, 2.42}, disps[] = {0.36, 1.0, 2.04};
    const double lf = 486.1, lc = 656.3, ld = 587.56, lambda[3] = {lc, 587.6, lf};
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            double nd = nds[a], v = 20.0 / disps[b];
            double bb = (nd - 1.0) / (v * (1.0 / (lf * lf) - 1.0 / (lc * lc))), aa = nd - bb / (ld * ld);
            float n[3];
            for (int c = 0; c < 3; c++) {
                n[c] = st_dispersed_ior((float)nd, (float)disps[b], (st_u32)c);
                double want = aa + bb / (lambda[c] * lambda[c]);
                if (fabs(n[c] - want) > 2e-4 * (nd - 1.0) * disps[b])
                    fail_msg("n_d %g, dispersion %g, channel %d: %.6f, Cauchy %.6f", nd, disps[b],
                             c, n[c], want);
            }
            double spread = n[2] - n[0], abbe = (nd - 1.0) / v;
            if (fabs(spread - abbe) > 1e-3 * abbe)
                fail_msg("n_F - n_C = %.6f, (n_d - 1) / V_d = %.6f", spread, abbe);
        }
    for (int c = 0; c < 3; c++) {
        assert_true(st_dispersed_ior(1.5f, 0.0f, (st_u32)c) == 1.5f);
        assert_true(st_dispersed_ior(1.01f, 50.0f, (st_u32)c) >= 1.0f);
    }
}

/* A clear coat over white bases reflects at most what it receives: over a
 * Lambertian base, a white metal and smooth glass (R + T), from normal to
 * grazing; a full coat over a black Lambertian base reflects exactly its
 * own lobe, 0.04 at normal incidence when smooth (the coat's F0). */
static void coat_furnace(void **state)
{
    (void)state;
    const float bases[][5] = {/* base, metallic, roughness, transmission, specular */
                              {1.0f, 0.0f, 1.0f, 0.0f, 0.0f},
                              {1.0f, 1.0f, 0.0f, 0.0f, 1.0f},
                              {1.0f, 1.0f, 0.5f, 0.0f, 1.0f},
                              {1.0f, 0.0f, 0.0f, 1.0f, 1.0f}};
    const double zs[] = {0.95, 0.5, 0.15};
    for (int p = 0; p < 4; p++)
        for (int k = 0; k < 3; k++)
            for (int r = 0; r < 2; r++) {
                const float base[3] = {1.0f, 1.0f, 1.0f};
                st_dielectric d = st_dielectric_make(bases[p][3], bases[p][1], base, 1.5f, 1, 0);
                st_brdf b = st_brdf_make(base, bases[p][1], bases[p][2], bases[p][4], base, 1.5f,
                                         bases[p][3]);
                st_coat c = st_coat_make(1.0f, r ? 0.4f : 0.0f);
                double se, a = sampled_energy_coated(&b, &d, &c, dir_from(zs[k], 0.3), 200000,
                                                     &se);
                if (!(a <= 1.0 + 5.0 * se + 2e-3) || !(a > 0.3))
                    fail_msg("base %d, coat roughness %d, wo.z %g: energy %.5f +- %.5f", p, r,
                             zs[k], a, se);
            }
    const float black[3] = {0.0f, 0.0f, 0.0f};
    st_dielectric d = st_dielectric_make(0.0f, 0.0f, black, 1.5f, 1, 0);
    st_brdf b = st_brdf_make(black, 0.0f, 1.0f, 0.0f, black, 1.5f, 0.0f);
    st_coat c = st_coat_make(1.0f, 0.0f);
    double se, a = sampled_energy_coated(&b, &d, &c, dir_from(1.0, 0.0), 100000, &se);
    if (fabs(a - 0.04) > 5.0 * se + 1e-3)
        fail_msg("smooth coat over black: %.5f +- %.5f, want 0.04", a, se);
}

/* ---- sheen (bsdf_sheen.h) -------------------------------------------------- */

/* The Charlie distribution integrates to 1 against n.h over the hemisphere
 * of normals, ∫ D cos θh dωh = (2 + 1/α) ∫ sin^(1/α+1) θ cos θ dθ = 1, at
 * every α (the lobe's D read back from D V at wo = wi = h, where V is
 * 1 / ((1 + 2 Λ(h.z)) 4 h.z²) by the specification's Λ, in double). */
static double sheen_fit(double x, double a)
{
    double t = (1.0 - a) * (1.0 - a);
    return (21.5473 + 3.7772 * t) / (1.0 + (3.82987 - 0.50552 * t) * pow(x, 0.19823 - 0.03022 * t)) +
           (-1.97760 + 0.70367 * t) * x - 4.32054 - 0.53913 * t;
}

static double sheen_lambda(double mu, double a)
{
    return mu < 0.5 ? exp(sheen_fit(mu, a)) : exp(2.0 * sheen_fit(0.5, a) - sheen_fit(1.0 - mu, a));
}

static void sheen_distribution_is_normalised(void **state)
{
    (void)state;
    const float rough[] = {0.1f, 0.3f, 0.6f, 1.0f};
    const float white[3] = {1.0f, 1.0f, 1.0f};
    for (int r = 0; r < 4; r++) {
        st_sheen sh = st_sheen_make(white, rough[r]);
        double a = sh.alpha, sum = 0.0;
        const int nz = 4000, nphi = 4;
        for (int i = 0; i < nz; i++)
            for (int j = 0; j < nphi; j++) {
                st_dir h = dir_from((i + 0.5) / nz, 2.0 * PI * (j + 0.5) / nphi);
                double v = 1.0 / ((1.0 + 2.0 * sheen_lambda(h.z, a)) * 4.0 * h.z * h.z);
                sum += st_sheen_lobe(&sh, h, h) / v * h.z;
            }
        sum *= 2.0 * PI / ((double)nz * nphi);
        if (fabs(sum - 1.0) > 2e-3)
            fail_msg("sheen roughness %g: ∫ D n.h dω = %.5f, want 1", rough[r], sum);
    }
}

/* sheen_table.h against the test's own quadrature of the device's lobe:
 * the midpoint rule in (θi, φ) over the whole hemisphere (another grid,
 * spacing and precision than the generator's), at nodes of the table,
 * where the lookup must return the entry itself. */
static void sheen_table_matches_quadrature(void **state)
{
    (void)state;
    const int rows[] = {3, 6, 10, 16, 24, 31}, cols[] = {3, 6, 10, 16, 22, 28, 31};
    const float white[3] = {1.0f, 1.0f, 1.0f};
    const int nt = 1200, nphi = 600;
    for (int a = 0; a < 6; a++)
        for (int c = 0; c < 7; c++) {
            int j = rows[a], i = cols[c];
            float r = (float)j / 31.0f, x = (float)i / 31.0f, mu = x * x;
            float entry = st_sheen_albedo_table[32 * j + i];
            if (fabsf(st_sheen_albedo(r, mu) - entry) > 1e-6f * fmaxf(1.0f, entry))
                fail_msg("row %d, column %d: lookup %.7f, entry %.7f", j, i,
                         st_sheen_albedo(r, mu), entry);
            st_sheen sh = st_sheen_make(white, r);
            st_dir wo = dir_from(mu, 0.0);
            double sum = 0.0;
            for (int t = 0; t < nt; t++) {
                double th = 0.5 * PI * (t + 0.5) / nt;
                for (int k = 0; k < nphi; k++) {
                    st_dir wi = dir_from(cos(th), 2.0 * PI * (k + 0.5) / nphi);
                    sum += st_sheen_lobe(&sh, wo, wi) * wi.z * sin(th);
                }
            }
            sum *= 0.5 * PI / nt * 2.0 * PI / nphi;
            if (fabs(sum - entry) > 2e-3 + 2e-3 * entry)
                fail_msg("sheenRoughness %.3f, cos %.4f: quadrature %.5f, table %.5f", r, mu, sum,
                         entry);
        }
}

/* White furnaces. A sheen over a black Lambertian base reflects its colour
 * times the lobe's albedo, per channel, max3(colour) E in the brightest (E
 * from the table at a node, against the Monte Carlo estimate of the
 * sampled material). Over a white Lambertian base it reflects at most 1,
 * and what the albedo scaling keeps: max3 E(wo) + ∫ max(0, 1 - max3
 * max(E(wo), E(wi))) cos / π dωi (that integral by the midpoint rule in
 * cos θi, through the table), which is 1 less the lobe's energy lost where
 * wi's E exceeds wo's. */
static void sheen_furnace(void **state)
{
    (void)state;
    const float black[3] = {0.0f, 0.0f, 0.0f}, white[3] = {1.0f, 1.0f, 1.0f};
    const float colour[3] = {0.9f, 0.6f, 0.3f};
    const int cols[] = {10, 20, 28}, rows[] = {6, 12, 20, 31};
    for (int a = 0; a < 4; a++)
        for (int c = 0; c < 3; c++) {
            float r = rows[a] / 31.0f, x = cols[c] / 31.0f, mu = x * x;
            st_dir wo = dir_from(mu, 0.4);
            float e = st_sheen_albedo_table[32 * rows[a] + cols[c]];
            st_dielectric d = st_dielectric_make(0.0f, 0.0f, black, 1.5f, 1, 0);
            st_brdf dark = st_brdf_make(black, 0.0f, 1.0f, 0.0f, black, 1.5f, 0.0f);
            st_sheen sh = st_sheen_make(colour, r);
            for (int ch = 0; ch < 3; ch++) {
                double se, got = sampled_energy_layered(&dark, &d, &sh, &no_coat, wo, ch, 400000,
                                                        &se);
                if (fabs(got - colour[ch] * e) > 5.0 * se + 2e-3)
                    fail_msg("sheen %.3f over black, cos %.4f, channel %d: %.5f +- %.5f, want %.5f",
                             r, mu, ch, got, se, colour[ch] * e);
            }
            st_brdf lambert = st_brdf_make(white, 0.0f, 1.0f, 0.0f, white, 1.5f, 0.0f);
            double kept = 0.0;
            const int n = 4000;
            for (int i = 0; i < n; i++) {
                float mi = (float)((i + 0.5) / n);
                double m = fmax(e, st_sheen_albedo(r, mi));
                kept += fmax(0.0, 1.0 - colour[0] * m) * 2.0 * mi / n;
            }
            double want = colour[0] * e + kept, se;
            double got = sampled_energy_layered(&lambert, &d, &sh, &no_coat, wo, 0, 400000, &se);
            if (!(got <= 1.0 + 5.0 * se) || fabs(got - want) > 5.0 * se + 2e-3)
                fail_msg("sheen %.3f over white, cos %.4f: %.5f +- %.5f, want %.5f (<= 1)", r, mu,
                         got, se, want);
            if (rows[a] >= 12 && !(got > 0.9))
                fail_msg("sheen %.3f over white, cos %.4f: %.5f, want close to 1", r, mu, got);
        }
}

/* Without a sheen (black colour) the sheened material is the coated one bit
 * for bit, f, pdf and samples: the kernels take the plain form for lanes
 * without a sheen and the sheened one where some lane has one. */
static void black_sheen_changes_nothing(void **state)
{
    (void)state;
    uint64_t s = 17;
    for (int i = 0; i < 3000; i++) {
        st_dielectric d;
        st_brdf b = glass((float)next_unit(&s), (float)next_unit(&s), (float)next_unit(&s),
                          i % 2 ? (float)next_unit(&s) : 0.0f, 1.5f, &d);
        st_coat cc = st_coat_make(i % 3 ? (float)next_unit(&s) : 0.0f, (float)next_unit(&s));
        const float black[3] = {0.0f, 0.0f, 0.0f};
        st_sheen sh = st_sheen_make(black, (float)next_unit(&s));
        st_dir wo = dir_from(0.01 + 0.99 * next_unit(&s), 2 * PI * next_unit(&s));
        st_dir wi = dir_from(-1.0 + 2.0 * next_unit(&s), 2 * PI * next_unit(&s));
        float u1 = (float)next_unit(&s), u2 = (float)next_unit(&s), u3 = (float)next_unit(&s);
        float f[3], g[3];
        st_coated_eval(&b, &d, &cc, wo, wi, f);
        st_coated_sheened_eval(&b, &d, &sh, &cc, wo, wi, g);
        for (int k = 0; k < 3; k++)
            assert_memory_equal(&f[k], &g[k], sizeof(float));
        float p = st_coated_pdf(&b, &d, &cc, wo, wi), q = st_coated_sheened_pdf(&b, &d, &sh, &cc, wo, wi);
        assert_memory_equal(&p, &q, sizeof(float));
        st_dir a = st_coated_sample(&b, &d, &cc, wo, u1, u2, u3);
        st_dir c = st_coated_sheened_sample(&b, &d, &sh, &cc, wo, u1, u2, u3);
        assert_memory_equal(&a, &c, sizeof a);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ggx_and_visible_normals_are_normalised),
        cmocka_unit_test(ggx_terms_match_their_definitions),
        cmocka_unit_test(anisotropic_terms_match_their_definitions),
        cmocka_unit_test(anisotropy_zero_is_isotropic),
        cmocka_unit_test(brdf_is_reciprocal),
        cmocka_unit_test(albedo_matches_quadrature),
        cmocka_unit_test(specular_zero_is_lambert),
        cmocka_unit_test(white_metal_albedo),
        cmocka_unit_test(anisotropic_white_metal_albedo),
        cmocka_unit_test(pdf_integrates_to_one),
        cmocka_unit_test(sampler_passes_chi_square),
        cmocka_unit_test(fresnel_matches_definition),
        cmocka_unit_test(dielectric_furnace),
        cmocka_unit_test(transmission_mixture_energy),
        cmocka_unit_test(dielectric_is_reciprocal),
        cmocka_unit_test(thin_wall_passes_straight_through),
        cmocka_unit_test(transmission_sampler_passes_chi_square),
        cmocka_unit_test(diffuse_transmission_furnace),
        cmocka_unit_test(diffuse_transmission_is_reciprocal),
        cmocka_unit_test(diffuse_transmission_zero_changes_nothing),
        cmocka_unit_test(dispersed_ior_matches_cauchy),
        cmocka_unit_test(coat_furnace),
        cmocka_unit_test(sheen_distribution_is_normalised),
        cmocka_unit_test(sheen_table_matches_quadrature),
        cmocka_unit_test(sheen_furnace),
        cmocka_unit_test(black_sheen_changes_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
