/* st_render.h — the render: a scene's BVH and buffers uploaded once to a
 * device, then waves of samples pushed through the kernels
 * (generate_rays -> [trace_rays ->
 * shade_hits -> trace_shadow_rays] per path vertex -> splat_samples), and
 * resolve_film at the
 * end. Nothing returns to the host inside a wave; between waves only a
 * progress count.
 *
 * Determinism: a render's item space is (pixel, sample), item g = sample *
 * width * height + pixel; every random number is a function of (seed, pixel,
 * sample, dimension) and the film sums are 64-bit integers, so the image does
 * not depend on the wave size, the work-group size or the order of the adds. */
#ifndef ST_RENDER_H
#define ST_RENDER_H

#include "st_device.h"
#include "st_error.h"
#include "st_filter.h"
#include "st_image.h"
#include "st_names.h"
#include "st_sampling.h"
#include "st_scene.h"
#include "st_shared.h"

typedef struct st_render_options {
    st_u32 width, height;
    st_u32 spp;        /* samples per pixel of the whole image (defines the pattern) */
    st_u32 sample_begin, sample_end; /* this call renders sample indices
                                        [begin, end) of every pixel; end 0: spp */
    st_u32 seed;
    st_u32 sampler;    /* ST_SAMPLER_* */
    st_u32 scramble;   /* 1 (default) or 0 */
    st_u32 integrator; /* ST_INTEGRATOR_* */
    st_u32 max_depth;
    st_filter filter;
    st_u32 reconstruction; /* ST_RECON_SPLAT or ST_RECON_FIS */
    /* adaptive sampling (adaptive.c): spp samples per pixel on average, a
     * pilot of min_spp everywhere, then more where the error estimate is
     * larger, at most max_spp in a pixel and, with noise_threshold > 0, no
     * more than bring the estimate to the threshold; 0: the defaults of
     * st_render_adaptive_counts */
    int adaptive;
    st_u32 min_spp, max_spp;
    float noise_threshold;
    /* the view: which of the scene's cameras, what environment, how
     * textures are filtered (the scene itself is never changed) */
    st_i32 camera;     /* index into scene->cameras; -1: scene->default_camera;
                          ST_CAMERA_AUTO: scene->auto_camera */
    int look_at_given; /* 1: look_at replaces that camera (st_render_view_camera) */
    float look_at[9];  /* --look-at: eye, target and up, in the scene's units */
    float fov;         /* --fov: vertical field of view, degrees, of the view's
                          (perspective) camera; 0: the camera's own */
    int env_given;     /* 1: env below; 0: the default (st_render_env) */
    float env[3];      /* the environment's radiance, linear RGB: uniform, or the map's
                          scale */
    const struct st_envmap *env_map; /* an equirectangular map (borrowed; it must
                          outlive the renders that use it); NULL: uniform */
    float env_rotate;  /* the environment's turn about +Y, degrees (kernels/integrator/envmap.h) */
    st_u32 texture_filter; /* ST_TEXFILTER_* (default trilinear) */
    /* --crop: only the window [crop_x, crop_x + crop_w) x [crop_y, crop_y +
     * crop_h) of the image, each pixel equal to the full render's bit for
     * bit (its samples, and those of the filter's apron around it, are the
     * full render's); crop_w 0: the whole image */
    st_u32 crop_x, crop_y, crop_w, crop_h;
    st_u32 wave;       /* items per wave; 0: automatic */
    st_u32 local_size; /* work-group size; 0: the driver's choice */
    int profile;       /* time every stage (the device's clock: st_render_stats) */
    int warm;          /* launch every kernel of the plan, at every vertex, even where no
                          path is left (one work-item, which finds nothing to do), so that a
                          driver that compiles a kernel at its first launch (PoCL) compiles
                          all of a render's in a small warm-up render of its options */
    st_u32 packet_path; /* ST_PACKET_* (--packets) */
    st_u32 aov;        /* ST_AOV_* (st_shared.h): render that AOV over the same samples
                          instead of radiance (R, G, B: its value; depth in R); NONE */
} st_render_options;

/* The AOVs by ST_AOV_* (NONE's entry empty): the name --aov takes, and the
 * channels an EXR holds, as pbrt-v4's GBufferFilm and OpenEXR's conventions
 * name them (Albedo.R/G/B, N.X/Y/Z, P.X/Y/Z, Z), the first `channels` of
 * the AOV render's R, G, B; `layer` prefixes its raw sums in a split
 * render's part (st_film.h). */
typedef struct st_aov_layout {
    const char *name, *layer;
    st_u32 channels;
    const char *channel[3];
} st_aov_layout;
extern const st_aov_layout st_aov_layouts[ST_AOV_COUNT];
/* AOV aov's channels, named as st_aov_layouts says, from the first of a
 * render's (or resolve's) image of it; *out placed as it. ST_ERR_NOMEM. */
st_status st_render_aov_image(const st_image *rendered, st_u32 aov, st_image *out,
                              st_error *err);

/* Names on the command line, indexed by ST_INTEGRATOR_* /
 * ST_RECON_*; st_name_lookup returns the index or -1. Sampler and filter
 * names, defaults and checks: st_sampling.h, st_filter.h. */
extern const char *const st_integrator_names[2];
extern const char *const st_reconstruction_names[2];

/* The defaults of `strata render`. */
st_render_options st_render_defaults(void);
/* The max depth a render of s takes when none is asked for: the default 5,
 * or ST_GLASS_DEPTH where a material transmits (KHR_materials_transmission).
 * A path through glass spends two vertices on every pane or wall it crosses
 * (a vase's base, a bulb around a filament, a glass behind a glass), so at
 * 5 thick glass and what lies behind it go dark; 12 is Cycles' default
 * count of transmission bounces. Russian roulette still ends the paths that
 * carry little. Tests: tests/cli/test_glass_depth.sh. */
#define ST_GLASS_DEPTH 12u
st_u32 st_render_default_depth(const st_scene *s);
/* An adaptive render's pilot (min_spp, or spp / 8 within 2 .. 16) and cap
 * per pixel (max_spp, or 8 spp). */
void st_render_adaptive_counts(const st_render_options *o, st_u32 *pilot, st_u32 *max_spp);
/* Checks sizes, limits, the sampler (st_sampler_check), the filter
 * (st_filter_check) and the fixed-point headroom; ST_ERR_USAGE naming the
 * offending field ("spp", "sample range", "filter radius", ...). */
st_status st_render_check(const st_render_options *o, st_error *err);

/* Which rays are traced in packets of ST_W per work-item (packet_path;
 * kernels/geom/packet.h), same film bit for bit but for ties between triangles:
 * AUTO the device's lanes' and scene size's (st_renderer_packets), NONE one
 * ray per work-item, COHERENT the camera rays and the shadow rays from their
 * hits, ALL every ray. Shadow rays only in scenes whose materials are all
 * opaque. The other choices of kernel are the renderer's own (src/render/plan.c). */
enum { ST_PACKET_AUTO, ST_PACKET_NONE, ST_PACKET_COHERENT, ST_PACKET_ALL };
extern const char *const st_packet_names[4]; /* --packets: by ST_PACKET_* */
enum { ST_STAGE_GENERATE, ST_STAGE_TRACE, ST_STAGE_SHADE, ST_STAGE_SHADOW,
       ST_STAGE_LIVE,
       ST_STAGE_BIN, ST_STAGE_SPLAT, ST_STAGE_SPLAT_TILES, ST_STAGE_SPLAT_PIXELS, ST_STAGE_RESOLVE, ST_STAGE_COUNT };
extern const char *const st_stage_names[ST_STAGE_COUNT]; /* kernel names */

typedef struct st_render_stats {
    double seconds;                      /* wall time of the passes and resolve */
    double stage_seconds[ST_STAGE_COUNT]; /* with profile only: the stage's launches' time on
                                             the device, start to end (no wait between) */
    st_u64 samples, rays, closest_rays, shadow_rays, splats;
    st_u32 clamped, nonfinite, zero_weight;
    st_u32 *spp_map; /* adaptive only: samples per pixel, malloc'ed, the caller frees */
    int adaptive_uniform; /* adaptive with a QMC sampler: adapting would not pay, rendered
                             uniformly */
} st_render_stats;

typedef struct st_renderer st_renderer;

/* Builds the BVH, the light table and the device program, and uploads the
 * scene. The scene and device are borrowed and must outlive the renderer. */
st_status st_renderer_create(st_device *dev, const st_scene *scene, st_renderer **out,
                             st_error *err);
void st_renderer_destroy(st_renderer *r); /* NULL: does nothing */
double st_renderer_bvh_seconds(const st_renderer *r);
st_u32 st_renderer_light_count(const st_renderer *r);
/* The ST_PACKET_* a render of o uses on r's device and scene (AUTO resolved). */
int st_renderer_packets(const st_renderer *r, const st_render_options *o);
/* What the last render ran: the kernels' lane width and the kernels it
 * launched, in order ("lanes 8: generate_rays, trace_rays,
 * ..."); valid until the next call or render. */
const char *st_renderer_ran(st_renderer *r);
/* The camera a render of o sees: the scene's (st_scene_view_camera of
 * o->camera), or o->look_at's (st_scene_look_at; yfov: o->fov, else a
 * perspective camera's own, else 40 degrees), with o->fov as its field of
 * view where given. ST_ERR_USAGE "camera ...", "look at ..." or "fov ...";
 * --fov on an orthographic camera (it has none). */
st_status st_render_view_camera(const st_scene *scene, const st_render_options *o,
                                st_scene_camera *out, st_error *err);
/* The environment radiance a render of scene with options o sees (a map's
 * scale where o has a map): o->env where given, else 1 with a map and
 * the scene's default lighting (st_scene.default_env) without: the scale
 * of the default sky (st_envmap_sky) where scene->default_sky. */
void st_render_env(const st_scene *scene, const st_render_options *o, float env[3]);

/* --lanes auto (src/render/lanes_auto.c): the kernels' lane width (ST_W)
 * chosen by measurement. On a CPU device the first render times a short
 * calibration pass (the built-in Cornell box, direct and path) at each
 * width 1, 4, 8 and 16 and keeps the fastest (the narrowest within 3 % of
 * it) in a wisdom file, "lanes" in $STRATA_CACHE_DIR, else
 * in strata/ beside PoCL's cache ($XDG_CACHE_HOME or ~/.cache), one line per
 * device keyed by the platform, device, driver and strata's version; later
 * renders read it. Any other device takes 1 without a calibration. Every
 * width renders the same image bit for bit. */
#define ST_LANES_CANDIDATES 4
#define ST_LANES_PATH_MAX 1100
enum { ST_LANES_FORCED, ST_LANES_GPU, ST_LANES_UNMEASURED, ST_LANES_REMEMBERED,
       ST_LANES_MEASURED };
typedef struct st_lanes_choice {
    unsigned lanes;
    int how;                         /* ST_LANES_*: how lanes was chosen */
    double rate[ST_LANES_CANDIDATES]; /* samples/s of the calibration at 1, 4, 8, 16
                                         lanes (0: not measured, or not remembered) */
    char path[ST_LANES_PATH_MAX];    /* the wisdom file ("" where no folder is known) */
    int kept;                        /* measured: the choice was written to path */
    char why_not_kept[512];
} st_lanes_choice;
/* The remembered choice for the device: REMEMBERED, or UNMEASURED with the
 * device's vector width (st_device_default_lanes), or GPU with 1. */
st_status st_render_lanes_recall(const st_device_info *info, st_lanes_choice *c, st_error *err);
/* Measures: opens a device of spec (st_device_create; threads as
 * st_device_limit_compute_units, 0: all) per width, renders the calibration
 * at each in turn (the fastest of five, by CPU time over the compute units:
 * rates a machine's other load does not bend), sets c's lanes, rates and how
 * (MEASURED) and writes the wisdom file (c->kept; failing to write it is
 * not an error: c->why_not_kept says why). Call after st_render_lanes_recall
 * filled c->path. A width that does not build is left out (rate 0). */
st_status st_render_lanes_measure(const char *spec, unsigned threads, st_lanes_choice *c,
                                  st_error *err);
/* The width and how it was chosen, for `strata devices` and notes: "8
 * (measured: 1: 3.17, 4: 4.44, 8: 4.95, 16: 4.93 M samples/s, the narrowest
 * within 3 % of the fastest; kept in PATH)". Returns buf. */
const char *st_render_lanes_describe(const st_lanes_choice *c, char *buf, size_t cap);

typedef void (*st_progress_fn)(void *ctx, double fraction);

/* The pixels whose samples a render of o takes (row-major rectangle x, y,
 * w, h): the whole image, or a crop's window with the filter's apron (the
 * pixels whose samples can reach it); with a tiled sampler or adaptive
 * sampling, whose samples are not per pixel, the whole image even for a crop. */
void st_render_region(const st_render_options *o, st_u32 region[4]);

/* Whether an adaptive render of o is rendered uniformly instead: every
 * sampler but random, sobol and halton spreads its samples across a pixel's
 * sample indices in a way that depends on the render's spp (strata, index
 * shuffles over spp, blocks of a global sequence), and giving pixels
 * different counts breaks that stratification, which measured worse than
 * uniform at equal cost on landscape frames. Such a render is the uniform
 * one at the mean spp, its spp map spp everywhere. */
int st_render_adaptive_falls_back(const st_render_options *o);

/* Whether an adaptive render of o is a QMC sampler's (sobol, halton), whose
 * pixels take 2^k prefixes of their sequences after a pilot of the uniform
 * render's first st_render_adaptive_qmc_pilot samples (a power of two). */
int st_render_adaptive_qmc(const st_render_options *o);
st_u32 st_render_adaptive_qmc_pilot(const st_render_options *o);

/* Renders into *out: channels R, G, B (resolved, linear) and W (Σ f); *sums,
 * when not NULL, receives the raw fixed-point film (an st_film_pixel per
 * pixel: ST_FILM_SUMS int64, Σ f L for R, G, B, and Σ f; malloc'ed, caller
 * frees) for merging. With a crop, both hold the window only, and *out's
 * x0, y0, display_width, display_height place it in the image. */
st_status st_render(st_renderer *r, const st_render_options *o, st_image *out, st_i64 **sums,
                    st_render_stats *stats, st_progress_fn progress, void *progress_ctx,
                    st_error *err);

/* A look at the film while a render runs (--display-server): after a wave,
 * once `seconds` have passed since the last look (or the render began), and
 * four times the last look's own time (the callback's included), fn
 * gets the image so far: R, G, B of the crop's window (or the image), placed
 * as st_render's image, its sums divided on the host as resolve_film divides
 * them (not the final image, which st_render returns; nothing is counted).
 * The image is valid during the call. AOV renders show none. NULL fn: no
 * look; it lasts until set again. */
typedef void (*st_preview_fn)(void *ctx, const st_image *so_far);
void st_renderer_set_preview(st_renderer *r, double seconds, st_preview_fn fn, void *ctx);

/* Resolves raw sums (ST_FILM_SUMS per pixel, as st_render returns them) on the device
 * with the render's own resolve_film kernel (aov: the ST_AOV_* they hold, whose
 * values keep their sign), so a merged split render equals
 * one render of all the samples bit for bit. *out: R, G, B, W as st_render;
 * stats (may be NULL) gets the zero-weight and non-finite counts. */
st_status st_render_resolve(st_device *dev, const st_i64 *sums, st_u32 width, st_u32 height,
                            st_u32 aov, st_image *out, st_render_stats *stats, st_error *err);

#endif
