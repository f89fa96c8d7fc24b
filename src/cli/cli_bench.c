#define _XOPEN_SOURCE 700 /* nftw */
/* cli_bench.c — `strata bench`: throughput of each kernel stage, the BVH
 * build and the kernel build (cached: from the kernel cache a render reads,
 * in a child process; cold, with --cold: an empty cache of its own, thrown
 * away), after checking that the device renders correctly. */
#include <cjson/cJSON.h> /* Debian libcjson-dev */
#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli_check.h"
#include "cli_commands.h"
#include "cli_error.h"
#include "st_version.h"
#include "cli_session.h"
#include "cli_text.h"

static int remove_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb; (void)flag; (void)ftw;
    return remove(path);
}

/* Seconds to build the program and run its kernels once (PoCL compiles each
 * kernel again at its first launch), measured in a child process; cold: with
 * an empty kernel cache. The session is opened with the bench's own settings,
 * so that its warm-up launches what the bench's render launches (cli_session.c),
 * then an 8 x 8 render runs. Negative when the measurement failed. */
static double build_seconds(const st_cli_render_args *a, int cold)
{
    int fd[2];
    if (pipe(fd) != 0)
        return -1.0;
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0)
        return -1.0;
    if (pid == 0) {
        close(fd[0]);
        char dir[] = "/tmp/strata-cold-XXXXXX";
        if (cold && mkdtemp(dir))
            setenv("POCL_CACHE_DIR", dir, 1);
        st_cli_render_args tiny = *a;
        tiny.opt.width = tiny.opt.height = 8;
        tiny.opt.spp = 1;
        if (tiny.opt.adaptive) { /* the least plan it takes: a pilot of 1, one more */
            tiny.opt.spp = 2;
            tiny.opt.min_spp = 1;
            tiny.opt.max_spp = 0;
        }
        tiny.said = 1;
        st_cli_render_args full = *a;
        full.said = 1;
        st_error err = {0};
        st_cli_session s;
        st_image img = {0};
        double t0 = st_cli_now(), t = -1.0;
        if (st_cli_session_open(&full, &s, &err) == ST_OK &&
            st_render(s.renderer, &tiny.opt, &img, NULL, NULL, NULL, NULL, &err) == ST_OK)
            t = st_cli_now() - t0 - s.load_seconds - s.lanes_seconds -
                st_renderer_bvh_seconds(s.renderer);
        st_image_free(&img);
        st_cli_session_close(&s);
        if (cold)
            nftw(dir, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
        ssize_t w = write(fd[1], &t, sizeof t);
        _exit(w == (ssize_t)sizeof t ? 0 : 1);
    }
    close(fd[1]);
    double t = -1.0;
    if (read(fd[0], &t, sizeof t) != (ssize_t)sizeof t)
        t = -1.0;
    close(fd[0]);
    waitpid(pid, NULL, 0);
    return t;
}

typedef struct bench_result {
    st_render_stats total; /* the fastest run, its stages timed within it */
    double cold, cached, bvh, load; /* cold: negative where not asked (--cold) */
    st_u32 triangles, lights;
    const char *device, *scene;
    const char *packets; /* the rays traced in packets (--packets, auto resolved) */
    const char *kernels; /* what the render ran (st_renderer_ran) */
    unsigned lanes;      /* the kernels' lane width */
    const st_lanes_choice *lanes_choice; /* how it was chosen */
    st_cli_check check;
} bench_result;

/* What stage k processed in a render of `pixels` pixels, and its unit
 * (per second); NULL where the stage has no count of its own (the live
 * list's compaction: a throughput there would be made up). */
static double stage_count(const st_render_stats *s, int k, double pixels, const char **unit)
{
    switch (k) {
    case ST_STAGE_GENERATE: *unit = "samples/s"; return (double)s->samples;
    case ST_STAGE_TRACE: *unit = "rays/s"; return (double)s->closest_rays;
    case ST_STAGE_SHADE: *unit = "hits/s"; return (double)s->closest_rays;
    case ST_STAGE_SHADOW: *unit = "rays/s"; return (double)s->shadow_rays;
    case ST_STAGE_BIN: *unit = "samples/s"; return (double)s->samples;
    case ST_STAGE_SPLAT:
    case ST_STAGE_SPLAT_TILES:
    case ST_STAGE_SPLAT_PIXELS: *unit = "splats/s"; return (double)s->splats;
    case ST_STAGE_RESOLVE: *unit = "pixels/s"; return pixels;
    default: *unit = NULL; return 0.0;
    }
}

/* The row of what the render's time holds besides its stages' launches: the
 * host's work between them (the waits for the live paths' count, reading
 * the film back) and the gaps between one launch and the next. */
#define OUTSIDE "outside_stages"
static double outside_stages(const st_render_stats *s)
{
    double sum = 0;
    for (int k = 0; k < ST_STAGE_COUNT; k++)
        sum += s->stage_seconds[k];
    return s->seconds > sum ? s->seconds - sum : 0.0;
}

static void print_text(const st_cli_render_args *a, const bench_result *b)
{
    const st_render_options *o = &a->opt;
    printf("device     %s\nscene      %s (%u triangles, %u emissive)\n", b->device, b->scene,
           b->triangles, b->lights);
    printf("settings   %ux%u, %u spp, %s sampler, %s filter r=%g, %s integrator, max depth %u, "
           "packets %s\n",
           o->width, o->height, o->spp, st_sampler_names[o->sampler],
           st_filter_names[o->filter.kind], (double)o->filter.radius,
           st_integrator_names[o->integrator], o->max_depth, b->packets);
    char how[1400];
    printf("lanes      %s\n", st_render_lanes_describe(b->lanes_choice, how, sizeof how));
    printf("kernels    %s\n", b->kernels);
    printf("check      %s\n", b->check.message);
    printf("bvh build  %.4f s (%.2f M triangles/s)\n", b->bvh,
           b->bvh > 0 ? b->triangles / b->bvh * 1e-6 : 0.0);
    if (b->cold >= 0.0)
        printf("kernels    cold build %.2f s, cached %.2f s (program build + first launch)\n",
               b->cold, b->cached);
    else
        printf("kernels    cached %.2f s (program build + first launch; --cold: an empty "
               "cache)\n", b->cached);
    double pixels = (double)o->width * o->height, total = b->total.seconds;
    printf("%-22s %10s %14s %7s\n", "stage", "seconds", "throughput", "share");
    for (int k = 0; k < ST_STAGE_COUNT; k++) {
        const char *unit;
        double n = stage_count(&b->total, k, pixels, &unit), t = b->total.stage_seconds[k];
        printf("%-22s %10.4f ", st_stage_names[k], t);
        if (unit && t > 0) /* a rate where the stage ran and has a count */
            printf("%9.2f M %-9s", n / t * 1e-6, unit);
        else
            printf("%9s   %-9s", "-", "");
        printf(" %5.1f%%\n", total > 0 ? 100.0 * t / total : 0.0);
    }
    double other = outside_stages(&b->total);
    printf("%-22s %10.4f %9s   %-9s %5.1f%%\n", OUTSIDE, other, "-", "",
           total > 0 ? 100.0 * other / total : 0.0);
    st_cli_print_summary("bench", o, &b->total, -1.0);
}

/* ---- --json ---------------------------------------------------------------------------- */

/* The value as printf's fmt shows it (so "%.4f" seconds stay four places, as the text output),
 * read back into a double for cJSON. NaN and infinity survive and cJSON prints them as null,
 * since JSON has no such numbers (RFC 8259 section 6). */
static double shown(const char *fmt, double v)
{
    char buf[64];
    snprintf(buf, sizeof buf, fmt, v);
    return strtod(buf, NULL);
}

/* How the lane width was chosen, by ST_LANES_*. */
static const char *const lanes_how[] = {[ST_LANES_FORCED] = "forced",
                                        [ST_LANES_GPU] = "gpu",
                                        [ST_LANES_UNMEASURED] = "unmeasured",
                                        [ST_LANES_REMEMBERED] = "remembered",
                                        [ST_LANES_MEASURED] = "measured"};

/* Adds a number or string to o; returns 0 when cJSON could not allocate. */
static int put_num(cJSON *o, const char *key, double v)
{
    return cJSON_AddNumberToObject(o, key, v) != NULL;
}

static int put_str(cJSON *o, const char *key, const char *v)
{
    return cJSON_AddStringToObject(o, key, v ? v : "") != NULL;
}

/* The settings, the check and the build times: the keys before "stages". */
static int json_head(cJSON *root, const st_cli_render_args *a, const bench_result *b)
{
    const st_render_options *o = &a->opt;
    int ok = put_str(root, "version", st_version) &&
             put_str(root, "device", b->device) && put_str(root, "scene", b->scene) &&
             put_num(root, "triangles", b->triangles) && put_num(root, "width", o->width) &&
             put_num(root, "height", o->height) && put_num(root, "spp", o->spp) &&
             put_str(root, "sampler", st_sampler_names[o->sampler]) &&
             put_str(root, "filter", st_filter_names[o->filter.kind]) &&
             put_num(root, "filter_radius", shown("%g", (double)o->filter.radius)) &&
             put_str(root, "integrator", st_integrator_names[o->integrator]) &&
             put_num(root, "max_depth", o->max_depth) && put_str(root, "packets", b->packets) &&
             put_num(root, "lanes", b->lanes) &&
             put_str(root, "lanes_chosen", lanes_how[b->lanes_choice->how]) &&
             put_str(root, "kernels", b->kernels);
    cJSON *check = ok ? cJSON_AddObjectToObject(root, "check") : NULL;
    return check && cJSON_AddTrueToObject(check, "passed") &&
           put_str(check, "message", b->check.message) &&
           put_num(root, "bvh_seconds", shown("%.6f", b->bvh)) &&
           (b->cold < 0.0 || put_num(root, "kernel_build_cold_seconds", shown("%.4f", b->cold))) &&
           put_num(root, "kernel_build_cached_seconds", shown("%.4f", b->cached));
}

/* "stages": {name: {seconds, per_second, unit}} in stage order (seconds
 * alone where stage_count has no count) and last outside_stages (seconds),
 * which add up to "total"'s seconds. */
static int json_stages(cJSON *root, const st_cli_render_args *a, const bench_result *b)
{
    double pixels = (double)a->opt.width * a->opt.height;
    cJSON *stages = cJSON_AddObjectToObject(root, "stages");
    int ok = stages != NULL;
    for (int k = 0; k < ST_STAGE_COUNT && ok; k++) {
        const char *unit;
        double n = stage_count(&b->total, k, pixels, &unit), t = b->total.stage_seconds[k];
        cJSON *st = cJSON_AddObjectToObject(stages, st_stage_names[k]);
        ok = st && put_num(st, "seconds", shown("%.6f", t));
        if (ok && unit) /* a stage without a count of its own has its seconds alone */
            ok = put_num(st, "per_second", shown("%.1f", t > 0 ? n / t : 0.0)) &&
                 put_str(st, "unit", unit);
    }
    cJSON *other = ok ? cJSON_AddObjectToObject(stages, OUTSIDE) : NULL;
    ok = other && put_num(other, "seconds", shown("%.6f", outside_stages(&b->total)));
    const st_render_stats *t = &b->total;
    cJSON *total = ok ? cJSON_AddObjectToObject(root, "total") : NULL;
    return total && put_num(total, "seconds", shown("%.6f", t->seconds)) &&
           put_num(total, "samples_per_second", shown("%.1f", t->samples / t->seconds)) &&
           put_num(total, "rays_per_second", shown("%.1f", t->rays / t->seconds)) &&
           put_num(total, "rays", (double)t->rays); /* exact below 2^53 rays */
}

/* One line of JSON on stdout, built with cJSON so strings (a scene path, a device name) are
 * escaped. The keys and their nesting are the interface scripts read: keep them. */
static st_status print_json(const st_cli_render_args *a, const bench_result *b, st_error *err)
{
    cJSON *root = cJSON_CreateObject();
    if (root && !(json_head(root, a, b) && json_stages(root, a, b))) {
        cJSON_Delete(root);
        root = NULL;
    }
    return st_cli_put_json(root, err);
}

/* Repeats (at most this many times, and only while the runs so far took less
 * than BENCH_SECONDS) so that a small render is timed over more than one
 * run: the scheduler's noise on a render of a few milliseconds can exceed it. */
#define BENCH_RUNS 64
#define BENCH_SECONDS 0.5

/* The fastest of repeated renders, each timed whole and stage by stage at
 * once (profile: every launch timed by the device's clock, nothing waited
 * for), so that the stages and what lies outside them add up to the total
 * of the run they come from. The counts are every run's. */
static st_status measure(const st_cli_session *s, const st_render_options *o, bench_result *b,
                         st_error *err)
{
    st_render_options timed = *o;
    timed.profile = 1;
    double spent = 0;
    for (int run = 0; run < BENCH_RUNS && spent < BENCH_SECONDS; run++) {
        st_render_stats st = {0};
        st_image img = {0};
        st_status rc = st_render(s->renderer, &timed, &img, NULL, &st, NULL, NULL, err);
        st_image_free(&img);
        free(st.spp_map);
        st.spp_map = NULL;
        if (rc != ST_OK)
            return rc;
        if (run == 0 || st.seconds < b->total.seconds)
            b->total = st;
        spent += st.seconds;
    }
    return ST_OK;
}

int st_cli_bench(int argc, char **argv)
{
    st_cli_render_args a;
    int rc = st_cli_parse_render_args(argc, argv, 1, &a);
    if (rc)
        return rc == ST_CLI_HELP ? 0 : rc;
    if (a.rays)
        return st_cli_bench_trace(&a);
    bench_result b;
    memset(&b, 0, sizeof b);
    /* before this process touches OpenCL: fork() and OpenCL do not mix */
    /* the cached build first: where the lane width is not yet measured on
     * this device, that child measures it (in the real kernel cache, its
     * time left out) and the cold one and this process read its choice */
    b.cached = build_seconds(&a, 0);
    b.cold = a.cold ? build_seconds(&a, 1) : -1.0;
    st_error err = {0};
    st_cli_session s;
    st_image img = {0};
    if (st_cli_session_open(&a, &s, &err) || st_cli_check_device(s.dev, &a.opt, &b.check, &err)) {
        rc = st_cli_session_fail(&s, &err);
        goto done;
    }
    if (measure(&s, &a.opt, &b, &err)) {
        rc = st_cli_fail(&err);
        goto done;
    }
    b.bvh = st_renderer_bvh_seconds(s.renderer);
    b.triangles = s.scene->tri_count;
    b.lights = st_renderer_light_count(s.renderer);
    b.device = st_device_get_info(s.dev)->name;
    b.scene = s.scene->name;
    b.packets = st_packet_names[st_renderer_packets(s.renderer, &a.opt)];
    b.kernels = st_renderer_ran(s.renderer);
    b.lanes = st_device_get_info(s.dev)->lanes;
    b.lanes_choice = &s.lanes;
    if (a.json) {
        if (print_json(&a, &b, &err) != ST_OK)
            rc = st_cli_fail(&err);
    } else {
        print_text(&a, &b);
    }
done:
    st_image_free(&img);
    st_cli_session_close(&s);
    return rc;
}
