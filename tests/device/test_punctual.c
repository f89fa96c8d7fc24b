/* test_punctual.c — KHR_lights_punctual: the import of point, spot and
 * directional lights (tests/scenes/punctual.gltf), the irradiance each
 * gives a Lambertian plane against its definition, and next-event
 * estimation's choice among lights by power.
 *
 * The scene: the quad z = 0 (normal +Z), grey Lambert (base colour 0.5,
 * specularFactor 0), seen head-on by an orthographic camera (ymag 0.4) from
 * +Z; a point light (colour (1, 0.5, 0.25), intensity 0.2) at (0.1, 0,
 * 0.5); a spot (intensity 0.3, cones 0.3 and 0.6 rad) at (0, 0, 0.5)
 * shining down -Z; a directional light (colour (0.5, 1, 1), intensity 1.5)
 * whose node turns -Z by 40 degrees about +X. Each pixel of a direct
 * render with a box filter is the mean over the pixel of albedo / π x E,
 * E = I cos θ / d² (times the spot's falloff t², t = (cos α - cos 0.6) /
 * (cos 0.3 - cos 0.6) clamped to [0, 1], α from the spot's axis) or
 * E cos 40° for the directional light: computed here on a 16 x 16 grid of
 * points in the pixel, with a tolerance of 5 standard errors of the
 * pixel's sampling (the spread of E over it) plus 0.2 %. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "device_fixture.h"
#include "st_envmap.h"
#include "st_lights.h"
#include "st_render.h"
#include "st_scene.h"

#define PI 3.14159265358979323846
#define N 24     /* image width and height */
#define YMAG 0.4 /* the camera's half height */
#define SUN_DEG 40.0

static st_scene *load(void)
{
    st_error err = {0};
    st_scene *s = NULL;
    if (st_scene_load("tests/scenes/punctual.gltf", &s, &err) != ST_OK)
        fail_msg("load: %s", err.msg);
    return s;
}

/* The file's values (above), independent of the importer's arithmetic. */
static void imports_the_files_lights(void **state)
{
    (void)state;
    st_scene *s = load();
    assert_int_equal(s->punctual_count, 3);
    const st_punctual *p = s->punctual;
    assert_int_equal((int)p[0].pos[3], ST_PUNCT_POINT);
    assert_int_equal((int)p[1].pos[3], ST_PUNCT_SPOT);
    assert_int_equal((int)p[2].pos[3], ST_PUNCT_DIRECTIONAL);
    const float want_pos[3] = {0.1f, 0.0f, 0.5f}, want_i[3] = {0.2f, 0.1f, 0.05f};
    for (int k = 0; k < 3; k++) {
        assert_float_equal(p[0].pos[k], want_pos[k], 1e-6);
        assert_float_equal(p[0].intensity[k], want_i[k], 1e-6);
        assert_float_equal(p[1].intensity[k], 0.3f, 1e-6);
    }
    assert_float_equal(p[1].dir[2], -1.0f, 1e-6);
    assert_float_equal(p[1].dir[3], cos(0.6), 1e-6);       /* cos outer */
    assert_float_equal(p[1].intensity[3], cos(0.3), 1e-6); /* cos inner */
    double a = SUN_DEG * PI / 180.0; /* R_x(a) (0, 0, -1) = (0, sin a, -cos a) */
    assert_float_equal(p[2].dir[0], 0.0f, 1e-6);
    assert_float_equal(p[2].dir[1], sin(a), 1e-6);
    assert_float_equal(p[2].dir[2], -cos(a), 1e-6);
    assert_float_equal(p[2].intensity[0], 0.75f, 1e-6);
    assert_float_equal(p[2].intensity[1], 1.5f, 1e-6);
    /* the lights make the scene lit: no white environment by default */
    assert_true(s->emitted_power > 0.0);
    assert_float_equal(s->default_env[0], 0.0f, 0.0);
    st_scene_destroy(s);
}

/* Irradiance (RGB) at (x, y, 0) from light `which` (0 point, 1 spot,
 * 2 directional), from the definitions above. */
static void irradiance(int which, double x, double y, double e[3])
{
    static const double color[3][3] = {{1.0, 0.5, 0.25}, {1.0, 1.0, 1.0}, {0.5, 1.0, 1.0}};
    static const double intensity[3] = {0.2, 0.3, 1.5};
    double v = 0.0;
    if (which == 2) {
        v = cos(SUN_DEG * PI / 180.0);
    } else {
        double lx = which == 0 ? 0.1 : 0.0, h = 0.5;
        double d2 = (x - lx) * (x - lx) + y * y + h * h, cos_t = h / sqrt(d2);
        v = cos_t / d2;
        if (which == 1) { /* the spot's axis is -Z: its angle to the point is θ */
            double t = (cos_t - cos(0.6)) / (cos(0.3) - cos(0.6));
            t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
            v *= t * t;
        }
    }
    for (int c = 0; c < 3; c++)
        e[c] = color[which][c] * intensity[which] * v;
}

/* The pixel's expected value (albedo / π x mean E over it) and the spread
 * of albedo / π x E over the pixel (for the tolerance), channel c. Pixel
 * (i, j): x from -YMAG (left), y from +YMAG (top row). */
static void pixel_expect(unsigned mask, int i, int j, int c, double *mean, double *sd)
{
    const int m = 16;
    double px = 2.0 * YMAG / N, sum = 0.0, sum2 = 0.0;
    for (int a = 0; a < m; a++)
        for (int b = 0; b < m; b++) {
            double x = -YMAG + (i + (a + 0.5) / m) * px, y = YMAG - (j + (b + 0.5) / m) * px;
            double v = 0.0, e[3];
            for (int which = 0; which < 3; which++)
                if (mask & (1u << which)) {
                    irradiance(which, x, y, e);
                    v += 0.5 / PI * e[c];
                }
            sum += v;
            sum2 += v * v;
        }
    *mean = sum / (m * m);
    *sd = sqrt(fmax(0.0, sum2 / (m * m) - *mean * *mean));
}

/* A direct render lit only by the lights in mask (the others removed). */
static st_image render_lights(unsigned mask, st_u32 spp)
{
    st_scene *s = load();
    st_u32 k = 0;
    for (st_u32 i = 0; i < s->punctual_count; i++)
        if (mask & (1u << i))
            s->punctual[k++] = s->punctual[i];
    s->punctual_count = k;
    st_render_options o = st_render_defaults();
    o.env_given = 1;
    o.env[0] = o.env[1] = o.env[2] = 0.0f;
    o.width = o.height = N;
    o.spp = spp;
    o.seed = 11;
    o.sampler = ST_SAMPLER_RANDOM;
    o.filter = st_filter_default(ST_FILTER_BOX);
    o.integrator = ST_INTEGRATOR_DIRECT;
    st_error err = {0};
    st_renderer *r = NULL;
    st_image img = {0};
    if (st_renderer_create(dev, s, &r, &err) ||
        st_render(r, &o, &img, NULL, NULL, NULL, NULL, &err))
        fail_msg("render: %s", err.msg);
    st_renderer_destroy(r);
    st_scene_destroy(s);
    return img;
}

/* Every pixel against its expected value; *inside, *falloff, *outside
 * count the spot's pixels in each part of the cone (mask 2). */
static void check_pixels(unsigned mask, st_u32 spp, const char *what)
{
    st_image img = render_lights(mask, spp);
    int regions[3] = {0, 0, 0};
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            double x = -YMAG + (i + 0.5) * 2.0 * YMAG / N, y = YMAG - (j + 0.5) * 2.0 * YMAG / N;
            double theta = atan(sqrt(x * x + y * y) / 0.5);
            regions[theta < 0.3 ? 0 : theta < 0.6 ? 1 : 2]++;
            for (int c = 0; c < 3; c++) {
                double want, sd;
                pixel_expect(mask, i, j, c, &want, &sd);
                double got = img.data[((size_t)j * N + (size_t)i) * img.channels + (size_t)c];
                double tol = 5.0 * sd / sqrt((double)spp) + 2e-3 * want + 1e-6;
                if (fabs(got - want) > tol)
                    fail_msg("%s: pixel (%d, %d) channel %d: %.6g, want %.6g (+- %.2g)", what, i,
                             j, c, got, want, tol);
            }
        }
    print_message("%s: %d x %d pixels within tolerance (spot regions: %d inside, %d falloff, "
                  "%d outside)\n", what, N, N, regions[0], regions[1], regions[2]);
    assert_true(regions[0] > 0 && regions[1] > 0 && regions[2] > 0);
    st_image_free(&img);
}

static void point_light_irradiance(void **state)
{
    (void)state;
    check_pixels(1u, 64, "point");
}

static void spot_light_irradiance(void **state)
{
    (void)state;
    check_pixels(2u, 64, "spot");
}

static void directional_light_irradiance(void **state)
{
    (void)state;
    check_pixels(4u, 16, "directional");
}

/* All three at once: next-event estimation picks one per sample by power,
 * so each pixel is a noisy estimate; the mean residual over the image must
 * vanish within 5 standard errors (the residuals' own spread). */
static void three_lights_picked_by_power(void **state)
{
    (void)state;
    const st_u32 spp = 256;
    st_image img = render_lights(7u, spp);
    double sum = 0.0, sum2 = 0.0, want_sum = 0.0;
    const int n = N * N;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            double want, sd;
            pixel_expect(7u, i, j, 1, &want, &sd);
            double r = img.data[((size_t)j * N + (size_t)i) * img.channels + 1] - want;
            sum += r;
            sum2 += r * r;
            want_sum += want;
        }
    double mean = sum / n, se = sqrt(fmax(0.0, sum2 / n - mean * mean) / (n - 1));
    print_message("three lights: mean residual %.3g +- %.2g (mean %.4g)\n", mean, se,
                  want_sum / n);
    if (fabs(mean) > 5.0 * se + 1e-6)
        fail_msg("mean residual %.3g, more than 5 standard errors (%.2g)", mean, se);
    st_image_free(&img);
}

/* The selection table against the powers from their definitions: 4π I for
 * a point light, the falloff integrated over the sphere numerically for a
 * spot, E π r² for a directional light; the share against area lights and
 * a uniform environment (4π² r² L, pbrt-v4). */
static void table_picks_by_power(void **state)
{
    (void)state;
    st_punctual l[3];
    memset(l, 0, sizeof l);
    const float ci = (float)cos(0.2), co = (float)cos(0.7);
    for (int c = 0; c < 3; c++) {
        l[0].intensity[c] = (float)(c + 1);   /* mean 2 */
        l[1].intensity[c] = 3.0f;
        l[2].intensity[c] = c == 0 ? 4.0f : 1.0f; /* mean 2 */
    }
    l[0].pos[3] = (float)ST_PUNCT_POINT;
    l[1].pos[3] = (float)ST_PUNCT_SPOT;
    l[1].dir[3] = co;
    l[1].intensity[3] = ci;
    l[2].pos[3] = (float)ST_PUNCT_DIRECTIONAL;
    const double radius = 1.5;
    double spot = 0.0; /* ∫ t(cos)² dω = 2π ∫ t² d cos, midpoint rule */
    const int m = 200000;
    for (int k = 0; k < m; k++) {
        double c = -1.0 + (k + 0.5) * 2.0 / m;
        double t = (c - co) / (ci - co);
        t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
        spot += 2.0 * PI * 3.0 * t * t * 2.0 / m;
    }
    const double power[3] = {4.0 * PI * 2.0, spot, PI * radius * radius * 2.0};
    const double total = power[0] + power[1] + power[2];
    for (int k = 0; k < 3; k++)
        assert_float_equal(st_punctual_power(&l[k], radius), power[k], 1e-4 * power[k]);
    float cdf[3];
    assert_float_equal(st_punctual_cdf(l, 3, radius, cdf), total, 1e-4 * total);
    assert_float_equal(cdf[0], power[0] / total, 1e-5);
    assert_float_equal(cdf[1] - cdf[0], power[1] / total, 1e-5);
    assert_float_equal(cdf[2], 1.0f, 0.0);
    const float env[3] = {0.5f, 0.5f, 0.5f}, none[3] = {0.0f, 0.0f, 0.0f};
    double env_power = 4.0 * PI * PI * radius * radius * 0.5, rest = 7.0 + env_power;
    assert_float_equal(st_env_power(NULL, env, radius), env_power, 1e-9 * env_power);
    assert_float_equal(st_env_power(NULL, none, radius), 0.0, 0.0);
    assert_float_equal(st_punctual_share(total, 7.0, env_power), total / (total + rest), 1e-6);
    assert_float_equal(st_punctual_share(total, 0.0, 0.0), 1.0f, 0.0);
    assert_float_equal(st_punctual_share(0.0, 7.0, env_power), 0.0f, 0.0);
    memset(l, 0, sizeof l); /* lights that emit nothing are never picked */
    st_punctual_cdf(l, 3, radius, cdf);
    assert_float_equal(cdf[2], 0.0f, 0.0);
}

/* The lights belong to the scene's content hash. */
static void lights_change_the_hash(void **state)
{
    (void)state;
    st_scene *s = load();
    st_u32 h = st_scene_content_hash(s);
    float keep = s->punctual[1].intensity[0];
    s->punctual[1].intensity[0] = keep + 1.0f;
    assert_int_not_equal(st_scene_content_hash(s), h);
    s->punctual[1].intensity[0] = keep;
    assert_int_equal(st_scene_content_hash(s), h);
    s->punctual_count = 2;
    assert_int_not_equal(st_scene_content_hash(s), h);
    st_scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest host[] = {
        cmocka_unit_test(imports_the_files_lights),
        cmocka_unit_test(table_picks_by_power),
        cmocka_unit_test(lights_change_the_hash),
    };
    const struct CMUnitTest device[] = {
        cmocka_unit_test(point_light_irradiance),
        cmocka_unit_test(spot_light_irradiance),
        cmocka_unit_test(directional_light_irradiance),
        cmocka_unit_test(three_lights_picked_by_power),
    };
    int failed = cmocka_run_group_tests(host, NULL, NULL);
    return failed | cmocka_run_group_tests(device, device_setup, device_teardown);
}
