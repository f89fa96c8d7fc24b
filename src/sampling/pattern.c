/* pattern.c — point sets for the laboratory (see st_sampling.h). */
#include "st_sampling.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rng.h"
#include "samplers.h"

int st_sampling_pattern_is_random(st_u32 sampler, st_u32 scramble)
{
    if (sampler == ST_SAMPLER_UNIFORM)
        return 0;
    /* zsobol's digit permutations follow the seed even unscrambled */
    if (sampler == ST_SAMPLER_HALTON || sampler == ST_SAMPLER_HAMMERSLEY ||
        sampler == ST_SAMPLER_PADDED_SOBOL || sampler == ST_SAMPLER_SOBOL)
        return scramble != 0;
    return 1;
}

/* The points of a tiled sampler: tile[2 i], tile[2 i + 1] in pixels of a
 * side x side torus, point i in pixel i mod side^2 as its sample i / side^2,
 * spp a pixel; scaled to the unit square, and dimensions past 2 as the
 * renderer draws them (the pad tables, st_sampling_pad_tables, read through
 * the point's tile pixel and sample). Takes tile. */
static st_status tiled_points(st_u32 sampler, float *tile, st_u32 side, st_u32 spp, st_u32 dims,
                              st_u32 seed, float **points, st_u32 *n, st_error *err)
{
    st_u32 pixels = side * side;
    *n = pixels * spp;
    st_u32 *pad = NULL, pad_count;
    st_status rc = dims > 2u ? st_sampling_pad_tables(sampler, spp, seed, &pad, &pad_count, err)
                             : ST_OK;
    float *pts = rc == ST_OK ? malloc(sizeof(float) * (size_t)*n * dims) : NULL;
    if (rc == ST_OK && !pts)
        rc = st_fail(err, ST_ERR_NOMEM, "out of memory for %u points", *n);
    if (rc != ST_OK) {
        free(tile);
        free(pad);
        return rc;
    }
    st_params p;
    memset(&p, 0, sizeof p);
    p.width = p.height = side;
    p.spp = spp;
    p.seed = seed;
    p.sampler = sampler;
    for (st_u32 i = 0; i < *n; i++) {
        st_u32 pixel = i % pixels;
        st_sample_id id = st_sample_begin(&p, pixel % side, pixel / side, i / pixels);
        id.pmj02 = pad;
        for (st_u32 d = 0; d < dims; d++) {
            float x = d < 2u ? tile[2 * i + d] / (float)side : st_sample_dim(&p, &id, d);
            pts[(size_t)i * dims + d] = x < 1.0f ? x : nextafterf(1.0f, 0.0f);
        }
    }
    free(tile);
    free(pad);
    *points = pts;
    return ST_OK;
}

/* The lecture's pattern of a tiled sampler over the unit square: Bridson's
 * Poisson disk (st_sampling_poisson_tile, about count points) or Mitchell's
 * best candidate (st_sampling_best_candidate_tile), one pixel of count
 * points as far as the later dimensions go. */
static st_status lecture(st_u32 sampler, st_u32 count, st_u32 dims, st_u32 seed,
                         float **points, st_u32 *n, st_error *err)
{
    float *tile = NULL;
    st_u32 got = count;
    st_status rc = sampler == ST_SAMPLER_POISSON
                       ? st_sampling_poisson_tile(count, seed, &tile, &got, NULL, err)
                       : st_sampling_best_candidate_tile(count, seed, &tile, err);
    if (rc != ST_OK)
        return rc;
    return tiled_points(sampler, tile, 1u, got, dims, seed, points, n, err);
}

st_status st_sampling_pattern_pixels(st_u32 sampler, st_u32 count, st_u32 dims, st_u32 seed,
                                     float **points, st_u32 *out_count, st_error *err)
{
    *points = NULL;
    *out_count = 0;
    if (!ST_SAMPLER_IS_TILED(sampler))
        return st_fail(err, ST_ERR_USAGE, "%s: one point per pixel is poisson's and "
                       "best-candidate's rule, not this sampler's",
                       sampler < ST_SAMPLER_COUNT ? st_sampler_names[sampler] : "sampler");
    if (count < 1 || count > ST_SAMPLING_PATTERN_MAX_COUNT || dims < 1 ||
        dims > ST_SAMPLING_PATTERN_MAX_DIMS)
        return st_fail(err, ST_ERR_USAGE, "count %u, dims %u: must be in 1..%u and 1..%u", count,
                       dims, ST_SAMPLING_PATTERN_MAX_COUNT, ST_SAMPLING_PATTERN_MAX_DIMS);
    float *tile = NULL;
    st_u32 side = (st_u32)sqrt((double)count);
    while ((st_u64)side * side > count) /* floor, whatever sqrt rounded to */
        side--;
    st_u32 spp = count / (side * side);
    st_status rc = st_sampling_pixel_tile(sampler, side, spp, seed, &tile, NULL, err);
    if (rc != ST_OK)
        return rc;
    return tiled_points(sampler, tile, side, spp, dims, seed, points, out_count, err);
}

st_status st_sampling_pattern(st_u32 sampler, st_u32 count, st_u32 dims, st_u32 seed,
                          st_u32 scramble, float **points, st_u32 *out_count, st_error *err)
{
    *points = NULL;
    *out_count = 0;
    if (sampler >= ST_SAMPLER_COUNT)
        return st_fail(err, ST_ERR_USAGE, "unknown sampler %u", sampler);
    if (count < 1 || count > ST_SAMPLING_PATTERN_MAX_COUNT)
        return st_fail(err, ST_ERR_USAGE, "count %u: must be in 1..%u", count,
                       ST_SAMPLING_PATTERN_MAX_COUNT);
    if (dims < 1 || dims > ST_SAMPLING_PATTERN_MAX_DIMS)
        return st_fail(err, ST_ERR_USAGE, "dims %u: must be in 1..%u", dims, ST_SAMPLING_PATTERN_MAX_DIMS);
    if (ST_SAMPLER_IS_TILED(sampler))
        return lecture(sampler, count, dims, seed, points, out_count, err);
    st_params p;
    memset(&p, 0, sizeof p);
    p.width = p.height = 1;
    p.spp = count;
    p.seed = seed;
    p.sampler = sampler;
    p.scramble = scramble;
    st_sampler_prepare(&p);
    /* pmj02: the renderer's tables for spp = count */
    st_u32 *pmj02 = NULL;
    int pmj = sampler == ST_SAMPLER_PMJ02 || sampler == ST_SAMPLER_PMJ02BN;
    if (pmj && count > (1u << ST_PMJ02_MAX_LOG2))
        return st_fail(err, ST_ERR_USAGE, "count %u: %s's tables hold at most %u points", count,
                       st_sampler_names[sampler], 1u << ST_PMJ02_MAX_LOG2);
    size_t words = 0;
    if (pmj && (sampler == ST_SAMPLER_PMJ02BN
                    ? st_sampling_pmj02bn_tables(count, seed, &pmj02, &words, err)
                    : st_sampling_pmj02(st_log2_ceil(count), ST_PMJ02_SETS, seed, &pmj02, err)) !=
                   ST_OK)
        return err ? err->status : ST_ERR_NOMEM;
    /* scrambled Halton: the renderer's digit permutation tables, in the slot */
    p.halton_tables = sampler == ST_SAMPLER_HALTON && scramble;
    if (p.halton_tables && st_sampling_halton_tables(seed, &pmj02, &words, err) != ST_OK)
        return err ? err->status : ST_ERR_NOMEM;
    float *pts = malloc(sizeof(float) * (size_t)count * dims);
    if (!pts) {
        free(pmj02);
        return st_fail(err, ST_ERR_NOMEM, "out of memory for %u points", count);
    }
    for (st_u32 i = 0; i < count; i++) {
        st_sample_id id = st_sample_begin(&p, 0u, 0u, i);
        id.pmj02 = pmj02;
        for (st_u32 d = 0; d < dims; d++)
            pts[(size_t)i * dims + d] = st_sample_dim(&p, &id, d);
    }
    free(pmj02);
    *points = pts;
    *out_count = count;
    return ST_OK;
}
