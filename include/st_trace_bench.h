/* st_trace_bench.h — rays alone through the device's closest-hit kernel
 * (trace_rays): the trace benchmark of `strata bench --rays`.
 *
 * Two ray sets, each a pure function of (seed, ray index), so a benchmark is
 * repeatable and a test can trace the same rays on the host:
 *   camera: the primary ray of the view's camera through a uniformly random
 *           point of the width x height image (the generate stage's, camera.h);
 *   random: origin uniform in the scene's bounding box, direction uniform on
 *           the unit sphere. */
#ifndef ST_TRACE_BENCH_H
#define ST_TRACE_BENCH_H

#include "st_render.h"

enum { ST_RAYS_CAMERA, ST_RAYS_RANDOM, ST_RAYS_COUNT };
extern const char *const st_ray_set_names[ST_RAYS_COUNT]; /* "camera", "random" */

/* Rays first .. first + n - 1 of a set, for the scene and the view of o
 * (camera, width, height, seed). tmax is infinite. ST_ERR_USAGE for an
 * unknown set or a camera index the scene does not have. */
st_status st_trace_bench_rays(const st_scene *scene, const st_render_options *o, int set,
                              st_u64 first, size_t n, st_ray *out, st_error *err);

typedef struct st_trace_bench_result {
    st_u64 rays, hits;
    double seconds; /* the trace_rays launches alone: making and uploading rays not counted */
    int sorted;     /* 1: each wave's rays sorted by ray first (the plan's), counted in seconds */
} st_trace_bench_result;

/* Traces count rays of the set through the renderer's trace kernel, in waves
 * of o->wave rays (0: a render's default wave), with o->local_size, after
 * one untimed wave (PoCL compiles a kernel at its first launch). */
st_status st_trace_bench(st_renderer *r, const st_render_options *o, int set, st_u64 count,
                         st_trace_bench_result *out, st_error *err);

/* The timed builds a build's figure is the median of: one build of a
 * small scene takes microseconds, and one timing of it moved by half
 * between runs. */
#define ST_TRACE_BENCH_BUILDS 5

/* The median of the n seconds in t (sorted in place). */
double st_trace_bench_median(double *t, int n);

/* Seconds of the BVH build of r's scene as the renderer makes it (the same
 * threads, the triangles' sides set), timed as tools/bench_embree.c times
 * Embree's: the median of ST_TRACE_BENCH_BUILDS builds after an untimed
 * build of one triangle, so that neither builder is timed with its code
 * cold. The trees are dropped. */
st_status st_trace_bench_build(st_renderer *r, double *seconds, st_error *err);

/* Rays traced alone, in one launch of one kernel, for the tests that
 * compare the single-ray and the packet kernels (kernels/geom/packet.h) with
 * each other and with the host: st_trace_closest gives the closest hits of
 * rays[0 .. n) through trace_rays, or trace_rays_packet when packets;
 * st_trace_shadow whether each ray (o, d, tmax; tmax <= 0: no ray) is
 * blocked through trace_shadow_rays, or trace_shadow_rays_packet:
 * blocked[i] 1 blocked, 0 clear, -1 not traced. Launched with
 * o->local_size. */
st_status st_trace_closest(st_renderer *r, const st_render_options *o, int packets,
                           const st_ray *rays, size_t n, st_hit *hits, st_error *err);
st_status st_trace_shadow(st_renderer *r, const st_render_options *o, int packets,
                          const st_ray *rays, size_t n, int *blocked, st_error *err);

#endif
