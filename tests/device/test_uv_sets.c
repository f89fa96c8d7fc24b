/* test_uv_sets.c — the second texture coordinate set (TEXCOORD_1): every
 * texture reads the set its reference names (texCoord, or
 * KHR_texture_transform's texCoord), on the host and on the device.
 *
 * tests/scenes/two_uv.gltf (make_test_scenes.py) is the 2 x 2 quad of
 * textured_quad, unlit white, seen by an orthographic camera that shows
 * x, y in [-0.4, 0.4]. TEXCOORD_0 is the constant (0.25, 0.5); TEXCOORD_1
 * is the quad's own uv, u = (x + 1) / 2, v = (1 - y) / 2, stored as
 * normalised unsigned shorts (0 or 65535: exactly 0 or 1). The base colour
 * texture, a 2 x 1 image red | blue with NEAREST magnification, reads
 * TEXCOORD_1: the view's left half (x < 0, u < 0.5) shows red (1, 0, 0),
 * the right half blue (0, 0, 1), where TEXCOORD_0 would show red in every
 * pixel. Its normal map reads TEXCOORD_1 too, so the generated tangents
 * are dP/du = +x, and w = +1: dP/dv points to -y, so the bitangent a glTF
 * normal map needs, -dP/dv, is +y = n x t. */
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

#define SCENES "tests/scenes/"

static st_scene *load(const char *path)
{
    st_error err = {0};
    st_scene *s = NULL;
    if (st_scene_load(path, &s, &err) != ST_OK)
        fail_msg("load %s: %s", path, err.msg);
    return s;
}

static int has_warning(const st_scene *s, const char *phrase)
{
    for (st_u32 i = 0; i < s->warning_count; i++)
        if (strstr(s->warnings[i], phrase))
            return 1;
    return 0;
}

/* The quad's two triangles hold vertices 0 1 2 and 0 2 3 (x, y) =
 * (-1, -1), (1, -1), (1, 1), (-1, 1); TEXCOORD_1 = ((x + 1) / 2, (1 - y) / 2)
 * read from the normalised shorts exactly; TEXCOORD_0 (0.25, 0.5). */
static void second_set_read_per_vertex(void **state)
{
    (void)state;
    static const char *files[] = {SCENES "two_uv.gltf", SCENES "two_uv_transform.gltf"};
    static const double xy[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    static const int tri_vertex[2][3] = {{0, 1, 2}, {0, 2, 3}};
    for (int f = 0; f < 2; f++) {
        st_scene *s = load(files[f]);
        assert_int_equal(s->tri_count, 2);
        assert_non_null(s->uvs1);
        for (int t = 0; t < 2; t++)
            for (int v = 0; v < 3; v++) {
                const double *p = xy[tri_vertex[t][v]];
                const float *uv0 = s->uvs + 6 * t + 2 * v, *uv1 = s->uvs1 + 6 * t + 2 * v;
                assert_true(uv0[0] == 0.25f && uv0[1] == 0.5f);
                assert_true(uv1[0] == (float)((p[0] + 1.0) / 2.0));
                assert_true(uv1[1] == (float)((1.0 - p[1]) / 2.0));
            }
        const st_material *m = &s->materials[0];
        assert_int_not_equal(m->base_color_tex, ST_NO_TEXTURE);
        assert_int_equal(s->textures[m->base_color_tex].uv_set, 1);
        assert_int_equal(s->warning_count, 0);
        st_scene_destroy(s);
    }
}

/* A scene whose textures all read TEXCOORD_0 keeps no second set. */
static void second_set_kept_only_when_read(void **state)
{
    (void)state;
    st_scene *s = load(SCENES "textured_quad.gltf");
    assert_null(s->uvs1);
    for (st_u32 i = 0; i < s->texture_count; i++)
        assert_int_equal(s->textures[i].uv_set, 0);
    st_scene_destroy(s);
}

/* Tangents come from the normal map's set: TEXCOORD_0 is constant (no
 * tangent from it), TEXCOORD_1 gives +x with w = +1 (header). */
static void tangents_follow_the_normal_maps_set(void **state)
{
    (void)state;
    st_scene *s = load(SCENES "two_uv.gltf");
    assert_int_equal(s->textures[s->materials[0].normal_tex].uv_set, 1);
    for (int t = 0; t < 2; t++)
        for (int v = 0; v < 3; v++) {
            const float *tan = s->tangents + 12 * t + 4 * v;
            assert_true(tan[0] == 1.0f && tan[1] == 0.0f && tan[2] == 0.0f);
            assert_true(tan[3] == 1.0f);
        }
    st_scene_destroy(s);
}

/* texCoord 2: a warning naming it, and no texture (the factor alone, as for
 * an image that cannot be read). */
static void third_set_warns_and_keeps_the_factor(void **state)
{
    (void)state;
    st_scene *s = load(SCENES "two_uv_coord2.gltf");
    assert_true(has_warning(s, "material 0: baseColorTexture uses TEXCOORD_2"));
    assert_int_equal(s->materials[0].base_color_tex, ST_NO_TEXTURE);
    assert_int_equal(s->materials[0].base_color[0], 1.0f);
    st_scene_destroy(s);
}

/* A 16 x 12 render of s from its camera with spp samples (o changed by the
 * caller where given). */
static st_image render(const st_scene *s, const st_render_options *given)
{
    st_render_options o = given ? *given : st_render_defaults();
    o.width = 16;
    o.height = 12;
    o.seed = 3;
    st_error err = {0};
    st_renderer *r = NULL;
    st_image img = {0};
    if (st_renderer_create(dev, s, &r, &err) ||
        st_render(r, &o, &img, NULL, NULL, NULL, NULL, &err))
        fail_msg("render %s: %s", s->name, err.msg);
    st_renderer_destroy(r);
    return img;
}

/* The render of two_uv (16 x 12, the camera's view): the columns away from
 * the middle (more than the Mitchell filter's 2-pixel radius from the
 * seam at x = 0) show the texel of the side they see, exactly (unlit). */
static void render_reads_the_texture_through_its_set(void **state)
{
    (void)state;
    static const char *files[] = {SCENES "two_uv.gltf", SCENES "two_uv_transform.gltf"};
    for (int f = 0; f < 2; f++) {
        st_scene *s = load(files[f]);
        st_render_options o = st_render_defaults();
        o.spp = 4;
        st_image img = render(s, &o);
        for (st_u32 y = 0; y < img.height; y++)
            for (st_u32 x = 0; x < img.width; x++) {
                if (x > 4 && x < 11)
                    continue;
                const double want[3] = {x < 8 ? 1.0 : 0.0, 0.0, x < 8 ? 0.0 : 1.0};
                const float *px = img.data + 4 * ((size_t)y * img.width + x);
                for (int c = 0; c < 3; c++)
                    if (fabs(px[c] - want[c]) > 1e-5)
                        fail_msg("%s: pixel (%u, %u) channel %d: %g, want %g", files[f], x, y,
                                 c, px[c], want[c]);
            }
        st_image_free(&img);
        st_scene_destroy(s);
    }
}

static double image_mean(const st_image *img)
{
    double sum = 0.0;
    for (size_t p = 0; p < (size_t)img->width * img->height; p++)
        for (int c = 0; c < 3; c++)
            sum += img->data[4 * p + (size_t)c];
    return sum / (3.0 * img->width * img->height);
}

/* Next-event estimation reads an emissive texture through its set: the
 * ground under two_uv_light's emitter, whose texture on TEXCOORD_1 is black
 * on its half x < 0, receives what half_light's emitter (that half left out,
 * untextured) sends it, in expectation; through TEXCOORD_0 (the white texel
 * everywhere) it would receive about twice as much. Direct lighting, no
 * environment, 64 samples a pixel: the two means agree within 3 % (the
 * noise of each is well under 1 %). */
static void light_sampling_reads_the_emissive_texture_through_its_set(void **state)
{
    (void)state;
    st_render_options o = st_render_defaults();
    o.integrator = ST_INTEGRATOR_DIRECT;
    o.env_given = 1;
    o.env[0] = o.env[1] = o.env[2] = 0.0f;
    o.spp = 64;
    double mean[2];
    static const char *files[] = {SCENES "two_uv_light.gltf", SCENES "half_light.gltf"};
    for (int f = 0; f < 2; f++) {
        st_scene *s = load(files[f]);
        st_image img = render(s, &o);
        mean[f] = image_mean(&img);
        st_image_free(&img);
        st_scene_destroy(s);
    }
    print_message("ground: textured emitter %.5f, half emitter %.5f\n", mean[0], mean[1]);
    assert_true(mean[1] > 0.0);
    assert_true(fabs(mean[0] / mean[1] - 1.0) < 0.03);
}

int main(void)
{
    const struct CMUnitTest host[] = {
        cmocka_unit_test(second_set_read_per_vertex),
        cmocka_unit_test(second_set_kept_only_when_read),
        cmocka_unit_test(tangents_follow_the_normal_maps_set),
        cmocka_unit_test(third_set_warns_and_keeps_the_factor),
    };
    const struct CMUnitTest device[] = {
        cmocka_unit_test(render_reads_the_texture_through_its_set),
        cmocka_unit_test(light_sampling_reads_the_emissive_texture_through_its_set),
    };
    int failed = cmocka_run_group_tests_name("uv sets (host)", host, NULL, NULL);
    return failed + cmocka_run_group_tests_name("uv sets (device)", device, device_setup,
                                                device_teardown);
}
