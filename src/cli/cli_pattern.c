/* cli_pattern.c — `strata pattern`: a sampler's points as CSV, a scatter
 * plot, the periodogram (averaged over seeds for randomised samplers) with its
 * radial average, and the star and L2-star discrepancies. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_text.h"
#include "cli_args.h"
#include "cli_commands.h"
#include "cli_error.h"
#include "cli_names.h"
#include "rng.h"
#include "samplers.h"
#include "st_sampling.h"
#include "st_plot.h"
#include "st_render.h"

static const char pattern_help[] =
    "usage: strata pattern --sampler NAME --count N [options]\n"
    "  --sampler NAME      random, uniform, stratified, halton, hammersley, poisson,\n"
    "                      best-candidate, paddedsobol, sobol, zsobol, joint-stratified,\n"
    "                      pmj02, pmj02bn (count at most 4096)\n"
    "  --count N           number of points (poisson: the target; the radius follows)\n"
    "  --pixels            poisson, best-candidate: the renderer's tile instead of the\n"
    "                      lecture's pattern (Bridson's dart throwing, Mitchell's best\n"
    "                      candidate over the square): floor(sqrt(N))^2 pixels, each\n"
    "                      getting its share of the points one at a time, which costs\n"
    "                      the closest pairs (min distance x sqrt(N) about 0.6 at one\n"
    "                      point a pixel, 0.78 without pixels)\n"
    "  --dims D            dimensions per point (default 2)\n"
    "  --seed S            random seed (default 0)\n"
    "  --scramble on|none  randomise halton, hammersley, the sobols, stratified order (default on)\n"
    "  --csv FILE|-        the points, one per line, comma-separated, in [0,1)^D, after a\n"
    "                      header row x0,x1,... naming the dimensions\n"
    "  --png FILE          scatter plot of the first two dimensions\n"
    "  --spectrum FILE     periodogram |sum_j exp(-2 pi i k.x_j)|^2 / N over integer k,\n"
    "                      centred, log-scaled (PNG)\n"
    "  --radial FILE|-     radially averaged power as CSV (frequency,power,count)\n"
    "  --kmax K            largest |k| component of the spectrum (default 2 sqrt(N), 32..256)\n"
    "  --range LO,HI       the spectrum's colour range in log10 P (default: the data's)\n"
    "  --seeds K           seeds averaged by the spectrum of a randomised sampler (default 16)\n"
    "  --discrepancy       print the star discrepancy (exact, first two dimensions), the\n"
    "                      L2-star discrepancy (Warnock's formula, all dimensions) and\n"
    "                      the minimum distance between points x sqrt(N) (first two);\n"
    "                      O(N^2): at most 65536 points (about 16 s)\n";

typedef struct pattern_args {
    st_u32 sampler, count, dims, seed, scramble, kmax, seeds;
    int have_sampler, have_count, discrepancy, scramble_given, pixels;
    const char *csv, *png, *spectrum, *radial;
    double range[2]; /* --range LO,HI of the spectrum's colours (log10 P); equal: the data's */
} pattern_args;

/* Both discrepancies are O(N^2): measured here, ~4 ns a point pair (N = 65536:
 * 16 s of CPU), so a million points would take over an hour with no word. */
#define DISCREPANCY_MAX_COUNT 65536u
#define DISCREPANCY_PAIR_NS 4.0

enum { P_SAMPLER = 300, P_COUNT, P_DIMS, P_SEED, P_SCRAMBLE, P_CSV, P_PNG, P_SPECTRUM, P_RADIAL,
       P_KMAX, P_SEEDS, P_DISCREPANCY, P_RANGE, P_PIXELS };

/* --range LO,HI: two finite numbers, LO < HI. */
static int parse_range(const char *v, double range[2])
{
    char tail;
    if (sscanf(v, "%lf,%lf%c", &range[0], &range[1], &tail) != 2 || !isfinite(range[0]) ||
        !isfinite(range[1]) || range[0] >= range[1])
        return st_cli_usage_error("--range %s: expected LO,HI with LO < HI (log10 of the power)", v);
    return ST_CLI_OK;
}

static int parse(int argc, char **argv, pattern_args *a)
{
    static const struct option opts[] = {
        {"sampler", required_argument, 0, P_SAMPLER}, {"count", required_argument, 0, P_COUNT},
        {"dims", required_argument, 0, P_DIMS}, {"seed", required_argument, 0, P_SEED},
        {"scramble", required_argument, 0, P_SCRAMBLE}, {"csv", required_argument, 0, P_CSV},
        {"png", required_argument, 0, P_PNG}, {"spectrum", required_argument, 0, P_SPECTRUM},
        {"radial", required_argument, 0, P_RADIAL}, {"kmax", required_argument, 0, P_KMAX},
        {"seeds", required_argument, 0, P_SEEDS}, {"range", required_argument, 0, P_RANGE},
        {"discrepancy", no_argument, 0, P_DISCREPANCY}, {"pixels", no_argument, 0, P_PIXELS},
        {"help", no_argument, 0, 'h'},
        {0, 0, 0, 0}};
    memset(a, 0, sizeof *a);
    a->dims = 2;
    a->scramble = 1;
    a->seeds = 16;
    opterr = 0;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, ":h", opts, NULL)) != -1) {
        const char *v = optarg;
        int rc = ST_CLI_OK;
        switch (c) {
        case 'h': fputs(pattern_help, stdout); return ST_CLI_HELP;
        case '?': return st_cli_unknown_option("pattern", argv[optind - 1], opts);
        case ':': return st_cli_usage_error("pattern: option %s needs a value", argv[optind - 1]);
        case P_SAMPLER: {
            int k = st_sampler_lookup(v);
            if (k < 0)
                return st_cli_unknown_name("--sampler", v, st_sampler_names, ST_SAMPLER_COUNT);
            a->sampler = (st_u32)k;
            a->have_sampler = 1;
            break;
        }
        case P_COUNT:
            rc = st_cli_parse_u32("--count", v, 1, ST_SAMPLING_PATTERN_MAX_COUNT, &a->count);
            a->have_count = 1;
            break;
        case P_DIMS: rc = st_cli_parse_u32("--dims", v, 1, ST_SAMPLING_PATTERN_MAX_DIMS, &a->dims); break;
        case P_SEED: rc = st_cli_parse_u32("--seed", v, 0, 0xffffffffu, &a->seed); break;
        case P_SCRAMBLE:
            if (strcmp(v, "on") && strcmp(v, "none"))
                return st_cli_usage_error("--scramble %s: expected on or none", v);
            a->scramble = !strcmp(v, "on");
            a->scramble_given = 1;
            break;
        case P_CSV: a->csv = v; break;
        case P_PNG: a->png = v; break;
        case P_SPECTRUM: a->spectrum = v; break;
        case P_RADIAL: a->radial = v; break;
        case P_KMAX: rc = st_cli_parse_u32("--kmax", v, 1, ST_SPECTRUM_KMAX_MAX, &a->kmax); break;
        case P_SEEDS: rc = st_cli_parse_u32("--seeds", v, 1, 4096, &a->seeds); break;
        case P_DISCREPANCY: a->discrepancy = 1; break;
        case P_PIXELS: a->pixels = 1; break;
        case P_RANGE: rc = parse_range(v, a->range); break;
        }
        if (rc)
            return rc;
    }
    if (optind < argc)
        return st_cli_usage_error("pattern: unexpected argument %s", argv[optind]);
    if (!a->have_sampler || !a->have_count)
        return st_cli_usage_error("pattern: --sampler and --count are required");
    if (a->scramble_given && !st_sampler_takes_scramble(a->sampler))
        return st_cli_usage_error("--scramble applies to stratified, halton, hammersley, "
                                  "paddedsobol, sobol and zsobol, not %s", st_sampler_names[a->sampler]);
    if (a->pixels && !ST_SAMPLER_IS_TILED(a->sampler))
        return st_cli_usage_error("--pixels applies to poisson and best-candidate, not %s",
                                  st_sampler_names[a->sampler]);
    if (a->discrepancy && a->count > DISCREPANCY_MAX_COUNT) {
        double pairs = (double)a->count * a->count;
        return st_cli_usage_error("--discrepancy with --count %u: O(N^2) work, %.3g point pairs "
                                  "(about %.0f s at %g ns a pair); at most %u points",
                                  a->count, pairs, pairs * DISCREPANCY_PAIR_NS * 1e-9,
                                  DISCREPANCY_PAIR_NS, DISCREPANCY_MAX_COUNT);
    }
    if (!a->csv && !a->png && !a->spectrum && !a->radial && !a->discrepancy)
        return st_cli_usage_error("pattern: nothing to do (give --csv, --png, --spectrum, "
                                  "--radial or --discrepancy)");
    st_outfile_role files[] = {{a->csv, "--csv"}, {a->png, "--png"}, {a->spectrum, "--spectrum"},
                               {a->radial, "--radial"}};
    return st_cli_check_apart(files, 4, 4);
}


typedef struct points_ctx { const float *pts; st_u32 n, dims; } points_ctx;

static void emit_points(FILE *f, const void *ctx)
{
    const points_ctx *c = ctx;
    /* a header row naming the dimensions, as every CSV strata writes has one */
    for (st_u32 d = 0; d < c->dims; d++)
        fprintf(f, "x%u%c", d, d + 1 == c->dims ? '\n' : ',');
    for (st_u32 i = 0; i < c->n; i++)
        for (st_u32 d = 0; d < c->dims; d++)
            fprintf(f, "%.9g%c", (double)c->pts[(size_t)i * c->dims + d],
                    d + 1 == c->dims ? '\n' : ',');
}

typedef struct radial_ctx { const double *radial; const st_u32 *counts; st_u32 kmax; } radial_ctx;

static void emit_radial(FILE *f, const void *ctx)
{
    const radial_ctx *c = ctx;
    fprintf(f, "frequency,power,count\n");
    for (st_u32 b = 0; b <= c->kmax; b++)
        fprintf(f, "%u,%.9g,%u\n", b, c->radial[b], c->counts[b]);
}

static st_status scatter(const pattern_args *a, const float *pts, st_u32 n, st_error *err)
{
    char title[160];
    snprintf(title, sizeof title, "%s, N = %u%s", st_sampler_names[a->sampler], n,
             a->scramble ? "" : ", unscrambled");
    st_plot_scatter s;
    memset(&s, 0, sizeof s);
    s.title = title;
    s.points = pts;
    s.count = n;
    s.stride = a->dims;
    if (a->sampler == ST_SAMPLER_STRATIFIED)
        st_stratified_grid(n, &s.strata_nx, &s.strata_ny);
    s.toroidal = ST_SAMPLER_IS_TILED(a->sampler);
    s.xlabel = "x (dimension 1)";
    s.ylabel = "y (dimension 2)";
    return st_plot_save_scatter(a->png, &s, 640, 680, err);
}

static int by_value(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* The colour range from the data: log10 P from its 1st percentile to its largest value over
 * every k but k = 0, whose power is always N (the scale would spend itself on that one cell),
 * the percentile so that a few exact cancellations (Halton's k_y = 0 row holds 1e-30) do not
 * stretch it; [-1, 1] when nothing else is positive. */
static void data_range(const double *power, st_u32 kmax, double *lo, double *hi)
{
    st_u32 side = 2 * kmax + 1;
    size_t n = 0;
    double *v = malloc((size_t)side * side * sizeof *v);
    for (size_t i = 0; v && i < (size_t)side * side; i++)
        if (i != (size_t)kmax * side + kmax && power[i] > 0 && isfinite(power[i]))
            v[n++] = log10(power[i]);
    *lo = -1, *hi = 1;
    if (n > 1) {
        qsort(v, n, sizeof *v, by_value);
        if (v[n / 100] < v[n - 1])
            *lo = v[n / 100], *hi = v[n - 1];
    }
    free(v);
}

/* The points asked for, at seed: the pattern, or with --pixels the
 * renderer's tile. */
static st_status points_of(const pattern_args *a, st_u32 seed, float **pts, st_u32 *n,
                           st_error *err)
{
    if (a->pixels)
        return st_sampling_pattern_pixels(a->sampler, a->count, a->dims, seed, pts, n, err);
    return st_sampling_pattern(a->sampler, a->count, a->dims, seed, a->scramble, pts, n, err);
}

/* The periodogram averaged over seeds seed, seed+1, ... (one pass for a
 * deterministic pattern), its picture and its radial average. */
static st_status spectrum(const pattern_args *a, st_u32 n0, st_error *err)
{
    st_u32 kmax = a->kmax;
    if (!kmax) {
        kmax = (st_u32)(2.0 * sqrt((double)n0));
        kmax = kmax < 32 ? 32 : kmax > 256 ? 256 : kmax;
    }
    st_u32 side = 2 * kmax + 1, runs = st_sampling_pattern_is_random(a->sampler, a->scramble) ? a->seeds : 1;
    double *power = calloc((size_t)side * side, sizeof *power);
    double *radial = calloc(kmax + 1, sizeof *radial);
    st_u32 *counts = calloc(kmax + 1, sizeof *counts);
    st_status rc = ST_OK;
    if (!power || !radial || !counts) {
        rc = st_fail(err, ST_ERR_NOMEM, "out of memory for the spectrum");
        goto done;
    }
    for (st_u32 r = 0; r < runs && rc == ST_OK; r++) {
        float *pts;
        st_u32 n;
        rc = points_of(a, a->seed + r, &pts, &n, err);
        if (rc == ST_OK)
            rc = st_spectrum_periodogram(pts, n, a->dims, kmax, power, err);
        free(pts);
    }
    for (size_t i = 0; rc == ST_OK && i < (size_t)side * side; i++)
        power[i] /= runs;
    if (rc == ST_OK && a->spectrum) {
        char title[160];
        snprintf(title, sizeof title, "%s, N = %u: periodogram, mean of %u seed%s",
                 st_sampler_names[a->sampler], n0, runs, runs > 1 ? "s" : "");
        st_plot_heatmap h;
        memset(&h, 0, sizeof h);
        h.title = title;
        h.colorbar_label = "log10 P(k)";
        h.values = power;
        h.width = h.height = side;
        h.log10 = 1;
        h.vmin = a->range[0];
        h.vmax = a->range[1];
        if (h.vmin >= h.vmax) /* not given: from the data */
            data_range(power, kmax, &h.vmin, &h.vmax);
        h.xlabel = "frequency k_x (cycles per unit)";
        h.ylabel = "frequency k_y";
        h.x0 = h.y0 = -(double)kmax;
        h.x1 = h.y1 = (double)kmax;
        rc = st_plot_save_heatmap(a->spectrum, &h, 720, 680, err);
    }
    if (rc == ST_OK && a->radial) {
        st_spectrum_radial(power, kmax, radial, counts);
        radial_ctx c = {radial, counts, kmax};
        rc = st_cli_write_text(a->radial, emit_radial, &c, err);
    }
done:
    free(power);
    free(radial);
    free(counts);
    return rc;
}

int st_cli_pattern(int argc, char **argv)
{
    pattern_args a;
    int rc = parse(argc, argv, &a);
    if (rc)
        return rc == ST_CLI_HELP ? 0 : rc;
    st_error err = {0};
    float *pts = NULL;
    st_u32 n = 0;
    if (points_of(&a, a.seed, &pts, &n, &err))
        return st_cli_fail(&err);
    points_ctx pc = {pts, n, a.dims};
    if ((a.csv && st_cli_write_text(a.csv, emit_points, &pc, &err)) ||
        (a.png && scatter(&a, pts, n, &err)) ||
        ((a.spectrum || a.radial) && spectrum(&a, n, &err))) {
        free(pts);
        return st_cli_fail(&err);
    }
    if (a.discrepancy) {
        float *xy = malloc(sizeof(float) * 2 * n);
        if (!xy) {
            free(pts);
            return st_cli_fail(&(st_error){ST_ERR_NOMEM, "out of memory"});
        }
        for (st_u32 i = 0; i < n; i++) {
            xy[2 * i] = pts[(size_t)i * a.dims];
            xy[2 * i + 1] = a.dims > 1 ? pts[(size_t)i * a.dims + 1] : 0.0f;
        }
        if (a.dims >= 2)
            printf("star discrepancy (exact, 2-D): %.9f\n", st_star_discrepancy_2d(xy, n));
        if (a.dims >= 2 && n >= 2) /* blue noise keeps it near 0.75, random falls to 0 */
            printf("minimum distance x sqrt(N) (2-D): %.4f (toroidal %.4f)\n",
                   st_min_distance_2d(xy, n, 0) * sqrt((double)n),
                   st_min_distance_2d(xy, n, 1) * sqrt((double)n));
        printf("L2-star discrepancy (Warnock, %u-D): %.9f\n", a.dims,
               st_l2_star_discrepancy(pts, n, a.dims));
        free(xy);
    }
    free(pts);
    return 0;
}
