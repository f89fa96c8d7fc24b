/* film.cl — reconstruction: every sample adds f(x - x_i, y - y_i) L_i and
 * f(x - x_i, y - y_i) to each pixel whose centre lies within the filter
 * radius, as 64-bit fixed-point integers (fixed.h) with atom_add, so the sums
 * do not depend on the order of the adds; resolve divides. */
#include "st_shared.h"
#include "filters.h"
#include "fixed.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable

#define ST_MAX_TAPS 17 /* 2 * ST_FILTER_MAX_RADIUS + 1 */

static void count(__global uint *stats, st_u32 which)
{
    atomic_inc(&stats[which]);
}

/* Adds w L and w to one pixel's four sums. */
static void add_splat(__global long *a, float w, float3 L, st_u32 *clamped)
{
    atom_add(a + 0, st_fixed_from_float(st_fixed_clamp(w * L.x, clamped)));
    atom_add(a + 1, st_fixed_from_float(st_fixed_clamp(w * L.y, clamped)));
    atom_add(a + 2, st_fixed_from_float(st_fixed_clamp(w * L.z, clamped)));
    atom_add(a + 3, st_fixed_from_float(w));
}

/* Range of pixel indices whose centre k + 0.5 satisfies |k + 0.5 - x| < r. */
static int2 taps(float x, float r, st_u32 n)
{
    int lo = (int)ceil(x - r - 0.5f), hi = (int)floor(x + r - 0.5f);
    if ((float)lo + 0.5f - x <= -r)
        lo++;
    if ((float)hi + 0.5f - x >= r)
        hi--;
    return (int2)(max(lo, 0), min(hi, (int)n - 1));
}

/* Reads film positions and radiance (w: rays traced); adds to accum (4 longs
 * per pixel: Σ f L for R, G, B and Σ f); adds to tally[i] (the work-item's
 * own slot, the same in every wave, so no atomics: splats made, closest and
 * shadow rays traced). */
__kernel void splat_samples(const st_params p, __global const float2 *film,
                            __global const uint2 *sample_id, __global const float4 *radiance,
                            __global long *accum, __global long *half_film,
                            __global uint4 *tally, __global uint *stats)
{
    st_u32 i = get_global_id(0);
    if (i >= p.item_count)
        return;
    float2 f = film[i];
    if (ST_SAMPLER_IS_TILED(p.sampler) && !(f.x < (float)p.width && f.y < (float)p.height))
        return; /* a tile point outside the image (generate.cl) */
    float4 rad = radiance[i];
    float3 L = rad.xyz;
    st_u32 rays = (st_u32)rad.w;
    uint4 t = tally[i];
    t.y += rays & 0xffffu;
    t.z += rays >> 16;
    if (!(isfinite(L.x) && isfinite(L.y) && isfinite(L.z))) {
        count(stats, ST_STAT_NONFINITE);
        L = (float3)(0.0f);
    }
    st_filter flt = p.filter;
    st_u32 clamped = 0u;
    int to_half = p.half_buffer && (sample_id[i].y & 1u) == 0u;
    if (p.reconstruction == ST_RECON_FIS) {
        /* the offset was drawn from |f|: weight f / pdf = sign(f) x ∫|f|, and
         * the constant cancels in Σ w L / Σ w */
        st_u32 px = sample_id[i].x % p.width, py = sample_id[i].x / p.width;
        float w = st_filter_eval_1d(&flt, f.x - (float)px - 0.5f) *
                  st_filter_eval_1d(&flt, f.y - (float)py - 0.5f);
        w = w > 0.0f ? 1.0f : w < 0.0f ? -1.0f : 0.0f;
        add_splat(accum + 4 * (size_t)sample_id[i].x, w, L, &clamped);
        if (to_half)
            add_splat(half_film + 4 * (size_t)sample_id[i].x, w, L, &clamped);
        tally[i] = t + (uint4)(1u, 0u, 0u, 0u);
        if (clamped)
            count(stats, ST_STAT_CLAMPED);
        return;
    }
    int2 xs = taps(f.x, flt.radius, p.width), ys = taps(f.y, flt.radius, p.height);
    float wx[ST_MAX_TAPS];
    for (int x = xs.x; x <= xs.y; x++)
        wx[x - xs.x] = st_filter_eval_1d(&flt, (float)x + 0.5f - f.x);
    for (int y = ys.x; y <= ys.y; y++) {
        float wy = st_filter_eval_1d(&flt, (float)y + 0.5f - f.y);
        for (int x = xs.x; x <= xs.y; x++) {
            float w = wx[x - xs.x] * wy;
            add_splat(accum + 4 * ((size_t)y * p.width + x), w, L, &clamped);
            if (to_half)
                add_splat(half_film + 4 * ((size_t)y * p.width + x), w, L, &clamped);
        }
    }
    t.x += (st_u32)max(xs.y - xs.x + 1, 0) * (st_u32)max(ys.y - ys.x + 1, 0);
    tally[i] = t;
    if (clamped)
        count(stats, ST_STAT_CLAMPED);
}

/* Reads accum; writes image (R, G, B, Σ f): I = Σ f L / Σ f, negative values
 * (from negative filter lobes) clamped to 0; a pixel whose weight sum is not
 * positive, or whose value is not finite, becomes 0 and is counted. */
__kernel void resolve_film(const st_params p, __global const long *accum,
                           __global float4 *image, __global uint *stats)
{
    st_u32 i = get_global_id(0);
    if (i >= p.width * p.height)
        return;
    __global const long *a = accum + 4 * (size_t)i;
    float w = (float)a[3] * (1.0f / ST_FIXED_SCALE);
    float3 v = (float3)(0.0f);
    if (w > 0.0f) {
        v = (float3)((float)a[0], (float)a[1], (float)a[2]) * (1.0f / ST_FIXED_SCALE) / w;
        if (!(isfinite(v.x) && isfinite(v.y) && isfinite(v.z))) {
            count(stats, ST_STAT_NONFINITE);
            v = (float3)(0.0f);
        }
        v = fmax(v, (float3)(0.0f));
    } else {
        count(stats, ST_STAT_ZERO_WEIGHT);
    }
    image[i] = (float4)(v, w);
}
