/* sampler.c — the sampler module on the host (st_sampling.h): names,
 * predicates, the check of a render's sampler settings and the preparation
 * of the per-render fields the kernels' samplers.h reads. Invariant: the
 * check accepts exactly the settings whose Halton indices st_halton_index
 * (samplers.h) computes without wrapping past 2^32. */
#include "st_sampling.h"

#include <string.h>

#include "rng.h"
#include "st_names.h"
#include "samplers.h"

const char *const st_sampler_names[ST_SAMPLER_COUNT] = {
    "random", "uniform", "stratified", "halton", "hammersley", "poisson", "best-candidate",
    "paddedsobol", "sobol", "zsobol", "joint-stratified", "pmj02", "pmj02bn"};

int st_sampler_lookup(const char *name)
{
    return st_name_lookup(st_sampler_names, (int)ST_SAMPLER_COUNT, name);
}

int st_sampler_takes_scramble(st_u32 sampler)
{
    return sampler == ST_SAMPLER_STRATIFIED || sampler == ST_SAMPLER_HALTON ||
           sampler == ST_SAMPLER_HAMMERSLEY || sampler == ST_SAMPLER_PADDED_SOBOL ||
           sampler == ST_SAMPLER_SOBOL || sampler == ST_SAMPLER_ZSOBOL;
}

int st_sampler_is_tiled(st_u32 sampler)
{
    return ST_SAMPLER_IS_TILED(sampler);
}

/* The smallest m with 2^m >= width and height (pbrt-v4's SobolSampler
 * scale), at most 16. */
static st_u32 sobol_log2(st_u32 width, st_u32 height)
{
    st_u32 m = 0;
    while (m < 16u && ((1u << m) < width || (1u << m) < height))
        m++;
    return m;
}

/* Global Sobol' and ZSobol index the sequence with 32 bits: 2m bits of pixel
 * and the sample's bits above them (st_sobol_global_index, st_zsobol_index). */
static st_status sobol_check(st_u32 sampler, st_u32 width, st_u32 height, st_u32 spp,
                             st_error *err)
{
    st_u32 m = sobol_log2(width, height), l = st_log2_ceil(spp);
    if (width > 65536u || height > 65536u)
        return st_fail(err, ST_ERR_USAGE, "image size %ux%u: %s needs at most 65536 a side", width,
                       height, st_sampler_names[sampler]);
    if (2u * m + l > 32u)
        return st_fail(err, ST_ERR_USAGE,
                       "spp %u: %s indices would pass 2^32 at %ux%u pixels (2^%u x 2^%u grid)",
                       spp, st_sampler_names[sampler], width, height, m, m);
    return ST_OK;
}

/* The per-render constants of the samplers that have them. */
void st_sampler_prepare(st_params *p)
{
    st_stratified_grid(p->spp, &p->strat_nx, &p->strat_ny);
    st_halton_setup(p);
    p->sobol_log2 = sobol_log2(p->width, p->height);
}

st_status st_sampler_check(st_u32 sampler, st_u32 width, st_u32 height, st_u32 spp,
                           st_error *err)
{
    if (sampler >= ST_SAMPLER_COUNT)
        return st_fail(err, ST_ERR_USAGE, "sampler %u: unknown", sampler);
    if (sampler == ST_SAMPLER_SOBOL || sampler == ST_SAMPLER_ZSOBOL)
        return sobol_check(sampler, width, height, spp, err);
    if ((sampler == ST_SAMPLER_PMJ02 || sampler == ST_SAMPLER_PMJ02BN) &&
        spp > (1u << ST_PMJ02_MAX_LOG2))
        return st_fail(err, ST_ERR_USAGE, "spp %u: %s's tables hold at most %u samples per "
                       "pixel", spp, st_sampler_names[sampler], 1u << ST_PMJ02_MAX_LOG2);
    if (sampler != ST_SAMPLER_HALTON)
        return ST_OK;
    st_params p;
    memset(&p, 0, sizeof p);
    p.width = width;
    p.height = height;
    p.spp = spp;
    st_sampler_prepare(&p);
    if ((st_u64)p.halton_stride * spp > 0xffffffffull)
        return st_fail(err, ST_ERR_USAGE,
                       "spp %u: Halton indices would pass 2^32 at %ux%u pixels (stride %u)",
                       spp, width, height, p.halton_stride);
    return ST_OK;
}
