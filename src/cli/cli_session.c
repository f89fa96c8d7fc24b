/* cli_session.c — the session (device, scene, renderer) that render, bench
 * and converge open the same way, and what they (and merge) print or save of
 * a render. */
#include "cli_session.h"

#include "cli_progress.h"

#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#include "cli_error.h"

double st_cli_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

void st_cli_print_scene_list(void)
{
    const char *names[64];
    st_u32 n = st_scene_builtin_names(names, 64);
    for (st_u32 i = 0; i < n; i++)
        puts(names[i]);
}

/* Renders w (and frees the image) if its settings are accepted; settings a
 * small warm-up image cannot take are simply not warmed up. */
static st_status warm_render(st_renderer *r, const st_render_options *w, st_error *err)
{
    st_error ignored = {0};
    if (st_render_check(w, &ignored) != ST_OK)
        return ST_OK;
    st_image img = {0};
    st_status rc = st_render(r, w, &img, NULL, NULL, NULL, NULL, err);
    st_image_free(&img);
    return rc;
}

/* Where the driver compiles at launch (PoCL, st_device_info.compiles_at_launch;
 * a GPU driver compiles in the build, and Oclgrind interprets): PoCL compiles
 * each kernel at its first launch, which would otherwise fall in the render's
 * first wave, its rate and its time. So before the render, a render of 8 x 8
 * pixels with the render's own settings (at most 16 spp; no crop, no sample
 * range past its spp), warm (st_render_options.warm: every vertex's kernels
 * even where its few paths have all ended), launches what it launches. (PoCL compiles a kernel again
 * for grids 2^16 work-items wide or wider; st_device_launch lays long launches
 * out in narrower rows, so the one compile serves the render.) */
static st_status warm_up(st_renderer *r, const st_render_options *o, st_error *err)
{
    st_render_options w = *o;
    w.width = w.height = 8;
    w.warm = 1; /* the kernels of vertices its few paths may not reach too */
    w.crop_x = w.crop_y = w.crop_w = w.crop_h = 0;
    if (w.spp > 16) {
        w.spp = 16;
        w.min_spp = w.max_spp = 0;
    }
    if (w.sample_end > w.spp)
        w.sample_begin = w.sample_end = 0;
    return warm_render(r, &w, err);
}

/* The lane width: --lanes N, else the remembered measurement, else a
 * measurement now (once per device, driver and version), said in a note
 * while it runs (it compiles every width's kernels the first time) and
 * after, with its figures. */
static st_status choose_lanes(const st_cli_render_args *a, st_cli_session *s, st_error *err)
{
    if (a->lanes) {
        memset(&s->lanes, 0, sizeof s->lanes);
        s->lanes.lanes = a->lanes;
        s->lanes.how = ST_LANES_FORCED;
        return ST_OK;
    }
    if (st_render_lanes_recall(st_device_get_info(s->dev), &s->lanes, err) != ST_OK)
        return err->status;
    if (s->lanes.how != ST_LANES_UNMEASURED)
        return ST_OK;
    if (!a->said && !a->quiet)
        fprintf(stderr, "strata: note: measuring which lane width is fastest on this device "
                "(once; --lanes N skips it)...\n");
    double t0 = st_cli_now();
    if (st_render_lanes_measure(a->device, a->threads, &s->lanes, err) != ST_OK)
        return err->status;
    s->lanes_seconds = st_cli_now() - t0;
    char line[1024];
    if (!a->said && !a->quiet)
        fprintf(stderr, "strata: note: lanes %s\n",
                st_render_lanes_describe(&s->lanes, line, sizeof line));
    return ST_OK;
}

st_status st_cli_session_open(st_cli_render_args *a, st_cli_session *s, st_error *err)
{
    memset(s, 0, sizeof *s);
    double t0 = st_cli_now();
    if (st_scene_load(a->scene, &s->scene, err) != ST_OK)
        return err->status;
    if (a->env_file && st_envmap_load(a->env_file, &s->env_map, err) != ST_OK)
        return err->status;
    a->opt.env_map = s->env_map; /* the view's environment, in every render's options */
    if (!a->depth_given)
        a->opt.max_depth = st_render_default_depth(s->scene);
    s->load_seconds = st_cli_now() - t0;
    for (st_u32 i = 0; !a->said && i < s->scene->warning_count; i++)
        st_cli_put_line("strata: warning: ", s->scene->warnings[i]); /* scene text, escaped */
    if (!a->said)
        st_cli_light_notes(s->scene, &a->opt);
    /* the camera is checked before the device starts, in the flag's words */
    st_scene_camera cam;
    if (st_render_view_camera(s->scene, &a->opt, &cam, err) != ST_OK) {
        st_cli_option_words(err, st_cli_render_option_names);
        return err->status;
    }
    if (st_device_create(a->device, &s->dev, err) != ST_OK)
        return st_cli_device_words(err);
    if (a->threads && st_device_limit_compute_units(s->dev, a->threads, err) != ST_OK) {
        static const st_cli_option_name threads[] = {{"threads", "--threads"}, {NULL, NULL}};
        st_cli_option_words(err, threads);
        return err->status;
    }
    if (choose_lanes(a, s, err) != ST_OK || st_device_set_lanes(s->dev, s->lanes.lanes, err) != ST_OK)
        return err->status;
    st_cli_notice notice;
    st_cli_notice_start(&notice, a->quiet);
    t0 = st_cli_now();
    st_status rc = st_device_build(s->dev, NULL, err);
    double built = st_cli_now();
    st_cli_catch_interrupts(); /* PoCL's LLVM put its own handlers over ours as the device began */
    if (rc == ST_OK && a->opt.local_size &&
        (rc = st_device_check_local_size(s->dev, a->opt.local_size, err)) != ST_OK) {
        static const st_cli_option_name local[] = {{"local size", "--local-size"}, {NULL, NULL}};
        st_cli_option_words(err, local);
    }
    if (rc == ST_OK)
        rc = st_renderer_create(s->dev, s->scene, &s->renderer, err);
    double created = st_cli_now();
    if (rc == ST_OK && st_device_get_info(s->dev)->compiles_at_launch)
        rc = warm_up(s->renderer, &a->opt, err);
    s->build_seconds = (built - t0) + (st_cli_now() - created);
    st_cli_notice_stop(&notice);
    return rc;
}

void st_cli_adaptive_note(const st_render_options *o)
{
    if (st_render_adaptive_falls_back(o))
        fprintf(stderr, "strata: note: --adaptive with sampler %s renders uniformly at %u spp: %s "
                "(only random, sobol and halton adapt)\n", st_sampler_names[o->sampler], o->spp,
                ST_CLI_ADAPTIVE_FALLBACK);
}

void st_cli_adaptive_no_gain_note(const st_render_options *o, const st_render_stats *st)
{
    if (o->adaptive && st->adaptive_uniform)
        fprintf(stderr, "strata: note: --adaptive with sampler %s rendered uniformly at %u spp: "
                "%s\n", st_sampler_names[o->sampler], o->spp, ST_CLI_ADAPTIVE_NO_GAIN);
}

void st_cli_light_notes(const st_scene *scene, const st_render_options *o)
{
    float env[3];
    st_render_env(scene, o, env);
    int has_env = env[0] > 0.0f || env[1] > 0.0f || env[2] > 0.0f;
    static const char *const why[] = {
        [ST_ENV_NOTHING_EMITS] = "nothing in the scene emits light; it is lit by the default "
                                 "sky, white over a grey ground (--env to change)",
        [ST_ENV_DIM_EMITTERS] = "most of the light it emits comes from surfaces no brighter "
                                "than white; it is lit by the default sky as well "
                                "(--env 0 to turn it off)",
        [ST_ENV_OWN_LIGHTS] = "lit by its own lights alone, no environment (--env 1 for a "
                              "white one)",
        [ST_ENV_ENCLOSED] = "the camera is inside a closed model; no environment (--env 1 for "
                            "a white one)",
        [ST_ENV_HEADLIGHT] = "nothing in it emits light and the camera is inside a closed "
                             "model, where no sky reaches; a light at the default camera "
                             "lights it (add lights to the scene to change)",
        [ST_ENV_DARK_VIEW] = "its own lights would leave most of the view black; the default "
                             "sky is kept, dimmed to 0.25 (--env 0 to turn it off)",
    };
    char line[1024]; /* the scene's name is a path: the user's bytes, escaped */
    /* the headlight is the scene's, there whatever the environment */
    if ((!o->env_given && !o->env_map) || scene->env_default == ST_ENV_HEADLIGHT) {
        snprintf(line, sizeof line, "%s: %s", scene->name, why[scene->env_default]);
        st_cli_put_line("strata: note: ", line);
    } else if (!has_env && scene->emitted_power <= 0.0) {
        snprintf(line, sizeof line, "%s: no light at all (nothing emits and --env is 0): the "
                 "image will be black", scene->name);
        st_cli_put_line("strata: warning: ", line);
    }
}

st_status st_cli_device_words(st_error *err)
{
    static const st_cli_option_name device[] = {{"device", "--device"}, {NULL, NULL}};
    if (st_cli_option_words(err, device)) {
        size_t n = strlen(err->msg);
        snprintf(err->msg + n, sizeof err->msg - n, " (see `strata devices`)");
    }
    return err->status;
}

int st_cli_session_fail(const st_cli_session *s, const st_error *err)
{
    int rc = st_cli_fail(err);
    const char *log = s->dev ? st_device_build_log(s->dev) : "";
    if (err->status == ST_ERR_DEVICE && log[0])
        fprintf(stderr, "%s\n", log); /* the compiler log, after the cause */
    return rc;
}

void st_cli_session_close(st_cli_session *s)
{
    st_renderer_destroy(s->renderer);
    st_envmap_free(s->env_map);
    st_scene_destroy(s->scene);
    st_device_destroy(s->dev);
    memset(s, 0, sizeof *s);
}

int st_cli_has_extension(const char *path, const char *ext)
{
    size_t n = strlen(path), k = strlen(ext);
    return n > k && !strcasecmp(path + n - k, ext);
}

/* The film's counts (ST_EXR_INT_ATTRS, written as EXR ints), the same numbers
 * the summary prints. */
static int count_attrs(const st_render_stats *st, st_attr *attrs)
{
    const char *names[3] = {ST_EXR_INT_ATTRS};
    const st_u32 counts[3] = {st->clamped, st->nonfinite, st->zero_weight};
    for (int k = 0; k < 3; k++) {
        snprintf(attrs[k].name, sizeof attrs[k].name, "%s", names[k]);
        snprintf(attrs[k].value, sizeof attrs[k].value, "%u", counts[k]);
        /* an EXR int holds counts below 2^31; a double holds every st_u32 exactly */
        attrs[k].type = counts[k] <= INT32_MAX ? ST_ATTR_INT : ST_ATTR_DOUBLE;
    }
    return 3;
}

/* The render's settings, as EXR header attributes (at most ST_CLI_MAX_ATTRS). */
int st_cli_render_attrs(const st_cli_render_args *a, const st_cli_session *s,
                        const st_render_stats *st, st_attr *attrs)
{
    const st_render_options *o = &a->opt;
    const st_filter *f = &o->filter;
    int n = 0;
#define TYPED(key, t, ...)                                                                 \
    do {                                                                                   \
        snprintf(attrs[n].name, sizeof attrs[n].name, "strata.%s", key);                   \
        snprintf(attrs[n].value, sizeof attrs[n].value, __VA_ARGS__);                      \
        attrs[n++].type = t;                                                               \
    } while (0)
#define ATTR(key, ...) TYPED(key, ST_ATTR_STRING, __VA_ARGS__)
    ATTR("scene", "%s", s->scene->name);
    ATTR("scene_hash", "crc32:%08x", (unsigned)st_scene_content_hash(s->scene));
    ATTR("sampler", "%s", st_sampler_names[o->sampler]);
    ATTR("scramble", "%s", o->scramble ? "on" : "none");
    TYPED("spp", ST_ATTR_INT, "%u", o->spp);
    ATTR("sample_range", "%u:%u", o->sample_begin, o->sample_end ? o->sample_end : o->spp);
    if (a->part_n)
        ATTR("part", "%u/%u", a->part_k, a->part_n);
    ATTR("filter", "%s", st_filter_names[f->kind]);
    TYPED("filter_radius", ST_ATTR_FLOAT, "%.9g", (double)f->radius);
    ATTR("reconstruction", "%s", st_reconstruction_names[o->reconstruction]);
    if (f->kind == ST_FILTER_MITCHELL)
        ATTR("filter_bc", "%.9g,%.9g", (double)f->b, (double)f->c);
    if (f->kind == ST_FILTER_GAUSSIAN)
        TYPED("filter_sigma", ST_ATTR_FLOAT, "%.9g", (double)f->sigma);
    if (f->kind == ST_FILTER_LANCZOS)
        TYPED("filter_tau", ST_ATTR_FLOAT, "%.9g", (double)f->tau);
    TYPED("seed", ST_ATTR_DOUBLE, "%u", o->seed); /* 32 bits: exact in a double */
    if (o->adaptive) {
        st_u32 pilot, max_spp;
        st_render_adaptive_counts(o, &pilot, &max_spp);
        if (st_render_adaptive_falls_back(o))
            ATTR("adaptive", "fallback: uniform at mean_spp %u (sampler %s: %s)", o->spp,
                 st_sampler_names[o->sampler], ST_CLI_ADAPTIVE_FALLBACK);
        else if (st->adaptive_uniform)
            ATTR("adaptive", "uniform at mean_spp %u (sampler %s: %s)", o->spp,
                 st_sampler_names[o->sampler], ST_CLI_ADAPTIVE_NO_GAIN);
        else if (st_render_adaptive_qmc(o))
            ATTR("adaptive", "mean_spp %u, pilot %u, max_spp %u, noise_threshold %.9g", o->spp,
                 st_render_adaptive_qmc_pilot(o), max_spp, (double)o->noise_threshold);
        else
            ATTR("adaptive", "mean_spp %u, min_spp %u, max_spp %u, noise_threshold %.9g",
                 o->spp, pilot, max_spp, (double)o->noise_threshold);
        TYPED("samples_total", ST_ATTR_DOUBLE, "%llu", (unsigned long long)st->samples);
    }
    ATTR("integrator", "%s", st_integrator_names[o->integrator]);
    TYPED("max_depth", ST_ATTR_INT, "%u", o->max_depth);
    float env[3];
    st_render_env(s->scene, o, env);
    if (a->env_file) {
        ATTR("env", "%s", a->env_file);
        TYPED("env_rotate", ST_ATTR_FLOAT, "%.9g", (double)o->env_rotate);
    } else if (!o->env_given && s->scene->default_sky) {
        ATTR("env", "default sky x %.9g", (double)env[0]);
    } else {
        ATTR("env", "%.9g,%.9g,%.9g", (double)env[0], (double)env[1], (double)env[2]);
    }
    ATTR("texture_filter", "%s", o->texture_filter == ST_TEXFILTER_NONE ? "none"
                                 : o->texture_filter == ST_TEXFILTER_BILINEAR
                                     ? "bilinear"
                                     : "trilinear");
    if (o->look_at_given)
        ATTR("camera", "look-at %.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g",
             (double)o->look_at[0], (double)o->look_at[1], (double)o->look_at[2],
             (double)o->look_at[3], (double)o->look_at[4], (double)o->look_at[5],
             (double)o->look_at[6], (double)o->look_at[7], (double)o->look_at[8]);
    else if (s->scene->camera_count && o->camera != ST_CAMERA_AUTO)
        TYPED("camera", ST_ATTR_INT, "%d", o->camera >= 0 ? (int)o->camera : 0);
    else
        ATTR("camera", "default framing");
    st_scene_camera view;
    st_error ignored = {0}; /* checked when the session opened */
    if (st_render_view_camera(s->scene, o, &view, &ignored) == ST_OK && !view.orthographic)
        TYPED("fov", ST_ATTR_FLOAT, "%.9g", (double)view.yfov * 180.0 / 3.14159265358979323846);
    if (a->aovs) {
        char list[64] = "";
        for (st_u32 k = 1; k < ST_AOV_COUNT; k++)
            if ((a->aovs >> k) & 1u)
                snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s",
                         list[0] ? "," : "", st_aov_layouts[k].name);
        ATTR("aov", "%s", list);
    }
    ATTR("device", "%s", st_device_get_info(s->dev)->name);
    ATTR("kernels", "%s", st_renderer_ran(s->renderer));
    TYPED("render_seconds", ST_ATTR_DOUBLE, "%.6f", st->seconds);
#undef ATTR
#undef TYPED
    return n + count_attrs(st, attrs + n);
}

int st_cli_settings_only(st_attr *attrs, int n)
{
    int kept = 0;
    for (int i = 0; i < n; i++)
        if (strcmp(attrs[i].name, "strata.render_seconds") && strcmp(attrs[i].name, "strata.device") &&
            strcmp(attrs[i].name, "strata.kernels"))
            attrs[kept++] = attrs[i];
    return kept;
}

int st_cli_png_settings(const st_cli_render_args *a, st_image *rgb, st_attr *attrs, int n)
{
    st_tonemap_apply(rgb->data, (size_t)rgb->width * rgb->height, rgb->channels, a->exposure,
                     (st_tonemap)a->tonemap);
    n = st_cli_settings_only(attrs, n);
    snprintf(attrs[n].name, sizeof attrs[n].name, "strata.exposure");
    snprintf(attrs[n].value, sizeof attrs[n].value, "%g", (double)a->exposure);
    snprintf(attrs[++n].name, sizeof attrs[n].name, "strata.tonemap");
    snprintf(attrs[n].value, sizeof attrs[n].value, "%s", st_tonemap_names[a->tonemap]);
    return n + 1;
}

st_status st_cli_rgb_of(const st_image *in, st_image *out, st_error *err)
{
    const char *names[3] = {"R", "G", "B"};
    if (st_image_create(out, in->width, in->height, 3, names, err) != ST_OK)
        return err->status;
    size_t n = (size_t)in->width * in->height;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++)
            out->data[3 * i + c] = in->data[in->channels * i + c];
    st_image_place_like(out, in);
    return ST_OK;
}

void st_cli_print_summary(const char *what, const st_render_options *o, const st_render_stats *st,
                          double compile_seconds)
{
    double t = st->seconds > 0 ? st->seconds : 1e-9;
    printf("strata: %s %ux%u, ", what, o->width, o->height);
    if (o->crop_w)
        printf("window %ux%u at (%u, %u), ", o->crop_w, o->crop_h, o->crop_x, o->crop_y);
    if (o->sample_begin || o->sample_end) /* a part: its own samples */
        printf("samples %u:%u of %u spp", o->sample_begin, o->sample_end, o->spp);
    else
        printf("%u spp", o->spp);
    printf(" in %.3f s: %.2f M samples/s, %.2f M rays/s", st->seconds, st->samples / t * 1e-6,
           st->rays / t * 1e-6);
    if (o->adaptive) {
        st_u32 pilot, max_spp;
        st_render_adaptive_counts(o, &pilot, &max_spp);
        if (st_render_adaptive_qmc(o))
            pilot = st_render_adaptive_qmc_pilot(o);
        printf("; adaptive: %llu samples in all, %.2f per pixel (pilot %u, at most %u)",
               (unsigned long long)st->samples,
               (double)st->samples / ((double)o->width * o->height), pilot, max_spp);
    }
    if (st->clamped || st->nonfinite || st->zero_weight)
        printf(" (%u splats clamped, %u non-finite, %u pixels without weight)", st->clamped,
               st->nonfinite, st->zero_weight);
    if (compile_seconds >= 0) /* the render's time above leaves it out */
        printf("; kernels compiled in %.3f s before it", compile_seconds);
    putchar('\n');
}

st_status st_cli_render_with_progress(const st_cli_session *s, const st_render_options *o,
                                      const char *label, int quiet, st_image *img,
                                      st_error *err)
{
    st_cli_progress_state prog;
    st_cli_progress_init(&prog, label, quiet);
    st_u32 region[4];
    st_render_region(o, region);
    if (!o->adaptive)
        st_cli_progress_work(&prog, (double)region[2] * region[3] * o->spp, "samples");
    st_status rc = st_render(s->renderer, o, img, NULL, NULL, st_cli_progress, &prog, err);
    st_cli_progress_done(&prog);
    return rc;
}
