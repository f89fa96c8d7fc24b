/* test_sampler_render.c — every sampler in the renderer (issue: samplers):
 * deterministic for a fixed seed, and converging to the same image: against
 * a 2048-spp Sobol reference of the default scene (direct lighting, 24 x 24),
 * the RMSE at 64 spp is well below the RMSE at 4 spp for each sampler. For
 * independent samples the ratio is about sqrt(4/64) = 0.25; the bound 0.6
 * leaves room for the uniform grid, whose pixel positions do not improve
 * (its light samples do). */
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(every_sampler_deterministic_and_converging),
    };
    return cmocka_run_group_tests_name("sampler_render", tests, setup, teardown);
}
