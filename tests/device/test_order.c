/* test_order.c — the ray order before a trace (order.cl): on the device, the
 * keys of a wave's positions are order.h's keys, at width 1 on the host, in
 * the frame of the bounds of the first ST_ORDER_SAMPLE rays of each block
 * (paths alive, rays finite), a dead path's key marked, `order` lists the
 * positions' items in the stable sort of those keys (a dead path's
 * marked) and `order_ray` the live ones' rays; over every item of a wave
 * and over a list of live paths, several blocks and a ragged last one. A
 * lane that keys another ray, a sample or a bound the host does not take,
 * a mark on the wrong path, or a scatter that loses, repeats or reorders
 * an item fails it. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "order.h"
#include "render_int.h"
#include "st_trace_bench.h"
#include "device_fixture.h"

#define ITEMS (3u * ST_ORDER_BLOCK + 1234u)

/* The bounds order_bounds gathers over positions [0, n) of list (NULL:
 * the items themselves). */
static void host_bounds(const st_ray *rays, const st_path *path, const st_u32 *list, st_u32 n,
                        st_u32 b[ST_ORDER_BOUNDS])
{
    memset(b, 0, ST_ORDER_BOUNDS * sizeof *b);
    for (st_u32 first = 0; first < n; first += ST_ORDER_BLOCK) {
        st_u32 end = first + ST_ORDER_SAMPLE < n ? first + ST_ORDER_SAMPLE : n;
        for (st_u32 g = first; g < end; g++) {
            st_u32 i = list ? list[g] : g;
            st_lv3 d = {rays[i].d[0], rays[i].d[1], rays[i].d[2]};
            float v[5] = {rays[i].o[0], rays[i].o[1], rays[i].o[2], 0.0f, 0.0f};
            st_order_octahedral(d, &v[3], &v[4]);
            if (path[i].depth == ST_PATH_DEAD || !isfinite(v[0] + v[1] + v[2] + v[3] + v[4]))
                continue;
            for (st_u32 c = 0; c < 5; c++) {
                st_u32 at = c < 3 ? c : 3 + c, neg = c < 3 ? at + 3 : at + 2;
                st_u32 hi = st_order_monotone(v[c]), lo = st_order_monotone(-v[c]);
                b[at] = hi > b[at] ? hi : b[at];
                b[neg] = lo > b[neg] ? lo : b[neg];
            }
        }
    }
}

/* Sorts rays (items 0 .. ITEMS - 1; paths dead where `dead`) on the device
 * over positions [0, n) of list (NULL: every item, n = ITEMS) and checks
 * keys and order against the host's. */
static void check_order(st_renderer *r, const st_ray *rays, const st_u32 *list, st_u32 n,
                        int dead)
{
    st_error err = {0};
    st_wave w;
    st_path *path = calloc(ITEMS, sizeof *path);
    st_u32 *key = malloc(n * sizeof *key), *order = malloc(n * sizeof *order);
    st_u32 *want = malloc(n * sizeof *want), count[1u << ST_ORDER_KEY_BITS] = {0};
    st_ray *sorted = malloc(n * sizeof *sorted);
    assert_true(path && key && order && want && sorted);
    for (st_u32 i = 0; dead && i < ITEMS; i += 7)
        path[i].depth = ST_PATH_DEAD;
    st_params p;
    memset(&p, 0, sizeof p);
    p.item_count = ITEMS;
    p.vertex = list ? 1u : 0u;
    p.live_count = list ? n : 0u;
    st_shading sh;
    memset(&sh, 0, sizeof sh);
    assert_int_equal(st_wave_create(dev, ITEMS, 1, 0, 1, &w, &err), ST_OK);
    assert_int_equal(st_device_buffer_write(dev, w.b[ST_WAVE_ray], ITEMS * sizeof *rays, rays,
                                            &err), ST_OK);
    assert_int_equal(st_device_buffer_write(dev, w.b[ST_WAVE_path], ITEMS * sizeof *path, path,
                                            &err), ST_OK);
    if (list)
        assert_int_equal(st_device_buffer_write(dev, w.b[ST_WAVE_live_a], n * sizeof *list, list,
                                                &err), ST_OK);
    for (int k = ST_K_ORDER_BOUNDS; k <= ST_K_ORDER_SCATTER_HIGH; k++)
        assert_int_equal(st_wave_bind_stage(r->kernel[k], &p, &sh, r->scene_buf, &w, &err), ST_OK);
    assert_int_equal(st_render_order(r, &p, n, 0, &err), ST_OK);
    assert_int_equal(st_device_buffer_read(dev, w.b[ST_WAVE_order_key], n * sizeof *key, key,
                                           &err), ST_OK);
    assert_int_equal(st_device_buffer_read(dev, w.b[ST_WAVE_order], n * sizeof *order, order,
                                           &err), ST_OK);
    assert_int_equal(st_device_buffer_read(dev, w.b[ST_WAVE_order_ray], n * sizeof *sorted,
                                           sorted, &err), ST_OK);
    /* the keys, in the frame of the host's bounds */
    st_u32 b[ST_ORDER_BOUNDS];
    host_bounds(rays, path, list, n, b);
    st_order_frame f = st_order_frame_of(b);
    for (st_u32 g = 0; g < n; g++) {
        st_u32 i = list ? list[g] : g;
        const st_ray *ray = &rays[i];
        st_lv3 o = {ray->o[0], ray->o[1], ray->o[2]}, d = {ray->d[0], ray->d[1], ray->d[2]};
        st_u32 k = (st_u32)st_order_key(&f, o, d);
        st_u32 mark = path[i].depth == ST_PATH_DEAD ? ST_ORDER_DEAD_KEY : 0u;
        if (key[g] != (k | mark))
            fail_msg("position %u: device key %#x, host %#x", g, key[g], k | mark);
        count[k]++;
    }
    /* the stable sort: each key's positions in their order */
    st_u32 start = 0;
    for (st_u32 k = 0; k < 1u << ST_ORDER_KEY_BITS; k++) {
        st_u32 c = count[k];
        count[k] = start;
        start += c;
    }
    st_u32 dead_seen = 0;
    for (st_u32 g = 0; g < n; g++) {
        st_u32 i = list ? list[g] : g;
        want[count[key[g] & (ST_ORDER_DEAD_KEY - 1u)]++] =
            path[i].depth == ST_PATH_DEAD ? i | ST_ORDER_DEAD : i;
    }
    assert_memory_equal(order, want, n * sizeof *want);
    for (st_u32 j = 0; j < n; j++) /* and each live item's ray beside it */
        if (order[j] & ST_ORDER_DEAD)
            dead_seen++;
        else
            assert_memory_equal(&sorted[j], &rays[order[j]], sizeof *sorted);
    assert_true(dead ? dead_seen > 0 : dead_seen == 0);
    /* and the frame is not the empty one: the keys spread */
    assert_true(key[0] != key[n / 2] || key[0] != key[n - 1]);
    st_wave_destroy(&w);
    free(path);
    free(key);
    free(order);
    free(want);
    free(sorted);
}

static void order_is_the_stable_sort_of_the_keys(void **state)
{
    (void)state;
    st_scene *s = fixture_scene("cornell-box");
    st_renderer *r = NULL;
    st_error err = {0};
    assert_int_equal(st_renderer_create(dev, s, &r, &err), ST_OK);
    st_render_options o = st_render_defaults();
    st_ray *rays = malloc(ITEMS * sizeof *rays);
    st_u32 *list = malloc(ITEMS * sizeof *list), n = 0;
    assert_true(rays && list);
    for (st_u32 i = ITEMS; i-- > 0;) /* a list of every third item, backwards */
        if (i % 3 == 1)
            list[n++] = i;
    for (int set = 0; set < ST_RAYS_COUNT; set++) {
        assert_int_equal(st_trace_bench_rays(s, &o, set, 0, ITEMS, rays, &err), ST_OK);
        check_order(r, rays, NULL, ITEMS, 0);
        check_order(r, rays, NULL, ITEMS, 1);
        check_order(r, rays, list, n, 1);
    }
    free(rays);
    free(list);
    st_renderer_destroy(r);
    st_scene_destroy(s);
}

/* The keys' definitions at width 1: the octahedral map's square and its
 * folds, the floats' order kept by st_order_monotone and undone by
 * st_order_float, the cells' edges. */
static void keys_follow_their_definitions(void **state)
{
    (void)state;
    static const float dirs[][3] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0},
                                    {1, 1, 1}, {1, -2, -3}, {-2, 1, -1}};
    static const float want[][2] = {{0, 0}, {1, 1}, {1, 0}, {-1, 0}, {0, 1},
                                    {1.0f / 3, 1.0f / 3}, {2.0f / 3, -5.0f / 6}, {-0.75f, 0.5f}};
    for (size_t k = 0; k < sizeof dirs / sizeof dirs[0]; k++) {
        st_lv3 d = {dirs[k][0], dirs[k][1], dirs[k][2]};
        float x, y;
        st_order_octahedral(d, &x, &y);
        assert_true(fabsf(x - want[k][0]) < 1e-6f && fabsf(y - want[k][1]) < 1e-6f);
    }
    static const float f[] = {-INFINITY, -3.5f, -1e-30f, -0.0f, 0.0f, 1e-30f, 2.0f, INFINITY};
    for (size_t k = 0; k + 1 < sizeof f / sizeof f[0]; k++) {
        assert_true(st_order_monotone(f[k]) < st_order_monotone(f[k + 1]));
        assert_true(st_order_monotone(f[k]) > 0u);
        assert_true(st_order_float(st_order_monotone(f[k])) == f[k]);
    }
    st_u32 b[ST_ORDER_BOUNDS] = {0};
    b[0] = st_order_monotone(4.0f); /* origin x in [-4, 4]: 4 cells of 2 */
    b[3] = st_order_monotone(4.0f);
    st_order_frame fr = st_order_frame_of(b);
    assert_true(fr.scale[1] == 0.0f && fr.scale[4] == 0.0f); /* nothing gathered */
    assert_true(fr.bits[0] == ST_ORDER_ORIGIN_BITS && fr.bits[3] == ST_ORDER_DIR_BITS);
    assert_int_equal(st_order_cell(&fr, 0, -9.0f), 0);
    assert_int_equal(st_order_cell(&fr, 0, -2.01f), 0);
    assert_int_equal(st_order_cell(&fr, 0, -2.0f), 1);
    assert_int_equal(st_order_cell(&fr, 0, 3.99f), 3);
    assert_int_equal(st_order_cell(&fr, 0, 9.0f), 3);
    assert_int_equal(st_order_cell(&fr, 0, NAN), 0);
    b[0] = b[3] = st_order_monotone(0.0f); /* origins one point: every bit to directions */
    b[6] = b[8] = st_order_monotone(1.0f);
    fr = st_order_frame_of(b);
    assert_true(fr.bits[0] == 0 && fr.bits[2] == 0 && fr.bits[3] == ST_ORDER_KEY_BITS / 2);
    st_lv3 o = {0.0f, 0.0f, 0.0f}, d = {1.0f, 0.0f, 0.0f}; /* x = 1: the last cell */
    assert_int_equal(st_order_key(&fr, o, d), 0xaaaa);     /* x's bits above y's, 8 each */
    assert_int_equal(st_order_interleave2(3, 0, 2), 10);  /* 0b1010 */
    assert_int_equal(st_order_interleave3(0, 1, 0, 2), 2); /* a's bit above b's above c's */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(keys_follow_their_definitions),
        cmocka_unit_test(order_is_the_stable_sort_of_the_keys),
    };
    return cmocka_run_group_tests(tests, device_setup, device_teardown);
}
