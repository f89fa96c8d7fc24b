/* test_render_paths.c — the first stages in one kernel (generate_rays) and
 * the box filter's splat gathered by pixel (splat_pixels) against the
 * kernels they replace on the same render, and shade (ST_W items per
 * work-item) and the tile splat's weights (splat_tiles) built at every lane
 * width against the device's own or the per-sample splat: the films (raw
 * 64-bit sums), the counts (splats, rays, clamped, non-finite) and the
 * images equal bit for bit, over wave sizes below, at and above the
 * region's pixel count, crops, odd image sizes, spp 1 and spp that divide
 * nothing, several samplers, both integrators and every kind of material
 * and light; the list of live paths against every item at every vertex;
 * and each path runs only its own kernels; and resolve_film at every lane
 * width against its definition. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>
#include "skip.h"

#include "st_device.h"
#include "st_envmap.h"
#include "st_image.h"
#include "st_render.h"
#include "st_scene.h"
#include "device_fixture.h"
#include "plan.h"

/* The choices render_run forces on the renderer (plan.h; zero: its own). */
static st_plan_force forced;
/* The device renderer_for renders on: the fixture's, or one built at
 * another lane width. */
static st_device *on;

/* One profiled render's results. */
typedef struct run {
    st_i64 *sums;
    st_image img;
    st_render_stats st;
} run;

static run render_run(st_renderer *r, st_render_options o)
{
    run out;
    memset(&out, 0, sizeof out);
    st_error err = {0};
    o.profile = 1;
    st_renderer_force(r, &forced);
    if (st_render(r, &o, &out.img, &out.sums, &out.st, NULL, NULL, &err) != ST_OK)
        fail_msg("render: %s", err.msg);
    return out;
}

/* Whether the last render of r launched kernel `name` (st_renderer_ran:
 * "lanes W: k1, k2, ..."), after checking the lane width it names. */
static int ran(st_renderer *r, const char *name)
{
    const char *text = st_renderer_ran(r);
    char lanes[32];
    snprintf(lanes, sizeof lanes, "lanes %u:", st_device_get_info(on ? on : dev)->lanes);
    assert_true(strncmp(text, lanes, strlen(lanes)) == 0);
    for (const char *p = strchr(text, ':'); p; p = strchr(p, ',')) {
        p += 2; /* ": " or ", " */
        size_t n = strcspn(p, ",");
        if (n == strlen(name) && !strncmp(p, name, n))
            return 1;
    }
    return 0;
}

static void run_free(run *a)
{
    free(a->sums);
    free(a->st.spp_map);
    st_image_free(&a->img);
}

/* a and b (renders of o's window) are the same bit for bit: sums, image and counts. */
static void assert_same_run(const run *a, const run *b, const st_render_options *o)
{
    size_t px = o->crop_w ? (size_t)o->crop_w * o->crop_h : (size_t)o->width * o->height;
    assert_memory_equal(a->sums, b->sums, px * 4 * sizeof(st_i64));
    assert_int_equal(a->img.width, b->img.width);
    assert_memory_equal(a->img.data, b->img.data, px * 4 * sizeof(float));
    assert_true(a->st.samples == b->st.samples && a->st.splats == b->st.splats);
    assert_true(a->st.closest_rays == b->st.closest_rays);
    assert_true(a->st.shadow_rays == b->st.shadow_rays);
    assert_int_equal(a->st.clamped, b->st.clamped);
    assert_int_equal(a->st.nonfinite, b->st.nonfinite);
    assert_int_equal(a->st.zero_weight, b->st.zero_weight);
}

static st_render_options small(st_u32 w, st_u32 h, st_u32 spp)
{
    st_render_options o = st_render_defaults();
    o.width = w;
    o.height = h;
    o.spp = spp;
    o.seed = 11;
    o.filter = st_filter_default(ST_FILTER_BOX);
    return o;
}

/* The variations both comparisons run: (wave, crop, size, spp, sampler,
 * integrator). 37 x 23 = 851 pixels; a crop's region is its window with a
 * one-pixel apron. */
typedef struct variant {
    st_u32 w, h, spp, wave, sampler, integrator;
    st_u32 crop[4];
} variant;

static const variant variants[] = {
    {37, 23, 4, 0, ST_SAMPLER_RANDOM, ST_INTEGRATOR_DIRECT, {0}},     /* one wave */
    {37, 23, 5, 333, ST_SAMPLER_RANDOM, ST_INTEGRATOR_PATH, {0}},     /* waves < npix */
    {37, 23, 7, 851, ST_SAMPLER_HALTON, ST_INTEGRATOR_DIRECT, {0}},   /* wave = npix */
    {37, 23, 3, 2000, ST_SAMPLER_SOBOL, ST_INTEGRATOR_PATH, {0}},     /* 2.35 npix */
    {37, 23, 1, 0, ST_SAMPLER_STRATIFIED, ST_INTEGRATOR_DIRECT, {0}}, /* 1 spp */
    {41, 29, 6, 500, ST_SAMPLER_PMJ02, ST_INTEGRATOR_DIRECT, {5, 7, 13, 9}},  /* crop */
    {41, 29, 9, 0, ST_SAMPLER_ZSOBOL, ST_INTEGRATOR_PATH, {0, 20, 41, 9}},    /* crop, 1 wave */
};

static st_render_options variant_options(const variant *v)
{
    st_render_options o = small(v->w, v->h, v->spp);
    o.wave = v->wave;
    o.sampler = v->sampler;
    o.integrator = v->integrator;
    o.crop_x = v->crop[0];
    o.crop_y = v->crop[1];
    o.crop_w = v->crop[2];
    o.crop_h = v->crop[3];
    return o;
}

/* A renderer on the device for fixture scene `name` (*scene: the scene, for
 * the caller to destroy after the renderer). */
static st_renderer *renderer_for(const char *name, st_scene **scene)
{
    st_renderer *r = NULL;
    st_error err = {0};
    *scene = fixture_scene(name);
    if (st_renderer_create(on ? on : dev, *scene, &r, &err) != ST_OK)
        fail_msg("renderer %s: %s", name, err.msg);
    return r;
}

/* Renders o with the splat forced to ST_SPLAT_PER_SAMPLE (the atomics) and
 * `other`: the same film, image and counts. Returns the other run's seconds
 * in splat_pixels; the reference ran splat_samples alone. *clamped (if
 * given): the samples clamped. */
static double same_splat_counted(st_renderer *r, st_render_options o, int other, st_u32 *clamped)
{
    forced.splat = ST_SPLAT_PER_SAMPLE;
    run a = render_run(r, o);
    forced.splat = other;
    run b = render_run(r, o);
    forced.splat = ST_SPLAT_AUTO;
    assert_same_run(&a, &b, &o);
    assert_true(a.st.stage_seconds[ST_STAGE_SPLAT] > 0.0);
    assert_true(a.st.stage_seconds[ST_STAGE_SPLAT_PIXELS] == 0.0);
    double gathered = b.st.stage_seconds[ST_STAGE_SPLAT_PIXELS];
    if (clamped)
        *clamped = a.st.clamped;
    run_free(&a);
    run_free(&b);
    return gathered;
}

static double same_splat(st_renderer *r, st_render_options o, int other)
{
    return same_splat_counted(r, o, other, NULL);
}

/* splat_pixels against splat_samples with the box filter: the variants
 * (each asked for and by default, where a CPU device gathers), a box of
 * radius 0.3 (samples near a pixel's edge reach no pixel), samples on a
 * pixel's edge (unscrambled, reaching the pixels across it), clamped splats
 * (the hot furnace: every sample counts once). Where the render does not
 * allow the gather (a tiled sampler, filter importance sampling, a wider
 * box, Mitchell) a request falls back to the per-sample path; an adaptive
 * render gathers its pilot only (its rounds run splat_samples too). */
static void splat_pixels_equals_per_sample(void **state)
{
    (void)state;
    st_scene *scene = NULL;
    st_renderer *r = renderer_for("cornell-box", &scene);
    for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
        st_render_options o = variant_options(&variants[v]);
        assert_true(same_splat(r, o, ST_SPLAT_PIXELS) > 0.0);
        int cpu = st_device_get_info(dev)->is_cpu;
        assert_true((same_splat(r, o, ST_SPLAT_AUTO) > 0.0) == cpu);
    }
    st_render_options narrow = small(30, 20, 6);
    narrow.filter.radius = 0.3f;
    narrow.wave = 1500;
    assert_true(same_splat(r, narrow, ST_SPLAT_PIXELS) > 0.0);
    /* unscrambled Hammersley puts sample 0 on its pixel's corner, which the
     * closed box shares with the three pixels across it; a crop's window
     * edge lies on such corners too */
    st_render_options corner = small(30, 20, 4);
    corner.sampler = ST_SAMPLER_HAMMERSLEY;
    corner.scramble = 0;
    corner.wave = 450;
    assert_true(same_splat(r, corner, ST_SPLAT_PIXELS) > 0.0);
    run edge = render_run(r, corner);
    assert_true(edge.st.splats > edge.st.samples); /* the corners were shared */
    run_free(&edge);
    corner.crop_x = 3, corner.crop_y = 2, corner.crop_w = 11, corner.crop_h = 7;
    assert_true(same_splat(r, corner, ST_SPLAT_PIXELS) > 0.0);
    st_render_options no[4] = {small(30, 20, 3), small(30, 20, 3), small(30, 20, 3),
                               small(30, 20, 3)};
    no[0].sampler = ST_SAMPLER_POISSON;
    no[1].reconstruction = ST_RECON_FIS;
    no[2].filter.radius = 1.0f;
    no[3].filter = st_filter_default(ST_FILTER_MITCHELL);
    for (int k = 0; k < 4; k++)
        assert_true(same_splat(r, no[k], ST_SPLAT_PIXELS) == 0.0);
    st_render_options adaptive = small(24, 20, 16);
    adaptive.adaptive = 1;
    adaptive.min_spp = 4;
    adaptive.sampler = ST_SAMPLER_RANDOM; /* others render uniformly */
    st_render_options ref = adaptive;
    ref.profile = 1;
    forced.splat = ST_SPLAT_PER_SAMPLE;
    run a = render_run(r, ref);
    forced.splat = ST_SPLAT_PIXELS;
    run b = render_run(r, adaptive);
    forced.splat = ST_SPLAT_AUTO;
    assert_same_run(&a, &b, &adaptive);
    assert_memory_equal(a.st.spp_map, b.st.spp_map, 24 * 20 * sizeof(st_u32));
    assert_true(b.st.stage_seconds[ST_STAGE_SPLAT_PIXELS] > 0.0);
    assert_true(b.st.stage_seconds[ST_STAGE_SPLAT] > 0.0);
    run_free(&a);
    run_free(&b);
    st_renderer_destroy(r);
    st_scene_destroy(scene);

    r = renderer_for("tests/scenes/hot-furnace.gltf", &scene);
    st_render_options hot = small(20, 12, 3);
    hot.max_depth = 0;
    hot.wave = 500;
    st_u32 clamped = 0;
    assert_true(same_splat_counted(r, hot, ST_SPLAT_PIXELS, &clamped) > 0.0);
    assert_int_equal(clamped, 20 * 12 * 3);
    st_renderer_destroy(r);
    st_scene_destroy(scene);
}

/* Renders o of scene `name` on the fixture's device and on `on` (another
 * lane width): the same film, image and counts, and both ran shade_hits. */
static void same_at_width(const char *name, const st_render_options *o)
{
    st_scene *scene = NULL;
    st_device *other = on;
    on = NULL;
    st_renderer *r = renderer_for(name, &scene);
    run a = render_run(r, *o);
    assert_true(ran(r, forced.shadow == ST_SHADOW_IN_SHADE ? "shade_hits_shadowed" : "shade_hits"));
    st_renderer_destroy(r);
    on = other;
    st_error err = {0};
    if (st_renderer_create(on, scene, &r, &err) != ST_OK)
        fail_msg("renderer %s: %s", name, err.msg);
    run b = render_run(r, *o);
    assert_true(ran(r, forced.shadow == ST_SHADOW_IN_SHADE ? "shade_hits_shadowed" : "shade_hits"));
    assert_same_run(&a, &b, o);
    run_free(&a);
    run_free(&b);
    st_renderer_destroy(r);
    st_scene_destroy(scene);
}

/* The scenes of the shade comparison: area lights on Lambertian boxes
 * (the bench's Cornell box, build/scenes/cornell-bench.gltf, and the built-in one),
 * tests/scenes/shade_mix.gltf (textured, alpha, vertex-coloured and
 * metallic materials beside Lambertian ones, an emitter with an emissive
 * texture, misses), textures.gltf (MASK and BLEND, textures),
 * punctual.gltf (point, spot and directional lights) and Khronos models
 * (vertex colours; emissive strength; DamagedHelmet's textured GGX with a
 * normal map and emission). */
static const char *const shade_scenes[] = {
    "build/scenes/cornell-bench.gltf", "cornell-box", "tests/scenes/shade_mix.gltf",
    "tests/scenes/textures.gltf", "tests/scenes/punctual.gltf", "tests/scenes/glass.gltf",
    "tests/scenes/coat.gltf",
    "tests/scenes/sheen.gltf", "tests/scenes/sheen_quad.gltf",
    "../shared/scenes/khronos/VC/VC.gltf",
    "../shared/scenes/khronos/EmissiveStrengthTest/EmissiveStrengthTest.gltf",
    "../shared/scenes/khronos/DamagedHelmet/DamagedHelmet.glb"};

/* Shade at lane width `on` against the fixture's on each scene: both
 * integrators, a uniform environment or the scene's own lighting, the
 * random sampler (its dimensions made in lanes) and Halton, waves that fill
 * no last lane. */
/* Whether scene `name` lies in ../shared and is not there; a test that
 * passed one over ends in skipped_shared(), which says so. */
static int left_out;
static int absent(const char *name)
{
    if (strncmp(name, "../shared", 9) != 0 || access(name, R_OK) == 0)
        return 0;
    left_out++;
    return 1;
}

/* Ends the test as skipped when it ran without a scene of ../shared: the
 * scenes it has checked passed, but not all it names. */
static void skipped_shared(void)
{
    if (left_out) {
        left_out = 0;
        ST_SKIP("../shared/scenes/khronos not found (the Khronos sample models): "
                "checked without them");
    }
}

static void same_shade_scenes(void)
{
    static const st_u32 waves[] = {0, 333, 1001};
    for (size_t k = 0; k < sizeof shade_scenes / sizeof shade_scenes[0]; k++) {
        if (absent(shade_scenes[k]))
            continue;
        for (size_t w = 0; w < sizeof waves / sizeof waves[0]; w++) {
            st_render_options o = small(37, 23, 3);
            o.integrator = w == 1 ? ST_INTEGRATOR_DIRECT : ST_INTEGRATOR_PATH;
            o.sampler = w == 2 ? ST_SAMPLER_HALTON : ST_SAMPLER_RANDOM;
            o.wave = waves[w];
            if (w == 0) { /* the environment sampled beside the scene's lights */
                o.env_given = 1;
                o.env[0] = 0.6f, o.env[1] = 0.7f, o.env[2] = 0.8f;
            }
            same_at_width(shade_scenes[k], &o);
        }
    }
}

/* shade_hits built at the other lane widths (1, 4, 8 and 16 but for the
 * fixture's own) against the fixture's, bit for bit: same_shade_scenes,
 * the variants (samplers, crops), an adaptive render and shadow rays
 * traced in shade (shade_hits_shadowed). A lane's arithmetic reordered at
 * one width, or a lane that reads another's values, fails it. */
static void shade_at_every_width(void **state)
{
    (void)state;
    static const unsigned widths[] = {1, 4, 8, 16};
    for (size_t k = 0; k < sizeof widths / sizeof widths[0]; k++) {
        if (widths[k] == st_device_get_info(dev)->lanes)
            continue;
        st_error err = {0};
        if (st_device_create(NULL, &on, &err) != ST_OK ||
            st_device_set_lanes(on, widths[k], &err) != ST_OK || st_device_build(on, NULL, &err))
            fail_msg("device at %u lanes: %s", widths[k], err.msg);
        same_shade_scenes();
        for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
            st_render_options o = variant_options(&variants[v]);
            same_at_width("cornell-box", &o);
        }
        st_render_options adaptive = small(24, 20, 16);
        adaptive.adaptive = 1;
        adaptive.min_spp = 4;
        adaptive.sampler = ST_SAMPLER_RANDOM;
        adaptive.wave = 700;
        same_at_width("cornell-box", &adaptive);
        st_render_options shadowed = small(30, 20, 3);
        shadowed.integrator = ST_INTEGRATOR_PATH;
        forced.shadow = ST_SHADOW_IN_SHADE;
        same_at_width("tests/scenes/shade_mix.gltf", &shadowed);
        forced.shadow = ST_SHADOW_AUTO;
        st_device_destroy(on);
        on = NULL;
    }
    skipped_shared();
}

/* Renders o of scene `name` with the forced choice *choice = a, then b:
 * the same film, image and counts. ran[0], ran[1]: whether each render
 * ran `kernel`. */
static void same_forced(const char *name, const st_render_options *o, int *choice, int a, int b,
                        const char *kernel, int ran_kernel[2])
{
    st_scene *scene = NULL;
    st_renderer *r = renderer_for(name, &scene);
    *choice = a;
    run x = render_run(r, *o);
    ran_kernel[0] = ran(r, kernel);
    *choice = b;
    run y = render_run(r, *o);
    ran_kernel[1] = ran(r, kernel);
    *choice = 0; /* *_AUTO */
    assert_same_run(&x, &y, o);
    run_free(&x);
    run_free(&y);
    st_renderer_destroy(r);
    st_scene_destroy(scene);
}

/* o rendered over every item at every vertex (ST_PATHS_ALL) and over the
 * list of live paths (ST_PATHS_LIVE, live.cl): the same films, images and
 * counts, and only the second listed the live paths. */
static void same_with_live_lists(const char *name, const st_render_options *o)
{
    int listed[2];
    same_forced(name, o, &forced.paths, ST_PATHS_ALL, ST_PATHS_LIVE, "live_scatter", listed);
    assert_false(listed[0]);
    assert_true(listed[1]);
}

/* The list of live paths against every item at every vertex, bit for bit:
 * the shade scenes (cut-outs that a path goes on through without a bounce,
 * unlit surfaces that end it, glass that refracts it), open to a uniform
 * environment (paths that leave the scene at any vertex) or not, deep paths
 * (roulette), waves whose lists fill no last lane, packets at every vertex,
 * and an adaptive render. A path dropped from the list, or listed twice,
 * fails it. */
static void live_lists_keep_every_path(void **state)
{
    (void)state;
    static const st_u32 waves[] = {0, 333, 1001};
    for (size_t k = 0; k < sizeof shade_scenes / sizeof shade_scenes[0]; k++) {
        if (absent(shade_scenes[k]))
            continue;
        for (size_t w = 0; w < sizeof waves / sizeof waves[0]; w++) {
            st_render_options o = small(37, 23, 3);
            o.integrator = w == 2 ? ST_INTEGRATOR_DIRECT : ST_INTEGRATOR_PATH;
            o.max_depth = w == 1 ? 9 : 5;
            o.wave = waves[w];
            o.packet_path = w == 1 ? ST_PACKET_ALL : ST_PACKET_AUTO;
            if (w != 2) {
                o.env_given = 1;
                o.env[0] = 0.6f, o.env[1] = 0.7f, o.env[2] = 0.8f;
            }
            same_with_live_lists(shade_scenes[k], &o);
        }
    }
    st_render_options adaptive = small(24, 20, 16);
    adaptive.adaptive = 1;
    adaptive.min_spp = 4;
    adaptive.sampler = ST_SAMPLER_RANDOM;
    adaptive.integrator = ST_INTEGRATOR_PATH;
    adaptive.wave = 700;
    same_with_live_lists("tests/scenes/shade_mix.gltf", &adaptive);
    skipped_shared();
}

/* A bounce's rays traced in the order of their sort by ray (order.cl)
 * against the order of the list, bit for bit, counts included: the shade
 * scenes' paths (cut-outs, unlit surfaces, glass), open to an environment,
 * deep (roulette), in waves whose lists fill several of the sort's blocks
 * or part of one; and only the sorted renders ran the sort. An item the
 * sort loses or repeats leaves a ray untraced or traced twice, and fails it. */
static void rays_in_order_keep_every_path(void **state)
{
    (void)state;
    static const st_u32 waves[] = {0, 5000};
    for (size_t k = 0; k < sizeof shade_scenes / sizeof shade_scenes[0]; k++) {
        if (absent(shade_scenes[k]))
            continue;
        for (size_t w = 0; w < sizeof waves / sizeof waves[0]; w++) {
            st_render_options o = small(96, 64, 4);
            o.integrator = ST_INTEGRATOR_PATH;
            o.max_depth = w ? 7 : 4;
            o.wave = waves[w];
            o.env_given = 1;
            o.env[0] = 0.6f, o.env[1] = 0.7f, o.env[2] = 0.8f;
            int sorted[2];
            same_forced(shade_scenes[k], &o, &forced.order, ST_ORDER_OFF, ST_ORDER_ON,
                        "order_scatter_high", sorted);
            assert_false(sorted[0]);
            assert_true(sorted[1]);
        }
    }
    skipped_shared();
}

/* Renders o of scene `name` with the last vertex's rays traversed and by
 * trace_rays_last: the same film, image and counts. Returns whether the
 * second ran trace_rays_last (the first must not). */
static int same_last_vertex(const char *name, const st_render_options *o)
{
    int last[2];
    same_forced(name, o, &forced.last, ST_LAST_TRAVERSE, ST_LAST_EMITTERS, "trace_rays_last",
                last);
    assert_false(last[0]);
    return last[1];
}

/* Next-event estimation's area light picked in lanes (shade's area_lanes)
 * against lane by lane (light_gather's binary search), bit for bit, counts
 * included: scenes lit by area lights alone, two triangles of equal power
 * (the Cornell boxes), four of two sizes (lamp_and_glow), an emissive
 * texture (two_uv_light); direct lighting and paths, random and Halton
 * samples. A lane that picks its light or rescales its u otherwise than
 * st_cdf_pick does fails it. */
static void area_lights_in_lanes(void **state)
{
    (void)state;
    static const char *const scenes[] = {"cornell-box", "build/scenes/cornell-bench.gltf",
                                         "tests/scenes/lamp_and_glow.gltf",
                                         "tests/scenes/two_uv_light.gltf"};
    for (size_t k = 0; k < sizeof scenes / sizeof scenes[0]; k++) {
        if (absent(scenes[k]))
            continue;
        for (int v = 0; v < 2; v++) {
            st_render_options o = small(37, 23, 4);
            o.integrator = v ? ST_INTEGRATOR_PATH : ST_INTEGRATOR_DIRECT;
            o.sampler = v ? ST_SAMPLER_HALTON : ST_SAMPLER_RANDOM;
            int shaded[2];
            same_forced(scenes[k], &o, &forced.area, ST_AREA_LANE_BY_LANE, ST_AREA_AUTO,
                        "shade_hits", shaded);
            assert_true(shaded[0] && shaded[1]);
        }
    }
    skipped_shared();
}

/* trace_rays_last (emitters first, then an any-hit test), with shade
 * ending the paths whose last ray meets no emitter before storing it
 * (dark_bounces), against the traversal at the last vertex, bit for bit,
 * counts included: direct lighting, paths open to
 * a uniform environment or to a map (rays that see it past every
 * emitter), emission seen at the camera alone (max depth 0), waves whose
 * lists fill no last lane; on the shade scenes and on emitters one- and
 * two-sided, closed and open, beside punctual lights and glass. Scenes with
 * a cut-out, an unlit surface or an emissive texture keep the traversal
 * (their light can come from outside the light list), the Cornell box and
 * the glowing boxes do not. */
static void last_vertex_by_emitters(void **state)
{
    (void)state;
    static const char *const more[] = {
        "tests/scenes/glow_box.gltf", "tests/scenes/glow_box_one_sided.gltf",
        "tests/scenes/glow_box_open.gltf", "tests/scenes/lamp_and_glow.gltf",
        "tests/scenes/glass_furnace.gltf", "tests/scenes/shadow_cutout.gltf"};
    const size_t ns = sizeof shade_scenes / sizeof shade_scenes[0];
    const size_t nm = sizeof more / sizeof more[0];
    float rgb[8 * 4 * 3];
    for (size_t i = 0; i < sizeof rgb / sizeof rgb[0]; i++)
        rgb[i] = 0.25f + 0.05f * (float)(i % 17);
    st_envmap *map = NULL;
    st_error err = {0};
    if (st_envmap_make(rgb, 8, 4, "gradient", &map, &err) != ST_OK)
        fail_msg("env map: %s", err.msg);
    for (size_t k = 0; k < ns + nm; k++) {
        const char *name = k < ns ? shade_scenes[k] : more[k - ns];
        if (absent(name))
            continue;
        int any = 0;
        for (int c = 0; c < 4; c++) {
            st_render_options o = small(37, 23, 3);
            o.wave = c == 1 ? 333 : 0;
            o.integrator = c == 0 ? ST_INTEGRATOR_DIRECT : ST_INTEGRATOR_PATH;
            o.max_depth = c == 3 ? 0 : 3;
            if (c == 1) {
                o.env_given = 1;
                o.env[0] = 0.6f, o.env[1] = 0.7f, o.env[2] = 0.8f;
            }
            if (c == 2)
                o.env_map = map;
            any |= same_last_vertex(name, &o);
        }
        if (!strcmp(name, "cornell-box") || strstr(name, "glow_box"))
            assert_true(any);
        if (strstr(name, "cutout") || strstr(name, "DamagedHelmet"))
            assert_false(any);
    }
    st_envmap_free(map);
    skipped_shared();
}

/* A renderer of `scene` on device d (the fixture's or one at another width). */
static st_renderer *renderer_on(st_device *d, st_scene *scene)
{
    st_renderer *r = NULL;
    st_error err = {0};
    if (st_renderer_create(d, scene, &r, &err) != ST_OK)
        fail_msg("renderer: %s", err.msg);
    return r;
}

/* The renders of splat_lanes_at_every_width: every filter (box wider than
 * the gather's half pixel; mitchell with its own B, C as well, whose
 * products a lane must contract as width 1 does; lanczos with τ below its
 * radius), waves and bins whose items fill no last lane, an adaptive render
 * (its rounds' splats weighted), a crop, one wave, waves narrower than an
 * image row, a pixel's sums past 2^31 in one wave (splat_tiles' int32
 * window must widen its rows in time), and a tiled sampler (points off the
 * image). */
static st_render_options splat_case(size_t k)
{
    static const st_u32 kinds[] = {ST_FILTER_BOX,         ST_FILTER_TRIANGLE,
                                   ST_FILTER_GAUSSIAN,    ST_FILTER_MITCHELL,
                                   ST_FILTER_CATMULL_ROM, ST_FILTER_LANCZOS,
                                   ST_FILTER_BLACKMAN_HARRIS};
    size_t nk = sizeof kinds / sizeof kinds[0];
    st_render_options o = small(37, 23, 3);
    o.wave = 333;
    o.sampler = ST_SAMPLER_HALTON;
    o.filter = st_filter_default(kinds[k % nk]);
    if (k < nk) {
        if (kinds[k] == ST_FILTER_BOX)
            o.filter.radius = 1.5f;
        return o;
    }
    switch (k - nk) {
    case 0: /* mitchell's own parameters, a radius that is no integer */
        o.filter = st_filter_default(ST_FILTER_MITCHELL);
        o.filter.b = 0.2f, o.filter.c = 0.45f, o.filter.radius = 2.5f;
        return o;
    case 1:
        o.filter = st_filter_default(ST_FILTER_LANCZOS);
        o.filter.radius = 2.0f, o.filter.tau = 1.5f;
        return o;
    case 2:
        o = small(24, 20, 16);
        o.adaptive = 1;
        o.min_spp = 4;
        o.sampler = ST_SAMPLER_RANDOM; /* others render uniformly */
        o.filter = st_filter_default(ST_FILTER_LANCZOS);
        return o;
    case 3: /* a crop: the region is its window and apron */
        o = small(41, 29, 6);
        o.wave = 500;
        o.crop_x = 5, o.crop_y = 7, o.crop_w = 13, o.crop_h = 9;
        o.filter = st_filter_default(ST_FILTER_LANCZOS);
        return o;
    case 4: /* one wave, larger than a bin's pixels times spp */
        o = small(70, 45, 5);
        o.wave = 0;
        o.filter = st_filter_default(ST_FILTER_MITCHELL);
        return o;
    case 5: /* waves narrower than an image row */
        o = small(37, 23, 2);
        o.wave = 29;
        o.filter = st_filter_default(ST_FILTER_MITCHELL);
        return o;
    case 6: /* each pixel's weight sum alone near 256 x 2^24 = 2^32 */
        o = small(40, 24, 256);
        o.wave = 0;
        o.filter = st_filter_default(ST_FILTER_LANCZOS);
        return o;
    default:
        o.sampler = ST_SAMPLER_POISSON;
        o.filter = st_filter_default(ST_FILTER_MITCHELL);
        return o;
    }
}
#define SPLAT_CASES 15u

/* The box renders that splat_pixels gathers (ST_W pixels a work-item) in
 * splat_lanes_at_every_width: waves below the region's pixels whose last
 * work-item fills no lane of 4, 8 or 16 (851 pixels), one wave of a path
 * render, a radius of 0.3 (samples near an edge reach no pixel), and
 * unscrambled Hammersley, whose sample 0 lies on its pixel's corner (shared
 * with the pixels across it), whole and cropped. */
static st_render_options gather_case(size_t k)
{
    st_render_options o = small(37, 23, 3);
    o.sampler = ST_SAMPLER_HALTON;
    switch (k) {
    case 0:
        o.wave = 333;
        return o;
    case 1:
        o.spp = 5, o.wave = 0;
        o.integrator = ST_INTEGRATOR_PATH;
        return o;
    case 2:
        o.filter.radius = 0.3f;
        o.wave = 1500;
        return o;
    default:
        o = small(30, 20, 4);
        o.sampler = ST_SAMPLER_HAMMERSLEY;
        o.scramble = 0;
        o.wave = 450;
        if (k == 4)
            o.crop_x = 3, o.crop_y = 2, o.crop_w = 11, o.crop_h = 7;
        return o;
    }
}
#define GATHER_CASES 5u

/* Renders o with r (at some lane width) forced to `splat` against ref's
 * splat_samples: the same film, image and counts, and r ran `kernel`.
 * Returns the samples clamped. */
static st_u32 same_as_per_sample(st_renderer *ref, st_renderer *r, st_render_options o,
                                 int splat, const char *kernel)
{
    forced.splat = ST_SPLAT_PER_SAMPLE;
    run a = render_run(ref, o);
    forced.splat = splat;
    run b = render_run(r, o);
    forced.splat = ST_SPLAT_AUTO;
    assert_true(ran(r, kernel));
    assert_same_run(&a, &b, &o);
    st_u32 clamped = b.st.clamped;
    run_free(&a);
    run_free(&b);
    return clamped;
}

/* splat_tiles, whose weights are made ST_W samples at a time in lanes
 * (filter_lanes.h), built at 1, 4, 8 and 16 lanes, owned by one work-item
 * and shared by a work-group, against splat_samples on the fixture's device,
 * whose weights are made one sample at a time (width 1): films, images and
 * counts equal bit for bit for each of splat_case's renders; and the hot
 * furnace, whose splats clamp (a sample counts once). splat_pixels likewise,
 * its samples summed ST_W pixels at a time, for gather_case's renders and
 * the hot furnace (every sample clamped: each lane goes the scalar way). */
static void splat_lanes_at_every_width(void **state)
{
    (void)state;
    static const unsigned widths[] = {1, 4, 8, 16};
    static const int tiles[] = {ST_SPLAT_TILES_ALONE, ST_SPLAT_TILES};
    st_scene *box = fixture_scene("cornell-box"), *hot = fixture_scene("tests/scenes/hot-furnace.gltf");
    st_renderer *ref = renderer_on(dev, box), *ref_hot = renderer_on(dev, hot);
    for (size_t w = 0; w < sizeof widths / sizeof widths[0]; w++) {
        st_error err = {0};
        st_device *d = dev;
        if (widths[w] != st_device_get_info(dev)->lanes &&
            (st_device_create(NULL, &d, &err) != ST_OK ||
             st_device_set_lanes(d, widths[w], &err) != ST_OK || st_device_build(d, NULL, &err)))
            fail_msg("device at %u lanes: %s", widths[w], err.msg);
        on = d;
        st_renderer *r = renderer_on(d, box), *r_hot = renderer_on(d, hot);
        for (size_t k = 0; k <= SPLAT_CASES; k++) {
            st_render_options o = k < SPLAT_CASES ? splat_case(k) : small(20, 12, 3);
            if (k == SPLAT_CASES) {
                o.max_depth = 0;
                o.filter = st_filter_default(ST_FILTER_LANCZOS);
            }
            for (size_t t = 0; t < 2; t++) {
                st_u32 clamped = k < SPLAT_CASES
                                     ? same_as_per_sample(ref, r, o, tiles[t], "splat_tiles")
                                     : same_as_per_sample(ref_hot, r_hot, o, tiles[t],
                                                          "splat_tiles");
                if (k == SPLAT_CASES) /* and the reference's count: assert_same_run */
                    assert_true(clamped > 0u);
            }
        }
        for (size_t k = 0; k < GATHER_CASES; k++)
            same_as_per_sample(ref, r, gather_case(k), ST_SPLAT_PIXELS, "splat_pixels");
        st_render_options hot_box = small(20, 12, 3);
        hot_box.max_depth = 0;
        hot_box.wave = 100;
        assert_int_equal(same_as_per_sample(ref_hot, r_hot, hot_box, ST_SPLAT_PIXELS,
                                            "splat_pixels"),
                         20 * 12 * 3);
        st_renderer_destroy(r);
        st_renderer_destroy(r_hot);
        if (d != dev)
            st_device_destroy(d);
        on = NULL;
    }
    st_renderer_destroy(ref);
    st_renderer_destroy(ref_hot);
    st_scene_destroy(box);
    st_scene_destroy(hot);
}

/* Film sums for resolve_at_every_width, pixel i of n: every seventh pixel
 * of zero weight (sums left nonzero), every seventh from the next of
 * negative weight (a negative lobe's sum: its value below 0, clamped),
 * one of weight 0 with zero sums too, the others pseudo-random sums of
 * either sign up to 2^40 over weights up to 2^30. */
static void resolve_sums(st_i64 *sums, size_t n)
{
    uint64_t x = 0x9e3779b97f4a7c15u;
    for (size_t i = 0; i < n; i++) {
        st_i64 *s = sums + 4 * i;
        for (int c = 0; c < 4; c++) {
            x = x * 6364136223846793005u + 1442695040888963407u;
            s[c] = (st_i64)(x >> 23) - ((st_i64)1 << 40); /* within ±2^40 */
        }
        s[3] = (s[3] >> 10) | 1; /* nonzero, within ±2^30 */
        if (s[3] < 0)
            s[3] = -s[3];
        if (i % 7 == 0)
            s[3] = 0;
        if (i % 7 == 1)
            s[3] = -s[3];
    }
    memset(sums + 4 * (n - 1), 0, 4 * sizeof *sums);
}

/* st_render_resolve built at every lane width: each pixel is the
 * definition (resolve_film: Σ f L / Σ f as floats from the 64-bit sums,
 * negative values 0, no weight 0 and counted), over an image whose pixels
 * fill no last lane, and the images of every width are the same bit for
 * bit. */
static void resolve_at_every_width(void **state)
{
    (void)state;
    static const unsigned widths[] = {1, 4, 8, 16};
    enum { W = 13, H = 7, N = W * H };
    st_i64 sums[4 * N];
    resolve_sums(sums, N);
    st_u32 zero = 0;
    for (size_t i = 0; i < N; i++)
        zero += sums[4 * i + 3] == 0;
    st_image first = {0};
    for (size_t k = 0; k < sizeof widths / sizeof widths[0]; k++) {
        st_error err = {0};
        st_device *d = fixture_device_at(widths[k]);
        st_image img = {0};
        st_render_stats st = {0};
        if (st_render_resolve(d, sums, W, H, ST_AOV_NONE, &img, &st, &err) != ST_OK)
            fail_msg("resolve at %u lanes: %s", widths[k], err.msg);
        assert_int_equal(st.zero_weight, zero);
        assert_int_equal(st.nonfinite, 0);
        for (size_t i = 0; i < N; i++) {
            const st_i64 *s = sums + 4 * i;
            float w = (float)s[3] * (1.0f / ST_FIXED_SCALE), want[3] = {0.0f, 0.0f, 0.0f};
            for (int c = 0; w != 0.0f && c < 3; c++) {
                float v = (float)s[c] * (1.0f / ST_FIXED_SCALE) / w;
                want[c] = v > 0.0f ? v : 0.0f;
            }
            for (int c = 0; c < 3; c++)
                assert_true(img.data[4 * i + (size_t)c] == want[c]);
            assert_true(img.data[4 * i + 3] == w);
        }
        if (k == 0)
            first = img;
        else {
            assert_memory_equal(img.data, first.data, sizeof(float) * 4 * N);
            st_image_free(&img);
        }
        st_device_destroy(d);
    }
    st_image_free(&first);
}

/* Profiling times each launch by the device's clock, nothing waited for:
 * the stages that ran have a time, and they add up to no more than the
 * render's wall time (an in-order queue runs one command at a time). A
 * warm render (st_render_options.warm: every vertex's kernels launched even
 * where no path is left) gives the same film and counts, and launches at
 * least the kernels the render launches. */
static void stage_times_within_the_render(void **state)
{
    (void)state;
    st_scene *scene;
    st_renderer *r = renderer_for("cornell-box", &scene);
    st_render_options o = small(24, 16, 4);
    o.integrator = ST_INTEGRATOR_PATH;
    o.max_depth = 8;
    run a = render_run(r, o);
    double sum = 0.0;
    for (int k = 0; k < ST_STAGE_COUNT; k++) {
        assert_true(a.st.stage_seconds[k] >= 0.0);
        sum += a.st.stage_seconds[k];
    }
    assert_true(sum <= a.st.seconds);
    static const int ran_always[] = {ST_STAGE_GENERATE, ST_STAGE_TRACE, ST_STAGE_SHADE,
                                     ST_STAGE_RESOLVE};
    for (unsigned i = 0; i < sizeof ran_always / sizeof *ran_always; i++)
        assert_true(a.st.stage_seconds[ran_always[i]] > 0.0);
    char plain[1024];
    snprintf(plain, sizeof plain, "%s", st_renderer_ran(r));
    o.warm = 1;
    run b = render_run(r, o);
    assert_same_run(&a, &b, &o);
    const char *warm = st_renderer_ran(r);
    for (const char *p = strchr(plain, ':'); p; p = strchr(p, ',')) {
        p += 2;
        char name[64];
        snprintf(name, sizeof name, "%.*s", (int)strcspn(p, ","), p);
        assert_true(ran(r, name));
    }
    assert_true(strlen(warm) >= strlen(plain));
    run_free(&a);
    run_free(&b);
    st_renderer_destroy(r);
    st_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(splat_pixels_equals_per_sample),
        cmocka_unit_test(shade_at_every_width),
        cmocka_unit_test(live_lists_keep_every_path),
        cmocka_unit_test(rays_in_order_keep_every_path),
        cmocka_unit_test(last_vertex_by_emitters),
        cmocka_unit_test(area_lights_in_lanes),
        cmocka_unit_test(splat_lanes_at_every_width),
        cmocka_unit_test(resolve_at_every_width),
        cmocka_unit_test(stage_times_within_the_render),
    };
    return cmocka_run_group_tests_name("render_paths", tests, device_setup, device_teardown);
}
