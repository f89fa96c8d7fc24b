/* cli_compare.c — `strata compare`: renders every combination of samplers, sample counts and
 * filters, measures each against a reference, and lays them out on one sheet (st_sheet.h) with
 * their settings and RMSE; --csv gives the numbers. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_args.h"
#include "cli_commands.h"
#include "cli_error.h"
#include "cli_names.h"
#include "cli_progress.h"
#include "cli_session.h"
#include "cli_text.h"
#include "st_diff.h"
#include "st_sheet.h"

#define MAX_LIST 8

static const char compare_help[] =
    "usage: strata compare [SCENE] --sampler LIST -o SHEET.png|.pdf|.svg [options] [render options]\n"
    "  --sampler LIST        comma-separated samplers, one row each: random, uniform,\n"
    "                        stratified, halton, hammersley, poisson, best-candidate, sobol,\n"
    "                        paddedsobol, zsobol, joint-stratified, pmj02, pmj02bn\n"
    "  --spp LIST            comma-separated samples per pixel (default 16)\n"
    "  --filter LIST         comma-separated filters: box, triangle, gaussian, mitchell,\n"
    "                        lanczos, catmull-rom, blackman-harris (default mitchell)\n"
    "                        (a row holds every spp with every filter)\n"
    "  --reference-spp N     the reference: rendered here with sobol, N spp, another seed,\n"
    "                        the first filter (default 256), or\n"
    "  --reference FILE.exr  a reference image of the same size\n"
    "  --crop X,Y,W,H        a magnified inset of this pixel rectangle under every image\n"
    "  -o SHEET              the sheet: .png, .pdf or .svg\n"
    "  --csv FILE|-          sampler,spp,filter,rmse,psnr\n"
    "  render options: --width, --height, --seed, --integrator, --max-depth, --device, -q, ...\n"
    "  (not --filter-radius and the other filter parameters: each filter takes its defaults)\n";

typedef struct compare_args {
    st_cli_render_args r;
    st_u32 samplers[MAX_LIST], spp[MAX_LIST], filters[MAX_LIST];
    st_u32 nsamplers, nspp, nfilters, reference_spp;
    st_u32 crop[4];
    const char *reference, *out, *csv;
} compare_args;

typedef struct result {
    st_u32 sampler, spp, filter;
    st_diff_result d;
} result;

/* A comma-separated list of names (table names, count) or of counts (names NULL). */
static int parse_list(const char *opt, const char *s, const char *const *names, int count,
                      st_u32 *out, st_u32 *n)
{
    char buf[512];
    snprintf(buf, sizeof buf, "%s", s);
    *n = 0;
    for (char *tok = strtok(buf, ","); tok; tok = strtok(NULL, ",")) {
        if (*n == MAX_LIST)
            return st_cli_usage_error("%s %s: at most %d entries", opt, s, MAX_LIST);
        int k = names ? st_name_lookup(names, count, tok) : 0;
        if (names && k < 0)
            return st_cli_unknown_name(opt, tok, names, count);
        if (names)
            out[(*n)++] = (st_u32)k;
        else if (st_cli_parse_u32(opt, tok, 1, 1u << 20, &out[(*n)++]))
            return ST_CLI_EXIT_USAGE;
    }
    return *n ? ST_CLI_OK : st_cli_usage_error("%s '%s': an empty list", opt, s);
}

static int is_own(const char *a)
{
    static const char *const own[] = {"--sampler", "--spp", "--filter", "--reference-spp",
                                      "--reference", "-o", "--output", "--csv", "--crop"};
    for (size_t i = 0; i < sizeof own / sizeof own[0]; i++)
        if (!strcmp(a, own[i]))
            return 1;
    return 0;
}

/* One option of compare's own (is_own), with its value v. */
static int parse_own(compare_args *c, const char *a, const char *v)
{
    if (!strcmp(a, "--sampler"))
        return parse_list(a, v, st_sampler_names, ST_SAMPLER_COUNT, c->samplers, &c->nsamplers);
    if (!strcmp(a, "--spp"))
        return parse_list(a, v, NULL, 0, c->spp, &c->nspp);
    if (!strcmp(a, "--filter"))
        return parse_list(a, v, st_filter_names, ST_FILTER_COUNT, c->filters, &c->nfilters);
    if (!strcmp(a, "--reference-spp"))
        return st_cli_parse_u32(a, v, 1, 1u << 20, &c->reference_spp);
    if (!strcmp(a, "--reference"))
        return c->reference = v, ST_CLI_OK;
    if (!strcmp(a, "-o") || !strcmp(a, "--output"))
        return c->out = v, ST_CLI_OK;
    if (!strcmp(a, "--csv"))
        return c->csv = v, ST_CLI_OK;
    if (!strcmp(a, "--crop")) {
        char tail;
        st_u32 *g = c->crop;
        if (sscanf(v, "%u,%u,%u,%u%c", &g[0], &g[1], &g[2], &g[3], &tail) != 4 ||
            strchr(v, '-') || g[2] == 0 || g[3] == 0)
            return st_cli_usage_error("--crop %s: expected X,Y,W,H with W, H >= 1", v);
        return ST_CLI_OK;
    }
    return st_cli_usage_error("compare: %s is not an option of compare", a);
}

static int check_args(compare_args *c)
{
    if (!c->nsamplers)
        return st_cli_usage_error("compare: --sampler LIST is required (see strata compare --help)");
    if (!c->out)
        return st_cli_usage_error("compare: -o SHEET.png|.pdf|.svg is required");
    if (!st_cli_has_extension(c->out, ".png") && !st_cli_has_extension(c->out, ".pdf") &&
        !st_cli_has_extension(c->out, ".svg"))
        return st_cli_usage_error("-o %s: the sheet must end in .png, .pdf or .svg", c->out);
    if (c->reference && c->reference_spp)
        return st_cli_usage_error("compare: --reference and --reference-spp exclude each other");
    const st_render_options *o = &c->r.opt;
    if (c->crop[2] && (c->crop[0] >= o->width || c->crop[1] >= o->height ||
                       c->crop[2] > o->width - c->crop[0] || c->crop[3] > o->height - c->crop[1]))
        return st_cli_usage_error("--crop %u,%u,%u,%u: outside the %ux%u image", c->crop[0],
                                  c->crop[1], c->crop[2], c->crop[3], o->width, o->height);
    if (!c->nspp)
        c->spp[c->nspp++] = 16;
    if (!c->nfilters)
        c->filters[c->nfilters++] = ST_FILTER_MITCHELL;
    if (!c->reference_spp)
        c->reference_spp = 256;
    st_outfile_role files[] = {{c->out, "-o"}, {c->csv, "--csv"}, {c->r.scene, "the scene"},
                               {c->reference, "--reference"}, {c->r.env_file, "--env"}};
    return st_cli_check_apart(files, 5, 2);
}

static int parse(int argc, char **argv, compare_args *c)
{
    memset(c, 0, sizeof *c);
    char **rest = calloc((size_t)argc + 1, sizeof *rest);
    int nrest = 0, rc = ST_CLI_OK;
    if (!rest)
        return st_cli_usage_error("out of memory");
    rest[nrest++] = argv[0];
    for (int i = 1; i < argc && rc == ST_CLI_OK; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(compare_help, stdout);
            rc = ST_CLI_HELP;
        } else if (!strncmp(a, "--filter-", 9)) {
            rc = st_cli_usage_error("compare: %s: each filter of --filter takes its defaults", a);
        } else if (!is_own(a)) {
            rest[nrest++] = argv[i];
        } else if (i + 1 >= argc) {
            rc = st_cli_usage_error("compare: option %s needs a value", a);
        } else {
            rc = parse_own(c, a, argv[++i]);
        }
    }
    if (rc == ST_CLI_OK)
        rc = st_cli_parse_render_args(nrest, rest, 2, &c->r);
    free(rest);
    return rc ? rc : check_args(c);
}

static st_status get_reference(const compare_args *c, st_cli_session *s, st_image *ref,
                               st_error *err)
{
    const st_render_options *o = &c->r.opt;
    if (c->reference) {
        if (st_image_load(c->reference, ref, err) != ST_OK)
            return err->status;
        if (ref->width != o->width || ref->height != o->height)
            return st_fail(err, ST_ERR_USAGE, "%s: %ux%u pixels, the sheet renders %ux%u",
                           c->reference, ref->width, ref->height, o->width, o->height);
        return ST_OK;
    }
    st_render_options ro = *o;
    ro.sampler = ST_SAMPLER_SOBOL;
    ro.spp = c->reference_spp;
    ro.seed = o->seed + 0x5eed5eedu; /* independent of the compared renders (as converge) */
    ro.filter = st_filter_default(c->filters[0]);
    return st_cli_render_with_progress(s, &ro, "compare: reference", c->r.quiet, ref, err);
}

/* Renders every combination into imgs (row-major: sampler, then spp, then filter). */
static st_status render_all(const compare_args *c, st_cli_session *s, const st_image *ref,
                            st_image *imgs, result *res, st_error *err)
{
    st_cli_progress_state prog;
    st_cli_progress_init(&prog, "compare", c->r.quiet);
    st_u32 n = c->nsamplers * c->nspp * c->nfilters, k = 0;
    st_cli_progress_work(&prog, n, "renders");
    for (st_u32 i = 0; i < c->nsamplers; i++)
        for (st_u32 j = 0; j < c->nspp; j++)
            for (st_u32 f = 0; f < c->nfilters; f++, k++) {
                st_render_options o = c->r.opt;
                o.sampler = c->samplers[i];
                o.spp = c->spp[j];
                o.filter = st_filter_default(c->filters[f]);
                memset(&res[k], 0, sizeof res[k]);
                res[k].sampler = c->samplers[i];
                res[k].spp = c->spp[j];
                res[k].filter = c->filters[f];
                if (st_render_check(&o, err) != ST_OK ||
                    st_render(s->renderer, &o, &imgs[k], NULL, NULL, NULL, NULL, err) != ST_OK ||
                    st_diff_images(&imgs[k], ref, &res[k].d, err) != ST_OK) {
                    st_cli_progress_done(&prog);
                    return err->status;
                }
                st_cli_progress(&prog, (double)(k + 1) / n);
            }
    st_cli_progress_done(&prog);
    return ST_OK;
}

typedef struct csv_ctx {
    const result *res;
    st_u32 n;
} csv_ctx;

static void emit_csv(FILE *f, const void *ctx)
{
    const csv_ctx *c = ctx;
    fprintf(f, "sampler,spp,filter,rmse,psnr\n");
    for (st_u32 i = 0; i < c->n; i++)
        fprintf(f, "%s,%u,%s,%.9g,%.6g\n", st_sampler_names[c->res[i].sampler], c->res[i].spp,
                st_filter_names[c->res[i].filter], c->res[i].d.rmse, c->res[i].d.psnr);
}

static st_status write_sheet(const compare_args *c, const st_cli_session *s, const st_image *ref,
                             const st_image *imgs, const result *res, st_error *err)
{
    st_u32 n = c->nsamplers * c->nspp * c->nfilters;
    st_sheet_cell cells[MAX_LIST * MAX_LIST * MAX_LIST];
    char text[MAX_LIST * MAX_LIST * MAX_LIST][2][96];
    for (st_u32 k = 0; k < n; k++) {
        snprintf(text[k][0], sizeof text[k][0], "%s, %u spp, %s", st_sampler_names[res[k].sampler],
                 res[k].spp, st_filter_names[res[k].filter]);
        snprintf(text[k][1], sizeof text[k][1], "RMSE %.5f", res[k].d.rmse);
        cells[k] = (st_sheet_cell){&imgs[k], text[k][0], text[k][1]};
    }
    char ref_caption[160], title[320];
    if (c->reference)
        snprintf(ref_caption, sizeof ref_caption, "reference: %s", c->reference);
    else
        snprintf(ref_caption, sizeof ref_caption, "reference: sobol, %u spp, %s",
                 c->reference_spp, st_filter_names[c->filters[0]]);
    snprintf(title, sizeof title, "%s, %ux%u, seed %u: RMSE against the reference", s->scene->name,
             c->r.opt.width, c->r.opt.height, c->r.opt.seed);
    st_sheet sh = {.title = title, .reference = {ref, ref_caption, NULL}, .cells = cells,
                   .rows = c->nsamplers, .cols = c->nspp * c->nfilters};
    memcpy(sh.inset, c->crop, sizeof sh.inset);
    csv_ctx cc = {res, n};
    if (c->csv && st_cli_write_text(c->csv, emit_csv, &cc, err) != ST_OK)
        return err->status;
    return st_sheet_save(c->out, &sh, err);
}

int st_cli_compare(int argc, char **argv)
{
    compare_args c;
    int rc = parse(argc, argv, &c);
    if (rc)
        return rc == ST_CLI_HELP ? 0 : rc;
    st_u32 n = c.nsamplers * c.nspp * c.nfilters;
    st_image ref = {0}, *imgs = calloc(n, sizeof *imgs);
    result *res = calloc(n, sizeof *res);
    st_error err = {0};
    st_cli_session s;
    memset(&s, 0, sizeof s);
    if (!imgs || !res)
        rc = st_cli_fail(&(st_error){ST_ERR_NOMEM, "out of memory"});
    else if (st_cli_session_open(&c.r, &s, &err) || get_reference(&c, &s, &ref, &err) ||
             render_all(&c, &s, &ref, imgs, res, &err))
        rc = st_cli_session_fail(&s, &err);
    else if (write_sheet(&c, &s, &ref, imgs, res, &err))
        rc = st_cli_fail_options(&err, st_cli_render_option_names);
    else if (!c.r.quiet)
        printf("strata: compared %u renders with the reference: %s\n", n, c.out);
    for (st_u32 k = 0; imgs && k < n; k++)
        st_image_free(&imgs[k]);
    st_image_free(&ref);
    free(imgs);
    free(res);
    st_cli_session_close(&s);
    return rc;
}
