/* cli_converge.c — `strata converge`: how fast each sampler's error falls
 * with the number of samples per pixel. One process, one scene upload and one
 * kernel build; for each sampler and sample count, K seeds (one for the
 * deterministic patterns), RMSE and relative MSE against a reference, over
 * the whole image or a --region; a CSV and a log-log plot with the fitted
 * slope of each sampler (error ∝ N^slope: -0.5 for independent samples).
 *
 * The reference has noise of its own: a measured MSE is the true MSE plus
 * the reference's variance (independent of the study's renders), so the
 * curves flatten onto that floor at high spp and a slope fitted into it
 * comes out too flat. A reference made here is therefore the mean of two
 * independent renders of N/2 spp (other seeds), whose difference estimates
 * its variance: floor^2 = mean over the region and R, G, B of (a - b)^2 / 4.
 * Each render's RMSE is then reported with the floor taken out in quadrature,
 * sqrt(max(e^2 - floor^2, 0)) (the measured one beside it, rmse_measured);
 * a slope is fitted only over points whose measured RMSE is at least
 * FLOOR_FACTOR times the floor (below, the difference of two nearly equal
 * squares is mostly the floor's own uncertainty), and the floor is reported.
 * A given --reference FILE has no estimate (one image cannot show its own
 * noise): nothing is taken out. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_text.h"
#include "cli_args.h"
#include "cli_commands.h"
#include "cli_error.h"
#include "cli_names.h"
#include "cli_progress.h"
#include "cli_session.h"
#include "st_sampling.h"
#include "st_plot.h"

#define MAX_SERIES 16
#define MAX_SPP 32
#define FLOOR_FACTOR 3.0

static const char converge_help[] =
    "usage: strata converge [SCENE] --sampler LIST --spp-list LIST [options] [render options]\n"
    "  --sampler LIST        comma-separated samplers: random, uniform, stratified, halton,\n"
    "                        hammersley, poisson, best-candidate, paddedsobol, sobol, zsobol,\n"
    "                        joint-stratified, pmj02, pmj02bn\n"
    "  --spp-list LIST       comma-separated samples per pixel, e.g. 4,16,64,256\n"
    "  --reference FILE.exr  the reference image (same size), or\n"
    "  --reference-spp N     render it here (default 1024): the mean of two paddedsobol\n"
    "                        renders of N/2 spp with other seeds, whose difference gives\n"
    "                        the reference's own error (the floor, reported); slopes are\n"
    "                        fitted only where the RMSE is at least 3 times the floor\n"
    "  --seeds K             seeds per randomised sampler and count (default 4)\n"
    "  --region X,Y,W,H      measure only this pixel rectangle (default: the whole image)\n"
    "  --csv FILE|-          sampler,spp,seeds,rmse,rmse_stderr,rel_mse,rmse_measured: rmse\n"
    "                        with the reference's floor taken out in quadrature,\n"
    "                        sqrt(e^2 - floor^2) per render (rmse_measured: e)\n"
    "  --png FILE            log-log plot of RMSE against spp, the fitted slope in the legend\n"
    "  --error-spectrum FILE power spectrum of the per-pixel error (mean of R, G, B minus the\n"
    "                        reference) at the first --spp-list count, one panel per sampler,\n"
    "                        mean over seeds (PNG): white error is flat, blue noise dark inside\n"
    "  --adaptive            also each sampler with adaptive sampling at the same cost (N spp\n"
    "                        on average, the default pilot and cap; --noise-threshold), at\n"
    "                        its mean spp\n"
    "  render options: --width, --height, --filter..., --integrator, --max-depth, --device, ...\n"
    "  (not --spp, --max-spp, --min-spp, --sample-range, --part, --spp-map: the study\n"
    "  sets them)\n"
    "relative MSE: the mean of (x - r)^2 / (r^2 + 0.01) over pixels and R, G, B\n";

typedef struct converge_args {
    st_cli_render_args r;
    st_u32 samplers[MAX_SERIES], nsamplers;
    st_u32 spp[MAX_SPP], nspp;
    const char *reference, *csv, *png;
    const char *error_spectrum; /* --error-spectrum FILE.png, or NULL */
    st_u32 reference_spp, seeds;
    st_u32 region[4];
    int have_region;
    double floor; /* the reference's own RMSE over the region; NaN: not estimated */
} converge_args;

/* Parses a comma-separated list of unsigned integers or of sampler names. */
static int parse_list(const char *opt, const char *s, int names, st_u32 *out, st_u32 max,
                      st_u32 *n)
{
    char buf[512];
    snprintf(buf, sizeof buf, "%s", s);
    *n = 0;
    for (char *tok = strtok(buf, ","); tok; tok = strtok(NULL, ",")) {
        if (*n == max)
            return st_cli_usage_error("%s %s: at most %u entries", opt, s, max);
        if (names) {
            int k = st_sampler_lookup(tok);
            if (k < 0)
                return st_cli_unknown_name(opt, tok, st_sampler_names, ST_SAMPLER_COUNT);
            out[(*n)++] = (st_u32)k;
        } else if (st_cli_parse_u32(opt, tok, 1, 1u << 20, &out[(*n)++])) {
            return ST_CLI_EXIT_USAGE;
        }
    }
    if (*n == 0)
        return st_cli_usage_error("%s '%s': an empty list", opt, s);
    for (st_u32 i = 1; !names && i < *n; i++)
        if (out[i] <= out[i - 1])
            return st_cli_usage_error("%s %s: counts must increase", opt, s);
    return ST_CLI_OK;
}

static int parse(int argc, char **argv, converge_args *c)
{
    memset(c, 0, sizeof *c);
    c->reference_spp = 1024;
    c->seeds = 4;
    char **rest = calloc((size_t)argc + 1, sizeof *rest);
    int nrest = 0, rc = ST_CLI_OK, have_sampler = 0, have_spp = 0;
    if (!rest)
        return st_cli_usage_error("out of memory");
    rest[nrest++] = argv[0];
    for (int i = 1; i < argc && rc == ST_CLI_OK; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int takes = !strcmp(a, "--sampler") || !strcmp(a, "--spp-list") ||
                    !strcmp(a, "--reference") || !strcmp(a, "--reference-spp") ||
                    !strcmp(a, "--seeds") || !strcmp(a, "--region") || !strcmp(a, "--csv") ||
                    !strcmp(a, "--png") || !strcmp(a, "--error-spectrum");
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(converge_help, stdout);
            rc = ST_CLI_HELP;
        } else if (!strcmp(a, "--spp") || !strcmp(a, "--max-spp") || !strcmp(a, "--min-spp") ||
                   !strcmp(a, "--sample-range") || !strcmp(a, "--part") ||
                   !strcmp(a, "--spp-map")) {
            rc = st_cli_usage_error("converge: %s is set by the study (use --spp-list)", a);
        } else if (takes && !v) {
            rc = st_cli_usage_error("converge: option %s needs a value", a);
        } else if (!strcmp(a, "--sampler")) {
            rc = parse_list(a, v, 1, c->samplers, MAX_SERIES, &c->nsamplers);
            have_sampler = 1;
        } else if (!strcmp(a, "--spp-list")) {
            rc = parse_list(a, v, 0, c->spp, MAX_SPP, &c->nspp);
            have_spp = 1;
        } else if (!strcmp(a, "--reference")) {
            c->reference = v;
        } else if (!strcmp(a, "--reference-spp")) {
            rc = st_cli_parse_u32(a, v, 1, 1u << 20, &c->reference_spp);
        } else if (!strcmp(a, "--seeds")) {
            rc = st_cli_parse_u32(a, v, 1, 1024, &c->seeds);
        } else if (!strcmp(a, "--csv")) {
            c->csv = v;
        } else if (!strcmp(a, "--png")) {
            c->png = v;
        } else if (!strcmp(a, "--error-spectrum")) {
            c->error_spectrum = v;
        } else if (!strcmp(a, "--region")) {
            char tail;
            st_u32 *g = c->region;
            if (sscanf(v, "%u,%u,%u,%u%c", &g[0], &g[1], &g[2], &g[3], &tail) != 4 ||
                strchr(v, '-') || g[2] == 0 || g[3] == 0)
                rc = st_cli_usage_error("--region %s: expected X,Y,W,H with W, H >= 1", v);
            c->have_region = 1;
        } else {
            rest[nrest++] = argv[i];
            continue;
        }
        if (takes)
            i++;
    }
    if (rc == ST_CLI_OK)
        rc = st_cli_parse_render_args(nrest, rest, 2, &c->r);
    free(rest);
    if (rc)
        return rc;
    if (!have_sampler || !have_spp)
        return st_cli_usage_error("converge: --sampler LIST and --spp-list LIST are required");
    const st_render_options *o = &c->r.opt;
    if (c->have_region && ((st_u64)c->region[0] + c->region[2] > o->width ||
                           (st_u64)c->region[1] + c->region[3] > o->height))
        return st_cli_usage_error("--region %u,%u,%u,%u: outside the %ux%u image", c->region[0],
                                  c->region[1], c->region[2], c->region[3], o->width, o->height);
    if (!c->have_region) {
        c->region[2] = o->width;
        c->region[3] = o->height;
    }
    if (!c->csv && !c->png && !c->error_spectrum)
        return st_cli_usage_error("converge: nothing to write (give --csv, --png or "
                                  "--error-spectrum)");
    if (c->error_spectrum && c->nsamplers * (o->adaptive ? 2u : 1u) > ST_PLOT_MAX_PANELS)
        return st_cli_usage_error("--error-spectrum: at most %u panels (samplers, with "
                                  "--adaptive twice)", ST_PLOT_MAX_PANELS);
    st_outfile_role files[] = {{c->csv, "--csv"}, {c->png, "--png"},
                               {c->error_spectrum, "--error-spectrum"}, {c->r.scene, "the scene"},
                               {c->reference, "--reference"}, {c->r.env_file, "--env"}};
    return st_cli_check_apart(files, 6, 3);
}

typedef struct series {
    char name[48];
    st_u32 sampler, adaptive, n;
    double spp[MAX_SPP], rmse[MAX_SPP], stderr_[MAX_SPP], rel[MAX_SPP], seeds[MAX_SPP];
    double measured[MAX_SPP]; /* rmse before the floor is taken out */
    double slope;   /* fitted over the falling part above the floor only */
    st_u32 falling; /* points 0 .. falling-1 fall; a plateau follows when falling < n */
    st_u32 above;   /* points 0 .. above-1 lie FLOOR_FACTOR times above the floor */
    double *error_power; /* --error-spectrum: region-sized, summed over seeds */
    st_u32 error_runs;
} series;

/* RMSE and relative MSE of img against ref over the region (R, G, B). */
static void measure(const converge_args *c, const st_image *img, const st_image *ref,
                    int ir[3], double *rmse, double *rel)
{
    double se = 0, rs = 0;
    size_t n = 0;
    for (st_u32 y = c->region[1]; y < c->region[1] + c->region[3]; y++)
        for (st_u32 x = c->region[0]; x < c->region[0] + c->region[2]; x++) {
            size_t i = (size_t)y * img->width + x;
            for (int ch = 0; ch < 3; ch++) {
                double r = ref->data[i * ref->channels + ir[ch]];
                double d = img->data[i * img->channels + ch] - r;
                se += d * d;
                rs += d * d / (r * r + 0.01);
                n++;
            }
        }
    *rmse = sqrt(se / n);
    *rel = rs / n;
}

/* How many leading points still fall: each must be below the one before by more than twice
 * their combined standard error, at a local rate steeper than N^-0.1; from the first that is
 * not, the curve has reached a plateau (the uniform grid converges to its own biased image). */
static st_u32 falling_part(const series *s)
{
    st_u32 k = 1;
    while (k < s->n) {
        double drop = s->rmse[k - 1] - s->rmse[k];
        double noise = 2.0 * sqrt(s->stderr_[k - 1] * s->stderr_[k - 1] +
                                  s->stderr_[k] * s->stderr_[k]);
        double rate = log(s->rmse[k] / s->rmse[k - 1]) / log(s->spp[k] / s->spp[k - 1]);
        if (!(drop > noise && rate < -0.1))
            break;
        k++;
    }
    return k;
}

/* How many leading points lie at least FLOOR_FACTOR times above the floor (all of them
 * when it is not known). */
static st_u32 above_floor(const series *s, double floor)
{
    st_u32 k = 0;
    while (k < s->n && !(s->measured[k] < FLOOR_FACTOR * floor))
        k++;
    return k;
}

/* Least-squares slope of log(rmse) against log(spp) over the falling part above the floor
 * (NaN when that is a single point or none). */
static double fit_slope(series *s, double floor)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    s->falling = falling_part(s);
    s->above = above_floor(s, floor);
    st_u32 n = s->falling < s->above ? s->falling : s->above;
    for (st_u32 i = 0; i < n; i++) {
        double x = log(s->spp[i]), y = log(s->rmse[i]);
        sx += x; sy += y; sxx += x * x; sxy += x * y;
    }
    double d = n * sxx - sx * sx;
    return n > 1 && d != 0 ? (n * sxy - sx * sy) / d : NAN;
}

/* The reference made here: the mean of two independent paddedsobol renders
 * of ceil(N/2) spp into *ref (R, G, B at channels 0..2), and c->floor from
 * their difference over the region: Var((a + b) / 2) = E[(a - b)^2] / 4. */
static st_status render_reference(converge_args *c, st_cli_session *s, st_image *ref,
                                  st_error *err)
{
    st_render_options ro = c->r.opt;
    ro.sampler = ST_SAMPLER_PADDED_SOBOL;
    ro.spp = (c->reference_spp + 1) / 2;
    ro.adaptive = 0;
    st_image other = {0};
    ro.seed = c->r.opt.seed + 0x5eed5eedu; /* independent of the study's seeds */
    if (st_cli_render_with_progress(s, &ro, "converge: reference, first half", c->r.quiet, ref,
                                    err) != ST_OK)
        return err->status;
    ro.seed += 1u;
    if (st_cli_render_with_progress(s, &ro, "converge: reference, second half", c->r.quiet,
                                    &other, err) != ST_OK)
        return err->status;
    double sq = 0;
    size_t n = 0;
    for (st_u32 y = 0; y < ref->height; y++)
        for (st_u32 x = 0; x < ref->width; x++) {
            size_t i = (size_t)y * ref->width + x;
            int in = x >= c->region[0] && x < c->region[0] + c->region[2] &&
                     y >= c->region[1] && y < c->region[1] + c->region[3];
            for (int ch = 0; ch < 3; ch++) {
                float *a = &ref->data[i * ref->channels + ch];
                double b = other.data[i * other.channels + ch], d = *a - b;
                if (in) {
                    sq += d * d / 4;
                    n++;
                }
                *a = (float)(((double)*a + b) / 2);
            }
        }
    c->floor = sqrt(sq / (double)n);
    st_image_free(&other);
    return ST_OK;
}

static st_status get_reference(converge_args *c, st_cli_session *s, st_image *ref, int ir[3],
                               st_error *err)
{
    const st_render_options *o = &c->r.opt;
    c->floor = NAN;
    if (c->reference) {
        if (st_image_load(c->reference, ref, err) != ST_OK)
            return err->status;
        if (ref->width != o->width || ref->height != o->height)
            return st_fail(err, ST_ERR_USAGE, "%s: %ux%u pixels, the study renders %ux%u",
                           c->reference, ref->width, ref->height, o->width, o->height);
    } else if (render_reference(c, s, ref, err) != ST_OK) {
        return err->status;
    }
    const char *names[3] = {"R", "G", "B"};
    for (int ch = 0; ch < 3; ch++)
        if ((ir[ch] = st_image_find_channel(ref, names[ch])) < 0)
            return st_fail(err, ST_ERR_FORMAT, "%s: no channel %s",
                           c->reference ? c->reference : "reference", names[ch]);
    return ST_OK;
}

/* --error-spectrum: adds the power spectrum of the region's error image
 * e = mean over R, G, B of (img - ref) to the series' sum. */
static st_status add_error_spectrum(const converge_args *c, const st_image *img,
                                    const st_image *ref, const int ir[3], series *se,
                                    st_error *err)
{
    st_u32 w = c->region[2], h = c->region[3];
    double *e = malloc(sizeof *e * w * h);
    if (!se->error_power)
        se->error_power = calloc((size_t)w * h, sizeof *se->error_power);
    if (!e || !se->error_power) {
        free(e);
        return st_fail(err, ST_ERR_NOMEM, "out of memory for the error spectrum");
    }
    for (st_u32 y = 0; y < h; y++)
        for (st_u32 x = 0; x < w; x++) {
            size_t i = (size_t)(y + c->region[1]) * img->width + x + c->region[0];
            double d = 0;
            for (int ch = 0; ch < 3; ch++)
                d += img->data[i * img->channels + ch] - ref->data[i * ref->channels + ir[ch]];
            e[(size_t)y * w + x] = d / 3;
        }
    st_status rc = st_spectrum_image(e, w, h, se->error_power, err);
    se->error_runs++;
    free(e);
    return rc;
}

/* --error-spectrum: one log-scaled heatmap per series, side by side, with
 * one colour range for all (the mean over seeds; heatmap rows run upwards,
 * so row r of the image is frequency ky = r - h/2 either way). */
static st_status write_error_spectrum(const converge_args *c, series *ss, st_u32 ns,
                                      st_error *err)
{
    st_u32 w = c->region[2], h = c->region[3];
    st_plot_heatmap hm[ST_PLOT_MAX_PANELS];
    st_plot_panel panels[ST_PLOT_MAX_PANELS];
    char titles[ST_PLOT_MAX_PANELS][96];
    double lo = INFINITY, hi = -INFINITY;
    for (st_u32 i = 0; i < ns; i++)
        for (size_t j = 0; j < (size_t)w * h; j++) {
            double v = ss[i].error_power[j] /= ss[i].error_runs;
            if (v > 0) {
                lo = fmin(lo, log10(v));
                hi = fmax(hi, log10(v));
            }
        }
    for (st_u32 i = 0; i < ns; i++) {
        snprintf(titles[i], sizeof titles[i], "%s, %u spp: error spectrum (%u seeds)",
                 ss[i].name, c->spp[0], ss[i].error_runs);
        hm[i] = (st_plot_heatmap){.title = titles[i], .colorbar_label = "log10 |E(k)|^2 / N",
                                  .xlabel = "frequency k_x (cycles per region width)",
                                  .ylabel = "frequency k_y (cycles per region height)",
                                  .values = ss[i].error_power, .width = w, .height = h,
                                  .log10 = 1, .vmin = lo, .vmax = hi > lo ? hi : lo + 1,
                                  .x0 = -(double)(w / 2), .x1 = (double)(w - 1 - w / 2),
                                  .y0 = -(double)(h / 2), .y1 = (double)(h - 1 - h / 2)};
        panels[i] = (st_plot_panel){.kind = ST_PLOT_HEATMAP, .heatmap = &hm[i]};
    }
    return st_plot_save_row(c->error_spectrum, panels, ns, 560, 540, err);
}

/* The study's progress, counted in samples (a render of 1024 spp costs 1024 of 1 spp):
 * a render's own fraction placed after the samples of the renders before it. */
typedef struct study_progress {
    st_cli_progress_state *prog;
    double done, total; /* samples: rendered before the current render, in all */
    double render;      /* the current render's samples */
} study_progress;

static void study_progress_cb(void *ctx, double fraction)
{
    study_progress *p = ctx;
    st_cli_progress(p->prog, (p->done + fraction * p->render) / p->total);
}

/* The samples of every render of series se at point k (the mean spp of an adaptive one). */
static double point_samples(const converge_args *c, const series *se, st_u32 k)
{
    st_u32 runs = st_sampling_pattern_is_random(se->sampler, c->r.opt.scramble) || se->adaptive
                      ? c->seeds : 1;
    return (double)runs * c->spp[k] * c->r.opt.width * c->r.opt.height;
}

/* One point of one series: K seeds (one for a deterministic pattern). */
static st_status run_point(const converge_args *c, st_cli_session *s, const st_image *ref,
                           int ir[3], series *se, st_u32 k, study_progress *prog, st_error *err)
{
    st_render_options o = c->r.opt;
    o.sampler = se->sampler;
    o.adaptive = se->adaptive;
    o.spp = c->spp[k]; /* adaptive: the mean, so both cost the same */
    st_u32 runs = st_sampling_pattern_is_random(o.sampler, o.scramble) || o.adaptive ? c->seeds : 1;
    double sum = 0, sum2 = 0, raw = 0, rel = 0, samples = 0;
    for (st_u32 r = 0; r < runs; r++) {
        st_image img = {0};
        st_render_stats st = {0};
        o.seed = c->r.opt.seed + r;
        prog->render = (double)o.spp * o.width * o.height;
        if (st_render(s->renderer, &o, &img, NULL, &st, study_progress_cb, prog, err) != ST_OK)
            return err->status;
        double e, q;
        measure(c, &img, ref, ir, &e, &q);
        if (c->error_spectrum && k == 0 && add_error_spectrum(c, &img, ref, ir, se, err) != ST_OK) {
            st_image_free(&img);
            return err->status;
        }
        raw += e;
        if (c->floor == c->floor) /* the reference's own error out, in quadrature */
            e = sqrt(fmax(e * e - c->floor * c->floor, 0.0));
        sum += e;
        sum2 += e * e;
        rel += q;
        samples += (double)st.samples;
        free(st.spp_map);
        st_image_free(&img);
        prog->done += prog->render; /* the render's own last report said so already */
    }
    double mean = sum / runs, var = runs > 1 ? (sum2 - runs * mean * mean) / (runs - 1) : 0;
    se->spp[k] = se->adaptive ? samples / runs / ((double)o.width * o.height) : c->spp[k];
    se->rmse[k] = mean;
    se->measured[k] = raw / runs;
    se->stderr_[k] = runs > 1 ? sqrt(fmax(var, 0) / runs) : 0;
    se->rel[k] = rel / runs;
    se->seeds[k] = runs;
    se->n = k + 1;
    return ST_OK;
}

typedef struct csv_ctx { const series *ss; st_u32 ns; } csv_ctx;

static void emit_csv(FILE *f, const void *ctx)
{
    const csv_ctx *c = ctx;
    fprintf(f, "sampler,spp,seeds,rmse,rmse_stderr,rel_mse,rmse_measured\n");
    for (st_u32 i = 0; i < c->ns; i++)
        for (st_u32 k = 0; k < c->ss[i].n; k++)
            fprintf(f, "%s,%.6g,%.0f,%.9g,%.9g,%.9g,%.9g\n", c->ss[i].name, c->ss[i].spp[k],
                    c->ss[i].seeds[k], c->ss[i].rmse[k], c->ss[i].stderr_[k], c->ss[i].rel[k],
                    c->ss[i].measured[k]);
}

/* "halton (slope -0.98)", "uniform (slope -0.51, flat from 16)", "sobol (slope -1.48 to
 * 256, then the floor)". */
static void series_legend(const series *s, char *buf, size_t size)
{
    if (s->falling >= s->n && s->above >= s->n)
        snprintf(buf, size, "%s (slope %.2f)", s->name, s->slope);
    else if (s->falling < s->above && s->falling < 2)
        snprintf(buf, size, "%s (plateau from %g spp)", s->name, s->spp[0]);
    else if (s->falling < s->above)
        snprintf(buf, size, "%s (slope %.2f, flat from %g)", s->name, s->slope,
                 s->spp[s->falling - 1]);
    else if (s->above < 2)
        snprintf(buf, size, "%s (at the floor)", s->name);
    else
        snprintf(buf, size, "%s (slope %.2f to %g, then the floor)", s->name, s->slope,
                 s->spp[s->above - 1]);
}

/* Guide lines N^-1/2 and N^-1 through the geometric mean of every series' first RMSE. */
static void guides(const series *ss, st_u32 ns, double *x, double *half, double *one)
{
    double lg = 0;
    for (st_u32 i = 0; i < ns; i++)
        lg += log(ss[i].measured[0]);
    double y0 = exp(lg / ns);
    for (st_u32 k = 0; k < ss[0].n; k++) {
        x[k] = ss[0].spp[k];
        half[k] = y0 * sqrt(ss[0].spp[0] / x[k]);
        one[k] = y0 * ss[0].spp[0] / x[k];
    }
}

static st_status write_outputs(const converge_args *c, series *ss, st_u32 ns, st_error *err)
{
    csv_ctx cc = {ss, ns};
    if (c->csv && st_cli_write_text(c->csv, emit_csv, &cc, err) != ST_OK)
        return err->status;
    if (c->png) {
        st_plot_series ps[MAX_SERIES * 2 + 3];
        char legend[MAX_SERIES * 2][96];
        for (st_u32 i = 0; i < ns; i++) {
            series_legend(&ss[i], legend[i], sizeof legend[i]);
            ps[i] = (st_plot_series){.name = legend[i], .x = ss[i].spp, .y = ss[i].measured,
                                     .n = ss[i].n, .style = ST_PLOT_STYLE_LINE_POINTS,
                                     .yerr = ss[i].stderr_};
        }
        double gx[MAX_SPP], g1[MAX_SPP], g2[MAX_SPP];
        guides(ss, ns, gx, g1, g2);
        ps[ns] = (st_plot_series){.name = "N^-1/2", .x = gx, .y = g1, .n = ss[0].n,
                                  .color = 0x888888, .width = 1.2, .dashed = 1};
        ps[ns + 1] = (st_plot_series){.name = "N^-1", .x = gx, .y = g2, .n = ss[0].n,
                                      .color = 0x444444, .width = 1.2, .dashed = 1};
        double fx[2] = {gx[0], gx[ss[0].n - 1]}, fy[2] = {c->floor, c->floor};
        st_u32 extra = 2;
        if (c->floor > 0) /* the reference's own error: the curves cannot fall below it */
            ps[ns + extra++] = (st_plot_series){.name = "reference floor", .x = fx, .y = fy,
                                                .n = 2, .color = 0xaa3333, .width = 1.2,
                                                .dashed = 1};
        char title[160];
        snprintf(title, sizeof title, "RMSE against samples per pixel (region %u,%u %ux%u)",
                 c->region[0], c->region[1], c->region[2], c->region[3]);
        st_plot_lines pl = {.title = title, .xlabel = "samples per pixel", .ylabel = "RMSE",
                             .series = ps, .series_count = ns + extra,
                             .flags = ST_PLOT_LOG_X | ST_PLOT_LOG_Y, .legend_outside = 1};
        if (st_plot_save_lines(c->png, &pl, 960, 600, err) != ST_OK)
            return err->status;
    }
    return ST_OK;
}

int st_cli_converge(int argc, char **argv)
{
    converge_args *c = calloc(1, sizeof *c);
    series *ss = calloc(MAX_SERIES * 2, sizeof *ss);
    if (!c || !ss) {
        free(c);
        free(ss);
        return st_cli_fail(&(st_error){ST_ERR_NOMEM, "out of memory"});
    }
    int rc = parse(argc, argv, c);
    if (rc) {
        free(c);
        free(ss);
        return rc == ST_CLI_HELP ? 0 : rc;
    }
    st_u32 ns = 0;
    for (st_u32 i = 0; i < c->nsamplers; i++)
        for (int adaptive = 0; adaptive <= c->r.opt.adaptive; adaptive++) {
            series *s = &ss[ns++];
            s->sampler = c->samplers[i];
            s->adaptive = adaptive;
            snprintf(s->name, sizeof s->name, "%s%s", st_sampler_names[s->sampler],
                     adaptive ? "+adaptive" : "");
            if (adaptive) {
                st_render_options o = c->r.opt;
                o.sampler = s->sampler;
                o.adaptive = 1;
                st_cli_adaptive_note(&o);
            }
        }
    double total = 0;
    for (st_u32 i = 0; i < ns; i++)
        for (st_u32 k = 0; k < c->nspp; k++)
            total += point_samples(c, &ss[i], k);
    st_error err = {0};
    st_cli_session s;
    st_image ref = {0};
    int ir[3];
    st_cli_progress_state prog;
    if (st_cli_session_open(&c->r, &s, &err) || get_reference(c, &s, &ref, ir, &err)) {
        rc = st_cli_session_fail(&s, &err);
        goto done;
    }
    st_cli_progress_init(&prog, "converge", c->r.quiet);
    st_cli_progress_work(&prog, total, "samples");
    study_progress sp = {.prog = &prog, .total = total};
    for (st_u32 i = 0; i < ns && !rc; i++) {
        for (st_u32 k = 0; k < c->nspp && !rc; k++)
            if (run_point(c, &s, &ref, ir, &ss[i], k, &sp, &err))
                rc = st_cli_session_fail(&s, &err);
        ss[i].slope = fit_slope(&ss[i], c->floor);
    }
    st_cli_progress_done(&prog);
    if (rc)
        goto done;
    if (write_outputs(c, ss, ns, &err) ||
        (c->error_spectrum && write_error_spectrum(c, ss, ns, &err))) {
        rc = st_cli_fail(&err);
        goto done;
    }
    if (!c->r.quiet) {
        FILE *f = c->csv && !strcmp(c->csv, "-") ? stderr : stdout;
        if (c->floor == c->floor)
            fprintf(f, "converge: reference floor %.3g (RMSE of the reference's own noise; "
                       "slopes fitted where the RMSE is %g times above it)\n",
                    c->floor, FLOOR_FACTOR);
        else
            fprintf(f, "converge: reference floor not estimated (a given reference)\n");
        fprintf(f, "converge: slopes");
        for (st_u32 i = 0; i < ns; i++) {
            fprintf(f, " %s %.3f", ss[i].name, ss[i].slope);
            if (ss[i].falling < ss[i].n && ss[i].falling < ss[i].above) /* a plateau follows */
                fprintf(f, " (to %g spp, then a plateau)", ss[i].spp[ss[i].falling - 1]);
            else if (ss[i].above < ss[i].n) /* the floor follows */
                fprintf(f, " (to %g spp, then the reference floor)",
                        ss[i].above ? ss[i].spp[ss[i].above - 1] : 0.0);
        }
        fprintf(f, "\n");
    }
done:
    for (st_u32 i = 0; i < ns; i++)
        free(ss[i].error_power);
    st_image_free(&ref);
    st_cli_session_close(&s);
    free(c);
    free(ss);
    return rc;
}
