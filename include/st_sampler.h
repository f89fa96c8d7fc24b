/* st_sampling.h — the sampler as a concept on the host: names, what each kind
 * is (per-pixel or tiled, scrambled or not), the check of a render's sampler
 * settings, and the preparation of st_params' sampler fields. The per-sample
 * functions the kernels run (radical inverse, Halton index, Sobol, ...) stay
 * in kernels/sample/samplers.h; the tiles of the tiled samplers come from the
 * sampling module (st_sampling.h).
 *
 * A sampler is an ST_SAMPLER_* value (st_shared.h). Nothing here allocates or
 * prints; the check returns ST_ERR_USAGE with a message naming the field
 * ("spp 70000: ..."), which the CLI may rewrite as the option that sets it.
 *
 * Tests: tests/unit/test_sampling_settings.c (names, predicates, preparation, the Halton
 * check); tests/unit/test_sampling_kernels.c guards kernels/sample/samplers.h. */
#ifndef ST_SAMPLER_H
#define ST_SAMPLER_H

#include "st_error.h"
#include "st_shared.h"

/* Names, indexed by ST_SAMPLER_*. */
extern const char *const st_sampler_names[ST_SAMPLER_COUNT];
/* The ST_SAMPLER_* of a name, or -1. */
int st_sampler_lookup(const char *name);

/* Whether the scramble switch changes the sampler (stratified: the order of
 * its strata; halton, hammersley, sobol: digit scrambling). */
int st_sampler_takes_scramble(st_u32 sampler);

/* Whether the sampler places its points across pixels from a host-made tile
 * (poisson, best-candidate) rather than per pixel; the kernels test the same
 * ST_SAMPLER_IS_TILED. Per-pixel sampling is what filter importance sampling
 * and adaptive rounds need. */
int st_sampler_is_tiled(st_u32 sampler);

/* Checks that sampler is known and that its indices fit in 32 bits for a
 * width x height image at spp samples per pixel: Halton's global index is
 * stride * spp, with stride = 2^e2 3^e3 the pixel scales (st_sampler_prepare).
 * ST_ERR_USAGE naming the field ("sampler", "spp"). */
st_status st_sampler_check(st_u32 sampler, st_u32 width, st_u32 height, st_u32 spp,
                           st_error *err);

/* Fills p's sampler fields (stratified grid, Halton scales and their
 * inverses) from p->width, p->height and p->spp (pbrt-v4's HaltonSampler
 * constructor for the pixel scales). */
void st_sampler_prepare(st_params *p);

#endif
