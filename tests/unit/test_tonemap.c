/* test_tonemap.c — guards src/image/tonemap.c (include/st_tonemap.h) against its definitions. Expected
 * values: exposure is an exact power of two; Reinhard's grey x maps to x/(1+x); Hable's filmic
 * values were computed from the formula in Python 3 (h(1)/h(11.2) = 0.304300561467247,
 * h(0.5)/h(11.2) = 0.17196964226803543, h(4)/h(11.2) = 0.7132380109726539). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>

#include "st_tonemap.h"

static void one(float r, float g, float b, float ev, st_tonemap t, float out[3])
{
    out[0] = r, out[1] = g, out[2] = b;
    st_tonemap_apply(out, 1, 3, ev, t);
}

static void exposure_scales_by_powers_of_two(void **state)
{
    (void)state;
    float c[3];
    one(0.3f, 0.5f, 2.0f, 1.0f, ST_TONEMAP_CLAMP, c);
    assert_true(c[0] == 0.6f && c[1] == 1.0f && c[2] == 4.0f); /* clamp leaves > 1 to the encoder */
    one(0.3f, 0.5f, 2.0f, -2.0f, ST_TONEMAP_CLAMP, c);
    assert_true(c[0] == 0.075f && c[1] == 0.125f && c[2] == 0.5f);
    one(0.3f, 0.5f, 2.0f, 0.0f, ST_TONEMAP_CLAMP, c);
    assert_true(c[0] == 0.3f && c[1] == 0.5f && c[2] == 2.0f);
}

static void reinhard_maps_luminance(void **state)
{
    (void)state;
    float c[3];
    one(1.0f, 1.0f, 1.0f, 0.0f, ST_TONEMAP_REINHARD, c); /* grey: L = 1 -> 1/2 */
    for (int j = 0; j < 3; j++)
        assert_true(fabsf(c[j] - 0.5f) < 1e-7f);
    one(1.5f, 1.5f, 1.5f, 1.0f, ST_TONEMAP_REINHARD, c); /* 3 after exposure -> 3/4 */
    assert_true(fabsf(c[1] - 0.75f) < 1e-7f);
    one(2.0f, 1.0f, 0.5f, 0.0f, ST_TONEMAP_REINHARD, c); /* hue kept: ratios unchanged */
    assert_true(fabsf(c[0] / c[1] - 2.0f) < 1e-6f && fabsf(c[2] / c[1] - 0.5f) < 1e-6f);
    double lum = 0.2126 * 2.0 + 0.7152 * 1.0 + 0.0722 * 0.5;
    assert_true(fabs(c[1] - 1.0 / (1.0 + lum)) < 1e-7);
    one(0.0f, 0.0f, 0.0f, 0.0f, ST_TONEMAP_REINHARD, c);
    assert_true(c[0] == 0.0f && c[1] == 0.0f && c[2] == 0.0f);
}

static void filmic_follows_hable(void **state)
{
    (void)state;
    float c[3];
    one(1.0f, 0.5f, 4.0f, 0.0f, ST_TONEMAP_FILMIC, c);
    assert_true(fabs(c[0] - 0.304300561467247) < 1e-7);
    assert_true(fabs(c[1] - 0.17196964226803543) < 1e-7);
    assert_true(fabs(c[2] - 0.7132380109726539) < 1e-7);
    one(11.2f, 0.0f, 1e-9f, 0.0f, ST_TONEMAP_FILMIC, c); /* white point -> 1, black -> 0 */
    assert_true(fabsf(c[0] - 1.0f) < 1e-6f && c[1] == 0.0f && fabsf(c[2]) < 1e-8f);
    float prev = 0.0f; /* increasing */
    for (int k = 1; k <= 200; k++) {
        one(k * 0.05f, 0, 0, 0.0f, ST_TONEMAP_FILMIC, c);
        assert_true(c[0] > prev);
        prev = c[0];
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(exposure_scales_by_powers_of_two),
        cmocka_unit_test(reinhard_maps_luminance),
        cmocka_unit_test(filmic_follows_hable),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
