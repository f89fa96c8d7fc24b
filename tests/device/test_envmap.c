/* test_envmap.c — environment maps (--env FILE, kernels/integrator/envmap.h,
 * src/render/envmap.c) and next-event estimation's choice among lights by power.
 *
 * On the host, the distribution against its definition: the convention's
 * directions, the rotation, the pdf integrating to 1 over the sphere (Monte
 * Carlo with uniform directions), the sampled texels following f_ij =
 * luminance x sin θ_j / Σ f (chi-square), and importance sampling of a
 * small bright sun estimating the irradiance with a far smaller variance
 * than uniform sampling, both means agreeing with the exact value. Every
 * expected value is computed here from the map's texels and the stated
 * convention (this file's own direction formula), not by the code under
 * test. The errors of reading a map, and its power.
 *
 * On the device, a white Lambertian plane (tests/scenes/textured_quad.gltf,
 * normal +Z, orthographic view) under a map: each pixel is E / π, E = ∫ L
 * cos⁺ dω of the map (with its rotation) by midpoint quadrature over 8 x 8
 * points a texel, for the direct integrator (next-event estimation alone)
 * and the path integrator (MIS with the BSDF samples), within 5 standard
 * errors of the image's mean plus 0.3 % of E / π. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image_write.h>

#include "device_fixture.h"
#include "scratch.h"
#include "st_envmap.h"
#include "st_image.h"
#include "st_lights.h"
#include "st_render.h"
#include "st_scene.h"
#include "envmap.h"

#define PI 3.14159265358979323846

/* The convention, written out independently: u from the left edge, v from
 * the top; u = 1/2 looks along -Z, u = 3/4 along +X, v = 0 is +Y. */
static void dir_of(double u, double v, double d[3])
{
    double phi = 2.0 * PI * (u - 0.5), theta = PI * v;
    d[0] = sin(theta) * sin(phi);
    d[1] = cos(theta);
    d[2] = -sin(theta) * cos(phi);
}

static void uv_of(const double d[3], double *u, double *v)
{
    double phi = atan2(d[0], -d[2]);
    *u = phi / (2.0 * PI) + 0.5;
    *v = acos(fmax(-1.0, fmin(1.0, d[1]))) / PI;
}

/* splitmix64, for the tests' own random numbers */
static uint64_t rng_state;
static double rnd(void)
{
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

static void uniform_sphere(double d[3])
{
    double z = 1.0 - 2.0 * rnd(), r = sqrt(fmax(0.0, 1.0 - z * z)), phi = 2.0 * PI * rnd();
    d[0] = r * cos(phi);
    d[1] = r * sin(phi);
    d[2] = z;
}

static st_envmap *make(const float *rgb, st_u32 w, st_u32 h)
{
    st_envmap *m = NULL;
    st_error err = {0};
    if (st_envmap_make(rgb, w, h, "test map", &m, &err) != ST_OK)
        fail_msg("make: %s", err.msg);
    return m;
}

/* A w x h map of a dim sky (0.05 0.1 0.2 above the horizon, 0.02 below) and
 * a sun: the 2 x 2 texels at (i0, j0) of radiance (2000, 1800, 1500). */
static float *sun_rgb(st_u32 w, st_u32 h, st_u32 i0, st_u32 j0)
{
    float *rgb = malloc(sizeof *rgb * 3 * w * h);
    for (st_u32 j = 0; j < h; j++)
        for (st_u32 i = 0; i < w; i++) {
            float *c = rgb + 3 * (j * w + i);
            int sun = i - i0 < 2u && j - j0 < 2u, up = j < h / 2;
            c[0] = sun ? 2000.0f : up ? 0.05f : 0.02f;
            c[1] = sun ? 1800.0f : up ? 0.1f : 0.02f;
            c[2] = sun ? 1500.0f : up ? 0.2f : 0.02f;
        }
    return rgb;
}

static double lum(const float *c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

/* The map's radiance (channel c) seen along d, nearest texel, by the
 * convention above. */
static double radiance(const st_envmap *m, const double d[3], int c)
{
    double u, v;
    uv_of(d, &u, &v);
    st_u32 i = (st_u32)fmin(u * m->width, m->width - 1), j = (st_u32)fmin(v * m->height, m->height - 1);
    return m->texels[4 * (j * m->width + i) + c];
}

/* ---- host: convention, rotation, distribution --------------------------------------------- */

static void convention_and_rotation(void **state)
{
    (void)state;
    const float uv[4][2] = {{0.5f, 0.5f}, {0.75f, 0.5f}, {0.25f, 0.5f}, {0.5f, 0.0f}};
    const float want[4][3] = {{0, 0, -1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}};
    for (int k = 0; k < 4; k++) {
        float d[3], u, v;
        st_env_direction(uv[k][0], uv[k][1], d);
        for (int a = 0; a < 3; a++)
            assert_float_equal(d[a], want[k][a], 1e-6);
        st_env_coords(d, &u, &v);
        if (k < 3) /* the pole has no u */
            assert_float_equal(u, uv[k][0], 1e-6);
        assert_float_equal(v, uv[k][1], 1e-6);
    }
    rng_state = 1;
    for (int n = 0; n < 1000; n++) { /* coords and direction invert each other */
        double u = rnd(), v = 0.01 + 0.98 * rnd(), dd[3];
        float d[3], fu, fv;
        dir_of(u, v, dd);
        for (int a = 0; a < 3; a++)
            d[a] = (float)dd[a];
        st_env_coords(d, &fu, &fv);
        assert_float_equal(fu, u, 1e-5);
        assert_float_equal(fv, v, 1e-5);
    }
    /* --env-rotate 90: the feature at +Z is seen at +X, -Z's at -X; 30
     * degrees moves a feature's azimuth by 30 degrees, up stays up */
    const float rot90[2] = {0.0f, 1.0f}, z[3] = {0, 0, 1}, mz[3] = {0, 0, -1};
    float out[3], back[3];
    st_env_rotate(rot90, 1, z, out);
    assert_float_equal(out[0], 1.0f, 1e-6);
    assert_float_equal(out[2], 0.0f, 1e-6);
    st_env_rotate(rot90, 1, mz, out);
    assert_float_equal(out[0], -1.0f, 1e-6);
    const float rot30[2] = {(float)cos(PI / 6), (float)sin(PI / 6)};
    float d[3], u0, v0, u1, v1;
    st_env_direction(0.4f, 0.3f, d);
    st_env_rotate(rot30, 1, d, out);
    st_env_coords(d, &u0, &v0);
    st_env_coords(out, &u1, &v1);
    /* u grows from -Z towards +X, so turning from +Z towards +X moves a
     * feature to smaller u (to the left in the image) */
    assert_float_equal(u1 - u0, -30.0 / 360.0, 1e-6);
    assert_float_equal(v1, v0, 1e-6);
    st_env_rotate(rot30, 0, out, back); /* to the map's frame: the inverse */
    for (int a = 0; a < 3; a++)
        assert_float_equal(back[a], d[a], 1e-6);
    st_render_options o = st_render_defaults();
    st_error err = {0};
    o.env_rotate = INFINITY;
    assert_int_equal(st_render_check(&o, &err), ST_ERR_USAGE);
}

/* A 16 x 8 map of random positive radiance and a bright texel. */
static st_envmap *random_map(void)
{
    enum { W = 16, H = 8 };
    float rgb[3 * W * H];
    rng_state = 7;
    for (int k = 0; k < 3 * W * H; k++)
        rgb[k] = (float)(0.2 + rnd());
    rgb[3 * (2 * W + 11) + 1] = 40.0f;
    return make(rgb, W, H);
}

/* ∫ pdf dω = 1: 4π times the mean of the pdf over uniform directions,
 * within 4 standard errors. */
static void pdf_integrates_to_one(void **state)
{
    (void)state;
    st_envmap *m = random_map();
    rng_state = 3;
    const int n = 400000;
    double sum = 0.0, sum2 = 0.0;
    for (int k = 0; k < n; k++) {
        double d[3];
        uniform_sphere(d);
        float fd[3] = {(float)d[0], (float)d[1], (float)d[2]}, u, v;
        st_u32 i, j;
        st_env_coords(fd, &u, &v);
        st_env_texel(m->width, m->height, u, v, &i, &j);
        double x = 4.0 * PI * st_env_solid_angle_pdf(st_env_texel_pdf(m->cdf, m->width, m->height, i, j), v);
        sum += x;
        sum2 += x * x;
    }
    double mean = sum / n, se = sqrt((sum2 / n - mean * mean) / n);
    print_message("∫ pdf dω = %.5f +- %.5f\n", mean, se);
    assert_true(fabs(mean - 1.0) < 4.0 * se);
    st_envmap_free(m);
}

/* Sampled directions land in texel (i, j) with probability f_ij / Σ f
 * (chi-square over the 128 texels, critical value at p = 1e-4 by
 * Wilson-Hilferty), and the returned pdf is that texel's: but for the rare
 * point that float rounding puts on the far edge of its texel, (i + 1 - ε)
 * / w becoming (i + 1) / w, where the lookup finds the neighbour (at most
 * 1 in 10^4 here; the kernel takes the pdf and radiance of the texel its
 * lookup finds, so such a sample stays consistent with a miss there). */
static void samples_follow_the_luminance(void **state)
{
    (void)state;
    st_envmap *m = random_map();
    st_u32 w = m->width, h = m->height;
    double f[128], total = 0.0;
    for (st_u32 j = 0; j < h; j++)
        for (st_u32 i = 0; i < w; i++)
            total += f[j * w + i] = lum(&m->texels[4 * (j * w + i)]) * sin(PI * (j + 0.5) / h);
    long count[128] = {0}, edge = 0;
    const long n = 500000;
    rng_state = 11;
    for (long k = 0; k < n; k++) {
        float u, v, d[3];
        float p = st_env_sample(m->cdf, w, h, (float)rnd(), (float)rnd(), &u, &v);
        st_env_direction(u, v, d);
        double dd[3] = {d[0], d[1], d[2]}, tu, tv;
        uv_of(dd, &tu, &tv);
        st_u32 i = (st_u32)fmin(tu * w, w - 1), j = (st_u32)fmin(tv * h, h - 1);
        count[j * w + i]++;
        edge += fabs(p - f[j * w + i] / total * w * h) > 1e-4 * p;
    }
    print_message("%ld of %ld samples on a texel's far edge\n", edge, n);
    assert_true(edge * 10000 <= n);
    double chi2 = 0.0;
    for (int b = 0; b < 128; b++) {
        double e = n * f[b] / total;
        chi2 += (count[b] - e) * (count[b] - e) / e;
    }
    double dof = 127.0, z = 3.719, crit = dof * pow(1.0 - 2.0 / (9.0 * dof) + z * sqrt(2.0 / (9.0 * dof)), 3.0);
    print_message("chi-square %.1f (critical %.1f, 127 degrees of freedom)\n", chi2, crit);
    assert_true(chi2 < crit);
    st_envmap_free(m);
}

/* The exact irradiance on a plane of normal n from map m (turned by rot
 * degrees): midpoint quadrature over k x k points a texel. */
static double irradiance(const st_envmap *m, const double n[3], double rot, int c, int k)
{
    double a = rot * PI / 180.0, e = 0.0;
    st_u32 w = m->width, h = m->height;
    for (st_u32 j = 0; j < h; j++)
        for (int b = 0; b < k; b++) {
            double v = (j + (b + 0.5) / k) / h, dom = 2.0 * PI * PI * sin(PI * v) / ((double)w * h * k * k);
            for (st_u32 i = 0; i < w; i++)
                for (int q = 0; q < k; q++) {
                    double d[3], r[3];
                    dir_of((i + (q + 0.5) / k) / w, v, d);
                    r[0] = cos(a) * d[0] + sin(a) * d[2]; /* R_y(a): +Z towards +X */
                    r[1] = d[1];
                    r[2] = -sin(a) * d[0] + cos(a) * d[2];
                    double c_n = r[0] * n[0] + r[1] * n[1] + r[2] * n[2];
                    if (c_n > 0.0)
                        e += m->texels[4 * (j * w + i) + c] * c_n * dom;
                }
        }
    return e;
}

/* Irradiance on the plane of normal +Y from a sun map: importance sampling
 * and uniform sampling are both unbiased (within 4 standard errors of the
 * quadrature) and importance sampling's variance is under a tenth of
 * uniform sampling's. */
static void near_sky(double got, double want, double tol)
{
    if (fabs(got - want) > tol)
        fail_msg("sky texel %.5f, want %.5f", got, want);
}

static void importance_sampling_beats_uniform(void **state)
{
    (void)state;
    float *rgb = sun_rgb(64, 32, 40, 9);
    st_envmap *m = make(rgb, 64, 32);
    free(rgb);
    const double up[3] = {0, 1, 0};
    double exact = irradiance(m, up, 0.0, 1, 8);
    const int n = 100000;
    double s[2] = {0, 0}, s2[2] = {0, 0};
    rng_state = 5;
    for (int k = 0; k < n; k++) {
        float u, v, fd[3];
        float p = st_env_sample(m->cdf, m->width, m->height, (float)rnd(), (float)rnd(), &u, &v);
        st_env_direction(u, v, fd);
        double d[3] = {fd[0], fd[1], fd[2]}, pdf = st_env_solid_angle_pdf(p, v);
        double x = pdf > 0.0 ? radiance(m, d, 1) * fmax(d[1], 0.0) / pdf : 0.0;
        uniform_sphere(d);
        double y = radiance(m, d, 1) * fmax(d[1], 0.0) * 4.0 * PI;
        s[0] += x, s2[0] += x * x, s[1] += y, s2[1] += y * y;
    }
    double mean[2], var[2];
    for (int k = 0; k < 2; k++) {
        mean[k] = s[k] / n;
        var[k] = s2[k] / n - mean[k] * mean[k];
        assert_true(fabs(mean[k] - exact) < 4.0 * sqrt(var[k] / n));
    }
    print_message("E = %.4f: importance %.4f (variance %.4g), uniform %.4f (variance %.4g)\n", exact,
                  mean[0], var[0], mean[1], var[1]);
    assert_true(var[0] < 0.1 * var[1]);
    st_envmap_free(m);
}

/* A constant map's integral is 4π L and its power π r² 4π L, as a uniform
 * environment's; the choice between environment and area lights is their
 * share of the power. */
static void power_and_choice(void **state)
{
    (void)state;
    float rgb[3 * 8 * 4];
    for (int k = 0; k < 3 * 8 * 4; k++)
        rgb[k] = k % 3 == 0 ? 0.5f : 2.0f; /* mean over R, G, B: 1.5 */
    st_envmap *m = make(rgb, 8, 4);
    const float env[3] = {0.5f, 2.0f, 2.0f};
    assert_float_equal(m->integral, 4.0 * PI * 1.5, 1e-9 * m->integral);
    assert_float_equal(st_env_power(m, NULL, 2.0), PI * 4.0 * 4.0 * PI * 1.5, 1e-6);
    assert_float_equal(st_env_power(m, NULL, 2.0), st_env_power(NULL, env, 2.0), 1e-6);
    st_envmap_free(m);
    assert_float_equal(st_env_pick(3.0, 1.0, 5), 0.25f, 1e-7);
    assert_float_equal(st_env_pick(3.0, 0.0, 5), 0.0f, 0.0);
    assert_float_equal(st_env_pick(0.0, 1.0, 0), 1.0f, 0.0);
    assert_float_equal(st_env_pick(3.0, 1.0, 0), 1.0f, 0.0); /* no emissive triangle to sample */
    /* with punctual lights: each kind by its power */
    float ps = st_punctual_share(6.0, 3.0, 1.0);
    assert_float_equal(ps, 0.6f, 1e-7);
    assert_float_equal((1.0f - ps) * st_env_pick(3.0, 1.0, 5), 0.1f, 1e-7);
    assert_float_equal((1.0f - ps) * (1.0f - st_env_pick(3.0, 1.0, 5)), 0.3f, 1e-7);
}

/* ---- host: reading and refusing ------------------------------------------------------------ */

static void expect_error(const char *path, st_status status, const char *words)
{
    st_envmap *m = NULL;
    st_error err = {0};
    assert_int_equal(st_envmap_load(path, &m, &err), status);
    assert_null(m);
    assert_non_null(strstr(err.msg, path));
    if (!strstr(err.msg, words))
        fail_msg("'%s' lacks '%s'", err.msg, words);
}

static void reads_exr_and_hdr(void **state)
{
    (void)state;
    enum { W = 6, H = 3 };
    float rgb[3 * W * H];
    for (int k = 0; k < 3 * W * H; k++)
        rgb[k] = 0.25f * (float)(k % 7) + 0.125f;
    char exr[512], hdr[512];
    snprintf(exr, sizeof exr, "%s", scratch_path("map.exr"));
    snprintf(hdr, sizeof hdr, "%s", scratch_path("map.HDR"));
    st_image img;
    st_error err = {0};
    assert_int_equal(st_image_create(&img, W, H, 3, NULL, &err), ST_OK);
    memcpy(img.data, rgb, sizeof rgb);
    assert_int_equal(st_image_save_exr(exr, &img, NULL, 0, &err), ST_OK);
    assert_true(stbi_write_hdr(hdr, W, H, 3, rgb));
    const char *paths[2] = {exr, hdr};
    for (int f = 0; f < 2; f++) {
        st_envmap *m = NULL;
        if (st_envmap_load(paths[f], &m, &err) != ST_OK)
            fail_msg("%s", err.msg);
        assert_int_equal(m->width, W);
        assert_int_equal(m->height, H);
        for (int k = 0; k < W * H; k++)
            for (int c = 0; c < 3; c++) /* RGBE keeps 8 bits of mantissa */
                assert_float_equal(m->texels[4 * k + c], rgb[3 * k + c], f ? 0.01 * rgb[3 * k + c] : 0.0);
        st_envmap_free(m);
    }
    /* refused, naming the file: one channel only, a black map, an 8-bit
     * image, a missing file, another extension, an empty (0 x 0) map */
    st_image y;
    const char *yname[1] = {"Y"};
    assert_int_equal(st_image_create(&y, W, H, 1, yname, &err), ST_OK);
    snprintf(exr, sizeof exr, "%s", scratch_path("y.exr"));
    assert_int_equal(st_image_save_exr(exr, &y, NULL, 0, &err), ST_OK);
    expect_error(exr, ST_ERR_FORMAT, "no R channel");
    snprintf(exr, sizeof exr, "%s", scratch_path("black.exr"));
    memset(img.data, 0, sizeof rgb);
    assert_int_equal(st_image_save_exr(exr, &img, NULL, 0, &err), ST_OK);
    expect_error(exr, ST_ERR_FORMAT, "black");
    snprintf(hdr, sizeof hdr, "%s", scratch_path("png.hdr"));
    assert_int_equal(st_image_save_png(hdr, &img, &err), ST_OK);
    expect_error(hdr, ST_ERR_FORMAT, "not a Radiance HDR");
    expect_error("/nonexistent/sky.hdr", ST_ERR_IO, "cannot open");
    expect_error("/nonexistent/sky.exr", ST_ERR_IO, "");
    expect_error("sky.png", ST_ERR_USAGE, ".exr or .hdr");
    st_envmap *m = NULL;
    float nan_rgb[3] = {NAN, 1.0f, 1.0f};
    assert_int_equal(st_envmap_make(nan_rgb, 1, 1, "nan", &m, &err), ST_ERR_FORMAT);
    st_error e2 = {0}, e3 = {0};
    assert_int_equal(st_envmap_make(nan_rgb, 0, 1, "empty", &m, &e2), ST_ERR_FORMAT);
    assert_int_equal(st_envmap_make(NULL, 1u << 14, 1u << 13, "huge", &m, &e3), ST_ERR_FORMAT);
    err = e3;
    if (!strstr(err.msg, "2^26"))
        fail_msg("'%s' lacks 2^26", err.msg);
    assert_null(m);
    assert_int_equal(scratch_entries(NULL, 0), 5); /* reading wrote nothing */
    st_image_free(&img);
    st_image_free(&y);
}

/* The default sky (st_envmap_sky): L = 1 - (1 - z) sin(elevation) above the
 * horizon (z = ST_SKY_ZENITH), the ground's ST_SKY_GROUND below. A surface
 * facing up receives E / π = 2 ∫ L sin e cos e de over [0, π/2] = 1 -
 * 2 (1 - z) / 3; one facing down, the ground alone; one facing sideways,
 * half of each, (1 - 4 (1 - z) / 3π + g) / 2 (∫∫ L cos² e cos φ de dφ over
 * the quarter spheres). The map's rows (each its centre's value) give these
 * within 0.5 %; its top row is nearly z, its bottom row the ground. */
static void default_sky_irradiance(void **state)
{
    (void)state;
    st_envmap *m = NULL;
    st_error err = {0};
    assert_int_equal(st_envmap_sky(&m, &err), ST_OK);
    const double z = ST_SKY_ZENITH, g = ST_SKY_GROUND;
    const double up[3] = {0, 1, 0}, down[3] = {0, -1, 0}, side[3] = {0, 0, 1};
    const double want[3] = {1.0 - 2.0 * (1.0 - z) / 3.0, g, 0.5 * (1.0 - 4.0 * (1.0 - z) / (3.0 * PI) + g)};
    const double *n[3] = {up, down, side};
    for (int k = 0; k < 3; k++) {
        double e = irradiance(m, n[k], 0.0, 1, 16) / PI; /* 16: fine in azimuth, 4 texels wide */
        print_message("default sky, normal %d: E / pi %.5f, want %.5f\n", k, e, want[k]);
        if (fabs(e - want[k]) > 5e-3 * want[k])
            fail_msg("normal %d: E / pi %.5f, want %.5f", k, e, want[k]);
    }
    near_sky(m->texels[1], z, 0.02);
    near_sky(m->texels[4 * (m->width * (m->height - 1)) + 1], g, 0.0);
    st_envmap_free(m);
}

/* ---- device: a white plane under a map ----------------------------------------------------- */

static st_scene *white_plane(float emit)
{
    st_error err = {0};
    st_scene *s = NULL;
    if (st_scene_load("tests/scenes/textured_quad.gltf", &s, &err) != ST_OK)
        fail_msg("load: %s", err.msg);
    st_material *m = &s->materials[0];
    for (int k = 0; k < 4; k++) {
        m->base_color[k] = 1.0f;
        m->specular[k] = 0.0f; /* Lambertian, albedo 1 */
        m->emission[k] = emit;
    }
    m->metallic = 0.0f;
    m->base_color_tex = m->emission_tex = m->metallic_roughness_tex = ST_NO_TEXTURE;
    m->specular_tex = m->specular_color_tex = ST_NO_TEXTURE;
    s->emitted_power = PI * 4.0 * emit; /* the 2 x 2 quad's, as loading computes it */
    return s;
}

/* The map plane_shows_irradiance leaves to the scene's default (the
 * renderer's own sky) instead of naming it. */
static const st_envmap *default_sky;

/* Renders the plane (emitting emit: then an area light too, which cannot
 * light itself) under m turned by rot and compares each channel's mean with
 * emit + E / π. */
static void plane_shows_irradiance(const st_envmap *m, double rot, float emit, st_u32 integrator,
                                   st_u32 spp)
{
    st_scene *s = white_plane(emit);
    st_render_options o = st_render_defaults();
    o.env_map = s->default_sky && m == default_sky ? NULL : m;
    o.env_rotate = (float)rot;
    o.width = 16;
    o.height = 12;
    o.spp = spp;
    o.seed = 9;
    o.integrator = integrator;
    st_error err = {0};
    st_renderer *r = NULL;
    st_image img = {0};
    if (st_renderer_create(dev, s, &r, &err) ||
        st_render(r, &o, &img, NULL, NULL, NULL, NULL, &err))
        fail_msg("render: %s", err.msg);
    const double z[3] = {0, 0, 1};
    size_t n = (size_t)img.width * img.height;
    for (int c = 0; c < 3; c++) {
        double want = emit + irradiance(m, z, rot, c, 8) / PI, mean = 0.0, var = 0.0;
        for (size_t p = 0; p < n; p++)
            mean += img.data[4 * p + c] / (double)n;
        for (size_t p = 0; p < n; p++)
            var += (img.data[4 * p + c] - mean) * (img.data[4 * p + c] - mean) / (double)(n - 1);
        double se = sqrt(var / (double)n);
        print_message("%s, rotate %g, channel %d: mean %.5f (+- %.5f), emit + E / π = %.5f\n",
                      integrator == ST_INTEGRATOR_PATH ? "path" : "direct", rot, c, mean, se, want);
        if (fabs(mean - want) > 5.0 * se + 3e-3 * (want - emit))
            fail_msg("channel %d: mean %.5f, want %.5f", c, mean, want);
    }
    st_image_free(&img);
    st_renderer_destroy(r);
    st_scene_destroy(s);
}

/* A constant map of radiance 1: the white furnace, each pixel 1. */
static void constant_map_furnace(void **state)
{
    (void)state;
    float rgb[3 * 32 * 16];
    for (int k = 0; k < 3 * 32 * 16; k++)
        rgb[k] = 1.0f;
    st_envmap *m = make(rgb, 32, 16);
    plane_shows_irradiance(m, 0.0, 0.0f, ST_INTEGRATOR_DIRECT, 64);
    plane_shows_irradiance(m, 0.0, 0.0f, ST_INTEGRATOR_PATH, 64);
    st_envmap_free(m);
}

/* A sun a little off the plane's normal (+Z), where the rotation moves it:
 * 0 and ±70 degrees give different irradiance, which the renders follow. */
static void sun_map_irradiance_and_rotation(void **state)
{
    (void)state;
    float *rgb = sun_rgb(64, 32, 38, 12); /* about 35 degrees from -Z... */
    st_envmap *m = make(rgb, 64, 32);
    free(rgb);
    const double rots[3] = {180.0, 110.0, -110.0}; /* ...turned to face +Z, or away */
    for (int k = 0; k < 3; k++) {
        plane_shows_irradiance(m, rots[k], 0.0f, ST_INTEGRATOR_PATH, 64);
        plane_shows_irradiance(m, rots[k], 0.0f, ST_INTEGRATOR_DIRECT, 64);
    }
    const double z[3] = {0, 0, 1};
    double e[3];
    for (int k = 0; k < 3; k++)
        e[k] = irradiance(m, z, rots[k], 1, 4);
    print_message("E at 180, 110, -110 degrees: %.3f %.3f %.3f\n", e[0], e[1], e[2]);
    assert_true(fabs(e[1] - e[2]) > 0.2 * e[0]); /* the test tells the turn's sign */
    st_envmap_free(m);
}

/* The plane emitting too: next-event estimation then chooses between the
 * map and the area light by power (the light's samples add nothing: it
 * cannot light itself), and the MIS weights use the same probabilities, so
 * the mean stays emit + E / π. */
static void map_and_area_light_chosen_by_power(void **state)
{
    (void)state;
    float *rgb = sun_rgb(64, 32, 38, 12);
    st_envmap *m = make(rgb, 64, 32);
    free(rgb);
    /* area power π x 4 x 100, the map's about π r² x 62 (r = √2): the map
     * is chosen about a quarter of the time */
    plane_shows_irradiance(m, 180.0, 100.0f, ST_INTEGRATOR_PATH, 64);
    plane_shows_irradiance(m, 180.0, 100.0f, ST_INTEGRATOR_DIRECT, 64);
    st_envmap_free(m);
}

/* A render that names no environment, of a scene whose default is the sky
 * (textured_quad: its emitters are dim), sees the sky: the white plane
 * facing +Z, half sky and half ground, shows E / π of st_envmap_sky's map. */
static void default_sky_lights_a_scene_without_env(void **state)
{
    (void)state;
    st_envmap *m = NULL;
    st_error err = {0};
    assert_int_equal(st_envmap_sky(&m, &err), ST_OK);
    default_sky = m;
    plane_shows_irradiance(m, 0.0, 0.0f, ST_INTEGRATOR_DIRECT, 64);
    plane_shows_irradiance(m, 0.0, 0.0f, ST_INTEGRATOR_PATH, 64);
    default_sky = NULL;
    st_envmap_free(m);
}

int main(void)
{
    const struct CMUnitTest host[] = {
        cmocka_unit_test(convention_and_rotation),
        cmocka_unit_test(pdf_integrates_to_one),
        cmocka_unit_test(samples_follow_the_luminance),
        cmocka_unit_test(importance_sampling_beats_uniform),
        cmocka_unit_test(power_and_choice),
        cmocka_unit_test(default_sky_irradiance),
        cmocka_unit_test_setup_teardown(reads_exr_and_hdr, scratch_make, scratch_remove),
    };
    const struct CMUnitTest device[] = {
        cmocka_unit_test(constant_map_furnace),
        cmocka_unit_test(sun_map_irradiance_and_rotation),
        cmocka_unit_test(map_and_area_light_chosen_by_power),
        cmocka_unit_test(default_sky_lights_a_scene_without_env),
    };
    int failed = cmocka_run_group_tests_name("envmap, host", host, NULL, NULL);
    return failed + cmocka_run_group_tests_name("envmap, device", device, device_setup, device_teardown);
}
