/* st_signal.h — the 1-D sampling and reconstruction laboratory (`strata
 * signal`), after the lecture "Sampling and reconstruction" (Computer
 * Graphics I, lecture 11, ShanghaiTech) and pbr-book 4ed §8.1:
 *
 *   sampling        III_T(x) f(x) = Σ_i δ(x - x_i) f(x_i),  x_i = (i + o) T
 *   its spectrum    F(ν) ⊗ III_{1/T}(ν): copies of F every 1/T; Nyquist 1/(2T)
 *   ideal           f~(x) = Σ_i sinc((x - x_i)/T) f(x_i),  sinc(u) = sin(πu)/(πu)
 *   finite filter   f~(x) = Σ_i r((x - x_i)/T) f(x_i) / Σ_i r((x - x_i)/T)
 *   jittered        x_i = (i + ξ_i) T, ξ_i uniform in [0, 1): a sine's samples
 *                   keep E[sin(2π f x_i)] = sinc(f T) sin(2π f (i + 1/2) T) of it,
 *                   so an alias shrinks by |sinc(f T)| and the rest turns into
 *                   noise spread over every frequency (the lecture: jitter turns
 *                   aliasing into noise)
 *                   (the weighted average the renderer's film computes), or the
 *                   lecture's convolution Σ_i r((x - x_i)/T) f(x_i) / ∫ r(u) du
 *
 * r is any of strata's filters (kernels/film/filters.h, the splat kernel's own
 * st_filter_eval_1d) with radius, sigma and tau in units of the sample
 * spacing T. A sine of frequency f sampled below the Nyquist rate (f > 1/(2T))
 * comes back at the alias frequency |f - k/T|, k = round(f T).
 *
 * Ends of the domain [0, L): samples are taken over a window wider than [0, L)
 * by `margin` samples on each side (a finite filter: ceil(radius) + 1, so every
 * point of [0, L) sees every sample its filter reaches; sinc: sinc_margin), so
 * [0, L) is all interior. The sinc sum is truncated to that window: the tail
 * of Σ sinc(u - i) f(x_i) left out is an oscillating series whose terms fall as
 * 1/(π |u - i|), so the truncation error is of the order 1/(π^2 M) for a
 * margin of M samples (tests/unit/test_signal.c states the bound it checks).
 *
 * Spectra are magnitudes of FFTW's DFT with a periodic Hann window
 * w_j = 1/2 - 1/2 cos(2πj/n) (Harris, "On the Use of Windows for Harmonic
 * Analysis with the DFT", Proc. IEEE 1978), two-sided and divided by Σ w_j:
 * a sine of amplitude A reads A/2 at ±f. The sampled signal's spectrum is the
 * DFT of the samples in [0, L), periodic in ν with period 1/T and shown over
 * as many periods as the dense spectrum covers (its copies every 1/T); the
 * division by Σ w_j makes it T |F{III_T f}|, so each copy is as tall as F.
 *
 * Ownership: st_signal_build fills an st_signal_result whose arrays are
 * malloc'ed; st_signal_result_free releases them. Nothing here prints.
 * Errors: ST_ERR_USAGE naming the option (--spacing, --points, ...) for bad
 * options, ST_ERR_NOMEM when memory runs out or FFTW cannot plan a transform.
 * Tests: tests/unit/test_signal.c, tests/cli/test_signal.sh. */
#ifndef ST_SIGNAL_H
#define ST_SIGNAL_H

#include "st_error.h"
#include "st_shared.h"

/* Functions of x (--function). */
#define ST_SIGNAL_SINE 0u   /* sin(2π f x + φ) */
#define ST_SIGNAL_SINES 1u  /* (1/K) Σ_k sin(2π f_k x + φ) */
#define ST_SIGNAL_CHIRP 2u  /* sin(2π (f0 x + (f1 - f0) x^2 / (2L)) + φ): frequency f0 at 0, f1 at L */
#define ST_SIGNAL_STEP 3u   /* 0 for x < edge, 1 for x >= edge */
#define ST_SIGNAL_SQUARE 4u /* +1 while frac(f x + φ/2π) < 1/2, else -1 */
#define ST_SIGNAL_FUNCTION_COUNT 5u
extern const char *const st_signal_function_names[ST_SIGNAL_FUNCTION_COUNT];

#define ST_SIGNAL_MAX_FREQS 16u
#define ST_SIGNAL_MAX_RADIUS 64.0f          /* largest filter radius, in units of T */
#define ST_SIGNAL_MAX_SAMPLES (1u << 24)    /* samples in the whole window */
#define ST_SIGNAL_MAX_POINTS (1u << 22)     /* dense points over [0, L) */
#define ST_SIGNAL_DEFAULT_SINC_MARGIN 16384u
#define ST_SIGNAL_MAX_WORK 4.0e9            /* points x window samples of a sinc sum */

typedef struct st_signal_function {
    st_u32 kind;                       /* ST_SIGNAL_* */
    double freq;                       /* sine, square: cycles per unit length */
    double phase;                      /* sine, sines, chirp, square: radians */
    double freqs[ST_SIGNAL_MAX_FREQS]; /* sines */
    st_u32 freq_count;
    double f0, f1;                     /* chirp */
    double edge;                       /* step */
    double length;                     /* L (the chirp's sweep length) */
} st_signal_function;

/* Reconstruction modes of a finite filter. */
#define ST_SIGNAL_AVERAGE 0u     /* Σ r f / Σ r: exact for constants */
#define ST_SIGNAL_CONVOLUTION 1u /* Σ r f / ∫ r (the lecture's (III_T f) ⊗ r) */

typedef struct st_signal_filter {
    int sinc;         /* nonzero: the ideal sinc sum over every sample (filter, mode unused) */
    st_filter filter; /* ST_FILTER_*; radius, sigma, tau in units of T */
    st_u32 mode;      /* ST_SIGNAL_AVERAGE or ST_SIGNAL_CONVOLUTION */
} st_signal_filter;

/* Samples: values[i] = f(x0 + (i + jitter[i]) * spacing), i = 0 .. count-1;
 * jitter NULL: uniform, f(x0 + i * spacing). */
typedef struct st_signal_samples {
    double x0, spacing;
    st_u32 count;
    const double *values;
    const double *jitter; /* each in [0, 1), or NULL */
} st_signal_samples;

typedef struct st_signal_options {
    st_signal_function fn;   /* fn.length is set from length */
    double length;           /* L > 0: the domain [0, L) */
    double spacing;          /* T > 0 */
    double offset;           /* o in [0, 1): samples at (i + o) T */
    int jitter;              /* nonzero: at (i + ξ_i) T instead, ξ_i uniform in [0, 1) from
                                a hash of (seed, i): jittered (stratified) sampling; offset 0 */
    st_u32 seed;             /* the jitter's */
    st_signal_filter recon;
    st_u32 points;           /* dense points P over [0, L); 0: automatic (see st_signal_check) */
    st_u32 sinc_margin;      /* samples beyond each end for sinc; 0: the default */
} st_signal_options;

typedef struct st_signal_result {
    /* dense grid x_j = j L / P, j = 0 .. P-1 */
    st_u32 points;
    double *x, *original, *reconstruction, *error; /* error = reconstruction - original */
    /* samples in [0, L): sample_x[i] = (i + o) T */
    st_u32 sample_count;
    double *sample_x, *sample_value, *sample_reconstruction;
    st_u32 margin;           /* window samples beyond each end of [0, L) */
    st_u32 zero_weight;      /* dense points whose Σ r was 0 (reconstruction NaN) */
    double rms_error, max_error; /* over the dense points with a reconstruction */
    /* spectra: dense bins k / L (k = 0 .. P/2); sampled bins k / (n T) */
    st_u32 bins;
    double *freq, *spectrum_original, *spectrum_reconstruction;
    st_u32 sampled_bins;
    double *sampled_freq, *spectrum_sampled;
    double dominant_original, dominant_reconstruction; /* cycles per unit length */
    double nyquist;          /* 1 / (2T) */
} st_signal_result;

/* The function's value at x (defined for every real x). */
double st_signal_eval(const st_signal_function *fn, double x);

/* Highest frequency the function holds (step: 0, square: its fundamental). */
double st_signal_max_frequency(const st_signal_function *fn);

/* The frequency a sine of frequency f shows after sampling at spacing T:
 * |f - k/T| with k = round(f T) (the copy of the spectrum nearest to 0). */
double st_signal_alias_frequency(double f, double spacing);

/* Reconstructs the samples at the m points x[] into out[]. A finite filter
 * whose weights sum to 0 at a point gives NaN there, counted in *zero_weight
 * (may be NULL). ST_ERR_USAGE for a bad filter or spacing. */
st_status st_signal_reconstruct(const st_signal_samples *s, const st_signal_filter *r,
                                const double *x, st_u32 m, double *out, st_u32 *zero_weight,
                                st_error *err);

/* Hann-windowed magnitude spectrum of n >= 2 values (FFTW, r2c): mag[k] =
 * |Σ_j w_j v_j e^{-2πijk/n}| / Σ_j w_j for k = 0 .. n/2 (n/2 + 1 values).
 * With remove_mean, the window-weighted mean Σ w v / Σ w is subtracted first,
 * so a constant leaks into no bin. */
st_status st_signal_spectrum(const double *v, st_u32 n, int remove_mean, double *mag,
                             st_error *err);

/* Frequency of the largest bin k >= 1 of mag[0 .. bins-1] (bin spacing df),
 * refined by a parabola through the log magnitudes of its neighbours (J. O.
 * Smith, "Spectral Audio Signal Processing", 2011, "Quadratic Interpolation of
 * Spectral Peaks"). 0 when every bin k >= 1 is 0. */
double st_signal_dominant_frequency(const double *mag, st_u32 bins, double df);

/* Validates o and fills in automatic values (points, sinc_margin): the dense
 * grid must resolve the function (P > 2 f_max L); automatic P is the smallest
 * odd multiple p >= 5 of L/T (when L/T is a whole number, so dense points
 * fall on the samples and a box of radius 1/2 never lands exactly between two)
 * with P >= 4096 and P >= 8 f_max L. ST_ERR_USAGE naming the option. */
st_status st_signal_check(st_signal_options *o, st_error *err);

/* Samples, reconstructs, measures and transforms (checks o first). */
st_status st_signal_build(const st_signal_options *o, st_signal_result *out, st_error *err);
void st_signal_result_free(st_signal_result *r); /* NULL or zeroed: does nothing */

#endif
