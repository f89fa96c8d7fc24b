/* test_trace_bench.c — the trace benchmark's rays and counts: the ray sets
 * are what st_trace_bench.h says (unit directions, origins in the box,
 * uniform on the sphere, camera rays through the image), repeatable; the
 * device's hit count equals the host's st_intersect_wide_closest over the same
 * rays and does not depend on the wave size. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "plan.h"
#include "st_bvh.h"
#include "st_scene.h"
#include "st_trace_bench.h"
#include "trace.h"
#include "device_fixture.h"

#define N_RAYS 20000

static st_ray *make_rays(const st_scene *s, const st_render_options *o, int set, size_t n)
{
    st_error err = {0};
    st_ray *r = malloc(n * sizeof *r);
    assert_non_null(r);
    if (st_trace_bench_rays(s, o, set, 0, n, r, &err) != ST_OK)
        fail_msg("rays: %s", err.msg);
    return r;
}

/* Random rays: |d| = 1 to float rounding, origins inside the box, and the
 * mean direction within 4 standard errors of 0 (each component of a uniform
 * direction has variance 1/3). */
static void random_rays_are_uniform(void **state)
{
    (void)state;
    st_scene *s = fixture_scene("cornell-box");
    st_render_options o = st_render_defaults();
    st_ray *r = make_rays(s, &o, ST_RAYS_RANDOM, N_RAYS);
    double mean[3] = {0, 0, 0};
    for (size_t i = 0; i < N_RAYS; i++) {
        double len2 = 0.0;
        for (int a = 0; a < 3; a++) {
            len2 += (double)r[i].d[a] * r[i].d[a];
            mean[a] += r[i].d[a] / N_RAYS;
            assert_true(r[i].o[a] >= s->bounds_min[a] && r[i].o[a] <= s->bounds_max[a]);
        }
        assert_true(fabs(len2 - 1.0) < 1e-6);
        assert_true(isinf(r[i].tmax));
    }
    for (int a = 0; a < 3; a++)
        assert_true(fabs(mean[a]) < 4.0 * sqrt(1.0 / 3.0 / N_RAYS));
    free(r);
    st_scene_destroy(s);
}

/* Camera rays start at the camera (perspective) and lie inside the field of
 * view: the angle to the forward axis is at most the half diagonal's. */
static void camera_rays_start_at_the_camera(void **state)
{
    (void)state;
    st_scene *s = fixture_scene("cornell-box");
    st_render_options o = st_render_defaults();
    o.width = 64;
    o.height = 32;
    st_scene_camera c;
    st_error err = {0};
    assert_int_equal(st_scene_view_camera(s, -1, &c, &err), ST_OK);
    assert_false(c.orthographic);
    st_ray *r = make_rays(s, &o, ST_RAYS_CAMERA, N_RAYS);
    double th = tan(0.5 * c.yfov), half_diag = sqrt(th * th * (1.0 + 4.0)); /* aspect 2 */
    double min_cos = 1.0 / sqrt(1.0 + half_diag * half_diag);
    for (size_t i = 0; i < N_RAYS; i++) {
        double cosv = 0.0;
        for (int a = 0; a < 3; a++) {
            assert_true(r[i].o[a] == c.origin[a]);
            cosv += (double)r[i].d[a] * c.forward[a];
        }
        assert_true(cosv >= min_cos - 1e-6);
    }
    free(r);
    st_scene_destroy(s);
}

/* The same index gives the same ray, from any first index. */
static void rays_are_a_function_of_the_index(void **state)
{
    (void)state;
    st_scene *s = fixture_scene("cornell-box");
    st_render_options o = st_render_defaults();
    st_error err = {0};
    for (int set = 0; set < ST_RAYS_COUNT; set++) {
        st_ray *all = make_rays(s, &o, set, 100), part[40];
        assert_int_equal(st_trace_bench_rays(s, &o, set, 50, 40, part, &err), ST_OK);
        assert_memory_equal(all + 50, part, sizeof part);
        free(all);
    }
    assert_int_equal(st_trace_bench_rays(s, &o, ST_RAYS_COUNT, 0, 1, NULL, &err), ST_ERR_USAGE);
    st_scene_destroy(s);
}

/* The build's figure is the middle timing, or the mean of the middle two,
 * whatever their order. */
static void build_time_is_the_median(void **state)
{
    (void)state;
    double odd[5] = {9.0, 1.0, 7.0, 3.0, 5.0}, even[4] = {4.0, 8.0, 1.0, 2.0};
    assert_true(st_trace_bench_median(odd, 5) == 5.0);
    assert_true(st_trace_bench_median(even, 4) == 3.0);
    double one = 2.5;
    assert_true(st_trace_bench_median(&one, 1) == 2.5);
}

/* Host count of closest hits over the same rays (trace.h on the host). */
static st_u64 host_hits(const st_scene *s, const st_ray *w, size_t n)
{
    st_error err = {0};
    st_bvh *bvh = NULL;
    if (st_bvh_build(s->positions, s->tri_count, &bvh, &err) != ST_OK)
        fail_msg("bvh: %s", err.msg);
    st_bvh_set_sides(bvh, s->tri_material, s->materials); /* cull as the renderer does */
    st_u64 hits = 0;
    for (size_t i = 0; i < n; i++) {
        st_ray r;
        memcpy(r.o, w[i].o, sizeof r.o);
        memcpy(r.d, w[i].d, sizeof r.d);
        r.tmax = w[i].tmax;
        st_hit h;
        hits += (st_u64)st_intersect_wide_closest(bvh->wide, &r, &h);
    }
    st_bvh_destroy(bvh);
    return hits;
}

/* The device counts what the host counts. The device may contract to fma
 * (trace.h), which can move a ray that grazes an edge or a silhouette to the
 * other side: allowed for at most 1 ray in 2000. The count does not depend
 * on the wave size. */
static void device_hits_match_the_host(void **state)
{
    (void)state;
    static const char *const scenes[] = {"cornell-box", "soft-shadows"};
    for (int k = 0; k < 2; k++) {
        st_scene *s = fixture_scene(scenes[k]);
        st_renderer *r = NULL;
        st_error err = {0};
        assert_int_equal(st_renderer_create(dev, s, &r, &err), ST_OK);
        for (int set = 0; set < ST_RAYS_COUNT; set++) {
            st_render_options o = st_render_defaults();
            st_ray *w = make_rays(s, &o, set, N_RAYS);
            st_u64 host = host_hits(s, w, N_RAYS);
            st_trace_bench_result a, b;
            assert_int_equal(st_trace_bench(r, &o, set, N_RAYS, &a, &err), ST_OK);
            o.wave = 777;
            assert_int_equal(st_trace_bench(r, &o, set, N_RAYS, &b, &err), ST_OK);
            assert_true(a.rays == N_RAYS && b.rays == N_RAYS && a.hits == b.hits);
            double diff = fabs((double)a.hits - (double)host);
            if (diff > N_RAYS / 2000.0)
                fail_msg("%s %s: device %llu hits, host %llu", scenes[k], st_ray_set_names[set],
                         (unsigned long long)a.hits, (unsigned long long)host);
            assert_true(host > N_RAYS / 10 && host < N_RAYS); /* not a trivial scene */
            free(w);
        }
        st_renderer_destroy(r);
        st_scene_destroy(s);
    }
}

/* The rays sorted by ray first (order.cl, forced on) hit what they hit
 * unsorted, in waves of several of the sort's blocks and of part of one;
 * the result says which ran. */
static void sorted_rays_hit_the_same(void **state)
{
    (void)state;
    st_scene *s = fixture_scene("soft-shadows");
    st_renderer *r = NULL;
    st_error err = {0};
    assert_int_equal(st_renderer_create(dev, s, &r, &err), ST_OK);
    st_plan_force force = {0};
    for (int set = 0; set < ST_RAYS_COUNT; set++)
        for (st_u32 wave = 1000; wave <= 20000; wave += 19000) {
            st_render_options o = st_render_defaults();
            o.wave = wave;
            st_trace_bench_result a, b;
            force.order = ST_ORDER_OFF;
            st_renderer_force(r, &force);
            assert_int_equal(st_trace_bench(r, &o, set, N_RAYS, &a, &err), ST_OK);
            force.order = ST_ORDER_ON;
            st_renderer_force(r, &force);
            assert_int_equal(st_trace_bench(r, &o, set, N_RAYS, &b, &err), ST_OK);
            assert_true(!a.sorted && b.sorted);
            assert_true(a.rays == N_RAYS && b.rays == N_RAYS && a.hits == b.hits);
        }
    st_renderer_destroy(r);
    st_scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(random_rays_are_uniform),
        cmocka_unit_test(camera_rays_start_at_the_camera),
        cmocka_unit_test(rays_are_a_function_of_the_index),
        cmocka_unit_test(build_time_is_the_median),
        cmocka_unit_test(device_hits_match_the_host),
        cmocka_unit_test(sorted_rays_hit_the_same),
    };
    return cmocka_run_group_tests(tests, device_setup, device_teardown);
}
