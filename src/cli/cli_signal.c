/* cli_signal.c — `strata signal`: the 1-D sampling and reconstruction
 * laboratory (st_signal.h). Parses the options, runs st_signal_build, writes
 * the CSV tables and the three-panel plot (signal, error, spectra with the
 * Nyquist frequency marked) through a temporary name, and prints one summary
 * line: the RMS error over [0, L) and the dominant frequencies, so that an
 * alias |f - k/T| shows as a number. The only part of the module that prints. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "cli_text.h"
#include "cli_args.h"
#include "cli_commands.h"
#include "cli_error.h"
#include "cli_names.h"
#include "st_plot.h"
#include "st_render.h"
#include "st_signal.h"

#define PANEL_W 720u
#define PANEL_H 480u
#define SPECTRUM_FLOOR 1e-6 /* bottom of the log magnitude axis */

static const char signal_help[] =
    "usage: strata signal [options]\n"
    "Samples f(x) at x_i = (i + O) T, rebuilds it on a dense grid over [0, L) and prints\n"
    "the RMS error and the dominant frequencies of the original and the reconstruction.\n"
    "Function:\n"
    "  --function NAME     sine, sines, chirp, step, square (default sine)\n"
    "                        sine    sin(2 pi f x + phase)\n"
    "                        sines   (1/K) sum_k sin(2 pi f_k x + phase)\n"
    "                        chirp   sin(2 pi (f0 x + (f1 - f0) x^2 / 2L) + phase): f0 at 0, f1 at L\n"
    "                        step    0 for x < edge, 1 from the edge on\n"
    "                        square  +1 for the first half of each period 1/f, -1 after\n"
    "  --freq F            sine, square: frequency in cycles per unit length (default 0.1)\n"
    "  --freqs F1,F2,...   sines: up to 16 frequencies (required)\n"
    "  --f0 F, --f1 F      chirp: frequencies at x = 0 and x = L (default 0 and 1/T)\n"
    "  --phase P           sine, sines, chirp, square: phase in radians (default 0)\n"
    "  --edge X            step: position of the edge (default L/2)\n"
    "  (an option the chosen function does not take is a usage error)\n"
    "Sampling:\n"
    "  --length L          the domain [0, L) (default 64)\n"
    "  --spacing T         sample spacing (default 1); or --rate R = 1/T samples per unit\n"
    "  --offset O          samples at (i + O) T, O in [0, 1) (default 0)\n"
    "  --jitter            jittered samples instead: at (i + u_i) T, u_i uniform in [0, 1),\n"
    "                      one in each interval; an alias above Nyquist shrinks by\n"
    "                      |sinc(f T)| and the rest turns into noise over every frequency\n"
    "  --seed S            the jitter's random numbers (default 0)\n"
    "  Samples continue beyond both ends of [0, L) (sinc: --sinc-margin of them; a filter:\n"
    "  ceil(radius) + 1), so the whole of [0, L) is interior.\n"
    "Reconstruction:\n"
    "  --filter NAME|sinc  sinc (default): f~(x) = sum_i sinc((x - x_i)/T) f(x_i), the ideal\n"
    "                      reconstruction, summed over the whole sample window; or one of\n"
    "                      box, triangle, gaussian, mitchell, lanczos, catmull-rom,\n"
    "                      blackman-harris, evaluated at (x - x_i)/T\n"
    "  --reconstruct average|convolution   a filter r (default average):\n"
    "                      average      sum_i r f(x_i) / sum_i r (as the renderer's film)\n"
    "                      convolution  sum_i r f(x_i) / integral of r (the lecture's\n"
    "                                   (III_T f) conv r; constants may ripple)\n"
    "  --filter-radius R   radius in units of T (default: the filter's own, as render)\n"
    "  --filter-b B, --filter-c C   mitchell's parameters (default 1/3, 1/3)\n"
    "  --filter-sigma S    gaussian's standard deviation, units of T (default 0.5)\n"
    "  --filter-tau X      lanczos' window scale (default: the radius)\n"
    "  --sinc-margin M     samples beyond each end for sinc (default 16384, fewer when\n"
    "                      points x samples would pass 1e9; the truncation error is\n"
    "                      about 1/(pi^2 M (1/2 - f T)) for a sine)\n"
    "  (a filter parameter the chosen filter does not take is a usage error)\n"
    "Output:\n"
    "  --points P          dense points x_j = j L / P (default: an odd multiple of L/T,\n"
    "                      at least 4096 and 8 f L)\n"
    "  --csv FILE|-        x,original,sample,reconstruction,error over the dense points and\n"
    "                      the samples in [0, L), sorted by x; sample is blank off the samples\n"
    "  --spectrum-csv FILE|-   series,frequency,magnitude for the series original, sampled\n"
    "                      and reconstruction, up to --fmax\n"
    "  --png FILE          three panels: original, samples and reconstruction; the error;\n"
    "                      the spectra (log scale) with the Nyquist frequency 1/(2T) marked\n"
    "  --fmax F            highest frequency in the spectrum plot and CSV (default: 2.5/T or\n"
    "                      1.25 f_max, within the dense grid's band)\n"
    "Spectra: |DFT| / sum(w) with a periodic Hann window w (FFTW): a sine of amplitude 1\n"
    "reads 1/2; the sampled spectrum repeats every 1/T (its copies). The dominant frequency\n"
    "is the largest bin above 0 after removing the mean, refined by a parabola.\n";

typedef struct signal_cli {
    st_signal_options o;
    const char *csv, *spectrum_csv, *png;
    double fmax;
    const char *given[32]; /* option values seen, by option id - S_BASE */
} signal_cli;

enum { S_BASE = 500, S_FUNCTION = S_BASE, S_FREQ, S_FREQS, S_F0, S_F1, S_PHASE, S_EDGE,
       S_LENGTH, S_SPACING, S_RATE, S_OFFSET, S_FILTER, S_RECONSTRUCT, S_RADIUS, S_B, S_C,
       S_SIGMA, S_TAU, S_SINC_MARGIN, S_POINTS, S_CSV, S_SPECTRUM_CSV, S_PNG, S_FMAX, S_JITTER,
       S_SEED, S_END };

static const struct option signal_opts[] = {
    {"function", required_argument, 0, S_FUNCTION}, {"freq", required_argument, 0, S_FREQ},
    {"freqs", required_argument, 0, S_FREQS}, {"f0", required_argument, 0, S_F0},
    {"f1", required_argument, 0, S_F1}, {"phase", required_argument, 0, S_PHASE},
    {"edge", required_argument, 0, S_EDGE}, {"length", required_argument, 0, S_LENGTH},
    {"spacing", required_argument, 0, S_SPACING}, {"rate", required_argument, 0, S_RATE},
    {"offset", required_argument, 0, S_OFFSET}, {"jitter", no_argument, 0, S_JITTER},
    {"seed", required_argument, 0, S_SEED}, {"filter", required_argument, 0, S_FILTER},
    {"reconstruct", required_argument, 0, S_RECONSTRUCT},
    {"filter-radius", required_argument, 0, S_RADIUS}, {"filter-b", required_argument, 0, S_B},
    {"filter-c", required_argument, 0, S_C}, {"filter-sigma", required_argument, 0, S_SIGMA},
    {"filter-tau", required_argument, 0, S_TAU},
    {"sinc-margin", required_argument, 0, S_SINC_MARGIN},
    {"points", required_argument, 0, S_POINTS}, {"csv", required_argument, 0, S_CSV},
    {"spectrum-csv", required_argument, 0, S_SPECTRUM_CSV}, {"png", required_argument, 0, S_PNG},
    {"fmax", required_argument, 0, S_FMAX}, {"help", no_argument, 0, 'h'}, {0, 0, 0, 0}};

_Static_assert(S_END - S_BASE <= 32, "signal_cli.given is too small");

static const char *given(const signal_cli *c, int id) { return c->given[id - S_BASE]; }

/* ---- parsing ----------------------------------------------------------------------- */

/* A float option into a double; a missing option leaves *out alone. */
static int opt_double(const signal_cli *c, int id, const char *name, double *out)
{
    float v;
    if (!given(c, id))
        return ST_CLI_OK;
    if (st_cli_parse_float(name, given(c, id), &v))
        return ST_CLI_EXIT_USAGE;
    *out = v;
    return ST_CLI_OK;
}

static int parse_freqs(const char *list, st_signal_function *fn)
{
    char buf[1024];
    if (strlen(list) >= sizeof buf)
        return st_cli_usage_error("--freqs: list too long");
    strcpy(buf, list);
    fn->freq_count = 0;
    char *save = NULL;
    for (char *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
        float v;
        if (fn->freq_count == ST_SIGNAL_MAX_FREQS)
            return st_cli_usage_error("--freqs %s: at most %u frequencies", list,
                                      ST_SIGNAL_MAX_FREQS);
        if (st_cli_parse_float("--freqs", t, &v))
            return ST_CLI_EXIT_USAGE;
        fn->freqs[fn->freq_count++] = v;
    }
    if (!fn->freq_count)
        return st_cli_usage_error("--freqs %s: expected F1,F2,...", list);
    return ST_CLI_OK;
}

/* Options that only some functions take. */
static int check_function_options(const signal_cli *c, st_u32 kind)
{
    static const struct { int id; const char *name; unsigned kinds; } only[] = {
        {S_FREQ, "--freq", 1u << ST_SIGNAL_SINE | 1u << ST_SIGNAL_SQUARE},
        {S_FREQS, "--freqs", 1u << ST_SIGNAL_SINES},
        {S_F0, "--f0", 1u << ST_SIGNAL_CHIRP},
        {S_F1, "--f1", 1u << ST_SIGNAL_CHIRP},
        {S_EDGE, "--edge", 1u << ST_SIGNAL_STEP},
        {S_PHASE, "--phase", ~(1u << ST_SIGNAL_STEP)}};
    for (size_t i = 0; i < sizeof only / sizeof only[0]; i++)
        if (given(c, only[i].id) && !(only[i].kinds & (1u << kind)))
            return st_cli_usage_error("%s does not apply to --function %s", only[i].name,
                                      st_signal_function_names[kind]);
    return ST_CLI_OK;
}

static int parse_function(signal_cli *c)
{
    st_signal_function *fn = &c->o.fn;
    const char *name = given(c, S_FUNCTION) ? given(c, S_FUNCTION) : "sine";
    int k = st_name_lookup(st_signal_function_names, ST_SIGNAL_FUNCTION_COUNT, name);
    if (k < 0)
        return st_cli_unknown_name("--function", name, st_signal_function_names,
                                   ST_SIGNAL_FUNCTION_COUNT);
    fn->kind = (st_u32)k;
    if (check_function_options(c, fn->kind))
        return ST_CLI_EXIT_USAGE;
    fn->freq = 0.1;
    fn->f0 = 0.0;
    fn->f1 = 1.0 / c->o.spacing;
    fn->edge = 0.5 * c->o.length;
    if (fn->kind == ST_SIGNAL_SINES && !given(c, S_FREQS))
        return st_cli_usage_error("--function sines needs --freqs F1,F2,...");
    if (given(c, S_FREQS) && parse_freqs(given(c, S_FREQS), fn))
        return ST_CLI_EXIT_USAGE;
    if (opt_double(c, S_FREQ, "--freq", &fn->freq) || opt_double(c, S_F0, "--f0", &fn->f0) ||
        opt_double(c, S_F1, "--f1", &fn->f1) || opt_double(c, S_PHASE, "--phase", &fn->phase) ||
        opt_double(c, S_EDGE, "--edge", &fn->edge))
        return ST_CLI_EXIT_USAGE;
    return ST_CLI_OK;
}

static int parse_sampling(signal_cli *c)
{
    st_signal_options *o = &c->o;
    o->length = 64.0;
    o->spacing = 1.0;
    if (given(c, S_SPACING) && given(c, S_RATE))
        return st_cli_usage_error("--spacing and --rate: give one of them (T = 1/R)");
    double rate = 0.0;
    if (opt_double(c, S_LENGTH, "--length", &o->length) ||
        opt_double(c, S_SPACING, "--spacing", &o->spacing) ||
        opt_double(c, S_RATE, "--rate", &rate) || opt_double(c, S_OFFSET, "--offset", &o->offset))
        return ST_CLI_EXIT_USAGE;
    o->jitter = given(c, S_JITTER) != NULL;
    if (given(c, S_SEED) && !o->jitter)
        return st_cli_usage_error("--seed applies to --jitter only");
    if (given(c, S_SEED) && st_cli_parse_u32("--seed", given(c, S_SEED), 0, 0xffffffffu, &o->seed))
        return ST_CLI_EXIT_USAGE;
    if (o->jitter && given(c, S_OFFSET))
        return st_cli_usage_error("--offset with --jitter: each jittered sample takes its own "
                                  "offset in its interval");
    if (given(c, S_RATE)) {
        if (!(rate > 0.0))
            return st_cli_usage_error("--rate %s: must be positive", given(c, S_RATE));
        o->spacing = 1.0 / rate;
    }
    if (!(o->spacing > 0.0))
        return st_cli_usage_error("--spacing %s: must be positive", given(c, S_SPACING));
    if (!(o->length > 0.0))
        return st_cli_usage_error("--length %s: must be positive", given(c, S_LENGTH));
    return ST_CLI_OK;
}

static int parse_filter(signal_cli *c)
{
    st_signal_filter *r = &c->o.recon;
    const char *name = given(c, S_FILTER) ? given(c, S_FILTER) : "sinc";
    st_cli_filter_args fa = {given(c, S_RADIUS), given(c, S_B), given(c, S_C), given(c, S_SIGMA),
                             given(c, S_TAU)};
    r->sinc = !strcasecmp(name, "sinc");
    if (r->sinc) {
        static const int ids[] = {S_RADIUS, S_B, S_C, S_SIGMA, S_TAU, S_RECONSTRUCT};
        static const char *names[] = {"--filter-radius", "--filter-b", "--filter-c",
                                      "--filter-sigma", "--filter-tau", "--reconstruct"};
        for (size_t i = 0; i < sizeof ids / sizeof ids[0]; i++)
            if (given(c, ids[i]))
                return st_cli_usage_error("%s does not apply to sinc (the ideal sum over every "
                                          "sample; see --sinc-margin)", names[i]);
        return given(c, S_SINC_MARGIN)
                   ? st_cli_parse_u32("--sinc-margin", given(c, S_SINC_MARGIN), 1,
                                      ST_SIGNAL_MAX_SAMPLES / 2, &c->o.sinc_margin)
                   : ST_CLI_OK;
    }
    int k = st_filter_lookup(name);
    if (k < 0)
        return st_cli_usage_error("--filter %s: unknown; expected sinc, box, triangle, gaussian, "
                                  "mitchell, lanczos, catmull-rom or blackman-harris", name);
    if (given(c, S_SINC_MARGIN))
        return st_cli_usage_error("--sinc-margin applies to sinc only, not %s", name);
    r->filter = st_filter_default((st_u32)k);
    if (st_cli_apply_filter_args(&fa, &r->filter))
        return ST_CLI_EXIT_USAGE;
    const char *mode = given(c, S_RECONSTRUCT);
    if (mode && strcmp(mode, "average") && strcmp(mode, "convolution"))
        return st_cli_usage_error("--reconstruct %s: expected average or convolution", mode);
    r->mode = mode && !strcmp(mode, "convolution") ? ST_SIGNAL_CONVOLUTION : ST_SIGNAL_AVERAGE;
    return ST_CLI_OK;
}

/* The filter module names fields; signal's options for them. */
static const st_cli_option_name filter_option_names[] = {
    {"filter kind", "--filter"}, {"filter radius", "--filter-radius"},
    {"filter b", "--filter-b"}, {"filter c", "--filter-c"},
    {"filter sigma", "--filter-sigma"}, {"filter tau", "--filter-tau"}, {NULL, NULL}};

static int parse(int argc, char **argv, signal_cli *c)
{
    opterr = 0;
    optind = 1;
    int o;
    while ((o = getopt_long(argc, argv, ":h", signal_opts, NULL)) != -1) {
        if (o == 'h') {
            fputs(signal_help, stdout);
            return ST_CLI_HELP;
        }
        if (o == '?')
            return st_cli_unknown_option("signal", argv[optind - 1], signal_opts);
        if (o == ':')
            return st_cli_usage_error("signal: option %s needs a value", argv[optind - 1]);
        c->given[o - S_BASE] = optarg ? optarg : "on"; /* a flag: given */
    }
    if (optind < argc)
        return st_cli_usage_error("signal: unexpected argument %s", argv[optind]);
    c->csv = given(c, S_CSV);
    c->spectrum_csv = given(c, S_SPECTRUM_CSV);
    c->png = given(c, S_PNG);
    if (c->csv && c->spectrum_csv && !strcmp(c->csv, "-") && !strcmp(c->spectrum_csv, "-"))
        return st_cli_usage_error("--csv - and --spectrum-csv -: only one table can go to stdout");
    if (given(c, S_POINTS) && st_cli_parse_u32("--points", given(c, S_POINTS), 16,
                                               ST_SIGNAL_MAX_POINTS, &c->o.points))
        return ST_CLI_EXIT_USAGE;
    if (parse_sampling(c) || parse_function(c) || parse_filter(c) ||
        opt_double(c, S_FMAX, "--fmax", &c->fmax))
        return ST_CLI_EXIT_USAGE;
    if (given(c, S_FMAX) && !(c->fmax > 0.0))
        return st_cli_usage_error("--fmax %s: must be positive", given(c, S_FMAX));
    st_error err = {0};
    if (st_signal_check(&c->o, &err) != ST_OK)
        return st_cli_fail_options(&err, filter_option_names);
    st_outfile_role files[] = {{c->csv, "--csv"}, {c->spectrum_csv, "--spectrum-csv"},
                               {c->png, "--png"}};
    return st_cli_check_apart(files, 3, 3);
}

/* ---- output ------------------------------------------------------------------------ */

typedef void (*emit_fn)(FILE *, const signal_cli *, const st_signal_result *);

/* What st_cli_write_text hands back to emit_pair: one table and its inputs. */
typedef struct signal_table {
    emit_fn emit;
    const signal_cli *c;
    const st_signal_result *r;
} signal_table;

static void emit_pair(FILE *f, const void *ctx)
{
    const signal_table *t = ctx;
    t->emit(f, t->c, t->r);
}

/* Writes one table through st_cli_write_text (a temporary and rename), or to stdout for "-". */
static st_status write_text(const char *path, emit_fn emit, const signal_cli *c,
                            const st_signal_result *r, st_error *err)
{
    signal_table t = {emit, c, r};
    return st_cli_write_text(path, emit_pair, &t, err);
}

static void put(FILE *f, double v, char end)
{
    if (isfinite(v))
        fprintf(f, "%.9g%c", v, end);
    else
        fputc(end, f); /* blank: no value (a point where the filter weights summed to 0) */
}

static void emit_signal(FILE *f, const signal_cli *c, const st_signal_result *r)
{
    double tol = 1e-9 * c->o.length;
    fprintf(f, "x,original,sample,reconstruction,error\n");
    st_u32 j = 0, i = 0;
    while (j < r->points || i < r->sample_count) {
        int dense = j < r->points && (i >= r->sample_count || r->x[j] <= r->sample_x[i] + tol);
        int sample = i < r->sample_count && (j >= r->points || r->sample_x[i] <= r->x[j] + tol);
        double x = dense ? r->x[j] : r->sample_x[i];
        double orig = dense ? r->original[j] : r->sample_value[i];
        double rec = dense ? r->reconstruction[j] : r->sample_reconstruction[i];
        put(f, x, ',');
        put(f, orig, ',');
        if (sample)
            put(f, r->sample_value[i], ',');
        else
            fputc(',', f);
        put(f, rec, ',');
        put(f, rec - orig, '\n');
        j += dense;
        i += sample;
    }
}

static double spectrum_fmax(const signal_cli *c, const st_signal_result *r)
{
    double band = r->freq[r->bins - 1];
    if (c->fmax > 0.0)
        return fmin(c->fmax, band);
    return fmin(band, fmax(2.5 / c->o.spacing, 1.25 * st_signal_max_frequency(&c->o.fn)));
}

static st_u32 count_upto(const double *freq, st_u32 n, double fmax)
{
    st_u32 k = 0;
    while (k < n && freq[k] <= fmax * (1.0 + 1e-12))
        k++;
    return k;
}

static void emit_spectrum(FILE *f, const signal_cli *c, const st_signal_result *r)
{
    double top = spectrum_fmax(c, r);
    const struct { const char *name; const double *freq, *mag; st_u32 n; } s[3] = {
        {"original", r->freq, r->spectrum_original, r->bins},
        {"sampled", r->sampled_freq, r->spectrum_sampled, r->sampled_bins},
        {"reconstruction", r->freq, r->spectrum_reconstruction, r->bins}};
    fprintf(f, "series,frequency,magnitude\n");
    for (int k = 0; k < 3; k++)
        for (st_u32 b = 0, n = count_upto(s[k].freq, s[k].n, top); b < n; b++)
            fprintf(f, "%s,%.9g,%.9g\n", s[k].name, s[k].freq[b], s[k].mag[b]);
}

/* "sinc" or "lanczos (r = 3 T, average)". */
static void describe_filter(const st_signal_filter *r, char *buf, size_t size)
{
    if (r->sinc)
        snprintf(buf, size, "sinc");
    else
        snprintf(buf, size, "%s (r = %g T, %s)", st_filter_names[r->filter.kind],
                 (double)r->filter.radius,
                 r->mode == ST_SIGNAL_CONVOLUTION ? "convolution" : "average");
}

/* "sine f = 0.8" and the like. */
static void describe_function(const st_signal_function *fn, char *buf, size_t size)
{
    const char *name = st_signal_function_names[fn->kind];
    switch (fn->kind) {
    case ST_SIGNAL_SINE:
    case ST_SIGNAL_SQUARE: snprintf(buf, size, "%s f = %g", name, fn->freq); break;
    case ST_SIGNAL_CHIRP: snprintf(buf, size, "chirp f = %g..%g", fn->f0, fn->f1); break;
    case ST_SIGNAL_STEP: snprintf(buf, size, "step at %g", fn->edge); break;
    default: {
        int n = snprintf(buf, size, "sines f =");
        for (st_u32 k = 0; k < fn->freq_count && n > 0 && (size_t)n < size; k++)
            n += snprintf(buf + n, size - n, "%s%g", k ? "," : " ", fn->freqs[k]);
    }
    }
}

/* Min-max decimation for drawing: a series of more than 2 * DRAW_BUCKETS points
 * becomes, per bucket of consecutive points, its lowest and highest y in x
 * order, so the drawn envelope is the data's while cairo strokes a few
 * thousand segments instead of millions (a 500000-point line took 90 s).
 * A bucket with no finite value gives one NaN, which breaks the line. */
#define DRAW_BUCKETS (2u * PANEL_W)

typedef struct drawn {
    double *x, *y; /* owned when `own`, else the caller's arrays */
    st_u32 n;
    int own;
} drawn;

/* The plot's series, as write_png decimates them. */
enum { D_ORIG, D_REC, D_SAMPLES, D_ERR, D_SSAMP, D_SORIG, D_SREC, D_COUNT };

static int decimate(const double *x, const double *y, st_u32 n, drawn *d)
{
    d->x = (double *)x;
    d->y = (double *)y;
    d->n = n;
    d->own = 0;
    if (n <= 2u * DRAW_BUCKETS)
        return 0;
    d->x = malloc(sizeof(double) * 2u * DRAW_BUCKETS);
    d->y = malloc(sizeof(double) * 2u * DRAW_BUCKETS);
    d->own = 1;
    d->n = 0;
    if (!d->x || !d->y)
        return -1;
    for (st_u32 b = 0; b < DRAW_BUCKETS; b++) {
        st_u32 lo = (st_u32)((uint64_t)b * n / DRAW_BUCKETS);
        st_u32 hi = (st_u32)((uint64_t)(b + 1) * n / DRAW_BUCKETS);
        st_u32 imin = hi, imax = hi;
        for (st_u32 i = lo; i < hi; i++)
            if (isfinite(y[i])) {
                if (imin == hi || y[i] < y[imin])
                    imin = i;
                if (imax == hi || y[i] > y[imax])
                    imax = i;
            }
        if (imin == hi) {
            d->x[d->n] = x[lo];
            d->y[d->n++] = NAN;
            continue;
        }
        st_u32 first = imin < imax ? imin : imax, second = imin < imax ? imax : imin;
        d->x[d->n] = x[first];
        d->y[d->n++] = y[first];
        if (second != first) {
            d->x[d->n] = x[second];
            d->y[d->n++] = y[second];
        }
    }
    return 0;
}

static void drawn_free(drawn *d)
{
    if (d->own) {
        free(d->x);
        free(d->y);
    }
}

static st_status draw_png(const signal_cli *c, const st_signal_result *r, const drawn *d,
                          st_error *err)
{
    char fname[256], filt[128], t1[512], t2[160], nyq_label[64];
    describe_function(&c->o.fn, fname, sizeof fname);
    describe_filter(&c->o.recon, filt, sizeof filt);
    snprintf(t1, sizeof t1, "%s, T = %g: %s", fname, c->o.spacing, filt);
    snprintf(t2, sizeof t2, "error f~ - f (rms %.3g)", r->rms_error);
    snprintf(nyq_label, sizeof nyq_label, "Nyquist 1/2T = %g", r->nyquist);
#define SERIES(k) .x = d[k].x, .y = d[k].y, .n = d[k].n
    st_plot_series sig[3] = {
        {.name = "original f", SERIES(D_ORIG), .color = 0x1f77b4},
        {.name = "reconstruction f~", SERIES(D_REC), .color = 0xd62728},
        {.name = "samples f(x_i)", SERIES(D_SAMPLES), .style = ST_PLOT_STYLE_POINTS,
         .color = 0x222222}};
    st_plot_series er = {.name = NULL, SERIES(D_ERR), .color = 0xd62728};
    st_plot_series sp[3] = {
        {.name = "sampled (copies every 1/T)", SERIES(D_SSAMP), .color = 0xaaaaaa, .width = 3},
        {.name = "original (Hann window)", SERIES(D_SORIG), .color = 0x1f77b4},
        {.name = "reconstruction", SERIES(D_SREC), .color = 0xd62728, .width = 1.5}};
#undef SERIES
    st_plot_marker marks[2] = {{.x = r->nyquist, .label = nyq_label},
                               {.x = 2.0 * r->nyquist, .label = "1/T"}};
    st_plot_lines p1 = {.title = t1, .xlabel = "x", .ylabel = "f(x)", .series = sig,
                        .series_count = 3};
    st_plot_lines p2 = {.title = t2, .xlabel = "x", .ylabel = "f~(x) - f(x)", .series = &er,
                        .series_count = 1};
    st_plot_lines p3 = {.title = "spectra: |DFT| / sum w, Hann window",
                        .xlabel = "frequency (cycles per unit length)", .ylabel = "magnitude",
                        .series = sp, .series_count = 3, .markers = marks, .marker_count = 2u,
                        .flags = ST_PLOT_LOG_Y, .xmin = 0.0, .xmax = spectrum_fmax(c, r),
                        .ymin = SPECTRUM_FLOOR, .ymax = 1.0};
    st_plot_panel panels[3] = {{.kind = ST_PLOT_LINES, .lines = &p1},
                               {.kind = ST_PLOT_LINES, .lines = &p2},
                               {.kind = ST_PLOT_LINES, .lines = &p3}};
    return st_plot_save_row(c->png, panels, 3, PANEL_W, PANEL_H, err);
}

/* The three panels: signal (original, reconstruction, samples), error, spectra. */
static st_status write_png(const signal_cli *c, const st_signal_result *r, st_error *err)
{
    double top = spectrum_fmax(c, r);
    drawn d[D_COUNT];
    int bad = decimate(r->x, r->original, r->points, &d[D_ORIG]);
    bad |= decimate(r->x, r->reconstruction, r->points, &d[D_REC]);
    bad |= decimate(r->sample_x, r->sample_value, r->sample_count, &d[D_SAMPLES]);
    bad |= decimate(r->x, r->error, r->points, &d[D_ERR]);
    bad |= decimate(r->sampled_freq, r->spectrum_sampled,
                    count_upto(r->sampled_freq, r->sampled_bins, top), &d[D_SSAMP]);
    bad |= decimate(r->freq, r->spectrum_original, count_upto(r->freq, r->bins, top),
                    &d[D_SORIG]);
    bad |= decimate(r->freq, r->spectrum_reconstruction, count_upto(r->freq, r->bins, top),
                    &d[D_SREC]);
    st_status rc = bad ? st_fail(err, ST_ERR_NOMEM, "%s: out of memory for the plot", c->png)
                       : draw_png(c, r, d, err);
    for (int i = 0; i < D_COUNT; i++)
        drawn_free(&d[i]);
    return rc;
}

static void print_summary(FILE *f, const signal_cli *c, const st_signal_result *r)
{
    char fname[256], filt[128];
    describe_function(&c->o.fn, fname, sizeof fname);
    describe_filter(&c->o.recon, filt, sizeof filt);
    fprintf(f, "signal: %s, T = %g (Nyquist %g), %u samples in [0, %g), %s: rms error %.6g "
               "over %u points, max %.6g; dominant frequency: original %.6g, reconstruction %.6g",
            fname, c->o.spacing, r->nyquist, r->sample_count, c->o.length, filt, r->rms_error,
            r->points - r->zero_weight, r->max_error, r->dominant_original,
            r->dominant_reconstruction);
    if (c->o.fn.kind == ST_SIGNAL_SINE) {
        double k = floor(c->o.fn.freq * c->o.spacing + 0.5);
        fprintf(f, "; alias |f - k/T| = %.6g (k = %g)",
                st_signal_alias_frequency(c->o.fn.freq, c->o.spacing), k);
    }
    if (r->zero_weight)
        fprintf(f, "; %u points with zero filter weight (no reconstruction)", r->zero_weight);
    fputc('\n', f);
}

int st_cli_signal(int argc, char **argv)
{
    signal_cli c;
    memset(&c, 0, sizeof c);
    int rc = parse(argc, argv, &c);
    if (rc)
        return rc == ST_CLI_HELP ? 0 : rc;
    st_error err = {0};
    st_signal_result r;
    if (st_signal_build(&c.o, &r, &err) != ST_OK)
        return st_cli_fail(&err);
    if ((c.csv && write_text(c.csv, emit_signal, &c, &r, &err)) ||
        (c.spectrum_csv && write_text(c.spectrum_csv, emit_spectrum, &c, &r, &err)) ||
        (c.png && write_png(&c, &r, &err))) {
        st_signal_result_free(&r);
        return st_cli_fail(&err);
    }
    int to_stdout = (c.csv && !strcmp(c.csv, "-")) ||
                    (c.spectrum_csv && !strcmp(c.spectrum_csv, "-"));
    print_summary(to_stdout ? stderr : stdout, &c, &r);
    st_signal_result_free(&r);
    return 0;
}
