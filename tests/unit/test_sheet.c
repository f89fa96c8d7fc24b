/* test_sheet.c — guards src/lab/sheet.c (include/st_sheet.h). Layout-independent checks on the
 * PNG: every image pixel appears as a square of its exact sRGB code, enlarged by the factor the
 * header states, so the count of a colour that only one image holds is known in advance
 * (w * h * factor^2, plus the inset's share); the sheet's size is st_sheet_size's. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "scratch.h"
#include "st_sheet.h"

#include <cairo/cairo.h>

static void solid(st_image *img, uint32_t w, uint32_t h, float r, float g, float b)
{
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(img, w, h, 3, NULL, &err), ST_OK);
    for (size_t i = 0; i < (size_t)w * h; i++)
        img->data[3 * i] = r, img->data[3 * i + 1] = g, img->data[3 * i + 2] = b;
}

/* Pixels of the sheet whose RGB is exactly that of linear (r, g, b) through the sRGB encoder. */
static long count_colour(const char *path, float r, float g, float b, int *w, int *h)
{
    cairo_surface_t *sf = cairo_image_surface_create_from_png(path);
    assert_int_equal(cairo_surface_status(sf), CAIRO_STATUS_SUCCESS);
    *w = cairo_image_surface_get_width(sf), *h = cairo_image_surface_get_height(sf);
    uint32_t want = (uint32_t)st_image_srgb_quantize(r) << 16 |
                    (uint32_t)st_image_srgb_quantize(g) << 8 | st_image_srgb_quantize(b);
    const unsigned char *px = cairo_image_surface_get_data(sf);
    int stride = cairo_image_surface_get_stride(sf);
    long n = 0;
    for (int y = 0; y < *h; y++)
        for (int x = 0; x < *w; x++) {
            uint32_t v;
            memcpy(&v, px + (size_t)y * stride + 4 * x, 4);
            n += (v & 0xffffff) == want;
        }
    cairo_surface_destroy(sf);
    return n;
}

static void images_are_enlarged_whole(void **state)
{
    (void)state;
    st_image ref, a, b;
    solid(&ref, 10, 6, 0.2f, 0.05f, 0.6f); /* factor floor(256 / 10) = 25 */
    solid(&a, 10, 6, 0.7f, 0.3f, 0.01f);
    solid(&b, 10, 6, 0.01f, 0.5f, 0.4f);
    st_sheet_cell cells[2] = {{&a, "a", "RMSE 1"}, {&b, "b", NULL}};
    st_sheet s = {.title = "t", .reference = {&ref, "ref", NULL}, .cells = cells, .rows = 1,
                  .cols = 2};
    const char *path = scratch_path("s.png");
    st_error err = {ST_OK, ""};
    assert_int_equal(st_sheet_save(path, &s, &err), ST_OK);
    int w, h;
    uint32_t sw, sh;
    st_sheet_size(&s, 10, 6, &sw, &sh);
    assert_int_equal(count_colour(path, 0.7f, 0.3f, 0.01f, &w, &h), 10 * 6 * 25 * 25);
    assert_int_equal(count_colour(path, 0.2f, 0.05f, 0.6f, &w, &h), 10 * 6 * 25 * 25);
    assert_int_equal(w, (int)sw);
    assert_int_equal(h, (int)sh);
    /* an inset of 2x3 pixels: factor floor(250 / 2) = 125, the rest of b's colour covered by
     * the inset's outline only where it crosses b's image: count at least the inset's area */
    s.inset[0] = 1, s.inset[1] = 1, s.inset[2] = 2, s.inset[3] = 3;
    assert_int_equal(st_sheet_save(path, &s, &err), ST_OK);
    long n = count_colour(path, 0.01f, 0.5f, 0.4f, &w, &h);
    assert_true(n >= 2 * 3 * 125 * 125 && n < 2 * 3 * 125 * 125 + 10 * 6 * 25 * 25);
    st_image_free(&ref), st_image_free(&a), st_image_free(&b);
}

static void bad_sheets_fail_and_leave_nothing(void **state)
{
    (void)state;
    st_image a, b;
    solid(&a, 4, 4, 0.5f, 0.5f, 0.5f);
    solid(&b, 5, 4, 0.5f, 0.5f, 0.5f);
    st_sheet_cell cells[1] = {{&b, "b", NULL}};
    st_sheet s = {.reference = {&a, "a", NULL}, .cells = cells, .rows = 1, .cols = 1};
    st_error err = {ST_OK, ""};
    assert_int_equal(st_sheet_save(scratch_path("x.png"), &s, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "different sizes"));
    cells[0].image = &a;
    st_error e2 = {ST_OK, ""}, e3 = {ST_OK, ""}, e4 = {ST_OK, ""};
    assert_int_equal(st_sheet_save(scratch_path("x.jpg"), &s, &e2), ST_ERR_USAGE);
    assert_non_null(strstr(e2.msg, "a sheet is .png, .pdf or .svg"));
    s.inset[0] = 3, s.inset[1] = 0, s.inset[2] = 2, s.inset[3] = 1;
    assert_int_equal(st_sheet_save(scratch_path("x.pdf"), &s, &e3), ST_ERR_USAGE);
    assert_non_null(strstr(e3.msg, "inset 3,0,2,1 is outside the 4x4 image"));
    assert_int_equal(scratch_entries(NULL, 0), 0);
    s.inset[0] = 2;
    assert_int_equal(st_sheet_save(scratch_path("x.svg"), &s, &e4), ST_OK);
    assert_int_equal(scratch_entries(NULL, 0), 1);
    st_image_free(&a), st_image_free(&b);
}

/* Whether every pixel of the rectangle [x0, x1) x [y0, y1) of the PNG is white. */
static int all_white(const char *path, int x0, int x1, int y0, int y1)
{
    cairo_surface_t *sf = cairo_image_surface_create_from_png(path);
    assert_int_equal(cairo_surface_status(sf), CAIRO_STATUS_SUCCESS);
    const unsigned char *px = cairo_image_surface_get_data(sf);
    int stride = cairo_image_surface_get_stride(sf), white = 1;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            uint32_t v;
            memcpy(&v, px + (size_t)y * stride + 4 * x, 4);
            white &= (v & 0xffffff) == 0xffffff;
        }
    cairo_surface_destroy(sf);
    return white;
}

/* A caption far wider than its cell is drawn smaller, inside the cell: the gap
 * between the reference's column and the next stays white in the caption band
 * (the sheet has no title, so the band starts at the margin plus the image). */
static void captions_fit_their_cells(void **state)
{
    (void)state;
    st_image ref, a;
    solid(&ref, 96, 40, 0.2f, 0.2f, 0.2f); /* factor 2: cells 192 wide */
    solid(&a, 96, 40, 0.5f, 0.5f, 0.5f);
    st_sheet_cell cells[1] = {{&a, "best-candidate, 16 spp, mitchell, and more words besides",
                               "RMSE 0.0123456789 over the whole image, seeds 1 to 8"}};
    st_sheet s = {.reference = {&ref, "reference: sobol, 1024 spp, mitchell, seed 1593192557",
                                NULL},
                  .cells = cells, .rows = 1, .cols = 1};
    const char *path = scratch_path("captions.png");
    st_error err = {ST_OK, ""};
    assert_int_equal(st_sheet_save(path, &s, &err), ST_OK);
    uint32_t w, h;
    st_sheet_size(&s, 96, 40, &w, &h);
    int gap0 = 12 + 192, gap1 = gap0 + 12, band0 = 12 + 80;
    assert_true(all_white(path, gap0, gap1, band0, (int)h));
    assert_true(all_white(path, (int)w - 12, (int)w, band0, (int)h)); /* the right margin too */
    assert_false(all_white(path, 12, gap0, band0, (int)h));          /* the caption is there */
    st_image_free(&ref), st_image_free(&a);
}

/* The images of an SVG sheet are embedded at the size they are shown (each pixel
 * already a block), so no viewer has to scale, and smooth, them. */
static void svg_images_are_embedded_enlarged(void **state)
{
    (void)state;
    st_image ref, a;
    solid(&ref, 10, 6, 0.2f, 0.05f, 0.6f); /* factor 25: shown 250 x 150 */
    solid(&a, 10, 6, 0.7f, 0.3f, 0.01f);
    st_sheet_cell cells[1] = {{&a, "a", NULL}};
    st_sheet s = {.reference = {&ref, "ref", NULL}, .cells = cells, .rows = 1, .cols = 1};
    const char *path = scratch_path("s.svg");
    st_error err = {ST_OK, ""};
    assert_int_equal(st_sheet_save(path, &s, &err), ST_OK);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    static char svg[1 << 20];
    size_t n = fread(svg, 1, sizeof svg - 1, f);
    fclose(f);
    svg[n] = '\0';
    int images = 0;
    for (const char *p = svg; (p = strstr(p, "<image ")); p++) {
        unsigned iw = 0, ih = 0;
        const char *wp = strstr(p, " width=\""), *hp = strstr(p, " height=\"");
        assert_non_null(wp);
        assert_non_null(hp);
        assert_int_equal(sscanf(wp, " width=\"%u\"", &iw), 1);
        assert_int_equal(sscanf(hp, " height=\"%u\"", &ih), 1);
        assert_int_equal(iw, 250);
        assert_int_equal(ih, 150);
        images++;
    }
    assert_int_equal(images, 2);
    st_image_free(&ref), st_image_free(&a);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(captions_fit_their_cells, scratch_make, scratch_remove),
        cmocka_unit_test_setup_teardown(svg_images_are_embedded_enlarged, scratch_make,
                                        scratch_remove),
        cmocka_unit_test_setup_teardown(images_are_enlarged_whole, scratch_make, scratch_remove),
        cmocka_unit_test_setup_teardown(bad_sheets_fail_and_leave_nothing, scratch_make,
                                        scratch_remove),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
