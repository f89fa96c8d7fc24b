/* test_shading.c — the glTF BRDF and normal maps on the device: a white
 * furnace, a normal-mapped plane against the analytic tilt, and a clear
 * coat's own normal map against its highlight (below).
 *
 * A white metal (base colour 1, metallic 1) under a uniform environment of
 * radiance 1, seen head-on (tests/scenes/textured_quad.gltf: a quad filling
 * an orthographic view, its material replaced here): each pixel shows the
 * BRDF's directional albedo at normal incidence, which is at most 1 (no
 * pixel above 1 beyond the noise) and tends to 1 as roughness goes to 0
 * (GGX reflects all at α -> 0, Fresnel of a white metal is 1). Its mean is
 * compared with the albedo by midpoint quadrature of f cos on the host, an
 * independent computation of the same integral (no sampling, no MIS), for
 * the rough ones. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "device_fixture.h"
#include "st_render.h"
#include "st_scene.h"
#include "bsdf.h"

static st_scene *white_metal(float roughness)
{
    st_error err = {0};
    st_scene *s = NULL;
    if (st_scene_load("tests/scenes/textured_quad.gltf", &s, &err) != ST_OK)
        fail_msg("load: %s", err.msg);
    st_material *m = &s->materials[0];
    for (int k = 0; k < 4; k++) {
        m->base_color[k] = 1.0f;
        m->specular[k] = 1.0f;
        m->emission[k] = 0.0f;
    }
    m->metallic = 1.0f;
    m->roughness = roughness;
    m->base_color_tex = m->emission_tex = m->metallic_roughness_tex = ST_NO_TEXTURE;
    return s;
}

/* The integrator of render_view. */
static st_u32 view_integrator = ST_INTEGRATOR_PATH;

/* A render of s from its camera `camera` (-1: the default) inside a uniform
 * environment of radiance 1. */
static st_image render_view(const st_scene *s, st_u32 spp, st_i32 camera)
{
    st_render_options o = st_render_defaults();
    o.camera = camera;
    o.env_given = 1;
    o.env[0] = o.env[1] = o.env[2] = 1.0f;
    o.width = 16;
    o.height = 12;
    o.spp = spp;
    o.seed = 5;
    o.integrator = view_integrator;
    st_error err = {0};
    st_renderer *r = NULL;
    st_image img = {0};
    if (st_renderer_create(dev, s, &r, &err) || st_render(r, &o, &img, NULL, NULL, NULL, NULL, &err))
        fail_msg("render: %s", err.msg);
    st_renderer_destroy(r);
    return img;
}

static st_image render_furnace(const st_scene *s, st_u32 spp)
{
    return render_view(s, spp, -1);
}

/* The directional albedo at normal incidence by the midpoint rule in
 * (cos θ, φ); isotropic, so φ needs few points. */
static double albedo_head_on(float roughness)
{
    const float one[3] = {1.0f, 1.0f, 1.0f};
    st_brdf b = st_brdf_make(one, 1.0f, roughness, 1.0f, one, 1.5f, 0.0f);
    st_dir wo = {0.0f, 0.0f, 1.0f};
    const int nz = 200000;
    double sum = 0.0;
    for (int i = 0; i < nz; i++) {
        float z = (float)((i + 0.5) / nz), r = sqrtf(fmaxf(0.0f, 1.0f - z * z));
        st_dir wi = {r, 0.0f, z};
        float f[3];
        st_brdf_eval(&b, wo, wi, f);
        sum += f[0] * z;
    }
    return sum * 2.0 * 3.14159265358979323846 / nz;
}

static void white_furnace(void **state)
{
    (void)state;
    const float rough[] = {0.0f, 0.5f, 1.0f};
    for (int k = 0; k < 3; k++) {
        st_scene *s = white_metal(rough[k]);
        st_image img = render_furnace(s, 64);
        size_t n = (size_t)img.width * img.height;
        double mean = 0.0, var = 0.0, want = albedo_head_on(rough[k]);
        for (size_t p = 0; p < n; p++)
            mean += img.data[4 * p] / (double)n;
        for (size_t p = 0; p < n; p++)
            var += (img.data[4 * p] - mean) * (img.data[4 * p] - mean) / (double)(n - 1);
        double se = sqrt(var / (double)n);
        print_message("roughness %.1f: mean %.5f (+- %.5f), quadrature %.5f\n", rough[k], mean,
                      se, want);
        for (size_t p = 0; p < n; p++)
            if (!(img.data[4 * p] <= 1.0f + 6.0 * sqrt(var) + 1e-4))
                fail_msg("roughness %g: pixel %zu is %g, above 1", rough[k], p, img.data[4 * p]);
        /* the midpoint rule cannot resolve the mirror-like peak at roughness 0 */
        if (rough[k] > 0.0f && (!(want <= 1.0 + 1e-3) || fabs(mean - want) > 5.0 * se + 2e-3))
            fail_msg("roughness %g: mean %.5f, quadrature albedo %.5f", rough[k], mean, want);
        /* α = 1 head-on: D = 1/π, V = 1 / (2 (1 + z)), so ∫ f z dω = ∫ z / (1 + z) dz
         * = 1 - ln 2 */
        if (rough[k] == 1.0f && fabs(want - (1.0 - log(2.0))) > 1e-4)
            fail_msg("roughness 1: quadrature %.5f, closed form 1 - ln 2", want);
        if (rough[k] == 0.0f && fabs(mean - 1.0) > 2e-3)
            fail_msg("roughness 0: mean %.5f, want 1", mean);
        st_image_free(&img);
        st_scene_destroy(s);
    }
}

/* The direct integrator's BSDF sample, combined with its light sample by
 * MIS: a smooth white metal under the uniform environment shows its
 * albedo, 1 within the noise of 16 samples (a few per cent), in every
 * pixel (light sampling alone, a cosine direction, almost never meets the
 * mirror's peak: black pixels and fireflies), and 1 in the mean. Rougher,
 * the mean matches the quadrature albedo. */
static void direct_mis_resolves_smooth_metal(void **state)
{
    (void)state;
    const float rough[] = {0.0f, 0.5f};
    view_integrator = ST_INTEGRATOR_DIRECT;
    for (int k = 0; k < 2; k++) {
        st_scene *s = white_metal(rough[k]);
        st_image img = render_furnace(s, 16);
        size_t n = (size_t)img.width * img.height;
        double mean = 0.0, want = rough[k] > 0.0f ? albedo_head_on(rough[k]) : 1.0;
        for (size_t p = 0; p < n; p++) {
            mean += img.data[4 * p] / (double)n;
            if (rough[k] == 0.0f && fabs(img.data[4 * p] - 1.0) > 0.1)
                fail_msg("roughness 0, direct: pixel %zu is %g, want about 1", p, img.data[4 * p]);
        }
        print_message("roughness %.1f, direct: mean %.5f, albedo %.5f\n", rough[k], mean, want);
        if (fabs(mean - want) > 0.01)
            fail_msg("roughness %g, direct: mean %.5f, albedo %.5f", rough[k], mean, want);
        st_image_free(&img);
        st_scene_destroy(s);
    }
    view_integrator = ST_INTEGRATOR_PATH;
}

/* A plane whose normal map tilts the shading normal by θ, under a uniform
 * environment 1, seen head-on: the cosine lobe around the tilted normal
 * loses what falls below the geometric surface (light never comes through
 * it), leaving albedo x (1 + cos θ) / 2 (the projected solid angle of a
 * hemisphere tilted by θ, clipped by the plane, over π). cos θ from the
 * map's bytes (238, 128, 191) and the scale, computed here. */
static void normal_map_tilts_by_its_angle(void **state)
{
    (void)state;
    const float scales[] = {1.0f, 0.5f, 0.0f};
    for (int k = 0; k < 3; k++) {
        st_error err = {0};
        st_scene *s = NULL;
        if (st_scene_load("tests/scenes/normal_tilt.gltf", &s, &err) != ST_OK)
            fail_msg("load: %s", err.msg);
        assert_int_not_equal(s->materials[0].normal_tex, ST_NO_TEXTURE);
        s->materials[0].normal_scale = scales[k];
        double x = (238.0 / 255.0 * 2.0 - 1.0) * scales[k], y = (128.0 / 255.0 * 2.0 - 1.0) * scales[k],
               z = 191.0 / 255.0 * 2.0 - 1.0, want = 0.5 * (1.0 + z / sqrt(x * x + y * y + z * z));
        st_image img = render_furnace(s, 64);
        size_t n = (size_t)img.width * img.height;
        double mean = 0.0, var = 0.0;
        for (size_t p = 0; p < n; p++)
            mean += img.data[4 * p + 1] / (double)n;
        for (size_t p = 0; p < n; p++)
            var += (img.data[4 * p + 1] - mean) * (img.data[4 * p + 1] - mean) / (double)(n - 1);
        double se = sqrt(var / (double)n);
        print_message("normal scale %.1f: mean %.5f (+- %.5f), (1 + cos θ) / 2 = %.5f\n",
                      scales[k], mean, se, want);
        if (fabs(mean - want) > 5.0 * se + 1e-3)
            fail_msg("scale %g: mean %.5f, want %.5f", scales[k], mean, want);
        st_image_free(&img);
        st_scene_destroy(s);
    }
}

/* The plane of normal_tilt with its normal map's file missing
 * (tests/scenes/normal_missing.gltf): the map is left out, so the white
 * Lambertian plane under the uniform environment 1 shows its albedo, 1, in
 * every pixel, where a white texel in the map's place would tilt the
 * normal by some 55 degrees and darken it to about (1 + cos 55°) / 2. */
static void unreadable_normal_map_leaves_the_plane_flat(void **state)
{
    (void)state;
    st_error err = {0};
    st_scene *s = NULL;
    if (st_scene_load("tests/scenes/normal_missing.gltf", &s, &err) != ST_OK)
        fail_msg("load: %s", err.msg);
    st_image img = render_furnace(s, 16);
    size_t n = (size_t)img.width * img.height;
    double mean = 0.0;
    for (size_t p = 0; p < n; p++)
        mean += img.data[4 * p + 1] / (double)n;
    print_message("normal map unreadable: mean %.5f, want 1\n", mean);
    if (fabs(mean - 1.0) > 0.01)
        fail_msg("mean %.5f, want 1", mean);
    st_image_free(&img);
    st_scene_destroy(s);
}

/* Every pixel of img equals want to 1e-5. */
static void assert_every_pixel(const st_image *img, const double want[3], const char *what)
{
    for (size_t p = 0; p < (size_t)img->width * img->height; p++)
        for (int c = 0; c < 3; c++)
            if (fabs(img->data[4 * p + (size_t)c] - want[c]) > 1e-5)
                fail_msg("%s: pixel %zu channel %d: %g, want %g", what, p, c,
                         img->data[4 * p + (size_t)c], want[c]);
}

/* A smooth white metal whose normal map tilts the shading normal by about
 * 60 degrees (tests/scenes/normal_tilt.gltf), seen head-on under the
 * uniform environment 1: the mirror direction about the tilted normal lies
 * 120 degrees from the geometric normal, below the surface. The adapted
 * normal reflects it above, so every pixel keeps the metal's albedo, 1
 * within the noise of 16 samples (a few per cent), and none goes black;
 * the mean is 1 (energy neither lost nor made). */
static void tilted_glossy_keeps_its_energy(void **state)
{
    (void)state;
    st_error err = {0};
    st_scene *s = NULL;
    if (st_scene_load("tests/scenes/normal_tilt.gltf", &s, &err) != ST_OK)
        fail_msg("load: %s", err.msg);
    st_material *m = &s->materials[0];
    for (int k = 0; k < 4; k++)
        m->base_color[k] = m->specular[k] = 1.0f;
    m->metallic = 1.0f;
    m->roughness = 0.0f;
    for (int integrator = 0; integrator < 2; integrator++) {
        view_integrator = integrator ? ST_INTEGRATOR_PATH : ST_INTEGRATOR_DIRECT;
        st_image img = render_furnace(s, 16);
        size_t n = (size_t)img.width * img.height;
        double mean = 0.0;
        for (size_t p = 0; p < n; p++) {
            mean += img.data[4 * p] / (double)n;
            if (fabs(img.data[4 * p] - 1.0) > 0.1)
                fail_msg("%s: pixel %zu is %g, want 1", integrator ? "path" : "direct", p,
                         img.data[4 * p]);
        }
        print_message("tilted mirror, %s: mean %.5f\n", integrator ? "path" : "direct", mean);
        if (fabs(mean - 1.0) > 0.01)
            fail_msg("%s: mean %.5f, want 1", integrator ? "path" : "direct", mean);
        st_image_free(&img);
    }
    view_integrator = ST_INTEGRATOR_PATH;
    st_scene_destroy(s);
}

/* COLOR_0 multiplies the base colour: a white Lambertian quad whose vertex
 * colour is (128, 64, 255) / 255, under a uniform environment 1, shows
 * that colour in every pixel (exactly: for a Lambertian surface open to the
 * environment each sample gives albedo x env, test_texture.c). */
static void vertex_color_multiplies_base_colour(void **state)
{
    (void)state;
    st_error err = {0};
    st_scene *s = NULL;
    if (st_scene_load("tests/scenes/vertex_color.gltf", &s, &err) != ST_OK)
        fail_msg("load: %s", err.msg);
    st_image img = render_furnace(s, 4);
    const double want[3] = {128.0 / 255.0, 64.0 / 255.0, 1.0};
    assert_every_pixel(&img, want, "vertex colour");
    st_image_free(&img);
    st_scene_destroy(s);
}

/* KHR_materials_unlit: the quad shows its base colour (0.3, 0.6, 0.9)
 * exactly, whatever lights it (here a uniform environment 1, which a lit
 * surface would reflect with its BRDF). */
static void unlit_shows_base_colour(void **state)
{
    (void)state;
    st_error err = {0};
    st_scene *s = NULL;
    if (st_scene_load("tests/scenes/unlit.gltf", &s, &err) != ST_OK)
        fail_msg("load: %s", err.msg);
    assert_true(s->materials[0].flags & ST_MAT_UNLIT);
    st_image img = render_furnace(s, 4);
    const double want[3] = {0.3, 0.6, 0.9};
    assert_every_pixel(&img, want, "unlit");
    st_image_free(&img);
    st_scene_destroy(s);
}

/* doubleSided: a cube whose fronts face out, unlit (0.3, 0.6, 0.9), in an
 * environment of 1. From outside (camera 1) both kinds show their colour in
 * every pixel; from inside (camera 0) the one-sided cube's backs are culled,
 * so every ray leaves and sees the environment, while the two-sided one
 * shows its colour. */
static void double_sided_culls_backs_of_one_sided(void **state)
{
    (void)state;
    const double colour[3] = {0.3, 0.6, 0.9}, env[3] = {1.0, 1.0, 1.0};
    const char *file[2] = {"tests/scenes/sided_one.gltf", "tests/scenes/sided_two.gltf"};
    for (int two = 0; two < 2; two++) {
        st_error err = {0};
        st_scene *s = NULL;
        if (st_scene_load(file[two], &s, &err) != ST_OK)
            fail_msg("load: %s", err.msg);
        assert_int_equal((s->materials[0].flags & ST_MAT_DOUBLE_SIDED) != 0u, two);
        st_image in = render_view(s, 2, 0), out = render_view(s, 2, 1);
        assert_every_pixel(&in, two ? colour : env, two ? "two-sided, inside" : "one-sided, inside");
        assert_every_pixel(&out, colour, "outside");
        st_image_free(&in);
        st_image_free(&out);
        st_scene_destroy(s);
    }
}

/* The mean of the pixels of img's first `cols` columns, all three channels. */
static double columns_mean(const st_image *img, int cols)
{
    double sum = 0.0;
    for (size_t y = 0; y < img->height; y++)
        for (size_t x = 0; x < (size_t)cols; x++)
            for (int c = 0; c < 3; c++)
                sum += img->data[4 * (y * img->width + x) + (size_t)c];
    return sum / (3.0 * cols * img->height);
}

/* The ground's mean over the left (x < 0) columns of tests/scenes/shadow_NAME,
 * under a uniform environment 1, nearest-texel textures. */
static st_u32 ground_seed = 5;
static double ground_left(const char *name, st_u32 spp)
{
    char path[96];
    snprintf(path, sizeof path, "tests/scenes/shadow_%s.gltf", name);
    st_error err = {0};
    st_scene *s = NULL;
    if (st_scene_load(path, &s, &err) != ST_OK)
        fail_msg("load: %s", err.msg);
    st_render_options o = st_render_defaults();
    o.env_given = 1;
    o.env[0] = o.env[1] = o.env[2] = 1.0f;
    o.width = 16;
    o.height = 12;
    o.spp = spp;
    o.seed = ground_seed;
    o.integrator = ST_INTEGRATOR_PATH;
    o.texture_filter = ST_TEXFILTER_NONE;
    st_renderer *r = NULL;
    st_image img = {0};
    if (st_renderer_create(dev, s, &r, &err) || st_render(r, &o, &img, NULL, NULL, NULL, NULL, &err))
        fail_msg("render: %s", err.msg);
    double m = columns_mean(&img, 6); /* x < -0.1: clear of the filter's reach across x = 0 */
    st_renderer_destroy(r);
    st_image_free(&img);
    st_scene_destroy(s);
    return m;
}

/* A cut-out casts a cut-out shadow: the ground under the MASK quad whose
 * left half is alpha 0 is lit as under an opaque quad of the right half
 * alone. The two renders draw the same samples (rays through a cut-out go on
 * with the same sample dimensions), so they differ only by the rounding of
 * hit points: 1e-3 relative. Shadow rays that took the whole quad as opaque
 * would darken the ground as much as shadow_opaque does, far more. */
static void alpha_cutout_casts_cutout_shadow(void **state)
{
    (void)state;
    double cut = ground_left("cutout", 16), half = ground_left("half", 16),
           opaque = ground_left("opaque", 16);
    print_message("ground x < 0: cut-out %.5f, right half %.5f, whole quad %.5f\n", cut, half,
                  opaque);
    assert_true(fabs(cut - half) <= 1e-3 * half);
    assert_true(half - opaque > 0.1 * half);
}

/* BLEND alpha 0.5 on the shadow rays: each passes the black quad with
 * probability 1/2, so the ground, albedo 0.5 under the environment 1, shows
 * in expectation the mean of the opaque quad's shadow and the open sky's
 * 0.5 (a flat ground sees no other surface). Tolerance 0.007: four standard
 * deviations (0.0017) of blend - want, measured over seeds 1 to 20. */
static void alpha_blend_shadow_passes_half(void **state)
{
    (void)state;
    double blend = ground_left("blend", 64), opaque = ground_left("opaque", 64);
    double want = 0.5 * (opaque + 0.5);
    print_message("ground x < 0: blend %.5f, whole quad %.5f, want %.5f\n", blend, opaque, want);
    assert_true(fabs(blend - want) <= 0.007);
}

/* The coat of tests/scenes/coat_normal.gltf (factor 1, roughness 0.5,
 * Fresnel of ior 1.5) about the normal nc over a white Lambertian base
 * about N = +z, seen head-on (wo = +z) and lit by a directional light of
 * irradiance 1 from li: f cos, written out from the specification's
 * formulas (GGX D, height-correlated Smith V, Schlick's Fresnel at F0 =
 * 0.04) apart from the kernels. The base under the coat keeps
 * (1 - Fc(wo.nc)) (1 - Fc(li.nc)) of its albedo / π, and the cosine is
 * the base's, li.N. */
static double coat_pixel(const double nc[3], const double li[3])
{
    const double pi = 3.14159265358979323846, a2 = 0.0625; /* α = 0.5² */
    double wo[3] = {0.0, 0.0, 1.0}, h[3], hl = 0.0;
    for (int k = 0; k < 3; k++)
        h[k] = wo[k] + li[k], hl += h[k] * h[k];
    double o = nc[2], i = nc[0] * li[0] + nc[1] * li[1] + nc[2] * li[2];
    double hn = (h[0] * nc[0] + h[1] * nc[1] + h[2] * nc[2]) / sqrt(hl), oh = h[2] / sqrt(hl);
    double t = hn * hn * (a2 - 1.0) + 1.0, d = a2 / (pi * t * t);
    double v = 0.5 / (i * sqrt(o * o + a2 * (1.0 - o * o)) + o * sqrt(i * i + a2 * (1.0 - i * i)));
    double fo = 0.04 + 0.96 * pow(1.0 - oh, 5.0);
    double pass = (1.0 - (0.04 + 0.96 * pow(1.0 - o, 5.0))) *
                  (1.0 - (0.04 + 0.96 * pow(1.0 - i, 5.0)));
    return (pass / pi + fo * d * v) * li[2];
}

/* The mean of each channel of s in the uniform environment env (0: lit by
 * its own lights alone), in mean[3]. */
static void view_means(const st_scene *s, float env, double mean[3])
{
    st_render_options o = st_render_defaults();
    o.env_given = 1;
    o.env[0] = o.env[1] = o.env[2] = env;
    o.width = 16;
    o.height = 12;
    o.spp = 16;
    o.seed = 5;
    st_error err = {0};
    st_renderer *r = NULL;
    st_image img = {0};
    if (st_renderer_create(dev, s, &r, &err) ||
        st_render(r, &o, &img, NULL, NULL, NULL, NULL, &err))
        fail_msg("render: %s", err.msg);
    st_renderer_destroy(r);
    size_t n = (size_t)img.width * img.height;
    for (int k = 0; k < 3; k++) {
        mean[k] = 0.0;
        for (size_t p = 0; p < n; p++)
            mean[k] += img.data[4 * p + k] / (double)n;
    }
    st_image_free(&img);
}

static double own_light_mean(const st_scene *s)
{
    double mean[3];
    view_means(s, 0.0f, mean);
    return mean[0];
}

/* clearcoatNormalTexture (tests/scenes/coat_normal.gltf): the coat's map
 * (normal_tilt's texel at scale 1/3) tilts the coat's normal by some 30
 * degrees towards the tangent, and the light stands at the view's mirror
 * direction about it, so the coat's highlight peaks in every pixel. The
 * render matches coat_pixel about the tilted coat normal over the flat
 * base, and neither a coat without its map nor a base that took the map
 * too would (their values are printed beside it). */
static void coat_normal_map_tilts_the_coat_alone(void **state)
{
    (void)state;
    st_error err = {0};
    st_scene *s = NULL;
    if (st_scene_load("tests/scenes/coat_normal.gltf", &s, &err) != ST_OK)
        fail_msg("load: %s", err.msg);
    assert_int_not_equal(s->materials[0].clearcoat_normal_tex, ST_NO_TEXTURE);
    assert_int_equal(s->materials[0].normal_tex, ST_NO_TEXTURE);
    assert_int_equal(s->punctual_count, 1);
    double li[3], w = s->tangents[3]; /* the first vertex's handedness */
    for (int k = 0; k < 3; k++)
        li[k] = -s->punctual[0].dir[k];
    /* the map's texel (bytes 238, 128, 191) at scale 1/3 in the frame
     * tangent +x, bitangent w (+z x +x) = w +y, normal +z */
    double nc[3] = {(238.0 / 255.0 * 2.0 - 1.0) / 3.0, w * (128.0 / 255.0 * 2.0 - 1.0) / 3.0,
                    191.0 / 255.0 * 2.0 - 1.0};
    double len = sqrt(nc[0] * nc[0] + nc[1] * nc[1] + nc[2] * nc[2]);
    for (int k = 0; k < 3; k++)
        nc[k] /= len;
    const double flat[3] = {0.0, 0.0, 1.0};
    double want = coat_pixel(nc, li), untilted = coat_pixel(flat, li);
    double both = coat_pixel(nc, li) / li[2] * (nc[0] * li[0] + nc[1] * li[1] + nc[2] * li[2]);
    double mean = own_light_mean(s);
    print_message("coat normal map: mean %.6f, want %.6f (coat untilted %.6f, base tilted too "
                  "%.6f)\n", mean, want, untilted, both);
    assert_true(fabs(want - untilted) > 0.05 * want && fabs(want - both) > 0.05 * want);
    if (fabs(mean - want) > 2e-4 * want)
        fail_msg("mean %.6f, want %.6f", mean, want);
    st_scene_destroy(s);
}

/* coat_normal with the coat's map's file missing: the map is left out
 * (not a white texel, which would tilt the coat by some 55 degrees), so
 * the plane shows the untilted coat's value. */
static void unreadable_coat_normal_map_is_left_out(void **state)
{
    (void)state;
    st_error err = {0};
    st_scene *s = NULL;
    if (st_scene_load("tests/scenes/coat_normal_missing.gltf", &s, &err) != ST_OK)
        fail_msg("load: %s", err.msg);
    assert_int_equal(s->materials[0].clearcoat_normal_tex, ST_NO_TEXTURE);
    double li[3];
    for (int k = 0; k < 3; k++)
        li[k] = -s->punctual[0].dir[k];
    const double flat[3] = {0.0, 0.0, 1.0};
    double want = coat_pixel(flat, li), mean = own_light_mean(s);
    print_message("coat normal map unreadable: mean %.6f, want %.6f\n", mean, want);
    if (fabs(mean - want) > 2e-4 * want)
        fail_msg("mean %.6f, want %.6f", mean, want);
    st_scene_destroy(s);
}

/* A thin wall's reflectance at normal incidence: one face's Fresnel R =
 * ((ior - 1) / (ior + 1))², summed over the light that bounces between
 * the two faces, R' = R + (1 - R)² R / (1 - R²) = 2 R / (1 + R). */
static double thin_reflectance(double ior)
{
    double r = (ior - 1.0) / (ior + 1.0);
    return 2.0 * r * r / (1.0 + r * r);
}

/* Thin-walled transmission (tests/scenes/thin_pane.gltf: a smooth quad of
 * transmission 1, ior 1.5, base colour (0.9, 0.7, 0.3), no
 * KHR_materials_volume, before a lamp of radiance 1): the camera sees the
 * lamp straight through, (1 - R') x base colour in each channel; no
 * refraction into an interior (which would give (1 - R) c / 1.5²). */
static void thin_pane_passes_the_lamp_straight_through(void **state)
{
    (void)state;
    st_error err = {0};
    st_scene *s = NULL;
    if (st_scene_load("tests/scenes/thin_pane.gltf", &s, &err) != ST_OK)
        fail_msg("load: %s", err.msg);
    assert_true(s->materials[1].flags & ST_MAT_THIN);
    const double c[3] = {0.9, 0.7, 0.3}, t = 1.0 - thin_reflectance(1.5);
    double mean[3];
    view_means(s, 0.0f, mean);
    for (int k = 0; k < 3; k++) {
        print_message("thin pane, channel %d: mean %.6f, want %.6f\n", k, mean[k], t * c[k]);
        if (fabs(mean[k] - t * c[k]) > 1e-3 * c[k])
            fail_msg("channel %d: mean %.6f, want %.6f", k, mean[k], t * c[k]);
    }
    st_scene_destroy(s);
}

/* A white thin pane in a white furnace (tests/scenes/thin_pane_white.gltf,
 * environment 1, seen head-on): smooth, what it reflects and what it
 * passes add up to 1 (R' + T' = 1, the slab absorbs nothing); rough (0.3,
 * 0.7), R' and T' share one GGX lobe, the transmission its mirror image,
 * so together they keep what a white metal's lobe keeps at normal
 * incidence (albedo_head_on, by quadrature). */
static void thin_pane_keeps_the_furnace_energy(void **state)
{
    (void)state;
    const float rough[] = {0.0f, 0.3f, 0.7f};
    for (int j = 0; j < 3; j++) {
        st_error err = {0};
        st_scene *s = NULL;
        if (st_scene_load("tests/scenes/thin_pane_white.gltf", &s, &err) != ST_OK)
            fail_msg("load: %s", err.msg);
        s->materials[1].roughness = rough[j];
        double mean[3];
        view_means(s, 1.0f, mean);
        double want = rough[j] == 0.0f ? 1.0 : albedo_head_on(rough[j]);
        print_message("white thin pane, roughness %.1f: mean %.6f, want %.6f\n", rough[j],
                      mean[0], want);
        if (fabs(mean[0] - want) > 2e-3)
            fail_msg("roughness %g: mean %.6f, want %.6f", rough[j], mean[0], want);
        st_scene_destroy(s);
    }
}

int main(void)
{
    const struct CMUnitTest device[] = {
        cmocka_unit_test(white_furnace),
        cmocka_unit_test(direct_mis_resolves_smooth_metal),
        cmocka_unit_test(normal_map_tilts_by_its_angle),
        cmocka_unit_test(unreadable_normal_map_leaves_the_plane_flat),
        cmocka_unit_test(coat_normal_map_tilts_the_coat_alone),
        cmocka_unit_test(unreadable_coat_normal_map_is_left_out),
        cmocka_unit_test(thin_pane_passes_the_lamp_straight_through),
        cmocka_unit_test(thin_pane_keeps_the_furnace_energy),
        cmocka_unit_test(tilted_glossy_keeps_its_energy),
        cmocka_unit_test(vertex_color_multiplies_base_colour),
        cmocka_unit_test(unlit_shows_base_colour),
        cmocka_unit_test(double_sided_culls_backs_of_one_sided),
        cmocka_unit_test(alpha_cutout_casts_cutout_shadow),
        cmocka_unit_test(alpha_blend_shadow_passes_half),
    };
    return cmocka_run_group_tests_name("shading", device, device_setup, device_teardown);
}
