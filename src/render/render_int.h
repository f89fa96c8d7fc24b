/* render_int.h — the renderer's inside, shared by the files that make it
 * up, lowest first: render_names.c (the kernels' and options' names),
 * device_scene.c (the scene on the device), adaptive.c (adaptive rounds),
 * render.c (the pass loop). Each calls only the ones before it: adaptive.c
 * is handed the pass loop's wave runner rather than calling back up into
 * render.c. Not a public header. */
#ifndef ST_RENDER_INT_H
#define ST_RENDER_INT_H

#include "plan.h"
#include "st_envmap.h"
#include "st_render.h"
#include "wave.h"

#include <time.h>

#define ST_RAN_MAX 32 /* distinct kernels one render launches, at most (all it has are fewer) */

/* Every kernel a render launches, in one table: its name in the program
 * and the stage its launches are timed in (st_render_stats.stage_seconds;
 * -1: none, the adaptive rounds' own work). The plan (plan.c) chooses
 * entries of it per stage and path vertex; the pass loop (render.c)
 * launches what the plan chose. */
#define ST_KERNEL_LIST(X)                                                                  \
    X(GENERATE, "generate_rays", ST_STAGE_GENERATE)                                        \
    X(TRACE, "trace_rays", ST_STAGE_TRACE)                                                 \
    X(TRACE_PACKET, "trace_rays_packet", ST_STAGE_TRACE)                                   \
    X(TRACE_LAST, "trace_rays_last", ST_STAGE_TRACE)                                       \
    X(SHADE, "shade_hits", ST_STAGE_SHADE)                                                 \
    X(SHADE_SHADOWED, "shade_hits_shadowed", ST_STAGE_SHADE)                               \
    X(SHADOW, "trace_shadow_rays", ST_STAGE_SHADOW)                                        \
    X(SHADOW_PACKET, "trace_shadow_rays_packet", ST_STAGE_SHADOW)                          \
    X(LIVE_COUNT, "live_count", ST_STAGE_LIVE)                                             \
    X(LIVE_SCAN, "live_scan", ST_STAGE_LIVE)                                               \
    X(LIVE_SCATTER, "live_scatter", ST_STAGE_LIVE)                                         \
    X(BIN_COUNT, "bin_samples", ST_STAGE_BIN)                                              \
    X(BIN_SCAN, "bin_scan", ST_STAGE_BIN)                                                  \
    X(BIN_SCATTER, "bin_scatter", ST_STAGE_BIN)                                            \
    X(SPLAT, "splat_samples", ST_STAGE_SPLAT)                                              \
    X(SPLAT_TILES, "splat_tiles", ST_STAGE_SPLAT_TILES)                                    \
    X(SPLAT_PIXELS, "splat_pixels", ST_STAGE_SPLAT_PIXELS)                                 \
    X(SPLAT_EDGES, "splat_edges", ST_STAGE_SPLAT_PIXELS)                                   \
    X(RESOLVE, "resolve_film", ST_STAGE_RESOLVE)                                           \
    X(ADAPTIVE_MOMENTS, "adaptive_moments", -1)                                            \
    X(ADAPTIVE_ESTIMATE, "adaptive_estimate", -1)                                          \
    X(ADAPTIVE_BLEND, "adaptive_blend", -1)                                                \
    X(ORDER_BOUNDS, "order_bounds", ST_STAGE_TRACE)                                        \
    X(ORDER_KEYS, "order_keys", ST_STAGE_TRACE)                                            \
    X(ORDER_COUNT_LOW, "order_count_low", ST_STAGE_TRACE)                                  \
    X(ORDER_SCAN, "order_scan", ST_STAGE_TRACE)                                            \
    X(ORDER_SCATTER_LOW, "order_scatter_low", ST_STAGE_TRACE)                              \
    X(ORDER_COUNT_HIGH, "order_count_high", ST_STAGE_TRACE)                                \
    X(ORDER_SCATTER_HIGH, "order_scatter_high", ST_STAGE_TRACE)
#define ST_AS_KERNEL(id, name, stage) ST_K_##id,
enum { ST_KERNEL_LIST(ST_AS_KERNEL) ST_KERNEL_COUNT };
#undef ST_AS_KERNEL
extern const char *const st_kernel_names[ST_KERNEL_COUNT];
extern const int st_kernel_stages[ST_KERNEL_COUNT];

struct st_renderer {
    st_device *dev;
    const st_scene *scene;
    /* ST_SCENE_BUFFERS: the scene, uploaded once; tile, fis_cdf and pmj02
     * are the per-render inputs (render.c), env_texels and env_cdf the
     * environment map's (st_renderer_upload_env_map) */
    cl_mem scene_buf[ST_SCENE_BUFFER_COUNT];
    cl_kernel kernel[ST_KERNEL_COUNT]; /* by ST_K_* */
    int all_opaque; /* every material ST_ALPHA_OPAQUE: shadow packets may be used */
    /* all_opaque, no unlit surface, and every emissive surface in the light
     * list (its emission a factor, no texture): a ray of the last vertex
     * sees light only at a light-list triangle or in the environment
     * (trace_rays_last may be used) */
    int emitters_listed;
    st_u32 light_count;
    st_u32 punct_count; /* KHR_lights_punctual lights (scene->punctual) */
    const st_envmap *env_map; /* the map uploaded, a render's st_render_options.env_map
                                 (borrowed) or sky; NULL: none */
    st_envmap *sky; /* the default sky (st_envmap_sky) where scene->default_sky; else NULL */
    float ray_eps;
    double bvh_seconds;
    /* the key of the tiled sampler's tile in scene_buf[ST_SCENE_tile],
     * kept for renders with the same key */
    st_u32 tile_sampler, tile_spp, tile_seed, tile_size, tile_points;
    /* the key of the sampler tables in scene_buf[ST_SCENE_pmj02]: pmj02's
     * (log2 0: none) or Halton's digit permutations (render.c) */
    st_u32 pmj02_seed, pmj02_log2;
    st_plan_force force; /* st_renderer_force */
    struct {             /* st_renderer_set_preview */
        st_preview_fn fn;
        void *ctx;
        double seconds, last, cost; /* the interval; the last look's end and its seconds */
    } preview;
    st_plan plan;        /* the last render's (st_plan_make) */
    /* the kernels the last render launched, in order, and their description
     * (st_renderer_ran) */
    cl_kernel ran[ST_RAN_MAX];
    unsigned ran_count;
    char ran_text[1024];
};

/* Progress over the items of a render. */
typedef struct st_progress_state {
    st_progress_fn fn;
    void *ctx;
    double done, total;
} st_progress_state;

/* Seconds on the monotonic clock. */
static inline double st_render_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* Items [first, first + total) of the current item space, in waves. */
/* Uploads map m (NULL: none, a placeholder) as the environment of the
 * renders that follow: st_render calls it when its options name another
 * map than the one uploaded (device_scene.c). */
st_status st_renderer_upload_env_map(st_renderer *r, const st_envmap *m, st_error *err);

/* Notes kernel kl among those the render ran (strata bench and the EXR
 * header name them: st_renderer_ran), once, in launch order (plan.c). */
void st_render_note_ran(st_renderer *r, cl_kernel kl);

/* Sorts the n rays a trace at p's vertex runs over by origin and direction
 * (order.cl, its kernels bound to the wave): `order` then lists their items
 * in that order, for a trace with p.ordered set (order.c). */
st_status st_render_order(st_renderer *r, const st_params *p, size_t n, size_t local,
                          st_error *err);

/* The wave a render of `pixels` pixels takes without --wave (render.c). */
size_t st_render_default_wave(const st_device *dev, size_t pixels, int adaptive);

/* Work-items of a kernel that takes the device's ST_W items a work-item:
 * ceil(n / ST_W) (plan.c). */
size_t st_render_lane_items(st_device *dev, size_t n);

/* The threads the BVH build of tri_count triangles takes for device info:
 * the build's own default (st_bvh_threads), but no more than a CPU device's
 * compute units, which --threads limits (device_scene.c). */
unsigned st_renderer_bvh_threads(const st_device_info *info, st_u32 tri_count);

st_status st_render_items(st_renderer *r, st_params *p, st_wave *w, const st_render_options *o,
                          st_u64 first, st_u64 total, st_progress_state *pr, st_error *err);
/* st_render_items' type, as adaptive.c is handed it. */
typedef st_status (*st_render_items_fn)(st_renderer *r, st_params *p, st_wave *w,
                                        const st_render_options *o, st_u64 first, st_u64 total,
                                        st_progress_state *pr, st_error *err);

/* An adaptive render (adaptive.c): the pilot's `total` items (its plan
 * from render.c), the allocation, the later samples and the blend, each
 * run of items by `items` (st_render_items). */
st_status st_render_adaptive(st_renderer *r, st_params *p, st_wave *w,
                             const st_render_options *o, st_u64 total, st_progress_state *pr,
                             st_render_stats *st, st_render_items_fn items, st_error *err);

/* After a wave of a render whose renderer has a preview (preview.c): the
 * film so far over the window win (x, y, w, h: the crop's, or the image)
 * to its callback, when its interval has passed. */
st_status st_render_preview(st_renderer *r, st_wave *w, const st_render_options *o,
                            const st_u32 win[4], st_error *err);

/* The camera basis of a view at an image aspect (device_scene.c). */
st_camera st_render_camera(const st_scene_camera *c, st_u32 w, st_u32 h);

#endif
