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

/* adaptive.cl's kernels, in the order of st_adaptive_kernel_names */
enum { ST_ADAPTIVE_MOMENTS, ST_ADAPTIVE_ESTIMATE, ST_ADAPTIVE_BLEND, ST_ADAPTIVE_KERNELS };
extern const char *const st_adaptive_kernel_names[ST_ADAPTIVE_KERNELS];
/* order.cl's kernels (st_order_kernel_names) */
enum { ST_ORDER_BOUNDS_K, ST_ORDER_KEYS_K, ST_ORDER_COUNT_LOW_K, ST_ORDER_SCAN_K,
       ST_ORDER_SCATTER_LOW_K, ST_ORDER_COUNT_HIGH_K, ST_ORDER_SCATTER_HIGH_K, ST_ORDER_KERNELS };
extern const char *const st_order_kernel_names[ST_ORDER_KERNELS];

struct st_renderer {
    st_device *dev;
    const st_scene *scene;
    /* ST_SCENE_BUFFERS: the scene, uploaded once; tile, fis_cdf and pmj02
     * are the per-render inputs (render.c), env_texels and env_cdf the
     * environment map's (st_renderer_upload_env_map) */
    cl_mem scene_buf[ST_SCENE_BUFFER_COUNT];
    cl_kernel k[ST_STAGE_COUNT];
    cl_kernel adaptive[ST_ADAPTIVE_KERNELS]; /* adaptive.cl, by ST_ADAPTIVE_* */
    cl_kernel bin_scan, bin_scatter; /* the rest of ST_STAGE_BIN (film.cl) */
    cl_kernel splat_edges; /* the rest of ST_STAGE_SPLAT_PIXELS (film.cl) */
    cl_kernel live_count, live_scan;  /* the rest of ST_STAGE_LIVE (live.cl) */
    cl_kernel shade_shadowed; /* shade_hits_shadowed: ST_STAGE_SHADE with its shadow rays */
    /* ST_STAGE_TRACE and ST_STAGE_SHADOW in packets of ST_W rays (trace.cl, shadow.cl) */
    cl_kernel trace_packet, shadow_packet;
    cl_kernel trace_last; /* trace_rays_last: ST_STAGE_TRACE at the last vertex */
    cl_kernel order[ST_ORDER_KERNELS]; /* the ray order before a trace (order.c) */
    int all_opaque; /* every material ST_ALPHA_OPAQUE: shadow packets may be used */
    /* all_opaque, no unlit surface, and every emissive surface in the light
     * list (its emission a factor, no texture): a ray of the last vertex
     * sees light only at a light-list triangle or in the environment
     * (trace_rays_last may be used) */
    int emitters_listed;
    st_u32 light_count;
    st_u32 punct_count; /* KHR_lights_punctual lights (scene->punctual) */
    const st_envmap *env_map; /* the map uploaded, a render's st_render_options.env_map
                                 (borrowed); NULL: none */
    float ray_eps;
    double bvh_seconds;
    /* the key of the tiled sampler's tile in scene_buf[ST_SCENE_tile],
     * kept for renders with the same key */
    st_u32 tile_sampler, tile_spp, tile_seed, tile_size, tile_points;
    /* the key of the sampler tables in scene_buf[ST_SCENE_pmj02]: pmj02's
     * (log2 0: none) or Halton's digit permutations (render.c) */
    st_u32 pmj02_seed, pmj02_log2;
    st_plan_force force; /* st_renderer_force */
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

/* The camera basis of a view at an image aspect (device_scene.c). */
st_camera st_render_camera(const st_scene_camera *c, st_u32 w, st_u32 h);

#endif
