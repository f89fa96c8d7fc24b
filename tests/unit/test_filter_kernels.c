/* test_filter_kernels.c — guards kernels/film/filters.h, the reconstruction filters the
 * splat kernel and `strata filter` evaluate.
 *
 * Each filter is checked against its formula evaluated in double by code
 * written here (the definitions; the lecture, "Image reconstruction"):
 *   box 1; triangle r - |x|; gaussian exp(-x^2/2σ^2) - exp(-r^2/2σ^2);
 *   mitchell k_{B,C}(2|x|/r) (Mitchell & Netravali, "Reconstruction Filters in
 *   Computer Graphics", SIGGRAPH 1988); catmull-rom = k_{0,1/2}, written here in
 *   Keys' form (Keys, "Cubic Convolution Interpolation for Digital Image
 *   Processing", IEEE TASSP 1981, a = -1/2); lanczos sinc(x) sinc(x/τ);
 *   blackman-harris, the 4-term window of Harris (Proc. IEEE 1978) over [-r, r],
 *   written here in its even form a0 + a1 cos(πx/r) + a2 cos(2πx/r) + a3 cos(3πx/r).
 * Tolerance: 2e-6 absolute. The header computes in float (24-bit mantissa,
 * rounding ~6e-8 relative per operation, values of order 1, at most r <= 8 for
 * the triangle), so a few hundred rounding steps' worth of slack; a wrong
 * coefficient or branch is off by far more.
 * Exact properties (no tolerance): zero for |x| > r, even symmetry, and
 * separability f(x, y) == f(x) f(y). Mitchell's cubic integrates to 1 over
 * [-2, 2] for any B, C: checked by Simpson's rule (exact for cubics on each
 * piece), tolerance 1e-5 for the float evaluations summed. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>

#include "st_shared.h"
#include "filters.h"

#define TOL 2e-6

static const double PI = 3.14159265358979323846;

static st_filter make_filter(st_u32 kind, float radius, float b, float c, float sigma,
                             float tau)
{
    st_filter f = {kind, radius, b, c, sigma, tau, {0.0f, 0.0f}};
    return f;
}

/* The filters under test, with several parameter sets each. */
static const st_filter *filters(size_t *count)
{
    static st_filter list[64];
    size_t n = 0;
    const float radii[] = {0.5f, 1.0f, 1.5f, 2.0f, 2.5f, 4.0f, 8.0f};
    for (size_t i = 0; i < 7; i++) {
        list[n++] = make_filter(ST_FILTER_BOX, radii[i], 0, 0, 0, 0);
        list[n++] = make_filter(ST_FILTER_TRIANGLE, radii[i], 0, 0, 0, 0);
        list[n++] = make_filter(ST_FILTER_CATMULL_ROM, radii[i], 0, 0, 0, 0);
        list[n++] = make_filter(ST_FILTER_BLACKMAN_HARRIS, radii[i], 0, 0, 0, 0);
    }
    const float gauss[][2] = {{1.5f, 0.5f}, {2.0f, 0.5f}, {1.0f, 0.25f}, {3.0f, 1.0f},
                              {2.5f, 0.8f}, {0.5f, 0.5f}};
    for (size_t i = 0; i < 6; i++)
        list[n++] = make_filter(ST_FILTER_GAUSSIAN, gauss[i][0], 0, 0, gauss[i][1], 0);
    const float mitchell[][3] = {{2.0f, 1.0f / 3, 1.0f / 3}, {2.0f, 0.0f, 0.5f}, {2.0f, 1.0f, 0.0f},
                                 {2.0f, 0.0f, 0.0f},         {1.0f, 0.5f, 0.25f}, {3.0f, 1.0f / 3, 1.0f / 3},
                                 {1.5f, 0.2f, 0.7f}};
    for (size_t i = 0; i < 7; i++)
        list[n++] = make_filter(ST_FILTER_MITCHELL, mitchell[i][0], mitchell[i][1], mitchell[i][2], 0, 0);
    const float lanczos[][2] = {{2.0f, 2.0f}, {3.0f, 3.0f}, {3.0f, 1.5f},
                                {2.0f, 1.0f}, {4.0f, 2.0f}, {8.0f, 8.0f}, {1.0f, 3.0f}};
    for (size_t i = 0; i < 7; i++)
        list[n++] = make_filter(ST_FILTER_LANCZOS, lanczos[i][0], 0, 0, 0, lanczos[i][1]);
    *count = n;
    return list;
}

/* ---- the formulas, in double ------------------------------------------------ */

/* Mitchell–Netravali: 6k(t) = (12-9B-6C)t^3 + (-18+12B+6C)t^2 + (6-2B), t < 1;
 * (-B-6C)t^3 + (6B+30C)t^2 + (-12B-48C)t + (8B+24C), 1 <= t < 2; 0 beyond. */
static double mitchell_ref(double t, double b, double c)
{
    t = fabs(t);
    if (t < 1.0)
        return ((12 - 9 * b - 6 * c) * t * t * t + (-18 + 12 * b + 6 * c) * t * t + (6 - 2 * b)) / 6;
    if (t < 2.0)
        return ((-b - 6 * c) * t * t * t + (6 * b + 30 * c) * t * t + (-12 * b - 48 * c) * t +
                (8 * b + 24 * c)) /
               6;
    return 0.0;
}

/* Keys' cubic with a = -1/2 (Catmull-Rom): (a+2)|t|^3 - (a+3)|t|^2 + 1 for
 * |t| < 1, a|t|^3 - 5a|t|^2 + 8a|t| - 4a for 1 <= |t| < 2. */
static double catmull_rom_ref(double t)
{
    const double a = -0.5;
    t = fabs(t);
    if (t < 1.0)
        return (a + 2) * t * t * t - (a + 3) * t * t + 1;
    if (t < 2.0)
        return a * t * t * t - 5 * a * t * t + 8 * a * t - 4 * a;
    return 0.0;
}

static double sinc_ref(double x)
{
    return x == 0.0 ? 1.0 : sin(PI * x) / (PI * x);
}

static double filter_ref(const st_filter *f, double x)
{
    double r = f->radius, ax = fabs(x);
    if (ax > r)
        return 0.0;
    switch (f->kind) {
    case ST_FILTER_BOX:
        return 1.0;
    case ST_FILTER_TRIANGLE:
        return r - ax;
    case ST_FILTER_GAUSSIAN: {
        double s2 = (double)f->sigma * f->sigma;
        return exp(-x * x / (2 * s2)) - exp(-r * r / (2 * s2));
    }
    case ST_FILTER_MITCHELL:
        return mitchell_ref(2 * ax / r, f->b, f->c);
    case ST_FILTER_CATMULL_ROM:
        return catmull_rom_ref(2 * ax / r);
    case ST_FILTER_LANCZOS:
        return sinc_ref(x) * sinc_ref(x / f->tau);
    case ST_FILTER_BLACKMAN_HARRIS: {
        const double a0 = 0.35875, a1 = 0.48829, a2 = 0.14128, a3 = 0.01168;
        double u = PI * x / r;
        return a0 + a1 * cos(u) + a2 * cos(2 * u) + a3 * cos(3 * u);
    }
    default:
        fail_msg("unknown filter kind %u", f->kind);
        return 0.0;
    }
}

/* Points across (-r - 1, r + 1): a fine regular grid, the breakpoints of the
 * piecewise filters (0, ±r/2, ±r) and their float neighbours. */
static size_t sample_points(float r, float *xs)
{
    size_t n = 0;
    for (int i = -2000; i <= 2000; i++)
        xs[n++] = (float)i * (r + 1.0f) / 2000.0f;
    const float brk[] = {0.0f, 0.5f * r, r};
    for (size_t k = 0; k < 3; k++)
        for (int s = -1; s <= 1; s += 2) {
            float b = s * brk[k];
            xs[n++] = b;
            xs[n++] = nextafterf(b, INFINITY);
            xs[n++] = nextafterf(b, -INFINITY);
        }
    return n;
}

static const char *kind_name(st_u32 k)
{
    static const char *names[] = {"box",     "triangle",    "gaussian",       "mitchell",
                                  "lanczos", "catmull-rom", "blackman-harris"};
    return k < 7 ? names[k] : "?";
}

/* ---- tests -------------------------------------------------------------------- */

static void filters_match_formulas(void **state)
{
    (void)state;
    size_t count;
    const st_filter *fs = filters(&count);
    float xs[4100];
    for (size_t i = 0; i < count; i++) {
        const st_filter *f = &fs[i];
        size_t n = sample_points(f->radius, xs);
        for (size_t k = 0; k < n; k++) {
            double got = st_filter_eval_1d(f, xs[k]), want = filter_ref(f, xs[k]);
            if (!(fabs(got - want) <= TOL))
                fail_msg("%s r=%g b=%g c=%g sigma=%g tau=%g at x=%.9g: %.9g, formula %.9g",
                         kind_name(f->kind), f->radius, f->b, f->c, f->sigma, f->tau, xs[k], got,
                         want);
        }
    }
}

/* Known values: box 1 inside; triangle r at 0; gaussian 1 - exp(-r^2/2σ^2) at
 * 0; catmull-rom 1 at 0; lanczos sinc(1/2) sinc(1/2τ) at 1/2; blackman-harris
 * a0 + a1 + a2 + a3 = 1 at 0; mitchell (6 - 2B)/6 at 0 (B = C = 1/3: 8/9). */
static void filters_known_values(void **state)
{
    (void)state;
    st_filter box = make_filter(ST_FILTER_BOX, 0.5f, 0, 0, 0, 0);
    st_filter tri = make_filter(ST_FILTER_TRIANGLE, 2.0f, 0, 0, 0, 0);
    st_filter gau = make_filter(ST_FILTER_GAUSSIAN, 1.5f, 0, 0, 0.5f, 0);
    st_filter mit = make_filter(ST_FILTER_MITCHELL, 2.0f, 1.0f / 3, 1.0f / 3, 0, 0);
    st_filter lan = make_filter(ST_FILTER_LANCZOS, 3.0f, 0, 0, 0, 3.0f);
    st_filter bh = make_filter(ST_FILTER_BLACKMAN_HARRIS, 2.0f, 0, 0, 0, 0);
    assert_true(st_filter_eval_1d(&box, 0.49f) == 1.0f);
    assert_true(st_filter_eval_1d(&tri, 0.0f) == 2.0f);
    assert_true(st_filter_eval_1d(&tri, 1.5f) == 0.5f);
    assert_true(fabs(st_filter_eval_1d(&gau, 0.0f) - (1.0 - exp(-4.5))) <= TOL);
    assert_true(fabs(st_filter_eval_1d(&mit, 0.0f) - 8.0 / 9.0) <= TOL);
    assert_true(fabs(st_filter_eval_1d(&lan, 0.5f) - (2 / PI) * (6 / PI) * sin(PI / 6)) <= TOL);
    assert_true(fabs(st_filter_eval_1d(&lan, 1.0f)) <= TOL); /* sinc(1) = 0 */
    assert_true(fabs(st_filter_eval_1d(&bh, 0.0f) - 1.0) <= TOL);
}

/* 0 for |x| > r, including just past ±r, ±inf and NaN; the formula on the
 * closed interval, at x = ±r exactly too (pbrt-v4's filters: the box is 1
 * there, so a sample on a pixel's edge weighs in both pixels); and 0 for
 * unknown kinds (an error path: the splat kernel then adds nothing). */
static void filters_zero_outside_radius(void **state)
{
    (void)state;
    size_t count;
    const st_filter *fs = filters(&count);
    for (size_t i = 0; i < count; i++) {
        const st_filter *f = &fs[i];
        float r = f->radius;
        const float xs[] = {nextafterf(r, INFINITY), -nextafterf(r, INFINITY),
                            r + 0.5f, 2 * r, 100.0f, -1e30f, INFINITY, -INFINITY, NAN};
        for (size_t k = 0; k < sizeof xs / sizeof xs[0]; k++)
            if (st_filter_eval_1d(f, xs[k]) != 0.0f)
                fail_msg("%s r=%g at x=%g: %g, expected 0", kind_name(f->kind), r, xs[k],
                         st_filter_eval_1d(f, xs[k]));
        /* at the radius and just inside, the piecewise filters still take
         * their formula */
        const float at[] = {r, -r, nextafterf(r, 0.0f)};
        for (size_t k = 0; k < sizeof at / sizeof at[0]; k++)
            if (!(fabs(st_filter_eval_1d(f, at[k]) - filter_ref(f, at[k])) <= TOL))
                fail_msg("%s r=%g at x=%g: %g, formula %g", kind_name(f->kind), r, at[k],
                         st_filter_eval_1d(f, at[k]), filter_ref(f, at[k]));
        if (f->kind == ST_FILTER_BOX)
            assert_true(st_filter_eval_1d(f, r) == 1.0f && st_filter_eval_1d(f, -r) == 1.0f);
    }
    st_filter bad = make_filter(ST_FILTER_COUNT, 2.0f, 0, 0, 0, 0);
    assert_true(st_filter_eval_1d(&bad, 0.0f) == 0.0f);
    assert_true(st_filter_eval(&bad, 0.1f, 0.1f) == 0.0f);
    /* a zero radius (which st_filter_check refuses) leaves the point x = 0 */
    st_filter zero = make_filter(ST_FILTER_BOX, 0.0f, 0, 0, 0, 0);
    assert_true(st_filter_eval_1d(&zero, 0.0f) == 1.0f);
    assert_true(st_filter_eval_1d(&zero, 0x1p-149f) == 0.0f);
}

/* f(-x) == f(x) bit for bit: a splat's weight must not depend on which side of
 * the pixel centre the sample fell. */
static void filters_symmetric_exactly(void **state)
{
    (void)state;
    size_t count;
    const st_filter *fs = filters(&count);
    float xs[4100];
    for (size_t i = 0; i < count; i++) {
        const st_filter *f = &fs[i];
        size_t n = sample_points(f->radius, xs);
        for (size_t k = 0; k < n; k++) {
            float a = st_filter_eval_1d(f, xs[k]), b = st_filter_eval_1d(f, -xs[k]);
            if (a != b)
                fail_msg("%s r=%g: f(%.9g) = %.9g but f(%.9g) = %.9g", kind_name(f->kind),
                         f->radius, xs[k], a, -xs[k], b);
        }
    }
}

/* f(x, y) == f(x) f(y) exactly. */
static void filters_separable_exactly(void **state)
{
    (void)state;
    size_t count;
    const st_filter *fs = filters(&count);
    for (size_t i = 0; i < count; i++) {
        const st_filter *f = &fs[i];
        for (int a = -40; a <= 40; a++)
            for (int b = -40; b <= 40; b++) {
                float x = a * f->radius / 37.0f, y = b * f->radius / 29.0f;
                float want = st_filter_eval_1d(f, x) * st_filter_eval_1d(f, y);
                if (st_filter_eval(f, x, y) != want)
                    fail_msg("%s: f(%g, %g) = %g, f(x) f(y) = %g", kind_name(f->kind), x, y,
                             st_filter_eval(f, x, y), want);
            }
    }
}

/* ∫ k_{B,C}(t) dt over [-2, 2] = 1 for every B, C (the family is normalised):
 * with radius r the filter is k(2x/r), so ∫ f = r/2. Composite Simpson with the
 * breakpoints -r, -r/2, 0, r/2, r on the grid: exact for the cubic pieces, so
 * the error is the float evaluation only; tolerance 1e-5 relative to r/2. */
static double simpson(const st_filter *f, int n)
{
    double r = f->radius, h = 2 * r / n, sum = 0.0;
    for (int i = 0; i <= n; i++) {
        double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
        sum += w * st_filter_eval_1d(f, (float)(-r + i * h));
    }
    return sum * h / 3;
}

static void mitchell_integrates_to_one(void **state)
{
    (void)state;
    const float bc[][2] = {{1.0f / 3, 1.0f / 3}, {0, 0.5f}, {1, 0}, {0, 0}, {0.5f, 0.25f},
                           {0.2f, 0.7f}, {0.75f, 0.1f}};
    const float radii[] = {2.0f, 1.0f, 3.0f, 0.5f};
    for (size_t i = 0; i < sizeof bc / sizeof bc[0]; i++)
        for (size_t k = 0; k < 4; k++) {
            st_filter f = make_filter(ST_FILTER_MITCHELL, radii[k], bc[i][0], bc[i][1], 0, 0);
            double integral = simpson(&f, 4096);
            if (!(fabs(integral / (radii[k] / 2.0) - 1.0) <= 1e-5))
                fail_msg("B=%g C=%g r=%g: integral %.9g, expected %g", bc[i][0], bc[i][1],
                         radii[k], integral, radii[k] / 2.0);
        }
    /* catmull-rom is the same family at B = 0, C = 1/2 */
    st_filter cr = make_filter(ST_FILTER_CATMULL_ROM, 2.0f, 0, 0, 0, 0);
    assert_true(fabs(simpson(&cr, 4096) - 1.0) <= 1e-5);
}

/* Catmull-Rom interpolates: k(0) = 1, k(±1) = 0, k(±2) = 0 (t = 2x/r), while
 * Mitchell with B > 0 does not (k(0) = 1 - B/3, k(1) = B/6). */
static void catmull_rom_interpolates(void **state)
{
    (void)state;
    const float radii[] = {2.0f, 1.0f, 4.0f, 3.0f};
    for (size_t k = 0; k < 4; k++) {
        float r = radii[k];
        st_filter cr = make_filter(ST_FILTER_CATMULL_ROM, r, 0, 0, 0, 0);
        st_filter m = make_filter(ST_FILTER_MITCHELL, r, 0.0f, 0.5f, 0, 0);
        assert_true(fabs(st_filter_eval_1d(&cr, 0.0f) - 1.0) <= TOL);
        assert_true(fabs(st_filter_eval_1d(&cr, r / 2)) <= TOL);
        assert_true(fabs(st_filter_eval_1d(&cr, -r / 2)) <= TOL);
        assert_true(st_filter_eval_1d(&cr, r) == 0.0f);
        for (int i = -100; i <= 100; i++) {
            float x = i * r / 80.0f;
            assert_true(fabs(st_filter_eval_1d(&cr, x) - st_filter_eval_1d(&m, x)) <= TOL);
        }
    }
    st_filter mn = make_filter(ST_FILTER_MITCHELL, 2.0f, 1.0f / 3, 1.0f / 3, 0, 0);
    assert_true(fabs(st_filter_eval_1d(&mn, 0.0f) - 8.0 / 9.0) <= TOL);
    assert_true(fabs(st_filter_eval_1d(&mn, 1.0f) - 1.0 / 18.0) <= TOL);
}

/* st_filter_taps_1d, the weights of all taps of one axis that every splat
 * path takes: for samples s across a pixel (and near the image's left edge,
 * where x_k = lo + k + 1/2 - s rounds), at the taps the splat kernel uses
 * plus one outside on each side, each weight is the formula at that tap's
 * float x_k: exactly st_filter_eval_1d's value for every filter but lanczos,
 * and for lanczos (sines turned from the tap nearest 0) within TAPS_TOL.
 * TAPS_TOL: each turn rounds four products and two sums, a few 2^-24 ≈
 * 6e-8 per tap, so at most 16 turns give ~4e-6 on sin(π x / τ), divided by
 * π |x| / τ >= π / (2 τ) away from the centre tap (τ <= 8 here: x 2.6), and
 * the centre tap's own sines are relatively accurate: 1e-5 in all. A wrong
 * sign, phase or step is off by far more (and the exact checks
 * filters_* above keep guarding st_filter_eval_1d). */
#define TAPS_TOL 1e-5

static void taps_1d_match_formulas(void **state)
{
    (void)state;
    size_t count;
    const st_filter *fs = filters(&count);
    double worst = 0.0;
    for (size_t i = 0; i < count; i++) {
        const st_filter *f = &fs[i];
        for (int j = 0; j < 400; j++) {
            float s = j < 200 ? 100.0f + (float)j / 199.0f : (float)(j - 200) / 97.0f;
            if (j == 17)
                s = 100.5f; /* the centre tap at exactly 0: sinc's limit, 1 */
            int lo = (int)ceilf(s - f->radius - 0.5f) - 1;
            int n = (int)floorf(s + f->radius - 0.5f) + 1 - lo + 1;
            if (n > ST_MAX_TAPS) { /* r = 8: keep the taps inside the radius */
                lo++;
                n = ST_MAX_TAPS;
            }
            float w[ST_MAX_TAPS];
            st_filter_taps_1d(f, lo, n, s, w);
            for (int k = 0; k < n; k++) {
                float x = (float)(lo + k) + 0.5f - s;
                double want = filter_ref(f, x), err = fabs(w[k] - want);
                if (f->kind != ST_FILTER_LANCZOS && w[k] != st_filter_eval_1d(f, x))
                    fail_msg("%s r=%g s=%.9g tap %d: %.9g, st_filter_eval_1d %.9g",
                             kind_name(f->kind), f->radius, s, k, w[k], st_filter_eval_1d(f, x));
                if (!(err <= TAPS_TOL))
                    fail_msg("%s r=%g tau=%g s=%.9g tap %d (x=%.9g): %.9g, formula %.9g",
                             kind_name(f->kind), f->radius, f->tau, s, k, x, w[k], want);
                if (fabs(x) > f->radius && w[k] != 0.0f)
                    fail_msg("%s r=%g at x=%g: %g, expected 0", kind_name(f->kind), f->radius,
                             x, w[k]);
                if (f->kind == ST_FILTER_LANCZOS && err > worst)
                    worst = err;
            }
            if (j == 17 && f->kind == ST_FILTER_LANCZOS)
                assert_true(w[(int)floorf(s) - lo] == 1.0f);
        }
    }
    printf("# lanczos taps: largest difference from the formula %.3g\n", worst);
}

/* st_tap_range1, the taps every splat path gives a sample (film.cl), against
 * the definition by brute force: the pixels k in [0, n) whose centre's
 * offset, as st_tap_offset computes it in float, lies within the closed
 * support, |k + 1/2 - s| <= r. Positions across and beyond an image 4099
 * pixels wide (where a float's step is 2^-12 and the ends' estimates round
 * across an integer), each near an end's tie, s = m + 1/2 +- r, and up to
 * three floats either side of it; and evenly spread ones. An empty range
 * is any with hi < lo. */
static void tap_range_brute_force(void **state)
{
    (void)state;
    static const float radii[] = {0.0625f, 0.3f, 0.5f, 1.0f, 1.3f, 2.0f, 2.2f, 3.0f, 7.7f};
    const int n = 4099;
    uint64_t x = 0x9e3779b97f4a7c15u;
    for (size_t i = 0; i < sizeof radii / sizeof radii[0]; i++) {
        float r = radii[i];
        for (int j = 0; j < 20000; j++) {
            x = x * 6364136223846793005u + 1442695040888963407u;
            int m = (int)(x >> 33) % (n + 4) - 2, steps = (int)(x >> 20 & 7u) - 3;
            float s = (float)m + 0.5f + (x >> 30 & 1u ? r : -r);
            for (; steps != 0; steps += steps < 0 ? 1 : -1)
                s = nextafterf(s, steps < 0 ? -1e9f : 1e9f);
            if (j % 5 == 0)
                s = -9.0f + (float)j * ((float)(n + 18) / 20000.0f);
            int lo, hi, want_lo = n, want_hi = -1;
            st_tap_range1(s, r, n, &lo, &hi);
            for (int k = (int)s - 10; k <= (int)s + 10; k++)
                if (k >= 0 && k < n && fabsf(st_tap_offset1(k, 0, s)) <= r) {
                    want_lo = k < want_lo ? k : want_lo;
                    want_hi = k;
                }
            if (want_hi < want_lo ? hi >= lo : lo != want_lo || hi != want_hi)
                fail_msg("r=%g s=%.9g: taps %d..%d, by definition %d..%d", r, s, lo, hi,
                         want_lo, want_hi);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(filters_match_formulas),
        cmocka_unit_test(filters_known_values),
        cmocka_unit_test(filters_zero_outside_radius),
        cmocka_unit_test(filters_symmetric_exactly),
        cmocka_unit_test(filters_separable_exactly),
        cmocka_unit_test(mitchell_integrates_to_one),
        cmocka_unit_test(catmull_rom_interpolates),
        cmocka_unit_test(taps_1d_match_formulas),
        cmocka_unit_test(tap_range_brute_force),
    };
    return cmocka_run_group_tests_name("filters", tests, NULL, NULL);
}
