/* st_filter.h — the reconstruction filter as a concept: its names and
 * defaults, the check of its parameters, and what the host derives from its
 * profile f(x) (kernels/film/filters.h: st_filter_eval_1d, the very code the splat
 * kernel runs): the integral ∫ f, the importance-sampling table of |f|,
 * samples of the profile and the frequency response. The renderer
 * (render.c), the filter lab (`strata filter`) and the 1-D signal lab
 * (signal.c) all call this module, so what the lab shows is what renders.
 *
 * Filters are separable, f(x, y) = f(x) f(y), and 0 for |x| >= r; everything
 * here is per axis (the 2-D integral ∫∫ f is the square of the 1-D one). An
 * st_filter is a plain value (st_shared.h). Nothing here allocates or prints;
 * the check returns ST_ERR_USAGE with a message naming the field
 * ("filter radius 9: must be in [0.0625, 8]"), which the CLI may rewrite as the
 * option that sets it.
 *
 * Tests: tests/unit/test_filter.c (integral, FIS table, profile, response, check);
 * tests/unit/test_filter_kernels.c guards the evaluation in kernels/film/filters.h. */
#ifndef ST_FILTER_H
#define ST_FILTER_H

#include "st_error.h"
#include "st_shared.h"

/* Names, indexed by ST_FILTER_*. */
extern const char *const st_filter_names[ST_FILTER_COUNT];
/* The ST_FILTER_* of a name, or -1. */
int st_filter_lookup(const char *name);

/* A filter of the given kind with its default radius and parameters
 * (B = C = 1/3, σ = 0.5, τ = r). */
st_filter st_filter_default(st_u32 kind);

/* The parameters a kind reads besides its radius (a mask of the bits below),
 * so a front end can refuse one that would be ignored. */
#define ST_FILTER_USES_BC 1u    /* mitchell: b, c */
#define ST_FILTER_USES_SIGMA 2u /* gaussian */
#define ST_FILTER_USES_TAU 4u   /* lanczos */
st_u32 st_filter_parameters(st_u32 kind);

/* The parameter ranges st_filter_check accepts (pixels for r, σ, τ). Inside
 * them every filter has ∫|f| > 0, even at the importance-sampling table's bin
 * centres (a NaN table otherwise: a Gaussian with σ >> r is 0 in float
 * everywhere), and |f| stays small enough for the film's fixed point: B and C
 * span Mitchell and Netravali's own parameter square (any value was once
 * accepted; B = -1572861 made weights that wrapped the film's Σf).
 * Tests: test_filter.c filter_check_*, filter_fis_cdf_finite_at_range_corners. */
#define ST_FILTER_MIN_RADIUS 0.0625f
#define ST_FILTER_BC_MIN 0.0f
#define ST_FILTER_BC_MAX 1.0f
#define ST_FILTER_SIGMA_MIN 0.015625f
#define ST_FILTER_SIGMA_MAX 16.0f
#define ST_FILTER_TAU_MIN 0.0625f
#define ST_FILTER_TAU_MAX 64.0f

/* Checks kind, radius in [ST_FILTER_MIN_RADIUS, max_radius] (the renderer
 * passes ST_FILTER_MAX_RADIUS, its splat kernel's limit; the signal lab its
 * own) and the parameters the kind reads, each in its range above.
 * ST_ERR_USAGE naming the field and the range ("filter b -2: must be in
 * [0, 1]"): "filter kind", "filter radius", "filter b", "filter c",
 * "filter sigma", "filter tau". */
st_status st_filter_check(const st_filter *f, float max_radius, st_error *err);

/* ∫_{-r}^{r} f(x) dx by the midpoint rule over 2^16 intervals (the kinks of
 * triangle and mitchell sit on interval ends; measured against closed forms:
 * relative error < 1e-6). Signal's convolution mode divides by it. */
double st_filter_integral(const st_filter *f);

/* The table of filter importance sampling: cdf[0] = 0, cdf[ST_FIS_BINS] = 1,
 * and cdf[i + 1] - cdf[i] the share of ∫|f| in bin i of ST_FIS_BINS equal
 * bins of [-r, r], by one midpoint sample per bin (pbrt-v4's FilterSampler
 * tabulates |f| the same way). cdf holds ST_FIS_BINS + 1 floats. The
 * generate kernel inverts it (generate.cl). */
void st_filter_fis_cdf(const st_filter *f, float *cdf);

/* n >= 2 samples of the profile: x[i] = -r + 2 r i / (n - 1), y[i] = f(x[i]). */
void st_filter_profile(const st_filter *f, st_u32 n, double *x, double *y);

/* The Fourier transform F(ω) = ∫ f(x) e^{-2πiωx} dx at ω cycles per pixel
 * (f is even: ∫ f(x) cos(2πωx) dx), by Simpson's rule over [-r, r] with 4096
 * intervals; the support is open at ±r, so an end takes the limit of f from
 * inside (1 for the box). F(0) is the integral. */
double st_filter_transform(const st_filter *f, double omega);

/* |F(ω)| / |F(0)| at the n frequencies omega[i]: the response normalised so
 * the pass band starts at 1 (the Nyquist frequency of the pixel grid is 1/2). */
void st_filter_response(const st_filter *f, st_u32 n, const double *omega, double *magnitude);

#endif
