/* render.c — the pass loop (see st_render.h): a render's options checked and
 * turned into kernel parameters, its item space cut into waves pushed
 * through the stage kernels, then resolve and read-back. The scene on the
 * device is device_scene.c's, the wave buffers wave.c's, the adaptive rounds
 * adaptive.c's. */
#include "render_int.h"
#include "plan.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "st_mem_plan.h"
#include "st_sampling.h"
#include "filters.h"
#include "st_lights.h"

st_render_options st_render_defaults(void)
{
    st_render_options o;
    memset(&o, 0, sizeof o);
    o.width = 512;
    o.height = 512;
    o.spp = 16;
    o.sampler = ST_SAMPLER_HALTON;
    o.scramble = 1;
    o.integrator = ST_INTEGRATOR_PATH;
    o.max_depth = 5;
    o.filter = st_filter_default(ST_FILTER_MITCHELL);
    o.camera = -1;
    o.texture_filter = ST_TEXFILTER_TRILINEAR;
    /* a fixed work-group size: PoCL compiles a kernel again for every new
     * size, and a driver's choice follows the global size, which changes
     * from wave to wave in adaptive rounds (measured several times slower) */
    o.local_size = 64;
    return o;
}

st_u32 st_render_default_depth(const st_scene *s)
{
    for (st_u32 m = 0; m < s->material_count; m++)
        if (s->materials[m].transmission > 0.0f)
            return ST_GLASS_DEPTH;
    return st_render_defaults().max_depth;
}

/* The samples per pixel the sampler is made for: an adaptive render's
 * pixels draw sample indices up to its cap. */
static st_u32 sampler_spp(const st_render_options *o)
{
    st_u32 pilot, max_spp;
    if (!o->adaptive)
        return o->spp;
    st_render_adaptive_counts(o, &pilot, &max_spp);
    return max_spp;
}

/* An adaptive render's options: a per-pixel sampler, a pilot of at least
 * one sample below the mean, a cap at or above it, the whole sample range. */
static st_status check_adaptive(const st_render_options *o, st_error *err)
{
    st_u32 pilot, max_spp;
    st_render_adaptive_counts(o, &pilot, &max_spp);
    if (st_sampler_is_tiled(o->sampler))
        return st_fail(err, ST_ERR_USAGE, "adaptive needs a per-pixel sampler, not %s",
                       st_sampler_names[o->sampler]);
    if (pilot >= o->spp)
        return st_fail(err, ST_ERR_USAGE,
                       "min spp %u: the pilot must be below the mean spp %u (every pixel gets "
                       "at least one sample more)", pilot, o->spp);
    if (max_spp < o->spp)
        return st_fail(err, ST_ERR_USAGE, "max spp %u: must be at least the mean spp %u",
                       max_spp, o->spp);
    if (!(o->noise_threshold >= 0.0f))
        return st_fail(err, ST_ERR_USAGE, "noise threshold %g: must not be negative (0: none)",
                       (double)o->noise_threshold);
    if (o->sample_begin || o->sample_end)
        return st_fail(err, ST_ERR_USAGE, "adaptive renders cannot be split by sample range");
    return ST_OK;
}

st_status st_render_view_camera(const st_scene *scene, const st_render_options *o,
                                st_scene_camera *out, st_error *err)
{
    const float deg = (float)(3.14159265358979323846 / 180.0);
    if (st_scene_view_camera(scene, o->camera, out, err) != ST_OK)
        return err->status;
    if (o->fov == 0.0f && !o->look_at_given)
        return ST_OK;
    if (o->fov != 0.0f && out->orthographic && !o->look_at_given)
        return st_fail(err, ST_ERR_USAGE, "fov %g: the view's camera is orthographic (it has "
                       "no field of view; --look-at makes a perspective one)", (double)o->fov);
    float yfov = o->fov != 0.0f ? o->fov * deg : out->orthographic ? 40.0f * deg : out->yfov;
    if (o->look_at_given)
        return st_scene_look_at(o->look_at, o->look_at + 3, o->look_at + 6, yfov, out, err);
    if (!(yfov > 0.0f && yfov < 180.0f * deg))
        return st_fail(err, ST_ERR_USAGE, "fov %g: must lie strictly between 0 and 180 degrees",
                       (double)o->fov);
    out->yfov = yfov;
    return ST_OK;
}

st_status st_render_check(const st_render_options *o, st_error *err)
{
    if (o->width < 1 || o->height < 1 || o->width > 32768 || o->height > 32768)
        return st_fail(err, ST_ERR_USAGE, "image size %ux%u: width and height must be 1..32768",
                       o->width, o->height);
    if ((st_u64)o->width * o->height > (1ull << 28))
        return st_fail(err, ST_ERR_USAGE, "image size %ux%u: more than 2^28 pixels", o->width,
                       o->height);
    if (o->spp < 1)
        return st_fail(err, ST_ERR_USAGE, "spp must be at least 1");
    if (!isfinite(o->env_rotate))
        return st_fail(err, ST_ERR_USAGE, "env rotate %g: not a finite angle", (double)o->env_rotate);
    if (o->texture_filter > ST_TEXFILTER_TRILINEAR)
        return st_fail(err, ST_ERR_USAGE, "texture filter %u: unknown", o->texture_filter);
    st_u32 end = o->sample_end ? o->sample_end : o->spp;
    if (o->sample_begin >= end || end > o->spp)
        return st_fail(err, ST_ERR_USAGE, "sample range %u:%u: must satisfy 0 <= K < M <= spp (%u)",
                       o->sample_begin, o->sample_end, o->spp);
    st_status rc = st_sampler_check(o->sampler, o->width, o->height, sampler_spp(o), err);
    if (rc != ST_OK)
        return rc;
    if (o->reconstruction > ST_RECON_FIS)
        return st_fail(err, ST_ERR_USAGE, "reconstruction %u: unknown", o->reconstruction);
    /* both draw per pixel: FIS offsets each pixel's own samples, adaptive
     * sampling adds samples to chosen pixels */
    if (o->reconstruction == ST_RECON_FIS && st_sampler_is_tiled(o->sampler))
        return st_fail(err, ST_ERR_USAGE,
                       "reconstruction fis needs a per-pixel sampler; %s places its points "
                       "across pixels", st_sampler_names[o->sampler]);
    if (o->adaptive && (rc = check_adaptive(o, err)) != ST_OK)
        return rc;
    if (o->aov >= ST_AOV_COUNT)
        return st_fail(err, ST_ERR_USAGE, "aov %u: unknown", o->aov);
    if (o->aov != ST_AOV_NONE && o->adaptive) /* its samples follow the radiance's error */
        return st_fail(err, ST_ERR_USAGE, "aov %s: an adaptive render's samples follow its "
                       "radiance, which an AOV render does not see (drop --adaptive)",
                       st_aov_layouts[o->aov].name);
    if (o->max_depth > 64)
        return st_fail(err, ST_ERR_USAGE, "max depth %u: at most 64", o->max_depth);
    if ((o->crop_w || o->crop_h || o->crop_x || o->crop_y) &&
        (!o->crop_w || !o->crop_h || (st_u64)o->crop_x + o->crop_w > o->width ||
         (st_u64)o->crop_y + o->crop_h > o->height))
        return st_fail(err, ST_ERR_USAGE,
                       "crop %u,%u,%u,%u: the window must be non-empty and inside the %ux%u image",
                       o->crop_x, o->crop_y, o->crop_w, o->crop_h, o->width, o->height);
    const st_filter *f = &o->filter;
    if ((rc = st_filter_check(f, ST_FILTER_MAX_RADIUS, err)) != ST_OK)
        return rc;
    /* fixed-point headroom (fixed.h): splats one pixel can receive (from an
     * adaptive render's neighbours, up to their cap each) */
    double reach = ceil(2.0 * f->radius) + 1.0;
    st_u32 most = o->spp, pilot;
    if (o->adaptive)
        st_render_adaptive_counts(o, &pilot, &most);
    if ((double)most * reach * reach > ST_FIXED_MAX_SPLATS)
        return st_fail(err, ST_ERR_USAGE,
                       "spp %u with filter radius %g could overflow the 64-bit film "
                       "(limit: spp x (ceil(2r)+1)^2 <= 2^23 - 1)",
                       most, (double)f->radius);
    return ST_OK;
}


/* Binds every stage kernel to this render's values, scene and state; per
 * wave only the st_params argument changes. */
static st_status bind_stages(st_renderer *r, const st_render_options *o, const st_params *p,
                             const st_shading *sh, const st_wave *w, st_error *err)
{
    /* every kernel of the table but those of the film's own (resolve and
     * the adaptive rounds: st_wave_bind_film) */
    for (int k = 0; k < ST_KERNEL_COUNT; k++) {
        int film = k == ST_K_RESOLVE || (k >= ST_K_ADAPTIVE_MOMENTS && k <= ST_K_ADAPTIVE_BLEND);
        if (!film && st_wave_bind_stage(r->kernel[k], p, sh, r->scene_buf, w, err) != ST_OK)
            return err->status;
    }
    /* splat_tiles' window, after the stage parameters (a size, no buffer) */
    int alone = st_plan_tile_group(&r->plan, o) == 1;
    size_t window = p->bins ? st_plan_window_bytes(p->bin_side, p->filter.radius, alone)
                            : sizeof(st_i64);
    if (st_device_set_arg(r->kernel[ST_K_SPLAT_TILES], 2 + ST_SCENE_BUFFER_COUNT +
                          ST_WAVE_BUFFER_COUNT, window, NULL, err) != ST_OK)
        return err->status;
    return st_wave_bind_film(r->kernel[ST_K_RESOLVE], p, w, err);
}

/* Launches kernel k (ST_K_*) over `items` work-items in groups of `local`;
 * with profiling, timed in its stage by the device's clock
 * (collect_stage_times). */
static st_status run_kernel(st_renderer *r, int k, const st_params *p, size_t items,
                            size_t local, const st_render_options *o, st_error *err)
{
    cl_kernel kl = r->kernel[k];
    if (st_wave_set_params(kl, p, err) != ST_OK)
        return err->status;
    st_render_note_ran(r, kl);
    st_device_time_launches(r->dev, o->profile ? st_kernel_stages[k] : -1);
    st_status rc = st_device_launch(r->dev, kl, items || !o->warm ? items : 1u, local, err);
    st_device_time_launches(r->dev, -1);
    return rc;
}

_Static_assert(ST_STAGE_COUNT <= ST_DEVICE_TIME_TAGS, "a stage is a launch timing tag");

/* With profiling, at the render's end: the device times of its launches
 * added to their stages' (each launch's own start to end on the device, no
 * wait between launches, so the stages add up to less than the render's
 * wall time, the rest being the host's work and the gaps between launches). */
static st_status collect_stage_times(st_renderer *r, const st_render_options *o,
                                     st_render_stats *st, st_error *err)
{
    return o->profile ? st_device_timed_seconds(r->dev, st->stage_seconds, ST_STAGE_COUNT, err)
                      : ST_OK;
}

/* Launches kernel k over `items` work-items in the render's groups. */
static st_status run_stage(st_renderer *r, int k, const st_params *p, size_t items,
                           const st_render_options *o, st_error *err)
{
    return run_kernel(r, k, p, items, o->local_size, o, err);
}

/* Reconstruction of a wave: splat_pixels then splat_edges (the taps of
 * samples on pixel edges), splat_samples, or splat_tiles,
 * one work-group per bin (st_plan_tile_group), in one launch or in the
 * plan's four passes, after the counting sort by bin (three kernels, timed
 * as the stage bin_samples) where the items do not lie in their pixels in
 * order (st_items_by_pixel). */
static st_status splat_wave(st_renderer *r, const st_params *p, const st_render_options *o,
                            st_error *err)
{
    size_t n = p->item_count, group = st_plan_tile_group(&r->plan, o);
    size_t npix = (size_t)p->region_w * p->region_h;
    if (st_plan_gathers(&r->plan, p)) {
        size_t m = n < npix ? n : npix;
        if (run_stage(r, ST_K_SPLAT_PIXELS, p, m, o, err) ||
            run_stage(r, ST_K_SPLAT_EDGES, p, m, o, err))
            return err->status;
        return ST_OK;
    }
    if (!p->bins)
        return run_stage(r, ST_K_SPLAT, p, n, o, err);
    if (!st_items_by_pixel(p) &&
        (run_stage(r, ST_K_BIN_COUNT, p, n, o, err) || run_stage(r, ST_K_BIN_SCAN, p, 1, o, err) ||
         run_stage(r, ST_K_BIN_SCATTER, p, n, o, err)))
        return err->status;
    st_params q = *p;
    st_u32 passes = r->plan.tile_passes ? 4u : 1u;
    size_t bins = r->plan.tile_passes ? (size_t)(p->bins_x + 1) / 2 *
                                            ((p->bins / p->bins_x + 1) / 2)
                                      : p->bins;
    for (st_u32 c = 0; c < passes; c++) {
        q.bin_pass = r->plan.tile_passes ? c + 1u : 0u;
        if (run_kernel(r, ST_K_SPLAT_TILES, &q, bins * group, group, o, err))
            return err->status;
    }
    return ST_OK;
}

/* Side of the tile in pixels for the tiled samplers: about 2^14 points, at
 * most 64 x 64 pixels (st_sampling_pixel_tile's cost grows with the count). */
static st_u32 tile_side(st_u32 spp)
{
    st_u32 t = (st_u32)sqrt(16384.0 / spp);
    return t < 1u ? 1u : t > 64u ? 64u : t;
}

/* Makes (or reuses) the tile of a tiled sampler: spp points in each of its
 * T x T pixels, uploaded once. */
static st_status prepare_tile(st_renderer *r, const st_render_options *o, st_error *err)
{
    int tiled = ST_SAMPLER_IS_TILED(o->sampler);
    if (r->scene_buf[ST_SCENE_tile] && (!tiled || (r->tile_sampler == o->sampler && r->tile_spp == o->spp &&
                               r->tile_seed == o->seed)))
        return ST_OK;
    st_device_buffer_destroy(r->dev, r->scene_buf[ST_SCENE_tile]);
    r->scene_buf[ST_SCENE_tile] = NULL;
    if (!tiled) /* kernels take the argument anyway */
        return st_device_buffer_create(r->dev, 16, NULL, &r->scene_buf[ST_SCENE_tile], err);
    st_u32 side = tile_side(o->spp), count = side * side * o->spp;
    float *pts = NULL;
    st_status rc = st_sampling_pixel_tile(o->sampler, side, o->spp, o->seed, &pts, NULL, err);
    if (rc != ST_OK)
        return rc;
    rc = st_device_buffer_create(r->dev, sizeof(st_tile_point) * count, pts, &r->scene_buf[ST_SCENE_tile], err);
    free(pts);
    r->tile_sampler = o->sampler;
    r->tile_spp = o->spp;
    r->tile_seed = o->seed;
    r->tile_size = side;
    r->tile_points = count;
    return rc;
}

/* Whether a render reads Halton's digit permutation tables: the scrambled
 * Halton sampler (its unscrambled digits are the identity). */
static int halton_tables_used(const st_render_options *o)
{
    return o->sampler == ST_SAMPLER_HALTON && o->scramble;
}

/* The key r->pmj02_log2 takes for Halton's tables: above every pmj02 size. */
#define HALTON_TABLES_KEY 64u

/* Uploads Halton's digit permutation tables for o->seed into pmj02's slot. */
static st_status upload_halton_tables(st_renderer *r, const st_render_options *o,
                                      st_error *err)
{
    st_u32 *words = NULL;
    size_t n = 0;
    st_status rc = st_sampling_halton_tables(o->seed, &words, &n, err);
    if (rc != ST_OK)
        return rc;
    size_t bytes = sizeof(st_u32) * n;
    unsigned long long max_alloc = st_device_max_alloc(r->dev);
    if (max_alloc && bytes > max_alloc)
        rc = st_fail(err, ST_ERR_DEVICE,
                     "Halton's digit tables (%zu bytes) exceed the device's largest buffer "
                     "(CL_DEVICE_MAX_MEM_ALLOC_SIZE, %llu bytes): use another --sampler or "
                     "--scramble none",
                     bytes, max_alloc);
    else
        rc = st_device_buffer_create(r->dev, bytes, words, &r->scene_buf[ST_SCENE_pmj02], err);
    free(words);
    r->pmj02_seed = o->seed;
    r->pmj02_log2 = rc == ST_OK ? HALTON_TABLES_KEY : 0u;
    return rc;
}

/* Makes (or reuses) the sampler's tables in pmj02's slot: pmj02's,
 * ST_PMJ02_SETS sequences of 2^ceil(log2 spp) points (pmj02bn's with its
 * pixel tile after them), uploaded once per
 * seed and size; a tiled sampler's pads, made for each render; or the
 * scrambled Halton sampler's digit permutations, once per seed. */
static st_status prepare_pmj02(st_renderer *r, const st_render_options *o, st_error *err)
{
    int tiled = ST_SAMPLER_IS_TILED(o->sampler), bn = o->sampler == ST_SAMPLER_PMJ02BN;
    int halton = halton_tables_used(o);
    int used = o->sampler == ST_SAMPLER_PMJ02 || bn || tiled || halton;
    st_u32 log2n = 1u; /* ceil(log2 spp) + 1: 0 stands for none */
    while (used && !halton && (1u << (log2n - 1u)) < o->spp)
        log2n++;
    st_u32 key = halton ? HALTON_TABLES_KEY : log2n + 32u * bn; /* + 32: pmj02bn's */
    if (r->scene_buf[ST_SCENE_pmj02] &&
        (!used || (r->pmj02_seed == o->seed && r->pmj02_log2 == key)))
        return ST_OK;
    st_device_buffer_destroy(r->dev, r->scene_buf[ST_SCENE_pmj02]);
    r->scene_buf[ST_SCENE_pmj02] = NULL;
    r->pmj02_log2 = 0u;
    if (!used) /* kernels take the argument anyway */
        return st_device_buffer_create(r->dev, 16, NULL, &r->scene_buf[ST_SCENE_pmj02], err);
    if (halton)
        return upload_halton_tables(r, o, err);
    st_u32 *pts = NULL, n = 1u << (log2n - 1u);
    size_t words = 2u * ST_PMJ02_SETS * (size_t)n;
    /* a tiled sampler's pad tables take the slot, made anew for each render */
    st_status rc = tiled ? st_sampling_pad_tables(o->sampler, o->spp, o->seed, &pts, &n, err)
                 : bn    ? st_sampling_pmj02bn_tables(o->spp, o->seed, &pts, &words, err)
                         : st_sampling_pmj02(log2n - 1u, ST_PMJ02_SETS, o->seed, &pts, err);
    if (rc != ST_OK)
        return rc;
    size_t bytes = sizeof(st_u32) * (tiled ? 2u * ST_PMJ02_SETS * (size_t)n : words);
    rc = st_device_buffer_create(r->dev, bytes, pts, &r->scene_buf[ST_SCENE_pmj02], err);
    free(pts);
    r->pmj02_seed = o->seed;
    r->pmj02_log2 = rc == ST_OK && !tiled ? key : 0u;
    return rc;
}

/* The CDF of |f| over ST_FIS_BINS equal bins of [-r, r] (midpoint rule),
 * uploaded for filter importance sampling (pbrt-v4's FilterSampler
 * tabulates |f| the same way). */
static st_status prepare_fis(st_renderer *r, const st_render_options *o, st_error *err)
{
    float cdf[ST_FIS_BINS + 1];
    st_filter_fis_cdf(&o->filter, cdf);
    st_device_buffer_destroy(r->dev, r->scene_buf[ST_SCENE_fis_cdf]);
    r->scene_buf[ST_SCENE_fis_cdf] = NULL;
    return st_device_buffer_create(r->dev, sizeof cdf, cdf, &r->scene_buf[ST_SCENE_fis_cdf], err);
}

void st_render_env(const st_scene *scene, const st_render_options *o, float env[3])
{
    static const float one[3] = {1.0f, 1.0f, 1.0f};
    memcpy(env, o->env_given ? o->env : o->env_map ? one : scene->default_env, 3 * sizeof(float));
}

static st_shading make_shading(const st_renderer *r, const st_render_options *o)
{
    st_shading sh;
    memset(&sh, 0, sizeof sh);
    const st_scene *s = r->scene;
    st_render_env(s, o, sh.env);
    if (r->env_map) { /* the map, scaled by env (its upload: st_render) */
        sh.env_size[0] = r->env_map->width;
        sh.env_size[1] = r->env_map->height;
    }
    double a = o->env_rotate * (3.14159265358979323846 / 180.0);
    sh.env_rot[0] = (float)cos(a);
    sh.env_rot[1] = (float)sin(a);
    sh.texture_filter = o->texture_filter;
    sh.texture_count = s->texture_count;
    sh.punct_count = r->punct_count;
    double area = s->emitted_power - s->punctual_power;
    double env = st_env_power(r->env_map, sh.env, st_scene_radius(s));
    if (r->punct_count)
        sh.punct_share = st_punctual_share(s->punctual_power, area, env);
    sh.env_pick = st_env_pick(area, env, r->light_count);
    return sh;
}

static void set_region(st_params *p, const st_u32 region[4])
{
    p->region_x = region[0];
    p->region_y = region[1];
    p->region_w = region[2];
    p->region_h = region[3];
}

/* The crop's window, or the whole image. */
static void crop_window(const st_render_options *o, st_u32 win[4])
{
    int crop = o->crop_w != 0;
    win[0] = crop ? o->crop_x : 0;
    win[1] = crop ? o->crop_y : 0;
    win[2] = crop ? o->crop_w : o->width;
    win[3] = crop ? o->crop_h : o->height;
}

void st_render_region(const st_render_options *o, st_u32 region[4])
{
    int whole = !o->crop_w || o->adaptive || st_sampler_is_tiled(o->sampler);
    crop_window(o, region);
    if (whole) {
        region[0] = region[1] = 0;
        region[2] = o->width;
        region[3] = o->height;
        return;
    }
    /* a sample of pixel k lies in [k, k + 1) and reaches the pixels whose
     * centres are within the radius: at most ceil(r) pixels away (FIS:
     * its own pixel only) */
    st_u32 a = o->reconstruction == ST_RECON_FIS ? 0u : (st_u32)ceilf(o->filter.radius);
    st_u32 x0 = region[0] > a ? region[0] - a : 0, y0 = region[1] > a ? region[1] - a : 0;
    st_u32 x1 = region[0] + region[2] + a, y1 = region[1] + region[3] + a;
    region[0] = x0;
    region[1] = y0;
    region[2] = (x1 < o->width ? x1 : o->width) - x0;
    region[3] = (y1 < o->height ? y1 : o->height) - y0;
}

static st_params make_params(const st_renderer *r, const st_render_options *o,
                             const st_scene_camera *cam)
{
    st_params p;
    memset(&p, 0, sizeof p);
    p.width = o->width;
    p.height = o->height;
    p.spp = o->spp;
    p.seed = o->seed;
    p.sampler = o->sampler;
    p.scramble = o->scramble;
    p.halton_tables = (st_u32)halton_tables_used(o);
    p.integrator = o->integrator;
    p.max_depth = o->integrator == ST_INTEGRATOR_DIRECT ? 1u : o->max_depth;
    p.light_count = r->light_count;
    p.ray_eps = r->ray_eps;
    p.filter = o->filter;
    p.reconstruction = o->reconstruction;
    p.camera = st_render_camera(cam, o->width, o->height);
    p.aov = o->aov;
    if (o->aov != ST_AOV_NONE) { /* the camera ray's first hit (and one through a cut-out) */
        p.integrator = ST_INTEGRATOR_DIRECT;
        p.max_depth = 1u;
    }
    st_u32 region[4];
    st_render_region(o, region);
    set_region(&p, region);
    st_sampler_prepare(&p);
    return p;
}

/* The paths a trace or shade launch at p's vertex runs over: every item of
 * the wave at vertex 0, then those still alive (st_live_count in st_shared.h). */
static size_t live_paths(const st_params *p)
{
    return p->vertex == 0u ? p->item_count : p->live_count;
}

/* Vertex v's rays of stage k (ST_STAGE_TRACE or ST_STAGE_SHADOW) over its
 * live paths, by the kernel the plan chose (st_plan_vertex): in packets,
 * ceil(n / lanes) work-items, or one ray a work-item, a trace's rays sorted
 * first where the plan says so (the sort timed with the stage). */
static st_status run_trace(st_renderer *r, int k, st_u32 v, const st_params *p,
                           const st_render_options *o, st_error *err)
{
    const st_plan_vertex *x = &r->plan.vertex[v];
    size_t n = live_paths(p);
    int kernel = k == ST_STAGE_TRACE ? x->trace : x->shadow;
    if (k == ST_STAGE_TRACE ? x->trace_lanes : x->shadow_lanes)
        n = st_render_lane_items(r->dev, n);
    if (k != ST_STAGE_TRACE || !x->sorted)
        return run_stage(r, kernel, p, n, o, err);
    st_params q = *p;
    q.ordered = 1u;
    st_device_time_launches(r->dev, o->profile ? ST_STAGE_TRACE : -1);
    st_status rc = st_render_order(r, &q, n, o->local_size, err);
    st_device_time_launches(r->dev, -1);
    if (rc != ST_OK)
        return rc;
    return run_stage(r, kernel, &q, n, o, err);
}

/* Stage shade over the vertex's live paths, ST_W per work-item (ceil(n /
 * ST_W) work-items): shade_hits, or shade_hits_shadowed with its shadow rays. */
static st_status run_shade(st_renderer *r, const st_params *p, const st_render_options *o,
                           st_error *err)
{
    return run_stage(r, r->plan.shade, p, st_render_lane_items(r->dev, live_paths(p)), o, err);
}

/* The list of the paths that go on from p's vertex, for the next (live.cl:
 * a count per chunk of shade's words, their scan, the scatter); its length
 * read back into p->live_count. */
static st_status list_live(st_renderer *r, const st_wave *w, st_params *p,
                           const st_render_options *o, st_error *err)
{
    size_t words = st_render_lane_items(r->dev, live_paths(p));
    size_t chunks = (words + ST_LIVE_CHUNK - 1u) / ST_LIVE_CHUNK;
    if (run_stage(r, ST_K_LIVE_COUNT, p, chunks, o, err) ||
        run_stage(r, ST_K_LIVE_SCAN, p, 1, o, err) ||
        run_stage(r, ST_K_LIVE_SCATTER, p, chunks, o, err))
        return err->status;
    return st_device_buffer_read(r->dev, w->b[ST_WAVE_live_total], sizeof p->live_count,
                                 &p->live_count, err);
}

/* One wave: items [first, first + n) of the render's item space. */
static st_status run_wave(st_renderer *r, const st_wave *w, st_params *p,
                          const st_render_options *o, st_error *err)
{
    /* generate: ST_W items a work-item */
    if (run_stage(r, ST_K_GENERATE, p, st_render_lane_items(r->dev, p->item_count), o, err))
        return err->status;
    /* vertex k = 0 .. max_depth: light is gathered (NEE) at the first
     * max_depth vertices; the last one only adds emission (MIS), as the
     * direct integrator's second (max_depth 1). Shadow rays in shade: timed
     * as its stage. */
    st_u32 vertices = p->max_depth + 1u;
    for (st_u32 v = 0; v < vertices; v++) {
        p->vertex = r->plan.live_lists ? v : 0u; /* 0: every item */
        if (run_trace(r, ST_STAGE_TRACE, v, p, o, err) || run_shade(r, p, o, err))
            return err->status;
        if (r->plan.vertex[v].shadow >= 0 && run_trace(r, ST_STAGE_SHADOW, v, p, o, err))
            return err->status;
        if (r->plan.live_lists && v + 1u < vertices) {
            if (list_live(r, w, p, o, err) != ST_OK)
                return err->status;
            if (p->live_count == 0u && !o->warm)
                break;
        }
    }
    p->vertex = 0;
    return splat_wave(r, p, o, err);
}

/* The tallies of the work-item slots and of splat_tiles' bins (the plan's
 * first bins), summed into the stats. */
static st_status read_tallies(st_renderer *r, const st_wave *w, st_render_stats *st,
                              st_error *err)
{
    size_t bins = r->plan.bins;
    st_tally *tally = malloc(st_wave_bytes(w, ST_WAVE_tally));
    st_bin_tally *bin = malloc((bins ? bins : 1) * sizeof *bin);
    st_film_stats counts;
    st_status rc = tally && bin ? ST_OK
                                : st_fail(err, ST_ERR_NOMEM,
                                          "out of memory reading the ray counts back");
    if (rc == ST_OK)
        rc = st_device_buffer_read(r->dev, w->b[ST_WAVE_tally], st_wave_bytes(w, ST_WAVE_tally),
                                   tally, err);
    if (rc == ST_OK && bins)
        rc = st_device_buffer_read(r->dev, w->b[ST_WAVE_bin_tally], bins * sizeof *bin, bin, err);
    if (rc == ST_OK)
        rc = st_device_buffer_read(r->dev, w->b[ST_WAVE_stats], sizeof counts, &counts, err);
    for (size_t i = 0; rc == ST_OK && i < w->items; i++) {
        st->splats += tally[i].splats;
        st->closest_rays += tally[i].closest_rays;
        st->shadow_rays += tally[i].shadow_rays;
    }
    for (size_t b = 0; rc == ST_OK && b < bins; b++) {
        st->splats += bin[b].splats;
        st->closest_rays += bin[b].closest_rays;
        st->shadow_rays += bin[b].shadow_rays;
    }
    free(tally);
    free(bin);
    if (rc != ST_OK)
        return rc;
    st->rays = st->closest_rays + st->shadow_rays;
    st->clamped = counts.clamped;
    st->nonfinite = counts.nonfinite;
    st->zero_weight = counts.zero_weight;
    return ST_OK;
}

/* A device buffer of `bytes` into a new malloc'ed block *out. */
static st_status read_new(st_device *dev, cl_mem mem, size_t bytes, void **out, st_error *err)
{
    *out = malloc(bytes);
    if (!*out)
        return st_fail(err, ST_ERR_NOMEM, "out of memory reading the film back");
    if (st_device_buffer_read(dev, mem, bytes, *out, err) != ST_OK) {
        free(*out);
        *out = NULL;
        return err->status;
    }
    return ST_OK;
}

/* Rows win[1] .. win[1] + win[3] - 1, columns win[0] .. win[0] + win[2] - 1
 * of a per-pixel device buffer (elem bytes a pixel) into dst. */
static st_status read_window(st_device *dev, cl_mem mem, size_t elem, const st_render_options *o,
                             const st_u32 win[4], void *dst, st_error *err)
{
    size_t row = elem * win[2];
    if (win[2] == o->width && win[3] == o->height)
        return st_device_buffer_read(dev, mem, row * win[3], dst, err);
    char *all;
    if (read_new(dev, mem, elem * o->width * o->height, (void **)&all, err) != ST_OK)
        return err->status;
    for (st_u32 y = 0; y < win[3]; y++)
        memcpy((char *)dst + row * y, all + elem * ((size_t)(win[1] + y) * o->width + win[0]), row);
    free(all);
    return ST_OK;
}

/* The window's raw sums in a new malloc'ed block *sums. */
static st_status read_sums(st_renderer *r, st_wave *w, const st_render_options *o,
                           const st_u32 win[4], st_i64 **sums, st_error *err)
{
    *sums = malloc(sizeof(st_film_pixel) * win[2] * win[3]);
    if (!*sums)
        return st_fail(err, ST_ERR_NOMEM, "out of memory reading the film back");
    return read_window(r->dev, w->b[ST_WAVE_film], sizeof(st_film_pixel), o, win, *sums, err);
}

/* The resolved image (R, G, B, W) of the crop's window (or the image), the
 * raw sums when asked, the stats and an adaptive render's spp map. */
static st_status read_results(st_renderer *r, st_wave *w, const st_render_options *o,
                              st_image *out, st_i64 **sums, st_render_stats *st, st_error *err)
{
    static const char *const names[4] = {"R", "G", "B", "W"};
    st_u32 win[4];
    crop_window(o, win);
    if (st_image_create(out, win[2], win[3], 4, names, err) ||
        read_window(r->dev, w->b[ST_WAVE_image], sizeof(st_pixel), o, win, out->data, err) ||
        read_tallies(r, w, st, err) || (sums && read_sums(r, w, o, win, sums, err)))
        return err->status;
    if (o->crop_w) {
        out->x0 = (int32_t)win[0];
        out->y0 = (int32_t)win[1];
        out->display_width = o->width;
        out->display_height = o->height;
    }
    if (!o->adaptive)
        return ST_OK;
    return read_new(r->dev, w->b[ST_WAVE_pixel_spp], st_wave_bytes(w, ST_WAVE_pixel_spp),
                    (void **)&st->spp_map, err);
}

/* read_results, leaving nothing allocated when it fails. */
static st_status read_back(st_renderer *r, st_wave *w, const st_render_options *o,
                           st_image *out, st_i64 **sums, st_render_stats *st, st_error *err)
{
    st_status rc = read_results(r, w, o, out, sums, st, err);
    if (rc != ST_OK) {
        st_image_free(out);
        if (sums) {
            free(*sums);
            *sums = NULL;
        }
    }
    return rc;
}

st_status st_render_items(st_renderer *r, st_params *p, st_wave *w, const st_render_options *o,
                          st_u64 first, st_u64 total, st_progress_state *pr, st_error *err)
{
    st_status rc = ST_OK;
    for (st_u64 done = 0; rc == ST_OK && done < total; done += w->items) {
        p->first_item = first + done;
        p->item_count = (st_u32)(total - done < w->items ? total - done : w->items);
        rc = run_wave(r, w, p, o, err);
        if (rc == ST_OK && pr->fn) {
            rc = st_device_finish(r->dev, err);
            pr->done += p->item_count;
            pr->fn(pr->ctx, pr->done < pr->total ? pr->done / pr->total : 1.0);
        }
        if (rc == ST_OK && r->preview.fn && o->aov == ST_AOV_NONE) {
            st_u32 win[4];
            crop_window(o, win);
            rc = st_render_preview(r, w, o, win, err);
        }
    }
    return rc;
}

st_status st_render_resolve(st_device *dev, const st_i64 *sums, st_u32 width, st_u32 height,
                            st_u32 aov, st_image *out, st_render_stats *stats, st_error *err)
{
    static const char *const names[4] = {"R", "G", "B", "W"};
    size_t pixels = (size_t)width * height;
    st_params p;
    memset(&p, 0, sizeof p);
    p.width = width;
    p.height = height;
    p.aov = aov;
    set_region(&p, (const st_u32[4]){0, 0, width, height});
    st_wave w;
    cl_kernel k;
    st_film_stats counts;
    if (st_device_build(dev, NULL, err) ||
        st_device_kernel(dev, st_stage_names[ST_STAGE_RESOLVE], &k, err) ||
        st_wave_create(dev, 1, pixels, 0, 0, &w, err))
        return err->status;
    st_status rc = ST_OK;
    if (st_device_buffer_write(dev, w.b[ST_WAVE_film], st_wave_bytes(&w, ST_WAVE_film), sums,
                               err) ||
        st_wave_bind_film(k, &p, &w, err) ||
        st_device_launch(dev, k, st_render_lane_items(dev, pixels), 0, err) ||
        st_image_create(out, width, height, 4, names, err) ||
        st_device_buffer_read(dev, w.b[ST_WAVE_image], st_wave_bytes(&w, ST_WAVE_image),
                              out->data, err) ||
        st_device_buffer_read(dev, w.b[ST_WAVE_stats], sizeof counts, &counts, err))
        rc = err->status;
    if (rc == ST_OK && stats) {
        stats->zero_weight = counts.zero_weight;
        stats->nonfinite = counts.nonfinite;
    }
    st_wave_destroy(&w);
    return rc;
}

/* The wave a render takes without --wave: 2^20 items, or the largest
 * power of two down to 2^18 whose buffers the device and the process can
 * hold (st_mem_plan_check; at 2^18 its error is the render's). A wave pays
 * for each stage's launch and, splatting by pixel, a pass over the film;
 * on a 2-core CPU 2^20 rendered fastest (2^21 and 2^22 slower again, their
 * buffers streamed from memory), and a GPU has more items to run at once. */
size_t st_render_default_wave(const st_device *dev, size_t pixels, int adaptive)
{
    size_t wave = (size_t)1 << 20;
    for (; wave > ((size_t)1 << 18); wave /= 2) {
        st_error scratch = {0};
        if (st_mem_plan_check(dev, wave, pixels, adaptive, 0, &scratch) == ST_OK)
            break;
    }
    return wave;
}

/* The items of the first pass: sample range K:M of every pixel; for a
 * tiled sampler, tile points [K N / spp, M N / spp) of every repetition of
 * the tile; for an adaptive render, its pilot everywhere. */
static void plan_items(const st_renderer *r, const st_render_options *o, st_params *p,
                       st_u64 *first, st_u64 *total)
{
    size_t pixels = (size_t)p->region_w * p->region_h;
    st_u32 end = o->sample_end ? o->sample_end : o->spp;
    *first = (st_u64)o->sample_begin * pixels;
    *total = (st_u64)(end - o->sample_begin) * pixels;
    if (st_sampler_is_tiled(o->sampler)) {
        st_u32 side = r->tile_size, n = r->tile_points;
        p->tile_size = side;
        p->tiles_x = (o->width + side - 1) / side;
        p->tile_begin = (st_u32)((st_u64)o->sample_begin * n / o->spp);
        p->tile_count = (st_u32)((st_u64)end * n / o->spp) - p->tile_begin;
        *first = 0;
        *total = (st_u64)p->tiles_x * ((o->height + side - 1) / side) * p->tile_count;
    }
    if (o->adaptive) {
        st_u32 pilot, max_spp;
        st_render_adaptive_counts(o, &pilot, &max_spp);
        *total = (st_u64)pilot * pixels;
    }
}

int st_render_adaptive_falls_back(const st_render_options *o)
{
    return o->adaptive && o->sampler != ST_SAMPLER_RANDOM && !st_render_adaptive_qmc(o);
}

/* An adaptive request for a sampler it would lose with: the uniform render
 * of the same mean spp, and its spp map (every pixel spp) as an adaptive
 * render's. */
static st_status render_fallback(st_renderer *r, const st_render_options *o, st_image *out,
                                 st_i64 **sums, st_render_stats *st, st_progress_fn progress,
                                 void *progress_ctx, st_error *err)
{
    st_render_options u = *o;
    u.adaptive = 0;
    u.min_spp = u.max_spp = 0;
    u.noise_threshold = 0.0f;
    size_t pixels = (size_t)o->width * o->height;
    st_u32 *map = malloc(pixels * sizeof *map);
    if (!map)
        return st_fail(err, ST_ERR_NOMEM, "out of memory for the spp map");
    for (size_t i = 0; i < pixels; i++)
        map[i] = o->spp;
    st_status rc = st_render(r, &u, out, sums, st, progress, progress_ctx, err);
    if (rc != ST_OK) {
        free(map);
        return rc;
    }
    st->spp_map = map;
    return ST_OK;
}

st_status st_render(st_renderer *r, const st_render_options *o, st_image *out, st_i64 **sums,
                    st_render_stats *stats, st_progress_fn progress, void *progress_ctx,
                    st_error *err)
{
    st_render_stats local;
    st_render_stats *st = stats ? stats : &local;
    memset(st, 0, sizeof *st);
    if (sums)
        *sums = NULL;
    if (st_render_check(o, err) != ST_OK)
        return err->status;
    if (st_render_adaptive_falls_back(o))
        return render_fallback(r, o, out, sums, st, progress, progress_ctx, err);
    size_t pixels = (size_t)o->width * o->height;
    st_scene_camera cam;
    st_render_options so = *o; /* what the sampler is made for */
    const st_envmap *env_map = o->env_map ? o->env_map : o->env_given ? NULL : r->sky;
    so.spp = sampler_spp(o);
    if (st_render_view_camera(r->scene, o, &cam, err) != ST_OK ||
        (r->env_map != env_map && st_renderer_upload_env_map(r, env_map, err) != ST_OK) ||
        prepare_tile(r, o, err) != ST_OK || prepare_fis(r, o, err) != ST_OK ||
        prepare_pmj02(r, &so, err) != ST_OK)
        return err->status;
    st_params p = make_params(r, &so, &cam);
    st_u64 first, total;
    plan_items(r, o, &p, &first, &total);
    size_t wave = o->wave ? o->wave : st_render_default_wave(r->dev, pixels, o->adaptive);
    if (wave > total)
        wave = (size_t)total;
    st_wave w;
    double t0 = st_render_now();
    st_progress_state pr = {progress, progress_ctx, 0.0, (double)total};
    if (o->adaptive)
        pr.total = (double)o->spp * pixels;
    st_shading sh = make_shading(r, o);
    r->plan = st_plan_make(r, o, &sh, &p);
    r->ran_count = 0;
    r->preview.last = t0; /* the first look comes an interval into the render */
    int ordered = r->plan.order == ST_ORDER_ON;
    st_status rc = st_mem_plan_check(r->dev, wave, pixels, o->adaptive, ordered, err) != ST_OK
                       ? err->status
                       : st_wave_create(r->dev, wave, pixels, o->adaptive, ordered, &w, err);
    if (rc != ST_OK)
        return rc;
    rc = bind_stages(r, o, &p, &sh, &w, err);
    if (rc == ST_OK && o->adaptive)
        rc = st_render_adaptive(r, &p, &w, o, total, &pr, st, st_render_items, err);
    else if (rc == ST_OK)
        rc = st_render_items(r, &p, &w, o, first, total, &pr, err);
    if (!o->adaptive)
        st->samples = total;
    st_u32 win[4];
    crop_window(o, win);
    set_region(&p, win); /* resolve the window alone: its counts are the window's */
    size_t resolve_items = st_render_lane_items(r->dev, (size_t)win[2] * win[3]);
    if (rc == ST_OK)
        rc = run_stage(r, ST_K_RESOLVE, &p, resolve_items, o, err);
    if (rc == ST_OK)
        rc = st_device_finish(r->dev, err);
    st->seconds = st_render_now() - t0;
    /* read even after a failure, so that no launch of this render is
     * counted in the next one's stages */
    st_error unread = {0};
    st_status timed = collect_stage_times(r, o, st, rc == ST_OK ? err : &unread);
    if (rc == ST_OK)
        rc = timed;
    if (rc == ST_OK)
        rc = read_back(r, &w, o, out, sums, st, err);
    st_wave_destroy(&w);
    return rc;
}
