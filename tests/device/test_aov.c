/* test_aov.c — the AOV renders (st_render_options.aov; ST_AOV_* in
 * st_shared.h): what the camera ray meets first, filtered as the image is.
 *  - tests/scenes/aov_plane.gltf, a Lambertian plane of base colour
 *    (0.2, 0.5, 0.8) at z = -1.5 filling an orthographic view from z = 2
 *    (half height 0.4), under Mitchell's filter, whose negative lobes must
 *    not bend a constant: albedo (0.2, 0.5, 0.8), normal (0, 0, 1), depth
 *    3.5 and position z -1.5 in every pixel, x and y within a tenth of a
 *    pixel of the pixel's centre on the plane;
 *  - tests/scenes/aov_sphere.gltf, a unit sphere about c = (0.5, -0.25, -1)
 *    whose vertices lie at c + their normal, so that at every hit the
 *    interpolated normal, normalised, is (P - c) / |P - c|: inside the disc
 *    the normal AOV equals that of the position AOV (to the second-order
 *    difference of averaging over a pixel), the depth AOV |P - eye|, and
 *    pixels that see nothing hold 0;
 *  - split renders (sample ranges) whose raw sums add, resolved by
 *    st_render_resolve with the AOV, equal the whole AOV render bit for bit;
 *  - a cut-out is seen through. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "device_fixture.h"
#include "st_render.h"

#define N 16

static st_image render_aov(const char *scene, st_u32 aov, const st_render_options *base,
                           st_i64 **sums)
{
    st_scene *s = fixture_scene(scene);
    st_render_options o = *base;
    o.aov = aov;
    st_error err = {0};
    st_renderer *r = NULL;
    st_image img = {0};
    if (st_renderer_create(dev, s, &r, &err) || st_render(r, &o, &img, sums, NULL, NULL, NULL, &err))
        fail_msg("render aov %u: %s", aov, err.msg);
    st_renderer_destroy(r);
    st_scene_destroy(s);
    return img;
}

static const float *px(const st_image *img, int x, int y)
{
    return img->data + ((size_t)y * img->width + x) * img->channels;
}

static void plane_gives_its_albedo_normal_depth_position(void **state)
{
    (void)state;
    st_render_options o = st_render_defaults(); /* mitchell: negative lobes */
    o.width = o.height = N;
    o.spp = 64;
    assert_int_equal(o.filter.kind, ST_FILTER_MITCHELL);
    const char *plane = "tests/scenes/aov_plane.gltf";
    st_image albedo = render_aov(plane, ST_AOV_ALBEDO, &o, NULL);
    st_image normal = render_aov(plane, ST_AOV_NORMAL, &o, NULL);
    st_image depth = render_aov(plane, ST_AOV_DEPTH, &o, NULL);
    st_image pos = render_aov(plane, ST_AOV_POSITION, &o, NULL);
    const double pixel = 0.8 / N; /* the view's height 2 ymag over N pixels */
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            /* a constant, weighted and divided by its weights: exact to the fixed point's 2^-24 */
            const double tol = 1e-5;
            assert_float_equal(px(&albedo, x, y)[0], 0.2, tol);
            assert_float_equal(px(&albedo, x, y)[1], 0.5, tol);
            assert_float_equal(px(&albedo, x, y)[2], 0.8, tol);
            assert_float_equal(px(&normal, x, y)[0], 0.0, tol);
            assert_float_equal(px(&normal, x, y)[1], 0.0, tol);
            assert_float_equal(px(&normal, x, y)[2], 1.0, tol);
            assert_float_equal(px(&depth, x, y)[0], 3.5, 4.0 * tol);
            assert_float_equal(px(&pos, x, y)[2], -1.5, 2.0 * tol);
            double cx = -0.4 + pixel * (x + 0.5), cy = 0.4 - pixel * (y + 0.5);
            if (fabs(px(&pos, x, y)[0] - cx) > 0.1 * pixel || fabs(px(&pos, x, y)[1] - cy) > 0.1 * pixel)
                fail_msg("pixel (%d, %d): position (%g, %g), centre (%g, %g)", x, y,
                         px(&pos, x, y)[0], px(&pos, x, y)[1], cx, cy);
        }
    st_image_free(&albedo);
    st_image_free(&normal);
    st_image_free(&depth);
    st_image_free(&pos);
}

static void sphere_normals_point_away_from_its_centre(void **state)
{
    (void)state;
    enum { W = 48 };
    st_render_options o = st_render_defaults();
    o.width = o.height = W;
    o.spp = 16;
    o.filter = st_filter_default(ST_FILTER_BOX);
    const char *sphere = "tests/scenes/aov_sphere.gltf";
    st_image normal = render_aov(sphere, ST_AOV_NORMAL, &o, NULL);
    st_image depth = render_aov(sphere, ST_AOV_DEPTH, &o, NULL);
    st_image pos = render_aov(sphere, ST_AOV_POSITION, &o, NULL);
    const double c[3] = {0.5, -0.25, -1.0}, eye[3] = {0.5, -0.25, 3.0};
    int inside = 0, outside = 0;
    for (int y = 1; y + 1 < W; y++)
        for (int x = 1; x + 1 < W; x++) {
            int all = 1, none = 1; /* the 3 x 3 pixels about it all see the sphere, or none */
            for (int j = -1; j <= 1; j++)
                for (int i = -1; i <= 1; i++) {
                    all &= px(&depth, x + i, y + j)[0] > 0.0f;
                    none &= px(&depth, x + i, y + j)[0] == 0.0f;
                }
            const float *n = px(&normal, x, y), *p = px(&pos, x, y);
            if (none) {
                outside++;
                for (int k = 0; k < 3; k++)
                    assert_true(n[k] == 0.0f && p[k] == 0.0f);
                continue;
            }
            if (!all)
                continue;
            inside++;
            double d[3], e[3], dl = 0.0, el = 0.0;
            for (int k = 0; k < 3; k++) {
                d[k] = p[k] - c[k];
                e[k] = p[k] - eye[k];
                dl += d[k] * d[k];
                el += e[k] * e[k];
            }
            for (int k = 0; k < 3; k++)
                if (fabs(n[k] - d[k] / sqrt(dl)) > 2e-3)
                    fail_msg("pixel (%d, %d): normal (%g, %g, %g), (P - c) / |P - c| (%g, %g, %g)",
                             x, y, n[0], n[1], n[2], d[0] / sqrt(dl), d[1] / sqrt(dl),
                             d[2] / sqrt(dl));
            /* the flat triangles lie inside the sphere by at most 1 - cos of half a
             * cell's diagonal (cells of pi/24 by pi/24 at most): 4.3e-3 */
            assert_float_equal(sqrt(dl), 1.0, 5e-3);
            assert_float_equal(px(&depth, x, y)[0], sqrt(el), 1e-3 * sqrt(el));
            assert_true(n[2] > 0.0f); /* facing the camera on +z */
        }
    assert_true(inside > 100 && outside > 100);
    st_image_free(&normal);
    st_image_free(&depth);
    st_image_free(&pos);
}

/* The parts' raw sums of every AOV add up to the whole render's, and resolve
 * to its pixels bit for bit (Lanczos: negative lobes, signed values). */
static void aov_parts_merge_bit_exactly(void **state)
{
    (void)state;
    st_render_options o = st_render_defaults();
    o.width = o.height = N;
    o.spp = 8;
    o.filter = st_filter_default(ST_FILTER_LANCZOS);
    const char *sphere = "tests/scenes/aov_sphere.gltf";
    for (st_u32 aov = 1; aov < ST_AOV_COUNT; aov++) {
        st_image whole = render_aov(sphere, aov, &o, NULL), part, merged;
        st_i64 *total = NULL, *sums = NULL;
        const st_u32 cuts[3] = {0, 3, 8};
        for (int k = 0; k < 2; k++) {
            st_render_options q = o;
            q.sample_begin = cuts[k];
            q.sample_end = cuts[k + 1];
            part = render_aov(sphere, aov, &q, k ? &sums : &total);
            st_image_free(&part);
        }
        size_t n = (size_t)ST_FILM_SUMS * N * N;
        for (size_t i = 0; i < n; i++)
            total[i] = (st_i64)((st_u64)total[i] + (st_u64)sums[i]);
        st_error err = {0};
        if (st_render_resolve(dev, total, N, N, aov, &merged, NULL, &err) != ST_OK)
            fail_msg("resolve: %s", err.msg);
        assert_int_equal(merged.channels, whole.channels);
        assert_memory_equal(merged.data, whole.data, sizeof(float) * whole.channels * N * N);
        int negative = 0; /* the normals and positions keep their signs through the resolve */
        for (size_t i = 0; i < (size_t)whole.channels * N * N; i++)
            negative |= whole.data[i] < 0.0f;
        if (aov == ST_AOV_NORMAL || aov == ST_AOV_POSITION)
            assert_true(negative);
        free(total);
        free(sums);
        st_image_free(&whole);
        st_image_free(&merged);
    }
}

/* Through a cut-out: tests/scenes/cutout.gltf, a red quad whose left half
 * is cut out (alpha 0) over a green one, seen by an orthographic camera. The
 * albedo is green where the camera ray passes through the cut-out (the
 * path's second vertex) and red elsewhere. (A scene with cut-outs never
 * traces its last vertex against the emitters alone: plan.c.) Box filter:
 * each pixel lies in one half. */
static void aov_sees_through_cutouts(void **state)
{
    (void)state;
    st_render_options o = st_render_defaults();
    o.width = o.height = N;
    o.spp = 4;
    o.filter = st_filter_default(ST_FILTER_BOX);
    st_image img = render_aov("tests/scenes/cutout.gltf", ST_AOV_ALBEDO, &o, NULL);
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            const float *a = px(&img, x, y);
            float want_r = x < N / 2 ? 0.0f : 1.0f;
            if (!(fabsf(a[0] - want_r) < 1e-5f && fabsf(a[1] - (1.0f - want_r)) < 1e-5f &&
                  fabsf(a[2]) < 1e-5f))
                fail_msg("pixel (%d, %d): albedo (%g, %g, %g)", x, y, a[0], a[1], a[2]);
        }
    st_image_free(&img);
}

/* An adaptive render's samples follow its radiance: refused with an AOV. */
static void aov_refuses_adaptive(void **state)
{
    (void)state;
    st_render_options o = st_render_defaults();
    o.adaptive = 1;
    o.sampler = ST_SAMPLER_RANDOM;
    o.aov = ST_AOV_ALBEDO;
    st_error err = {0};
    assert_int_equal(st_render_check(&o, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "aov albedo"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(plane_gives_its_albedo_normal_depth_position),
        cmocka_unit_test(sphere_normals_point_away_from_its_centre),
        cmocka_unit_test(aov_parts_merge_bit_exactly),
        cmocka_unit_test(aov_sees_through_cutouts),
        cmocka_unit_test(aov_refuses_adaptive),
    };
    return cmocka_run_group_tests(tests, device_setup, device_teardown);
}
