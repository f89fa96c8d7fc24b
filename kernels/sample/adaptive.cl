/* adaptive.cl — adaptive sampling's device side (the plan: src/render/adaptive.c).
 *
 * A pilot of N0 samples per pixel is splatted as usual; adaptive_moments
 * keeps, per pixel, the sums of Y = (r + g + b) / 3 and Y² of its own
 * samples; adaptive_estimate turns them into each pixel's error estimate
 * and moves the pilot's film aside. The host then gives pixel q m(q) more
 * samples; they are splatted into the emptied film with weight 1 / m(q)
 * (splat_scale), so that every pixel's later samples weigh 1 in all, as if
 * they had the same density everywhere: the filter's weights Σ f stay
 * balanced between sparse and dense pixels, and Σ f L / Σ f stays the
 * filtered image (with plain weights, a pixel next to a dense one would
 * mostly show its neighbour's samples). adaptive_blend combines the two
 * films, each a consistent estimate of the same pixel. */
#include "st_shared.h"
#include "filters.h"
#include "fixed.h"

/* The criterion: per-sample standard deviation over (μ² + ε²)^(γ / 2).
 * γ = 0 would minimise the summed squared error, γ = 1 the relative squared
 * error (x − r)² / (r² + ε²); ¾ lies between and, measured against ½ and 1
 * on the Cornell box and two Khronos models, gained clearly by both. */
#define ADAPTIVE_GAMMA 0.75f
#define ADAPTIVE_EPS 0.1f

/* Item i of the pilot is pixel i mod N, sample i / N (N pixels: generate.cl);
 * this wave holds items first_item .. first_item + item_count - 1. For each
 * pixel, adds its samples in this wave to moments: rgb[0] += Y, rgb[1] +=
 * Y², weight += 1. One work-item per pixel, in sample order: the float sums
 * are the same from run to run. */
__kernel void adaptive_moments(ST_FILM_PARAMS)
{
    st_u32 i = get_global_id(0), n = p.width * p.height;
    if (i >= n)
        return;
    st_pixel m = moments[i];
    for (st_u32 k = 0; k < p.adaptive_pilot; k++) {
        st_u64 g = (st_u64)k * n + i;
        if (g < p.first_item || g >= p.first_item + p.item_count)
            continue;
        float3 L = vload3(0, path[g - p.first_item].radiance);
        float y = (L.x + L.y + L.z) / 3.0f;
        if (!isfinite(y))
            continue; /* counted by the splat */
        m.rgb[0] += y;
        m.rgb[1] += y * y;
        m.weight += 1.0f;
    }
    moments[i] = m;
}

/* Pixel i's error estimate into splat_scale[i] (the host reads it and puts
 * the weights there): the pilot's samples of the 3 x 3 pixels round i
 * pooled (one pixel's N0 samples are too few to judge by; the pool also
 * sees an edge between neighbours, which the filter blends), then
 * sqrt(var) / (mean² + ε²)^(γ/2). The pilot's film moves to pilot_film and
 * the film starts again from 0 for the later samples. */
__kernel void adaptive_estimate(ST_FILM_PARAMS)
{
    st_u32 i = get_global_id(0);
    if (i >= p.width * p.height)
        return;
    int x = (int)(i % p.width), y = (int)(i / p.width);
    float s = 0.0f, s2 = 0.0f, n = 0.0f;
    for (int dy = max(y - 1, 0); dy <= min(y + 1, (int)p.height - 1); dy++)
        for (int dx = max(x - 1, 0); dx <= min(x + 1, (int)p.width - 1); dx++) {
            st_pixel m = moments[(st_u32)dy * p.width + (st_u32)dx];
            s += m.rgb[0];
            s2 += m.rgb[1];
            n += m.weight;
        }
    float mean = n > 0.0f ? s / n : 0.0f, var = n > 1.0f ? fmax(s2 / n - mean * mean, 0.0f) : 0.0f;
    splat_scale[i] = sqrt(var) / pow(mean * mean + ADAPTIVE_EPS * ADAPTIVE_EPS, 0.5f * ADAPTIVE_GAMMA);
    pilot_film[i] = film[i];
    for (int k = 0; k < ST_FILM_SUMS; k++)
        film[i].sum[k] = 0;
}

/* Σ f L / Σ f of one film's sums, and whether Σ f != 0 (as resolve_film). */
static int film_value(__global const st_film_pixel *px, float3 *v)
{
    __global const long *a = px->sum;
    if (a[3] == 0)
        return 0;
    *v = (float3)((float)a[0], (float)a[1], (float)a[2]) / (float)a[3];
    return 1;
}

/* ∫ f(u) du over [a, b] ∩ [-r, r], f the filter along one axis: 8-point
 * Gauss-Legendre on each half-pixel piece (the filters' kinks lie on that
 * grid at their default radii, where Mitchell's cubics are integrated
 * exactly; elsewhere the error is far below the noise it multiplies). */
static float filter_integral(const st_filter *f, float a, float b)
{
    const float x8[4] = {0.18343464f, 0.52553241f, 0.79666648f, 0.96028986f};
    const float w8[4] = {0.36268378f, 0.31370665f, 0.22238103f, 0.10122854f};
    a = fmax(a, -f->radius);
    b = fmin(b, f->radius);
    float sum = 0.0f;
    for (float lo = a; lo < b;) {
        float hi = fmin(b, (floor(2.0f * lo) + 1.0f) * 0.5f), h = 0.5f * (hi - lo),
              m = 0.5f * (hi + lo);
        for (int k = 0; k < 4; k++)
            sum += h * w8[k] * (st_filter_eval_1d(f, m - h * x8[k]) + st_filter_eval_1d(f, m + h * x8[k]));
        lo = hi;
    }
    return sum;
}

/* The later film's value at pixel i, from its sums N = Σ f L / m and
 * D = Σ f / m. N / D is a ratio estimator, biased where D varies much: a
 * pixel at the cap beside pixels of one or two samples, whose 1 / m weigh
 * up to a hundred of its own. With splatting and the random sampler (each
 * sample uniform in its pixel), E[D] = W = ∫ f over the image round the
 * pixel whatever the counts (the 1 / m cancels the count), and
 * P + (N − P D) / W, P the pilot's value (independent of these samples),
 * has expectation E[N] / W: the filtered image, exactly. It is N / D where
 * D = W, and its noise is N / D's to first order (P is near the value). */
static float3 later_value(__global const st_film_pixel *px, float3 P, const st_params *p,
                          st_u32 i)
{
    __global const long *a = px->sum;
    float3 N = (float3)((float)a[0], (float)a[1], (float)a[2]) / ST_FIXED_SCALE;
    float D = (float)a[3] / ST_FIXED_SCALE;
    float cx = (float)(i % p->width) + 0.5f, cy = (float)(i / p->width) + 0.5f;
    float W = filter_integral(&p->filter, -cx, (float)p->width - cx) *
              filter_integral(&p->filter, -cy, (float)p->height - cy);
    return P + (N - P * D) / W;
}

/* Pixel i of the film becomes α P + (1 − α) F, P the pilot's value, F the
 * later samples', α = N0 / n(i) (each weighted by its pixel's share of the
 * samples, as inverse variances would be), as sums of weight 1; where one
 * film has no weight the other alone; where neither, 0 (resolve counts it). */
__kernel void adaptive_blend(ST_FILM_PARAMS)
{
    st_u32 i = get_global_id(0);
    if (i >= p.width * p.height)
        return;
    float3 P = (float3)(0.0f), F = (float3)(0.0f);
    int has_p = film_value(pilot_film + i, &P), has_f = film_value(film + i, &F);
    if (!has_p && !has_f)
        return;
    float a = !has_f ? 1.0f : !has_p ? 0.0f : (float)p.adaptive_pilot / (float)pixel_spp[i];
    if (has_p && has_f && p.reconstruction == ST_RECON_SPLAT)
        F = later_value(film + i, P, &p, i);
    float3 v = a * P + (1.0f - a) * F;
    st_u32 clamped = 0;
    st_i64 sums[4];
    st_fixed_splat(1.0f, v.x, v.y, v.z, sums, &clamped);
    for (int k = 0; k < ST_FILM_SUMS; k++)
        film[i].sum[k] = sums[k];
    if (clamped)
        atomic_inc(&stats->clamped);
}
