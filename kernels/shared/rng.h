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

/* The functions below for one value (U = st_u32, F = st_f32, width 1, no
 * suffix) and, suffixed _lanes, for ST_W lanes of them (lanes.h), the same
 * numbers lane by lane:
 *   st_hash32(x)                  lowbias32;
 *   st_rng_key(seed, pixel, s)    the key of one sample, computed once, then
 *   st_rng_u32(key, dim)          per dimension,
 *   st_u32_to_unit(x)             the top 24 bits as a float in [0, 1), every
 *                                 value exactly representable,
 *   st_rng_unit(key, dim)         the two together. */
#define ST_RNG_DEFINE(U, F, n, sfx)                                                         \
    ST_FN U ST_CAT(st_hash32, sfx)(U x)                                                     \
    {                                                                                       \
        ST_HASH32_MIX(x);                                                                   \
        return x;                                                                           \
    }                                                                                       \
    ST_FN U ST_CAT(st_rng_key, sfx)(st_u32 seed, U pixel, U sample)                         \
    {                                                                                       \
        return ST_CAT(st_hash32, sfx)(                                                      \
            sample ^ ST_CAT(st_hash32, sfx)(pixel ^ st_hash32(seed ^ 0x5bd1e995u)));        \
    }                                                                                       \
    ST_FN U ST_CAT(st_rng_u32, sfx)(U key, U dim)                                           \
    {                                                                                       \
        return ST_CAT(st_hash32, sfx)(key ^ ST_CAT(st_hash32, sfx)(dim + 0x9e3779b9u));     \
    }                                                                                       \
    ST_FN F ST_CAT(st_u32_to_unit, sfx)(U x)                                                \
    {                                                                                       \
        return ST_TO_FLOAT(n, x >> 8) * 5.9604644775390625e-8f; /* 2^-24 */                 \
    }                                                                                       \
    ST_FN F ST_CAT(st_rng_unit, sfx)(U key, U dim)                                          \
    {                                                                                       \
        return ST_CAT(st_u32_to_unit, sfx)(ST_CAT(st_rng_u32, sfx)(key, dim));              \
    }

ST_RNG_DEFINE(st_u32, st_f32, 1, )
ST_RNG_DEFINE(st_lu, st_lf, ST_W, _lanes)

#endif
