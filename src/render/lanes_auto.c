/* lanes_auto.c — --lanes auto: the kernels' lane width chosen by measurement
 * (st_render.h: st_render_lanes_choose).
 *
 * Which width is fastest on a CPU is not a property the device reports: its
 * preferred vector width names the registers, not what the compiler makes of
 * sixteen lanes of a traversal or of shading (on a Zen 5 the 16-lane build
 * lost to the 8-lane one). So the first render on a device renders one short
 * calibration pass at each candidate width, keeps the fastest, and writes it
 * to a small file beside the kernel cache, keyed by the device, its driver
 * and strata's version, as FFTW keeps its wisdom; later renders read it. The
 * widths give the same image bit for bit, so the choice changes only speed.
 *
 * The wisdom file holds one line per device: the key, the chosen width and
 * the rates measured, tab-separated. It is rewritten whole, through a
 * temporary and a rename, so a reader never sees half a line. */
#include "render_int.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "st_outfile.h"
#include "st_version.h"

/* The calibration pass: the built-in Cornell box at 128 x 128, 16 spp, with
 * independent samples and the box filter (the comparison workload of
 * `make bench`), once with direct lighting and once with paths, each pair
 * a render that takes about a tenth of a second at the fastest width. The
 * widths take CAL_ROUNDS turns, each keeping its fastest pair. Wider is
 * chosen only where it is more than CAL_MARGIN faster than the narrowest
 * width within that margin of the fastest: a small scene's few, coherent
 * rays favour wide lanes, and a large mesh's rays, whose packets diverge
 * more, do not (on a Zen 4, 16 lanes beat 8 by 2 % on this pass and lost by
 * 5 to 6 % on the 327,680-triangle icosphere in the Cornell box). */
#define CAL_SCENE "cornell-box"
#define CAL_SIDE 128u
#define CAL_SPP 16u
#define CAL_ROUNDS 5
#define CAL_MARGIN 0.03

static const unsigned cal_widths[ST_LANES_CANDIDATES] = {1u, 4u, 8u, 16u};

/* The folder of the wisdom file: $STRATA_CACHE_DIR, else strata/ beside
 * PoCL's own cache folder ($XDG_CACHE_HOME/pocl, else ~/.cache/pocl). 0
 * where neither variable names one. */
static int wisdom_dir(char *dir, size_t cap)
{
    const char *own = getenv("STRATA_CACHE_DIR"), *xdg = getenv("XDG_CACHE_HOME");
    const char *home = getenv("HOME");
    int n;
    if (own && *own)
        n = snprintf(dir, cap, "%s", own);
    else if (xdg && *xdg)
        n = snprintf(dir, cap, "%s/strata", xdg);
    else if (home && *home)
        n = snprintf(dir, cap, "%s/.cache/strata", home);
    else
        return 0;
    return n > 0 && (size_t)n < cap;
}

/* mkdir -p of dir (its last two levels at most: ~/.cache may be missing). */
static void make_dir(const char *dir)
{
    char parent[ST_LANES_PATH_MAX];
    snprintf(parent, sizeof parent, "%s", dir);
    char *slash = strrchr(parent, '/');
    if (slash && slash != parent) {
        *slash = '\0';
        mkdir(parent, 0777);
    }
    mkdir(dir, 0777);
}

/* The key of a device's line: what can change which width is fastest.
 * Tabs and newlines in names become spaces, so the key stays one field. */
static void wisdom_key(const st_device_info *info, char *key, size_t cap)
{
    snprintf(key, cap, "strata %s | %s | %s | %s | %s", st_version, info->platform_name,
             info->name, info->driver_version, info->version);
    for (char *c = key; *c; c++)
        if (*c == '\t' || *c == '\n' || *c == '\r')
            *c = ' ';
}

/* "1:0.84 4:3.10 8:5.92 16:5.71": the rates (M samples/s) by width; 0 where
 * a width was not measured. */
static void format_rates(const st_lanes_choice *c, char *out, size_t cap)
{
    size_t n = 0;
    out[0] = '\0';
    for (int i = 0; i < ST_LANES_CANDIDATES && n < cap; i++)
        n += (size_t)snprintf(out + n, cap - n, "%s%u:%.3f", i ? " " : "", cal_widths[i],
                              c->rate[i] * 1e-6);
}

static void parse_rates(const char *s, st_lanes_choice *c)
{
    for (int i = 0; i < ST_LANES_CANDIDATES; i++) {
        unsigned w;
        double m;
        int used = 0;
        if (sscanf(s, " %u:%lf%n", &w, &m, &used) != 2)
            return;
        for (int j = 0; j < ST_LANES_CANDIDATES; j++)
            if (cal_widths[j] == w)
                c->rate[j] = m * 1e6;
        s += used;
    }
}

/* The whole file (NULL where there is none or it cannot be read). */
static char *read_wisdom(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *text = NULL;
    size_t len = 0, cap = 0;
    for (int ch; (ch = fgetc(f)) != EOF && len < (1u << 20);) {
        if (len + 2 > cap) {
            cap = cap ? 2 * cap : 4096;
            char *grown = realloc(text, cap);
            if (!grown)
                break;
            text = grown;
        }
        text[len++] = (char)ch;
    }
    fclose(f);
    if (text)
        text[len] = '\0';
    return text;
}

/* The line of key in text: its width and rates, or 0 where there is none
 * (or it names no width strata builds). */
static int find_line(const char *text, const char *key, st_lanes_choice *c)
{
    size_t klen = strlen(key);
    for (const char *line = text; line && *line;) {
        const char *end = strchr(line, '\n');
        if (!strncmp(line, key, klen) && line[klen] == '\t') {
            unsigned w = 0;
            int used = 0;
            if (sscanf(line + klen + 1, "%u%n", &w, &used) == 1 &&
                (w == 1u || w == 4u || w == 8u || w == 16u)) {
                c->lanes = w;
                if (line[klen + 1 + used] == '\t')
                    parse_rates(line + klen + 2 + used, c);
                return 1;
            }
        }
        line = end ? end + 1 : NULL;
    }
    return 0;
}

st_status st_render_lanes_recall(const st_device_info *info, st_lanes_choice *c, st_error *err)
{
    (void)err;
    memset(c, 0, sizeof *c);
    c->lanes = st_device_default_lanes(info);
    if (!info->is_cpu || info->is_gpu) { /* a GPU's work-items are its lanes (Oclgrind's
                                              simulator says it is both: one lane, as before) */
        c->how = ST_LANES_GPU;
        return ST_OK;
    }
    c->how = ST_LANES_UNMEASURED;
    char dir[ST_LANES_PATH_MAX - 16], key[1024];
    if (!wisdom_dir(dir, sizeof dir))
        return ST_OK;
    snprintf(c->path, sizeof c->path, "%s/lanes", dir);
    wisdom_key(info, key, sizeof key);
    char *text = read_wisdom(c->path);
    if (text && find_line(text, key, c))
        c->how = ST_LANES_REMEMBERED;
    free(text);
    return ST_OK;
}

/* 1 when the line of n bytes is this key's device under any version of
 * strata: the same key past its first " | " (the version before it). */
static int same_device(const char *line, size_t n, const char *key)
{
    const char *kd = strstr(key, " | ");
    char copy[ST_LANES_PATH_MAX];
    if (!kd || n >= sizeof copy)
        return 0;
    memcpy(copy, line, n);
    copy[n] = '\0';
    const char *ld = strstr(copy, " | ");
    size_t klen = strlen(kd);
    return ld && !strncmp(ld, kd, klen) && ld[klen] == '\t';
}

/* Writes c's line for key into the wisdom file, keeping the other devices'
 * lines and dropping this device's lines of other strata versions (whose
 * kernels are not these): the whole file anew, through a temporary and a
 * rename. */
static st_status keep_wisdom(const st_lanes_choice *c, const char *key, st_error *err)
{
    char dir[ST_LANES_PATH_MAX];
    snprintf(dir, sizeof dir, "%s", c->path);
    char *slash = strrchr(dir, '/');
    if (slash)
        *slash = '\0';
    make_dir(dir);
    char *old = read_wisdom(c->path);
    st_outfile *out;
    if (st_outfile_open(c->path, &out, err) != ST_OK) {
        free(old);
        return err->status;
    }
    FILE *f = st_outfile_stream(out);
    size_t klen = strlen(key);
    for (const char *line = old; line && *line;) {
        const char *end = strchr(line, '\n');
        size_t n = end ? (size_t)(end - line) : strlen(line);
        int same = n > klen && !strncmp(line, key, klen) && line[klen] == '\t';
        if (!same && n > 0 && !same_device(line, n, key))
            fprintf(f, "%.*s\n", (int)n, line);
        line = end ? end + 1 : NULL;
    }
    free(old);
    char rates[256];
    format_rates(c, rates, sizeof rates);
    fprintf(f, "%s\t%u\t%s\n", key, c->lanes, rates);
    return st_outfile_commit(out, err);
}

/* One width's renderer for the calibration: its own device (a program is
 * built for one width), the kernels compiled by an untimed first render. */
typedef struct cal_width {
    st_device *dev;
    st_renderer *r;
    double best; /* fastest calibration render, seconds; 0: none */
} cal_width;

static st_status cal_open(const char *spec, unsigned threads, unsigned lanes,
                          const st_scene *scene, const st_render_options *o, cal_width *w,
                          st_error *err)
{
    memset(w, 0, sizeof *w);
    st_image img = {0}, img2 = {0};
    st_render_options tiny = o[0], tiny2 = o[1];
    tiny.width = tiny.height = tiny2.width = tiny2.height = 8;
    tiny.warm = tiny2.warm = 1;
    st_status rc = st_device_create(spec, &w->dev, err);
    if (rc == ST_OK && threads)
        rc = st_device_limit_compute_units(w->dev, threads, err);
    if (rc == ST_OK)
        rc = st_device_set_lanes(w->dev, lanes, err);
    if (rc == ST_OK)
        rc = st_device_build(w->dev, NULL, err);
    if (rc == ST_OK)
        rc = st_renderer_create(w->dev, scene, &w->r, err);
    if (rc == ST_OK)
        rc = st_render(w->r, &tiny, &img, NULL, NULL, NULL, NULL, err);
    if (rc == ST_OK)
        rc = st_render(w->r, &tiny2, &img2, NULL, NULL, NULL, NULL, err);
    st_image_free(&img);
    st_image_free(&img2);
    return rc;
}

static void cal_close(cal_width *w)
{
    st_renderer_destroy(w->r);
    st_device_destroy(w->dev);
}

/* This process's CPU time, its threads' (PoCL's workers') included. */
static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* One calibration pair of w (o[0], o[1]), timed by the CPU time it took
 * over the device's compute units: the time it would take on the device's
 * threads alone. Another program's load stretches a render's wall time by
 * however long its threads waited for a core, differently from one
 * width's turn to the next; the CPU time counts the work (PoCL's threads
 * sleep, not spin, while they wait for work). */
static st_status cal_time(cal_width *w, const st_render_options *o, st_error *err)
{
    double t0 = cpu_seconds();
    st_status rc = ST_OK;
    for (int k = 0; k < 2 && rc == ST_OK; k++) {
        st_image img = {0};
        st_render_stats st;
        rc = st_render(w->r, &o[k], &img, NULL, &st, NULL, NULL, err);
        st_image_free(&img);
        free(st.spp_map);
    }
    double t = (cpu_seconds() - t0) / (double)st_device_get_info(w->dev)->compute_units;
    if (rc == ST_OK && (w->best == 0.0 || t < w->best))
        w->best = t;
    return rc;
}

/* The calibration's two renders (CAL_SCENE): direct lighting, then paths. */
static void cal_workload(st_render_options o[2])
{
    o[0] = st_render_defaults();
    o[0].width = o[0].height = CAL_SIDE;
    o[0].spp = CAL_SPP;
    o[0].sampler = ST_SAMPLER_RANDOM;
    o[0].filter = st_filter_default(ST_FILTER_BOX);
    o[1] = o[0];
    o[0].integrator = ST_INTEGRATOR_DIRECT;
    o[1].integrator = ST_INTEGRATOR_PATH;
}

st_status st_render_lanes_measure(const char *spec, unsigned threads, st_lanes_choice *c,
                                  st_error *err)
{
    st_scene *scene = NULL;
    cal_width w[ST_LANES_CANDIDATES];
    memset(w, 0, sizeof w);
    st_render_options o[2];
    cal_workload(o);
    double samples = 2.0 * o[0].width * o[0].height * o[0].spp;
    st_status rc = st_scene_load(CAL_SCENE, &scene, err);
    /* a width whose kernels do not build or run on this device is left out,
     * its rate 0; only a device that runs none of them fails */
    st_error last = {0};
    int usable = 0;
    for (int i = 0; rc == ST_OK && i < ST_LANES_CANDIDATES; i++) {
        memset(&last, 0, sizeof last);
        if (cal_open(spec, threads, cal_widths[i], scene, o, &w[i], &last) == ST_OK) {
            usable++;
            continue;
        }
        cal_close(&w[i]);
        memset(&w[i], 0, sizeof w[i]);
    }
    if (rc == ST_OK && !usable)
        rc = st_fail(err, last.status, "%s", last.msg);
    for (int round = 0; rc == ST_OK && round < CAL_ROUNDS; round++)
        for (int i = 0; rc == ST_OK && i < ST_LANES_CANDIDATES; i++)
            if (w[i].r)
                rc = cal_time(&w[i], o, err);
    if (rc == ST_OK) {
        const st_device_info *info = NULL;
        int best = -1;
        for (int i = 0; i < ST_LANES_CANDIDATES; i++) {
            c->rate[i] = w[i].best > 0.0 ? samples / w[i].best : 0.0;
            if (w[i].r && (best < 0 || c->rate[i] > c->rate[best]))
                best = i;
            if (w[i].dev)
                info = st_device_get_info(w[i].dev);
        }
        /* the narrowest width within CAL_MARGIN of the fastest */
        for (int i = 0; i < best; i++)
            if (w[i].r && c->rate[i] >= (1.0 - CAL_MARGIN) * c->rate[best]) {
                best = i;
                break;
            }
        c->lanes = cal_widths[best];
        c->how = ST_LANES_MEASURED;
        char key[1024];
        wisdom_key(info, key, sizeof key);
        st_error kept = {0};
        c->kept = c->path[0] && keep_wisdom(c, key, &kept) == ST_OK;
        if (!c->kept)
            snprintf(c->why_not_kept, sizeof c->why_not_kept, "%s",
                     c->path[0] ? kept.msg : "no cache folder (set STRATA_CACHE_DIR or HOME)");
    }
    for (int i = 0; i < ST_LANES_CANDIDATES; i++)
        cal_close(&w[i]);
    st_scene_destroy(scene);
    return rc;
}

const char *st_render_lanes_describe(const st_lanes_choice *c, char *buf, size_t cap)
{
    char rates[256];
    size_t n = 0;
    rates[0] = '\0';
    for (int i = 0; i < ST_LANES_CANDIDATES && n < sizeof rates; i++)
        if (c->rate[i] > 0.0)
            n += (size_t)snprintf(rates + n, sizeof rates - n, "%s%u: %.2f", n ? ", " : "",
                                  cal_widths[i], c->rate[i] * 1e-6);
    switch (c->how) {
    case ST_LANES_FORCED: snprintf(buf, cap, "%u (--lanes)", c->lanes); break;
    case ST_LANES_GPU:
        snprintf(buf, cap, "%u (a GPU: its work-items are its lanes)", c->lanes);
        break;
    case ST_LANES_UNMEASURED:
        snprintf(buf, cap, "%u (not measured yet: the device's vector width; the first "
                 "render measures)", c->lanes);
        break;
    default:
        snprintf(buf, cap, "%u (%s: %s M samples/s, the narrowest within %g %% of the fastest; "
                 "%s%s)", c->lanes, c->how == ST_LANES_MEASURED ? "measured" : "remembered", rates,
                 100.0 * CAL_MARGIN,
                 c->how == ST_LANES_REMEMBERED || c->kept ? "kept in " : "not kept: ",
                 c->how == ST_LANES_REMEMBERED || c->kept ? c->path : c->why_not_kept);
    }
    return buf;
}
