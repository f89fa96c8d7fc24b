/* test_sampling_image_spectrum.c — st_spectrum_image (src/sampling/image_spectrum.c) against
 * closed forms: a single bright pixel has a flat spectrum a^2 / N; a cosine
 * of frequency (3, 2) puts N/4 at +-(3, 2) and nothing elsewhere; results
 * accumulate; the mean over many white-noise images is flat at the variance
 * (tolerance 4 standard errors of the mean of exponential variables). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>

#include "st_sampling.h"

static void delta_has_flat_spectrum_and_accumulates(void **state)
{
    (void)state;
    st_u32 w = 12, h = 7;
    double v[84] = {0}, power[84] = {0};
    v[5 * w + 3] = 2.0;
    st_error err = {0};
    assert_int_equal(st_spectrum_image(v, w, h, power, &err), ST_OK);
    assert_int_equal(st_spectrum_image(v, w, h, power, &err), ST_OK);
    for (int i = 0; i < 84; i++)
        assert_true(fabs(power[i] - 2 * 4.0 / 84) < 1e-12);
}

static void cosine_peaks_at_its_frequency(void **state)
{
    (void)state;
    st_u32 w = 16, h = 8, n = 128;
    double v[128], power[128] = {0};
    for (st_u32 y = 0; y < h; y++)
        for (st_u32 x = 0; x < w; x++)
            v[y * w + x] = cos(6.283185307179586 * (3.0 * x / w + 2.0 * y / h));
    st_error err = {0};
    assert_int_equal(st_spectrum_image(v, w, h, power, &err), ST_OK);
    for (st_u32 r = 0; r < h; r++)
        for (st_u32 c = 0; c < w; c++) {
            int kx = (int)c - (int)w / 2, ky = (int)r - (int)h / 2;
            int peak = (kx == 3 && ky == 2) || (kx == -3 && ky == -2);
            double want = peak ? n / 4.0 : 0.0;
            if (fabs(power[r * w + c] - want) > 1e-9)
                fail_msg("k = (%d, %d): %.12g, expected %.12g", kx, ky, power[r * w + c], want);
        }
}

static void white_noise_is_flat_at_its_variance(void **state)
{
    (void)state;
    st_u32 w = 16, h = 16, runs = 400;
    double v[256], power[256] = {0};
    st_error err = {0};
    srand(7);
    for (st_u32 r = 0; r < runs; r++) {
        for (int i = 0; i < 256; i++)
            v[i] = ((double)rand() / RAND_MAX - 0.5) * sqrt(12.0); /* variance 1, mean 0 */
        assert_int_equal(st_spectrum_image(v, w, h, power, &err), ST_OK);
    }
    /* P(k) of one image is ~ exponential with mean 1 (sd 1): the mean of 400
     * has sd 0.05; k = 0 and the real frequencies (kx, ky in {0, 8}) are chi^2
     * with 1 degree of freedom (sd sqrt 2): sd 0.071. 4 sd: 0.29. */
    for (int i = 0; i < 256; i++)
        if (fabs(power[i] / runs - 1.0) > 0.29)
            fail_msg("bin %d: mean power %.3f, expected 1", i, power[i] / runs);
}

static void rejects_bad_arguments(void **state)
{
    (void)state;
    double v[4] = {0}, p[4] = {0};
    st_error err = {0};
    assert_int_equal(st_spectrum_image(NULL, 2, 2, p, &err), ST_ERR_USAGE);
    assert_int_equal(st_spectrum_image(v, 0, 2, p, &err), ST_ERR_USAGE);
    assert_int_equal(st_spectrum_image(v, 2, 2, NULL, &err), ST_ERR_USAGE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(delta_has_flat_spectrum_and_accumulates),
        cmocka_unit_test(cosine_peaks_at_its_frequency),
        cmocka_unit_test(white_noise_is_flat_at_its_variance),
        cmocka_unit_test(rejects_bad_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
