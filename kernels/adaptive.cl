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
    float w = (float)a[3];
    return w > 0.0f ? (float3)((float)a[0], (float)a[1], (float)a[2]) / w : (float3)(INFINITY);
}

/* Reads both films; for every pixel still sampling, either stops it (flag in
 * pixel_spp) or appends it to the active list and books adaptive_batch more
 * samples. *active_count ends as the number of active pixels (the list's
 * order varies from run to run; the set of (pixel, sample) pairs it makes
 * does not). */
__kernel void adaptive_mark(ST_FILM_PARAMS)
{
    st_u32 i = get_global_id(0);
    if (i >= p.width * p.height)
        return;
    st_u32 n = pixel_spp[i];
    if (n & ST_ADAPTIVE_STOPPED)
        return;
    float3 full = pixel_mean(film + i), part = pixel_mean(half_film + i);
    float3 d = fabs(full - part);
    float err = (d.x + d.y + d.z) / sqrt(1e-4f + fmax(full.x + full.y + full.z, 0.0f));
    if (n >= p.adaptive_max_spp || (isfinite(err) && err <= p.adaptive_threshold)) {
        pixel_spp[i] = n | ST_ADAPTIVE_STOPPED;
        return;
    }
    active[atomic_inc(active_count)] = i;
    pixel_spp[i] = n + p.adaptive_batch;
}
