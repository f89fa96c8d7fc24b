/* test_thin_film.c — KHR_materials_iridescence's thin-film Fresnel
 * (kernels/integrator/thin_film.h), run here on the host (the device's own
 * code), and its place in the BRDF (bsdf.h).
 *
 * The reference is the formula of the specification (Belcour & Barla 2017
 * adapted to RGB; the header names the two departures at zero thickness)
 * written again here in double, by complex phasors: the harmonic m of the
 * Airy sum is 2 C_m Re(e^(i m φ) Ŝ(m OPD)), with Ŝ the XYZ matching
 * functions' Gaussian fits as e^(i c p) e^(-s p²). The film must vanish at
 * zero thickness (the base's Schlick reflectance), be 1 past its critical
 * angle, and change nothing at weight 0. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <complex.h>
#include <math.h>

#include "bsdf.h"

#define PI 3.14159265358979323846

/* The fits' phasor sums per XYZ component at phase p with shifts sh[3],
 * then Rec. 709 RGB (the sRGB primaries' XYZ-to-RGB matrix). */
static void reference_sensitivity(double opd, const double *sh, double *rgb)
{
    static const double v[3] = {5.4856e-13, 4.4201e-13, 5.2481e-13};
    static const double c[3] = {1.6810e+06, 1.7953e+06, 2.2084e+06};
    static const double s[3] = {4.3278e+09, 9.3046e+09, 6.6121e+09};
    static const double m[3][3] = {{3.2404542, -1.5371385, -0.4985314},
                                   {-0.9692660, 1.8760108, 0.0415560},
                                   {0.0556434, -0.2040259, 1.0572252}};
    double p = 2.0 * PI * opd * 1e-9, xyz[3];
    for (int k = 0; k < 3; k++) {
        double complex z = v[k] * sqrt(2.0 * PI * s[k]) * cexp(I * (c[k] * p + sh[k])) *
                           exp(-s[k] * p * p);
        if (k == 0)
            z += 9.7470e-14 * sqrt(2.0 * PI * 4.5282e+09) * cexp(I * (2.2399e+06 * p + sh[0])) *
                 exp(-4.5282e+09 * p * p);
        xyz[k] = creal(z) / 1.0685e-7;
    }
    for (int r = 0; r < 3; r++)
        rgb[r] = m[r][0] * xyz[0] + m[r][1] * xyz[1] + m[r][2] * xyz[2];
}

/* The film's reflectance from the formula, in double. */
static void reference_film(double n2, double d, double cos1, const double *f0, double *out)
{
    double t = fmin(fmax(d / 0.03, 0.0), 1.0);
    n2 = 1.0 + (n2 - 1.0) * t * t * (3.0 - 2.0 * t);
    double sin2 = (1.0 - cos1 * cos1) / (n2 * n2);
    if (sin2 >= 1.0) {
        out[0] = out[1] = out[2] = 1.0;
        return;
    }
    double cos2 = sqrt(1.0 - sin2);
    double rs_ = (cos1 - n2 * cos2) / (cos1 + n2 * cos2);
    double rp_ = (n2 * cos1 - cos2) / (n2 * cos1 + cos2);
    double r12 = 0.5 * (rs_ * rs_ + rp_ * rp_), t121 = 1.0 - r12;
    /* phase shifts of π: φ12 off a denser film, φ21 = π - φ12, φ23 off a denser base */
    double opd = 2.0 * n2 * d * cos2, phi12 = n2 < 1.0 ? PI : 0.0, phi21 = PI - phi12;
    double r23[3], shift[3];
    for (int k = 0; k < 3; k++) {
        double q = sqrt(fmin(fmax(f0[k], 0.0), 0.9999)), n3 = (1.0 + q) / (1.0 - q);
        double r1 = pow((n3 - n2) / (n3 + n2), 2.0);
        r23[k] = r1 + (1.0 - r1) * pow(1.0 - cos2, 5.0);
        shift[k] = phi21 + (n3 < n2 ? PI : 0.0);
    }
    double s1[3], s2[3], sh2[3] = {2 * shift[0], 2 * shift[1], 2 * shift[2]};
    reference_sensitivity(opd, shift, s1);
    reference_sensitivity(2.0 * opd, sh2, s2);
    for (int k = 0; k < 3; k++) {
        double r123 = fmin(r12 * r23[k], 0.9999);
        double rs = t121 * t121 * r23[k] / (1.0 - r123);
        double c1 = (rs - t121) * sqrt(r123), c2 = (rs - t121) * r123;
        out[k] = fmax(r12 + rs + 2.0 * c1 * s1[k] + 2.0 * c2 * s2[k], 0.0);
    }
}

/* st_thin_film against the reference over films of ior 1.2 .. 2, 0 ..
 * 1200 nm, over dielectric and metallic bases, at cos θ 0.05 .. 1 (to
 * 1e-5: single against double precision). */
static void thin_film_matches_the_formula(void **state)
{
    (void)state;
    static const double iors[] = {1.2, 1.33, 1.5, 2.0};
    static const double thick[] = {0.0, 0.01, 50.0, 100.0, 250.0, 400.0, 700.0, 1200.0};
    /* not F0 0.04 (n3 1.5) under a film of ior 1.5: φ23 jumps by π where n3 = n2, and
     * single precision may fall on either side */
    static const double bases[][3] = {{0.05, 0.05, 0.05}, {0.95, 0.64, 0.54}, {0.2, 0.5, 0.9}};
    double worst = 0.0;
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 8; b++)
            for (int c = 0; c < 3; c++)
                for (int j = 0; j <= 19; j++) {
                    double cos1 = 0.05 + 0.05 * j, want[3];
                    reference_film(iors[a], thick[b], cos1, bases[c], want);
                    float f0[3] = {(float)bases[c][0], (float)bases[c][1], (float)bases[c][2]};
                    float got[3];
                    st_thin_film((float)iors[a], (float)thick[b], (float)cos1, f0, got);
                    for (int k = 0; k < 3; k++) {
                        worst = fmax(worst, fabs(got[k] - want[k]));
                        if (fabs(got[k] - want[k]) > 1e-5)
                            fail_msg("ior %g, %g nm, base %d, cos %g, channel %d: %.6f, "
                                     "formula %.6f",
                                     iors[a], thick[b], c, cos1, k, got[k], want[k]);
                    }
                }
    print_message("thin film: largest difference from the formula %.2e\n", worst);
}

/* No film is no film: at thickness 0 the reflectance is the base's
 * Schlick reflectance F0 + (1 - F0)(1 - cos)^5 (to 1e-6), whatever the
 * film's ior; and a film does make colours (a 300 nm film of ior 1.5 over
 * a grey base of F0 0.5 differs between channels by more than 0.05). */
static void zero_thickness_is_the_base(void **state)
{
    (void)state;
    for (int j = 0; j <= 20; j++) {
        float cos1 = 0.05f * (float)j, f0[3] = {0.04f, 0.5f, 0.9f}, got[3];
        st_thin_film(1.8f, 0.0f, cos1, f0, got);
        for (int k = 0; k < 3; k++) {
            double want = f0[k] + (1.0 - f0[k]) * pow(1.0 - cos1, 5.0);
            if (fabs(got[k] - want) > 1e-6)
                fail_msg("cos %g, F0 %g: %.7f, Schlick %.7f", cos1, f0[k], got[k], want);
        }
    }
    float grey[3] = {0.5f, 0.5f, 0.5f}, out[3];
    st_thin_film(1.5f, 300.0f, 0.8f, grey, out);
    double spread = fmax(fmax(out[0], out[1]), out[2]) - fmin(fmin(out[0], out[1]), out[2]);
    if (!(spread > 0.05))
        fail_msg("a 300 nm film: (%g, %g, %g), no colour", out[0], out[1], out[2]);
}

/* Past the film's critical angle (a film of ior below 1: sin θ2 > 1) the
 * film reflects everything. */
static void total_internal_reflection_reflects_all(void **state)
{
    (void)state;
    float f0[3] = {0.04f, 0.3f, 0.9f}, out[3];
    st_thin_film(0.8f, 200.0f, 0.3f, f0, out); /* sin² θ2 = 0.91 / 0.64 > 1 */
    for (int k = 0; k < 3; k++)
        assert_true(out[k] == 1.0f);
}

static st_brdf material(float c, float m, float r)
{
    const float base[3] = {c, 0.8f * c, 0.5f * c}, white[3] = {1.0f, 1.0f, 1.0f};
    return st_brdf_make(base, m, r, 1.0f, white, 1.5f, 0.0f);
}

/* In the BRDF: weight 0 changes nothing, bit for bit; with a film the BRDF
 * stays reciprocal (its Fresnel depends on wo.h = wi.h) and its specular
 * lobe's Fresnel is the mix of the parts' Schlick and film reflectances
 * by the weight (checked against st_thin_film at wo = wi = the normal,
 * where h = n, over a metal and a dielectric). */
static void iridescent_brdf(void **state)
{
    (void)state;
    uint64_t s = 5;
    for (int i = 0; i < 500; i++) {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        float u = (float)(s >> 40) / 16777216.0f;
        st_brdf a = material(0.3f + 0.6f * u, u, 0.2f + 0.7f * u), b = a;
        st_brdf_iridescent(&b, 0.0f, 1.3f, 400.0f);
        st_dir wo = st_lv3_make(0.3f * u, -0.2f, 0.9f), wi = st_lv3_make(-0.5f, 0.4f * u, 0.7f);
        wo = st_dir_normalize(wo);
        wi = st_dir_normalize(wi);
        float fa[3], fb[3];
        st_brdf_eval(&a, wo, wi, fa);
        st_brdf_eval(&b, wo, wi, fb);
        assert_memory_equal(fa, fb, sizeof fa);
        st_brdf c = a;
        st_brdf_iridescent(&c, u, 1.3f, 100.0f + 500.0f * u);
        st_brdf_eval(&c, wo, wi, fa);
        st_brdf_eval(&c, wi, wo, fb);
        for (int k = 0; k < 3; k++)
            if (fabsf(fa[k] - fb[k]) > 1e-5f * fmaxf(1.0f, fabsf(fa[k])))
                fail_msg("f(wo, wi) = %g but f(wi, wo) = %g", fa[k], fb[k]);
    }
    for (int metal = 0; metal < 2; metal++) {
        st_brdf b = material(0.9f, (float)metal, 0.5f);
        st_brdf_iridescent(&b, 0.7f, 1.3f, 350.0f);
        float fr[3], film[3], s0 = st_schlick(1.0f);
        st_brdf_fresnel(&b, s0, 1.0f, fr);
        st_thin_film(1.3f, 350.0f, 1.0f, metal ? b.f0m : b.f0d, film);
        for (int k = 0; k < 3; k++) {
            double base = metal ? b.f0m[k] : b.f0d[k];
            double want = (1.0 - 0.7) * base + 0.7 * film[k];
            if (fabs(fr[k] - want) > 1e-6)
                fail_msg("%s, channel %d: F %.6f, want %.6f", metal ? "metal" : "dielectric", k,
                         fr[k], want);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(thin_film_matches_the_formula),
        cmocka_unit_test(zero_thickness_is_the_base),
        cmocka_unit_test(total_internal_reflection_reflects_all),
        cmocka_unit_test(iridescent_brdf),
    };
    return cmocka_run_group_tests_name("thin_film", tests, NULL, NULL);
}
