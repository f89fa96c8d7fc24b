/* trace_bench.c — the trace benchmark (st_trace_bench.h): rays made on the
 * host, uploaded a wave at a time, traced by the renderer's own trace_rays
 * kernel, which alone is timed, with the sort by ray before it where the
 * plan sorts a large scene's rays (plan.c: st_plan_orders). */
#include "st_trace_bench.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "camera.h"
#include "render_int.h"
#include "rng.h"
#include "st_bvh.h"

const char *const st_ray_set_names[ST_RAYS_COUNT] = {"camera", "random"};

/* A ray's random numbers: ray index i split into the key's two words, so
 * every 64-bit index has its own stream. */
static st_u32 ray_key(st_u32 seed, int set, st_u64 i)
{
    return st_rng_key(seed ^ (st_u32)set * 0x68bc21ebu, (st_u32)i, (st_u32)(i >> 32));
}

/* The camera ray through the film point (fx, fy): the generate stage's
 * (camera.h, at width 1). */
static st_ray camera_ray(const st_camera *c, const st_render_options *o, float fx, float fy)
{
    st_lv3 org, dir;
    st_camera_rays(c, o->width, o->height, fx, fy, &org, &dir);
    st_ray r = {{org.x, org.y, org.z}, INFINITY, {dir.x, dir.y, dir.z}, 0.0f};
    return r;
}

/* Origin uniform in the box, direction uniform on the sphere (z = 1 - 2u,
 * azimuth 2 pi v: Archimedes' hat-box theorem). */
static st_ray random_ray(const st_scene *s, st_u32 key)
{
    st_ray r = {{0}, INFINITY, {0}, 0.0f};
    for (int a = 0; a < 3; a++) {
        float t = st_rng_unit(key, (st_u32)a);
        r.o[a] = s->bounds_min[a] + t * (s->bounds_max[a] - s->bounds_min[a]);
    }
    float z = 1.0f - 2.0f * st_rng_unit(key, 3u);
    float phi = 6.28318530717958647692f * st_rng_unit(key, 4u);
    float rad = sqrtf(fmaxf(0.0f, 1.0f - z * z));
    r.d[0] = rad * cosf(phi);
    r.d[1] = rad * sinf(phi);
    r.d[2] = z;
    return r;
}

st_status st_trace_bench_rays(const st_scene *scene, const st_render_options *o, int set,
                              st_u64 first, size_t n, st_ray *out, st_error *err)
{
    if (set < 0 || set >= ST_RAYS_COUNT)
        return st_fail(err, ST_ERR_USAGE, "ray set %d: expected camera or random", set);
    st_scene_camera view;
    if (st_render_view_camera(scene, o, &view, err) != ST_OK)
        return err->status;
    st_camera cam = st_render_camera(&view, o->width, o->height);
    for (size_t i = 0; i < n; i++) {
        st_u32 key = ray_key(o->seed, set, first + i);
        out[i] = set == ST_RAYS_RANDOM
                     ? random_ray(scene, key)
                     : camera_ray(&cam, o, st_rng_unit(key, 0u) * (float)o->width,
                                  st_rng_unit(key, 1u) * (float)o->height);
    }
    return ST_OK;
}

/* One wave: rays [first, first + n) uploaded, traced (timed), hits counted. */
static st_status trace_wave(st_renderer *r, const st_render_options *o, int set, st_u64 first,
                            size_t n, st_wave *w, st_ray *rays, st_hit *hits,
                            st_trace_bench_result *res, st_error *err)
{
    st_params p;
    memset(&p, 0, sizeof p);
    p.item_count = (st_u32)n;
    int packets = o->packet_path == ST_PACKET_ALL;
    p.ordered = !packets && st_plan_orders(r) == ST_ORDER_ON;
    cl_kernel k = packets ? r->kernel[ST_K_TRACE_PACKET] : r->kernel[ST_K_TRACE];
    if (st_trace_bench_rays(r->scene, o, set, first, n, rays, err) ||
        st_device_buffer_write(r->dev, w->b[ST_WAVE_ray], n * sizeof *rays, rays, err) ||
        st_wave_set_params(k, &p, err) || st_device_finish(r->dev, err))
        return err->status;
    size_t items = packets ? st_render_lane_items(r->dev, n) : n; /* a packet a work-item */
    double t0 = st_render_now();
    if ((p.ordered && st_render_order(r, &p, n, o->local_size, err)) ||
        st_device_launch(r->dev, k, items, o->local_size, err) ||
        st_device_finish(r->dev, err))
        return err->status;
    res->seconds += st_render_now() - t0;
    res->sorted = (int)p.ordered;
    if (st_device_buffer_read(r->dev, w->b[ST_WAVE_hit], n * sizeof *hits, hits, err))
        return err->status;
    for (size_t i = 0; i < n; i++)
        res->hits += hits[i].prim != ST_NO_HIT;
    res->rays += n;
    return ST_OK;
}

st_status st_trace_bench(st_renderer *r, const st_render_options *o, int set, st_u64 count,
                         st_trace_bench_result *out, st_error *err)
{
    memset(out, 0, sizeof *out);
    size_t wave = o->wave ? o->wave : st_render_default_wave(r->dev, 1, 0);
    if (count < wave)
        wave = count ? (size_t)count : 1;
    st_wave w;
    memset(&w, 0, sizeof w);
    st_ray *rays = malloc(wave * sizeof *rays);
    st_hit *hits = malloc(wave * sizeof *hits);
    st_params p;
    memset(&p, 0, sizeof p);
    st_shading sh;
    memset(&sh, 0, sizeof sh);
    st_status rc = ST_OK;
    if (!rays || !hits)
        rc = st_fail(err, ST_ERR_NOMEM, "out of memory for %zu bench rays", wave);
    /* every path alive (depth 0): trace_rays skips dead ones */
    if (!rc && (st_wave_create(r->dev, wave, 1, 0, st_plan_orders(r) == ST_ORDER_ON, &w, err) ||
                st_device_buffer_zero(r->dev, w.b[ST_WAVE_path], st_wave_bytes(&w, ST_WAVE_path), err) ||
                st_wave_bind_stage(r->kernel[ST_K_TRACE], &p, &sh, r->scene_buf, &w, err) ||
                st_wave_bind_stage(r->kernel[ST_K_TRACE_PACKET], &p, &sh, r->scene_buf, &w, err)))
        rc = err->status;
    for (int k = ST_K_ORDER_BOUNDS; k <= ST_K_ORDER_SCATTER_HIGH && rc == ST_OK; k++)
        rc = st_wave_bind_stage(r->kernel[k], &p, &sh, r->scene_buf, &w, err);
    /* PoCL compiles a kernel at its first launch: one untimed wave first */
    st_trace_bench_result warm = {0};
    if (rc == ST_OK)
        rc = trace_wave(r, o, set, 0, wave, &w, rays, hits, &warm, err);
    for (st_u64 first = 0; rc == ST_OK && first < count; first += wave) {
        size_t n = count - first < wave ? (size_t)(count - first) : wave;
        rc = trace_wave(r, o, set, first, n, &w, rays, hits, out, err);
    }
    st_wave_destroy(&w);
    free(rays);
    free(hits);
    return rc;
}

static int by_seconds(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double st_trace_bench_median(double *t, int n)
{
    qsort(t, (size_t)n, sizeof *t, by_seconds);
    return n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
}

st_status st_trace_bench_build(st_renderer *r, double *seconds, st_error *err)
{
    static const float one[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const st_scene *s = r->scene;
    unsigned threads = st_renderer_bvh_threads(st_device_get_info(r->dev), s->tri_count);
    st_bvh *bvh = NULL;
    if (st_bvh_build_threads(one, 1, threads, &bvh, err) != ST_OK)
        return err->status;
    st_bvh_destroy(bvh);
    double t[ST_TRACE_BENCH_BUILDS];
    for (int k = 0; k < ST_TRACE_BENCH_BUILDS; k++) {
        double t0 = st_render_now();
        if (st_bvh_build_threads(s->positions, s->tri_count, threads, &bvh, err) != ST_OK)
            return err->status;
        st_bvh_set_sides(bvh, s->tri_material, s->materials);
        t[k] = st_render_now() - t0;
        st_bvh_destroy(bvh);
    }
    *seconds = st_trace_bench_median(t, ST_TRACE_BENCH_BUILDS);
    return ST_OK;
}

/* Launches k over the n rays of wave w (ceil(n / lanes) work-items for a
 * packet kernel) with every path alive, and waits. */
static st_status launch_alone(st_renderer *r, const st_render_options *o, cl_kernel k, int packets,
                              size_t n, st_wave *w, st_error *err)
{
    st_params p;
    st_shading sh;
    memset(&p, 0, sizeof p);
    memset(&sh, 0, sizeof sh);
    p.item_count = (st_u32)n;
    p.ray_eps = r->ray_eps;
    size_t items = packets ? st_render_lane_items(r->dev, n) : n;
    if (st_device_buffer_zero(r->dev, w->b[ST_WAVE_path], st_wave_bytes(w, ST_WAVE_path), err) ||
        st_wave_bind_stage(k, &p, &sh, r->scene_buf, w, err) ||
        st_device_launch(r->dev, k, items, o->local_size, err))
        return err->status;
    return st_device_finish(r->dev, err);
}

st_status st_trace_closest(st_renderer *r, const st_render_options *o, int packets,
                           const st_ray *rays, size_t n, st_hit *hits, st_error *err)
{
    st_wave w;
    memset(&w, 0, sizeof w);
    st_status rc = st_wave_create(r->dev, n, 1, 0, 0, &w, err);
    if (!rc)
        rc = st_device_buffer_write(r->dev, w.b[ST_WAVE_ray], n * sizeof *rays, rays, err);
    if (!rc)
        rc = launch_alone(r, o, packets ? r->kernel[ST_K_TRACE_PACKET] : r->kernel[ST_K_TRACE], packets, n, &w,
                          err);
    if (!rc)
        rc = st_device_buffer_read(r->dev, w.b[ST_WAVE_hit], n * sizeof *hits, hits, err);
    st_wave_destroy(&w);
    return rc;
}

/* Shadow rays of contribution (1, 1, 1): radiance 1 clear, 0 blocked, and
 * shadow_rays 1 where traced. */
st_status st_trace_shadow(st_renderer *r, const st_render_options *o, int packets,
                          const st_ray *rays, size_t n, int *blocked, st_error *err)
{
    st_wave w;
    memset(&w, 0, sizeof w);
    st_shadow *s = calloc(n ? n : 1, sizeof *s);
    st_path *path = malloc((n ? n : 1) * sizeof *path);
    st_status rc = s && path ? ST_OK : st_fail(err, ST_ERR_NOMEM, "out of memory for %zu rays", n);
    for (size_t i = 0; !rc && i < n; i++) {
        s[i].ray = rays[i];
        s[i].contribution[0] = s[i].contribution[1] = s[i].contribution[2] = 1.0f;
    }
    if (!rc)
        rc = st_wave_create(r->dev, n, 1, 0, 0, &w, err);
    if (!rc)
        rc = st_device_buffer_write(r->dev, w.b[ST_WAVE_shadow], n * sizeof *s, s, err);
    if (!rc)
        rc = launch_alone(r, o, packets ? r->kernel[ST_K_SHADOW_PACKET] : r->kernel[ST_K_SHADOW], packets, n,
                          &w, err);
    if (!rc)
        rc = st_device_buffer_read(r->dev, w.b[ST_WAVE_path], n * sizeof *path, path, err);
    for (size_t i = 0; !rc && i < n; i++)
        blocked[i] = path[i].shadow_rays == 0u ? -1 : path[i].radiance[0] == 0.0f;
    st_wave_destroy(&w);
    free(s);
    free(path);
    return rc;
}
