/* st_sampling.h — a sampler's point set as the laboratory sees it: the
 * samples of one pixel with spp = count, from the same functions of the
 * shared kernel headers that the renderer runs (kernels/sample/samplers.h), or, for
 * the tiled samplers, the renderer's tile (st_sampling_pixel_tile). So
 * `strata pattern --sampler halton --scramble none` prints
 * (Φ2(i), Φ3(i), Φ5(i), ...) and hammersley (i/N, Φ2(i), ...).
 * Tests: tests/unit/test_sampling_pattern.c. */
#ifndef ST_PATTERN_H
#define ST_PATTERN_H

#include "st_error.h"
#include "st_shared.h"

/* Largest --count and --dims. */
#define ST_SAMPLING_PATTERN_MAX_COUNT 1048576u
#define ST_SAMPLING_PATTERN_MAX_DIMS 256u

/* The first `dims` dimensions of `count` points of sampler `sampler`
 * (ST_SAMPLER_*), seed and scramble as for a render; *points holds
 * *out_count * dims floats in [0, 1), point-major, malloc'ed (caller frees).
 * *out_count equals count except for the tiled samplers (poisson,
 * best-candidate), whose tile of side x side pixels with spp points in each
 * (side = floor(sqrt(count)), spp = count / side^2) holds side^2 spp <= count. */
st_status st_sampling_pattern(st_u32 sampler, st_u32 count, st_u32 dims, st_u32 seed,
                          st_u32 scramble, float **points, st_u32 *out_count, st_error *err);

/* Whether the pattern changes with the seed (spectra average over seeds). */
int st_sampling_pattern_is_random(st_u32 sampler, st_u32 scramble);

#endif
