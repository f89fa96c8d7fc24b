/* test_render_samplers.c — every sampler in the renderer (issue: samplers):
 * deterministic for a fixed seed, and converging to the same image: against
 * a 2048-spp Sobol reference of the default scene (direct lighting, 24 x 24),
 * the RMSE at 64 spp is well below the RMSE at 4 spp for each sampler. For
 * independent samples the ratio is about sqrt(4/64) = 0.25; the bound 0.6
 * leaves room for the uniform grid, whose pixel positions do not improve
 * (its light samples do). And ZSobol's error is blue noise across pixels. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "device_fixture.h"
#include "st_diff.h"
#include "st_render.h"
#include "st_sampling.h"

static st_scene *scene;
static st_renderer *renderer;

/* The device fixture, then the default scene on it. */
static int setup(void **state)
{
    st_error err = {0};
    if (device_setup(state) || st_scene_load(NULL, &scene, &err) ||
        st_renderer_create(dev, scene, &renderer, &err)) {
        fprintf(stderr, "setup: %s\n", err.msg);
        return -1;
    }
    return 0;
}

static int teardown(void **state)
{
    st_renderer_destroy(renderer);
    st_scene_destroy(scene);
    return device_teardown(state);
}

static st_image render(st_u32 sampler, st_u32 spp, st_u32 seed)
{
    st_render_options o = st_render_defaults();
    o.width = o.height = 24;
    o.spp = spp;
    o.seed = seed;
    o.sampler = sampler;
    o.integrator = ST_INTEGRATOR_DIRECT;
    st_image img = {0};
    st_error err = {0};
    if (st_render(renderer, &o, &img, NULL, NULL, NULL, NULL, &err) != ST_OK)
        fail_msg("%s: %s", st_sampler_names[sampler], err.msg);
    return img;
}

static double rmse(const st_image *a, const st_image *b)
{
    st_diff_result d;
    st_error err = {0};
    if (st_diff_images(a, b, &d, &err) != ST_OK)
        fail_msg("%s", err.msg);
    return d.rmse;
}

static void every_sampler_deterministic_and_converging(void **state)
{
    (void)state;
    st_image ref = render(ST_SAMPLER_SOBOL, 2048, 99);
    for (st_u32 s = 0; s < ST_SAMPLER_COUNT; s++) {
        st_image a = render(s, 4, 3), b = render(s, 4, 3), c = render(s, 64, 3);
        assert_memory_equal(a.data, b.data, sizeof(float) * 4 * 24 * 24);
        double e4 = rmse(&a, &ref), e64 = rmse(&c, &ref);
        print_message("%-15s rmse 4 spp %.5f, 64 spp %.5f (ratio %.2f)\n", st_sampler_names[s],
                      e4, e64, e64 / e4);
        if (!(e64 < 0.6 * e4))
            fail_msg("%s: rmse %.5f at 64 spp is not well below %.5f at 4 spp",
                     st_sampler_names[s], e64, e4);
        st_image_free(&a);
        st_image_free(&b);
        st_image_free(&c);
    }
    st_image_free(&ref);
}

/* 128 x 128, direct lighting, box filter (each sample in its own pixel, so
 * neighbouring pixels' errors are correlated only through the sampler). */
#define BW 128
#define RX 36 /* a smooth region of the back wall: light-sampling noise only */
#define RY 28
#define RW 56
#define RH 28
static st_image render_box(st_u32 sampler, st_u32 spp, st_u32 seed)
{
    st_render_options o = st_render_defaults();
    o.width = o.height = BW;
    o.spp = spp;
    o.seed = seed;
    o.sampler = sampler;
    o.integrator = ST_INTEGRATOR_DIRECT;
    o.filter = st_filter_default(ST_FILTER_BOX);
    st_image img = {0};
    st_error err = {0};
    if (st_render(renderer, &o, &img, NULL, NULL, NULL, NULL, &err) != ST_OK)
        fail_msg("%s: %s", st_sampler_names[sampler], err.msg);
    return img;
}

/* Mean power of the error's spectrum (st_spectrum_image, 8 seeds, 4 spp)
 * at the low frequencies 0 < |k| <= 1/8 cycle per pixel, over its mean at
 * every k != 0: about 1 for independent error, below 1 for blue noise. */
static double low_frequency_power_ratio(st_u32 sampler, const st_image *ref)
{
    double power[RW * RH] = {0}, e[RW * RH];
    st_error err = {0};
    for (st_u32 seed = 0; seed < 8; seed++) {
        st_image img = render_box(sampler, 4, seed);
        for (int y = 0; y < RH; y++)
            for (int x = 0; x < RW; x++) {
                size_t i = (size_t)(y + RY) * BW + x + RX;
                e[y * RW + x] = (img.data[4 * i] + img.data[4 * i + 1] + img.data[4 * i + 2] -
                                 ref->data[4 * i] - ref->data[4 * i + 1] - ref->data[4 * i + 2]) / 3;
            }
        assert_int_equal(st_spectrum_image(e, RW, RH, power, &err), ST_OK);
        st_image_free(&img);
    }
    double low = 0, all = 0;
    int nlow = 0, nall = 0;
    for (int r = 0; r < RH; r++)
        for (int c = 0; c < RW; c++) {
            int kx = c - RW / 2, ky = r - RH / 2;
            double m = hypot(kx / (double)RW, ky / (double)RH); /* cycles per pixel */
            if (kx == 0 && ky == 0)
                continue;
            all += power[r * RW + c];
            nall++;
            if (m <= 0.125) {
                low += power[r * RW + c];
                nlow++;
            }
        }
    return (low / nlow) / (all / nall);
}

/* ZSobol spreads the error as blue noise across pixels (Ahmed and Wonka
 * 2020): its low-frequency error power, relative to its mean, is well below
 * that of independent samples, on a smooth region (over the whole image the
 * edges' error dominates and is not blue: measured ratio 1.2). Tolerances:
 * random's ratio is 1 within its noise (about 75 bins x 8 seeds of
 * exponential variables: sd 0.04, bounds 0.7..1.3); zsobol's must be below
 * 0.6 and below 0.7 x random's (measured: random 0.995, zsobol 0.307). */
static void zsobol_error_is_blue_noise(void **state)
{
    (void)state;
    st_image ref = render_box(ST_SAMPLER_PADDED_SOBOL, 1024, 99);
    double r = low_frequency_power_ratio(ST_SAMPLER_RANDOM, &ref);
    double z = low_frequency_power_ratio(ST_SAMPLER_ZSOBOL, &ref);
    print_message("low-frequency error power / mean: random %.3f, zsobol %.3f\n", r, z);
    if (!(r > 0.7 && r < 1.3 && z < 0.6 && z < 0.7 * r))
        fail_msg("random %.3f, zsobol %.3f", r, z);
    st_image_free(&ref);
}

/* The box filter is closed at its radius (filters.h): unscrambled sequences
 * put sample 0 of every pixel on the pixel's corner (Hammersley and padded
 * Sobol', every sample 0; Sobol' and Halton, some), where an open box gave it
 * no pixel. Here every pixel's weight sum (the film's fourth sum, 1 per
 * sample that reaches it, in units of 2^24) is at least its own spp, no
 * pixel is without weight, every sample reaches a pixel, and each splat adds
 * exactly 1 to a weight: the film's total weight is the splat count. */
static void unscrambled_box_weighs_every_sample(void **state)
{
    (void)state;
    const st_u32 samplers[] = {ST_SAMPLER_HAMMERSLEY, ST_SAMPLER_PADDED_SOBOL, ST_SAMPLER_SOBOL,
                               ST_SAMPLER_HALTON};
    const st_u32 spps[] = {1, 4};
    for (size_t k = 0; k < sizeof samplers / sizeof samplers[0]; k++)
        for (size_t q = 0; q < 2; q++) {
            st_render_options o = st_render_defaults();
            o.width = o.height = 32;
            o.spp = spps[q];
            o.sampler = samplers[k];
            o.scramble = 0;
            o.integrator = ST_INTEGRATOR_DIRECT;
            o.filter = st_filter_default(ST_FILTER_BOX);
            st_image img = {0};
            st_i64 *sums = NULL;
            st_render_stats st;
            st_error err = {0};
            if (st_render(renderer, &o, &img, &sums, &st, NULL, NULL, &err) != ST_OK)
                fail_msg("%s: %s", st_sampler_names[samplers[k]], err.msg);
            const st_i64 one = (st_i64)ST_FIXED_SCALE;
            st_i64 total = 0;
            for (size_t i = 0; i < (size_t)o.width * o.height; i++) {
                st_i64 w = sums[4 * i + 3];
                if (w % one != 0 || w < (st_i64)o.spp * one)
                    fail_msg("%s %u spp: pixel %zu weighs %g, its own samples alone %u",
                             st_sampler_names[samplers[k]], o.spp, i, (double)w / one, o.spp);
                total += w / one;
            }
            assert_int_equal(st.zero_weight, 0);
            assert_true(st.samples == (st_u64)o.spp * o.width * o.height);
            assert_true(st.splats >= st.samples);
            assert_true((st_u64)total == st.splats);
            free(sums);
            free(st.spp_map);
            st_image_free(&img);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(unscrambled_box_weighs_every_sample),
        cmocka_unit_test(every_sampler_deterministic_and_converging),
        cmocka_unit_test(zsobol_error_is_blue_noise),
    };
    return cmocka_run_group_tests_name("sampler_render", tests, setup, teardown);
}
