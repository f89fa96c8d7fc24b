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

#include "lanes.h"

ST_FN st_f32 st_sinc(st_f32 x)
{
    if (fabs(x) < 1e-5f)
        return 1.0f;
    return sin(ST_PI_F * x) / (ST_PI_F * x);
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

/* f(x) of filter f, one axis (below). */
ST_FN st_f32 st_filter_eval_1d(const st_filter *f, st_f32 x);

/* The taps' weights in lanes (filter_lanes.h): width 1 for the host and a
 * kernel's one sample, and the kernels' ST_W. */
#define ST_N 1
#include "filter_lanes.h"
#undef ST_N
#if ST_W != 1
#define ST_N ST_W
#include "filter_lanes.h"
#undef ST_N
#endif

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
        return st_gaussian_1d1(ax, k, r);
    }
    case ST_FILTER_MITCHELL:
        return st_mitchell_1d1(2.0f * ax / r, f->b, f->c);
    case ST_FILTER_CATMULL_ROM:
        return st_mitchell_1d1(2.0f * ax / r, 0.0f, 0.5f);
    case ST_FILTER_LANCZOS:
        return st_sinc(ax) * st_sinc(ax / f->tau);
    case ST_FILTER_BLACKMAN_HARRIS:
        return st_blackman_harris_1d1(ax, r);
    default:
        return 0.0f;
    }
}

/* st_filter_taps1 with the filter's own turn (a caller with a single sample). */
ST_FN void st_filter_taps_1d(const st_filter *f, int lo, int n, st_f32 s, st_f32 *w)
{
    if (n > 0)
        st_filter_taps1(f, st_lanczos_turn_of(f), lo, n, n, s, w);
}

ST_FN st_f32 st_filter_eval(const st_filter *f, st_f32 x, st_f32 y)
{
    return st_filter_eval_1d(f, x) * st_filter_eval_1d(f, y);
}

#endif
