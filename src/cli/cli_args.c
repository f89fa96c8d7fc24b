/* cli_args.c — parsing of the render options (see cli_args.h). */
#include "cli_args.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "cli_display.h"
#include "cli_error.h"
#include "cli_names.h"
#include "st_trace_bench.h"

static const char render_help[] =
    "usage: strata %s [SCENE] [options]\n"
    "  SCENE                  a .gltf/.glb file or a built-in scene name (default: cornell-box)\n"
    "%s"
    "  --width W, --height H  image size in pixels (default 512x512)\n"
    "  --spp N                samples per pixel (default 16)\n"
    "  --sample-range K:M     render only sample indices K..M-1 of the --spp, K < M <= spp\n"
    "                         (split renders, for strata merge)\n"
    "  --part K/N             render part K (0..N-1) of N: the samples split as evenly as\n"
    "                         --spp allows, each part the same --sample-range strata merge\n"
    "                         expects (a Slurm array task: --part $SLURM_ARRAY_TASK_ID/N)\n"
    "  --crop X,Y,W,H         render only the window [X, X+W) x [Y, Y+H) of the image, each\n"
    "                         pixel as in the full render, bit for bit (the EXR's data window;\n"
    "                         a PNG holds the window alone); strata render's alone, not\n"
    "                         bench's or converge's\n"
    "  --sampler NAME         random, uniform, stratified, halton, hammersley, poisson,\n"
    "                         best-candidate, paddedsobol, sobol, zsobol, joint-stratified,\n"
    "                         pmj02, pmj02bn (spp at most 4096)\n"
    "                         (default halton); poisson and best-candidate place one point per\n"
    "                         pixel and pass, so every pixel gets its spp, at the cost of the\n"
    "                         closest pairs (min distance x sqrt(N) 0.6 at 1 spp against 0.78\n"
    "                         for the patterns of `strata pattern`)\n"
    "  --scramble on|none     randomise the sampler (digit permutations, shuffles; default on)\n"
    "  --filter NAME          box, triangle, gaussian, mitchell, lanczos, catmull-rom,\n"
    "                         blackman-harris (default mitchell)\n"
    "  --filter-radius R      filter radius in pixels, 1/16..8 (default: the filter's own)\n"
    "  --filter-b B, --filter-c C   mitchell's parameters, each in 0..1 (default 1/3, 1/3)\n"
    "  --filter-sigma S       gaussian's standard deviation, 1/64..16 (default 0.5)\n"
    "  --filter-tau T         lanczos' window scale, 1/16..64 (default: the radius)\n"
    "  --reconstruction splat|fis   splat each sample into every pixel within the filter\n"
    "                         radius (default), or filter importance\n"
    "                         sampling: offsets drawn\n"
    "                         from |f|, each sample in one pixel weighted by the sign of f\n"
    "  --adaptive             adaptive sampling at the cost of --spp on average: a pilot of\n"
    "                         --min-spp everywhere chooses the first counts, then 3 rounds\n"
    "                         put more samples where the error estimate is larger; unbiased:\n"
    "                         the image is the later samples' alone, each weighted as fixed\n"
    "                         before it was drawn; sobol and halton: counts in powers of\n"
    "                         two, or uniformly (with a note) where the pilot predicts no\n"
    "                         gain; other samplers render uniformly, with a note (unequal\n"
    "                         counts break their stratification)\n"
    "  --min-spp N            the pilot's samples per pixel (default spp/8 within 2..16)\n"
    "  --max-spp N            the most samples a pixel gets (default 8 x --spp)\n"
    "  --noise-threshold X    also stop a pixel once its estimated relative error is X\n"
    "                         (default: none; the render may then cost less than --spp)\n"
    "  --spp-map FILE.png     the samples each pixel received, colour-mapped with a legend\n"
    "  --env R,G,B | --env X  uniform environment light (linear radiance; 0: none). Default,\n"
    "                         with a note: a sky, white over a grey ground, unless the scene's\n"
    "                         own lights carry most of its light (then none, or the sky at 0.25\n"
    "                         where they leave most of the view dark)\n"
    "  --env FILE.exr|FILE.hdr   equirectangular environment map (linear RGB, +Y up; the image's\n"
    "                         centre looks along -Z, its right quarter along +X), sampled by its\n"
    "                         luminance\n"
    "  --env-rotate DEGREES   turn the environment about +Y, from +Z towards +X (default 0)\n"
    "  --texture-filter none|bilinear|trilinear   texture lookups: nearest texel, bilinear,\n"
    "                         or mip-mapped trilinear with ray-cone footprints (default)\n"
    "  --camera N|auto        the scene's N-th camera node (0 = the first, in scene order), or\n"
    "                         auto: the whole model from its front (glTF's +Z), a little\n"
    "                         above and to the side (the default for a file without cameras)\n"
    "  --look-at EX,EY,EZ,TX,TY,TZ[,UX,UY,UZ]   look from the eye E at the target T, up U\n"
    "                         (default +Y), in the scene's units, instead of the scene's camera\n"
    "  --fov DEGREES          vertical field of view of the camera (default: the camera's own;\n"
    "                         40 for --look-at over an orthographic one)\n"
    "  --seed S               random seed (default 0)\n"
    "  --integrator direct|path   (default path)\n"
    "  --max-depth D          path vertices at which light is gathered (pbrt's convention; default 5,\n"
    "                         12 in a scene with transmissive materials)\n"
    "  --device SPEC          cpu, gpu or P:D from `strata devices` (default cpu)\n"
    "  --wave N               work-items per wave (default 1048576, or down to 262144 where\n"
    "                         memory is short; the image does not change)\n"
    "  --local-size N         OpenCL work-group size (default 64; the image does not change;\n"
    "                         a CPU device's tile splat keeps one work-item per group;\n"
    "                         on a CPU at most (ulimit -s) / (4 KiB + 1 KiB per lane past\n"
    "                         the first): 744 for 8 MiB at 8 lanes)\n"
    "  --packets auto|none|coherent|all   rays traced in packets, one per lane of a work-item\n"
    "                         (--lanes): coherent = camera rays\n"
    "                         and the shadow rays from their hits, all = every ray (shadow rays\n"
    "                         only in scenes without alpha); auto: coherent where the\n"
    "                         kernels have lanes (--lanes above 1, a CPU device's), else\n"
    "                         none (the image does not change; `bench --rays`: with all only)\n"
    "  --lanes auto|1|4|8|16  items per work-item in the kernels' vector lanes; auto (the\n"
    "                         default): the fastest width measured on this device, once, and\n"
    "                         remembered (`strata devices` shows it; 1 on a GPU); the image\n"
    "                         does not change\n"
    "  --threads N            run on N of a CPU device's compute units (an OpenCL sub-device)\n"
    "                         and build the BVH on at most N threads (default all; the image\n"
    "                         does not change)\n"
    "  --aov LIST             also write albedo, normal, depth, position (comma-separated)\n"
    "                         into the EXR, beside R, G, B: Albedo.R/G/B, N.X/Y/Z (shading\n"
    "                         normal, world space), Z (distance from the camera), P.X/Y/Z,\n"
    "                         each filtered as the image is (EXR only; not with --adaptive)\n"
    "  --display-server HOST:PORT   show the image in the tev viewer while it renders\n"
    "                         (tev's default: localhost:14158); a viewer that is not there\n"
    "                         is a warning, and the render goes on\n"
    "  --exposure EV          PNG only: scale by 2^EV before the tone curve (default 0)\n"
    "  --tonemap NAME         PNG only: clamp (default), reinhard or filmic; an EXR stays linear\n"
    "  --scene-list           list the built-in scenes and exit\n"
    "  -q, --quiet            no progress and no summary (progress: a bar with the time left on\n"
    "                         a terminal, else a line at every 10 %% or 10 s)\n"
    "  -h, --help             this help\n";

enum {
    O_WIDTH = 256, O_HEIGHT, O_SPP, O_SAMPLE_RANGE, O_SAMPLER, O_SCRAMBLE, O_FILTER, O_RADIUS,
    O_B, O_C, O_SIGMA, O_TAU, O_SEED, O_INTEGRATOR, O_DEPTH, O_DEVICE, O_WAVE, O_LOCAL,
    O_SCENE_LIST, O_QUIET, O_JSON, O_RECON, O_ADAPTIVE, O_MIN_SPP, O_MAX_SPP, O_THRESHOLD,
    O_SPP_MAP, O_ENV, O_ENV_ROTATE, O_TEXFILTER, O_CAMERA, O_RAYS, O_COUNT, O_THREADS, O_EXPOSURE, O_TONEMAP, O_CROP,
    O_PACKETS, O_LANES, O_COLD, O_PART, O_LOOK_AT, O_FOV, O_AOV, O_DISPLAY
};

static const struct option options[] = {
    {"width", required_argument, 0, O_WIDTH},
    {"height", required_argument, 0, O_HEIGHT},
    {"spp", required_argument, 0, O_SPP},
    {"sample-range", required_argument, 0, O_SAMPLE_RANGE},
    {"part", required_argument, 0, O_PART},
    {"crop", required_argument, 0, O_CROP},
    {"sampler", required_argument, 0, O_SAMPLER},
    {"scramble", required_argument, 0, O_SCRAMBLE},
    {"filter", required_argument, 0, O_FILTER},
    {"filter-radius", required_argument, 0, O_RADIUS},
    {"filter-b", required_argument, 0, O_B},
    {"filter-c", required_argument, 0, O_C},
    {"filter-sigma", required_argument, 0, O_SIGMA},
    {"filter-tau", required_argument, 0, O_TAU},
    {"seed", required_argument, 0, O_SEED},
    {"integrator", required_argument, 0, O_INTEGRATOR},
    {"max-depth", required_argument, 0, O_DEPTH},
    {"device", required_argument, 0, O_DEVICE},
    {"wave", required_argument, 0, O_WAVE},
    {"local-size", required_argument, 0, O_LOCAL},
    {"packets", required_argument, 0, O_PACKETS},
    {"scene-list", no_argument, 0, O_SCENE_LIST},
    {"reconstruction", required_argument, 0, O_RECON},
    {"adaptive", no_argument, 0, O_ADAPTIVE},
    {"min-spp", required_argument, 0, O_MIN_SPP},
    {"max-spp", required_argument, 0, O_MAX_SPP},
    {"noise-threshold", required_argument, 0, O_THRESHOLD},
    {"spp-map", required_argument, 0, O_SPP_MAP},
    {"env", required_argument, 0, O_ENV},
    {"env-rotate", required_argument, 0, O_ENV_ROTATE},
    {"texture-filter", required_argument, 0, O_TEXFILTER},
    {"camera", required_argument, 0, O_CAMERA},
    {"look-at", required_argument, 0, O_LOOK_AT},
    {"fov", required_argument, 0, O_FOV},
    {"aov", required_argument, 0, O_AOV},
    {"display-server", required_argument, 0, O_DISPLAY},
    {"threads", required_argument, 0, O_THREADS},
    {"lanes", required_argument, 0, O_LANES},
    {"exposure", required_argument, 0, O_EXPOSURE},
    {"tonemap", required_argument, 0, O_TONEMAP},
    {"quiet", no_argument, 0, O_QUIET},
    {"json", no_argument, 0, O_JSON},
    {"cold", no_argument, 0, O_COLD},
    {"rays", required_argument, 0, O_RAYS},
    {"count", required_argument, 0, O_COUNT},
    {"output", required_argument, 0, 'o'},
    {"help", no_argument, 0, 'h'},
    {0, 0, 0, 0}};

int st_cli_parse_u32(const char *opt, const char *s, unsigned lo, unsigned hi, unsigned *out)
{
    char *end;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    if (*s == '\0' || *s == '-' || *end != '\0' || errno || v < lo || v > hi)
        return st_cli_usage_error("%s %s: expected an integer in %u..%u", opt, s, lo, hi);
    *out = (unsigned)v;
    return ST_CLI_OK;
}

int st_cli_parse_float(const char *opt, const char *s, float *out)
{
    char *end;
    errno = 0;
    float v = strtof(s, &end);
    if (*s == '\0' || *end != '\0' || errno || !isfinite(v))
        return st_cli_usage_error("%s %s: expected a finite number", opt, s);
    *out = v;
    return ST_CLI_OK;
}

static int parse_name(const char *opt, const char *const *names, int count, const char *s,
                      st_u32 *out)
{
    int i = st_name_lookup(names, count, s);
    if (i < 0)
        return st_cli_unknown_name(opt, s, names, count);
    *out = (st_u32)i;
    return ST_CLI_OK;
}

const st_cli_option_name st_cli_render_option_names[] = {
    {"sample range", "--sample-range"}, {"crop", "--crop"}, {"spp", "--spp"}, {"min spp", "--min-spp"},
    {"max spp", "--max-spp"}, {"noise threshold", "--noise-threshold"},
    {"max depth", "--max-depth"}, {"reconstruction", "--reconstruction"},
    {"adaptive", "--adaptive"}, {"sampler", "--sampler"}, {"filter kind", "--filter"},
    {"filter radius", "--filter-radius"}, {"filter b", "--filter-b"},
    {"filter c", "--filter-c"}, {"filter sigma", "--filter-sigma"},
    {"filter tau", "--filter-tau"}, {"texture filter", "--texture-filter"},
    {"camera", "--camera"}, {"look at", "--look-at"}, {"fov", "--fov"}, {NULL, NULL}};

int st_cli_option_words(st_error *err, const st_cli_option_name *names)
{
    for (const st_cli_option_name *n = names; n->field; n++) {
        size_t len = strlen(n->field);
        char next = err->msg[len];
        /* a whole field: "spp 3" is spp, "spp-map" or "sppx" is not */
        if (strncmp(err->msg, n->field, len) || (next && next != ' ' && next != ':'))
            continue;
        char msg[sizeof err->msg];
        snprintf(msg, sizeof msg, "%s%s", n->option, err->msg + len);
        memcpy(err->msg, msg, sizeof msg);
        return 1;
    }
    return 0;
}

int st_cli_fail_options(const st_error *err, const st_cli_option_name *names)
{
    st_error e = *err;
    st_cli_option_words(&e, names);
    return st_cli_fail(&e);
}

/* The filter module says which parameters a kind reads; one given for a kind
 * that ignores it is refused rather than silently dropped. */
int st_cli_apply_filter_args(const st_cli_filter_args *fa, st_filter *f)
{
    st_u32 uses = st_filter_parameters(f->kind);
    const char *name = st_filter_names[f->kind];
    if ((fa->b || fa->c) && !(uses & ST_FILTER_USES_BC))
        return st_cli_usage_error("--filter-b/--filter-c apply to mitchell only, not %s", name);
    if (fa->sigma && !(uses & ST_FILTER_USES_SIGMA))
        return st_cli_usage_error("--filter-sigma applies to gaussian only, not %s", name);
    if (fa->tau && !(uses & ST_FILTER_USES_TAU))
        return st_cli_usage_error("--filter-tau applies to lanczos only, not %s", name);
    if (fa->radius && st_cli_parse_float("--filter-radius", fa->radius, &f->radius))
        return ST_CLI_EXIT_USAGE;
    if (fa->radius && !fa->tau)
        f->tau = f->radius;
    if ((fa->b && st_cli_parse_float("--filter-b", fa->b, &f->b)) ||
        (fa->c && st_cli_parse_float("--filter-c", fa->c, &f->c)) ||
        (fa->sigma && st_cli_parse_float("--filter-sigma", fa->sigma, &f->sigma)) ||
        (fa->tau && st_cli_parse_float("--filter-tau", fa->tau, &f->tau)))
        return ST_CLI_EXIT_USAGE;
    return ST_CLI_OK;
}

/* --env: three non-negative finite numbers R,G,B, or one for all three, or
 * an environment map's file (.exr or .hdr: read when the session opens). */
static int parse_env(const char *v, st_cli_render_args *a)
{
    a->env_file = NULL;
    size_t len = strlen(v);
    if (len > 4 && (!strcasecmp(v + len - 4, ".exr") || !strcasecmp(v + len - 4, ".hdr"))) {
        a->env_file = v; /* the session reads it into opt.env_map */
        return ST_CLI_OK;
    }
    float c[3];
    int n = 0;
    const char *s = v;
    while (n < 3) {
        char *end;
        errno = 0;
        float x = strtof(s, &end);
        if (end == s || errno || !isfinite(x) || x < 0.0f)
            break;
        c[n++] = x;
        s = end;
        if (*s != ',' || n == 3)
            break;
        s++;
    }
    if (*s != '\0' || (n != 1 && n != 3))
        return st_cli_usage_error("--env %s: expected R,G,B or one value, each finite and >= 0, "
                                  "or a .exr or .hdr file", v);
    for (int k = 0; k < 3; k++)
        a->opt.env[k] = n == 1 ? c[0] : c[k];
    a->opt.env_given = 1;
    return ST_CLI_OK;
}

/* The device's thread count and the PNG's exposure and tone curve. */
static int parse_device_or_png(int c, const char *v, int bench, st_cli_render_args *a)
{
    if (c == O_THREADS)
        return st_cli_parse_u32("--threads", v, 1, 4096, &a->threads);
    if (c == O_LANES) {
        if (!strcmp(v, "auto")) {
            a->lanes = 0;
            return ST_CLI_OK;
        }
        if (st_cli_parse_u32("--lanes", v, 1, 16, &a->lanes) != ST_CLI_OK)
            return ST_CLI_EXIT_USAGE;
        if (a->lanes != 1 && a->lanes != 4 && a->lanes != 8 && a->lanes != 16)
            return st_cli_usage_error("--lanes %s: must be auto, 1, 4, 8 or 16", v);
        return ST_CLI_OK;
    }
    if (bench && (c == O_EXPOSURE || c == O_TONEMAP))
        return st_cli_usage_error("%s: only `strata render` writes a PNG",
                                  c == O_EXPOSURE ? "--exposure" : "--tonemap");
    if (c == O_EXPOSURE) {
        a->png_opt = "--exposure";
        if (st_cli_parse_float("--exposure", v, &a->exposure) != ST_CLI_OK)
            return ST_CLI_EXIT_USAGE;
        /* 2^64 takes the faintest float radiance past white and the brightest stays finite
         * through the tone curves; beyond it the curves overflow and the image goes black */
        if (fabsf(a->exposure) > 64.0f)
            return st_cli_usage_error("--exposure %s: must be in [-64, 64] (the image is scaled "
                                      "by 2^EV; beyond that every curve saturates or overflows)", v);
        return ST_CLI_OK;
    }
    if (c == O_TONEMAP) {
        a->png_opt = "--tonemap";
        return parse_name("--tonemap", st_tonemap_names, ST_TONEMAP_COUNT, v, &a->tonemap);
    }
    return ST_CLI_EXIT_USAGE;
}

/* The options of the view (environment, texture filter, camera) and of
 * adaptive sampling. */
static int parse_view_or_adaptive(int c, const char *v, int bench, st_cli_render_args *a)
{
    st_render_options *o = &a->opt;
    switch (c) {
    case O_ADAPTIVE: o->adaptive = 1; return ST_CLI_OK;
    case O_MIN_SPP: a->adaptive_opt = "--min-spp"; return st_cli_parse_u32("--min-spp", v, 1, 1u << 24, &o->min_spp);
    case O_MAX_SPP: a->adaptive_opt = "--max-spp"; return st_cli_parse_u32("--max-spp", v, 1, 1u << 24, &o->max_spp);
    case O_THRESHOLD:
        a->adaptive_opt = "--noise-threshold";
        return st_cli_parse_float("--noise-threshold", v, &o->noise_threshold);
    case O_SPP_MAP:
        if (bench)
            return st_cli_usage_error("--spp-map: `strata bench` writes no image");
        a->adaptive_opt = "--spp-map";
        a->spp_map = v;
        return ST_CLI_OK;
    case O_RECON:
        return parse_name("--reconstruction", st_reconstruction_names, 2, v, &o->reconstruction);
    case O_ENV: return parse_env(v, a);
    case O_ENV_ROTATE: return st_cli_parse_float("--env-rotate", v, &o->env_rotate);
    case O_TEXFILTER:
        return parse_name("--texture-filter", st_cli_texfilter_names, 3, v, &o->texture_filter);
    case O_CAMERA: {
        unsigned n;
        if (strcmp(v, "auto") == 0) {
            o->camera = ST_CAMERA_AUTO;
            return ST_CLI_OK;
        }
        if (st_cli_parse_u32("--camera", v, 0, 1u << 30, &n))
            return ST_CLI_EXIT_USAGE;
        o->camera = (st_i32)n;
        return ST_CLI_OK;
    }
    default: return parse_device_or_png(c, v, bench, a);
    }
}

/* --look-at: eye and target, and optionally up (default +Y), as 6 or 9
 * finite numbers separated by commas (their geometry is checked with the
 * scene's camera, st_render_view_camera). */
static int parse_look_at(const char *v, st_render_options *o)
{
    float x[9] = {0, 0, 0, 0, 0, 0, 0, 1, 0};
    int n = 0;
    const char *s = v;
    for (;;) {
        char *end;
        errno = 0;
        float f = strtof(s, &end);
        if (end == s || errno || !isfinite(f) || n == 9)
            break;
        x[n++] = f;
        s = end;
        if (*s != ',')
            break;
        s++;
    }
    if (*s != '\0' || (n != 6 && n != 9))
        return st_cli_usage_error("--look-at %s: expected EX,EY,EZ,TX,TY,TZ or "
                                  "EX,EY,EZ,TX,TY,TZ,UX,UY,UZ (finite numbers)", v);
    memcpy(o->look_at, x, sizeof x);
    o->look_at_given = 1;
    return ST_CLI_OK;
}

/* --aov: names of st_aov_layouts, separated by commas, each once. */
static int parse_aovs(const char *v, int bench, st_cli_render_args *a)
{
    const char *names[ST_AOV_COUNT - 1];
    for (st_u32 k = 1; k < ST_AOV_COUNT; k++)
        names[k - 1] = st_aov_layouts[k].name;
    if (bench)
        return st_cli_usage_error("--aov: only `strata render` writes them");
    a->aovs = 0;
    for (const char *s = v;;) {
        size_t len = strcspn(s, ",");
        char name[32];
        snprintf(name, sizeof name, "%.*s", (int)(len < sizeof name ? len : sizeof name - 1), s);
        int k = st_name_lookup(names, ST_AOV_COUNT - 1, name);
        if (k < 0 || len >= sizeof name)
            return st_cli_unknown_name("--aov", name, names, ST_AOV_COUNT - 1);
        if (a->aovs & (1u << (k + 1)))
            return st_cli_usage_error("--aov %s: %s given twice", v, name);
        a->aovs |= 1u << (k + 1);
        if (s[len] == '\0')
            return ST_CLI_OK;
        s += len + 1;
    }
}

/* n decimal integers of 0..2^32-1 separated by sep, nothing else (no sign,
 * space or wrap-around: sscanf's %u takes "4294967296" as 0); 0 or -1. */
static int parse_u32_list(const char *v, char sep, unsigned *out, int n)
{
    for (int i = 0; i < n; i++) {
        char *end;
        errno = 0;
        unsigned long long x = *v >= '0' && *v <= '9' ? strtoull(v, &end, 10) : 0;
        if (*v < '0' || *v > '9' || errno || x > UINT32_MAX || *end != (i + 1 < n ? sep : '\0'))
            return -1;
        out[i] = (unsigned)x;
        v = end + 1;
    }
    return 0;
}

/* --crop X,Y,W,H: four unsigned integers (the window is checked against the
 * image size by st_render_check, once --width and --height are known). */
static int parse_crop(const char *v, int bench, st_render_options *o)
{
    unsigned xywh[4];
    if (bench)
        return st_cli_usage_error("--crop: only `strata render` takes it");
    if (parse_u32_list(v, ',', xywh, 4) != 0)
        return st_cli_usage_error("--crop %s: expected X,Y,W,H (four integers in 0..%u)", v,
                                  UINT32_MAX);
    unsigned x = xywh[0], y = xywh[1], w = xywh[2], h = xywh[3];
    if (w == 0 || h == 0)
        return st_cli_usage_error("--crop %s: the window is empty", v);
    o->crop_x = x;
    o->crop_y = y;
    o->crop_w = w;
    o->crop_h = h;
    return ST_CLI_OK;
}

/* bench's trace benchmark: --rays camera|random, --count N. */
static int parse_trace_bench(int c, const char *v, int bench, st_cli_render_args *a)
{
    const char *opt = c == O_RAYS ? "--rays" : "--count";
    if (bench != 1)
        return st_cli_usage_error("%s: only `strata bench` takes it", opt);
    if (c == O_COUNT)
        return st_cli_parse_u32("--count", v, 1, 1u << 30, &a->ray_count);
    st_u32 set = 0;
    if (parse_name("--rays", st_ray_set_names, ST_RAYS_COUNT, v, &set))
        return ST_CLI_EXIT_USAGE;
    a->rays = 1 + (int)set;
    return ST_CLI_OK;
}

static int parse_one(int c, const char *v, int bench, st_cli_render_args *a,
                     st_cli_filter_args *fa)
{
    st_render_options *o = &a->opt;
    switch (c) {
    case O_WIDTH: return st_cli_parse_u32("--width", v, 1, 32768, &o->width);
    case O_HEIGHT: return st_cli_parse_u32("--height", v, 1, 32768, &o->height);
    case O_SPP: return st_cli_parse_u32("--spp", v, 1, 1u << 24, &o->spp);
    case O_SAMPLE_RANGE: {
        unsigned km[2];
        if (parse_u32_list(v, ':', km, 2) != 0)
            return st_cli_usage_error("--sample-range %s: expected K:M (sample indices K..M-1)", v);
        unsigned k = km[0], m = km[1];
        if (k >= m) /* M = 0 would mean "all samples": refuse rather than render them */
            return st_cli_usage_error("--sample-range %s: needs K < M <= spp", v);
        o->sample_begin = k;
        o->sample_end = m;
        return ST_CLI_OK;
    }
    case O_PART: {
        unsigned kn[2];
        if (parse_u32_list(v, '/', kn, 2) != 0 || kn[1] == 0 || kn[0] >= kn[1])
            return st_cli_usage_error("--part %s: expected K/N, parts K = 0..N-1 of N", v);
        a->part_k = kn[0];
        a->part_n = kn[1];
        return ST_CLI_OK;
    }
    case O_SAMPLER:
        return parse_name("--sampler", st_sampler_names, ST_SAMPLER_COUNT, v, &o->sampler);
    case O_SCRAMBLE:
        if (!strcasecmp(v, "none") || !strcasecmp(v, "on")) {
            o->scramble = !strcasecmp(v, "on");
            a->scramble_given = 1;
            return ST_CLI_OK;
        }
        return st_cli_usage_error("--scramble %s: expected on or none", v);
    case O_FILTER: {
        st_u32 k = 0;
        if (parse_name("--filter", st_filter_names, ST_FILTER_COUNT, v, &k))
            return ST_CLI_EXIT_USAGE;
        o->filter = st_filter_default(k);
        return ST_CLI_OK;
    }
    case O_RADIUS: fa->radius = v; return ST_CLI_OK;
    case O_B: fa->b = v; return ST_CLI_OK;
    case O_C: fa->c = v; return ST_CLI_OK;
    case O_SIGMA: fa->sigma = v; return ST_CLI_OK;
    case O_TAU: fa->tau = v; return ST_CLI_OK;
    case O_SEED: return st_cli_parse_u32("--seed", v, 0, 0xffffffffu, &o->seed);
    case O_INTEGRATOR: return parse_name("--integrator", st_integrator_names, 2, v, &o->integrator);
    case O_DEPTH:
        a->depth_given = 1;
        return st_cli_parse_u32("--max-depth", v, 0, 64, &o->max_depth);
    case O_DEVICE: a->device = v; return ST_CLI_OK;
    case O_WAVE: return st_cli_parse_u32("--wave", v, 1, 1u << 26, &o->wave);
    case O_LOCAL: return st_cli_parse_u32("--local-size", v, 1, 4096, &o->local_size);
    case O_PACKETS: return parse_name("--packets", st_packet_names, 4, v, &o->packet_path);
    case O_SCENE_LIST: a->scene_list = 1; return ST_CLI_OK;
    case O_QUIET:
    case 'q': a->quiet = 1; return ST_CLI_OK;
    case O_JSON:
        if (bench != 1)
            return st_cli_usage_error("--json: only `strata bench` takes it");
        a->json = 1;
        return ST_CLI_OK;
    case O_COLD:
        if (bench != 1)
            return st_cli_usage_error("--cold: only `strata bench` takes it");
        a->cold = 1;
        return ST_CLI_OK;
    case 'o':
        if (bench)
            return st_cli_usage_error("-o: `strata %s` writes no image", bench == 1 ? "bench" : "converge");
        if (a->noutputs == ST_CLI_MAX_OUTPUTS)
            return st_cli_usage_error("-o %s: at most %d outputs", v, ST_CLI_MAX_OUTPUTS);
        a->output = a->outputs[a->noutputs++] = v;
        return ST_CLI_OK;
    case O_RAYS:
    case O_COUNT: return parse_trace_bench(c, v, bench, a);
    case O_CROP: return parse_crop(v, bench, o);
    case O_LOOK_AT: return parse_look_at(v, o);
    case O_AOV: return parse_aovs(v, bench, a);
    case O_DISPLAY: {
        char host[256], port[16];
        if (bench)
            return st_cli_usage_error("--display-server: only `strata render` shows its image");
        a->display_server = v;
        return st_cli_display_parse(v, host, sizeof host, port, sizeof port);
    }
    case O_FOV:
        if (st_cli_parse_float("--fov", v, &o->fov))
            return ST_CLI_EXIT_USAGE;
        if (!(o->fov > 0.0f && o->fov < 180.0f))
            return st_cli_usage_error("--fov %s: must lie strictly between 0 and 180 degrees", v);
        return ST_CLI_OK;
    default: return parse_view_or_adaptive(c, v, bench, a);
    }
}

/* --part K/N as the sample range K*spp/N .. (K+1)*spp/N - 1: N consecutive
 * ranges that tile 0..spp, their sizes floor(spp/N) or one more. */
static int part_range(st_cli_render_args *a)
{
    st_render_options *o = &a->opt;
    if (o->sample_begin || o->sample_end)
        return st_cli_usage_error("--part %u/%u and --sample-range both choose the samples: "
                                  "give one", a->part_k, a->part_n);
    if (a->part_n > o->spp)
        return st_cli_usage_error("--part %u/%u: %u parts of --spp %u leave a part without "
                                  "samples (at most %u parts)", a->part_k, a->part_n,
                                  a->part_n, o->spp, o->spp);
    o->sample_begin = (st_u32)((st_u64)a->part_k * o->spp / a->part_n);
    o->sample_end = (st_u32)((st_u64)(a->part_k + 1) * o->spp / a->part_n);
    return ST_CLI_OK;
}

int st_cli_parse_render_args(int argc, char **argv, int bench, st_cli_render_args *a)
{
    memset(a, 0, sizeof *a);
    a->opt = st_render_defaults();
    st_cli_filter_args fa = {0};
    opterr = 0;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, ":o:hq", options, NULL)) != -1) {
        if (c == 'h') {
            printf(render_help, argv[0],
                   bench ? "  --json                 print one JSON object\n"
                           "  --cold                 also time the kernel build with an empty kernel\n"
                           "                         cache (a fresh one, thrown away after)\n"
                           "  --rays camera|random   trace rays alone (closest hit): camera rays through\n"
                           "                         random image points, or random origins in the scene's\n"
                           "                         box and directions on the sphere (fixed --seed)\n"
                           "  --count N              rays traced with --rays (default 2097152)\n"
                         : "  -o OUT.exr|OUT.png|-   output image (default strata.exr; -: a PNG on\n"
                           "                         standard output); repeat -o to write one render\n"
                           "                         to several files\n");
            return ST_CLI_HELP;
        }
        if (c == '?')
            return st_cli_unknown_option(argv[0], argv[optind - 1], options);
        if (c == ':')
            return st_cli_usage_error("%s: option %s needs a value", argv[0], argv[optind - 1]);
        if (parse_one(c, optarg, bench, a, &fa))
            return ST_CLI_EXIT_USAGE;
    }
    if (optind < argc)
        a->scene = argv[optind++];
    if (optind < argc)
        return st_cli_usage_error("%s: unexpected argument %s", argv[0], argv[optind]);
    if (st_cli_apply_filter_args(&fa, &a->opt.filter))
        return ST_CLI_EXIT_USAGE;
    if (a->part_n && part_range(a))
        return ST_CLI_EXIT_USAGE;
    if (a->scramble_given && !st_sampler_takes_scramble(a->opt.sampler))
        return st_cli_usage_error("--scramble applies to stratified, halton, hammersley, "
                                  "paddedsobol, sobol and zsobol, not %s", st_sampler_names[a->opt.sampler]);
    if (a->opt.env_rotate != 0.0f && !a->env_file)
        return st_cli_usage_error("--env-rotate turns an environment map: add --env FILE.exr|FILE.hdr");
    if (a->cold && a->rays)
        return st_cli_usage_error("--cold times a render's kernel build, not the trace benchmark's: "
                                  "drop --rays or --cold");
    if (a->ray_count && !a->rays)
        return st_cli_usage_error("--count applies to the trace benchmark only: add --rays");
    if (a->aovs && a->opt.adaptive)
        return st_cli_usage_error("--aov: not with --adaptive (its samples follow the image's "
                                  "noise, which the AOVs do not have)");
    if (a->adaptive_opt && !a->opt.adaptive)
        return st_cli_usage_error("%s applies to adaptive renders only: add --adaptive",
                                  a->adaptive_opt);
    st_error err = {0};
    if (st_render_check(&a->opt, &err) != ST_OK) {
        /* an adaptive render's film headroom is the --max-spp cap's, not --spp's */
        if (a->opt.adaptive && !strncmp(err.msg, "spp ", 4)) {
            char msg[sizeof err.msg];
            snprintf(msg, sizeof msg, "max %.*s", (int)sizeof msg - 5, err.msg);
            memcpy(err.msg, msg, sizeof msg);
        }
        return st_cli_fail_options(&err, st_cli_render_option_names);
    }
    return ST_CLI_OK;
}
