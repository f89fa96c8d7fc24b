/* adaptive.cl — adaptive sampling's decision, made on the device so that the
 * film never returns to the host between rounds.
 *
 * Error estimate (after Cycles and LuxCore): besides the film I (every
 * sample), a half film H takes only the even-numbered samples. Both estimate
 * the same pixel value, so their difference measures the noise of the mean:
 *   err = (|I_r - H_r| + |I_g - H_g| + |I_b - H_b|) / sqrt(1e-4 + I_r + I_g + I_b)
 * (the square root makes the threshold relative, with more tolerance in bright
 * pixels, where the eye sees noise less). A constant image has err = 0.
 * A pixel keeps sampling while err > threshold and it has fewer than max_spp
 * samples; once it stops it never restarts, so every pixel's samples are a
 * prefix 0 .. n-1 of its own sequence. */
#include "st_shared.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable

static float3 pixel_mean(__global const st_film_pixel *px)
{
    __global const long *a = px->sum;
    float w = (float)a[3]; /* defined wherever the weight sum is not 0, as resolve_film */
    return w != 0.0f ? (float3)((float)a[0], (float)a[1], (float)a[2]) / w : (float3)(INFINITY);
}

/* err of pixel i (see the file comment); INFINITY before it has a weight. */
static float pixel_error(__global const st_film_pixel *film, __global const st_film_pixel *half_film,
                         st_u32 i)
{
    float3 full = pixel_mean(film + i), part = pixel_mean(half_film + i);
    float3 d = fabs(full - part);
    return (d.x + d.y + d.z) / sqrt(1e-4f + fmax(full.x + full.y + full.z, 0.0f));
}

/* Reads both films; for every pixel still sampling, either stops it (flag in
 * pixel_spp) or appends it to the active list and books adaptive_batch more
 * samples. A pixel stops only when it and its 8 neighbours are all below
 * the threshold (as Cycles dilates its active mask): one estimate from a few
 * samples is often lucky, and a pixel that stops never restarts.
 * *active_count ends as the number of active pixels (the list's order
 * varies from run to run; the set of (pixel, sample) pairs it makes does
 * not). */
__kernel void adaptive_mark(ST_FILM_PARAMS)
{
    st_u32 i = get_global_id(0);
    if (i >= p.width * p.height)
        return;
    st_u32 n = pixel_spp[i];
    if (n & ST_ADAPTIVE_STOPPED)
        return;
    int x = (int)(i % p.width), y = (int)(i / p.width);
    float err = 0.0f;
    for (int dy = max(y - 1, 0); dy <= min(y + 1, (int)p.height - 1); dy++)
        for (int dx = max(x - 1, 0); dx <= min(x + 1, (int)p.width - 1); dx++)
            err = fmax(err, pixel_error(film, half_film, (st_u32)dy * p.width + (st_u32)dx));
    if (n >= p.adaptive_max_spp || (isfinite(err) && err <= p.adaptive_threshold)) {
        pixel_spp[i] = n | ST_ADAPTIVE_STOPPED;
        return;
    }
    active[atomic_inc(active_count)] = i;
    pixel_spp[i] = n + p.adaptive_batch;
}
