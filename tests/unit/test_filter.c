/* test_filter.c — guards src/filter/filter.c, the filter module (st_filter.h): the
 * integral, the FIS table, the profile, the frequency response, the
 * parameter check, names and defaults. (test_filter_kernels.c guards the evaluation
 * f(x) in kernels/film/filters.h.)
 *
 * Expected values are derived here, independently of the module:
 *   - integrals by a composite Simpson rule written below, 2^16 intervals,
 *     which puts every kink (triangle at 0, mitchell at ±r/2) on an interval
 *     end, and by closed forms: box 2r; triangle r^2 (f = r - |x|); gaussian
 *     σ√(2π) erf(r/(σ√2)) - 2r e^{-r²/2σ²}; mitchell and catmull-rom r/2
 *     (k_{B,C} integrates to 1 over t in [-2, 2], x = r t / 2);
 *   - transforms by closed forms: box 2r sinc(2rω) = sin(2πrω)/(πω);
 *     triangle (sin(πrω)/(πω))^2;
 *   - FIS bin masses by Simpson over each bin of |f| (64 intervals per bin).
 * Tolerances are stated at each test; the module computes f in float, so
 * nothing better than ~1e-7 relative is expected. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "st_filter.h"
#include "filters.h"

static const double PI = 3.14159265358979323846;

/* Every kind with a few parameter sets. */
static size_t cases(st_filter *out)
{
    size_t n = 0;
    const float radii[] = {0.5f, 1.0f, 2.0f, 3.7f};
    for (st_u32 k = 0; k < ST_FILTER_COUNT; k++)
        for (size_t i = 0; i < 4; i++) {
            st_filter f = st_filter_default(k);
            f.radius = radii[i];
            f.tau = k == ST_FILTER_LANCZOS ? radii[i] : f.tau;
            out[n++] = f;
        }
    st_filter g = st_filter_default(ST_FILTER_GAUSSIAN);
    g.sigma = 0.25f;
    out[n++] = g;
    st_filter m = st_filter_default(ST_FILTER_MITCHELL);
    m.b = 0.0f;
    m.c = 0.75f;
    out[n++] = m;
    st_filter l = st_filter_default(ST_FILTER_LANCZOS);
    l.tau = 1.5f;
    out[n++] = l;
    return n;
}

/* f just inside x: an end of [-r, r] takes the limit from inside (the same
 * as f(±r) for every kind, the support being closed). */
static double inside(const st_filter *f, double x, double toward)
{
    return st_filter_eval_1d(f, nextafterf((float)x, (float)toward));
}

/* ∫_a^b g(f(x)) cos(2πωx) dx by composite Simpson with n (even) intervals;
 * absolute: |f|. The ends take f's limit from inside [a, b]. */
static double simpson(const st_filter *f, double a, double b, int n, double omega, int absolute)
{
    double h = (b - a) / n, sum = 0.0;
    for (int i = 0; i <= n; i++) {
        double x = a + i * h;
        double v = i == 0 ? inside(f, x, b) : i == n ? inside(f, x, a) : st_filter_eval_1d(f, (float)x);
        double w = i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0;
        sum += w * (absolute ? fabs(v) : v) * cos(2.0 * PI * omega * x);
    }
    return sum * h / 3.0;
}

static double abs_integral(const st_filter *f)
{
    return simpson(f, -f->radius, f->radius, 1 << 16, 0.0, 1);
}

/* Against Simpson for every case: 1e-6 of ∫|f| (measured: < 3e-8). */
static void filter_integral_matches_simpson(void **state)
{
    (void)state;
    st_filter list[64];
    size_t n = cases(list);
    for (size_t i = 0; i < n; i++) {
        const st_filter *f = &list[i];
        double want = simpson(f, -f->radius, f->radius, 1 << 16, 0.0, 0);
        double got = st_filter_integral(f);
        if (!(fabs(got - want) <= 1e-6 * abs_integral(f)))
            fail_msg("%s r=%g: integral %.12g, simpson %.12g", st_filter_names[f->kind],
                     (double)f->radius, got, want);
    }
}

/* Closed forms, 1e-6 relative (midpoint rule with 2^16 intervals over float
 * weights). */
static void filter_integral_matches_closed_forms(void **state)
{
    (void)state;
    float radii[] = {0.5f, 1.0f, 2.0f, 3.7f};
    for (int q = 0; q < 4; q++) {
        double r = radii[q];
        st_filter f = st_filter_default(ST_FILTER_BOX);
        f.radius = radii[q];
        assert_true(fabs(st_filter_integral(&f) - 2 * r) < 1e-6 * 2 * r);
        f = st_filter_default(ST_FILTER_TRIANGLE);
        f.radius = radii[q];
        assert_true(fabs(st_filter_integral(&f) - r * r) < 1e-6 * r * r);
        f = st_filter_default(ST_FILTER_GAUSSIAN);
        f.radius = radii[q];
        f.sigma = 0.6f;
        double sg = f.sigma;
        double g = sg * sqrt(2 * PI) * erf(r / (sg * sqrt(2.0))) - 2 * r * exp(-r * r / (2 * sg * sg));
        assert_true(fabs(st_filter_integral(&f) - g) < 1e-6 * g);
        f = st_filter_default(ST_FILTER_MITCHELL);
        f.radius = radii[q];
        assert_true(fabs(st_filter_integral(&f) - r / 2) < 1e-6 * r);
        f = st_filter_default(ST_FILTER_CATMULL_ROM);
        f.radius = radii[q];
        assert_true(fabs(st_filter_integral(&f) - r / 2) < 1e-6 * r);
    }
}

/* The FIS table: starts at 0, ends at 1 exactly, never decreases, and bin i
 * holds the share of ∫|f| over bin i. The module samples |f| once per bin, so
 * a bin where f changes sign (lanczos) or bends sharply is off by O(h^2 f');
 * tolerance 5e-5 of the total per bin (measured: < 1.2e-5). */
static void filter_fis_cdf_matches_bin_masses(void **state)
{
    (void)state;
    st_filter list[64];
    size_t n = cases(list);
    float cdf[ST_FIS_BINS + 1];
    for (size_t c = 0; c < n; c++) {
        const st_filter *f = &list[c];
        st_filter_fis_cdf(f, cdf);
        assert_true(cdf[0] == 0.0f);
        assert_true(cdf[ST_FIS_BINS] == 1.0f);
        double r = f->radius, h = 2.0 * r / ST_FIS_BINS, total = abs_integral(f), worst = 0.0;
        for (st_u32 i = 0; i < ST_FIS_BINS; i++) {
            if (!(cdf[i + 1] >= cdf[i]))
                fail_msg("%s r=%g: cdf decreases at bin %u", st_filter_names[f->kind], r, i);
            double want = simpson(f, -r + i * h, -r + (i + 1) * h, 64, 0.0, 1) / total;
            worst = fmax(worst, fabs((double)cdf[i + 1] - cdf[i] - want));
        }
        if (!(worst <= 5e-5))
            fail_msg("%s r=%g: bin mass off by %.3g", st_filter_names[f->kind], r, worst);
    }
}

/* The profile is f itself at evenly spaced x from -r to r, exactly. */
static void filter_profile_samples_f(void **state)
{
    (void)state;
    st_filter list[64];
    size_t n = cases(list);
    double x[101], y[101];
    for (size_t c = 0; c < n; c++) {
        const st_filter *f = &list[c];
        st_filter_profile(f, 101, x, y);
        assert_true(x[0] == -(double)f->radius && x[100] == (double)f->radius);
        /* closed support: the ends are f(±r) (the box's 1) */
        assert_true(y[0] == y[100]);
        assert_true(f->kind != ST_FILTER_BOX || y[0] == 1.0);
        for (int i = 0; i < 101; i++) {
            assert_true(fabs(x[i] - (-f->radius + 2.0 * f->radius * i / 100)) < 1e-12);
            assert_true(y[i] == st_filter_eval_1d(f, (float)x[i]));
        }
    }
}

/* F(0) is the integral (Simpson against midpoint: 1e-6 of ∫|f|), and the
 * normalised response starts at 1. */
static void filter_transform_at_zero_is_integral(void **state)
{
    (void)state;
    st_filter list[64];
    size_t n = cases(list);
    for (size_t c = 0; c < n; c++) {
        const st_filter *f = &list[c];
        double dc = st_filter_transform(f, 0.0), integral = st_filter_integral(f);
        if (!(fabs(dc - integral) <= 1e-6 * abs_integral(f)))
            fail_msg("%s r=%g: F(0) %.12g, integral %.12g", st_filter_names[f->kind],
                     (double)f->radius, dc, integral);
        double w = 0.0, mag;
        st_filter_response(f, 1, &w, &mag);
        assert_true(fabs(mag - 1.0) < 1e-12);
    }
}

/* Box: F(ω) = sin(2πrω)/(πω); triangle: (sin(πrω)/(πω))^2; at 0..3 cycles
 * per pixel, 1e-6 absolute (Simpson with 4096 intervals, float weights). */
static void filter_transform_matches_closed_forms(void **state)
{
    (void)state;
    const float radii[] = {0.5f, 1.0f, 1.5f, 2.0f};
    for (int q = 0; q < 4; q++) {
        double r = radii[q];
        st_filter box = st_filter_default(ST_FILTER_BOX), tri = st_filter_default(ST_FILTER_TRIANGLE);
        box.radius = tri.radius = radii[q];
        for (int i = 0; i <= 60; i++) {
            double w = 0.05 * i;
            double fb = w == 0.0 ? 2 * r : sin(2 * PI * r * w) / (PI * w);
            double st = w == 0.0 ? r : sin(PI * r * w) / (PI * w);
            double gb = st_filter_transform(&box, w), gt = st_filter_transform(&tri, w);
            if (!(fabs(gb - fb) < 1e-6) || !(fabs(gt - st * st) < 1e-6))
                fail_msg("r=%g w=%g: box %.9g (want %.9g), triangle %.9g (want %.9g)", r, w, gb,
                         fb, gt, st * st);
            double mag;
            st_filter_response(&box, 1, &w, &mag);
            assert_true(fabs(mag - fabs(fb) / (2 * r)) < 1e-6);
        }
    }
}

/* One bad field at a time: the check fails with ST_ERR_USAGE and names it
 * (the field, not a command-line option). */
static void expect_rejected(st_filter f, float max_radius, const char *needle)
{
    st_error err = {0};
    if (st_filter_check(&f, max_radius, &err) != ST_ERR_USAGE || err.status != ST_ERR_USAGE)
        fail_msg("%s: accepted", needle);
    if (!strstr(err.msg, needle) || strstr(err.msg, "--"))
        fail_msg("message '%s' does not name '%s'", err.msg, needle);
}

static void filter_check_rejects_each_bad_parameter(void **state)
{
    (void)state;
    for (st_u32 k = 0; k < ST_FILTER_COUNT; k++) { /* every default renders */
        st_filter f = st_filter_default(k);
        st_error err = {0};
        assert_int_equal(st_filter_check(&f, ST_FILTER_MAX_RADIUS, &err), ST_OK);
    }
    st_filter f = st_filter_default(ST_FILTER_BOX);
    f.kind = ST_FILTER_COUNT;
    expect_rejected(f, 8.0f, "filter kind 7");
    const float bad_radii[] = {0.0f, -1.0f, NAN, INFINITY, 9.0f, 0.06f};
    for (int i = 0; i < 6; i++) {
        f = st_filter_default(ST_FILTER_TRIANGLE);
        f.radius = bad_radii[i];
        expect_rejected(f, 8.0f, "filter radius");
    }
    f.radius = 9.0f;
    expect_rejected(f, 8.0f, "filter radius 9: must be in [0.0625, 8]");
    st_error err = {0};
    assert_int_equal(st_filter_check(&f, 64.0f, &err), ST_OK); /* the caller's limit */
    const float bad_positive[] = {0.0f, -0.5f, NAN, INFINITY};
    for (int i = 0; i < 4; i++) {
        st_filter g = st_filter_default(ST_FILTER_GAUSSIAN), l = st_filter_default(ST_FILTER_LANCZOS);
        g.sigma = l.tau = bad_positive[i];
        expect_rejected(g, 8.0f, "filter sigma");
        expect_rejected(l, 8.0f, "filter tau");
        st_filter b = st_filter_default(ST_FILTER_BOX); /* box reads neither */
        b.sigma = b.tau = bad_positive[i];
        assert_int_equal(st_filter_check(&b, 8.0f, &err), ST_OK);
    }
    st_filter m = st_filter_default(ST_FILTER_MITCHELL);
    m.b = NAN;
    expect_rejected(m, 8.0f, "filter b");
    m = st_filter_default(ST_FILTER_MITCHELL);
    m.c = -INFINITY;
    expect_rejected(m, 8.0f, "filter c");
    /* the documented ranges, just outside each end (values of the report) */
    m = st_filter_default(ST_FILTER_MITCHELL);
    m.b = -1572861.0f;
    expect_rejected(m, 8.0f, "filter b -1.57286e+06: must be in [0, 1]");
    m.b = 0.5f;
    m.c = 1e30f;
    expect_rejected(m, 8.0f, "filter c 1e+30: must be in [0, 1]");
    m.c = -0.01f;
    expect_rejected(m, 8.0f, "filter c -0.01");
    st_filter g = st_filter_default(ST_FILTER_GAUSSIAN);
    g.sigma = 17.0f;
    expect_rejected(g, 8.0f, "filter sigma 17: must be in [0.015625, 16]");
    g.sigma = 0.015f;
    expect_rejected(g, 8.0f, "filter sigma 0.015");
    st_filter l = st_filter_default(ST_FILTER_LANCZOS);
    l.tau = 65.0f;
    expect_rejected(l, 8.0f, "filter tau 65: must be in [0.0625, 64]");
    l.tau = 0.06f;
    expect_rejected(l, 8.0f, "filter tau 0.06");
}

/* At every corner of the accepted ranges (radius, B, C, σ, τ at their ends)
 * the check passes and the FIS table is finite, starts at 0, ends at 1 and
 * never decreases: ∫|f| > 0 over the bin centres. A Gaussian with σ = 1e-4 at
 * r = 8 (outside the range) is 0 at every bin centre (|x| >= r/512, e^-12000),
 * the NaN table the ranges exclude. */
static void filter_fis_cdf_finite_at_range_corners(void **state)
{
    (void)state;
    const float radii[2] = {ST_FILTER_MIN_RADIUS, ST_FILTER_MAX_RADIUS};
    const float bc[2] = {ST_FILTER_BC_MIN, ST_FILTER_BC_MAX};
    const float sigma[2] = {ST_FILTER_SIGMA_MIN, ST_FILTER_SIGMA_MAX};
    const float tau[2] = {ST_FILTER_TAU_MIN, ST_FILTER_TAU_MAX};
    static float cdf[ST_FIS_BINS + 1];
    for (st_u32 k = 0; k < ST_FILTER_COUNT; k++)
        for (int corner = 0; corner < 16; corner++) {
            st_filter f = st_filter_default(k);
            f.radius = radii[corner & 1];
            f.b = bc[(corner >> 1) & 1];
            f.c = bc[(corner >> 2) & 1];
            f.sigma = sigma[(corner >> 3) & 1];
            f.tau = tau[(corner >> 3) & 1];
            st_error err = {0};
            assert_int_equal(st_filter_check(&f, ST_FILTER_MAX_RADIUS, &err), ST_OK);
            st_filter_fis_cdf(&f, cdf);
            assert_true(cdf[0] == 0.0f && cdf[ST_FIS_BINS] == 1.0f);
            for (st_u32 i = 1; i <= ST_FIS_BINS; i++)
                if (!isfinite(cdf[i]) || cdf[i] < cdf[i - 1])
                    fail_msg("%s corner %d: cdf[%u] = %g", st_filter_names[k], corner, i,
                             (double)cdf[i]);
        }
    st_filter g = st_filter_default(ST_FILTER_GAUSSIAN);
    g.radius = 8.0f;
    g.sigma = 1e-4f;
    st_filter_fis_cdf(&g, cdf);
    assert_true(isnan(cdf[1])); /* why the range exists */
}

static void filter_names_and_parameters(void **state)
{
    (void)state;
    for (st_u32 k = 0; k < ST_FILTER_COUNT; k++) {
        assert_int_equal(st_filter_lookup(st_filter_names[k]), (int)k);
        assert_int_equal(st_filter_default(k).kind, k);
        assert_true(st_filter_default(k).radius > 0.0f);
    }
    assert_int_equal(st_filter_lookup("sinc"), -1);
    assert_int_equal(st_filter_lookup(""), -1);
    assert_int_equal(st_filter_parameters(ST_FILTER_MITCHELL), ST_FILTER_USES_BC);
    assert_int_equal(st_filter_parameters(ST_FILTER_GAUSSIAN), ST_FILTER_USES_SIGMA);
    assert_int_equal(st_filter_parameters(ST_FILTER_LANCZOS), ST_FILTER_USES_TAU);
    assert_int_equal(st_filter_parameters(ST_FILTER_CATMULL_ROM), 0);
    assert_true(st_filter_default(ST_FILTER_LANCZOS).tau == st_filter_default(ST_FILTER_LANCZOS).radius);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(filter_integral_matches_simpson),
        cmocka_unit_test(filter_integral_matches_closed_forms),
        cmocka_unit_test(filter_fis_cdf_matches_bin_masses),
        cmocka_unit_test(filter_profile_samples_f),
        cmocka_unit_test(filter_transform_at_zero_is_integral),
        cmocka_unit_test(filter_transform_matches_closed_forms),
        cmocka_unit_test(filter_check_rejects_each_bad_parameter),
        cmocka_unit_test(filter_fis_cdf_finite_at_range_corners),
        cmocka_unit_test(filter_names_and_parameters),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
