/* signal.c — the 1-D sampling and reconstruction laboratory (st_signal.h):
 * a function sampled at spacing T over a window wider than [0, L), rebuilt on
 * a dense grid with the ideal sinc or one of the renderer's filters, with the
 * error and the FFTW spectra of the original, the samples and the
 * reconstruction. Invariant: every array of an st_signal_result belongs to it
 * alone, is either NULL or fully written, and is released by
 * st_signal_result_free; nothing here prints or exits. */
#include "st_signal.h"

#include <fftw3.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "filters.h"
#include "rng.h"
#include "st_filter.h"

#define PI 3.14159265358979323846
#define MIN_AUTO_POINTS 4096u
#define MIN_POINTS 16u
#define SINC_WORK_BUDGET 1.0e9 /* terms of the default sinc sum before its margin shrinks */
#define MIN_SINC_MARGIN 1024u

const char *const st_signal_function_names[ST_SIGNAL_FUNCTION_COUNT] = {"sine", "sines", "chirp",
                                                                        "step", "square"};

/* ---- functions --------------------------------------------------------------------- */

double st_signal_eval(const st_signal_function *fn, double x)
{
    switch (fn->kind) {
    case ST_SIGNAL_SINE:
        return sin(2.0 * PI * fn->freq * x + fn->phase);
    case ST_SIGNAL_SINES: {
        double sum = 0.0;
        for (st_u32 k = 0; k < fn->freq_count; k++)
            sum += sin(2.0 * PI * fn->freqs[k] * x + fn->phase);
        return fn->freq_count ? sum / fn->freq_count : 0.0;
    }
    case ST_SIGNAL_CHIRP: {
        /* phase 2π ∫_0^x (f0 + (f1 - f0) t / L) dt: instantaneous frequency
         * f0 at x = 0 and f1 at x = L, continuing linearly outside [0, L) */
        double slope = (fn->f1 - fn->f0) / fn->length;
        return sin(2.0 * PI * (fn->f0 * x + 0.5 * slope * x * x) + fn->phase);
    }
    case ST_SIGNAL_STEP:
        return x >= fn->edge ? 1.0 : 0.0;
    case ST_SIGNAL_SQUARE: {
        double t = fn->freq * x + fn->phase / (2.0 * PI);
        return t - floor(t) < 0.5 ? 1.0 : -1.0;
    }
    default:
        return 0.0;
    }
}

double st_signal_max_frequency(const st_signal_function *fn)
{
    switch (fn->kind) {
    case ST_SIGNAL_SINE:
    case ST_SIGNAL_SQUARE:
        return fn->freq;
    case ST_SIGNAL_SINES: {
        double m = 0.0;
        for (st_u32 k = 0; k < fn->freq_count; k++)
            m = fmax(m, fn->freqs[k]);
        return m;
    }
    case ST_SIGNAL_CHIRP:
        return fmax(fn->f0, fn->f1);
    default:
        return 0.0;
    }
}

double st_signal_alias_frequency(double f, double spacing)
{
    double k = floor(f * spacing + 0.5);
    return fabs(f - k / spacing);
}

/* ---- reconstruction ---------------------------------------------------------------- */

static st_status check_filter(const st_signal_filter *r, st_error *err)
{
    if (r->sinc)
        return ST_OK;
    /* the radius is in units of T here, not pixels */
    st_status rc = st_filter_check(&r->filter, ST_SIGNAL_MAX_RADIUS, err);
    if (rc != ST_OK)
        return rc;
    if (r->mode != ST_SIGNAL_AVERAGE && r->mode != ST_SIGNAL_CONVOLUTION)
        return st_fail(err, ST_ERR_USAGE, "--reconstruct: unknown mode %u", r->mode);
    return ST_OK;
}

/* Sample i's position in units of T from x0. */
static double sample_u(const st_signal_samples *s, st_u32 i)
{
    return s->jitter ? i + s->jitter[i] : (double)i;
}

/* Σ_i sinc(u - i) v_i over every sample. With u = k + φ (k whole, φ in [0, 1)),
 * sin(π(u - i)) = (-1)^(k-i) sin(πφ), so one sine serves the whole sum;
 * jittered samples take a sine each. */
static double sinc_sum(const st_signal_samples *s, double u)
{
    if (s->jitter) {
        double sum = 0.0;
        for (st_u32 i = 0; i < s->count; i++) {
            double d = PI * (u - sample_u(s, i));
            sum += s->values[i] * (d == 0.0 ? 1.0 : sin(d) / d);
        }
        return sum;
    }
    double k = floor(u), phi = u - k;
    if (phi == 0.0) /* on a sample: sinc is 1 there and 0 at every other */
        return k >= 0.0 && k < s->count ? s->values[(st_u32)k] : 0.0;
    double sum = 0.0, sign = fmod(k, 2.0) == 0.0 ? 1.0 : -1.0; /* (-1)^(k-0) */
    for (st_u32 i = 0; i < s->count; i++) {
        sum += sign * s->values[i] / (u - i);
        sign = -sign;
    }
    return sum * sin(PI * phi) / PI;
}

/* Σ_i r(u - u_i) v_i and Σ_i r(u - u_i) over the samples within the radius
 * (a jittered sample i lies in [i, i + 1)). */
static void filter_sums(const st_signal_samples *s, const st_filter *f, double u, double *num,
                        double *den)
{
    double lo = ceil(u - f->radius) - (s->jitter ? 1.0 : 0.0), hi = floor(u + f->radius);
    lo = lo < 0.0 ? 0.0 : lo;
    hi = hi > s->count - 1.0 ? s->count - 1.0 : hi;
    *num = *den = 0.0;
    for (double i = lo; i <= hi; i += 1.0) {
        double w = st_filter_eval_1d(f, (float)(u - sample_u(s, (st_u32)i)));
        *num += w * s->values[(st_u32)i];
        *den += w;
    }
}

st_status st_signal_reconstruct(const st_signal_samples *s, const st_signal_filter *r,
                                const double *x, st_u32 m, double *out, st_u32 *zero_weight,
                                st_error *err)
{
    if (!(s->spacing > 0.0) || !isfinite(s->spacing))
        return st_fail(err, ST_ERR_USAGE, "--spacing %g: must be positive", s->spacing);
    if (check_filter(r, err) != ST_OK)
        return err ? err->status : ST_ERR_USAGE;
    int convolve = !r->sinc && r->mode == ST_SIGNAL_CONVOLUTION;
    double integral = convolve ? st_filter_integral(&r->filter) : 1.0;
    if (convolve && !(fabs(integral) > 0.0))
        return st_fail(err, ST_ERR_USAGE, "--reconstruct convolution: the filter's integral is 0");
    st_u32 zeros = 0;
    for (st_u32 j = 0; j < m; j++) {
        double u = (x[j] - s->x0) / s->spacing;
        if (r->sinc) {
            out[j] = sinc_sum(s, u);
            continue;
        }
        double num, den;
        filter_sums(s, &r->filter, u, &num, &den);
        if (convolve) {
            out[j] = num / integral;
        } else if (den != 0.0) {
            out[j] = num / den;
        } else {
            out[j] = NAN;
            zeros++;
        }
    }
    if (zero_weight)
        *zero_weight = zeros;
    return ST_OK;
}

/* ---- spectra ----------------------------------------------------------------------- */

st_status st_signal_spectrum(const double *v, st_u32 n, int remove_mean, double *mag,
                             st_error *err)
{
    if (n < 2)
        return st_fail(err, ST_ERR_USAGE, "spectrum: needs at least 2 values, not %u", n);
    double *in = fftw_malloc(sizeof(double) * n);
    fftw_complex *spec = fftw_malloc(sizeof(fftw_complex) * (n / 2 + 1));
    fftw_plan plan = in && spec ? fftw_plan_dft_r2c_1d((int)n, in, spec, FFTW_ESTIMATE) : NULL;
    if (!plan) {
        fftw_free(in);
        fftw_free(spec);
        return st_fail(err, ST_ERR_NOMEM, "spectrum: FFTW could not plan a DFT of %u values", n);
    }
    double wsum = 0.0, mean = 0.0;
    for (st_u32 j = 0; j < n; j++) { /* periodic Hann window */
        double w = 0.5 - 0.5 * cos(2.0 * PI * j / n);
        wsum += w;
        mean += w * v[j];
    }
    mean = remove_mean ? mean / wsum : 0.0;
    for (st_u32 j = 0; j < n; j++)
        in[j] = (0.5 - 0.5 * cos(2.0 * PI * j / n)) * (v[j] - mean);
    fftw_execute(plan);
    for (st_u32 k = 0; k <= n / 2; k++)
        mag[k] = hypot(spec[k][0], spec[k][1]) / wsum;
    fftw_destroy_plan(plan);
    fftw_free(in);
    fftw_free(spec);
    return ST_OK;
}

double st_signal_dominant_frequency(const double *mag, st_u32 bins, double df)
{
    st_u32 best = 0;
    for (st_u32 k = 1; k < bins; k++)
        if (mag[k] > (best ? mag[best] : 0.0))
            best = k;
    if (!best)
        return 0.0;
    double p = 0.0;
    if (best + 1 < bins && mag[best - 1] > 0.0 && mag[best + 1] > 0.0) {
        double a = log(mag[best - 1]), b = log(mag[best]), c = log(mag[best + 1]);
        double d = a - 2.0 * b + c;
        p = d < 0.0 ? 0.5 * (a - c) / d : 0.0;
        p = p > 0.5 ? 0.5 : p < -0.5 ? -0.5 : p;
    }
    return (best + p) * df;
}

/* ---- options ----------------------------------------------------------------------- */

/* Samples (i + o) T inside [0, L). */
static double samples_inside(double length, double spacing, double offset)
{
    double n = ceil(length / spacing - offset);
    while (n > 0.0 && (n - 1.0 + offset) * spacing >= length)
        n -= 1.0;
    while ((n + offset) * spacing < length)
        n += 1.0;
    return n;
}

static st_status check_function(const st_signal_function *fn, st_error *err)
{
    if (fn->kind >= ST_SIGNAL_FUNCTION_COUNT)
        return st_fail(err, ST_ERR_USAGE, "--function: unknown function %u", fn->kind);
    if (!isfinite(fn->phase))
        return st_fail(err, ST_ERR_USAGE, "--phase %g: must be finite", fn->phase);
    if ((fn->kind == ST_SIGNAL_SINE || fn->kind == ST_SIGNAL_SQUARE) &&
        !(fn->freq >= 0.0 && isfinite(fn->freq)))
        return st_fail(err, ST_ERR_USAGE, "--freq %g: must be a finite number >= 0", fn->freq);
    if (fn->kind == ST_SIGNAL_SINES) {
        if (fn->freq_count < 1 || fn->freq_count > ST_SIGNAL_MAX_FREQS)
            return st_fail(err, ST_ERR_USAGE, "--freqs: give 1 to %u frequencies, not %u",
                           ST_SIGNAL_MAX_FREQS, fn->freq_count);
        for (st_u32 k = 0; k < fn->freq_count; k++)
            if (!(fn->freqs[k] >= 0.0 && isfinite(fn->freqs[k])))
                return st_fail(err, ST_ERR_USAGE, "--freqs: %g must be a finite number >= 0",
                               fn->freqs[k]);
    }
    if (fn->kind == ST_SIGNAL_CHIRP && !(fn->f0 >= 0.0 && fn->f1 >= 0.0 && isfinite(fn->f0) &&
                                         isfinite(fn->f1)))
        return st_fail(err, ST_ERR_USAGE, "--f0 %g / --f1 %g: must be finite numbers >= 0",
                       fn->f0, fn->f1);
    if (fn->kind == ST_SIGNAL_STEP && !isfinite(fn->edge))
        return st_fail(err, ST_ERR_USAGE, "--edge %g: must be finite", fn->edge);
    return ST_OK;
}

/* The smallest odd multiple p >= 5 of L/T (a whole number) with P >= `need`;
 * else P = max(need, 5 ceil(L/T)). */
static double auto_points(double nf, double need)
{
    double base = floor(nf + 0.5);
    if (base >= 1.0 && fabs(nf - base) <= 1e-6 * nf) {
        double p = fmax(5.0, ceil(need / base));
        if (fmod(p, 2.0) == 0.0)
            p += 1.0;
        return p * base;
    }
    return fmax(need, 5.0 * ceil(nf));
}

static st_status check_points(st_signal_options *o, double nf, double fhi, st_error *err)
{
    double resolve = 2.0 * fhi * o->length; /* P must exceed this */
    if (!o->points) {
        double p = auto_points(nf, fmax(MIN_AUTO_POINTS, 8.0 * fhi * o->length));
        if (p > ST_SIGNAL_MAX_POINTS)
            p = ST_SIGNAL_MAX_POINTS;
        o->points = (st_u32)p;
    }
    if (o->points < MIN_POINTS || o->points > ST_SIGNAL_MAX_POINTS)
        return st_fail(err, ST_ERR_USAGE, "--points %u: must be in %u..%u", o->points, MIN_POINTS,
                       ST_SIGNAL_MAX_POINTS);
    if (!(o->points > resolve))
        return st_fail(err, ST_ERR_USAGE,
                       "--points %u: the dense grid cannot resolve frequency %g over length %g "
                       "(needs more than 2 f L = %g points)",
                       o->points, fhi, o->length, resolve);
    return ST_OK;
}

st_status st_signal_check(st_signal_options *o, st_error *err)
{
    if (!(o->length > 0.0) || !isfinite(o->length))
        return st_fail(err, ST_ERR_USAGE, "--length %g: must be positive", o->length);
    if (!(o->spacing > 0.0) || !isfinite(o->spacing))
        return st_fail(err, ST_ERR_USAGE, "--spacing %g: must be positive", o->spacing);
    if (!(o->offset >= 0.0 && o->offset < 1.0))
        return st_fail(err, ST_ERR_USAGE, "--offset %g: must be in [0, 1)", o->offset);
    if (o->jitter && o->offset != 0.0)
        return st_fail(err, ST_ERR_USAGE, "--offset %g with --jitter: each jittered sample "
                       "takes its own offset in its interval", o->offset);
    double nf = o->length / o->spacing;
    if (!(nf <= ST_SIGNAL_MAX_SAMPLES))
        return st_fail(err, ST_ERR_USAGE, "--length %g / --spacing %g: more than %u samples",
                       o->length, o->spacing, ST_SIGNAL_MAX_SAMPLES);
    if (samples_inside(o->length, o->spacing, o->offset) < 2.0)
        return st_fail(err, ST_ERR_USAGE,
                       "--length %g / --spacing %g: fewer than 2 samples in [0, L)", o->length,
                       o->spacing);
    o->fn.length = o->length;
    if (check_function(&o->fn, err) != ST_OK || check_filter(&o->recon, err) != ST_OK)
        return err ? err->status : ST_ERR_USAGE;
    if (check_points(o, nf, st_signal_max_frequency(&o->fn), err) != ST_OK)
        return err ? err->status : ST_ERR_USAGE;
    double n = samples_inside(o->length, o->spacing, o->offset);
    if (o->recon.sinc && !o->sinc_margin) {
        double m = floor((SINC_WORK_BUDGET / o->points - n) / 2.0);
        m = fmin(m, ST_SIGNAL_DEFAULT_SINC_MARGIN);
        o->sinc_margin = (st_u32)fmax(m, MIN_SINC_MARGIN);
    }
    double margin = o->recon.sinc ? o->sinc_margin : ceil(o->recon.filter.radius) + 1.0;
    if (n + 2.0 * margin > ST_SIGNAL_MAX_SAMPLES)
        return st_fail(err, ST_ERR_USAGE, "--sinc-margin %u: more than %u samples in all",
                       o->sinc_margin, ST_SIGNAL_MAX_SAMPLES);
    if (o->recon.sinc && (double)o->points * (n + 2.0 * margin) > ST_SIGNAL_MAX_WORK)
        return st_fail(err, ST_ERR_USAGE,
                       "--points %u x %g samples: the sinc sum would take more than %g terms "
                       "(lower --points or --sinc-margin)",
                       o->points, n + 2.0 * margin, ST_SIGNAL_MAX_WORK);
    return ST_OK;
}

/* ---- the whole experiment ---------------------------------------------------------- */

void st_signal_result_free(st_signal_result *r)
{
    if (!r)
        return;
    double *arrays[] = {r->x, r->original, r->reconstruction, r->error, r->sample_x,
                        r->sample_value, r->sample_reconstruction, r->freq,
                        r->spectrum_original, r->spectrum_reconstruction, r->sampled_freq,
                        r->spectrum_sampled};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++)
        free(arrays[i]);
    memset(r, 0, sizeof *r);
}

static st_status alloc_result(st_signal_result *r, st_u32 p, st_u32 n, st_u32 sbins,
                              st_error *err)
{
    size_t bins = p / 2 + 1;
    r->x = malloc(sizeof(double) * p);
    r->original = malloc(sizeof(double) * p);
    r->reconstruction = malloc(sizeof(double) * p);
    r->error = malloc(sizeof(double) * p);
    r->sample_x = malloc(sizeof(double) * n);
    r->sample_value = malloc(sizeof(double) * n);
    r->sample_reconstruction = malloc(sizeof(double) * n);
    r->freq = malloc(sizeof(double) * bins);
    r->spectrum_original = malloc(sizeof(double) * bins);
    r->spectrum_reconstruction = malloc(sizeof(double) * bins);
    r->sampled_freq = malloc(sizeof(double) * sbins);
    r->spectrum_sampled = malloc(sizeof(double) * sbins);
    if (!r->x || !r->original || !r->reconstruction || !r->error || !r->sample_x ||
        !r->sample_value || !r->sample_reconstruction || !r->freq || !r->spectrum_original ||
        !r->spectrum_reconstruction || !r->sampled_freq || !r->spectrum_sampled)
        return st_fail(err, ST_ERR_NOMEM, "signal: out of memory for %u points", p);
    r->points = p;
    r->sample_count = n;
    r->bins = (st_u32)bins;
    r->sampled_bins = sbins;
    return ST_OK;
}

static void measure_error(st_signal_result *r)
{
    double sum = 0.0, worst = 0.0;
    st_u32 count = 0;
    for (st_u32 j = 0; j < r->points; j++) {
        r->error[j] = r->reconstruction[j] - r->original[j];
        if (!isfinite(r->error[j]))
            continue;
        sum += r->error[j] * r->error[j];
        worst = fmax(worst, fabs(r->error[j]));
        count++;
    }
    r->rms_error = count ? sqrt(sum / count) : NAN;
    r->max_error = count ? worst : NAN;
}

/* Spectra of the original and the reconstruction on the dense grid (a point
 * without a reconstruction takes its predecessor's value there), the sampled
 * spectrum tiled over the dense band, and the dominant frequencies. */
static st_status spectra(const st_signal_options *o, st_signal_result *r, st_error *err)
{
    st_u32 p = r->points, n = r->sample_count, bins = r->bins;
    double *tmp = malloc(sizeof(double) * p);
    double *smag = malloc(sizeof(double) * (n / 2 + 1));
    st_status rc = tmp && smag ? ST_OK : st_fail(err, ST_ERR_NOMEM, "signal: out of memory");
    for (st_u32 j = 0; rc == ST_OK && j < p; j++)
        tmp[j] = isfinite(r->reconstruction[j]) ? r->reconstruction[j] : j ? tmp[j - 1] : 0.0;
    for (st_u32 k = 0; k < bins; k++)
        r->freq[k] = k / o->length;
    if (rc == ST_OK)
        rc = st_signal_spectrum(r->original, p, 1, r->spectrum_original, err);
    if (rc == ST_OK)
        r->dominant_original = st_signal_dominant_frequency(r->spectrum_original, bins,
                                                            1.0 / o->length);
    if (rc == ST_OK)
        rc = st_signal_spectrum(tmp, p, 1, r->spectrum_reconstruction, err);
    if (rc == ST_OK)
        r->dominant_reconstruction = st_signal_dominant_frequency(r->spectrum_reconstruction,
                                                                  bins, 1.0 / o->length);
    /* the plotted spectra keep their mean (a step's DC is part of its picture) */
    if (rc == ST_OK)
        rc = st_signal_spectrum(r->original, p, 0, r->spectrum_original, err);
    if (rc == ST_OK)
        rc = st_signal_spectrum(tmp, p, 0, r->spectrum_reconstruction, err);
    if (rc == ST_OK)
        rc = st_signal_spectrum(r->sample_value, n, 0, smag, err);
    for (st_u32 k = 0; rc == ST_OK && k < r->sampled_bins; k++) {
        st_u32 m = k % n; /* |X_k| is periodic in k with period n, and |X_(n-k)| = |X_k| */
        r->sampled_freq[k] = k / (n * o->spacing);
        r->spectrum_sampled[k] = smag[m <= n / 2 ? m : n - m];
    }
    free(tmp);
    free(smag);
    return rc;
}

st_status st_signal_build(const st_signal_options *opts, st_signal_result *out, st_error *err)
{
    memset(out, 0, sizeof *out);
    st_signal_options o = *opts;
    if (st_signal_check(&o, err) != ST_OK)
        return err ? err->status : ST_ERR_USAGE;
    st_u32 n = (st_u32)samples_inside(o.length, o.spacing, o.offset);
    st_u32 margin = o.recon.sinc ? o.sinc_margin : (st_u32)ceil(o.recon.filter.radius) + 1u;
    st_u32 window = n + 2u * margin, p = o.points;
    double dense_nyquist = p / (2.0 * o.length);
    st_u32 sbins = (st_u32)floor(dense_nyquist * n * o.spacing) + 1u;
    double *values = malloc(sizeof(double) * window), *jitter = NULL;
    st_status rc = values ? alloc_result(out, p, n, sbins, err)
                          : st_fail(err, ST_ERR_NOMEM, "signal: out of memory for %u samples",
                                    window);
    if (rc != ST_OK)
        goto fail;
    out->margin = margin;
    out->nyquist = 0.5 / o.spacing;
    st_signal_samples s = {(o.offset - margin) * o.spacing, o.spacing, window, values, NULL};
    if (o.jitter)
        s.jitter = jitter = malloc(sizeof(double) * window);
    if (o.jitter && !jitter) {
        rc = st_fail(err, ST_ERR_NOMEM, "signal: out of memory for %u samples", window);
        goto fail;
    }
    for (st_u32 i = 0; jitter && i < window; i++) /* ξ of stratum i - margin */
        jitter[i] = st_rng_unit(st_rng_key(o.seed, i - margin, 0x6a697474u), 0u);
    for (st_u32 i = 0; i < window; i++)
        values[i] = st_signal_eval(&o.fn, s.x0 + sample_u(&s, i) * o.spacing);
    for (st_u32 j = 0; j < p; j++) {
        out->x[j] = j * o.length / p;
        out->original[j] = st_signal_eval(&o.fn, out->x[j]);
    }
    for (st_u32 i = 0; i < n; i++) {
        out->sample_x[i] = (i + o.offset + (jitter ? jitter[margin + i] : 0.0)) * o.spacing;
        out->sample_value[i] = values[margin + i];
    }
    rc = st_signal_reconstruct(&s, &o.recon, out->x, p, out->reconstruction, &out->zero_weight,
                               err);
    if (rc == ST_OK)
        rc = st_signal_reconstruct(&s, &o.recon, out->sample_x, n, out->sample_reconstruction,
                                   NULL, err);
    if (rc != ST_OK)
        goto fail;
    measure_error(out);
    rc = spectra(&o, out, err);
    if (rc != ST_OK)
        goto fail;
    free(values);
    free(jitter);
    return ST_OK;
fail:
    free(values);
    free(jitter);
    st_signal_result_free(out);
    return rc;
}
