/* halton.c — the scrambled Halton sampler's digit permutation tables
 * (st_sampling_halton_tables): the images of every digit at every position
 * that st_radical_inverse_scrambled reaches for a 32-bit index, per
 * dimension past the pixel's, for one render's seed. The kernels read them
 * instead of hashing each digit (samplers.h, st_radical_inverse_permuted),
 * as pbrt-v4's DigitPermutation tables do. */
#include "st_sampling.h"

#include <stdlib.h>

#include "rng.h"
#include "samplers.h"

/* 16-bit entries of dimension dim's table: every digit at every position. */
static size_t dim_entries(st_u32 dim)
{
    st_u32 b = st_primes[dim];
    return (size_t)st_scrambled_digit_count(b) * b;
}

st_status st_sampling_halton_tables(st_u32 seed, st_u32 **words, size_t *count, st_error *err)
{
    if (!words || !count)
        return st_fail(err, ST_ERR_USAGE, "Halton tables: NULL output");
    *words = NULL;
    *count = 0;
    size_t entries = 2u * ST_HALTON_TABLE_HEADER; /* the header, in 16-bit units */
    for (st_u32 dim = 2; dim < ST_PRIME_COUNT; dim++)
        entries += dim_entries(dim);
    size_t n = (entries + 1u) / 2u;
    st_u32 *w = calloc(n, sizeof *w);
    if (!w)
        return st_fail(err, ST_ERR_NOMEM, "out of memory for Halton's tables (%zu words)", n);
    st_u16 *e = (st_u16 *)w;
    size_t at = 2u * ST_HALTON_TABLE_HEADER;
    for (st_u32 dim = 2; dim < ST_PRIME_COUNT; dim++) {
        st_u32 b = st_primes[dim], key = st_halton_key(seed, dim);
        w[dim] = (st_u32)at;
        st_division_constants(b, &w[ST_PRIME_COUNT + dim], &w[2u * ST_PRIME_COUNT + dim],
                              &w[3u * ST_PRIME_COUNT + dim]);
        for (st_u32 k = 0; k < st_scrambled_digit_count(b); k++)
            for (st_u32 d = 0; d < b; d++)
                e[at++] = (st_u16)st_scrambled_digit(b, key, k, d);
    }
    *words = w;
    *count = n;
    return ST_OK;
}
