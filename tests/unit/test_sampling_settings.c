/* test_sampling_settings.c — guards src/sampling/sampler.c, the sampler module (st_sampling.h):
 * names, predicates, preparation and the Halton index check. (test_sampling_kernels.c
 * guards the per-sample functions of kernels/sample/samplers.h.)
 *
 * The Halton limit is derived here: at width x height the pixel scales are
 * 2^e2 >= min(width, 128) and 3^e3 >= min(height, 128), the stride their
 * product, and the largest index stride * spp - 1 must fit in 32 bits. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "st_sampling.h"

static void sampler_names_and_predicates(void **state)
{
    (void)state;
    for (st_u32 s = 0; s < ST_SAMPLER_COUNT; s++) {
        assert_int_equal(st_sampler_lookup(st_sampler_names[s]), (int)s);
        assert_int_equal(st_sampler_is_tiled(s), s == ST_SAMPLER_POISSON || s == ST_SAMPLER_BEST_CANDIDATE);
    }
    assert_int_equal(st_sampler_lookup("dart"), -1);
    assert_true(st_sampler_takes_scramble(ST_SAMPLER_HALTON));
    assert_true(st_sampler_takes_scramble(ST_SAMPLER_SOBOL));
    assert_true(st_sampler_takes_scramble(ST_SAMPLER_STRATIFIED));
    assert_false(st_sampler_takes_scramble(ST_SAMPLER_RANDOM));
    assert_false(st_sampler_takes_scramble(ST_SAMPLER_POISSON));
}

/* 200 x 100: 2^7 = 128 (width capped at 128), 3^5 = 243 >= 100: stride 31104. */
static void sampler_prepare_pixel_scales(void **state)
{
    (void)state;
    st_params p;
    memset(&p, 0, sizeof p);
    p.width = 200;
    p.height = 100;
    p.spp = 12;
    st_sampler_prepare(&p);
    assert_int_equal(p.halton_exp2, 7); /* 2^7 = 128: the cap */
    assert_int_equal(p.halton_exp3, 5);
    assert_int_equal(p.halton_stride, 128 * 243);
    assert_int_equal((p.halton_inv2 * (243 % 128)) % 128, 1); /* inverses mod each scale */
    assert_int_equal((p.halton_inv3 * (128 % 243)) % 243, 1);
    assert_int_equal(p.strat_nx * p.strat_ny, 12);
    assert_int_equal(p.strat_nx, 3);
}

static void sampler_check_halton_index_limit(void **state)
{
    (void)state;
    st_u32 stride = 128 * 243, limit = (st_u32)(0x100000000ull / stride);
    st_error err = {0};
    assert_int_equal(st_sampler_check(ST_SAMPLER_HALTON, 512, 512, limit, &err), ST_OK);
    assert_int_equal(st_sampler_check(ST_SAMPLER_HALTON, 512, 512, limit + 1, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "spp"));
    assert_null(strstr(err.msg, "--"));
    /* other samplers index by sample alone */
    st_error e2 = {0};
    assert_int_equal(st_sampler_check(ST_SAMPLER_PADDED_SOBOL, 512, 512, limit + 1, &e2), ST_OK);
    st_error e3 = {0};
    assert_int_equal(st_sampler_check(ST_SAMPLER_COUNT, 16, 16, 1, &e3), ST_ERR_USAGE);
    char want[32];
    snprintf(want, sizeof want, "sampler %u", ST_SAMPLER_COUNT);
    assert_non_null(strstr(e3.msg, want));
}

/* Global Sobol' and ZSobol: 2m bits of pixel (2^m = 512 >= 512) and
 * ceil(log2 spp) bits of sample fit 32 bits: spp 2^14 passes, 2^14 + 1 not. */
static void sampler_check_sobol_index_limit(void **state)
{
    (void)state;
    st_u32 samplers[2] = {ST_SAMPLER_SOBOL, ST_SAMPLER_ZSOBOL};
    for (int k = 0; k < 2; k++) {
        st_error err = {0};
        assert_int_equal(st_sampler_check(samplers[k], 512, 300, 1u << 14, &err), ST_OK);
        assert_int_equal(st_sampler_check(samplers[k], 512, 300, (1u << 14) + 1, &err),
                         ST_ERR_USAGE);
        assert_non_null(strstr(err.msg, "spp 16385"));
        assert_int_equal(st_sampler_check(samplers[k], 513, 2, 1u << 12, &err), ST_OK);
        assert_int_equal(st_sampler_check(samplers[k], 513, 2, (1u << 12) + 1, &err),
                         ST_ERR_USAGE);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sampler_names_and_predicates),
        cmocka_unit_test(sampler_prepare_pixel_scales),
        cmocka_unit_test(sampler_check_halton_index_limit),
        cmocka_unit_test(sampler_check_sobol_index_limit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
