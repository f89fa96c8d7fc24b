/* st_filter_lab.h — a reconstruction filter seen as a signal: its profile
 * f(x) over [-r, r] and its frequency response |F(ω)| (the continuous Fourier
 * transform, F(ω) = ∫ f(x) e^{-2πiωx} dx, normalised by F(0) so the pass band
 * starts at 1), evaluated from the same st_filter_eval_1d the splat kernel
 * runs. Frequencies are in cycles per pixel: the Nyquist frequency of the
 * pixel grid is 1/2. Tests: tests/test_filter_lab.c. */
#ifndef ST_FILTER_LAB_H
#define ST_FILTER_LAB_H

#include "st_error.h"
#include "st_shared.h"

/* n >= 2 samples of the profile: x[i] = -r + 2 r i / (n - 1), y[i] = f(x[i]). */
void st_filter_profile(const st_filter *f, st_u32 n, double *x, double *y);

/* |F(ω)| / |F(0)| at the n frequencies omega[i], by Simpson's rule over
 * [-r, r] with 4096 intervals (f is even: F(ω) = ∫ f(x) cos(2πωx) dx; the
 * kinks of triangle and mitchell sit on interval ends for these counts). */
void st_filter_response(const st_filter *f, st_u32 n, const double *omega, double *magnitude);

#endif
