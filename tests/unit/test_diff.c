/* test_diff.c — guards src/image/diff.c (include/st_diff.h).
 *
 * Expected values come from closed forms: an offset d on every sample gives RMSE = max = d and
 * PSNR = 20 log10(1/d); offsets of +d and -d alternating also give RMSE d; an offset d on half the
 * pixels gives d/sqrt(2). Offsets and values are multiples of powers of two, so every difference
 * is exact in float and the expected results hold exactly (tolerance 1e-15 relative where a
 * square root or log10 is involved). A brute-force long double sum checks random images.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "st_diff.h"

#include <math.h>
#include <string.h>

#define assert_near(got, want, tol)                                                          \
    do {                                                                                     \
        double g_ = (got), w_ = (want), t_ = (tol);                                          \
        if (!(fabs(g_ - w_) <= t_))                                                          \
            fail_msg("%s = %.17g, expected %.17g within %g", #got, g_, w_, t_);              \
    } while (0)

/* xorshift32 (Marsaglia, "Xorshift RNGs", J. Stat. Software 2003): test data only. */
static uint32_t next_random(uint32_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return *s;
}

/* A w x h R,G,B image of values k/256, k in 0..255, from seed. */
static void make_image(st_image *img, uint32_t w, uint32_t h, uint32_t seed)
{
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(img, w, h, 3, NULL, &err), ST_OK);
    for (size_t i = 0; i < (size_t)w * h * 3; i++)
        img->data[i] = (float)(next_random(&seed) % 256) / 256.f;
}

static void diff_identical_images_rmse_zero(void **state)
{
    (void)state;
    st_image a, b;
    make_image(&a, 13, 7, 1);
    make_image(&b, 13, 7, 1);
    st_diff_result r;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_diff_images(&a, &b, &r, &err), ST_OK);
    assert_true(r.rmse == 0.0);
    assert_true(r.max_abs == 0.0);
    assert_true(isinf(r.psnr) && r.psnr > 0);
    assert_int_equal(r.compared, 13 * 7 * 3);
    st_image_free(&a);
    st_image_free(&b);
}

static void diff_constant_offset_gives_rmse_and_max_d(void **state)
{
    (void)state;
    const double d = 0.125;
    st_image a, b;
    make_image(&a, 16, 9, 2);
    make_image(&b, 16, 9, 2);
    for (size_t i = 0; i < 16 * 9 * 3; i++)
        b.data[i] += (float)d; /* exact: k/256 + 1/8 */
    st_diff_result r;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_diff_images(&a, &b, &r, &err), ST_OK);
    assert_near(r.rmse, d, 1e-15 * d);
    assert_true(r.max_abs == d);
    assert_near(r.psnr, 20.0 * log10(8.0), 1e-12); /* 18.0618 dB */
    st_image_free(&a);
    st_image_free(&b);
}

static void diff_alternating_and_half_offsets(void **state)
{
    (void)state;
    const double d = 0.25;
    st_image a, b, c;
    make_image(&a, 10, 10, 3);
    make_image(&b, 10, 10, 3);
    make_image(&c, 10, 10, 3);
    for (size_t p = 0; p < 100; p++)
        for (size_t k = 0; k < 3; k++) {
            b.data[p * 3 + k] += (float)(p % 2 ? -d : d); /* +d, -d, +d, ... */
            if (p < 50)
                c.data[p * 3 + k] += (float)d; /* half the pixels */
        }
    st_diff_result r;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_diff_images(&a, &b, &r, &err), ST_OK);
    assert_near(r.rmse, d, 1e-15 * d);
    assert_true(r.max_abs == d);
    assert_int_equal(st_diff_images(&a, &c, &r, &err), ST_OK);
    assert_near(r.rmse, d / sqrt(2.0), 1e-15 * d);
    assert_true(r.max_abs == d);
    st_image_free(&a);
    st_image_free(&b);
    st_image_free(&c);
}

static void diff_equals_brute_force_sum(void **state)
{
    (void)state;
    st_image a, b;
    make_image(&a, 31, 17, 4);
    make_image(&b, 31, 17, 5);
    long double sum = 0, worst = 0;
    for (size_t i = 0; i < 31 * 17 * 3; i++) {
        long double e = (long double)a.data[i] - (long double)b.data[i];
        sum += e * e;
        if (fabsl(e) > worst)
            worst = fabsl(e);
    }
    double want = (double)sqrtl(sum / (31 * 17 * 3));
    st_diff_result r;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_diff_images(&a, &b, &r, &err), ST_OK);
    assert_near(r.rmse, want, 1e-14 * want);
    assert_true(r.max_abs == (double)worst);
    assert_near(r.psnr, -20.0 * log10(want), 1e-12);
    st_image_free(&a);
    st_image_free(&b);
}

static void diff_matches_channels_by_name(void **state)
{
    (void)state;
    const char *bgrw[4] = {"B", "G", "R", "W"};
    st_image a, b;
    make_image(&a, 5, 4, 6);
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(&b, 5, 4, 4, bgrw, &err), ST_OK);
    for (size_t p = 0; p < 20; p++) {
        b.data[p * 4 + 0] = a.data[p * 3 + 2];
        b.data[p * 4 + 1] = a.data[p * 3 + 1];
        b.data[p * 4 + 2] = a.data[p * 3 + 0];
        b.data[p * 4 + 3] = 1e9f; /* not compared */
    }
    st_diff_result r;
    assert_int_equal(st_diff_images(&a, &b, &r, &err), ST_OK);
    assert_true(r.rmse == 0.0);
    b.data[7 * 4 + 2] += 0.5f; /* R of pixel 7 */
    assert_int_equal(st_diff_images(&a, &b, &r, &err), ST_OK);
    assert_true(r.max_abs == 0.5);
    assert_near(r.rmse, sqrt(0.25 / 60.0), 1e-15);
    st_image_free(&a);
    st_image_free(&b);
}

static void expect_error(const st_image *a, const st_image *b, const char *needle)
{
    st_diff_result r;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_diff_images(a, b, &r, &err), ST_ERR_FORMAT);
    if (!strstr(err.msg, needle))
        fail_msg("message '%s' does not mention '%s'", err.msg, needle);
    assert_null(strchr(err.msg, '\n'));
    assert_true(r.rmse == 0 && r.compared == 0);
}

static void diff_size_mismatch_is_error(void **state)
{
    (void)state;
    st_image a, b;
    make_image(&a, 4, 4, 7);
    make_image(&b, 5, 4, 7);
    expect_error(&a, &b, "first 4x4, second 5x4");
    st_image_free(&a);
    st_image_free(&b);
}

static void diff_missing_or_uint_channel_is_error(void **state)
{
    (void)state;
    const char *rxb[3] = {"R", "X", "B"};
    st_image a, b;
    st_error err = {ST_OK, ""};
    make_image(&a, 3, 3, 8);
    assert_int_equal(st_image_create(&b, 3, 3, 3, rxb, &err), ST_OK);
    expect_error(&a, &b, "second image: no channel G");
    expect_error(&b, &a, "first image: no channel G");
    st_image_free(&b);
    make_image(&b, 3, 3, 8);
    b.types[2] = ST_PIXEL_UINT;
    expect_error(&a, &b, "second image: channel B is not float");
    st_image_free(&a);
    st_image_free(&b);
}

static void diff_non_finite_is_error(void **state)
{
    (void)state;
    st_image a, b;
    make_image(&a, 4, 3, 9);
    make_image(&b, 4, 3, 9);
    a.data[(2 * 4 + 1) * 3 + 2] = NAN; /* pixel (1, 2), B */
    expect_error(&a, &b, "first image: non-finite B at pixel (1, 2)");
    a.data[(2 * 4 + 1) * 3 + 2] = 0.f;
    b.data[0] = -INFINITY;
    expect_error(&a, &b, "second image: non-finite R at pixel (0, 0)");
    st_image_free(&a);
    st_image_free(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(diff_identical_images_rmse_zero),
        cmocka_unit_test(diff_constant_offset_gives_rmse_and_max_d),
        cmocka_unit_test(diff_alternating_and_half_offsets),
        cmocka_unit_test(diff_equals_brute_force_sum),
        cmocka_unit_test(diff_matches_channels_by_name),
        cmocka_unit_test(diff_size_mismatch_is_error),
        cmocka_unit_test(diff_missing_or_uint_channel_is_error),
        cmocka_unit_test(diff_non_finite_is_error),
    };
    return cmocka_run_group_tests_name("diff", tests, NULL, NULL);
}
