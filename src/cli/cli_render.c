/* cli_render.c — `strata render`: one render (or one sample range of it,
 * for strata merge) to an EXR or PNG, and an adaptive render's spp map. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_commands.h"
#include "cli_display.h"
#include "cli_error.h"
#include "cli_progress.h"
#include "cli_session.h"
#include "st_film.h"
#include "st_outfile.h"
#include "st_plot.h"

/* The adaptive render's samples per pixel as a colour-mapped picture. */
static st_status save_spp_map(const char *path, const st_render_options *o,
                              const st_render_stats *st, st_error *err)
{
    size_t n = (size_t)o->width * o->height;
    double *v = malloc(n * sizeof *v);
    if (!v)
        return st_fail(err, ST_ERR_NOMEM, "out of memory for the spp map");
    for (st_u32 y = 0; y < o->height; y++) /* the plot's row 0 is the bottom */
        for (st_u32 x = 0; x < o->width; x++)
            v[(size_t)(o->height - 1 - y) * o->width + x] = st->spp_map[(size_t)y * o->width + x];
    char title[160];
    st_u32 pilot, max_spp;
    st_render_adaptive_counts(o, &pilot, &max_spp);
    snprintf(title, sizeof title, "samples per pixel: mean %.2f, pilot %u, at most %u",
             (double)st->samples / (double)n, pilot, max_spp);
    st_plot_heatmap h = {.title = title, .colorbar_label = "samples per pixel", .values = v,
                         .xlabel = "x (pixels)", .ylabel = "y (pixels, from the bottom)",
                         .width = o->width, .height = o->height, .vmin = pilot + 1,
                         .vmax = max_spp};
    st_u32 pw = o->width + 160 < 640 ? 640 : o->width + 160;
    st_u32 ph = o->height + 120 < 480 ? 480 : o->height + 120;
    st_status rc = st_plot_save_heatmap(path, &h, pw > 8192 ? 8192 : pw, ph > 8192 ? 8192 : ph, err);
    free(v);
    return rc;
}

/* A PNG output: .png, or - (standard output, st_image_save). */
static int is_png(const char *out)
{
    return st_cli_has_extension(out, ".png") || !strcmp(out, "-");
}

/* Each -o ends in .exr or .png, or is - (a PNG on standard output); a split render writes
 * EXRs only; the PNG options need a PNG. */
static int check_outputs(const st_cli_render_args *a, int part)
{
    int pngs = 0;
    for (int i = 0; i < a->noutputs; i++) {
        const char *out = a->outputs[i];
        int png = is_png(out);
        if (!png && !st_cli_has_extension(out, ".exr"))
            return st_cli_usage_error("-o %s: the output must end in .exr or .png, or be - (a "
                                      "PNG on standard output)", out);
        if (part && png)
            return st_cli_usage_error("-o %s: a split render (--sample-range, --part) writes its raw "
                                      "film to an EXR, for strata merge", out);
        pngs += png;
    }
    if (a->aovs && pngs == a->noutputs)
        return st_cli_usage_error("--aov: the AOVs go into an EXR (a PNG holds R, G, B): add "
                                  "-o OUT.exr");
    if (a->png_opt && !pngs)
        return st_cli_usage_error("%s applies to PNG output only (an EXR stays linear): -o %s",
                                  a->png_opt, a->outputs[0]);
    return ST_CLI_OK;
}

/* Whether the filter has negative lobes (its profile dips below 0). */
static int has_negative_lobes(const st_filter *f)
{
    enum { N = 257 };
    double x[N], y[N];
    st_filter_profile(f, N, x, y);
    for (int i = 0; i < N; i++)
        if (y[i] < 0.0)
            return 1;
    return 0;
}

/* The AOVs (--aov) of the render: each an st_render of its own over the same
 * samples and filter (st_render_options.aov), its channels, or for a split
 * render its raw sums (st_film.h, under its layer's prefix), appended to out. */
static st_status add_aovs(const st_cli_render_args *a, const st_cli_session *s, int part,
                          st_image *out, double *seconds, st_error *err)
{
    st_status rc = ST_OK;
    for (st_u32 k = 1; k < ST_AOV_COUNT && rc == ST_OK; k++) {
        if (!((a->aovs >> k) & 1u))
            continue;
        const st_aov_layout *l = &st_aov_layouts[k];
        st_render_options o = a->opt;
        o.aov = k;
        st_image img = {0}, add = {0};
        st_i64 *sums = NULL;
        st_render_stats st = {0};
        rc = st_render(s->renderer, &o, &img, part ? &sums : NULL, &st, NULL, NULL, err);
        *seconds += st.seconds;
        if (rc == ST_OK)
            rc = part ? st_film_to_image(sums, img.width, img.height, l->layer, &add, err)
                      : st_render_aov_image(&img, k, &add, err);
        if (rc == ST_OK)
            rc = st_image_append(out, &add, err);
        free(sums);
        st_image_free(&img);
        st_image_free(&add);
    }
    return rc;
}

/* The EXRs first (linear, every attribute), then the PNGs (exposure and tone curve applied
 * once to rgb, the settings as text). */
static st_status save_outputs(const st_cli_render_args *a, const st_cli_session *s,
                              const st_render_stats *st, st_image *rgb, const st_image *exr,
                              st_error *err)
{
    st_attr attrs[ST_CLI_MAX_ATTRS];
    int nattrs = st_cli_render_attrs(a, s, st, attrs), toned = 0;
    for (int png = 0; png < 2; png++)
        for (int i = 0; i < a->noutputs; i++) {
            if (is_png(a->outputs[i]) != png)
                continue;
            if (png && !toned++)
                nattrs = st_cli_png_settings(a, rgb, attrs, nattrs);
            if (st_image_save(a->outputs[i], png ? rgb : exr, attrs, nattrs, err) != ST_OK)
                return err->status;
        }
    return ST_OK;
}

static int to_stdout(const st_cli_render_args *a)
{
    for (int i = 0; i < a->noutputs; i++)
        if (!strcmp(a->outputs[i], "-"))
            return 1;
    return 0;
}

int st_cli_render(int argc, char **argv)
{
    st_cli_render_args a;
    int rc = st_cli_parse_render_args(argc, argv, 0, &a);
    if (rc)
        return rc == ST_CLI_HELP ? 0 : rc;
    if (a.scene_list) {
        st_cli_print_scene_list();
        return 0;
    }
    if (a.noutputs == 0)
        a.outputs[a.noutputs++] = "strata.exr";
    int part = a.opt.sample_begin != 0 || a.opt.sample_end != 0;
    if ((rc = check_outputs(&a, part)))
        return rc;
    st_error err = {0};
    st_outfile_role files[ST_CLI_MAX_OUTPUTS + 3];
    int n = 0;
    for (int i = 0; i < a.noutputs; i++)
        files[n++] = (st_outfile_role){a.outputs[i], "-o"};
    files[n++] = (st_outfile_role){a.spp_map, "--spp-map"};
    int nout = n;
    files[n++] = (st_outfile_role){a.scene, "the scene"};
    files[n++] = (st_outfile_role){a.env_file, "--env"};
    if ((rc = st_cli_check_apart(files, n, nout)))
        return rc;
    /* a typo in an output's folder must not cost the render */
    for (int i = 0; i < a.noutputs; i++)
        if (st_outfile_check(a.outputs[i], &err) != ST_OK)
            return st_cli_fail(&err);
    if (a.spp_map && st_outfile_check(a.spp_map, &err) != ST_OK)
        return st_cli_fail(&err);
    st_cli_session s;
    st_image img = {0}, rgb = {0}, exr = {0}; /* exr: rgb and the AOVs */
    st_render_stats st = {0};
    st_cli_progress_state prog;
    st_u32 first = a.opt.sample_begin, last = a.opt.sample_end ? a.opt.sample_end : a.opt.spp;
    st_u32 region[4]; /* the pixels sampled: a crop's window and apron, or the image */
    st_render_region(&a.opt, region);
    st_i64 *sums = NULL;
    st_cli_display disp; /* --display-server */
    double aov_seconds = 0.0;
    int opened = st_cli_session_open(&a, &s, &err) == ST_OK;
    if (opened && a.display_server) {
        st_cli_display_init(&disp, a.display_server, a.outputs[0], a.opt.width, a.opt.height);
        st_renderer_set_preview(s.renderer, ST_CLI_DISPLAY_SECONDS, st_cli_display_preview, &disp);
        st_cli_display_open(&disp);
    }
    if (opened)
        st_cli_adaptive_note(&a.opt);
    if (opened && a.aovs && !a.quiet && has_negative_lobes(&a.opt.filter))
        fprintf(stderr, "strata: note: --aov with filter %s, whose negative lobes ring at "
                "edges: denoisers expect a box or gaussian filter\n",
                st_filter_names[a.opt.filter.kind]);
    /* the render's own progress, after the kernels are compiled (which the
     * session's notice covers) */
    st_cli_progress_init(&prog, "render", a.quiet);
    if (!a.opt.adaptive) /* an adaptive render's samples are not known in advance */
        st_cli_progress_work(&prog, (double)region[2] * region[3] * (last - first), "samples");
    int failed = !opened || st_render(s.renderer, &a.opt, &img, part ? &sums : NULL, &st,
                                      st_cli_progress, &prog, &err) != ST_OK;
    if (!failed && a.display_server) /* the final image, as the outputs hold it */
        st_cli_display_show(&disp, &img, 1);
    if (failed ||
        (part ? st_film_to_image(sums, img.width, img.height, "", &rgb, &err)
              : st_cli_rgb_of(&img, &rgb, &err)) ||
        st_image_append(&exr, &rgb, &err) || add_aovs(&a, &s, part, &exr, &aov_seconds, &err)) {
        st_cli_progress_done(&prog);
        rc = st_cli_session_fail(&s, &err);
    } else {
        st_cli_progress_done(&prog);
        st_image_place_like(&rgb, &img); /* a crop's window in the image */
        st_image_place_like(&exr, &img);
        if (save_outputs(&a, &s, &st, &rgb, &exr, &err) != ST_OK ||
            (a.spp_map && save_spp_map(a.spp_map, &a.opt, &st, &err) != ST_OK))
            rc = st_cli_fail(&err);
        else {
            st_cli_adaptive_no_gain_note(&a.opt, &st);
            if (!a.quiet && !to_stdout(&a)) { /* standard output holds the image */
                st_cli_print_summary("rendered", &a.opt, &st, s.build_seconds);
                if (a.aovs) /* passes of their own, after the image's */
                    printf("strata: AOVs rendered in %.3f s more\n", aov_seconds);
            }
        }
    }
    if (opened && a.display_server)
        st_cli_display_close(&disp);
    free(sums);
    free(st.spp_map);
    st_image_free(&img);
    st_image_free(&rgb);
    st_image_free(&exr);
    st_cli_session_close(&s);
    return rc;
}
