/* film.cl — reconstruction: every sample adds f(x - x_i, y - y_i) L_i and
 * f(x - x_i, y - y_i) to each pixel whose centre lies within the filter
 * radius, as 64-bit fixed-point integers (fixed.h) with atom_add, so the sums
 * do not depend on the order of the adds; resolve divides. */
#include "st_shared.h"
#include "filters.h"
#include "fixed.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#ifdef cl_khr_fp64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif

/* Where a sample's splats go: the film, or a work-group's window of
 * side x side pixels from (ox, oy) in local memory (acc; NULL: none), four
 * sums per pixel, added to the film later (splat_tiles). */
typedef struct splat_dest {
    __global st_film_pixel *film;
    float scale; /* every weight's factor (1; adaptive.cl's splat_scale) */
    __local long4 *acc;
    __local int4 *near; /* a window alone: int32 partial sums (splat_fitting_int4), else 0 */
    __local int *room;  /* and its rows' room (near_room) */
    int ox, oy, side;
    int alone; /* the work-group is one work-item: acc is its own, plain adds */
    st_lanczos_turn turn; /* st_lanczos_turn_of(the filter), made once */
    st_tally *counts;     /* where a sample's counts go: NULL, its tally; else summed here */
} splat_dest;

/* round(x) of four values |x| <= ST_SPLAT_MAX 2^24 at once (x = v 2^24,
 * st_fixed_from_float's v scaled). With doubles: x (exact) plus 1.5 2^52 is
 * rounded to an integer, ties to even (the default rounding), and as
 * |x| <= 2^40 < 2^51 the sum's low mantissa bits are that integer in two's
 * complement: a few vector instructions, where PoCL emulates
 * convert_long4_rte channel by channel. */
ST_HOT long4 fixed_from_scaled4(float4 x)
{
#ifdef cl_khr_fp64
    double4 d = convert_double4(x) + 6755399441055744.0;
    return as_long4(d) - (long4)(0x4338000000000000L);
#else
    return convert_long4_rte(x);
#endif
}

/* st_fixed_from_float of four values |v| <= ST_SPLAT_MAX at once. */
ST_HOT long4 fixed_from_float4(float4 v)
{
    return fixed_from_scaled4(v * ST_FIXED_SCALE);
}

/* The four sums of st_fixed_splat(w, L), as one vector (L1 = (L, 1)): the
 * products and conversions of all four channels at once when none needs
 * clamping (the same integers: w 1 = w), else st_fixed_splat's own path,
 * which clamps and counts. */
ST_HOT long4 fixed_splat4(float w, float4 L1, st_u32 *clamped)
{
    float4 v = w * L1;
    if (all(islessequal(fabs(v), (float4)(ST_SPLAT_MAX))))
        return fixed_from_float4(v);
    st_i64 sums[4];
    st_fixed_splat(w, L1.x, L1.y, L1.z, sums, clamped);
    return (long4)(sums[0], sums[1], sums[2], sums[3]);
}

/* Adds the four sums v to a film pixel's sums a atomically. A zero sum (a
 * channel of black radiance) is left out: it would not change the integer. */
ST_HOT void film_add(__global long *a, long4 v)
{
    if (v.x != 0)
        atom_add(a, v.x);
    if (v.y != 0)
        atom_add(a + 1, v.y);
    if (v.z != 0)
        atom_add(a + 2, v.z);
    if (v.w != 0)
        atom_add(a + 3, v.w);
}

/* Adds the four sums v to pixel (x, y), wherever they are accumulated (a
 * window pixel outside d's window goes to the film: film_add). */
ST_HOT void add_fixed(const st_params *p, const splat_dest *d, int x, int y, long4 v)
{
    int lx = x - d->ox, ly = y - d->oy;
    if (d->acc && lx >= 0 && ly >= 0 && lx < d->side && ly < d->side) {
        __local long *a = (__local long *)(d->acc + ly * d->side + lx);
        atom_add(a, v.x);
        atom_add(a + 1, v.y);
        atom_add(a + 2, v.z);
        atom_add(a + 3, v.w);
        return;
    }
    film_add(d->film[(size_t)y * p->width + x].sum, v);
}

/* A sample's taps (st_tap_range1 of each axis) on p's image: (first x,
 * last x, first y, last y). */
ST_HOT int4 sample_taps(const st_params *p, st_sample s)
{
    int x0, x1, y0, y1;
    st_tap_range1(s.film[0], p->filter.radius, (int)p->width, &x0, &x1);
    st_tap_range1(s.film[1], p->filter.radius, (int)p->height, &y0, &y1);
    return (int4)(x0, x1, y0, y1);
}

/* Filter importance sampling: the offset was drawn from |f|, so the weight
 * f / pdf = sign(f) x ∫|f|, and the constant cancels in Σ w L / Σ w; the
 * sample goes to its own pixel only. Returns the splats made (1). */
static st_u32 splat_fis(const st_params *p, st_sample s, float3 L, const splat_dest *d,
                        st_u32 *clamped)
{
    st_filter flt = p->filter;
    st_u32 px = s.pixel % p->width, py = s.pixel / p->width;
    float wx, wy;
    st_filter_taps1(&flt, d->turn, (int)px, 1, 1, s.film[0], &wx);
    st_filter_taps1(&flt, d->turn, (int)py, 1, 1, s.film[1], &wy);
    float w = wx * wy;
    w = w > 0.0f ? 1.0f : w < 0.0f ? -1.0f : 0.0f;
    add_fixed(p, d, (int)px, (int)py, fixed_splat4(w * d->scale, (float4)(L, 1.0f), clamped));
    return 1u;
}

/* A sample's taps (sample_taps: first and last x, first and last y) and their
 * 1-D weights, column k's at x[k st], row j's at y[j st] (st: the lanes the
 * weights were made in, filter_lanes.h); none for box, whose weight is 1
 * at every tap. */
typedef struct tap_weights {
    int4 t;
    const float *x, *y;
    int st;
    float bx, by; /* the largest |x[k st]|, |y[j st]| of the taps (max_abs<N>) */
    int near;     /* its taps go to the int32 window, their room made (near_room) */
} tap_weights;

/* Every pixel within the filter radius gets f(x - x_i) L and f(x - x_i),
 * with the separable weights f(dx) f(dy) (w): the integers of
 * st_fixed_splat(f d->scale, L) (fixed_splat4). Box weighs 1 at every tap
 * within the radius (taps), so its sums are the same at every tap: made
 * once. Returns the splats made. */
static st_u32 splat_taps(const st_params *p, tap_weights w, float3 L, const splat_dest *d,
                         st_u32 *clamped)
{
    int4 t = w.t;
    int nx = t.y - t.x + 1, ny = t.w - t.z + 1;
    float4 L1 = (float4)(L, 1.0f);
    if (p->filter.kind == ST_FILTER_BOX) {
        long4 v = fixed_splat4(d->scale, L1, clamped);
        for (int y = t.z; y <= t.w; y++)
            for (int x = t.x; x <= t.y; x++)
                add_fixed(p, d, x, y, v);
        return (st_u32)nx * (st_u32)ny;
    }
    for (int y = t.z; y <= t.w; y++)
        for (int x = t.x; x <= t.y; x++)
            add_fixed(p, d, x, y,
                      fixed_splat4(w.x[(x - t.x) * w.st] * w.y[(y - t.z) * w.st] * d->scale, L1,
                                   clamped));
    return (st_u32)nx * (st_u32)ny;
}

/* ---- int32 partial sums in a work-item's own window ----------------------
 * Most taps' integers round(x), x = w_x w_y scale L 2^24, lie far within
 * 2^31. In a window of a work-item alone (d->near) they are summed first in
 * an int32 window, a conversion of four floats to int32 and one add a tap:
 * widening four floats to doubles, or four ints to longs, takes two cycles
 * of one pipe on Zen 3, and that limited the tap loop. Row r of the int32
 * window is added to the 64-bit window (near_widen) before its sum could
 * overflow: room[r] bounds |sum| by the taps' bounds added since. Integer
 * sums commute, so the film is the same bit for bit. */

/* The largest tap of the int32 path, 2^26: the room of ST_W <= 16 samples
 * is then within 2^31 - 1; a brighter sample goes to the 64-bit window. */
#define NEAR_TAP_MAX 67108864.0f

/* A bound on |x| of every tap of a sample with largest weights |w_x| <= wx,
 * |w_y| <= wy and L1 = (L, 1): the products in the taps' own order
 * ((w_x w_y) scale) (L 2^24) of the bounds. Float rounding is monotone, so
 * no tap's product is larger; a NaN weight gives NaN (not within any
 * limit). */
ST_HOT float tap_bound(float wx, float wy, float scale, float4 L1)
{
    float4 a = fabs(L1); /* finite: item_radiance, so max needs no NaN rule as fmax's */
    float2 h = max(a.lo, a.hi);
    return wx * wy * fabs(scale) * (max(h.x, h.y) * ST_FIXED_SCALE);
}

/* round(x), ties to even, of four values |x| < 2^31: on an x86 CPU one
 * instruction (roundps) where clang has the builtin (PoCL's convert_int4_rte
 * and rint test each lane for large and special values), and the conversion
 * of an integer exact; elsewhere (Oclgrind cannot run llvm.roundeven) the
 * conversion that rounds. */
#if defined(__OPENCL_VERSION__) && defined(__AVX__) && defined(__has_builtin)
#if __has_builtin(__builtin_elementwise_roundeven)
#define ST_ROUNDEVEN4(x) convert_int4(__builtin_elementwise_roundeven(x))
#endif
#endif
#ifndef ST_ROUNDEVEN4
#define ST_ROUNDEVEN4(x) convert_int4_rte(x)
#endif

ST_HOT int4 near_round4(float4 x)
{
    return ST_ROUNDEVEN4(x);
}

/* Adds row r of the int32 window to the 64-bit window, and clears it. */
ST_HOT void near_widen(const splat_dest *d, int r)
{
    __local long4 *a = d->acc + r * d->side;
    __local int4 *b = d->near + r * d->side;
    for (int k = 0; k < d->side; k++) {
        a[k] += convert_long4(b[k]);
        b[k] = 0;
    }
    d->room[r] = 0;
}

/* Room in window rows r0 .. r1 for taps whose integers sum to at most
 * `need` in magnitude in any pixel: a row whose sum could pass 2^31 - 1 is
 * widened first. */
ST_HOT void near_room(const splat_dest *d, int r0, int r1, int need)
{
    for (int r = r0; r <= r1; r++) {
        if (d->room[r] > INT_MAX - need)
            near_widen(d, r);
        d->room[r] += need;
    }
}

/* The taps of a sample that fits, into the window of this work-item alone
 * (splat_rows.h): int32 partial sums, and long4 sums. */
#define ST_ROUND near_round4
#define ST_ACC int4
#include "splat_rows.h"
#undef ST_ACC
#undef ST_ROUND
#define ST_ROUND fixed_from_scaled4
#define ST_ACC long4
#include "splat_rows.h"
#undef ST_ACC
#undef ST_ROUND

/* Adds v to window pixel a: plainly when the window is this work-item's
 * alone, else atomically per sum. */
ST_HOT void add_window(__local long4 *a, long4 v, int alone)
{
    if (alone) {
        *a += v;
        return;
    }
    __local long *l = (__local long *)a;
    atom_add(l, v.x);
    atom_add(l + 1, v.y);
    atom_add(l + 2, v.z);
    atom_add(l + 3, v.w);
}

/* splat_taps into a work-group's window (d->acc), which holds every tap:
 * per tap one product, one vector conversion and one add of four sums
 * (add_window); box's sums are made once (splat_taps). Returns the splats
 * made. */
ST_HOT st_u32 splat_window(const st_params *p, tap_weights w, float3 L, const splat_dest *d,
                           st_u32 *clamped)
{
    int4 t = w.t;
    int nx = t.y - t.x + 1, ny = t.w - t.z + 1;
    float4 L1 = (float4)(L, 1.0f);
    __local long4 *row = d->acc + (t.z - d->oy) * d->side + (t.x - d->ox);
    if (p->filter.kind == ST_FILTER_BOX) {
        long4 v = fixed_splat4(d->scale, L1, clamped);
        for (int j = 0; j < ny; j++, row += d->side)
            for (int k = 0; k < nx; k++)
                add_window(row + k, v, d->alone);
        return (st_u32)nx * (st_u32)ny;
    }
    if (w.near) { /* its room made: splat_items<N> */
        splat_fitting_int4(d->near + (row - d->acc), d->side, w, nx, ny, d->scale, L1);
        return (st_u32)nx * (st_u32)ny;
    }
    /* no tap needs clamping: within ST_SPLAT_MAX, and L 2^24 finite */
    if (d->alone && tap_bound(w.bx, w.by, d->scale, L1) <= ST_SPLAT_MAX * ST_FIXED_SCALE) {
        splat_fitting_long4(row, d->side, w, nx, ny, d->scale, L1);
        return (st_u32)nx * (st_u32)ny;
    }
    for (int j = 0; j < ny; j++, row += d->side)
        for (int k = 0; k < nx; k++)
            add_window(row + k,
                       fixed_splat4(w.x[k * w.st] * w.y[j * w.st] * d->scale, L1, clamped),
                       d->alone);
    return (st_u32)nx * (st_u32)ny;
}

/* Item i's radiance (0 where it is not finite, which is counted), and the
 * path's rays added to *t: what every splat path starts from. */
ST_HOT float3 item_radiance(st_u32 i, __global const st_path *path, __global st_film_stats *stats,
                            st_tally *t)
{
    __global const st_path *pa = &path[i];
    float3 L = vload3(0, pa->radiance);
    t->closest_rays += pa->closest_rays;
    t->shadow_rays += pa->shadow_rays;
    if (!all(isfinite(L))) {
        atomic_inc(&stats->nonfinite);
        L = (float3)(0.0f);
    }
    return L;
}

/* Whether a sample's splat takes weights from filter_lanes.h: not box's
 * (1 at every tap) nor filter importance sampling's (its own pixel). */
ST_HOT int splat_weighs(const st_params *p)
{
    return p->filter.kind != ST_FILTER_BOX && p->reconstruction != ST_RECON_FIS;
}

/* The factor of every weight of sample s: its pixel's splat_scale in an
 * adaptive render's later rounds, else 1. */
ST_HOT float item_scale(const st_params *p, __global const st_f32 *splat_scale, st_sample s)
{
    return p->adaptive_scaled ? splat_scale[s.pixel] : 1.0f;
}

/* Item i's sample s (on the film), of radiance L and counts t
 * (item_radiance), to d with its taps' weights w (where splat_weighs) and
 * their factor scale (item_scale): adds the splats made to t, which goes
 * to tally[i] or is added to d->counts; counts the sample once if any of
 * its splats clamped. */
static void splat_weighted(const st_params *p, st_u32 i, st_sample s, tap_weights w, float3 L,
                           st_tally t, float scale, __global st_tally *tally,
                           __global st_film_stats *stats, splat_dest *d)
{
    st_u32 clamped = 0u;
    d->scale = scale;
    if (p->reconstruction == ST_RECON_FIS)
        t.splats += splat_fis(p, s, L, d, &clamped);
    else if (w.t.y < w.t.x || w.t.w < w.t.z)
        ; /* no pixel within the radius */
    else if (d->acc)
        t.splats += splat_window(p, w, L, d, &clamped);
    else
        t.splats += splat_taps(p, w, L, d, &clamped);
    if (d->counts) {
        d->counts->splats += t.splats;
        d->counts->closest_rays += t.closest_rays;
        d->counts->shadow_rays += t.shadow_rays;
    } else {
        tally[i] = t;
    }
    if (clamped)
        atomic_inc(&stats->clamped);
}

/* The splat of up to N samples a call, their taps' weights in N lanes
 * (splat_lanes.h): splat_items1 for one sample (splat_samples, and a GPU's
 * splat_tiles), splat_items<ST_W> for a CPU work-item's lanes. */
#define ST_N 1
#include "splat_lanes.h"
#undef ST_N
#if ST_W != 1
#define ST_N ST_W
#include "splat_lanes.h"
#undef ST_N
#endif

/* Reads sample and path; adds to film (weighted by splat_scale in an
 * adaptive render's later rounds); adds the splats made and the
 * path's rays to tally[i]. The per-sample path: filter importance sampling,
 * and the reference for splat_tiles. */
__kernel void splat_samples(ST_STAGE_PARAMS)
{
    st_u32 i = ST_ITEM();
    if (i >= p.item_count)
        return;
    if (!st_sample_on_film(&p, sample[i]))
        return; /* a tile point outside the image (generate.cl) */
    splat_dest d = {film, 1.0f, 0, 0, 0, 0, 0, 0, 0, st_lanczos_turn_of(&p.filter)};
    splat_items1(&p, &i, 1u, sample, path, tally, stats, splat_scale, &d);
}

/* ---- the box filter's splat gathered by pixel ------------------------------
 * With a box of radius 1/2 or less a sample in pixel k reaches k (a tap's
 * centre lies within r of the sample: |k' + 0.5 - x| <= 1/2 leaves k' = k)
 * or none (r < 1/2, near the pixel's edge), and, lying exactly on an edge
 * (the box is closed: filters.h), the pixels across it as well. With a
 * per-pixel sampler outside adaptive rounds, render item g lies in region
 * pixel g mod npix (generate.cl's region_lanes), so a wave's items of one
 * pixel are every npix-th: one work-item per pixel the wave touches sums its
 * items' integers for that pixel (fixed_splat4, scale 1, as splat_samples
 * makes them) and adds the sum to the film once, with plain adds, as no
 * other work-item of the launch touches the pixel: an edge sample's taps on
 * other pixels wait for splat_edges, which adds them atomically where
 * splat_pixels marked the pixel (edge). Integer sums commute: the film is
 * splat_samples' bit for bit, and so are the tallies and counts (render.c
 * chooses the path, test_render_paths.c compares them). */

/* The four sums a box splat adds at each of its taps, of radiance L (0
 * where not finite: item_radiance). */
ST_HOT long4 box_sums(float3 L, st_u32 *clamped)
{
    return fixed_splat4(1.0f, (float4)(L, 1.0f), clamped);
}

/* Item i's share of splat_pixels: its tally and counts, the sums it adds to
 * *acc for its own pixel, and *edge set where it reaches other pixels. */
ST_HOT void gather_item(const st_params *p, st_u32 i, __global const st_sample *sample,
                        __global const st_path *path, __global st_tally *tally,
                        __global st_film_stats *stats, int2 own, long4 *acc, st_u32 *edge)
{
    st_tally t = tally[i];
    float3 L = item_radiance(i, path, stats, &t);
    int4 k = sample_taps(p, sample[i]);
    if (k.y >= k.x && k.w >= k.z) {
        st_u32 clamped = 0u;
        long4 v = box_sums(L, &clamped);
        if (k.x <= own.x && own.x <= k.y && k.z <= own.y && own.y <= k.w)
            *acc += v;
        if (any(k != (int4)(own.x, own.x, own.y, own.y)))
            *edge = 1u;
        t.splats += (st_u32)(k.y - k.x + 1) * (st_u32)(k.w - k.z + 1);
        if (clamped)
            atomic_inc(&stats->clamped);
    }
    tally[i] = t;
}

/* Work-item j of min(item_count, npix): the region's pixel of item j, which
 * also holds items j + npix, j + 2 npix, ... of the wave. */
__kernel void splat_pixels(ST_STAGE_PARAMS)
{
    st_u32 j = ST_ITEM(), npix = p.region_w * p.region_h;
    if (j >= min(p.item_count, npix))
        return;
    st_u32 pixel = sample[j].pixel, across = 0u;
    int2 own = (int2)((int)(pixel % p.width), (int)(pixel / p.width));
    long4 acc = (long4)(0);
    for (st_u32 i = j; i < p.item_count; i += npix)
        gather_item(&p, i, sample, path, tally, stats, own, &acc, &across);
    edge[j] = across;
    __global long *a = film[pixel].sum;
    if (any(acc != 0))
        vstore4(vload4(0, a) + acc, 0, a);
}

/* After splat_pixels, over the same work-items: the taps on other pixels of
 * the edge samples of the pixels it marked, added atomically (pixels may
 * meet there from both sides), their radiance as item_radiance made it,
 * without counting again. */
__kernel void splat_edges(ST_STAGE_PARAMS)
{
    st_u32 j = ST_ITEM(), npix = p.region_w * p.region_h;
    if (j >= min(p.item_count, npix) || !edge[j])
        return;
    splat_dest d = {film, 1.0f, 0, 0, 0, 0, 0, 0, 0, st_lanczos_turn_of(&p.filter)};
    st_u32 pixel = sample[j].pixel, clamped = 0u;
    int2 own = (int2)((int)(pixel % p.width), (int)(pixel / p.width));
    for (st_u32 i = j; i < p.item_count; i += npix) {
        int4 k = sample_taps(&p, sample[i]);
        float3 L = vload3(0, path[i].radiance);
        long4 v = box_sums(all(isfinite(L)) ? L : (float3)(0.0f), &clamped);
        for (int y = k.z; y <= k.w; y++)
            for (int x = k.x; x <= k.y; x++)
                if (x != own.x || y != own.y)
                    add_fixed(&p, &d, x, y, v);
    }
}

/* ---- tile-owned reconstruction ---------------------------------------------
 * splat_tiles gives each image tile (bin) a work-group, which adds its
 * samples' splats into a local window (the tile plus the filter's apron)
 * and the window to the film once per pixel. Where a wave's items lie in
 * their pixels in order (st_items_by_pixel) a bin finds its items from its
 * pixels; otherwise a counting sort places them first: bin_samples counts,
 * bin_scan turns counts into starts, bin_scatter places the items, in the
 * order of its atomics, which may differ from run to run. The integers are
 * those of splat_samples and integer sums commute, so the film is the same
 * bit for bit, whatever the order; a sample is still counted clamped once. */

/* The bin of a sample on the film: of the pixel floor(film) clamped to the
 * image, where truncation serves as floor (the two differ below 0 only,
 * which the clamp takes to 0 either way). */
static st_u32 sample_bin(const st_params *p, st_sample s)
{
    int2 xy = clamp(convert_int2((float2)(s.film[0], s.film[1])), (int2)(0),
                    (int2)((int)p->width - 1, (int)p->height - 1));
    return (st_u32)xy.y / p->bin_side * p->bins_x + (st_u32)xy.x / p->bin_side;
}

/* Counts the wave's items per bin (bin_count is 0 before: wave.c, splat_tiles). */
__kernel void bin_samples(ST_STAGE_PARAMS)
{
    st_u32 i = ST_ITEM();
    if (i < p.item_count && st_sample_on_film(&p, sample[i]))
        atomic_inc(&bin_count[sample_bin(&p, sample[i])]);
}

/* One work-item: bin_start = the exclusive prefix sums of bin_count, whose
 * entries become bin_scatter's cursors (0). */
__kernel void bin_scan(ST_STAGE_PARAMS)
{
    if (ST_ITEM() != 0)
        return;
    st_u32 sum = 0;
    for (st_u32 b = 0; b < p.bins; b++) {
        bin_start[b] = sum;
        sum += bin_count[b];
        bin_count[b] = 0;
    }
    bin_start[p.bins] = sum;
}

/* Places each item on the film in its bin's range of bin_item. */
__kernel void bin_scatter(ST_STAGE_PARAMS)
{
    st_u32 i = ST_ITEM();
    if (i >= p.item_count || !st_sample_on_film(&p, sample[i]))
        return;
    st_u32 b = sample_bin(&p, sample[i]);
    bin_item[bin_start[b] + atomic_inc(&bin_count[b])] = i;
}

/* A bin's items as a list of positions 0 .. count - 1. Sorted: bin_item
 * from `first` on. By pixel: position j = m side² + t is the m-th item of
 * the tile's pixel t (row-major from (x0, y0)), which is wave item
 * ((q - first_item) mod npix) + m npix for the pixel's region index q,
 * where it lies on the region and in the wave. side is a power of two
 * (plan.c), 2^shift: shifts and masks, where divisions by a value the
 * compiler does not know cost more than the rest of the item's lookup. */
typedef struct bin_items {
    int by_pixel;
    st_u32 first, count;              /* sorted */
    st_u32 x0, y0, shift, lag, npix; /* by pixel; lag = first_item mod npix */
} bin_items;

/* A hint for item i's records, which splat_tiles reads soon: the stages
 * before left them far in the wave, out of the caches, and a tile's items
 * lie in runs of a row (perf: most of splat_tiles' time past its taps was
 * on their first loads). */
ST_HOT void prefetch_item(st_u32 i, __global const st_sample *sample, __global const st_path *path)
{
    ST_PREFETCH(&sample[i]);
    ST_PREFETCH(&path[i]);
    ST_PREFETCH((__global const char *)&path[i] + 47); /* 48 bytes may cross a line */
}

/* Bin b's list of items (bin_items): none for a tile off a crop's region. */
ST_HOT bin_items bin_items_of(const st_params *p, __global const st_u32 *bin_start, st_u32 b)
{
    bin_items l = {st_items_by_pixel(p), 0u, 0u, 0u, 0u, 0u, 0u, 0u};
    if (!l.by_pixel) {
        l.first = bin_start[b];
        l.count = bin_start[b + 1] - l.first;
        return l;
    }
    st_u32 side = p->bin_side;
    l.npix = p->region_w * p->region_h;
    l.shift = 31u - clz(side);
    l.x0 = b % p->bins_x * side;
    l.y0 = b / p->bins_x * side;
    l.lag = (st_u32)(p->first_item % l.npix);
    if (l.x0 + side > p->region_x && l.x0 < p->region_x + p->region_w &&
        l.y0 + side > p->region_y && l.y0 < p->region_y + p->region_h) /* a crop's */
        l.count = (p->item_count + l.npix - 1u) / l.npix * side * side;
    return l;
}

/* Positions j .. j + n - 1 of a bin by pixel: whether they lie in one row
 * of the tile and on the region, and then the first's region index q (in
 * the wave's order: lag later, plus npix) and its round m (j's item is
 * run_item(l, q, m), the next's run_item(l, q + 1, m), ...). The
 * coordinates are taken from the region's origin as unsigned, so that one
 * comparison each rejects both sides. */
ST_HOT int pixel_run(const st_params *p, const bin_items *l, st_u32 j, st_u32 n, st_u32 *q,
                     st_u32 *m)
{
    st_u32 side = 1u << l->shift, t = j & (side * side - 1u), c = t & (side - 1u);
    st_u32 x = l->x0 + c - p->region_x, y = l->y0 + (t >> l->shift) - p->region_y;
    *m = j >> (2u * l->shift);
    *q = y * p->region_w + x + l->npix - l->lag;
    return c + n <= side && x < p->region_w && n <= p->region_w - x && y < p->region_h;
}

/* The wave item of region index q (pixel_run's) in round m. */
ST_HOT st_u32 run_item(const bin_items *l, st_u32 q, st_u32 m)
{
    return (q >= l->npix ? q - l->npix : q) + m * l->npix;
}

/* Position j's item into *i; 0 where j holds none (a pixel off the region,
 * a sample beyond the wave). */
ST_HOT int bin_item_at(const st_params *p, __global const st_u32 *bin_item, const bin_items *l,
                       st_u32 j, st_u32 *i)
{
    st_u32 q, m;
    if (!l->by_pixel) {
        *i = bin_item[l->first + j];
        return 1;
    }
    if (!pixel_run(p, l, j, 1u, &q, &m))
        return 0;
    *i = run_item(l, q, m);
    return *i < p->item_count;
}

/* The items of positions j .. j + n - 1 (n <= ST_W) into item[]: returns
 * how many. By pixel, where the positions are one run of a tile's row on
 * the region (pixel_run), their items follow from the first's without a
 * lookup each. */
ST_HOT st_u32 bin_items_at(const st_params *p, __global const st_u32 *bin_item,
                           const bin_items *l, st_u32 j, st_u32 n, st_u32 *item)
{
    st_u32 k = 0, q, m;
    if (l->by_pixel && pixel_run(p, l, j, n, &q, &m)) {
        for (st_u32 e = 0; e < n; e++)
            if ((item[k] = run_item(l, q + e, m)) < p->item_count)
                k++;
        return k;
    }
    for (st_u32 e = j; e < j + n; e++)
        k += (st_u32)bin_item_at(p, bin_item, l, e, &item[k]);
    return k;
}

/* The item to prefetch at position j, whose item is i (prefetch_item), or
 * item_count: by pixel, the pixel below's (the next row's, read a row of
 * the tile later); sorted, the item two batches on. */
ST_HOT st_u32 bin_item_ahead(const st_params *p, __global const st_u32 *bin_item,
                             const bin_items *l, st_u32 j, st_u32 i)
{
    if (l->by_pixel)
        return i + p->region_w;
    return j + 2u * ST_W < l->count ? bin_item[l->first + j + 2u * ST_W] : p->item_count;
}

/* The bin work-group g works on, or p->bins where it has none. With
 * bin_pass 0 a launch covers every bin, and windows that overlap are
 * added to the film atomically; pass c + 1 covers the bins (2 u + c mod 2,
 * 2 v + c / 2), whose windows do not overlap (plan.c takes passes only
 * where an apron is at most half a tile), so the film adds are plain. */
ST_HOT st_u32 group_bin(const st_params *p, st_u32 g)
{
    if (!p->bin_pass)
        return g;
    st_u32 c = p->bin_pass - 1u, across = (p->bins_x + 1u) / 2u;
    st_u32 bx = g % across * 2u + c % 2u, by = g / across * 2u + c / 2u;
    return bx < p->bins_x && by < p->bins / p->bins_x ? by * p->bins_x + bx : p->bins;
}

/* Work-group g owns bin group_bin(g): its samples' splats go into acc, the
 * window of the tile and an apron of ceil(r) + 1 pixels on each side (which
 * holds every tap: st_tap_range stays within r + 0.5 of the sample), ST_W
 * samples at a time, their weights in lanes; then each window pixel's
 * nonzero sums go to the film. acc holds (bin_side + 2 apron)^2 pixels of
 * four longs (render.c sizes it from CL_DEVICE_LOCAL_MEM_SIZE). A
 * work-group of one work-item (CPU devices: render.c) adds into its window
 * without atomics, and into the int32 window and its rows' room that
 * follow it in acc (near_room; st_plan_window_bytes). Each work-item sums
 * its samples' counts (splats, the paths' rays) and adds them to the bin's
 * bin_tally once, where a tally per item cost a read and a write of a line
 * that the wave's earlier stages had left far behind. */
__kernel void splat_tiles(ST_STAGE_PARAMS, __local long4 *acc)
{
    st_u32 b = group_bin(&p, ST_GROUP()), lid = get_local_id(0), n = get_local_size(0);
    if (b >= p.bins)
        return; /* the whole group */
    bin_items l = bin_items_of(&p, bin_start, b);
    if (!l.count)
        return;
    int apron = (int)ceil(p.filter.radius) + 1, side = (int)p.bin_side + 2 * apron;
    int ox = (int)(b % p.bins_x * p.bin_side) - apron, oy = (int)(b / p.bins_x * p.bin_side) - apron;
    for (int j = (int)lid; j < side * side; j += (int)n)
        acc[j] = 0;
    __local int4 *near = n == 1u ? (__local int4 *)(acc + side * side) : 0;
    __local int *room = n == 1u ? (__local int *)(near + side * side) : 0;
    if (near) {
        for (int j = 0; j < side * side; j++)
            near[j] = 0;
        for (int j = 0; j < side; j++)
            room[j] = 0;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    st_tally counts = {0u, 0u, 0u, 0u};
    splat_dest d = {film, 1.0f, acc, near, room, ox, oy, side, n == 1u,
                    st_lanczos_turn_of(&p.filter), &counts};
    for (st_u32 j = lid * ST_W; j < l.count; j += n * ST_W) {
        st_u32 item[ST_W], k = bin_items_at(&p, bin_item, &l, j, min(j + ST_W, l.count) - j, item);
        for (st_u32 e = 0; e < k; e++) {
            st_u32 next = bin_item_ahead(&p, bin_item, &l, j + e, item[e]);
            if (next < p.item_count)
                prefetch_item(next, sample, path);
        }
        if (k)
            ST_CAT(splat_items, ST_W)(&p, item, k, sample, path, tally, stats, splat_scale, &d);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    /* window pixel j at (x, y) of the image, stepped without a division */
    int x = ox + (int)lid % side, y = oy + (int)lid / side;
    for (int j = (int)lid; j < side * side; j += (int)n) {
        int px = x, py = y;
        for (x += (int)n; x >= ox + side; x -= side)
            y++;
        if (px < 0 || py < 0 || px >= (int)p.width || py >= (int)p.height)
            continue;
        __global long *a = film[(size_t)py * p.width + px].sum;
        if (py + 1 < (int)p.height) /* the next row's pixel, out of the caches too */
            ST_PREFETCH(a + 4 * p.width);
        long4 v = near ? acc[j] + convert_long4(near[j]) : acc[j];
        if (p.bin_pass)
            vstore4(vload4(0, a) + v, 0, a);
        else
            film_add(a, v);
    }
    if (lid == 0 && !l.by_pixel)
        bin_count[b] = 0; /* for the next wave's bin_samples */
    __global st_bin_tally *bt = &bin_tally[b];
    if (counts.splats)
        atom_add(&bt->splats, (ulong)counts.splats);
    if (counts.closest_rays)
        atom_add(&bt->closest_rays, (ulong)counts.closest_rays);
    if (counts.shadow_rays)
        atom_add(&bt->shadow_rays, (ulong)counts.shadow_rays);
}

/* Reads film; writes image: I = Σ f L / Σ f wherever Σ f != 0 (the
 * lecture's definition; a negative sum from negative filter lobes divides
 * too, as in pbrt), negative values of radiance clamped to 0 (not an AOV's);
 * a pixel whose weight sum is 0 (no definition), or whose value is not
 * finite, becomes 0 and is counted. ST_W pixels a work-item: region pixels ST_W w .. ST_W w + n - 1
 * (a crop resolves its window only), their sums gathered (lanes past n
 * repeat the last pixel and are neither stored nor counted), the
 * arithmetic in lanes, each lane the operations of width 1, and the
 * counts added once per work-item. */
__kernel void resolve_film(ST_FILM_PARAMS)
{
    st_u32 first = ST_W * ST_ITEM(), npix = p.region_w * p.region_h;
    if (first >= npix)
        return;
    st_u32 n = min((st_u32)ST_W, npix - first), at[ST_W];
    float sum[ST_FILM_SUMS][ST_W];
    for (st_u32 k = 0; k < ST_W; k++) {
        at[k] = st_region_pixel(&p, first + min(k, n - 1u));
        for (int c = 0; c < ST_FILM_SUMS; c++)
            sum[c][k] = (float)film[at[k]].sum[c];
    }
    st_lf w = ST_VLOAD(ST_W, sum[3]) * (1.0f / ST_FIXED_SCALE);
    st_lv3 v = st_lv3_make(ST_VLOAD(ST_W, sum[0]), ST_VLOAD(ST_W, sum[1]), ST_VLOAD(ST_W, sum[2]));
    v = st_lv3_div(st_lv3_scale(v, ST_LF(1.0f / ST_FIXED_SCALE)), w);
    st_li used = ST_IOTA(ST_W) < (st_li)((int)n), zero = w == ST_LF(0.0f);
    st_li finite = isfinite(v.x) & isfinite(v.y) & isfinite(v.z);
    /* radiance's negative values (the filters' negative lobes) clamped to 0;
     * an AOV keeps its sign (normals, positions) */
    st_lv3 kept = p.aov != ST_AOV_NONE
                      ? v
                      : st_lv3_make(ST_FMAXF(v.x, ST_LF(0.0f)), ST_FMAXF(v.y, ST_LF(0.0f)),
                                    ST_FMAXF(v.z, ST_LF(0.0f)));
    v = st_lv3_select(st_lv3_make(ST_LF(0.0f), ST_LF(0.0f), ST_LF(0.0f)), kept, !zero & finite);
    st_u32 nonfinite = popcount(ST_MASK_BITS(ST_W, used & !zero & !finite)),
           unweighted = popcount(ST_MASK_BITS(ST_W, used & zero));
    if (nonfinite)
        atomic_add(&stats->nonfinite, nonfinite);
    if (unweighted)
        atomic_add(&stats->zero_weight, unweighted);
    float out[4][ST_W];
    ST_VSTORE(ST_W, v.x, out[0]);
    ST_VSTORE(ST_W, v.y, out[1]);
    ST_VSTORE(ST_W, v.z, out[2]);
    ST_VSTORE(ST_W, w, out[3]);
    for (st_u32 k = 0; k < n; k++) {
        st_pixel px = {{out[0][k], out[1][k], out[2][k]}, out[3][k]};
        image[at[k]] = px;
    }
}
