/* rng.h — counter-based random numbers: a pure function of (seed, pixel,
 * sample, dimension), as pbrt-v4's StartPixelSample and Cycles' path_rng_1D
 * are, so that no state is shared between work-items and any split of the
 * work gives the same numbers.
 *
 * The mixing function is "lowbias32" from Chris Wellons, "Prospecting for Hash
 * Functions" (2018, nullprogram.com/blog/2018/07/31/): a 32-bit bijection with
 * low avalanche bias. Keys are chained so each argument is fully mixed.
 * Tests: test_sampling_kernels.c rng_*. */
#ifndef ST_RNG_H
#define ST_RNG_H

#include "lanes.h"

/* lowbias32's steps on x, a 32-bit unsigned value or lanes of them. */
#define ST_HASH32_MIX(x)                                                                  \
    do {                                                                                    \
        (x) ^= (x) >> 16;                                                                   \
        (x) *= 0x7feb352du;                                                                 \
        (x) ^= (x) >> 15;                                                                   \
        (x) *= 0x846ca68bu;                                                                 \
        (x) ^= (x) >> 16;                                                                   \
    } while (0)

ST_FN st_u32 st_hash32(st_u32 x)
{
    ST_HASH32_MIX(x);
    return x;
}

/* Key of one sample: computed once, then st_rng_u32(key, dim) per dimension. */
ST_FN st_u32 st_rng_key(st_u32 seed, st_u32 pixel, st_u32 sample)
{
    return st_hash32(sample ^ st_hash32(pixel ^ st_hash32(seed ^ 0x5bd1e995u)));
}

ST_FN st_u32 st_rng_u32(st_u32 key, st_u32 dim)
{
    return st_hash32(key ^ st_hash32(dim + 0x9e3779b9u));
}

/* The top 24 bits as a float in [0, 1): every value exactly representable. */
ST_FN st_f32 st_u32_to_unit(st_u32 x)
{
    return (st_f32)(x >> 8) * 5.9604644775390625e-8f; /* 2^-24 */
}

ST_FN st_f32 st_rng_unit(st_u32 key, st_u32 dim)
{
    return st_u32_to_unit(st_rng_u32(key, dim));
}

/* The same numbers in lanes (lanes.h), lane by lane: st_rng_key of a pixel
 * and a sample per lane, st_rng_unit of a key and a dimension per lane. */
ST_FN st_lu st_hash32_lanes(st_lu x)
{
    ST_HASH32_MIX(x);
    return x;
}

ST_FN st_lu st_rng_key_lanes(st_u32 seed, st_lu pixel, st_lu sample)
{
    return st_hash32_lanes(sample ^ st_hash32_lanes(pixel ^ st_hash32(seed ^ 0x5bd1e995u)));
}

ST_FN st_lf st_rng_unit_lanes(st_lu key, st_lu dim)
{
    st_lu x = st_hash32_lanes(key ^ st_hash32_lanes(dim + 0x9e3779b9u)); /* st_rng_u32 */
    return ST_TO_FLOAT(ST_W, x >> 8) * 5.9604644775390625e-8f; /* st_u32_to_unit */
}

#endif
