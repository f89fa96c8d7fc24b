/* fixed.h — film sums in 64-bit fixed point, so that atomic adds commute and
 * an image does not depend on the order in which work-items finish (floats
 * added in arrival order would; pbrt-v4, Cycles and LuxCore add floats).
 *
 * A value v is stored as round(v * 2^24) (ST_FIXED_SCALE), resolution 6e-8.
 * Each splat adds at most ST_SPLAT_MAX = 2^16 in magnitude (larger values are
 * clamped and counted), i.e. 2^40 units, so a pixel takes 2^23 splats before
 * a signed 64-bit sum (2^63) could overflow (2^23 - 1 splats are safe); the host checks
 * spp * footprint <= ST_FIXED_MAX_SPLATS before it renders.
 * Tests: test_fixed.c. */
#ifndef ST_FIXED_H
#define ST_FIXED_H

/* Clamps v to [-ST_SPLAT_MAX, ST_SPLAT_MAX]; *clamped is set when it had to.
 * NaN (from 0 x inf) becomes 0 and counts as clamped: converting it to an
 * integer is undefined. */
ST_FN st_f32 st_fixed_clamp(st_f32 v, st_u32 *clamped)
{
    if (v != v) {
        *clamped = 1u;
        return 0.0f;
    }
    if (v > ST_SPLAT_MAX) {
        *clamped = 1u;
        return ST_SPLAT_MAX;
    }
    if (v < -ST_SPLAT_MAX) {
        *clamped = 1u;
        return -ST_SPLAT_MAX;
    }
    return v;
}

/* round(v * 2^24), ties to even, for |v| <= ST_SPLAT_MAX. */
ST_FN st_i64 st_fixed_from_float(st_f32 v)
{
#ifdef __OPENCL_VERSION__
    return convert_long_rte(v * ST_FIXED_SCALE);
#else
    return (st_i64)llrintf(v * ST_FIXED_SCALE);
#endif
}

/* The four fixed-point sums one splat adds to a pixel: w r, w g, w b and the
 * weight w itself, each clamped (st_fixed_clamp) before conversion. Σf must be
 * clamped like Σf L: an unclamped weight (a filter with huge lobes) once
 * wrapped the 64-bit sum. Every splat path (film.cl, and any tile-owned
 * accumulation) adds exactly these integers, so all give the same film.
 * Tests: test_fixed.c fixed_splat_*. */
ST_FN void st_fixed_splat(st_f32 w, st_f32 r, st_f32 g, st_f32 b, st_i64 *sums,
                          st_u32 *clamped)
{
    sums[0] = st_fixed_from_float(st_fixed_clamp(w * r, clamped));
    sums[1] = st_fixed_from_float(st_fixed_clamp(w * g, clamped));
    sums[2] = st_fixed_from_float(st_fixed_clamp(w * b, clamped));
    sums[3] = st_fixed_from_float(st_fixed_clamp(w, clamped));
}

#endif
