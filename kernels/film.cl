/* film.cl — reconstruction: every sample adds f(x - x_i, y - y_i) L_i and
 * f(x - x_i, y - y_i) to each pixel whose centre lies within the filter
 * radius, as 64-bit fixed-point integers (fixed.h) with atom_add, so the sums
 * do not depend on the order of the adds; resolve divides. */
#include "st_shared.h"
#include "filters.h"
#include "fixed.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable

/* Adds w L and w to one pixel's four sums. */
static void add_splat(__global st_film_pixel *px, float w, float3 L, st_u32 *clamped)
{
    __global long *a = px->sum;
    st_i64 v[4];
    st_fixed_splat(w, L.x, L.y, L.z, v, clamped);
    for (int k = 0; k < 4; k++)
        atom_add(a + k, v[k]);
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

/* Filter importance sampling: the offset was drawn from |f|, so the weight
 * f / pdf = sign(f) x ∫|f|, and the constant cancels in Σ w L / Σ w; the
 * sample goes to its own pixel only. Returns the splats made (1). */
static st_u32 splat_fis(const st_params *p, st_sample s, float3 L, __global st_film_pixel *film,
                        __global st_film_pixel *half_film, int to_half, st_u32 *clamped)
{
    st_filter flt = p->filter;
    st_u32 px = s.pixel % p->width, py = s.pixel / p->width;
    float w = st_filter_eval_1d(&flt, s.film[0] - (float)px - 0.5f) *
              st_filter_eval_1d(&flt, s.film[1] - (float)py - 0.5f);
    w = w > 0.0f ? 1.0f : w < 0.0f ? -1.0f : 0.0f;
    add_splat(film + s.pixel, w, L, clamped);
    if (to_half)
        add_splat(half_film + s.pixel, w, L, clamped);
    return 1u;
}

/* Every pixel within the filter radius gets f(x - x_i) L and f(x - x_i),
 * with the separable weights f(dx) f(dy). Returns the splats made. */
static st_u32 splat_taps(const st_params *p, st_sample s, float3 L, __global st_film_pixel *film,
                         __global st_film_pixel *half_film, int to_half, st_u32 *clamped)
{
    st_filter flt = p->filter;
    int2 xs = taps(s.film[0], flt.radius, p->width), ys = taps(s.film[1], flt.radius, p->height);
    float wx[ST_MAX_TAPS];
    for (int x = xs.x; x <= xs.y; x++)
        wx[x - xs.x] = st_filter_eval_1d(&flt, (float)x + 0.5f - s.film[0]);
    for (int y = ys.x; y <= ys.y; y++) {
        float wy = st_filter_eval_1d(&flt, (float)y + 0.5f - s.film[1]);
        for (int x = xs.x; x <= xs.y; x++) {
            float w = wx[x - xs.x] * wy;
            add_splat(film + ((size_t)y * p->width + x), w, L, clamped);
            if (to_half)
                add_splat(half_film + ((size_t)y * p->width + x), w, L, clamped);
        }
    }
    return (st_u32)max(xs.y - xs.x + 1, 0) * (st_u32)max(ys.y - ys.x + 1, 0);
}

/* Reads sample and path; adds to film (and, for even samples of an
 * adaptive render's first round, half_film); adds the splats made and the
 * path's rays to tally[i]. */
__kernel void splat_samples(ST_STAGE_PARAMS)
{
    st_u32 i = get_global_id(0);
    if (i >= p.item_count)
        return;
    st_sample s = sample[i];
    if (!st_sample_on_film(&p, s))
        return; /* a tile point outside the image (generate.cl) */
    __global const st_path *pa = &path[i];
    float3 L = vload3(0, pa->radiance);
    st_tally t = tally[i];
    t.closest_rays += pa->closest_rays;
    t.shadow_rays += pa->shadow_rays;
    if (!(isfinite(L.x) && isfinite(L.y) && isfinite(L.z))) {
        atomic_inc(&stats->nonfinite);
        L = (float3)(0.0f);
    }
    st_u32 clamped = 0u;
    int to_half = p.half_buffer && (s.index & 1u) == 0u;
    t.splats += p.reconstruction == ST_RECON_FIS
                    ? splat_fis(&p, s, L, film, half_film, to_half, &clamped)
                    : splat_taps(&p, s, L, film, half_film, to_half, &clamped);
    tally[i] = t;
    if (clamped)
        atomic_inc(&stats->clamped);
}

/* Reads film; writes image: I = Σ f L / Σ f wherever Σ f != 0 (the
 * lecture's definition; a negative sum from negative filter lobes divides
 * too, as in pbrt), negative values clamped to 0; a pixel whose weight sum
 * is 0 (no definition), or whose value is not finite, becomes 0 and is
 * counted. */
__kernel void resolve_film(ST_FILM_PARAMS)
{
    st_u32 i = get_global_id(0);
    if (i >= p.region_w * p.region_h)
        return;
    i = st_region_pixel(&p, i); /* a crop resolves its window only */
    __global const long *a = film[i].sum;
    float w = (float)a[3] * (1.0f / ST_FIXED_SCALE);
    float3 v = (float3)(0.0f);
    if (w != 0.0f) {
        v = (float3)((float)a[0], (float)a[1], (float)a[2]) * (1.0f / ST_FIXED_SCALE) / w;
        if (!(isfinite(v.x) && isfinite(v.y) && isfinite(v.z))) {
            atomic_inc(&stats->nonfinite);
            v = (float3)(0.0f);
        }
        v = fmax(v, (float3)(0.0f));
    } else {
        atomic_inc(&stats->zero_weight);
    }
    st_pixel out = {{v.x, v.y, v.z}, w};
    image[i] = out;
}
