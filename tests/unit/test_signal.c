/* test_signal.c — guards src/lab/signal.c, the 1-D sampling and reconstruction
 * laboratory, against the lecture's definitions computed here independently
 * (brute-force sums, closed forms), with these tolerances:
 *
 * - Ideal sinc of a band-limited sine (f < 1/(2T)): the sum runs over a window
 *   of M samples beyond each end of [0, L). The part left out is
 *   (sin(πφ)/π) Σ_i (-1)^i f(x_i)/(u - i) over |i| > M: an oscillating series
 *   of frequency |fT ± 1/2| whose terms fall as 1/(π|u - i|); summed by parts
 *   it is at most about 1/(π^2 M (1/2 - fT)). The test demands max |error|
 *   below that bound (M = 16384: 3.1e-5 at fT = 0.3, 1.2e-4 at fT = 0.45);
 *   measured: 3.2e-6 and 3.4e-5.
 * - Alias: the dominant frequency of the reconstruction of a sine with
 *   f > 1/(2T) is min_k |f - k/T| (brute force over k) within one DFT bin 1/L.
 * - Gibbs: sinc and lanczos (radius 3) overshoot a step by more than 5 %
 *   (max > 1.05 within 4T of the edge; the continuous Gibbs overshoot is 9 %);
 *   box and gaussian have no negative weights, so their weighted average stays
 *   within [0, 1] (checked to 1e-6) and blurs: the 10-90 % rise is wider than
 *   lanczos' (box radius T: it averages two samples; a box of radius T/2 is
 *   nearest-neighbour, a staircase with no rise at all).
 * - Constants: the weighted average Σ r c / Σ r is c to rounding (1e-12) for
 *   every filter; the truncated sinc sum of a constant misses by at most
 *   (1/π)(1/d_left + 1/d_right) (alternating tails, each bounded by its first
 *   term), d the distances (in samples) to the window's ends.
 * - Spectra: a Hann-windowed sine on bin k0 reads exactly 1/2 at k0 and 1/4 at
 *   k0 ± 1 (the window's DFT is 1/2, -1/4, -1/4), to 1e-12. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "st_render.h"
#include "st_signal.h"
#include "filters.h"

#define PI 3.14159265358979323846

/* ---- helpers ------------------------------------------------------------------------ */

static st_signal_options sine_options(double f, double spacing, double length)
{
    st_signal_options o;
    memset(&o, 0, sizeof o);
    o.length = length;
    o.spacing = spacing;
    o.fn.kind = ST_SIGNAL_SINE;
    o.fn.freq = f;
    o.recon.sinc = 1;
    return o;
}

static st_signal_options step_options(double edge, int sinc, st_u32 filter)
{
    st_signal_options o;
    memset(&o, 0, sizeof o);
    o.length = 64.0;
    o.spacing = 1.0;
    o.fn.kind = ST_SIGNAL_STEP;
    o.fn.edge = edge;
    o.recon.sinc = sinc;
    if (!sinc)
        o.recon.filter = st_filter_default(filter);
    return o;
}

static void build(const st_signal_options *o, st_signal_result *r)
{
    st_error err = {0};
    st_status s = st_signal_build(o, r, &err);
    if (s != ST_OK)
        fail_msg("st_signal_build: %s", err.msg);
}

/* Extremes of the reconstruction within `reach` of x = c. */
static void extremes_near(const st_signal_result *r, double c, double reach, double *lo,
                          double *hi)
{
    *lo = INFINITY;
    *hi = -INFINITY;
    for (st_u32 j = 0; j < r->points; j++)
        if (fabs(r->x[j] - c) <= reach) {
            *lo = fmin(*lo, r->reconstruction[j]);
            *hi = fmax(*hi, r->reconstruction[j]);
        }
}

/* Distance between the first crossings of 0.1 and 0.9 (linear interpolation
 * between dense points), searched within 8 samples of the edge. */
static double rise_10_90(const st_signal_result *r, double edge)
{
    double x10 = NAN, x90 = NAN;
    for (st_u32 j = 1; j < r->points; j++) {
        if (fabs(r->x[j] - edge) > 8.0)
            continue;
        double a = r->reconstruction[j - 1], b = r->reconstruction[j];
        double h = r->x[j] - r->x[j - 1];
        if (isnan(x10) && a < 0.1 && b >= 0.1)
            x10 = r->x[j - 1] + (0.1 - a) / (b - a) * h;
        if (isnan(x90) && a < 0.9 && b >= 0.9)
            x90 = r->x[j - 1] + (0.9 - a) / (b - a) * h;
    }
    return x90 - x10;
}

static double brute_alias(double f, double spacing)
{
    double best = INFINITY;
    for (int k = 0; k <= 64; k++)
        best = fmin(best, fabs(f - k / spacing));
    return best;
}

/* ---- functions --------------------------------------------------------------------- */

static void eval_matches_definitions(void **state)
{
    (void)state;
    st_signal_function fn;
    memset(&fn, 0, sizeof fn);
    fn.kind = ST_SIGNAL_STEP;
    fn.edge = 2.5;
    assert_true(st_signal_eval(&fn, 2.5) == 1.0);
    assert_true(st_signal_eval(&fn, nextafter(2.5, 0.0)) == 0.0);
    assert_true(st_signal_eval(&fn, -100.0) == 0.0);

    fn.kind = ST_SIGNAL_SQUARE;
    fn.freq = 0.25; /* period 4: +1 on [0, 2), -1 on [2, 4) */
    assert_true(st_signal_eval(&fn, 0.0) == 1.0);
    assert_true(st_signal_eval(&fn, 1.9) == 1.0);
    assert_true(st_signal_eval(&fn, 2.1) == -1.0);
    assert_true(st_signal_eval(&fn, -0.5) == -1.0);
    fn.phase = PI; /* half a period later */
    assert_true(st_signal_eval(&fn, 0.1) == -1.0);

    fn.kind = ST_SIGNAL_SINES;
    fn.phase = 0.0;
    fn.freq_count = 3;
    fn.freqs[0] = 0.1, fn.freqs[1] = 0.2, fn.freqs[2] = 0.35;
    for (double x = -3.0; x < 3.0; x += 0.37) {
        double want = (sin(2 * PI * 0.1 * x) + sin(2 * PI * 0.2 * x) + sin(2 * PI * 0.35 * x)) / 3;
        assert_true(fabs(st_signal_eval(&fn, x) - want) < 1e-14);
    }

    /* chirp: the phase's derivative / 2π is f0 + (f1 - f0) x / L */
    fn.kind = ST_SIGNAL_CHIRP;
    fn.f0 = 0.05, fn.f1 = 0.45, fn.length = 40.0;
    for (double x = 1.0; x < 40.0; x += 3.3) {
        double want = 0.05 + 0.4 * x / 40.0;
        double ph = 2 * PI * (0.05 * x + 0.2 * x * x / 40.0); /* written out */
        assert_true(fabs(st_signal_eval(&fn, x) - sin(ph)) < 1e-12);
        double h = 1e-4, a = 0.05 * (x - h) + 0.2 * (x - h) * (x - h) / 40.0,
               b = 0.05 * (x + h) + 0.2 * (x + h) * (x + h) / 40.0;
        assert_true(fabs((b - a) / (2 * h) - want) < 1e-9);
    }
    fn.f1 = fn.f0; /* a chirp of constant frequency is a sine */
    st_signal_function s = {.kind = ST_SIGNAL_SINE, .freq = 0.05};
    for (double x = 0.0; x < 40.0; x += 1.7)
        assert_true(fabs(st_signal_eval(&fn, x) - st_signal_eval(&s, x)) < 1e-12);
}

static void alias_frequency_matches_brute_force(void **state)
{
    (void)state;
    double spacings[] = {1.0, 0.5, 0.25, 2.0 / 3.0};
    for (int t = 0; t < 4; t++)
        for (double f = 0.0; f < 8.0; f += 0.0173) {
            double a = st_signal_alias_frequency(f, spacings[t]);
            assert_true(fabs(a - brute_alias(f, spacings[t])) < 1e-12);
            assert_true(a <= 0.5 / spacings[t] + 1e-12); /* folds into [0, Nyquist] */
        }
}

/* ---- reconstruction: definitions ---------------------------------------------------
 * Filter weights are floats (the kernel's own st_filter_eval_1d): the same
 * offset computed two ways in double may round to adjacent floats, 6e-8
 * apart, so brute-force comparisons of filter sums allow 1e-6. */

static void sinc_matches_direct_sum(void **state)
{
    (void)state;
    double v[50];
    srand(7);
    for (int i = 0; i < 50; i++)
        v[i] = rand() / (double)RAND_MAX - 0.5;
    st_signal_samples s = {-3.0, 0.5, 50, v, NULL};
    st_signal_filter r = {.sinc = 1};
    double x[200], out[200];
    for (int j = 0; j < 200; j++)
        x[j] = -10.0 + 0.1234 * j; /* inside, outside, on samples (x = -3 + 0.5 i) */
    x[0] = -3.0 + 0.5 * 17;       /* exactly on sample 17 */
    assert_int_equal(st_signal_reconstruct(&s, &r, x, 200, out, NULL, NULL), ST_OK);
    for (int j = 0; j < 200; j++) {
        double want = 0.0;
        for (int i = 0; i < 50; i++) {
            double u = (x[j] - (-3.0 + 0.5 * i)) / 0.5;
            want += (u == 0.0 ? 1.0 : sin(PI * u) / (PI * u)) * v[i];
        }
        assert_true(fabs(out[j] - want) < 1e-12);
    }
    assert_true(out[0] == v[17]);
}

static void average_matches_brute_force_weighted_sum(void **state)
{
    (void)state;
    double v[40];
    srand(11);
    for (int i = 0; i < 40; i++)
        v[i] = rand() / (double)RAND_MAX;
    st_signal_samples s = {1.0, 0.75, 40, v, NULL};
    double x[300], out[300];
    for (int j = 0; j < 300; j++)
        x[j] = -2.0 + 0.1071 * j;
    for (st_u32 k = 0; k < ST_FILTER_COUNT; k++) {
        st_signal_filter r = {.filter = st_filter_default(k), .mode = ST_SIGNAL_AVERAGE};
        st_u32 zeros = 99;
        assert_int_equal(st_signal_reconstruct(&s, &r, x, 300, out, &zeros, NULL), ST_OK);
        st_u32 want_zeros = 0;
        for (int j = 0; j < 300; j++) {
            double num = 0.0, den = 0.0; /* every sample, no window */
            for (int i = 0; i < 40; i++) {
                double w = st_filter_eval_1d(&r.filter, (float)((x[j] - (1.0 + 0.75 * i)) / 0.75));
                num += w * v[i];
                den += w;
            }
            if (den == 0.0) {
                assert_true(isnan(out[j]));
                want_zeros++;
            } else {
                assert_true(fabs(out[j] - num / den) < 1e-6);
            }
        }
        assert_int_equal(zeros, want_zeros);
    }
}

static void triangle_is_linear_interpolation(void **state)
{
    (void)state;
    double v[20];
    for (int i = 0; i < 20; i++)
        v[i] = cos(0.9 * i) + 0.1 * i;
    st_signal_samples s = {0.0, 2.0, 20, v, NULL};
    st_filter tri = st_filter_default(ST_FILTER_TRIANGLE); /* radius 1: r(u) = 1 - |u| */
    assert_true(tri.radius == 1.0f);
    double x[100], out[100];
    for (int j = 0; j < 100; j++)
        x[j] = 0.37 * j;
    for (st_u32 mode = 0; mode < 2; mode++) {
        st_signal_filter r = {.filter = tri, .mode = mode};
        assert_int_equal(st_signal_reconstruct(&s, &r, x, 100, out, NULL, NULL), ST_OK);
        for (int j = 0; j < 100; j++) {
            int i = (int)floor(x[j] / 2.0);
            double t = x[j] / 2.0 - i;
            double want = (1 - t) * v[i] + t * v[i + 1];
            assert_true(fabs(out[j] - want) < 1e-6); /* weights in float */
        }
    }
    assert_true(fabs(st_filter_integral(&tri) - 1.0) < 1e-8);
}

/* Convolution mode: Σ r(u - i) v_i / ∫ r; for a constant c that is
 * c Σ r / ∫ r, which ripples with u unless Σ r is constant (gaussian's does
 * not: 1.19 to 1.24 at r 1.5, σ 0.5). */
static void convolution_divides_by_filter_integral(void **state)
{
    (void)state;
    double v[32];
    for (int i = 0; i < 32; i++)
        v[i] = 0.7;
    st_signal_samples s = {0.0, 1.0, 32, v, NULL};
    st_signal_filter r = {.filter = st_filter_default(ST_FILTER_GAUSSIAN),
                          .mode = ST_SIGNAL_CONVOLUTION};
    double integral = st_filter_integral(&r.filter);
    double x[101], out[101], lo = INFINITY, hi = -INFINITY;
    for (int j = 0; j <= 100; j++)
        x[j] = 15.0 + j / 100.0;
    assert_int_equal(st_signal_reconstruct(&s, &r, x, 101, out, NULL, NULL), ST_OK);
    for (int j = 0; j <= 100; j++) {
        double sum = 0.0;
        for (int i = 0; i < 32; i++)
            sum += st_filter_eval_1d(&r.filter, (float)(x[j] - i));
        assert_true(fabs(out[j] - 0.7 * sum / integral) < 1e-6);
        lo = fmin(lo, out[j]);
        hi = fmax(hi, out[j]);
    }
    assert_true(hi - lo > 0.01); /* the ripple is there */
}

static void every_filter_reconstructs_constant_exactly(void **state)
{
    (void)state;
    double v[64];
    for (int i = 0; i < 64; i++)
        v[i] = 0.7;
    st_signal_samples s = {0.0, 1.0, 64, v, NULL};
    double x[500], out[500];
    for (int j = 0; j < 500; j++)
        x[j] = 10.0 + 0.0873 * j; /* [10, 53.6]: never exactly between two samples */
    /* 0: the filter's default. Not below 1.25: mitchell and catmull-rom squeezed
     * to radius 0.75 have Σ r crossing 0 between two samples (their negative
     * lobes outweigh the centre), where the average is undefined. At these
     * radii every filter keeps Σ r >= 0.33 (checked by brute force). */
    float radii[] = {0.0f, 1.25f, 2.5f, 6.0f};
    for (st_u32 k = 0; k < ST_FILTER_COUNT; k++)
        for (int q = 0; q < 4; q++) {
            st_signal_filter r = {.filter = st_filter_default(k)};
            if (radii[q] > 0.0f)
                r.filter.radius = r.filter.tau = radii[q];
            st_u32 zeros;
            assert_int_equal(st_signal_reconstruct(&s, &r, x, 500, out, &zeros, NULL), ST_OK);
            assert_int_equal(zeros, 0);
            for (int j = 0; j < 500; j++)
                if (fabs(out[j] - 0.7) > 1e-12)
                    fail_msg("%s r=%g at x=%g: %.17g", st_filter_names[k],
                             (double)r.filter.radius, x[j], out[j]);
        }
    st_signal_filter sinc = {.sinc = 1};
    assert_int_equal(st_signal_reconstruct(&s, &sinc, x, 500, out, NULL, NULL), ST_OK);
    for (int j = 0; j < 500; j++) {
        double bound = 0.7 / PI * (1.0 / (x[j] + 1.0) + 1.0 / (64.0 - x[j]));
        assert_true(fabs(out[j] - 0.7) <= bound);
    }
}

/* The box is closed at its radius (filters.h, as pbrt-v4's): a point
 * exactly between two samples, at T/2 from each, weighs both equally. */
static void box_between_two_samples_weighs_both(void **state)
{
    (void)state;
    double v[4] = {1, 2, 3, 4}, x[2] = {1.5, 1.25}, out[2];
    st_signal_samples s = {0.0, 1.0, 4, v, NULL};
    st_signal_filter r = {.filter = st_filter_default(ST_FILTER_BOX)}; /* radius 1/2, closed */
    st_u32 zeros = 1;
    assert_int_equal(st_signal_reconstruct(&s, &r, x, 2, out, &zeros, NULL), ST_OK);
    assert_true(out[0] == 2.5); /* (2 + 3) / 2 */
    assert_true(out[1] == 2.0); /* nearest neighbour */
    assert_int_equal(zeros, 0);
}

static void samples_lie_on_the_shah_grid(void **state)
{
    (void)state;
    for (int which = 0; which < 2; which++) {
        st_signal_options o = sine_options(0.3, 0.5, 10.0); /* fT = 0.15 */
        o.offset = 0.3;
        if (which) { /* triangle of radius 1 interpolates: f~(x_i) = f(x_i) */
            o.recon.sinc = 0;
            o.recon.filter = st_filter_default(ST_FILTER_TRIANGLE);
        }
        st_signal_result r;
        build(&o, &r);
        assert_int_equal(r.sample_count, 20); /* (i + 0.3) 0.5 < 10 for i = 0 .. 19 */
        for (st_u32 i = 0; i < r.sample_count; i++) {
            double x = (i + 0.3) * 0.5;
            assert_true(fabs(r.sample_x[i] - x) < 1e-12);
            assert_true(fabs(r.sample_value[i] - sin(2 * PI * 0.3 * x)) < 1e-12);
            assert_true(fabs(r.sample_reconstruction[i] - r.sample_value[i]) < 1e-6);
        }
        for (st_u32 j = 0; j < r.points; j++)
            assert_true(fabs(r.x[j] - j * 10.0 / r.points) < 1e-12);
        st_signal_result_free(&r);
    }
}

/* ---- the lecture's demonstrations ---------------------------------------------------- */

static void sinc_recovers_bandlimited_sine_above_nyquist(void **state)
{
    (void)state;
    const struct { double f, spacing, phase; } cases[] = {
        {0.3, 1.0, 0.0}, {0.45, 1.0, 0.0}, {0.1, 1.0, 1.1}, {0.6, 0.5, 0.4}, {0.05, 2.0, 2.0}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        st_signal_options o = sine_options(cases[c].f, cases[c].spacing, 64.0);
        o.fn.phase = cases[c].phase;
        st_signal_result r;
        build(&o, &r);
        assert_int_equal(r.margin, ST_SIGNAL_DEFAULT_SINC_MARGIN);
        double ft = cases[c].f * cases[c].spacing;
        double bound = 1.0 / (PI * PI * r.margin * (0.5 - ft));
        double worst = 0.0, sum = 0.0;
        for (st_u32 j = 0; j < r.points; j++) {
            double want = sin(2 * PI * cases[c].f * r.x[j] + cases[c].phase);
            double e = fabs(r.reconstruction[j] - want);
            worst = fmax(worst, e);
            sum += e * e;
        }
        if (!(worst < bound))
            fail_msg("f=%g T=%g: max error %g, bound %g", cases[c].f, cases[c].spacing, worst,
                     bound);
        assert_true(fabs(sqrt(sum / r.points) - r.rms_error) < 1e-9);
        assert_true(r.rms_error < bound && r.max_error < bound);
        assert_true(fabs(r.dominant_reconstruction - cases[c].f) < 1.0 / o.length);
        st_signal_result_free(&r);
    }
}

static void dominant_frequency_below_nyquist_is_alias(void **state)
{
    (void)state;
    double fs[] = {0.6, 0.8, 0.93, 1.3, 1.7, 2.2};
    for (int a = 0; a < 6; a++)
        for (int k = -1; k < (int)ST_FILTER_COUNT; k++) {
            st_signal_options o = sine_options(fs[a], 1.0, 64.0);
            if (k >= 0) {
                o.recon.sinc = 0;
                o.recon.filter = st_filter_default((st_u32)k);
            }
            st_signal_result r;
            build(&o, &r);
            double alias = brute_alias(fs[a], 1.0);
            if (fabs(r.dominant_reconstruction - alias) > 1.0 / o.length)
                fail_msg("f=%g %s: dominant %g, alias %g", fs[a],
                         k < 0 ? "sinc" : st_filter_names[k], r.dominant_reconstruction, alias);
            assert_true(fabs(r.dominant_original - fs[a]) < 1.0 / o.length);
            st_signal_result_free(&r);
        }
}

/* The peak of the reconstruction's spectrum within 2 bins of frequency f. */
static double peak_near(const st_signal_result *r, double f)
{
    double best = 0.0;
    for (st_u32 k = 0; k < r->bins; k++)
        if (fabs(r->freq[k] - f) <= 2.0 * (r->freq[1] - r->freq[0]))
            best = fmax(best, r->spectrum_reconstruction[k]);
    return best;
}

/* Jitter turns aliasing into noise (the lecture): sin(2π 0.9 x), T = 1,
 * L = 1024, sinc (margin 1024). Uniform samples rebuild the alias at 0.1,
 * amplitude 1: its peak reads about 1/2 (Hann, two-sided); bound >= 0.4.
 * Jittered samples (x_i = i + ξ_i) keep sinc(0.9) = 0.109 of the alias
 * coherently, a peak of 0.055, and the rest of the power (1 - 0.109²) / 2
 * spreads as noise over the band: about sqrt(0.49 × 1.5 / 1024) = 0.027 a
 * bin with the Hann window; bound 0.055 + 4 × 0.027, rounded up to 0.2.
 * The total error stays (noise instead of a wrong sine): the RMS error is
 * within a factor 1.5 of the uniform one's. Jittered samples lie in their
 * intervals, each at its own offset, and the same seed gives the same ones. */
static void jitter_turns_aliasing_into_noise(void **state)
{
    (void)state;
    st_signal_options o = sine_options(0.9, 1.0, 1024.0);
    o.sinc_margin = 1024;
    st_signal_result u, j, again;
    build(&o, &u);
    o.jitter = 1;
    o.seed = 3;
    build(&o, &j);
    build(&o, &again);
    double pu = peak_near(&u, 0.1), pj = peak_near(&j, 0.1);
    print_message("alias peak: uniform %.3f, jittered %.3f; rms error %.3f, %.3f\n", pu, pj,
                  u.rms_error, j.rms_error);
    assert_true(pu >= 0.4);
    assert_true(pj <= 0.2);
    assert_true(j.rms_error < 1.5 * u.rms_error && u.rms_error < 1.5 * j.rms_error);
    int moved = 0;
    for (st_u32 i = 0; i < j.sample_count; i++) {
        assert_true(j.sample_x[i] >= i && j.sample_x[i] < i + 1.0);
        assert_true(fabs(j.sample_value[i] - sin(2 * PI * 0.9 * j.sample_x[i])) < 1e-12);
        assert_true(j.sample_x[i] == again.sample_x[i]);
        moved += j.sample_x[i] != u.sample_x[i];
    }
    assert_true(moved > (int)j.sample_count / 2);
    st_signal_result_free(&u);
    st_signal_result_free(&j);
    st_signal_result_free(&again);
}

static void sinc_and_lanczos_overshoot_step(void **state)
{
    (void)state;
    double edges[] = {32.0, 32.5, 32.3};
    for (int e = 0; e < 3; e++)
        for (int which = 0; which < 2; which++) {
            st_signal_options o = step_options(edges[e], which == 0, ST_FILTER_LANCZOS);
            st_signal_result r;
            build(&o, &r);
            double lo, hi;
            extremes_near(&r, edges[e], 4.0, &lo, &hi);
            if (!(hi > 1.05 && lo < -0.05))
                fail_msg("%s, edge %g: range [%g, %g]", which ? "lanczos" : "sinc", edges[e], lo,
                         hi);
            st_signal_result_free(&r);
        }
}

static void box_and_gaussian_do_not_overshoot_and_blur(void **state)
{
    (void)state;
    double edges[] = {32.0, 32.5, 32.3};
    for (int e = 0; e < 3; e++) {
        st_signal_options o = step_options(edges[e], 0, ST_FILTER_LANCZOS);
        st_signal_result r;
        build(&o, &r);
        double lanczos_rise = rise_10_90(&r, edges[e]);
        st_signal_result_free(&r);
        assert_true(lanczos_rise > 0.3 && lanczos_rise < 1.0);

        const struct { st_u32 kind; float radius; int blurs; } cases[] = {
            {ST_FILTER_BOX, 0.5f, 0}, /* nearest neighbour: a jump, no blur */
            {ST_FILTER_BOX, 1.0f, 1}, {ST_FILTER_BOX, 2.0f, 1},
            {ST_FILTER_GAUSSIAN, 0.0f, 1}, {ST_FILTER_GAUSSIAN, 3.0f, 1}};
        for (int c = 0; c < 5; c++) {
            o = step_options(edges[e], 0, cases[c].kind);
            if (cases[c].radius > 0.0f)
                o.recon.filter.radius = cases[c].radius;
            build(&o, &r);
            double lo = INFINITY, hi = -INFINITY;
            for (st_u32 j = 0; j < r.points; j++) {
                lo = fmin(lo, r.reconstruction[j]);
                hi = fmax(hi, r.reconstruction[j]);
            }
            if (!(lo >= -1e-6 && hi <= 1.0 + 1e-6))
                fail_msg("%s r=%g: range [%.9g, %.9g]", st_filter_names[cases[c].kind],
                         (double)o.recon.filter.radius, lo, hi);
            double rise = rise_10_90(&r, edges[e]);
            if (cases[c].blurs && !(rise > lanczos_rise + 0.1))
                fail_msg("%s r=%g edge %g: rise %g, lanczos %g", st_filter_names[cases[c].kind],
                         (double)o.recon.filter.radius, edges[e], rise, lanczos_rise);
            st_signal_result_free(&r);
        }
    }
}

/* ---- spectra ----------------------------------------------------------------------- */

static void hann_spectrum_of_bin_sine_reads_half(void **state)
{
    (void)state;
    enum { N = 256, K0 = 19 };
    double v[N], mag[N / 2 + 1];
    for (int j = 0; j < N; j++)
        v[j] = 0.25 + cos(2 * PI * K0 * j / N);
    assert_int_equal(st_signal_spectrum(v, N, 0, mag, NULL), ST_OK);
    assert_true(fabs(mag[0] - 0.25) < 1e-12);   /* the mean, through the window's DC */
    assert_true(fabs(mag[1] - 0.125) < 1e-12);  /* and its -1/4 neighbour */
    assert_true(fabs(mag[K0] - 0.5) < 1e-12);
    assert_true(fabs(mag[K0 - 1] - 0.25) < 1e-12);
    assert_true(fabs(mag[K0 + 1] - 0.25) < 1e-12);
    for (int k = 2; k <= N / 2; k++)
        if (abs(k - K0) > 1)
            assert_true(mag[k] < 1e-12);
    assert_int_equal(st_signal_spectrum(v, N, 1, mag, NULL), ST_OK); /* mean removed */
    assert_true(mag[0] < 1e-12 && mag[1] < 1e-12);
    assert_true(fabs(st_signal_dominant_frequency(mag, N / 2 + 1, 1.0 / N) - (double)K0 / N) <
                1e-12);
}

static void dominant_frequency_refines_between_bins(void **state)
{
    (void)state;
    enum { N = 1024 };
    static double v[N], mag[N / 2 + 1];
    for (double frac = 0.0; frac < 1.0; frac += 0.125) {
        double f = (40.0 + frac) / N;
        for (int j = 0; j < N; j++)
            v[j] = sin(2 * PI * f * j + 0.3);
        assert_int_equal(st_signal_spectrum(v, N, 1, mag, NULL), ST_OK);
        double d = st_signal_dominant_frequency(mag, N / 2 + 1, 1.0 / N);
        assert_true(fabs(d - f) * N < 0.05); /* measured: 0.016 bins at most */
    }
    double zeros[8] = {0};
    assert_true(st_signal_dominant_frequency(zeros, 8, 1.0) == 0.0);
}

static void sampled_spectrum_has_copies_every_1_over_t(void **state)
{
    (void)state;
    st_signal_options o = sine_options(0.125, 1.0, 64.0); /* 8 cycles: on bin 8 */
    st_signal_result r;
    build(&o, &r);
    st_u32 n = r.sample_count;
    assert_int_equal(n, 64);
    assert_true(r.sampled_bins > 2 * n);
    for (st_u32 k = 0; k + n < r.sampled_bins; k++)
        assert_true(r.spectrum_sampled[k + n] == r.spectrum_sampled[k]); /* period 1/T */
    for (st_u32 k = 1; k < n; k++)
        assert_true(r.spectrum_sampled[n - k] == r.spectrum_sampled[k]); /* mirror */
    assert_true(fabs(r.sampled_freq[n] - 1.0) < 1e-12);
    /* peaks at f, 1/T - f, 1/T + f, each as tall as the original's (1/2) */
    st_u32 peaks[] = {8, 56, 72, 120, 136};
    for (int p = 0; p < 5; p++)
        assert_true(fabs(r.spectrum_sampled[peaks[p]] - 0.5) < 1e-12);
    assert_true(fabs(r.spectrum_original[8] - 0.5) < 1e-9);
    assert_true(fabs(r.nyquist - 0.5) < 1e-15);
    /* dense and sampled grids share the bins k / L here (L = n T) */
    assert_true(fabs(r.freq[8] - r.sampled_freq[8]) < 1e-15);
    st_signal_result_free(&r);
}

/* ---- options and errors ---------------------------------------------------------------- */

static void automatic_points_are_odd_multiple_of_samples(void **state)
{
    (void)state;
    st_signal_options o = sine_options(0.1, 1.0, 64.0);
    assert_int_equal(st_signal_check(&o, NULL), ST_OK);
    assert_int_equal(o.points, 65u * 64u); /* 65: the first odd p with 64 p >= 4096 */
    assert_int_equal(o.sinc_margin, ST_SIGNAL_DEFAULT_SINC_MARGIN);
    o = sine_options(40.0, 1.0, 64.0); /* 8 f L = 20480 points at least */
    assert_int_equal(st_signal_check(&o, NULL), ST_OK);
    assert_true(o.points >= 20480u && (o.points / 64u) % 2u == 1u && o.points % 64u == 0u);
    /* a box of radius 1/2 on the default grid never lands between two samples */
    o = step_options(32.5, 0, ST_FILTER_BOX);
    st_signal_result r;
    build(&o, &r);
    assert_int_equal(r.zero_weight, 0);
    assert_int_equal(r.margin, 2); /* ceil(1/2) + 1 */
    st_signal_result_free(&r);
}

static void expect_usage(st_signal_options o, const char *needle)
{
    st_error err = {0};
    st_signal_result r;
    memset(&r, 0xab, sizeof r);
    assert_int_equal(st_signal_build(&o, &r, &err), ST_ERR_USAGE);
    if (!strstr(err.msg, needle))
        fail_msg("message '%s' does not name '%s'", err.msg, needle);
    assert_null(r.x);
    assert_null(r.reconstruction);
    st_signal_result_free(&r); /* zeroed: harmless */
}

static void bad_options_are_usage_errors_naming_the_option(void **state)
{
    (void)state;
    st_signal_options o = sine_options(0.1, 1.0, 64.0);
    o.spacing = 0.0;
    expect_usage(o, "--spacing");
    o = sine_options(0.1, 1.0, -1.0);
    expect_usage(o, "--length");
    o = sine_options(0.1, 1.0, 64.0);
    o.offset = 1.0;
    expect_usage(o, "--offset");
    o = sine_options(0.01, 100.0, 64.0); /* one sample in [0, 64) */
    expect_usage(o, "fewer than 2 samples");
    o = sine_options(0.1, 1.0, 64.0);
    o.points = 512; /* f = 10 needs more than 2 f L = 1280 */
    o.fn.freq = 10.0;
    expect_usage(o, "--points 512");
    o = sine_options(-0.1, 1.0, 64.0);
    expect_usage(o, "--freq");
    o = sine_options(0.1, 1.0, 64.0);
    o.fn.kind = ST_SIGNAL_SINES;
    expect_usage(o, "--freqs");
    o.fn.kind = 99;
    expect_usage(o, "--function");
    o = sine_options(0.1, 1.0, 64.0);
    o.recon.sinc = 0;
    o.recon.filter = st_filter_default(ST_FILTER_BOX);
    o.recon.filter.radius = 0.0f;
    /* the filter module names fields; `strata signal` writes them as its
     * options (test_signal.sh "radius past the limit") */
    expect_usage(o, "filter radius 0");
    o.recon.filter.radius = 65.0f; /* past ST_SIGNAL_MAX_RADIUS, not the renderer's 8 */
    expect_usage(o, "must be in [0.0625, 64]");
    o.recon.filter = st_filter_default(ST_FILTER_GAUSSIAN);
    o.recon.filter.sigma = 0.0f;
    expect_usage(o, "filter sigma");
    o.recon.filter = st_filter_default(ST_FILTER_LANCZOS);
    o.recon.filter.tau = -1.0f;
    expect_usage(o, "filter tau");
    o.recon.filter = st_filter_default(ST_FILTER_MITCHELL);
    o.recon.mode = 7;
    expect_usage(o, "--reconstruct");
    o = sine_options(0.1, 1.0, 64.0);
    o.points = ST_SIGNAL_MAX_POINTS;
    o.sinc_margin = 4096;
    expect_usage(o, "--sinc-margin");

    double v[2] = {0, 1}, x = 0.5, out;
    st_signal_samples s = {0.0, -1.0, 2, v, NULL};
    st_signal_filter sinc = {.sinc = 1};
    st_error err = {0};
    assert_int_equal(st_signal_reconstruct(&s, &sinc, &x, 1, &out, NULL, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "--spacing"));
    assert_int_equal(st_signal_spectrum(v, 1, 0, &out, NULL), ST_ERR_USAGE);
    st_signal_result_free(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(eval_matches_definitions),
        cmocka_unit_test(alias_frequency_matches_brute_force),
        cmocka_unit_test(sinc_matches_direct_sum),
        cmocka_unit_test(average_matches_brute_force_weighted_sum),
        cmocka_unit_test(triangle_is_linear_interpolation),
        cmocka_unit_test(convolution_divides_by_filter_integral),
        cmocka_unit_test(every_filter_reconstructs_constant_exactly),
        cmocka_unit_test(box_between_two_samples_weighs_both),
        cmocka_unit_test(samples_lie_on_the_shah_grid),
        cmocka_unit_test(sinc_recovers_bandlimited_sine_above_nyquist),
        cmocka_unit_test(dominant_frequency_below_nyquist_is_alias),
        cmocka_unit_test(jitter_turns_aliasing_into_noise),
        cmocka_unit_test(sinc_and_lanczos_overshoot_step),
        cmocka_unit_test(box_and_gaussian_do_not_overshoot_and_blur),
        cmocka_unit_test(hann_spectrum_of_bin_sine_reads_half),
        cmocka_unit_test(dominant_frequency_refines_between_bins),
        cmocka_unit_test(sampled_spectrum_has_copies_every_1_over_t),
        cmocka_unit_test(automatic_points_are_odd_multiple_of_samples),
        cmocka_unit_test(bad_options_are_usage_errors_naming_the_option),
    };
    return cmocka_run_group_tests_name("signal", tests, NULL, NULL);
}
