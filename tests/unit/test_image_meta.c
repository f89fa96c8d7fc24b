/* test_image_meta.c — guards what strata's image files say about themselves (include/st_image.h):
 * typed EXR attributes, the Rec. 709 chromaticities and "software" of every EXR, and a PNG's
 * sRGB chunk and text chunks.
 *
 * Expected values come from the definitions, read back through the libraries directly (the
 * OpenEXR C API, libpng), not through the code under test: the chromaticities are ITU-R BT.709-6
 * table items 1.3 and 1.4 (R 0.640,0.330; G 0.300,0.600; B 0.150,0.060; D65 0.3127,0.3290).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "scratch.h"
#include "st_image.h"
#include "st_version.h"

#include <openexr.h>
#include <png.h>

static void set_attr(st_attr *a, const char *name, st_attr_type t, const char *value)
{
    memset(a, 0, sizeof *a);
    snprintf(a->name, sizeof a->name, "%s", name);
    snprintf(a->value, sizeof a->value, "%s", value);
    a->type = t;
}

static const exr_attribute_t *exr_attr(exr_const_context_t ctx, const char *name)
{
    const exr_attribute_t *a = NULL;
    assert_int_equal(exr_get_attribute_by_name(ctx, 0, name, &a), EXR_ERR_SUCCESS);
    return a;
}

static void exr_attributes_are_typed(void **state)
{
    (void)state;
    st_attr attrs[4];
    set_attr(&attrs[0], "strata.spp", ST_ATTR_INT, "64");
    set_attr(&attrs[1], "strata.filter_radius", ST_ATTR_FLOAT, "1.5");
    set_attr(&attrs[2], "strata.render_seconds", ST_ATTR_DOUBLE, "0.1");
    set_attr(&attrs[3], "strata.sampler", ST_ATTR_STRING, "halton");
    st_image img;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(&img, 2, 2, 3, NULL, &err), ST_OK);
    const char *path = scratch_path("typed.exr");
    assert_int_equal(st_image_save_exr(path, &img, attrs, 4, &err), ST_OK);

    exr_context_t ctx = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    assert_int_equal(exr_start_read(&ctx, path, &init), EXR_ERR_SUCCESS);
    const exr_attribute_t *a = exr_attr(ctx, "strata.spp");
    assert_int_equal(a->type, EXR_ATTR_INT);
    assert_int_equal(a->i, 64);
    a = exr_attr(ctx, "strata.filter_radius");
    assert_int_equal(a->type, EXR_ATTR_FLOAT);
    assert_true(a->f == 1.5f);
    a = exr_attr(ctx, "strata.render_seconds");
    assert_int_equal(a->type, EXR_ATTR_DOUBLE);
    assert_true(a->d == 0.1);
    a = exr_attr(ctx, "strata.sampler");
    assert_int_equal(a->type, EXR_ATTR_STRING);
    assert_string_equal(a->string->str, "halton");
    a = exr_attr(ctx, "chromaticities");
    assert_int_equal(a->type, EXR_ATTR_CHROMATICITIES);
    const float want[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
    const float got[8] = {a->chromaticities->red_x,   a->chromaticities->red_y,
                          a->chromaticities->green_x, a->chromaticities->green_y,
                          a->chromaticities->blue_x,  a->chromaticities->blue_y,
                          a->chromaticities->white_x, a->chromaticities->white_y};
    for (int k = 0; k < 8; k++)
        assert_true(got[k] == want[k]);
    a = exr_attr(ctx, "software");
    char software[128];
    snprintf(software, sizeof software, "strata %s", st_version);
    assert_string_equal(a->string->str, software);
    exr_finish(&ctx);

    /* and back through st_image_load_exr: typed, as the text they were written from */
    st_image back;
    st_attr *read = NULL;
    int n = 0;
    assert_int_equal(st_image_load_exr(path, &back, &read, &n, &err), ST_OK);
    assert_int_equal(n, 5);
    for (int i = 0; i < 4; i++) {
        assert_string_equal(read[i].name, attrs[i].name);
        assert_string_equal(read[i].value, attrs[i].value);
        assert_int_equal(read[i].type, attrs[i].type);
    }
    free(read);
    st_image_free(&back);
    st_image_free(&img);
}

static void exr_attribute_not_of_its_type_fails_leaves_nothing(void **state)
{
    (void)state;
    const char *bad[][2] = {{"1.5", "int"}, {"12x", "int"}, {"", "int"}, {"3000000000", "int"},
                            {"nan", "float"}, {"1e39", "float"}, {"abc", "double"}};
    st_image img;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(&img, 2, 2, 3, NULL, &err), ST_OK);
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        st_attr a;
        st_attr_type t = bad[i][1][0] == 'i' ? ST_ATTR_INT
                         : bad[i][1][0] == 'f' ? ST_ATTR_FLOAT : ST_ATTR_DOUBLE;
        set_attr(&a, "strata.x", t, bad[i][0]);
        const char *path = scratch_path("bad.exr");
        st_error e = {ST_OK, ""};
        assert_int_equal(st_image_save_exr(path, &img, &a, 1, &e), ST_ERR_FORMAT);
        assert_non_null(strstr(e.msg, "strata.x"));
        assert_int_equal(scratch_entries(NULL, 0), 0);
    }
    st_image_free(&img);
}

static void png_has_srgb_and_text(void **state)
{
    (void)state;
    st_image img;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(&img, 3, 2, 3, NULL, &err), ST_OK);
    st_attr attrs[2];
    set_attr(&attrs[0], "strata.spp", ST_ATTR_INT, "16");
    set_attr(&attrs[1], "strata.scene", ST_ATTR_STRING, "caf\xc3\xa9"); /* UTF-8: iTXt */
    const char *path = scratch_path("meta.png");
    assert_int_equal(st_image_save(path, &img, attrs, 2, &err), ST_OK);

    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    assert_non_null(info);
    if (setjmp(png_jmpbuf(png)))
        fail_msg("libpng could not read %s", path);
    png_init_io(png, f);
    png_read_info(png, info);
    int intent = -1;
    assert_true(png_get_sRGB(png, info, &intent) & PNG_INFO_sRGB);
    assert_int_equal(intent, PNG_sRGB_INTENT_PERCEPTUAL);
    png_textp text = NULL;
    int n = png_get_text(png, info, &text, NULL);
    assert_int_equal(n, 3);
    char software[128];
    snprintf(software, sizeof software, "strata %s", st_version);
    assert_string_equal(text[0].key, "Software");
    assert_string_equal(text[0].text, software);
    assert_string_equal(text[1].key, "strata.spp");
    assert_string_equal(text[1].text, "16");
    assert_string_equal(text[2].key, "strata.scene");
    assert_string_equal(text[2].text, "caf\xc3\xa9");
    assert_int_equal(text[2].compression, PNG_ITXT_COMPRESSION_NONE);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(f);
    st_image_free(&img);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(exr_attributes_are_typed, scratch_make, scratch_remove),
        cmocka_unit_test_setup_teardown(exr_attribute_not_of_its_type_fails_leaves_nothing,
                                        scratch_make, scratch_remove),
        cmocka_unit_test_setup_teardown(png_has_srgb_and_text, scratch_make, scratch_remove),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
