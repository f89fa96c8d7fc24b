/* test_view.c — the view from the command line (--look-at, --fov:
 * st_render_view_camera) through the renderer: tests/scenes/markers.gltf
 * holds two unlit cubes far smaller than a pixel, white at (1, 2, -3) and red
 * at (1.5, 2.25, -3.5). Looking at the white one, it lands in the centre
 * pixel; the red one lands in the pixel that the pinhole projection,
 * computed here from the look-at's definition (its own basis, not the
 * renderer's code), gives. The eye, up and field of view are chosen so that
 * the red cube's image lies well inside one pixel (checked below). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>

#include <cmocka.h>

#include "device_fixture.h"
#include "st_render.h"

#define N 65 /* odd: the image's centre is pixel 32's centre */
#define PI 3.14159265358979323846

static const float look_at[9] = {1.25f, 1.5f, 1.0f, 1.0f, 2.0f, -3.0f, 0.25f, 1.0f, 0.0f};
static const double red_at[3] = {1.5, 2.25, -3.5};
#define FOV 25.0f

static st_image render_markers(const st_render_options *o)
{
    st_scene *s = fixture_scene("tests/scenes/markers.gltf");
    st_error err = {0};
    st_renderer *r = NULL;
    st_image img = {0};
    if (st_renderer_create(dev, s, &r, &err) || st_render(r, o, &img, NULL, NULL, NULL, NULL, &err))
        fail_msg("render: %s", err.msg);
    st_renderer_destroy(r);
    st_scene_destroy(s);
    return img;
}

static st_render_options markers_options(void)
{
    st_render_options o = st_render_defaults();
    o.width = o.height = N;
    o.spp = 16;
    o.filter = st_filter_default(ST_FILTER_BOX); /* radius 1/2: a sample lights its own pixel */
    o.env_given = 1; /* black: only the unlit cubes show */
    o.integrator = ST_INTEGRATOR_DIRECT;
    o.look_at_given = 1;
    memcpy(o.look_at, look_at, sizeof look_at);
    o.fov = FOV;
    return o;
}

static void cross(const double *a, const double *b, double *out)
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalise(double *v)
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++)
        v[k] /= l;
}

/* Film position (x right, y down, pixels) of world point q: the pinhole
 * camera at the eye, forward f = target - eye, right r = f x up, true up
 * u = r x f; the image plane at distance 1 is 2 tan(fov / 2) high. */
static void project(const double *q, double *x, double *y)
{
    double f[3], up[3], r[3], u[3], d[3];
    for (int k = 0; k < 3; k++) {
        f[k] = (double)look_at[3 + k] - look_at[k];
        up[k] = look_at[6 + k];
        d[k] = q[k] - look_at[k];
    }
    normalise(f);
    cross(f, up, r);
    normalise(r);
    cross(r, f, u);
    double z = d[0] * f[0] + d[1] * f[1] + d[2] * f[2];
    double t = tan(0.5 * FOV * PI / 180.0);
    *x = 0.5 * N * (1.0 + (d[0] * r[0] + d[1] * r[1] + d[2] * r[2]) / (z * t));
    *y = 0.5 * N * (1.0 - (d[0] * u[0] + d[1] * u[1] + d[2] * u[2]) / (z * t));
}

/* The pixel where channel c minus channel c2 (or 0) is largest. */
static void brightest(const st_image *img, int c, int c2, int *bx, int *by)
{
    float best = -1.0f;
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            const float *px = img->data + ((size_t)y * N + x) * img->channels;
            float v = px[c] - (c2 >= 0 ? px[c2] : 0.0f);
            if (v > best) {
                best = v;
                *bx = x;
                *by = y;
            }
        }
    assert_true(best > 0.0f);
}

static void look_at_lands_the_target_in_the_centre(void **state)
{
    (void)state;
    st_render_options o = markers_options();
    st_image img = render_markers(&o);
    int x = -1, y = -1;
    brightest(&img, 1, -1, &x, &y); /* green: the white cube alone */
    assert_int_equal(x, N / 2);
    assert_int_equal(y, N / 2);
    double px, py;
    project(red_at, &px, &py);
    /* the red cube (0.02 wide, 6 units away: under 0.3 pixel) well inside one pixel */
    assert_true(fabs(px - floor(px) - 0.5) < 0.25 && fabs(py - floor(py) - 0.5) < 0.25);
    brightest(&img, 0, 1, &x, &y); /* red minus green: the red cube alone */
    assert_int_equal(x, (int)floor(px));
    assert_int_equal(y, (int)floor(py));
    st_image_free(&img);
}

/* A wider --fov brings the red cube nearer the centre, as the projection
 * at that angle says. */
static void fov_scales_the_view(void **state)
{
    (void)state;
    st_render_options o = markers_options();
    o.fov = 2.0f * FOV;
    st_image img = render_markers(&o);
    int x = -1, y = -1;
    brightest(&img, 0, 1, &x, &y);
    double t = tan(0.5 * FOV * PI / 180.0) / tan(FOV * PI / 180.0), px, py;
    project(red_at, &px, &py);
    px = 0.5 * N + (px - 0.5 * N) * t;
    py = 0.5 * N + (py - 0.5 * N) * t;
    if (!(fabs(x + 0.5 - px) <= 1.0 && fabs(y + 0.5 - py) <= 1.0))
        fail_msg("red cube at pixel (%d, %d), projected to (%.2f, %.2f)", x, y, px, py);
    st_image_free(&img);
}

/* --fov on an orthographic camera has nothing to change: refused, naming fov. */
static void fov_on_an_orthographic_camera_is_refused(void **state)
{
    (void)state;
    st_scene *s = fixture_scene("tests/scenes/aov_plane.gltf");
    st_render_options o = st_render_defaults();
    o.fov = 30.0f;
    st_scene_camera c;
    st_error err = {0};
    assert_int_equal(st_render_view_camera(s, &o, &c, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "fov"));
    o.look_at_given = 1; /* with --look-at the view is a perspective one */
    memcpy(o.look_at, look_at, sizeof look_at);
    err = (st_error){0};
    assert_int_equal(st_render_view_camera(s, &o, &c, &err), ST_OK);
    assert_int_equal(c.orthographic, 0);
    assert_float_equal(c.yfov, 30.0 * PI / 180.0, 1e-6);
    st_scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(look_at_lands_the_target_in_the_centre),
        cmocka_unit_test(fov_scales_the_view),
        cmocka_unit_test(fov_on_an_orthographic_camera_is_refused),
    };
    return cmocka_run_group_tests(tests, device_setup, device_teardown);
}
