/* filter_lanes.h — the 1-D weights of a filter's taps, written once over
 * ST_N lanes (lanes.h), each lane one sample's axis; filters.h includes it
 * once per width it needs, with ST_N defined, and gets st_mitchell_1d<N>,
 * st_lanczos_tap<N> and st_filter_taps<N>:
 *   1: the host's C, and a kernel's splat of one sample (the reference);
 *   ST_W: a kernel's splat of ST_W samples at once (film.cl).
 * A lane of any width computes what width 1 computes, with the same
 * operations in the same statements (OpenCL contracts a * b + c into fma
 * within a statement, so the statements must match too): a value that is
 * the same in every lane (the filter's parameters) is broadcast before
 * it takes part in lane arithmetic (clang contracts a scalar product added
 * to lanes differently), which changes no lane's arithmetic, and a branch of width 1 is a select of both
 * arms. So the film's integers do not depend on the width
 * (test_render_paths.c, test_packets_cli.sh). No include guard: one copy
 * per ST_N. */
#ifndef ST_N
#error "define ST_N (the lane count) before including filter_lanes.h"
#endif

#define ST_F ST_VEC(float, ST_N)
#define ST_I ST_VEC(int, ST_N)

/* Mitchell and Netravali's cubic k_{B,C}(t) (filters.h's formula), t >= 0,
 * both pieces computed and the one of each lane selected. B and C come in
 * lanes: a product of two scalars added to lanes would not be contracted
 * into an fma as width 1 contracts it. */
ST_HOT ST_F ST_CAT(st_mitchell_1d, ST_N)(ST_F t, ST_F b, ST_F c)
{
    ST_F near = ((12.0f - 9.0f * b - 6.0f * c) * t * t * t +
                 (-18.0f + 12.0f * b + 6.0f * c) * t * t + (6.0f - 2.0f * b)) *
                (1.0f / 6.0f);
    /* the second piece has a double root at t = 2: in factored form,
     * 6k(t) = (2 - t)^2 ((-B-6C) t + 2B + 6C), it keeps its relative accuracy
     * near t = 2 (the expanded sum of terms near 100 cancelled to errors of
     * 6e-6: test_filter_kernels.c filters_match_formulas) */
    ST_F u = 2.0f - t;
    ST_F far = u * u * ((-b - 6.0f * c) * t + 2.0f * b + 6.0f * c) * (1.0f / 6.0f);
    ST_F k = ST_SELECT(ST_N, (ST_F)(0.0f), far, t < 2.0f);
    return ST_SELECT(ST_N, k, near, t < 1.0f);
}

/* The Gaussian exp(k x²) - exp(k r²) (filters.h), k = -1 / 2σ², at ax =
 * |x| <= r (on the host in double, as C's exp computes it: the host's
 * filter tables depend on these bits). In lanes each lane's exp is its
 * own: PoCL's exp of a vector differs from its exp of one float in the
 * last bit, and a lane must compute at every width what it computes at
 * width 1. */
ST_HOT ST_F ST_CAT(st_gaussian_1d, ST_N)(ST_F ax, st_f32 k, st_f32 r)
{
#if ST_N == 1
    return exp(k * ax * ax) - exp(k * r * r);
#else
    st_f32 e[ST_N];
    ST_VSTORE(ST_N, k * ax * ax, e);
    for (int l = 0; l < ST_N; l++)
        e[l] = exp(e[l]);
    return ST_VLOAD(ST_N, e) - exp(k * r * r);
#endif
}

/* The Blackman-Harris window (filters.h) at ax = |x| <= r: the window is
 * even, and f(-x) == f(x) must hold bit for bit. With c = cos t, cos 2t =
 * 2c² - 1 and cos 3t = 4c³ - 3c make a0 - a1 c + a2 cos 2t - a3 cos 3t the
 * cubic (a0 - a2) + (3 a3 - a1) c + 2 a2 c² - 4 a3 c³: one cosine, not
 * three (PoCL's cosine is most of the window's cost). */
ST_HOT ST_F ST_CAT(st_blackman_harris_1d, ST_N)(ST_F ax, st_f32 r)
{
    const st_f32 a0 = 0.35875f, a1 = 0.48829f, a2 = 0.14128f, a3 = 0.01168f;
    ST_F c = cos(2.0f * ST_PI_F * (ax + r) / (2.0f * r));
    return ((-4.0f * a3 * c + 2.0f * a2) * c + (3.0f * a3 - a1)) * c + (a0 - a2);
}

/* Lanczos' weight sinc(x) sinc(x / τ) at a tap x from s1 = sin(π x) and
 * s2 = sin(π x / τ) (st_lanczos_taps<N> turns them from tap to tap); 0
 * beyond the radius. */
ST_HOT ST_F ST_CAT(st_lanczos_tap, ST_N)(const st_filter *f, ST_F x, ST_F s1, ST_F s2)
{
    ST_F ax = fabs(x), y = x / f->tau;
    ST_F a = ST_SELECT(ST_N, s1 / (ST_PI_F * x), (ST_F)(1.0f), ax < 1e-5f);
    ST_F b = ST_SELECT(ST_N, s2 / (ST_PI_F * y), (ST_F)(1.0f), fabs(y) < 1e-5f);
    return ST_SELECT(ST_N, (ST_F)(0.0f), a * b, ax <= f->radius);
}

/* The offset x_k = lo + k + 1/2 - s of tap k from the sample at s. */
ST_HOT ST_F ST_CAT(st_tap_offset, ST_N)(ST_I lo, int k, ST_F s)
{
    return ST_CONVERT(float, ST_N, lo + k) + 0.5f - s;
}

/* floor(v) and ceil(v), exactly, for v within int's range: truncation,
 * stepped by one where it went the wrong way. A few vector instructions,
 * where PoCL's floor and ceil test each lane for large and special values. */
ST_HOT ST_I ST_CAT(st_floor_int, ST_N)(ST_F v)
{
    ST_I t = ST_CONVERT(int, ST_N, v);
    return ST_SELECT(ST_N, t, t - 1, ST_CONVERT(float, ST_N, t) > v);
}

ST_HOT ST_I ST_CAT(st_ceil_int, ST_N)(ST_F v)
{
    ST_I t = ST_CONVERT(int, ST_N, v);
    return ST_SELECT(ST_N, t, t + 1, ST_CONVERT(float, ST_N, t) < v);
}

/* The taps of ST_N samples' axes at s: the pixels k whose centre lies in
 * the filter's closed support, |k + 1/2 - s| <= r, within [0, n), from *lo
 * to *hi (none where *hi < *lo). The ends are estimated, then moved by one
 * where the offset as st_tap_offset computes it says otherwise (the
 * estimate's own rounding may cross an integer, either way). */
ST_HOT void ST_CAT(st_tap_range, ST_N)(ST_F s, st_f32 r, int n, ST_I *lo, ST_I *hi)
{
    ST_F rl = (ST_F)(r);
    ST_I a = ST_CAT(st_ceil_int, ST_N)(s - rl - 0.5f);
    ST_I b = ST_CAT(st_floor_int, ST_N)(s + rl - 0.5f);
    ST_I a1 = ST_SELECT(ST_N, a, a + 1, ST_CAT(st_tap_offset, ST_N)(a, 0, s) < -rl);
    ST_I b1 = ST_SELECT(ST_N, b, b - 1, ST_CAT(st_tap_offset, ST_N)(b, 0, s) > rl);
    a1 = ST_SELECT(ST_N, a1, a1 - 1, ST_CAT(st_tap_offset, ST_N)(a, -1, s) >= -rl);
    b1 = ST_SELECT(ST_N, b1, b1 + 1, ST_CAT(st_tap_offset, ST_N)(b, 1, s) <= rl);
    *lo = ST_SELECT(ST_N, a1, (ST_I)(0), a1 < 0);
    *hi = ST_SELECT(ST_N, b1, (ST_I)(n - 1), b1 > n - 1);
}

/* One turn of sin(π x / τ) (*s2, with its cosine *c2) by dir δ (t: δ's
 * sine and cosine), and of sin(π x) (*sk) by a half turn, in the lanes of
 * `on`; the others keep theirs. */
ST_HOT void ST_CAT(st_lanczos_turn_lanes, ST_N)(st_lanczos_turn t, st_f32 dir, ST_I on, ST_F *s2,
                                                ST_F *c2, ST_F *sk)
{
    ST_F next = *s2 * t.c + dir * *c2 * t.s;
    ST_F c2n = *c2 * t.c - dir * *s2 * t.s;
    *s2 = ST_SELECT(ST_N, *s2, next, on);
    *c2 = ST_SELECT(ST_N, *c2, c2n, on);
    *sk = ST_SELECT(ST_N, *sk, -*sk, on);
}

/* Lanczos' factors sinc(x_k) and sinc(x_k / τ) at taps 0 .. m - 1, from
 * each lane's tap c nearest 0, j = k - c: sin(π x_k) = (-1)^j sin(π x_c),
 * and sin(π x_k / τ) = sin(a + j δ), a = π x_c / τ, δ = π / τ, turning (sin,
 * cos) through ±δ (t) once per tap away from c. Three sines per axis where
 * two per tap were. Starting at the tap nearest 0 keeps the relative
 * accuracy where sinc divides by a small x; the turns' rounding adds about
 * an ulp per tap (test_filter_kernels.c: within 1e-5 of the formula).
 * The turns down from c and up from c are two chains of dependent
 * products, run side by side in one loop, each from the lanes' outermost
 * c: a lane not yet at its own c keeps its sines (select), so it takes
 * the same turns in the same order however far the loop runs. */
ST_FN void ST_CAT(st_lanczos_taps, ST_N)(const st_filter *f, st_lanczos_turn t, ST_I lo,
                                         ST_I n, int m, ST_F s, st_f32 *w)
{
    /* the tap nearest 0 (of two, the first): the pixel whose centre is
     * nearest s, ceil(s) - 1, or the end of the range nearest it (x_k
     * is exact there; only a pixel left of 0 could round into a tie);
     * ceil(s) as truncation, plus one where that fell below s (a call
     * with tests of large and special values on the device) */
    ST_I ts = ST_CONVERT(int, ST_N, s);
    ST_I c = ts + ST_SELECT(ST_N, (ST_I)(0), (ST_I)(1), ST_CONVERT(float, ST_N, ts) < s) - 1 - lo;
    c = ST_SELECT(ST_N, c, (ST_I)(0), c < 0);
    c = ST_SELECT(ST_N, c, n - 1, c >= n);
    ST_F xc = ST_CONVERT(float, ST_N, lo + c) + 0.5f - s;
    ST_F a = xc / f->tau, s1 = st_sinpi(xc);
    ST_F sa = st_sinpi(a), ca = st_cospi(a);
    /* the lanes' c span c_lo .. c_hi (a lane of no taps has c = -1) */
    ST_F cf = ST_CONVERT(float, ST_N, c);
    int c_lo = (int)ST_HMIN(ST_N, cf), c_hi = (int)ST_HMAX(ST_N, cf);
    c_lo = c_lo < 0 ? 0 : c_lo;
    c_hi = c_hi > m - 1 ? m - 1 : c_hi;
    int steps = c_hi + 1 > m - c_lo ? c_hi + 1 : m - c_lo;
    ST_F s2d[ST_MAX_TAPS], s1d[ST_MAX_TAPS], s2u[ST_MAX_TAPS], s1u[ST_MAX_TAPS];
    ST_F d2 = sa, dc = ca, dk = s1, u2 = sa, uc = ca, uk = s1;
    for (int j = 0; j < steps; j++) {
        int kd = c_hi - j, ku = c_lo + j;
        if (kd >= 0) { /* down: lanes at or below their c */
            s2d[kd] = d2;
            s1d[kd] = dk;
            ST_CAT(st_lanczos_turn_lanes, ST_N)(t, -1.0f, (ST_I)(kd) <= c, &d2, &dc, &dk);
        }
        if (ku < m) { /* up: lanes at or above their c */
            s2u[ku] = u2;
            s1u[ku] = uk;
            ST_CAT(st_lanczos_turn_lanes, ST_N)(t, 1.0f, (ST_I)(ku) >= c, &u2, &uc, &uk);
        }
    }
    for (int k = 0; k < m; k++) {
        /* below c_lo only the turns down reached k, above c_hi only those up */
        ST_I up = (ST_I)(k) >= c;
        ST_F s1k = k < c_lo ? s1d[k] : k > c_hi ? s1u[k] : ST_SELECT(ST_N, s1d[k], s1u[k], up);
        ST_F s2k = k < c_lo ? s2d[k] : k > c_hi ? s2u[k] : ST_SELECT(ST_N, s2d[k], s2u[k], up);
        ST_VSTORE(ST_N,
                  ST_CAT(st_lanczos_tap, ST_N)(f, ST_CAT(st_tap_offset, ST_N)(lo, k, s), s1k, s2k),
                  w + k * ST_N);
    }
}

/* The 1-D weights of taps 0 .. m - 1 of ST_N samples' axes, lane l a
 * sample at s_l whose taps are the pixel centres lo_l + k + 1/2 (k < n_l <=
 * m <= ST_MAX_TAPS): w[k ST_N + l] = f(x_k), x_k = lo_l + k + 1/2 - s_l, with
 * lanczos' turn t (st_lanczos_turn_of(f)). A lane's weights past its n_l
 * are whatever the formula gives there. Every splat path (film.cl) takes its
 * weights from here, so the paths add the same integers. The same values as
 * st_filter_eval_1d per tap, but for lanczos (st_lanczos_taps<N>: within
 * float rounding). Every filter's taps are made in lanes, the Gaussian's
 * exp alone lane by lane (st_gaussian_1d<N>); PoCL's cos of a vector gives
 * each lane what it gives one float (splat_lanes_at_every_width). */
ST_FN void ST_CAT(st_filter_taps, ST_N)(const st_filter *f, st_lanczos_turn t, ST_I lo, ST_I n,
                                        int m, ST_F s, st_f32 *w)
{
    st_f32 r = f->radius;
    switch (f->kind) {
    case ST_FILTER_BOX: /* st_filter_eval_1d's box, without its call per tap */
        for (int k = 0; k < m; k++)
            ST_VSTORE(ST_N,
                      ST_SELECT(ST_N, (ST_F)(0.0f), (ST_F)(1.0f),
                                fabs(ST_CAT(st_tap_offset, ST_N)(lo, k, s)) <= r),
                      w + k * ST_N);
        return;
    case ST_FILTER_MITCHELL:
    case ST_FILTER_CATMULL_ROM: {
        /* st_filter_eval_1d's expression, without its call and switch per tap */
        int mi = f->kind == ST_FILTER_MITCHELL;
        st_f32 b = mi ? f->b : 0.0f, c = mi ? f->c : 0.5f;
        for (int k = 0; k < m; k++) {
            ST_F ax = fabs(ST_CAT(st_tap_offset, ST_N)(lo, k, s));
            ST_F v = ST_CAT(st_mitchell_1d, ST_N)(2.0f * ax / r, (ST_F)(b), (ST_F)(c));
            ST_VSTORE(ST_N, ST_SELECT(ST_N, (ST_F)(0.0f), v, ax <= r), w + k * ST_N);
        }
        return;
    }
    case ST_FILTER_LANCZOS:
        ST_CAT(st_lanczos_taps, ST_N)(f, t, lo, n, m, s, w);
        return;
    default: {
        /* the others, st_filter_eval_1d's expressions without its call and
         * switch per tap: each lane's tap a select of its formula and 0 */
        st_f32 g = f->kind == ST_FILTER_GAUSSIAN ? -0.5f / (f->sigma * f->sigma) : 0.0f;
        for (int k = 0; k < m; k++) {
            ST_F ax = fabs(ST_CAT(st_tap_offset, ST_N)(lo, k, s)), v = (ST_F)(0.0f);
            if (f->kind == ST_FILTER_TRIANGLE)
                v = r - ax;
            else if (f->kind == ST_FILTER_GAUSSIAN)
                v = ST_CAT(st_gaussian_1d, ST_N)(ax, g, r);
            else if (f->kind == ST_FILTER_BLACKMAN_HARRIS)
                v = ST_CAT(st_blackman_harris_1d, ST_N)(ax, r);
            ST_VSTORE(ST_N, ST_SELECT(ST_N, (ST_F)(0.0f), v, ax <= r), w + k * ST_N);
        }
    }
    }
}

#undef ST_F
#undef ST_I
