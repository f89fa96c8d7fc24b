/* test_render.c — the renderer on the OpenCL device (PoCL here): layouts the
 * device sees, BVH traversal on the device against brute force, determinism
 * (twice, any wave and work-group size, split sample ranges), reconstruction
 * of a constant image by every filter and sampler, the furnace's closed form,
 * and the golden image. */
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
#include "st_device.h"
#include "st_diff.h"
#include "st_image.h"
#include "st_render.h"
#include "st_sampling.h"
#include "st_scene.h"
#include "trace.h"
#include "wave.h"
#include "device_fixture.h"
#include "plan.h"
#include "thin_film.h"
#include "render_int.h"
#include "samplers.h"
#include "camera.h"

/* Renders scene `name` with o; returns the image and (optionally) the sums. */
static st_image render(const char *name, const st_render_options *o, st_i64 **sums)
{
    st_error err = {0};
    st_scene *scene = NULL;
    st_renderer *r = NULL;
    st_image img = {0};
    if (st_scene_load(name, &scene, &err) || st_renderer_create(dev, scene, &r, &err) ||
        st_render(r, o, &img, sums, NULL, NULL, NULL, &err))
        fail_msg("render %s: %s", name, err.msg);
    st_renderer_destroy(r);
    st_scene_destroy(scene);
    return img;
}

/* Renders scene `name` with o; returns the image and fills *st (the caller
 * frees st->spp_map). */
static st_image render_stats(const char *name, const st_render_options *o, st_render_stats *st)
{
    st_error err = {0};
    st_scene *scene = NULL;
    st_renderer *r = NULL;
    st_image img = {0};
    if (st_scene_load(name, &scene, &err) || st_renderer_create(dev, scene, &r, &err) ||
        st_render(r, o, &img, NULL, st, NULL, NULL, &err))
        fail_msg("render %s: %s", name, err.msg);
    st_renderer_destroy(r);
    st_scene_destroy(scene);
    return img;
}

/* render with both the raw sums and the stats. */
/* The choices render_sums_stats forces on its renderer (plan.h; zero: its own). */
static st_plan_force forced;

static st_image render_sums_stats(const char *name, const st_render_options *o, st_i64 **sums,
                                  st_render_stats *st)
{
    st_error err = {0};
    st_scene *scene = NULL;
    st_renderer *r = NULL;
    st_image img = {0};
    if (st_scene_load(name, &scene, &err) || st_renderer_create(dev, scene, &r, &err))
        fail_msg("render %s: %s", name, err.msg);
    st_renderer_force(r, &forced);
    if (st_render(r, o, &img, sums, st, NULL, NULL, &err))
        fail_msg("render %s: %s", name, err.msg);
    st_renderer_destroy(r);
    st_scene_destroy(scene);
    return img;
}

static st_render_options small(st_u32 w, st_u32 h, st_u32 spp)
{
    st_render_options o = st_render_defaults();
    o.width = w;
    o.height = h;
    o.spp = spp;
    o.seed = 7;
    return o;
}

/* small()'s render by path tracing, box filter, in a uniform environment of
 * radiance 1: the furnace-like setting of the material tests. */
static st_render_options in_white_env(st_u32 w, st_u32 h, st_u32 spp)
{
    st_render_options o = small(w, h, spp);
    o.filter = st_filter_default(ST_FILTER_BOX);
    o.integrator = ST_INTEGRATOR_PATH;
    o.env_given = 1;
    o.env[0] = o.env[1] = o.env[2] = 1.0f;
    return o;
}

/* tests/scenes/dark_box.gltf: a closed grey (0.5) cube, [-1, 1]^3, that
 * emits nothing, its camera at the centre looking down -Z (yfov 0.5). No
 * sky reaches inside, so the scene gains a point light at the camera
 * (scene.c, add_headlight) of intensity pi d^2, d a distance of the view:
 * the view's rays meet the -Z wall between 1 and sqrt(1 + 2 tan^2 0.25)
 * away, so I lies in (pi, 1.129 pi). The centre pixels face the light at
 * distance 1, and their direct radiance, (rho / pi) I cos / r^2 for a
 * Lambertian wall, lies in (0.5, 0.565); glTF's dielectric base (F0 0.04,
 * roughness 1: its diffuse part less what its specular lobe takes, plus that
 * lobe) and the pixels' few degrees off the axis (cos^3 above 0.99) move it
 * by a few percent, so 0.47 .. 0.6. Breaks with no light, or one elsewhere
 * or of another strength. */
static void enclosed_dark_scene_gets_a_headlight(void **state)
{
    (void)state;
    st_render_options o = small(16, 16, 64);
    o.filter = st_filter_default(ST_FILTER_BOX);
    o.integrator = ST_INTEGRATOR_DIRECT;
    st_image img = render("tests/scenes/dark_box.gltf", &o, NULL);
    for (st_u32 y = 7; y < 9; y++)
        for (st_u32 x = 7; x < 9; x++)
            for (int k = 0; k < 3; k++) {
                float v = img.data[4 * (y * 16 + x) + k];
                if (!(v > 0.47f && v < 0.6f))
                    fail_msg("pixel (%u, %u) channel %d: %.4f, want 0.47 .. 0.6", x, y, k, v);
            }
    st_image_free(&img);
}

static float frand(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (float)((*s >> 40) * (1.0 / 16777216.0));
}

/* trace_rays on the device against a brute-force loop over every triangle on
 * the host: same triangle, and t within 1e-5 x (t + 10), 10 being the scene's
 * size (the device may contract multiply-adds, and Moller-Trumbore's error in
 * t scales with the coordinates, not with t); where two triangles are that
 * close either may win. */
#define TOL(t) (1e-5f * ((t) + 10.0f))
/* With one_sided, every odd triangle is culled from behind (v0[3], which the
 * kernels' four-triangle leaf test reads lane by lane); the brute force's
 * st_intersect_triangle applies the same rule. Where both find the same
 * triangle, u and v agree within 1e-3 (contracted multiply-adds again). */
static void device_closest_check(int one_sided)
{
    enum { TRIS = 2000, RAYS = 8192 };
    uint64_t seed = 42;
    float *pos = malloc(sizeof(float) * 9 * TRIS);
    for (int t = 0; t < TRIS; t++) {
        float c[3] = {frand(&seed) * 10 - 5, frand(&seed) * 10 - 5, frand(&seed) * 10 - 5};
        for (int v = 0; v < 3; v++)
            for (int a = 0; a < 3; a++)
                pos[9 * t + 3 * v + a] = c[a] + frand(&seed) - 0.5f;
    }
    st_error err = {0};
    st_bvh *bvh;
    assert_int_equal(st_bvh_build(pos, TRIS, &bvh, &err), ST_OK);
    for (int t = 1; one_sided && t < TRIS; t += 2)
        bvh->tris[t].v0[3] = ST_TRI_ONE_SIDED;
    st_bvh_pack_leaves(bvh);
    st_ray *rays = calloc(RAYS, sizeof *rays);
    st_hit *hit = calloc(RAYS, sizeof *hit);
    for (int i = 0; i < RAYS; i++) {
        float d[3] = {frand(&seed) - 0.5f, frand(&seed) - 0.5f, frand(&seed) - 0.5f};
        float n = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (int a = 0; a < 3; a++) {
            rays[i].o[a] = frand(&seed) * 12 - 6;
            rays[i].d[a] = d[a] / n;
        }
        rays[i].tmax = i % 3 ? INFINITY : 3.0f;
    }
    /* the stage's own binding: the scene's BVH and triangles (the other
     * scene buffers unused), a wave of RAYS live paths (depth 0) */
    cl_mem scene[ST_SCENE_BUFFER_COUNT];
    for (int i = 0; i < ST_SCENE_BUFFER_COUNT; i++)
        assert_int_equal(st_device_buffer_create(dev, 16, NULL, &scene[i], &err), ST_OK);
    st_device_buffer_destroy(dev, scene[ST_SCENE_nodes]);
    st_device_buffer_destroy(dev, scene[ST_SCENE_tris]);
    assert_int_equal(st_device_buffer_create(dev, sizeof(st_bvh_wide_node) * (bvh->wide_count + bvh->leaf_slots), bvh->wide, &scene[ST_SCENE_nodes], &err), ST_OK);
    assert_int_equal(st_device_buffer_create(dev, sizeof(st_triangle) * TRIS, bvh->tris, &scene[ST_SCENE_tris], &err), ST_OK);
    st_wave w;
    assert_int_equal(st_wave_create(dev, RAYS, 1, 0, 0, &w, &err), ST_OK);
    assert_int_equal(st_device_buffer_write(dev, w.b[ST_WAVE_ray], sizeof *rays * RAYS, rays, &err), ST_OK);
    assert_int_equal(st_device_buffer_zero(dev, w.b[ST_WAVE_path], st_wave_bytes(&w, ST_WAVE_path), &err), ST_OK);
    st_params p;
    st_shading sh;
    memset(&p, 0, sizeof p);
    memset(&sh, 0, sizeof sh);
    p.item_count = RAYS;
    cl_kernel k;
    assert_int_equal(st_device_kernel(dev, "trace_rays", &k, &err), ST_OK);
    assert_int_equal(st_wave_bind_stage(k, &p, &sh, scene, &w, &err), ST_OK);
    assert_int_equal(st_device_launch(dev, k, RAYS, 0, &err), ST_OK);
    assert_int_equal(st_device_buffer_read(dev, w.b[ST_WAVE_hit], sizeof *hit * RAYS, hit, &err), ST_OK);
    int hits = 0;
    for (int i = 0; i < RAYS; i++) {
        st_ray r = rays[i];
        st_hit best = {r.tmax, 0, 0, ST_NO_HIT};
        for (st_u32 t = 0; t < TRIS; t++) {
            st_hit h = best;
            st_ray rr = r;
            rr.tmax = best.t;
            if (st_intersect_triangle(&bvh->tris[t], &rr, t, &h))
                best = h;
        }
        st_u32 prim = hit[i].prim;
        if (best.prim == ST_NO_HIT) {
            assert_int_equal(prim, ST_NO_HIT);
            continue;
        }
        hits++;
        assert_int_not_equal(prim, ST_NO_HIT);
        if (!(fabsf(hit[i].t - best.t) <= TOL(best.t)))
            fail_msg("ray %d: device t %.9g (triangle %u), host t %.9g (triangle %u)", i,
                     (double)hit[i].t, prim, (double)best.t, best.prim);
        if (prim == best.prim && !(fabsf(hit[i].u - best.u) <= 1e-3f && fabsf(hit[i].v - best.v) <= 1e-3f))
            fail_msg("ray %d: device u, v %.9g %.9g, host %.9g %.9g", i, (double)hit[i].u,
                     (double)hit[i].v, (double)best.u, (double)best.v);
        if (prim != best.prim) { /* a near tie: the device's triangle must be as close */
            st_hit h = {INFINITY, 0, 0, ST_NO_HIT};
            st_ray rr = r;
            rr.tmax = INFINITY;
            assert_true(st_intersect_triangle(&bvh->tris[prim], &rr, prim, &h));
            assert_true(fabsf(h.t - best.t) <= TOL(best.t));
        }
    }
    assert_true(hits > RAYS / 10); /* the test exercises hits, not only misses */
    for (int i = 0; i < ST_SCENE_BUFFER_COUNT; i++)
        st_device_buffer_destroy(dev, scene[i]);
    st_wave_destroy(&w);
    st_bvh_destroy(bvh);
    free(pos); free(rays); free(hit);
}

static void bvh_device_closest_equals_brute_force(void **state)
{
    (void)state;
    device_closest_check(0);
}

static void bvh_device_closest_equals_brute_force_one_sided(void **state)
{
    (void)state;
    device_closest_check(1);
}

/* generate_rays against the definitions, item by item: item g of a
 * per-pixel sampler is region pixel g mod n, sample g / n (n the region's
 * pixels), its film position the pixel plus the sampler's dimensions 0 and
 * 1 (samplers.h on the host), its key and word the sampler's; the camera
 * ray through it is camera.h's at width 1 (to rounding: the device fuses
 * multiply-adds), its path fresh. A wave that starts mid-sample and ends
 * off any lane boundary, over regions wider and narrower than the lanes. */
static void generate_matches_definitions(void **state)
{
    (void)state;
    enum { N = 1003 };
    static const struct {
        st_u32 sampler, region[4];
    } cases[] = {
        {ST_SAMPLER_RANDOM, {0, 0, 37, 23}},
        {ST_SAMPLER_RANDOM, {3, 2, 5, 3}}, /* rows narrower than the lanes */
        {ST_SAMPLER_HALTON, {0, 0, 37, 23}},
        {ST_SAMPLER_HALTON, {6, 1, 1, 7}}, /* one column */
        {ST_SAMPLER_STRATIFIED, {2, 4, 11, 6}},
        {ST_SAMPLER_SOBOL, {0, 0, 37, 23}},
    };
    st_error err = {0};
    cl_mem scene[ST_SCENE_BUFFER_COUNT];
    for (int i = 0; i < ST_SCENE_BUFFER_COUNT; i++)
        assert_int_equal(st_device_buffer_create(dev, 16, NULL, &scene[i], &err), ST_OK);
    st_wave w;
    assert_int_equal(st_wave_create(dev, N, 1, 0, 0, &w, &err), ST_OK);
    cl_kernel k;
    assert_int_equal(st_device_kernel(dev, "generate_rays", &k, &err), ST_OK);
    size_t lanes = st_device_get_info(dev)->lanes;
    st_sample *smp = calloc(N, sizeof *smp);
    st_ray *ray = calloc(N, sizeof *ray);
    st_path *path = calloc(N, sizeof *path);
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        st_params p;
        st_shading sh;
        memset(&p, 0, sizeof p);
        memset(&sh, 0, sizeof sh);
        p.width = 37, p.height = 23, p.spp = 64, p.seed = 5, p.sampler = cases[c].sampler;
        p.region_x = cases[c].region[0], p.region_y = cases[c].region[1];
        p.region_w = cases[c].region[2], p.region_h = cases[c].region[3];
        st_sampler_prepare(&p);
        st_camera cam = {{0.0f, 1.0f, 4.0f, 0.41f}, {1.0f, 0.0f, 0.0f, 37.0f / 23.0f},
                         {0.0f, 1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f, 0.0f}};
        p.camera = cam;
        st_u32 npix = p.region_w * p.region_h;
        p.first_item = 3ull * npix + 11u;
        p.item_count = N;
        assert_int_equal(st_wave_bind_stage(k, &p, &sh, scene, &w, &err), ST_OK);
        assert_int_equal(st_device_launch(dev, k, (N + lanes - 1) / lanes, 0, &err), ST_OK);
        assert_int_equal(st_device_buffer_read(dev, w.b[ST_WAVE_sample], sizeof *smp * N, smp, &err), ST_OK);
        assert_int_equal(st_device_buffer_read(dev, w.b[ST_WAVE_ray], sizeof *ray * N, ray, &err), ST_OK);
        assert_int_equal(st_device_buffer_read(dev, w.b[ST_WAVE_path], sizeof *path * N, path, &err), ST_OK);
        for (st_u32 i = 0; i < N; i++) {
            st_u64 g = p.first_item + i;
            st_u32 j = (st_u32)(g % npix), s = (st_u32)(g / npix);
            st_u32 px = p.region_x + j % p.region_w, py = p.region_y + j / p.region_w;
            st_sample_id id = st_sample_begin(&p, px, py, s);
            float fx = (float)px + st_sample_dim(&p, &id, 0u);
            float fy = (float)py + st_sample_dim(&p, &id, 1u);
            if (smp[i].film[0] != fx || smp[i].film[1] != fy || smp[i].pixel != id.pixel ||
                smp[i].index != s || smp[i].key != id.key || smp[i].word != st_sample_word(&p, &id))
                fail_msg("case %zu item %u: sample (%g, %g) pixel %u index %u, the definition's "
                         "(%g, %g) pixel %u index %u", c, i, smp[i].film[0], smp[i].film[1],
                         smp[i].pixel, smp[i].index, fx, fy, id.pixel, s);
            st_lv3 o, d;
            st_camera_rays(&cam, p.width, p.height, fx, fy, &o, &d);
            float want[6] = {o.x, o.y, o.z, d.x, d.y, d.z};
            float got[6] = {ray[i].o[0], ray[i].o[1], ray[i].o[2],
                            ray[i].d[0], ray[i].d[1], ray[i].d[2]};
            for (int a = 0; a < 6; a++)
                if (fabsf(got[a] - want[a]) > 1e-6f)
                    fail_msg("case %zu item %u: ray component %d %.9g, camera.h's %.9g", c, i, a,
                             got[a], want[a]);
            assert_true(isinf(ray[i].tmax) && path[i].depth == 0u && path[i].beta[0] == 1.0f &&
                        path[i].radiance[1] == 0.0f);
        }
    }
    free(smp);
    free(ray);
    free(path);
    st_wave_destroy(&w);
    for (int i = 0; i < ST_SCENE_BUFFER_COUNT; i++)
        st_device_buffer_destroy(dev, scene[i]);
}

static void assert_same_bits(const st_image *a, const st_image *b)
{
    assert_int_equal(a->width, b->width);
    assert_int_equal(a->height, b->height);
    assert_int_equal(a->channels, b->channels);
    assert_memory_equal(a->data, b->data, sizeof(float) * a->width * a->height * a->channels);
}

static void render_same_bits_twice(void **state)
{
    (void)state;
    st_render_options o = small(40, 30, 4);
    st_image a = render("cornell-box", &o, NULL), b = render("cornell-box", &o, NULL);
    assert_same_bits(&a, &b);
    st_image_free(&a);
    st_image_free(&b);
}

/* FNV-1a over n bytes, continuing from h. */
static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

/* Every byte a loaded scene holds: the struct and each array it owns. */
static uint64_t scene_hash(const st_scene *s)
{
    uint64_t h = fnv(14695981039346656037ull, s, sizeof *s);
    h = fnv(h, s->positions, 9 * sizeof(float) * s->tri_count);
    h = fnv(h, s->normals, 9 * sizeof(float) * s->tri_count);
    h = fnv(h, s->uvs, 6 * sizeof(float) * s->tri_count);
    if (s->uvs1)
        h = fnv(h, s->uvs1, 6 * sizeof(float) * s->tri_count);
    h = fnv(h, s->tri_material, sizeof(st_u32) * s->tri_count);
    h = fnv(h, s->materials, sizeof(st_material) * s->material_count);
    h = fnv(h, s->textures, sizeof(st_texture) * s->texture_count);
    h = fnv(h, s->texels, sizeof(st_u32) * s->texel_count);
    return fnv(h, s->cameras, sizeof(st_scene_camera) * s->camera_count);
}

/* One renderer renders several views of one scene (camera, environment,
 * texture filter) without touching it: every view equals a render of it by
 * a fresh renderer, the views differ, and the scene's bytes do not change. */
static void one_renderer_many_views(void **state)
{
    (void)state;
    st_error err = {0};
    st_scene *scene = NULL;
    st_renderer *r = NULL;
    if (st_scene_load("tests/scenes/camera_pick.gltf", &scene, &err) ||
        st_renderer_create(dev, scene, &r, &err))
        fail_msg("camera_pick: %s", err.msg);
    uint64_t before = scene_hash(scene);
    st_render_options v[3] = {small(24, 16, 2), small(24, 16, 2), small(24, 16, 2)};
    v[1].camera = 3;
    v[2].env_given = 1;
    v[2].env[0] = 0.25f;
    v[2].texture_filter = ST_TEXFILTER_NONE;
    st_image img[3], again;
    for (int i = 0; i < 3; i++)
        if (st_render(r, &v[i], &img[i], NULL, NULL, NULL, NULL, &err))
            fail_msg("view %d: %s", i, err.msg);
    assert_true(scene_hash(scene) == before);
    for (int i = 0; i < 3; i++) {
        again = render("tests/scenes/camera_pick.gltf", &v[i], NULL);
        assert_same_bits(&img[i], &again);
        st_image_free(&again);
    }
    size_t bytes = sizeof(float) * img[0].width * img[0].height * img[0].channels;
    assert_true(memcmp(img[0].data, img[1].data, bytes) != 0);
    assert_true(memcmp(img[0].data, img[2].data, bytes) != 0);
    v[0].camera = (st_i32)scene->camera_count;
    assert_int_equal(st_render(r, &v[0], &again, NULL, NULL, NULL, NULL, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "camera nodes"));
    for (int i = 0; i < 3; i++)
        st_image_free(&img[i]);
    st_renderer_destroy(r);
    st_scene_destroy(scene);
}

static void render_same_bits_any_wave_and_group_size(void **state)
{
    (void)state;
    st_u32 samplers[] = {ST_SAMPLER_RANDOM, ST_SAMPLER_STRATIFIED, ST_SAMPLER_HALTON,
                         ST_SAMPLER_SOBOL};
    for (size_t s = 0; s < sizeof samplers / sizeof samplers[0]; s++) {
        st_render_options o = small(37, 23, 4);
        o.sampler = samplers[s];
        st_image a = render("cornell-box", &o, NULL);
        o.wave = 1001;
        o.local_size = 16;
        st_image b = render("cornell-box", &o, NULL);
        o.wave = 333;
        o.local_size = 1;
        st_image c = render("cornell-box", &o, NULL);
        assert_same_bits(&a, &b);
        assert_same_bits(&a, &c);
        st_image_free(&a);
        st_image_free(&b);
        st_image_free(&c);
    }
}

/* Sample ranges [0, 3) + [3, 8) give the sums of [0, 8), bit for bit. */
static void render_split_sums_add_to_whole(void **state)
{
    (void)state;
    st_render_options o = small(24, 20, 8);
    o.sampler = ST_SAMPLER_STRATIFIED;
    st_i64 *whole, *p1, *p2;
    st_image a = render("cornell-box", &o, &whole);
    o.sample_end = 3;
    st_image b = render("cornell-box", &o, &p1);
    o.sample_begin = 3;
    o.sample_end = 8;
    st_image c = render("cornell-box", &o, &p2);
    for (size_t i = 0; i < 4u * 24 * 20; i++)
        assert_true(p1[i] + p2[i] == whole[i]);
    free(whole); free(p1); free(p2);
    st_image_free(&a); st_image_free(&b); st_image_free(&c);
}

/* The furnace at max depth 0 shows radiance 1 along every ray: the weighted
 * average Σ f L / Σ f is then 1 for any filter (negative lobes included) and
 * any sampler, up to the fixed-point resolution (2^-24 per add). */
static void constant_radiance_reconstructs_exactly(void **state)
{
    (void)state;
    for (st_u32 s = 0; s < ST_SAMPLER_COUNT; s++) {
        for (st_u32 f = 0; f < ST_FILTER_COUNT; f++) {
            st_render_options o = small(12, 10, 4);
            o.sampler = s;
            o.filter = st_filter_default(f);
            o.max_depth = 0;
            st_image img = render("furnace", &o, NULL);
            for (size_t i = 0; i < 12u * 10; i++)
                for (int c = 0; c < 3; c++)
                    if (fabsf(img.data[4 * i + c] - 1.0f) > 1e-5f)
                        fail_msg("sampler %s filter %s pixel %zu: %.9g", st_sampler_names[s],
                                 st_filter_names[f], i, (double)img.data[4 * i + c]);
            st_image_free(&img);
        }
    }
}

/* Filter importance sampling: each sample lands in its own pixel with weight
 * sign(f). A non-negative filter gives weight 1 everywhere, so a constant
 * scene is reproduced exactly; with lanczos's negative lobes Σ w L / Σ w is
 * still the constant wherever Σ w != 0, negative sums included (some pixels
 * must have one, or the check would prove nothing), and only Σ w = 0 gives 0,
 * counted. */
static void fis_constant_radiance(void **state)
{
    (void)state;
    st_u32 filters[] = {ST_FILTER_BOX, ST_FILTER_GAUSSIAN, ST_FILTER_LANCZOS};
    for (int k = 0; k < 3; k++) {
        st_render_options o = small(16, 12, 4);
        o.reconstruction = ST_RECON_FIS;
        o.filter = st_filter_default(filters[k]);
        o.max_depth = 0;
        st_render_stats st;
        st_image img = render_stats("furnace", &o, &st);
        st_u32 zero = 0, negative = 0;
        for (size_t i = 0; i < 16u * 12; i++) {
            float v = img.data[4 * i], w = img.data[4 * i + 3];
            if (w == 0.0f)
                assert_true(v == 0.0f);
            else
                assert_true(fabsf(v - 1.0f) <= 1e-6f);
            zero += w == 0.0f;
            negative += w < 0.0f;
        }
        assert_int_equal(zero, st.zero_weight);
        if (filters[k] == ST_FILTER_LANCZOS)
            assert_true(negative > 0 && zero > 0);
        st_image_free(&img);
    }
}

/* Every sampler gives every pixel exactly spp samples: with the box filter
 * (radius 1/2) a sample weighs 1 in its own pixel only, so the weight sum W
 * of every pixel is spp, and the furnace is 1 everywhere. 70 x 10 pixels:
 * for the tiled samplers one whole 64-pixel tile and a cut one across;
 * spp 1, 3 and 5. */
static void every_sampler_gives_every_pixel_spp(void **state)
{
    (void)state;
    st_u32 spps[3] = {1, 3, 5};
    for (st_u32 s = 0; s < ST_SAMPLER_COUNT; s++)
        for (int k = 0; k < 3; k++) {
            st_render_options o = small(70, 10, spps[k]);
            o.sampler = s;
            o.filter = st_filter_default(ST_FILTER_BOX);
            o.max_depth = 0;
            st_render_stats st;
            st_image img = render_stats("furnace", &o, &st);
            if (st.zero_weight)
                fail_msg("sampler %s spp %u: %u pixels without weight", st_sampler_names[s],
                         spps[k], st.zero_weight);
            for (size_t i = 0; i < 70u * 10; i++)
                if (img.data[4 * i + 3] != (float)spps[k] || img.data[4 * i] != 1.0f)
                    fail_msg("sampler %s spp %u pixel %zu: W %g value %g", st_sampler_names[s],
                             spps[k], i, (double)img.data[4 * i + 3], (double)img.data[4 * i]);
            st_image_free(&img);
        }
}

/* The overflow guard: radiance 10^5 (tests/scenes/hot-furnace.gltf) is above
 * ST_SPLAT_MAX = 2^16, so with a box filter every splat is clamped to 2^16
 * and counted; at 10^4 nothing is. */
static void splat_clamp_trips_above_limit(void **state)
{
    (void)state;
    st_render_options o = small(8, 6, 2);
    o.filter = st_filter_default(ST_FILTER_BOX);
    o.max_depth = 0;
    st_render_stats st;
    st_image img = render_stats("tests/scenes/hot-furnace.gltf", &o, &st);
    assert_int_equal(st.clamped, 8 * 6 * 2);
    for (size_t i = 0; i < 8u * 6; i++)
        assert_true(img.data[4 * i] == ST_SPLAT_MAX);
    st_image_free(&img);
    st_render_options ok = small(8, 6, 2);
    ok.max_depth = 0;
    st_image one = render("furnace", &ok, NULL);
    for (size_t i = 0; i < 8u * 6; i++)
        assert_true(fabsf(one.data[4 * i] - 1.0f) < 1e-6f);
    st_image_free(&one);
}

/* Renders `name` with o once by each reconstruction path, profiled: per
 * sample (the reference), tiles whose work-group shares the window (local
 * atomics) and tiles each owned by one work-item (plain adds); the films
 * (raw sums) and counts must be equal bit for bit, and each path must have
 * run only its own kernels. Returns whether the tile paths were used. */
static int same_film_both_splats(const char *name, st_render_options o)
{
    static const int paths[3] = {ST_SPLAT_PER_SAMPLE, ST_SPLAT_TILES, ST_SPLAT_TILES_ALONE};
    st_error err = {0};
    st_scene *scene = NULL;
    st_renderer *r = NULL;
    if (st_scene_load(name, &scene, &err) || st_renderer_create(dev, scene, &r, &err))
        fail_msg("load %s: %s", name, err.msg);
    o.profile = 1;
    st_i64 *sums[3];
    st_render_stats st[3];
    for (int k = 0; k < 3; k++) {
        st_image img = {0};
        forced.splat = paths[k];
        st_renderer_force(r, &forced);
        if (st_render(r, &o, &img, &sums[k], &st[k], NULL, NULL, &err))
            fail_msg("render %s: %s", name, err.msg);
        st_image_free(&img);
        free(st[k].spp_map);
    }
    forced.splat = ST_SPLAT_AUTO;
    size_t n = (size_t)o.width * o.height * 4;
    assert_true(st[0].stage_seconds[ST_STAGE_SPLAT] > 0.0);
    assert_true(st[0].stage_seconds[ST_STAGE_SPLAT_TILES] == 0.0);
    int tiles = st[1].stage_seconds[ST_STAGE_SPLAT_TILES] > 0.0;
    /* the counting sort runs where items do not lie in their pixels in
     * order: a tiled sampler's, and an adaptive render's rounds */
    int sorted = tiles && (st_sampler_is_tiled(o.sampler) || o.adaptive);
    for (int k = 1; k < 3; k++) {
        assert_memory_equal(sums[0], sums[k], n * sizeof(st_i64));
        assert_true(st[0].splats == st[k].splats && st[0].rays == st[k].rays);
        assert_int_equal(st[0].clamped, st[k].clamped);
        assert_int_equal(st[0].nonfinite, st[k].nonfinite);
        assert_true(tiles == (st[k].stage_seconds[ST_STAGE_SPLAT_TILES] > 0.0));
        assert_true(sorted == (st[k].stage_seconds[ST_STAGE_BIN] > 0.0));
        assert_true(tiles == (st[k].stage_seconds[ST_STAGE_SPLAT] == 0.0));
    }
    for (int k = 0; k < 3; k++)
        free(sums[k]);
    st_renderer_destroy(r);
    st_scene_destroy(scene);
    return tiles;
}

/* The tile-owned splat (bin_samples, splat_tiles), shared by a work-group
 * or owned by one work-item, adds the integers of the per-sample splat
 * (splat_samples), so the films are equal bit for bit: for
 * box, mitchell and lanczos, over several waves (small waves: the bins are
 * reset between them), on an image that is not a whole number of tiles, for
 * a split part, a tiled sampler (points off the image), clamped splats (the
 * hot furnace: a sample counts once however many taps clamp); filter
 * importance sampling always takes the per-sample path; an adaptive render
 * (its later splats weighted by splat_scale) takes either. */
static void tile_splat_equals_per_sample(void **state)
{
    (void)state;
    static const st_u32 filters[] = {ST_FILTER_BOX, ST_FILTER_MITCHELL, ST_FILTER_LANCZOS};
    for (size_t f = 0; f < sizeof filters / sizeof filters[0]; f++) {
        st_render_options o = small(70, 45, 4);
        o.filter = st_filter_default(filters[f]);
        o.wave = 1000;
        assert_true(same_film_both_splats("cornell-box", o));
    }
    st_render_options part = small(70, 45, 8);
    part.sample_begin = 3;
    part.sample_end = 6;
    assert_true(same_film_both_splats("cornell-box", part));
    st_render_options tiled = small(70, 45, 4);
    tiled.sampler = ST_SAMPLER_POISSON;
    tiled.filter = st_filter_default(ST_FILTER_LANCZOS);
    assert_true(same_film_both_splats("cornell-box", tiled));
    st_render_options hot = small(20, 12, 2);
    hot.filter = st_filter_default(ST_FILTER_LANCZOS);
    hot.max_depth = 0;
    assert_true(same_film_both_splats("tests/scenes/hot-furnace.gltf", hot));
    st_render_options adaptive = small(24, 20, 16); /* its later samples weighted */
    adaptive.adaptive = 1;
    adaptive.min_spp = 4;
    adaptive.sampler = ST_SAMPLER_RANDOM; /* others render uniformly */
    assert_true(same_film_both_splats("cornell-box", adaptive));
    adaptive.reconstruction = ST_RECON_FIS;
    assert_false(same_film_both_splats("cornell-box", adaptive));
}

/* Shadow rays traced inside shade_hits (shade_hits_shadowed, selected by
 * forced.shadow) and as a stage of their own (trace_shadow_rays) give the
 * same film bit for bit and the same counts, and each runs only its own
 * kernels: paths and direct lighting in the Cornell box, and shadows
 * through alpha cut-outs and blended surfaces (shadow.h's walk). */
static void shadows_in_shade_equal_stage(void **state)
{
    (void)state;
    static const char *scenes[] = {"cornell-box", "cornell-box", "tests/scenes/shadow_cutout.gltf",
                                   "tests/scenes/shadow_blend.gltf"};
    for (size_t c = 0; c < sizeof scenes / sizeof scenes[0]; c++) {
        st_render_options o = small(40, 30, 4);
        o.integrator = c == 1 ? ST_INTEGRATOR_DIRECT : ST_INTEGRATOR_PATH;
        o.profile = 1;
        st_i64 *sums[2];
        st_render_stats st[2];
        for (int k = 0; k < 2; k++) {
            forced.shadow = k ? ST_SHADOW_IN_SHADE : ST_SHADOW_STAGE;
            st_image img = render_sums_stats(scenes[c], &o, &sums[k], &st[k]);
            forced.shadow = ST_SHADOW_AUTO;
            st_image_free(&img);
            free(st[k].spp_map);
        }
        assert_memory_equal(sums[0], sums[1], (size_t)o.width * o.height * 4 * sizeof(st_i64));
        assert_true(st[0].shadow_rays > 0 && st[0].shadow_rays == st[1].shadow_rays);
        assert_true(st[0].rays == st[1].rays && st[0].splats == st[1].splats);
        assert_true(st[0].stage_seconds[ST_STAGE_SHADOW] > 0.0);
        assert_true(st[1].stage_seconds[ST_STAGE_SHADOW] == 0.0);
        assert_true(st[1].stage_seconds[ST_STAGE_SHADE] > 0.0);
        free(sums[0]);
        free(sums[1]);
    }
}

/* Furnace: emission 1 and albedo 1/2 on every wall of a closed cube, so the
 * radiance along every camera ray is Σ_{k=0..D} 2^-k. The mean of 32x32
 * pixels at 64 spp has a standard error near 0.3%; tolerance 1.5%. */
static void furnace_matches_closed_form(void **state)
{
    (void)state;
    for (st_u32 depth = 1; depth <= 6; depth += 5) {
        for (st_u32 integ = 0; integ < 2; integ++) {
            st_render_options o = small(32, 32, 64);
            o.integrator = integ;
            o.max_depth = depth;
            st_image img = render("furnace", &o, NULL);
            double sum = 0, want = 0;
            st_u32 d = integ == ST_INTEGRATOR_DIRECT ? 1 : depth;
            for (st_u32 k = 0; k <= d; k++)
                want += pow(0.5, k);
            for (size_t i = 0; i < 32u * 32; i++)
                sum += img.data[4 * i] + img.data[4 * i + 1] + img.data[4 * i + 2];
            double mean = sum / (3.0 * 32 * 32);
            if (fabs(mean / want - 1.0) > 0.015)
                fail_msg("%s depth %u: mean %.5f, closed form %.5f", st_integrator_names[integ],
                         depth, mean, want);
            st_image_free(&img);
        }
    }
}

/* A glass cube face-on to an orthographic camera in a uniform environment
 * of radiance 1 (tests/scenes/glass_slab.gltf: ior 1.5, attenuationColor
 * 0.5 after attenuationDistance 1, the cube's depth). Every ray meets both
 * faces at normal incidence, R = ((1.5 - 1) / (1.5 + 1))² = 0.04, T = 1 - R,
 * and the light inside bounces between the faces, losing A = 0.5 per
 * crossing: the radiance seen is R + T² A / (1 - R A) (the geometric series
 * of the inside). Outside the cube's face the environment, 1. Pixel means
 * over 512 samples, whose noise (Fresnel's choice between reflection and
 * refraction; Russian roulette) is below 0.01. Breaks with the absorption,
 * the Fresnel weight, the η² of the radiance BTDF or the side a refracted
 * ray goes on from. */
static void glass_slab_matches_closed_form(void **state)
{
    (void)state;
    st_render_options o = small(16, 16, 512);
    o.filter = st_filter_default(ST_FILTER_BOX);
    o.integrator = ST_INTEGRATOR_PATH;
    o.max_depth = 24;
    o.env_given = 1;
    o.env[0] = o.env[1] = o.env[2] = 1.0f;
    st_image img = render("tests/scenes/glass_slab.gltf", &o, NULL);
    const double r = 0.04, t = 1.0 - r, a = 0.5, want = r + t * t * a / (1.0 - r * a);
    double inside = 0.0, outside = 0.0;
    int n_in = 0, n_out = 0;
    for (st_u32 y = 0; y < 16; y++)
        for (st_u32 x = 0; x < 16; x++) {
            double v = img.data[4 * (y * 16 + x) + 1];
            int in = x >= 5 && x <= 10 && y >= 5 && y <= 10; /* well inside the face's half */
            int out = x <= 2 || x >= 13 || y <= 2 || y >= 13;
            inside += in ? v : 0.0;
            outside += out ? v : 0.0;
            n_in += in, n_out += out;
        }
    inside /= n_in, outside /= n_out;
    if (fabs(inside - want) > 0.01 || fabs(outside - 1.0) > 1e-5)
        fail_msg("glass slab: %.5f inside (closed form %.5f), %.5f outside (1)", inside, want,
                 outside);
    st_image_free(&img);
}

/* A closed smooth glass object loses no light: in a uniform environment of
 * radiance 1 with nothing else (tests/scenes/glass_furnace.gltf, the left
 * sphere, radius 0.8 about x = -1, 8 pixels per unit), every pixel whose
 * rays meet the sphere well inside its outline is 1 up to the noise of
 * Russian roulette and of paths cut at the depth limit inside (0.03 per
 * pixel, 0.005 in their mean; the outline's pixels, where interpolated
 * normals bend rays below the facets, are left out); the rough sphere
 * (right) loses what single scattering loses, and never shows more than 1. */
static void glass_furnace(void **state)
{
    (void)state;
    st_render_options o = small(32, 16, 256);
    o.filter = st_filter_default(ST_FILTER_BOX);
    o.integrator = ST_INTEGRATOR_PATH;
    o.max_depth = 32;
    o.env_given = 1;
    o.env[0] = o.env[1] = o.env[2] = 1.0f;
    st_image img = render("tests/scenes/glass_furnace.gltf", &o, NULL);
    double smooth = 0.0, rough = 0.0;
    int n_smooth = 0;
    for (st_u32 y = 0; y < 16; y++)
        for (st_u32 x = 0; x < 32; x++) {
            double v = img.data[4 * (y * 32 + x)];
            double px = -2.0 + (x + 0.5) / 8.0, py = 1.0 - (y + 0.5) / 8.0;
            if (x >= 16) {
                rough += v;
                continue;
            }
            if ((px + 1.0) * (px + 1.0) + py * py > 0.6 * 0.6)
                continue;
            smooth += v;
            n_smooth++;
            if (fabs(v - 1.0) > 0.03)
                fail_msg("smooth glass, pixel (%u, %u): %.4f, want 1", x, y, v);
        }
    smooth /= n_smooth, rough /= 16 * 16;
    if (fabs(smooth - 1.0) > 0.005 || !(rough <= 1.0 + 0.005) || !(rough > 0.8))
        fail_msg("glass furnace: smooth mean %.5f (1), rough mean %.5f (<= 1)", smooth, rough);
    st_image_free(&img);
}

/* The smooth sphere of glass_furnace coarse (tests/scenes/
 * glass_furnace_coarse.gltf: 6 rings, 8 segments, smooth normals), its
 * outline included: at a refracting surface the interpolated shading
 * normal is taken as it is and a sample's side is the geometry's
 * (integrator.h vertex_bounce), as Mitsuba 3's dielectrics do, so no path
 * ends where the shading normal strays from the facet's, and every pixel
 * within the facets' inscribed circle (radius 0.8 cos(pi / 8)) stays within
 * 0.06 of 1 (the noise of 256 samples and roulette, 0.03, and what crossing
 * a facet with the other side's shading frame leaves), their mean within
 * 0.005. Ending those paths, as before, left pixels of the outline at 0.56
 * and the mean at 0.983. */
static void glass_furnace_coarse_keeps_the_outline(void **state)
{
    (void)state;
    st_render_options o = small(64, 32, 256);
    o.filter = st_filter_default(ST_FILTER_BOX);
    o.integrator = ST_INTEGRATOR_PATH;
    o.max_depth = 32;
    o.env_given = 1;
    o.env[0] = o.env[1] = o.env[2] = 1.0f;
    st_image img = render("tests/scenes/glass_furnace_coarse.gltf", &o, NULL);
    double sum = 0.0, lowest = 1.0;
    int n = 0;
    for (st_u32 y = 0; y < 32; y++)
        for (st_u32 x = 0; x < 32; x++) {
            double v = img.data[4 * (y * 64 + x)];
            double px = -2.0 + (x + 0.5) / 16.0, py = 1.0 - (y + 0.5) / 16.0;
            if ((px + 1.0) * (px + 1.0) + py * py > pow(0.8 * cos(3.14159265358979 / 8.0), 2))
                continue;
            sum += v;
            n++;
            lowest = fmin(lowest, v);
            if (fabs(v - 1.0) > 0.06)
                fail_msg("coarse smooth glass, pixel (%u, %u): %.4f, want 1", x, y, v);
        }
    print_message("coarse glass furnace: %d pixels, mean %.5f, lowest %.4f\n", n, sum / n, lowest);
    if (fabs(sum / n - 1.0) > 0.005)
        fail_msg("coarse glass furnace: mean %.5f, want 1", sum / n);
    st_image_free(&img);
}

/* A full smooth clear coat (KHR_materials_clearcoat, ior 1.5) over a black
 * Lambertian base reflects the coat's Fresnel alone, F0 = 0.04 face-on: in
 * a uniform environment of radiance 1 an orthographic camera sees 0.04
 * (tests/scenes/coat_quad.gltf, left quad); over a white base (right) the
 * coat and what the base returns through it stay below 1 and above what
 * the base would return through the coat if the coat took F90 everywhere
 * (0.04 + 0.96 x 0.5). Breaks with a coat that is not added, or that adds
 * without taking from the base. */
static void coat_matches_its_fresnel(void **state)
{
    (void)state;
    st_render_options o = in_white_env(32, 16, 256);
    st_image img = render("tests/scenes/coat_quad.gltf", &o, NULL);
    double black = 0.0, white = 0.0;
    for (st_u32 y = 2; y < 14; y++)
        for (st_u32 x = 2; x < 30; x++) {
            if (x >= 14 && x < 18)
                continue;
            double v = img.data[4 * (y * 32 + x) + 1];
            if (x < 16)
                black += v;
            else
                white += v;
        }
    black /= 12 * 12, white /= 12 * 12;
    if (fabs(black - 0.04) > 0.002 || !(white < 1.0) || !(white > 0.52))
        fail_msg("coat over black %.5f (0.04), over white %.5f (0.52 .. 1)", black, white);
    st_image_free(&img);
}

/* The Charlie sheen's directional albedo E(μo) at α (white; KHR_materials_sheen's
 * definition, in double): ∫ D V cos θi dωi by the midpoint rule in
 * (cos θi, φ), computed here apart from the kernels and their table. */
static double sheen_fit(double x, double a)
{
    double t = (1.0 - a) * (1.0 - a);
    return (21.5473 + (25.3245 - 21.5473) * t) /
               (1.0 + (3.82987 + (3.32435 - 3.82987) * t) * pow(x, 0.19823 + (0.16801 - 0.19823) * t)) +
           (-1.97760 + (-1.27393 + 1.97760) * t) * x + (-4.32054 + (-4.85967 + 4.32054) * t);
}

static double sheen_lambda(double mu, double a)
{
    return mu < 0.5 ? exp(sheen_fit(mu, a)) : exp(2.0 * sheen_fit(0.5, a) - sheen_fit(1.0 - mu, a));
}

static double sheen_albedo(double mo, double a)
{
    const int nmu = 400, nphi = 200;
    double so = sqrt(1.0 - mo * mo), lo = sheen_lambda(mo, a), sum = 0.0;
    for (int i = 0; i < nmu; i++) {
        double mi = (i + 0.5) / nmu, si = sqrt(1.0 - mi * mi);
        double v = 1.0 / ((1.0 + lo + sheen_lambda(mi, a)) * 4.0 * mo);
        for (int j = 0; j < nphi; j++) {
            double ph = 3.14159265358979323846 * (j + 0.5) / nphi;
            double hx = so + si * cos(ph), hy = si * sin(ph), hz = mo + mi;
            double s2 = (hx * hx + hy * hy) / (hx * hx + hy * hy + hz * hz);
            sum += (2.0 + 1.0 / a) / (2.0 * 3.14159265358979323846) * pow(s2, 0.5 / a) * v;
        }
    }
    return sum * 2.0 * 3.14159265358979323846 / ((double)nmu * nphi);
}

/* KHR_materials_sheen in a uniform environment of radiance 1, on two
 * Lambertian quads seen at cos 0.5 by an orthographic camera
 * (tests/scenes/sheen_quad.gltf): over a black base (left; its colour and
 * roughness through textures) each channel shows colour x E(0.5); over a
 * white base (right) the sheen's 0.8 E(0.5) plus what the albedo scaling
 * leaves of the Lambertian, ∫ max(0, 1 - 0.8 max(E(0.5), E(μi))) 2 μi dμi,
 * with E computed here from the definition. Tolerance 0.4 % (the kernels'
 * table is bilinear, between its nodes) plus 0.001 (noise: 256 samples of
 * 144 pixels; both quads agreed to 1e-4 when written). Breaks with a sheen not added, not scaled, or its textures
 * not read. */
static void sheen_matches_its_albedo(void **state)
{
    (void)state;
    st_render_options o = in_white_env(32, 16, 256);
    st_image img = render("tests/scenes/sheen_quad.gltf", &o, NULL);
    double left[3] = {0.0, 0.0, 0.0}, right = 0.0;
    for (st_u32 y = 5; y < 11; y++) /* the quads span rows 4 .. 11 */
        for (st_u32 x = 2; x < 30; x++) {
            if (x >= 14 && x < 18)
                continue;
            for (int k = 0; k < 3; k++)
                if (x < 16)
                    left[k] += img.data[4 * (y * 32 + x) + k] / (12.0 * 6.0);
            if (x >= 16)
                right += img.data[4 * (y * 32 + x) + 1] / (12.0 * 6.0);
        }
    double r = 128.0 / 255.0, e = sheen_albedo(0.5, r * r);
    const double colour[3] = {1.0, 0.5, 0.25};
    for (int k = 0; k < 3; k++)
        if (fabs(left[k] - colour[k] * e) > 0.004 * colour[k] * e + 0.001)
            fail_msg("sheen over black, channel %d: %.5f, want %.5f", k, left[k], colour[k] * e);
    double e5 = sheen_albedo(0.5, 0.25), kept = 0.0;
    const int n = 100;
    for (int i = 0; i < n; i++) {
        double mi = (i + 0.5) / n;
        kept += fmax(0.0, 1.0 - 0.8 * fmax(e5, sheen_albedo(mi, 0.25))) * 2.0 * mi / n;
    }
    double want = 0.8 * e5 + kept;
    if (fabs(right - want) > 0.004 * want + 0.001 || !(right <= 1.0))
        fail_msg("sheen over white: %.5f, want %.5f", right, want);
    st_image_free(&img);
}

/* The directional albedo ∫ D V cos θi dωi of a white metal (F = 1) with
 * anisotropic GGX, α_t along x and α_b along y, towards wo = (sin θo cos ψ,
 * sin θo sin ψ, μo): the KHR_materials_anisotropy definition in double
 * (D = 1 / (π α_t α_b ((h.x / α_t)² + (h.y / α_b)² + h.z²)²), V = 1 / (2
 * (μi Λ'(o) + μo Λ'(i))), Λ'(w) = sqrt((α_t w.x)² + (α_b w.y)² + w.z²)),
 * by the midpoint rule in (cos θi, φ), apart from the kernels' code. */
static double aniso_albedo(double mo, double psi, double at, double ab)
{
    const int nmu = 600, nphi = 600;
    const double pi = 3.14159265358979323846, so = sqrt(1.0 - mo * mo);
    double o[3] = {so * cos(psi), so * sin(psi), mo}, sum = 0.0;
    double lo = sqrt(at * at * o[0] * o[0] + ab * ab * o[1] * o[1] + mo * mo);
    for (int i = 0; i < nmu; i++) {
        double mi = (i + 0.5) / nmu, si = sqrt(1.0 - mi * mi);
        for (int j = 0; j < nphi; j++) {
            double ph = 2.0 * pi * (j + 0.5) / nphi, w[3] = {si * cos(ph), si * sin(ph), mi};
            double h[3] = {o[0] + w[0], o[1] + w[1], o[2] + w[2]};
            double n = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
            double x = h[0] / n / at, y = h[1] / n / ab, t = x * x + y * y + h[2] * h[2] / (n * n);
            double d = 1.0 / (pi * at * ab * t * t);
            double li = sqrt(at * at * w[0] * w[0] + ab * ab * w[1] * w[1] + mi * mi);
            sum += d * 0.5 / (mi * lo + mo * li) * mi;
        }
    }
    return sum * 2.0 * pi / ((double)nmu * nphi);
}

/* KHR_materials_anisotropy in a uniform environment of radiance 1, on two
 * white metal quads seen at cos 0.5 by an orthographic camera
 * (tests/scenes/aniso_quad.gltf), each showing its directional albedo
 * (a flat quad sees only the environment). Left: roughness 0.4, strength
 * 0.8 x the texture's B (128 / 255), the texture's direction (1, 1) turned
 * counter-clockwise by 0.5 radians from the tangent (u, along x); wo lies
 * in the plane of the normal and the bitangent, so its azimuth from the
 * anisotropy direction is π/4 - 0.5 (the albedo is even in it). Right:
 * roughness 0.3, isotropic. Tolerance 0.3 % plus 0.001 (noise of 256
 * samples of 72 pixels). Breaks with the strength, texture, rotation (its
 * sense: the check below that π/4 + 0.5 would be told apart) or frame
 * wrong. */
static void anisotropy_matches_its_albedo(void **state)
{
    (void)state;
    st_render_options o = in_white_env(32, 16, 256);
    st_image img = render("tests/scenes/aniso_quad.gltf", &o, NULL);
    double left = 0.0, right = 0.0;
    for (st_u32 y = 5; y < 11; y++) /* the quads span rows 4 .. 11 */
        for (st_u32 x = 2; x < 30; x++) {
            if (x >= 14 && x < 18)
                continue;
            double v = img.data[4 * (y * 32 + x) + 1] / (12.0 * 6.0);
            if (x < 16)
                left += v;
            else
                right += v;
        }
    const double pi = 3.14159265358979323846, s = 0.8 * 128.0 / 255.0;
    double ab = 0.4 * 0.4, at = ab + (1.0 - ab) * s * s;
    double want = aniso_albedo(0.5, pi / 4 - 0.5, at, ab);
    double wrong = aniso_albedo(0.5, pi / 4 + 0.5, at, ab);
    double iso = aniso_albedo(0.5, 0.0, 0.09, 0.09);
    assert_true(fabs(want - wrong) > 0.01 * want); /* the test tells the senses apart */
    if (fabs(left - want) > 0.003 * want + 0.001)
        fail_msg("anisotropic: %.5f, want %.5f (turned the other way: %.5f)", left, want, wrong);
    if (fabs(right - iso) > 0.003 * iso + 0.001)
        fail_msg("isotropic: %.5f, want %.5f", right, iso);
    st_image_free(&img);
}

/* The form factor from a point to a parallel rectangle of sides x and y
 * at distance d, one corner over the point (a diffuse emitter's irradiance
 * there over π L): (1 / 2π) (X / sqrt(1 + X²) atan(Y / sqrt(1 + X²)) +
 * Y / sqrt(1 + Y²) atan(X / sqrt(1 + Y²))), X = x / d, Y = y / d. */
static double parallel_form_factor(double x, double y, double d)
{
    double a = x / d, b = y / d, sa = sqrt(1.0 + a * a), sb = sqrt(1.0 + b * b);
    return (a / sa * atan(b / sa) + b / sb * atan(a / sb)) / (2.0 * 3.14159265358979323846);
}

/* KHR_materials_diffuse_transmission: a lamp behind a Lambertian sheet
 * (tests/scenes/dtrans_lamp.gltf) lights its front, which nothing else
 * lights (no environment), with radiance t c L F: the transmitted share t =
 * 0.75 x the texture's A (204 / 255), the colour c = (1, 0.5, 1) x the sRGB
 * texel (255, 255, 128) decoded, the lamp's radiance L = 1 and F the form
 * factor from the point to the lamp [-1.5, 1.5]² at distance 0.5 (four
 * corner rectangles). The mean of each channel's ratio to it over the
 * inner 28 x 28 pixels is 1 within 1 % (noise of 256 samples of 784
 * pixels: about 0.2 %). Breaks where the sheet does not transmit, or its
 * share or colour (or their textures) are not applied. */
static void diffuse_transmission_lights_the_front(void **state)
{
    (void)state;
    st_render_options o = small(32, 32, 256);
    o.filter = st_filter_default(ST_FILTER_BOX);
    o.integrator = ST_INTEGRATOR_PATH;
    o.env_given = 1;
    o.env[0] = o.env[1] = o.env[2] = 0.0f;
    st_image img = render("tests/scenes/dtrans_lamp.gltf", &o, NULL);
    double blue = 128.0 / 255.0; /* the sRGB decoding of the colour texel's B */
    blue = blue <= 0.04045 ? blue / 12.92 : pow((blue + 0.055) / 1.055, 2.4);
    const double t = 0.75 * 204.0 / 255.0, c[3] = {1.0, 0.5, blue};
    double ratio[3] = {0.0, 0.0, 0.0};
    for (st_u32 y = 2; y < 30; y++)
        for (st_u32 x = 2; x < 30; x++) {
            double px = -1.0 + (x + 0.5) / 16.0, py = 1.0 - (y + 0.5) / 16.0, f = 0.0;
            for (int sx = -1; sx <= 1; sx += 2)
                for (int sy = -1; sy <= 1; sy += 2)
                    f += parallel_form_factor(1.5 + sx * px, 1.5 + sy * py, 0.5);
            for (int k = 0; k < 3; k++)
                ratio[k] += img.data[4 * (y * 32 + x) + k] / (t * c[k] * f) / (28.0 * 28.0);
        }
    for (int k = 0; k < 3; k++)
        if (fabs(ratio[k] - 1.0) > 0.01)
            fail_msg("channel %d: the front's radiance is %.4f of t c L F", k, ratio[k]);
    st_image_free(&img);
}

/* KHR_materials_iridescence in a uniform environment of radiance 1, on two
 * smooth quads seen at cos 0.5 (tests/scenes/irid_quad.gltf), each showing
 * its mirror reflectance, the Fresnel at wo.h = 0.5 (GGX at the least α
 * keeps all but 0.2 % of it): left a black dielectric (F0 0.04) under a
 * film of weight 191 / 255 (factor 1 x texture R), ior 1.3 and thickness
 * 200 + 400 x 128 / 255 nm (texture G), its Fresnel (1 - ι) Schlick +
 * ι film; right a metal of base colour c under a film of weight 0.5, ior
 * 1.8 and the default 400 nm, 0.5 (c + (1 - c) s) + 0.5 film(c). The film
 * is thin_film.h's on the host, whose formula tests/unit/test_thin_film.c
 * checks; this checks that the material reaches it (factor, textures,
 * thickness range, both parts of the lobe). Tolerance 0.5 % plus 0.002. */
static void iridescence_matches_its_fresnel(void **state)
{
    (void)state;
    st_render_options o = in_white_env(32, 16, 256);
    st_image img = render("tests/scenes/irid_quad.gltf", &o, NULL);
    double left[3] = {0.0, 0.0, 0.0}, right[3] = {0.0, 0.0, 0.0};
    for (st_u32 y = 5; y < 11; y++) /* the quads span rows 4 .. 11 */
        for (st_u32 x = 2; x < 30; x++) {
            if (x >= 14 && x < 18)
                continue;
            for (int k = 0; k < 3; k++)
                (x < 16 ? left : right)[k] += img.data[4 * (y * 32 + x) + k] / (12.0 * 6.0);
        }
    const double s = pow(0.5, 5.0), w = 191.0 / 255.0;
    float f0d[3] = {0.04f, 0.04f, 0.04f}, c[3] = {0.9f, 0.6f, 0.3f}, fl[3], fr[3];
    st_thin_film(1.3f, (float)(200.0 + 400.0 * 128.0 / 255.0), 0.5f, f0d, fl);
    st_thin_film(1.8f, 400.0f, 0.5f, c, fr);
    for (int k = 0; k < 3; k++) {
        double wl = (1.0 - w) * (0.04 + 0.96 * s) + w * fl[k];
        double wr = 0.5 * (c[k] + (1.0 - c[k]) * s) + 0.5 * fr[k];
        if (fabs(left[k] - wl) > 0.005 * wl + 0.002 || fabs(right[k] - wr) > 0.005 * wr + 0.002)
            fail_msg("channel %d: dielectric %.5f (want %.5f), metal %.5f (want %.5f)", k,
                     left[k], wl, right[k], wr);
    }
    st_image_free(&img);
}

/* The centroid column (in pixels) of channel k of img over rows y0 .. y1 - 1. */
static double channel_centroid(const st_image *img, int k, st_u32 y0, st_u32 y1)
{
    double sum = 0.0, moment = 0.0;
    for (st_u32 y = y0; y < y1; y++)
        for (st_u32 x = 0; x < img->width; x++) {
            double v = img->data[img->channels * (y * img->width + x) + k];
            sum += v;
            moment += v * (x + 0.5);
        }
    return moment / sum;
}

/* How far a slab of thickness t and ior n moves a ray that meets it at
 * incidence θ (Snell twice: the ray keeps its direction):
 * t sin θ (1 - cos θ / sqrt(n² - sin² θ)). */
static double slab_shift(double n, double t, double theta)
{
    double s = sin(theta), c = cos(theta);
    return t * s * (1.0 - c / sqrt(n * n - s * s));
}

/* KHR_materials_dispersion: a thin lamp seen through a glass slab 1 thick
 * at 45 degrees (tests/scenes/dispersion_slab.gltf, ior 1.5, dispersion 5)
 * appears moved sideways by slab_shift of each channel's ior, so its red
 * and blue images part: the distance between their centroids is that of
 * the shifts at n(656.3 nm) and n(486.1 nm) from the specification's
 * formula (computed here), within 15 % (the ghosts of internal reflections
 * and the pixels' noise), with green between them. With dispersion 0 the
 * image is bit for bit the slab's without the extension, and its red and
 * blue centroids agree to 0.2 pixels. */
static void dispersion_separates_colours(void **state)
{
    (void)state;
    st_render_options o = small(128, 64, 64);
    o.filter = st_filter_default(ST_FILTER_BOX);
    o.integrator = ST_INTEGRATOR_PATH;
    o.env_given = 1;
    o.env[0] = o.env[1] = o.env[2] = 0.0f;
    st_image img = render("tests/scenes/dispersion_slab.gltf", &o, NULL);
    double cr = channel_centroid(&img, 0, 16, 48), cg = channel_centroid(&img, 1, 16, 48);
    double cb = channel_centroid(&img, 2, 16, 48);
    double v = 20.0 / 5.0, nr = 1.5 + 0.5 / v * (523655.0 / (656.3 * 656.3) - 1.5168);
    double nb = 1.5 + 0.5 / v * (523655.0 / (486.1 * 486.1) - 1.5168);
    double theta = 3.14159265358979323846 / 4.0, px = 2.0 / 128.0;
    double want = fabs(slab_shift(nb, 1.0, theta) - slab_shift(nr, 1.0, theta)) / px;
    print_message("dispersion: centroids R %.2f G %.2f B %.2f px; R to B %.2f px, want %.2f\n",
                  cr, cg, cb, fabs(cb - cr), want);
    if (fabs(fabs(cb - cr) - want) > 0.15 * want || !((cg - cr) * (cb - cg) > 0.0))
        fail_msg("R at %.2f, G at %.2f, B at %.2f px: R to B %.2f px, want %.2f", cr, cg, cb,
                 fabs(cb - cr), want);
    st_image_free(&img);
    st_image zero = render("tests/scenes/dispersion_slab_zero.gltf", &o, NULL);
    st_image clear = render("tests/scenes/clear_slab.gltf", &o, NULL);
    assert_memory_equal(zero.data, clear.data, sizeof(float) * zero.channels * 128 * 64);
    double zr = channel_centroid(&zero, 0, 16, 48), zb = channel_centroid(&zero, 2, 16, 48);
    if (fabs(zr - zb) > 0.2)
        fail_msg("dispersion 0: R at %.2f, B at %.2f px", zr, zb);
    st_image_free(&zero);
    st_image_free(&clear);
}

/* The default scene against tests/golden/cornell-box-48.exr (made by
 * `strata render --width 48 --height 48 --spp 16 --seed 7 -o ...` when the
 * renderer was checked by eye and by the tests above). RMSE below 0.01 (the
 * image's mean is about 0.2; noise between devices of different float
 * rounding stays far below) catches any change in the image. */
static void golden_cornell_box(void **state)
{
    (void)state;
    st_render_options o = small(48, 48, 16);
    st_image img = render("cornell-box", &o, NULL), gold = {0};
    st_error err = {0};
    if (st_image_load("tests/golden/cornell-box-48.exr", &gold, &err) != ST_OK)
        fail_msg("%s", err.msg);
    st_diff_result d;
    assert_int_equal(st_diff_images(&img, &gold, &d, &err), ST_OK);
    if (d.rmse > 0.01)
        fail_msg("rmse %.6f against the golden image (tolerance 0.01)", d.rmse);
    st_image_free(&img);
    st_image_free(&gold);
}

/* The BVH build's threads: its own default, but no more than a CPU
 * device's compute units (--threads makes a sub-device of fewer), and its
 * default beside a GPU; one for a small scene whatever the device. */
static void bvh_threads_follow_the_device(void **state)
{
    (void)state;
    st_device_info cpu, gpu;
    memset(&cpu, 0, sizeof cpu);
    memset(&gpu, 0, sizeof gpu);
    cpu.is_cpu = 1;
    gpu.is_gpu = 1;
    const st_u32 big = 1000000u;
    unsigned own = st_bvh_threads(0u, big);
    cpu.compute_units = 1;
    assert_int_equal(st_renderer_bvh_threads(&cpu, big), 1);
    cpu.compute_units = own + 8u;
    assert_int_equal(st_renderer_bvh_threads(&cpu, big), own);
    gpu.compute_units = 1;
    assert_int_equal(st_renderer_bvh_threads(&gpu, big), own);
    cpu.compute_units = 2;
    assert_int_equal(st_renderer_bvh_threads(&cpu, 100u), 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(bvh_device_closest_equals_brute_force),
        cmocka_unit_test(bvh_threads_follow_the_device),
        cmocka_unit_test(generate_matches_definitions),
        cmocka_unit_test(glass_slab_matches_closed_form),
        cmocka_unit_test(glass_furnace),
        cmocka_unit_test(glass_furnace_coarse_keeps_the_outline),
        cmocka_unit_test(coat_matches_its_fresnel),
        cmocka_unit_test(sheen_matches_its_albedo),
        cmocka_unit_test(anisotropy_matches_its_albedo),
        cmocka_unit_test(diffuse_transmission_lights_the_front),
        cmocka_unit_test(iridescence_matches_its_fresnel),
        cmocka_unit_test(dispersion_separates_colours),
        cmocka_unit_test(bvh_device_closest_equals_brute_force_one_sided),
        cmocka_unit_test(render_same_bits_twice),
        cmocka_unit_test(one_renderer_many_views),
        cmocka_unit_test(render_same_bits_any_wave_and_group_size),
        cmocka_unit_test(render_split_sums_add_to_whole),
        cmocka_unit_test(constant_radiance_reconstructs_exactly),
        cmocka_unit_test(furnace_matches_closed_form),
        cmocka_unit_test(fis_constant_radiance),
        cmocka_unit_test(every_sampler_gives_every_pixel_spp),
        cmocka_unit_test(splat_clamp_trips_above_limit),
        cmocka_unit_test(tile_splat_equals_per_sample),
        cmocka_unit_test(shadows_in_shade_equal_stage),
        cmocka_unit_test(golden_cornell_box),
        cmocka_unit_test(enclosed_dark_scene_gets_a_headlight),
    };
    return cmocka_run_group_tests_name("render", tests, device_setup, device_teardown);
}
