/* spectrum.c — the Fourier view of a point set: its periodogram
 *   P(k) = |sum_j exp(-2 pi i k . x_j)|^2 / N,  k integer in [-kmax, kmax]^2,
 * and the radial average of P over rings |k| ~ b. For a uniform random set
 * E[P(k)] = 1 at every k != 0; a good sampling pattern (Poisson disk,
 * best-candidate) shows a dark ring of low power around the DC spike at k = 0
 * (Mitchell, "Spectrally Optimal Sampling for Distribution Ray Tracing",
 * SIGGRAPH 1991; Ulichney, "Digital Halftoning", 1987, for the radial mean).
 *
 * Invariant: the sum is direct and in double, so P is exact up to rounding;
 * results are ADDED to the caller's array, never overwritten. Tests:
 * tests/unit/test_sampling_point_sets.c spectrum_*. */
#include "st_sampling.h"

#include <math.h>
#include <stdlib.h>

#define TWO_PI 6.283185307179586

/* e[t] = exp(-2 pi i t x) for t = 0..kmax, by the recurrence
 * e[t] = e[t-1] * e[1]: one cos/sin per point and axis instead of one per k.
 * The relative error grows like t * 1e-16. */
static void phase_powers(double x, st_u32 kmax, double *re, double *im)
{
    double c = cos(TWO_PI * x), s = -sin(TWO_PI * x);
    re[0] = 1.0;
    im[0] = 0.0;
    for (st_u32 t = 1; t <= kmax; ++t) {
        re[t] = re[t - 1] * c - im[t - 1] * s;
        im[t] = re[t - 1] * s + im[t - 1] * c;
    }
}

/* Adds one point to the half spectrum F(kx, ky), ky = 0..kmax, kx = -kmax..kmax
 * (row-major, width 2kmax+1): F += exp(-2 pi i kx x) * exp(-2 pi i ky y). The
 * x powers for negative kx are the conjugates of the positive ones. */
static void add_point(const double *xr, const double *xi, const double *yr, const double *yi,
                      st_u32 kmax, double *fr, double *fi)
{
    st_u32 w = 2 * kmax + 1;
    for (st_u32 ky = 0; ky <= kmax; ++ky) {
        double cr = yr[ky], ci = yi[ky];
        double *rr = fr + (size_t)ky * w + kmax, *ri = fi + (size_t)ky * w + kmax;
        for (st_u32 t = 0; t <= kmax; ++t) { /* kx = +t */
            rr[t] += cr * xr[t] - ci * xi[t];
            ri[t] += cr * xi[t] + ci * xr[t];
        }
        for (st_u32 t = 1; t <= kmax; ++t) { /* kx = -t: conj(x^t) */
            rr[-(st_i64)t] += cr * xr[t] + ci * xi[t];
            ri[-(st_i64)t] += ci * xr[t] - cr * xi[t];
        }
    }
}

st_status st_spectrum_periodogram(const float *pts, st_u32 n, st_u32 stride, st_u32 kmax,
                                  double *power, st_error *err)
{
    if (!pts || !power)
        return st_fail(err, ST_ERR_USAGE, "periodogram: NULL points or output");
    if (n == 0)
        return st_fail(err, ST_ERR_USAGE, "periodogram: no points");
    if (stride < 2)
        return st_fail(err, ST_ERR_USAGE, "periodogram: stride %u < 2 floats per point", stride);
    if (kmax > ST_SPECTRUM_KMAX_MAX)
        return st_fail(err, ST_ERR_USAGE, "periodogram: kmax %u exceeds %u", kmax,
                       ST_SPECTRUM_KMAX_MAX);

    st_u32 w = 2 * kmax + 1;
    size_t half = (size_t)(kmax + 1) * w;
    double *fr = calloc(half, sizeof *fr), *fi = calloc(half, sizeof *fi);
    double *pw = malloc(4 * ((size_t)kmax + 1) * sizeof *pw);
    if (!fr || !fi || !pw) {
        free(fr);
        free(fi);
        free(pw);
        return st_fail(err, ST_ERR_NOMEM, "periodogram: out of memory for kmax %u", kmax);
    }
    double *xr = pw, *xi = xr + kmax + 1, *yr = xi + kmax + 1, *yi = yr + kmax + 1;
    for (st_u32 j = 0; j < n; ++j) {
        phase_powers(pts[(size_t)j * stride], kmax, xr, xi);
        phase_powers(pts[(size_t)j * stride + 1], kmax, yr, yi);
        add_point(xr, xi, yr, yi, kmax, fr, fi);
    }
    /* P(k) for ky >= 0; P(-k) = P(k) since F(-k) = conj F(k) for real points. */
    for (st_u32 ky = 0; ky <= kmax; ++ky)
        for (st_u32 c = 0; c < w; ++c) {
            size_t h = (size_t)ky * w + c;
            double p = (fr[h] * fr[h] + fi[h] * fi[h]) / n;
            power[(size_t)(kmax + ky) * w + c] += p;
            if (ky > 0)
                power[(size_t)(kmax - ky) * w + (w - 1 - c)] += p;
        }
    free(fr);
    free(fi);
    free(pw);
    return ST_OK;
}

void st_spectrum_radial(const double *power, st_u32 kmax, double *radial, st_u32 *counts)
{
    st_u32 w = 2 * kmax + 1;
    for (st_u32 b = 0; b <= kmax; ++b) {
        radial[b] = 0.0;
        counts[b] = 0;
    }
    for (st_u32 r = 0; r < w; ++r)
        for (st_u32 c = 0; c < w; ++c) {
            double kx = (double)c - kmax, ky = (double)r - kmax;
            /* |k|^2 is an integer, never (b + 1/2)^2: no ties to round. */
            st_u32 b = (st_u32)floor(sqrt(kx * kx + ky * ky) + 0.5);
            if (b <= kmax) {
                radial[b] += power[(size_t)r * w + c];
                counts[b]++;
            }
        }
    for (st_u32 b = 0; b <= kmax; ++b)
        radial[b] /= counts[b]; /* >= 1: k = (b, 0) is in bin b */
}
