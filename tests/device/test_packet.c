/* test_packet.c — packets of ST_W rays per work-item (kernels/geom/packet.h), at
 * every lane width the kernels build for (1, 4, 8, 16): every
 * lane's closest hit is the single-ray kernel's bit for bit (prim, t, u, v)
 * and every shadow ray is blocked exactly where the single-ray kernel says,
 * on coherent rays (neighbouring directions from one origin), random rays,
 * rays that miss, rays cut short by tmax (at the hit itself, half way, and
 * no ray at all for shadows), ragged tails (counts that are not multiples of
 * the width) and any work-group size; both agree with a brute-force loop on
 * the host. Renders with packets at every width give the same film as the
 * default width's renders without. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "st_bvh.h"
#include "st_scene.h"
#include "st_trace_bench.h"
#include "trace.h"
#include "device_fixture.h"

#define N_RAYS 12003 /* 1500 packets and a tail of 3 */

/* The rays of one kind: 0 coherent (packets of 8 directions within about
 * 0.01 rad of a random camera ray, as neighbouring pixels are), 1 random,
 * 2 camera rays turned round (most leave the scene), 3 random rays whose
 * tmax is cut (cut_tmax). */
static st_ray *make_rays(const st_scene *s, int kind, size_t n)
{
    st_render_options o = st_render_defaults();
    st_error err = {0};
    st_ray *r = malloc(n * sizeof *r);
    assert_non_null(r);
    int set = kind == 0 || kind == 2 ? ST_RAYS_CAMERA : ST_RAYS_RANDOM;
    if (st_trace_bench_rays(s, &o, set, 0, n, r, &err) != ST_OK)
        fail_msg("rays: %s", err.msg);
    for (size_t i = 0; i < n; i++) {
        if (kind == 0 && i % 8) {
            float k = 0.01f * (float)(i % 8);
            st_ray b = r[i - i % 8];
            float d[3] = {b.d[0] + k * b.d[1], b.d[1] - k * b.d[0] + 0.5f * k * b.d[2], b.d[2]};
            float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            for (int a = 0; a < 3; a++) {
                r[i].o[a] = b.o[a];
                r[i].d[a] = d[a] / len;
            }
        }
        for (int a = 0; kind == 2 && a < 3; a++)
            r[i].d[a] = -r[i].d[a];
    }
    return r;
}

/* The host's bvh for s, culling as the renderer does. */
static st_bvh *host_bvh(const st_scene *s)
{
    st_error err = {0};
    st_bvh *bvh = NULL;
    if (st_bvh_build(s->positions, s->tri_count, &bvh, &err) != ST_OK)
        fail_msg("bvh: %s", err.msg);
    st_bvh_set_sides(bvh, s->tri_material, s->materials);
    return bvh;
}

/* Brute force on the host: every triangle, the closest (or any) hit. */
static st_hit brute_closest(const st_bvh *bvh, const st_ray *w)
{
    st_ray r;
    memcpy(r.o, w->o, sizeof r.o);
    memcpy(r.d, w->d, sizeof r.d);
    r.tmax = w->tmax;
    st_hit h = {w->tmax, 0.0f, 0.0f, ST_NO_HIT};
    for (st_u32 i = 0; i < bvh->tri_count; i++)
        st_intersect_triangle(bvh->tris + i, &r, i, &h);
    return h;
}

/* tmax of hitting rays cut to the single-ray kernel's own hit t (rays 3 k:
 * that hit itself excluded, t < tmax), to half of it (3 k + 1: a miss) or
 * to 1.5 t (3 k + 2: the same hit). */
static void cut_tmax(st_renderer *r, st_ray *w, size_t n)
{
    st_error err = {0};
    st_render_options o = st_render_defaults();
    st_hit *h = malloc(n * sizeof *h);
    assert_int_equal(st_trace_closest(r, &o, 0, w, n, h, &err), ST_OK);
    for (size_t i = 0; i < n; i++)
        if (h[i].prim != ST_NO_HIT)
            w[i].tmax = (i % 3 == 0 ? 1.0f : i % 3 == 1 ? 0.5f : 1.5f) * h[i].t;
    free(h);
}

/* Closest hits: packet == single ray bit for bit, for local sizes 64 and 8
 * and n rays; both agree with brute force (prim; the device may contract
 * to fma, trace.h: at most 1 ray in 1000 may differ there), but for the
 * rays 3 k of an edge set, whose tmax is the device's own hit t, which the
 * host's t may lie on either side of. */
static void check_closest(st_renderer *r, const st_bvh *bvh, const st_ray *w, size_t n,
                          int edge, const char *what)
{
    st_error err = {0};
    st_hit *one = malloc(n * sizeof *one), *pk = malloc(n * sizeof *pk);
    st_render_options o = st_render_defaults();
    assert_int_equal(st_trace_closest(r, &o, 0, w, n, one, &err), ST_OK);
    size_t hits = 0, off = 0;
    for (int ls = 64; ls >= 8; ls /= 8) {
        o.local_size = (st_u32)ls;
        memset(pk, 0xab, n * sizeof *pk);
        assert_int_equal(st_trace_closest(r, &o, 1, w, n, pk, &err), ST_OK);
        for (size_t i = 0; i < n; i++)
            if (memcmp(&one[i], &pk[i], sizeof *pk))
                fail_msg("%s ray %zu: single prim %u t %a, packet prim %u t %a", what, i,
                         one[i].prim, one[i].t, pk[i].prim, pk[i].t);
    }
    for (size_t i = 0; i < n; i++) {
        hits += one[i].prim != ST_NO_HIT;
        if (!(edge && i % 3 == 0))
            off += brute_closest(bvh, &w[i]).prim != one[i].prim;
    }
    if (off > n / 1000)
        fail_msg("%s: %zu of %zu rays differ from brute force", what, off, n);
    printf("# %s: %zu rays, %zu hits, all equal; %zu off brute force\n", what, n, hits, off);
    free(one);
    free(pk);
}

/* Shadow rays: packet == single ray exactly; tmax <= 0 (every 7th ray
 * here) is no ray for either; both agree with brute force's any hit (edge:
 * as for check_closest). */
static void check_shadow(st_renderer *r, const st_bvh *bvh, st_ray *w, size_t n, int edge,
                         const char *what)
{
    st_error err = {0};
    int *one = malloc(n * sizeof *one), *pk = malloc(n * sizeof *pk);
    st_render_options o = st_render_defaults();
    for (size_t i = 0; i < n; i += 7)
        w[i].tmax = i % 2 ? 0.0f : -1.0f;
    assert_int_equal(st_trace_shadow(r, &o, 0, w, n, one, &err), ST_OK);
    assert_int_equal(st_trace_shadow(r, &o, 1, w, n, pk, &err), ST_OK);
    size_t blocked = 0, off = 0;
    for (size_t i = 0; i < n; i++) {
        if (one[i] != pk[i])
            fail_msg("%s shadow ray %zu: single %d, packet %d", what, i, one[i], pk[i]);
        int none = !(w[i].tmax > 0.0f);
        assert_int_equal(one[i], none ? -1 : one[i]);
        assert_true(none || one[i] >= 0);
        blocked += one[i] == 1;
        off += !none && !(edge && i % 3 == 0) && (brute_closest(bvh, &w[i]).prim != ST_NO_HIT) != one[i];
    }
    if (off > n / 1000)
        fail_msg("%s: %zu of %zu shadow rays differ from brute force", what, off, n);
    printf("# %s shadows: %zu rays, %zu blocked, all equal; %zu off brute force\n", what, n,
           blocked, off);
    free(one);
    free(pk);
}

/* The widths the kernels build for, and a device built at each (the
 * fixture's own where its width is the default). */
static const unsigned widths[] = {1, 4, 8, 16};
#define N_WIDTHS 4

static st_device *device_at(unsigned lanes)
{
    if (st_device_get_info(dev)->lanes == lanes)
        return dev;
    st_error err = {0};
    st_device *d = NULL;
    if (st_device_create(NULL, &d, &err) != ST_OK || st_device_set_lanes(d, lanes, &err) != ST_OK ||
        st_device_build(d, NULL, &err) != ST_OK)
        fail_msg("device at %u lanes: %s\n%s", lanes, err.msg, d ? st_device_build_log(d) : "");
    assert_int_equal(st_device_get_info(d)->lanes, lanes);
    return d;
}

static void device_done(st_device *d)
{
    if (d != dev)
        st_device_destroy(d);
}

static void packets_equal_single_rays_at(st_device *d)
{
    static const char *const scenes[] = {"cornell-box", "soft-shadows"};
    static const char *const kinds[] = {"coherent", "random", "away", "tmax"};
    static const size_t counts[] = {N_RAYS, 13, 3}; /* 3: a packet of 3 lanes alone */
    for (int sc = 0; sc < 2; sc++) {
        st_scene *s = fixture_scene(scenes[sc]);
        st_bvh *bvh = host_bvh(s);
        st_renderer *r = NULL;
        st_error err = {0};
        assert_int_equal(st_renderer_create(d, s, &r, &err), ST_OK);
        for (int kind = 0; kind < 4; kind++)
            for (int c = 0; c < 3; c++) {
                char what[64];
                snprintf(what, sizeof what, "%u lanes: %s %s %zu", st_device_get_info(d)->lanes,
                         scenes[sc], kinds[kind], counts[c]);
                st_ray *w = make_rays(s, kind, counts[c]);
                if (kind == 3)
                    cut_tmax(r, w, counts[c]);
                check_closest(r, bvh, w, counts[c], kind == 3, what);
                check_shadow(r, bvh, w, counts[c], kind == 3, what);
                free(w);
            }
        st_renderer_destroy(r);
        st_bvh_destroy(bvh);
        st_scene_destroy(s);
    }
}

/* check(d) on a device built at each width. */
static void at_every_width(void (*check)(st_device *d))
{
    for (int k = 0; k < N_WIDTHS; k++) {
        st_device *d = device_at(widths[k]);
        check(d);
        device_done(d);
    }
}

static void packets_equal_single_rays(void **state)
{
    (void)state;
    at_every_width(packets_equal_single_rays_at);
}

/* Renders with the coherent rays in packets, and with every closest-hit
 * ray in packets, at lane width d's, give the single-ray render's film on
 * the default width bit for bit and the same ray counts: paths and direct
 * light in the Cornell box, a one-sided cut-out scene (whose shadow rays
 * stay single: shadow.h's alpha walk), and a wave size that leaves a ragged
 * tail. */
static void renders_with_packets_equal_without_at(st_device *d)
{
    static const char *const scenes[] = {"cornell-box", "cornell-box", "soft-shadows",
                                         "tests/scenes/shadow_cutout.gltf"};
    for (int c = 0; c < 4; c++) {
        st_scene *s = fixture_scene(scenes[c]);
        st_renderer *r = NULL, *r_one = NULL;
        st_error err = {0};
        assert_int_equal(st_renderer_create(dev, s, &r_one, &err), ST_OK);
        assert_int_equal(st_renderer_create(d, s, &r, &err), ST_OK);
        st_render_options o = st_render_defaults();
        o.width = 36;
        o.height = 28;
        o.spp = 3;
        o.seed = 5;
        o.wave = 1001;
        o.integrator = c == 1 ? ST_INTEGRATOR_DIRECT : ST_INTEGRATOR_PATH;
        st_i64 *sums[3];
        st_render_stats st[3];
        for (int k = 0; k < 3; k++) {
            static const int paths[] = {ST_PACKET_NONE, ST_PACKET_COHERENT, ST_PACKET_ALL};
            o.packet_path = paths[k];
            st_image img = {0};
            memset(&st[k], 0, sizeof st[k]);
            if (st_render(k ? r : r_one, &o, &img, &sums[k], &st[k], NULL, NULL, &err) != ST_OK)
                fail_msg("render %s: %s", scenes[c], err.msg);
            st_image_free(&img);
            free(st[k].spp_map);
        }
        for (int k = 1; k < 3; k++) {
            assert_memory_equal(sums[0], sums[k], (size_t)o.width * o.height * 4 * sizeof(st_i64));
            assert_true(st[0].rays == st[k].rays && st[0].shadow_rays == st[k].shadow_rays);
        }
        assert_true(st[0].shadow_rays > 0);
        for (int k = 0; k < 3; k++)
            free(sums[k]);
        st_renderer_destroy(r);
        st_renderer_destroy(r_one);
        st_scene_destroy(s);
    }
}

static void renders_with_packets_equal_without(void **state)
{
    (void)state;
    at_every_width(renders_with_packets_equal_without_at);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(packets_equal_single_rays),
        cmocka_unit_test(renders_with_packets_equal_without),
    };
    return cmocka_run_group_tests(tests, device_setup, device_teardown);
}
