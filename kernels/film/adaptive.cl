/* adaptive.cl — adaptive sampling's device side (the plan: src/render/adaptive.c).
 *
 * A pilot of N0 samples per pixel is splatted as usual; adaptive_moments
 * keeps, per pixel, the sums of Y = (r + g + b) / 3 and Y² of its own
 * samples (the pilot's and every later round's); adaptive_estimate turns
 * them into each pixel's error estimate and, after the pilot, moves the
 * pilot's film aside. The host then gives pixel q, round by round, more
 * samples; a sample of round r is splatted into the emptied film with
 * weight w_r(q) / m_r(q) (splat_scale), its pixel's share of the weight
 * over its count, where Σ_r w_r(q) = 1 and each w_r, m_r is fixed before
 * round r's samples are drawn: the later film's sums are then unbiased
 * estimates of the filter's integrals over the image (Σ f L and Σ f), as
 * if every pixel had the same density, whatever the counts.
 * adaptive_blend resolves them against the pilot's film, which is not
 * part of the estimate but its control variate. */
#include "st_shared.h"
#include "filters.h"
#include "fixed.h"

/* The criterion: ST_ADAPTIVE_GAMMA, ST_ADAPTIVE_EPS (st_shared.h). */


/* The pixels of this work-item: ST_W of them from ST_W times its id, fewer
 * at the image's end (*count, 0 past it); returns the first. */
static st_u32 pixel_lanes(const st_params *p, st_u32 *count)
{
    st_u32 n = p->width * p->height, first = ST_W * ST_ITEM();
    *count = first < n ? min((st_u32)ST_W, n - first) : 0u;
    return first;
}

/* The pixels whose items this launch runs (N: the image's, or in a round
 * the active list's first adaptive_count; item i is pixel slot i mod N,
 * sample i / N: generate.cl): ST_W slots from ST_W times the work-item's
 * id, fewer at the end (*count, 0 past it), pixel[l] the pixel of slot l
 * (the last repeated past *count); returns N. */
static st_u32 slot_lanes(const st_params *p, __global const st_u32 *active, st_u32 *first,
                         st_u32 *count, int pixel[ST_W])
{
    st_u32 n = p->adaptive_count ? p->adaptive_count : p->width * p->height;
    *first = ST_W * ST_ITEM();
    *count = *first < n ? min((st_u32)ST_W, n - *first) : 0u;
    for (st_u32 l = 0; *count && l < ST_W; l++) {
        st_u32 s = *first + min(l, *count - 1u);
        pixel[l] = (int)(p->adaptive_count ? active[s] : s);
    }
    return n;
}

/* This wave holds items first_item .. first_item + item_count - 1 of the
 * pilot or of a round. For each pixel, adds its samples in this wave to
 * moments: rgb[0] += Y, rgb[1] += Y², weight += 1 (a sample whose Y is not
 * finite is counted as 0, as the splat counts it). ST_W pixels a
 * work-item, each lane one pixel's sums in sample order: the float sums are
 * the same from run to run and at every lane width. */
__kernel void adaptive_moments(ST_FILM_PARAMS)
{
    st_u32 first, count;
    int px[ST_W];
    st_u32 n = slot_lanes(&p, active, &first, &count, px);
    if (count == 0u)
        return;
    float m[3][ST_W];
    for (st_u32 l = 0; l < ST_W; l++) {
        st_pixel q = moments[px[l]];
        m[0][l] = q.rgb[0];
        m[1][l] = q.rgb[1];
        m[2][l] = q.weight;
    }
    st_lf s = ST_VLOAD(ST_W, m[0]), s2 = ST_VLOAD(ST_W, m[1]), w = ST_VLOAD(ST_W, m[2]);
    st_u64 k_end = (p.first_item + p.item_count + n - 1u) / n;
    for (st_u64 k = p.first_item / n; k < k_end; k++) {
        /* lane l is item k n + first + l, of this wave where lo <= l < hi */
        st_i64 off = (st_i64)(k * n + first) - (st_i64)p.first_item;
        int lo = (int)clamp(-off, (st_i64)0, (st_i64)count),
            hi = (int)clamp((st_i64)p.item_count - off, (st_i64)0, (st_i64)count);
        float L[3][ST_W];
        for (int l = 0; l < ST_W; l++) {
            float3 c = l >= lo && l < hi ? vload3(0, path[off + l].radiance) : (float3)(0.0f);
            L[0][l] = c.x;
            L[1][l] = c.y;
            L[2][l] = c.z;
        }
        st_li in = ST_IOTA(ST_W) >= lo & ST_IOTA(ST_W) < hi;
        st_lf y = (ST_VLOAD(ST_W, L[0]) + ST_VLOAD(ST_W, L[1]) + ST_VLOAD(ST_W, L[2])) / 3.0f;
        y = ST_SELECT(ST_W, ST_LF(0.0f), y, isfinite(y));
        s = ST_SELECT(ST_W, s, s + y, in);
        s2 = ST_SELECT(ST_W, s2, s2 + y * y, in);
        w = ST_SELECT(ST_W, w, w + 1.0f, in);
    }
    ST_VSTORE(ST_W, s, m[0]);
    ST_VSTORE(ST_W, s2, m[1]);
    ST_VSTORE(ST_W, w, m[2]);
    for (st_u32 l = 0; l < count; l++) {
        st_pixel q = {{m[0][l], m[1][l], 0.0f}, m[2][l]};
        moments[px[l]] = q;
    }
}

/* Pixel i's error estimate into splat_scale[i] (the host reads it and puts
 * the weights there): the samples so far of the 3 x 3 pixels round i
 * pooled (one pixel's N0 samples are too few to judge by; the pool also
 * sees an edge between neighbours, which the filter blends), then
 * sqrt(var) / (mean² + ε²)^(γ/2). After the pilot (adaptive_scaled 0) the
 * pilot's film moves to pilot_film and the film starts again from 0 for
 * the later samples. ST_W pixels a work-item, each lane adding its
 * neighbours in rows, as one pixel alone would. */
__kernel void adaptive_estimate(ST_FILM_PARAMS)
{
    st_u32 count, first = pixel_lanes(&p, &count);
    if (count == 0u)
        return;
    int at[ST_W];
    for (st_u32 l = 0; l < ST_W; l++)
        at[l] = (int)(first + min(l, count - 1u));
    st_li i = ST_VLOAD(ST_W, at), w = (st_li)((int)p.width), h = (st_li)((int)p.height);
    st_li x = i % w, y = i / w;
    st_lf s = ST_LF(0.0f), s2 = ST_LF(0.0f), n = ST_LF(0.0f);
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            st_li in_image = x + dx >= 0 & x + dx < w & y + dy >= 0 & y + dy < h;
            ST_VSTORE(ST_W, ST_SELECT(ST_W, i, i + dy * w + dx, in_image), at);
            float m[3][ST_W];
            for (st_u32 l = 0; l < ST_W; l++) {
                st_pixel px = moments[at[l]];
                m[0][l] = px.rgb[0];
                m[1][l] = px.rgb[1];
                m[2][l] = px.weight;
            }
            s = ST_SELECT(ST_W, s, s + ST_VLOAD(ST_W, m[0]), in_image);
            s2 = ST_SELECT(ST_W, s2, s2 + ST_VLOAD(ST_W, m[1]), in_image);
            n = ST_SELECT(ST_W, n, n + ST_VLOAD(ST_W, m[2]), in_image);
        }
    st_lf mean = ST_SELECT(ST_W, ST_LF(0.0f), s / n, n > 0.0f);
    st_lf spread = ST_FMAXF(s2 / n - mean * mean, ST_LF(0.0f));
    st_lf var = ST_SELECT(ST_W, ST_LF(0.0f), spread, n > 1.0f);
    st_lf e = ST_SQRTF(var) /
              pow(mean * mean + ST_ADAPTIVE_EPS * ST_ADAPTIVE_EPS, ST_LF(0.5f * ST_ADAPTIVE_GAMMA));
    float out[ST_W];
    ST_VSTORE(ST_W, e, out);
    for (st_u32 l = 0; l < count; l++) {
        st_u32 i = first + l;
        splat_scale[i] = out[l];
        if (p.adaptive_scaled)
            continue;
        pilot_film[i] = film[i];
        for (int k = 0; k < ST_FILM_SUMS; k++)
            film[i].sum[k] = 0;
    }
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

/* The sums of film pixels first .. first + count - 1 as floats, sum[c][l]
 * (the lanes past count repeat the last). */
static void film_lanes(__global const st_film_pixel *film, st_u32 first, st_u32 count,
                       float sum[ST_FILM_SUMS][ST_W])
{
    for (st_u32 l = 0; l < ST_W; l++)
        for (int c = 0; c < ST_FILM_SUMS; c++)
            sum[c][l] = (float)film[first + min(l, count - 1u)].sum[c];
}

/* Σ f L / Σ f of each lane's sums (as resolve_film), and in *has the lanes
 * where Σ f != 0 (a 64-bit sum is 0 exactly where its float is). */
static st_lv3 film_value(float sum[ST_FILM_SUMS][ST_W], st_li *has)
{
    st_lf w = ST_VLOAD(ST_W, sum[3]);
    *has = w != 0.0f;
    st_lv3 v = st_lv3_make(ST_VLOAD(ST_W, sum[0]), ST_VLOAD(ST_W, sum[1]), ST_VLOAD(ST_W, sum[2]));
    return st_lv3_div(v, w);
}

/* The later film's value from its sums N = Σ w f L / m and D = Σ w f / m.
 * Their expectations are the filter's integrals over the image round the
 * pixel, E[N] = ∫ f L and E[D] = W = ∫ f, whatever the counts and weights
 * (each pixel's weights sum to 1, and each is fixed before its samples are
 * drawn: src/render/adaptive.c), but N / D, a ratio estimator, is biased
 * where D varies much: a pixel at the cap beside pixels of one or two
 * samples, whose weights are up to a hundred times its own. P + (N − P D)
 * / W, P the pilot's value (independent of these samples), has
 * expectation E[N] / W: the filtered image, exactly; it is N / D where D
 * = W, and its noise is N / D's to first order (P is near the value). Each
 * lane's W is its own loop over the filter (filter_integral), one lane at
 * a time. */
static st_lv3 later_value(float sum[ST_FILM_SUMS][ST_W], st_lv3 P, const st_params *p,
                          st_u32 first, st_u32 count)
{
    float W[ST_W];
    for (st_u32 l = 0; l < ST_W; l++) {
        st_u32 i = first + min(l, count - 1u);
        float cx = (float)(i % p->width) + 0.5f, cy = (float)(i / p->width) + 0.5f;
        W[l] = filter_integral(&p->filter, -cx, (float)p->width - cx) *
               filter_integral(&p->filter, -cy, (float)p->height - cy);
    }
    st_lv3 N = st_lv3_make(ST_VLOAD(ST_W, sum[0]), ST_VLOAD(ST_W, sum[1]), ST_VLOAD(ST_W, sum[2]));
    N = st_lv3_scale(N, ST_LF(1.0f / ST_FIXED_SCALE));
    st_lf D = ST_VLOAD(ST_W, sum[3]) * (1.0f / ST_FIXED_SCALE), w = ST_VLOAD(ST_W, W);
    return st_lv3_make(P.x + (N.x - P.x * D) / w, P.y + (N.y - P.y * D) / w,
                       P.z + (N.z - P.z * D) / w);
}

/* Pixel i of the film becomes the later samples' value alone: with
 * splatting later_value against the pilot's P (0 where the pilot's film
 * has no weight), with filter importance sampling Σ w L / m over Σ w / m
 * (each sample in its own pixel: the denominator is Σ_r w_r = 1, so the
 * ratio is the weighted mean itself). The pilot's samples only chose the
 * counts: a weight taken from them would correlate with their values and
 * bias the image (Kirk and Arvo, "Unbiased sampling techniques for image
 * synthesis", SIGGRAPH 1991). Written as sums of weight 1; where the film
 * has no weight, 0 (resolve counts it). ST_W pixels a work-item. */
__kernel void adaptive_blend(ST_FILM_PARAMS)
{
    st_u32 count, first = pixel_lanes(&p, &count);
    if (count == 0u)
        return;
    float ps[ST_FILM_SUMS][ST_W], fs[ST_FILM_SUMS][ST_W];
    film_lanes(pilot_film, first, count, ps);
    film_lanes(film, first, count, fs);
    st_li has_p, has_f;
    st_lv3 none = st_lv3_make(ST_LF(0.0f), ST_LF(0.0f), ST_LF(0.0f));
    st_lv3 P = st_lv3_select(none, film_value(ps, &has_p), has_p);
    st_lv3 v = st_lv3_select(none, film_value(fs, &has_f), has_f);
    if (p.reconstruction == ST_RECON_SPLAT)
        v = later_value(fs, P, &p, first, count);
    float out[3][ST_W];
    int kept[ST_W];
    ST_VSTORE(ST_W, v.x, out[0]);
    ST_VSTORE(ST_W, v.y, out[1]);
    ST_VSTORE(ST_W, v.z, out[2]);
    ST_VSTORE(ST_W, has_f, kept);
    st_u32 clamped = 0;
    for (st_u32 l = 0; l < count; l++) {
        if (!kept[l])
            continue;
        st_u32 c = 0;
        st_i64 sums[4];
        st_fixed_splat(1.0f, out[0][l], out[1][l], out[2][l], sums, &c);
        for (int k = 0; k < ST_FILM_SUMS; k++)
            film[first + l].sum[k] = sums[k];
        clamped += c;
    }
    if (clamped)
        atomic_add(&stats->clamped, clamped);
}
