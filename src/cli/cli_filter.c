/* cli_filter.c — `strata filter NAME`: a filter's profile and frequency
 * response as CSV and as a two-panel plot with the Nyquist frequency marked. */
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
#include "filters.h"
#include "st_filter.h"
#include "st_plot.h"

#define PROFILE_POINTS 401
#define RESPONSE_POINTS 601
#define RESPONSE_MAX_FREQ 3.0 /* cycles per pixel */

static const char filter_help[] =
    "usage: strata filter NAME [options]\n"
    "  NAME           box, triangle, gaussian, mitchell, lanczos, catmull-rom, blackman-harris\n"
    "  --filter-radius R     radius in pixels (default: the filter's own)\n"
    "  --filter-b B, --filter-c C   mitchell's parameters (default 1/3, 1/3)\n"
    "  --filter-sigma S      gaussian's standard deviation (default 0.5)\n"
    "  --filter-tau T        lanczos' window scale (default: the radius)\n"
    "                        (render's options, spelt as render spells them)\n"
    "  --csv FILE|-   the profile (x,f) across [-r, r] (401 points), then the frequency\n"
    "                 response (frequency,magnitude) in cycles per pixel, |F(w)|/|F(0)|\n"
    "  --png FILE     the profile and the frequency response side by side, Nyquist marked\n"
    "                 (.png, .pdf or .svg by the extension)\n"
    "  --db           the response's plot in decibels, 20 log10 |F(w)|/|F(0)| down to -100\n"
    "                 dB, where the side lobes show\n";

typedef struct filter_cli {
    st_filter f;
    const char *csv, *png;
    int db;
    double x[PROFILE_POINTS], y[PROFILE_POINTS];
    double w[RESPONSE_POINTS], mag[RESPONSE_POINTS];
} filter_cli;

static int parse(int argc, char **argv, filter_cli *c)
{
    enum { F_RADIUS = 400, F_B, F_C, F_SIGMA, F_TAU, F_CSV, F_PNG, F_DB };
    static const struct option opts[] = {
        {"filter-radius", required_argument, 0, F_RADIUS},
        {"filter-b", required_argument, 0, F_B}, {"filter-c", required_argument, 0, F_C},
        {"filter-sigma", required_argument, 0, F_SIGMA},
        {"filter-tau", required_argument, 0, F_TAU}, {"csv", required_argument, 0, F_CSV},
        {"png", required_argument, 0, F_PNG}, {"db", no_argument, 0, F_DB},
        {"help", no_argument, 0, 'h'}, {0, 0, 0, 0}};
    st_cli_filter_args fa = {0};
    opterr = 0;
    optind = 1;
    int o;
    while ((o = getopt_long(argc, argv, ":h", opts, NULL)) != -1) {
        switch (o) {
        case 'h': fputs(filter_help, stdout); return ST_CLI_HELP;
        case '?': return st_cli_unknown_option("filter", argv[optind - 1], opts);
        case ':': return st_cli_usage_error("filter: option %s needs a value", argv[optind - 1]);
        case F_RADIUS: fa.radius = optarg; break;
        case F_B: fa.b = optarg; break;
        case F_C: fa.c = optarg; break;
        case F_SIGMA: fa.sigma = optarg; break;
        case F_TAU: fa.tau = optarg; break;
        case F_CSV: c->csv = optarg; break;
        case F_PNG: c->png = optarg; break;
        case F_DB: c->db = 1; break;
        }
    }
    if (optind >= argc)
        return st_cli_usage_error("filter: needs a filter name (see strata filter --help)");
    int k = st_filter_lookup(argv[optind]);
    if (k < 0)
        return st_cli_unknown_name("filter", argv[optind], st_filter_names, ST_FILTER_COUNT);
    if (optind + 1 < argc)
        return st_cli_usage_error("filter: unexpected argument %s", argv[optind + 1]);
    c->f = st_filter_default((st_u32)k);
    if (st_cli_apply_filter_args(&fa, &c->f))
        return ST_CLI_EXIT_USAGE;
    /* the renderer's limits: the lab shows filters that can render */
    st_error err = {0};
    if (st_filter_check(&c->f, ST_FILTER_MAX_RADIUS, &err) != ST_OK)
        return st_cli_fail_options(&err, st_cli_render_option_names);
    if (!c->csv && !c->png)
        return st_cli_usage_error("filter: nothing to do (give --csv or --png)");
    if (c->db && !c->png)
        return st_cli_usage_error("--db applies to the plot: add --png FILE");
    st_outfile_role files[] = {{c->csv, "--csv"}, {c->png, "--png"}};
    return st_cli_check_apart(files, 2, 2);
}

static void emit_csv(FILE *f, const void *ctx)
{
    const filter_cli *c = ctx;
    fprintf(f, "x,f\n");
    for (int i = 0; i < PROFILE_POINTS; i++)
        fprintf(f, "%.6f,%.9g\n", c->x[i], c->y[i]);
    fprintf(f, "\nfrequency,magnitude\n");
    for (int i = 0; i < RESPONSE_POINTS; i++)
        fprintf(f, "%.6f,%.9g\n", c->w[i], c->mag[i]);
}

static st_status write_png(const filter_cli *c, st_error *err)
{
    char title[128], title2[128];
    snprintf(title, sizeof title, "%s filter, r = %g: f(x)", st_filter_names[c->f.kind],
             (double)c->f.radius);
    snprintf(title2, sizeof title2, "%s: frequency response |F(w)|/|F(0)|",
             st_filter_names[c->f.kind]);
    double zx[2] = {-c->f.radius, c->f.radius}, zy[2] = {0, 0};
    st_plot_series prof[2] = {
        {.name = NULL, .x = zx, .y = zy, .n = 2, .color = 0x999999, .width = 1},
        {.name = "f(x)", .x = c->x, .y = c->y, .n = PROFILE_POINTS}};
    double db[RESPONSE_POINTS]; /* 20 log10 of the magnitude; a zero is -inf: the line breaks */
    for (int i = 0; i < RESPONSE_POINTS; i++)
        db[i] = c->mag[i] > 0 ? 20.0 * log10(c->mag[i]) : -INFINITY;
    st_plot_series resp = {.name = "|F(w)|", .x = c->w, .y = c->db ? db : c->mag,
                           .n = RESPONSE_POINTS};
    st_plot_marker nyq = {.x = 0.5, .label = "Nyquist (1/2 cycle per pixel)"};
    st_plot_lines left = {.title = title, .xlabel = "x (pixels)", .ylabel = "f(x)",
                          .series = prof, .series_count = 2};
    st_plot_lines right = {.title = title2, .xlabel = "frequency (cycles per pixel)",
                           .ylabel = "|F(w)| / |F(0)|", .series = &resp, .series_count = 1,
                           .markers = &nyq, .marker_count = 1, .xmin = 0,
                           .xmax = RESPONSE_MAX_FREQ, .ymin = 0, .ymax = 1.1};
    if (c->db) {
        snprintf(title2, sizeof title2, "%s: frequency response in dB", st_filter_names[c->f.kind]);
        right.ylabel = "20 log10 |F(w)|/|F(0)| (dB)";
        right.ymin = -100, right.ymax = 5;
    }
    st_plot_panel panels[2] = {{.kind = ST_PLOT_LINES, .lines = &left},
                               {.kind = ST_PLOT_LINES, .lines = &right}};
    return st_plot_save_row(c->png, panels, 2, 560, 420, err);
}

int st_cli_filter(int argc, char **argv)
{
    filter_cli *c = calloc(1, sizeof *c);
    if (!c)
        return st_cli_fail(&(st_error){ST_ERR_NOMEM, "out of memory"});
    int rc = parse(argc, argv, c);
    if (rc) {
        free(c);
        return rc == ST_CLI_HELP ? 0 : rc;
    }
    st_filter_profile(&c->f, PROFILE_POINTS, c->x, c->y);
    for (int i = 0; i < RESPONSE_POINTS; i++)
        c->w[i] = RESPONSE_MAX_FREQ * i / (RESPONSE_POINTS - 1);
    st_filter_response(&c->f, RESPONSE_POINTS, c->w, c->mag);
    st_error err = {0};
    if ((c->csv && st_cli_write_text(c->csv, emit_csv, c, &err)) || (c->png && write_png(c, &err)))
        rc = st_cli_fail(&err);
    free(c);
    return rc;
}
