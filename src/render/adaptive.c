/* adaptive.c — adaptive sampling at a budget of spp samples per pixel on
 * average (kernels/film/adaptive.cl has the device side):
 *  1. a pilot: N0 samples per pixel, splatted, and each pixel's moments;
 *  2. each pixel's error estimate e(q) (adaptive_estimate), read back;
 *  3. one allocation: pixel q gets m(q) >= 1 more samples, m ∝ e + β ē
 *     (the count that minimises Σ e² / m at a fixed Σ m; β ē is a
 *     defensive share for pixels whose few pilot samples looked calm),
 *     capped by --max-spp and, with a threshold X, by (e / X)² in all;
 *     the scale is the largest whose counts fit the budget;
 *  4. samples N0 .. N0 + m(q) - 1 of every pixel, a prefix of its own
 *     sequence, splatted with weight 1 / m(q) into an emptied film;
 *  5. adaptive_blend combines the pilot's film and the later one.
 * Every sample traced counts in the cost (the pilot is part of the image). */
#include "render_int.h"

#include <math.h>
#include <stdlib.h>

/* β above: the share of the mean estimate every pixel is given. */
#define ADAPTIVE_DEFENSIVE 0.1

void st_render_adaptive_counts(const st_render_options *o, st_u32 *pilot, st_u32 *max_spp)
{
    st_u32 n0 = o->spp / 4 < 2 ? 2 : o->spp / 4 > 16 ? 16 : o->spp / 4;
    *pilot = o->min_spp ? o->min_spp : n0;
    *max_spp = o->max_spp ? o->max_spp : 8 * o->spp;
}

/* The allocation's inputs and its result: m[q] more samples for pixel q. */
typedef struct allocation {
    const float *e;  /* error estimates */
    size_t pixels;
    double floor;    /* β ē */
    double cap;      /* most more samples per pixel */
    double x2;       /* threshold², 0: none */
    st_u32 pilot;
    st_u32 *m;
} allocation;

/* Pixel q's count at scale c: round(c (e + β ē)) within [1, cap], and
 * with a threshold X at most (e / X)² - N0 (at least 1). */
static st_u32 count_at(const allocation *a, size_t q, double c)
{
    double n = floor(c * (a->e[q] + a->floor) + 0.5), cap = a->cap;
    if (a->x2 > 0) {
        double need = ceil((double)a->e[q] * a->e[q] / a->x2) - a->pilot;
        cap = need < cap ? need : cap;
    }
    n = n < cap ? n : cap;
    return n < 1 ? 1u : (st_u32)n;
}

static double total_at(const allocation *a, double c)
{
    double sum = 0;
    for (size_t q = 0; q < a->pixels; q++)
        sum += count_at(a, q, c);
    return sum;
}

/* Fills a->m at the largest scale whose total is at most budget (found by
 * bisection: the total grows with the scale). */
static void allocate(allocation *a, double budget)
{
    double mean = 0;
    for (size_t q = 0; q < a->pixels; q++)
        mean += a->e[q];
    mean /= (double)a->pixels;
    a->floor = mean > 0 ? ADAPTIVE_DEFENSIVE * mean : 1.0; /* all calm: even counts */
    double lo = 0, hi = 1;
    while (total_at(a, hi) <= budget && hi < 1e30)
        lo = hi, hi *= 2;
    for (int k = 0; k < 64 && hi < 1e30; k++) {
        double mid = 0.5 * (lo + hi);
        *(total_at(a, mid) <= budget ? &lo : &hi) = mid;
    }
    for (size_t q = 0; q < a->pixels; q++)
        a->m[q] = count_at(a, q, hi < 1e30 ? lo : hi);
}

typedef struct ranked {
    st_u32 m, pixel;
} ranked;

/* More samples first, then by pixel: the same order every run. */
static int by_count(const void *x, const void *y)
{
    const ranked *a = x, *b = y;
    if (a->m != b->m)
        return a->m > b->m ? -1 : 1;
    return a->pixel < b->pixel ? -1 : a->pixel > b->pixel;
}

/* The pixels by falling count (malloc'ed; NULL: out of memory). */
static ranked *rank_pixels(const st_u32 *m, size_t n)
{
    ranked *rk = malloc(n * sizeof *rk);
    if (!rk)
        return NULL;
    for (size_t q = 0; q < n; q++)
        rk[q] = (ranked){m[q], (st_u32)q};
    qsort(rk, n, sizeof *rk, by_count);
    return rk;
}

/* The plan to the device: n(q) into pixel_spp, 1 / m(q) into splat_scale,
 * the ranking into active. */
static st_status upload_plan(st_renderer *r, st_wave *w, const st_u32 *m, st_u32 pilot,
                             const ranked *rk, st_error *err)
{
    size_t n = w->pixels;
    st_u32 *u = malloc(n * sizeof *u);
    float *f = malloc(n * sizeof *f);
    if (!u || !f) {
        free(u);
        free(f);
        return st_fail(err, ST_ERR_NOMEM, "out of memory for the adaptive plan");
    }
    for (size_t q = 0; q < n; q++) {
        u[q] = pilot + m[q];
        f[q] = 1.0f / (float)m[q];
    }
    st_status rc =
        st_device_buffer_write(r->dev, w->b[ST_WAVE_pixel_spp], n * sizeof *u, u, err);
    if (rc == ST_OK)
        rc = st_device_buffer_write(r->dev, w->b[ST_WAVE_splat_scale], n * sizeof *f, f, err);
    for (size_t q = 0; rc == ST_OK && q < n; q++)
        u[q] = rk[q].pixel;
    if (rc == ST_OK)
        rc = st_device_buffer_write(r->dev, w->b[ST_WAVE_active], n * sizeof *u, u, err);
    free(u);
    free(f);
    return rc;
}

/* Launches adaptive kernel k (ST_K_ADAPTIVE_*) over every pixel with p, the
 * device's ST_W pixels a work-item. */
static st_status launch(st_renderer *r, int k, const st_params *p, st_wave *w, st_error *err)
{
    size_t items = st_render_lane_items(r->dev, w->pixels);
    st_render_note_ran(r, r->kernel[k]);
    if (st_wave_set_params(r->kernel[k], p, err) ||
        st_device_launch(r->dev, r->kernel[k], items, 0, err))
        return err->status;
    return ST_OK;
}

/* Step 1: the pilot's `total` items in waves, each wave's moments taken. */
static st_status run_pilot(st_renderer *r, st_params *p, st_wave *w, const st_render_options *o,
                           st_u64 total, st_progress_state *pr, st_render_items_fn items,
                           st_error *err)
{
    st_status rc = ST_OK;
    for (st_u64 first = 0; rc == ST_OK && first < total; first += w->items) {
        st_u64 n = total - first < w->items ? total - first : w->items;
        rc = items(r, p, w, o, first, n, pr, err);
        if (rc == ST_OK)
            rc = launch(r, ST_K_ADAPTIVE_MOMENTS, p, w, err);
    }
    return rc;
}

/* Steps 2 and 3: the estimates read back and the counts m chosen. */
static st_status plan(st_renderer *r, st_params *p, st_wave *w, const st_render_options *o,
                      st_u32 pilot, st_u32 max_spp, st_u32 *m, st_error *err)
{
    size_t n = w->pixels;
    float *e = malloc(n * sizeof *e);
    if (!e)
        return st_fail(err, ST_ERR_NOMEM, "out of memory for the adaptive estimates");
    st_status rc = launch(r, ST_K_ADAPTIVE_ESTIMATE, p, w, err);
    if (rc == ST_OK)
        rc = st_device_buffer_read(r->dev, w->b[ST_WAVE_splat_scale], n * sizeof *e, e, err);
    if (rc == ST_OK) {
        double x = o->noise_threshold;
        allocation a = {e, n, 0, (double)(max_spp - pilot), x * x, pilot, m};
        allocate(&a, (double)(o->spp - pilot) * (double)n);
    }
    free(e);
    return rc;
}

/* Step 4: rounds over the ranking. A round gives the first `count` pixels
 * (all with m >= hi) their samples lo .. hi - 1 past the pilot; a pixel
 * leaves the list once its m is reached. */
static st_status run_rounds(st_renderer *r, st_params *p, st_wave *w, const st_render_options *o,
                            const ranked *rk, st_u32 pilot, st_progress_state *pr,
                            st_render_stats *st, st_render_items_fn items, st_error *err)
{
    st_status rc = ST_OK;
    st_u32 lo = 0;
    p->adaptive_scaled = 1;
    for (size_t j = w->pixels; rc == ST_OK && j-- > 0;) {
        st_u32 hi = rk[j].m, count = (st_u32)(j + 1);
        if (hi == lo)
            continue;
        p->adaptive_count = count;
        p->adaptive_base = pilot + lo;
        rc = items(r, p, w, o, 0, (st_u64)count * (hi - lo), pr, err);
        st->samples += (st_u64)count * (hi - lo);
        lo = hi;
    }
    p->adaptive_count = 0;
    p->adaptive_scaled = 0;
    return rc;
}

st_status st_render_adaptive(st_renderer *r, st_params *p, st_wave *w,
                             const st_render_options *o, st_u64 total, st_progress_state *pr,
                             st_render_stats *st, st_render_items_fn items, st_error *err)
{
    st_u32 pilot, max_spp;
    st_render_adaptive_counts(o, &pilot, &max_spp);
    p->adaptive_pilot = pilot;
    st_u32 *m = malloc(w->pixels * sizeof *m);
    if (!m)
        return st_fail(err, ST_ERR_NOMEM, "out of memory for the adaptive plan");
    ranked *rk = NULL;
    st_status rc = ST_OK;
    for (int k = ST_K_ADAPTIVE_MOMENTS; k <= ST_K_ADAPTIVE_BLEND && rc == ST_OK; k++)
        rc = st_wave_bind_film(r->kernel[k], p, w, err);
    if (rc == ST_OK)
        rc = run_pilot(r, p, w, o, total, pr, items, err);
    st->samples = total;
    if (rc == ST_OK)
        rc = plan(r, p, w, o, pilot, max_spp, m, err);
    if (rc == ST_OK && !(rk = rank_pixels(m, w->pixels)))
        rc = st_fail(err, ST_ERR_NOMEM, "out of memory for the adaptive plan");
    if (rc == ST_OK)
        rc = upload_plan(r, w, m, pilot, rk, err);
    if (rc == ST_OK)
        rc = run_rounds(r, p, w, o, rk, pilot, pr, st, items, err);
    if (rc == ST_OK)
        rc = launch(r, ST_K_ADAPTIVE_BLEND, p, w, err);
    free(rk);
    free(m);
    return rc;
}
