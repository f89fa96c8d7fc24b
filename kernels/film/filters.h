/* filters.h — reconstruction filters, evaluated in the splat kernel and by the
 * host (strata filter, tests). Separable: f(x, y) = f(x) f(y); every filter is
 * 0 for |x| > r and takes its formula on the closed interval |x| <= r, as
 * pbrt-v4's filters do: a sample exactly on a pixel's edge, where unscrambled
 * sequences put sample 0, weighs in the pixels on both sides (with an open
 * box it weighed in neither). No normalisation: the pixel value is the weighted average
 *   I(x, y) = Σ f(x - x_i, y - y_i) L_i / Σ f(x - x_i, y - y_i)
 * (the lecture), so constant factors cancel. Negative lobes (mitchell,
 * catmull-rom, lanczos) stay; the resolve kernel clamps negative pixels.
 *
 *   box              1
 *   triangle         r - |x|
 *   gaussian         exp(-x^2 / 2σ^2) - exp(-r^2 / 2σ^2)
 *   mitchell         k_{B,C}(2|x|/r), Mitchell & Netravali, "Reconstruction
 *                    Filters in Computer Graphics", SIGGRAPH 1988:
 *     6k(t) = (12-9B-6C)t^3 + (-18+12B+6C)t^2 + (6-2B)              t < 1
 *     6k(t) = (-B-6C)t^3 + (6B+30C)t^2 + (-12B-48C)t + (8B+24C)     1 <= t < 2
 *   catmull-rom      mitchell with B = 0, C = 1/2
 *   lanczos          sinc(x) sinc(x/τ), sinc(x) = sin(πx)/(πx) (Duchon 1979)
 *   blackman-harris  the 4-term window of Harris, "On the Use of Windows for
 *                    Harmonic Analysis with the DFT", Proc. IEEE 1978, over
 *                    [-r, r]: a0 - a1 cos(2πt) + a2 cos(4πt) - a3 cos(6πt),
 *                    t = (x + r) / 2r (as LuxCore and Cycles use it)
 * Tests: test_filter_kernels.c. */
#ifndef ST_FILTERS_H
#define ST_FILTERS_H

/* Largest radius a render accepts: the splat kernel keeps the per-column
 * weights of one sample in a private array of ST_MAX_TAPS entries
 * (st_shared.h derives both from ST_FILTER_MAX_RADIUS_PX). */
#define ST_FILTER_MAX_RADIUS ((st_f32)ST_FILTER_MAX_RADIUS_PX)

ST_HOT st_f32 st_mitchell_1d(st_f32 t, st_f32 b, st_f32 c)
{
    if (t < 1.0f)
        return ((12.0f - 9.0f * b - 6.0f * c) * t * t * t +
                (-18.0f + 12.0f * b + 6.0f * c) * t * t + (6.0f - 2.0f * b)) *
               (1.0f / 6.0f);
    /* the second piece has a double root at t = 2: in factored form,
     * 6k(t) = (2 - t)^2 ((-B-6C) t + 2B + 6C), it keeps its relative accuracy
     * near t = 2 (the expanded sum of terms near 100 cancelled to errors of
     * 6e-6: test_filter_kernels.c filters_match_formulas) */
    if (t < 2.0f) {
        st_f32 u = 2.0f - t;
        return u * u * ((-b - 6.0f * c) * t + 2.0f * b + 6.0f * c) * (1.0f / 6.0f);
    }
    return 0.0f;
}

ST_FN st_f32 st_sinc(st_f32 x)
{
    if (fabs(x) < 1e-5f)
        return 1.0f;
    return sin(ST_PI_F * x) / (ST_PI_F * x);
}

/* f(x) of filter f, one axis. */
ST_FN st_f32 st_filter_eval_1d(const st_filter *f, st_f32 x)
{
    st_f32 ax = fabs(x), r = f->radius;
    if (!(ax <= r))
        return 0.0f;
    switch (f->kind) {
    case ST_FILTER_BOX:
        return 1.0f;
    case ST_FILTER_TRIANGLE:
        return r - ax;
    case ST_FILTER_GAUSSIAN: {
        st_f32 k = -0.5f / (f->sigma * f->sigma);
        return exp(k * ax * ax) - exp(k * r * r);
    }
    case ST_FILTER_MITCHELL:
        return st_mitchell_1d(2.0f * ax / r, f->b, f->c);
    case ST_FILTER_CATMULL_ROM:
        return st_mitchell_1d(2.0f * ax / r, 0.0f, 0.5f);
    case ST_FILTER_LANCZOS:
        return st_sinc(ax) * st_sinc(ax / f->tau);
    case ST_FILTER_BLACKMAN_HARRIS: {
        /* |x|: the window is even, and f(-x) == f(x) must hold bit for bit */
        st_f32 t = 2.0f * ST_PI_F * (ax + r) / (2.0f * r);
        return 0.35875f - 0.48829f * cos(t) + 0.14128f * cos(2.0f * t) -
               0.01168f * cos(3.0f * t);
    }
    default:
        return 0.0f;
    }
}

/* sin(π x) and cos(π x): OpenCL's sinpi and cospi, whose argument
 * reduction is exact and cheap (PoCL's sin reduces by a multiple-precision
 * π: most of a lanczos splat's cost); on the host, in double. */
#ifdef __OPENCL_VERSION__
#define st_sinpi(x) sinpi(x)
#define st_cospi(x) cospi(x)
#else
static inline st_f32 st_sinpi(st_f32 x)
{
    return (st_f32)sin(3.14159265358979323846 * (double)x);
}
static inline st_f32 st_cospi(st_f32 x)
{
    return (st_f32)cos(3.14159265358979323846 * (double)x);
}
#endif

/* Lanczos' turn from one tap to the next of sin(π x / τ): the sine and
 * cosine of δ = π / τ, the same for every sample of a render, so a splat
 * kernel makes them once (st_lanczos_turn_of); zero for other filters,
 * which do not use it. */
typedef struct st_lanczos_turn {
    st_f32 s, c;
} st_lanczos_turn;

ST_FN st_lanczos_turn st_lanczos_turn_of(const st_filter *f)
{
    st_lanczos_turn t = {0.0f, 0.0f};
    if (f->kind == ST_FILTER_LANCZOS) {
        st_f32 d = 1.0f / f->tau;
        t.s = st_sinpi(d);
        t.c = st_cospi(d);
    }
    return t;
}

/* Lanczos' factors sinc(x_k) and sinc(x_k / τ) at the taps x_k = x_c + j of
 * one axis (st_filter_taps), j = k - c, from the tap c nearest 0: sin(π x_k) =
 * (-1)^j sin(π x_c), and sin(π x_k / τ) = sin(a + j δ), a = π x_c / τ,
 * δ = π / τ, turning (sin, cos) through ±δ (t) once per tap. Three sines
 * per axis where two per tap were. Starting at the tap nearest 0 keeps the
 * relative accuracy where sinc divides by a small x; the turns' rounding
 * adds about an ulp per tap (test_filter_kernels.c: within 1e-5 of the formula). */
ST_HOT st_f32 st_lanczos_tap(const st_filter *f, st_f32 x, st_f32 s1, st_f32 s2)
{
    st_f32 ax = fabs(x), y = x / f->tau;
    if (!(ax <= f->radius))
        return 0.0f;
    st_f32 a = ax < 1e-5f ? 1.0f : s1 / (ST_PI_F * x);
    st_f32 b = fabs(y) < 1e-5f ? 1.0f : s2 / (ST_PI_F * y);
    return a * b;
}

ST_FN void st_lanczos_taps(const st_filter *f, st_lanczos_turn t, const st_f32 *x, int n, int c,
                           st_f32 *w)
{
    st_f32 a = x[c] / f->tau, s1 = st_sinpi(x[c]);
    st_f32 sa = st_sinpi(a), ca = st_cospi(a);
    for (int dir = -1; dir <= 1; dir += 2) {
        st_f32 s2 = sa, c2 = ca, sk = s1;
        for (int k = c; k >= 0 && k < n; k += dir) {
            w[k] = st_lanczos_tap(f, x[k], sk, s2);
            st_f32 next = s2 * t.c + (st_f32)dir * c2 * t.s;
            c2 = c2 * t.c - (st_f32)dir * s2 * t.s;
            s2 = next;
            sk = -sk;
        }
    }
}

/* The 1-D weights of all n > 0 taps of one axis: w[k] = f(x_k) at the pixel
 * centres lo + k + 1/2 of a sample at s, x_k = lo + k + 1/2 - s (n <=
 * ST_MAX_TAPS), with lanczos' turn t (st_lanczos_turn_of(f)). Every splat
 * path (film.cl) takes its weights from here, so the paths add the same
 * integers. The same values as st_filter_eval_1d per tap, but for lanczos
 * (st_lanczos_taps: within float rounding). */
ST_FN void st_filter_taps(const st_filter *f, st_lanczos_turn t, int lo, int n, st_f32 s,
                          st_f32 *w)
{
    st_f32 r = f->radius;
    switch (f->kind) {
    case ST_FILTER_BOX: /* st_filter_eval_1d's box, without its call per tap */
        for (int k = 0; k < n; k++)
            w[k] = fabs((st_f32)(lo + k) + 0.5f - s) <= r ? 1.0f : 0.0f;
        return;
    case ST_FILTER_MITCHELL:
    case ST_FILTER_CATMULL_ROM: {
        /* st_filter_eval_1d's expression, without its call and switch per tap */
        int m = f->kind == ST_FILTER_MITCHELL;
        st_f32 b = m ? f->b : 0.0f, c = m ? f->c : 0.5f;
        for (int k = 0; k < n; k++) {
            st_f32 ax = fabs((st_f32)(lo + k) + 0.5f - s);
            w[k] = ax <= r ? st_mitchell_1d(2.0f * ax / r, b, c) : 0.0f;
        }
        return;
    }
    case ST_FILTER_LANCZOS: {
        st_f32 x[ST_MAX_TAPS];
        for (int k = 0; k < n; k++)
            x[k] = (st_f32)(lo + k) + 0.5f - s;
        /* the tap nearest 0 (of two, the first): the pixel whose centre is
         * nearest s, ceil(s) - 1, or the end of the range nearest it (x_k
         * is exact there; only a pixel left of 0 could round into a tie);
         * ceil(s) as truncation, plus one where that fell below s (a call
         * with tests of large and special values on the device) */
        int c = (int)s + ((st_f32)(int)s < s) - 1 - lo;
        c = c < 0 ? 0 : c >= n ? n - 1 : c;
        st_lanczos_taps(f, t, x, n, c, w);
        return;
    }
    default:
        for (int k = 0; k < n; k++)
            w[k] = st_filter_eval_1d(f, (st_f32)(lo + k) + 0.5f - s);
    }
}

/* st_filter_taps with the filter's own turn (a caller with a single sample). */
ST_FN void st_filter_taps_1d(const st_filter *f, int lo, int n, st_f32 s, st_f32 *w)
{
    if (n > 0)
        st_filter_taps(f, st_lanczos_turn_of(f), lo, n, s, w);
}

ST_FN st_f32 st_filter_eval(const st_filter *f, st_f32 x, st_f32 y)
{
    return st_filter_eval_1d(f, x) * st_filter_eval_1d(f, y);
}

#endif
