/* adaptive.c — adaptive sampling at a budget of spp samples per pixel on
 * average (kernels/film/adaptive.cl has the device side):
 *  1. a pilot: N0 samples per pixel, splatted into a film of its own, and
 *     each pixel's moments;
 *  2. rounds r = 1 .. ADAPTIVE_ROUNDS, each: every pixel's error estimate
 *     e(q) from the moments of all its samples so far (adaptive_estimate),
 *     read back; a target T(q) of later samples (allocate: T ∝ e + β ē,
 *     the count that minimises Σ e² / T at a fixed Σ T, β ē a defensive
 *     share for pixels whose samples looked calm; at least those taken,
 *     capped by --max-spp and, with a threshold X, by the relative error
 *     criterion e / sqrt(T) <= X); the largest scale whose targets fit the
 *     budget; this round's m(q) = ceil((T − n) / rounds left), n the later
 *     samples taken, all of T − n in the last round; then samples
 *     N0 + n .. N0 + n + m − 1 of every pixel, splatted with weight
 *     rest / (T − n), rest the pixel's share of the weight not yet given;
 *  3. adaptive_blend resolves the later film against the pilot's.
 * Sobol' and Halton take their own path (run_qmc, below): powers of two
 * per pixel, one round, or the uniform render where adapting would not pay.
 * Unbiased: a round's counts and weights are chosen before its samples are
 * drawn and each pixel's weights sum to 1, so the later film's sums are
 * unbiased whatever the counts (a martingale's sum: each round's samples
 * are unbiased given all that came before); the pilot's samples chose the
 * first counts and so are not part of the estimate (adaptive.cl). Every
 * sample traced counts in the cost. */
#include "render_int.h"

#include <math.h>
#include <stdlib.h>

/* β above: the share of the mean estimate every pixel is given. */
#define ADAPTIVE_DEFENSIVE 0.1
/* The rounds after the pilot: each spends a share of what is left, from
 * an estimate that has seen every sample before it. */
#define ADAPTIVE_ROUNDS 3

void st_render_adaptive_counts(const st_render_options *o, st_u32 *pilot, st_u32 *max_spp)
{
    st_u32 n0 = o->spp / 8 < 2 ? 2 : o->spp / 8 > 16 ? 16 : o->spp / 8;
    *pilot = o->min_spp ? o->min_spp : n0;
    *max_spp = o->max_spp ? o->max_spp : 8 * o->spp;
}

/* Per pixel: the later samples taken, the share of the weight not yet
 * given (0: done), this round's count and each of its samples' weight. */
typedef struct pixel_plan {
    st_u32 taken, m;
    double rest;
    float scale;
} pixel_plan;

/* The allocation's inputs: e the error estimates, pp the pixels' plans. */
typedef struct allocation {
    const float *e;
    pixel_plan *pp;
    size_t pixels;
    double floor;    /* β ē */
    double cap;      /* most later samples per pixel */
    double x2;       /* threshold², 0: none */
} allocation;

/* Pixel q's target at scale c: round(c (e + β ē)), with a threshold X at
 * most (e / X)², within [taken + 1, cap] while its weight is not all given
 * (its last sample carries what is left), else taken. */
static st_u32 target_at(const allocation *a, size_t q, double c)
{
    const pixel_plan *pp = &a->pp[q];
    double lo = pp->taken + 1.0, n = floor(c * (a->e[q] + a->floor) + 0.5), cap = a->cap;
    if (pp->rest <= 0.0)
        return pp->taken;
    if (a->x2 > 0) {
        double need = ceil((double)a->e[q] * a->e[q] / a->x2);
        cap = need < cap ? need : cap;
    }
    n = n < cap ? n : cap;
    return n < lo ? (st_u32)lo : (st_u32)n;
}

static double total_at(const allocation *a, double c)
{
    double sum = 0;
    for (size_t q = 0; q < a->pixels; q++)
        sum += target_at(a, q, c);
    return sum;
}

/* The largest scale whose targets total at most budget (found by
 * bisection: the total grows with the scale). */
static double scale_for(allocation *a, double budget)
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
    return hi < 1e30 ? lo : hi;
}

/* Round `round` (1-based) of the plan: each pixel's count m and sample
 * weight from its target, its weight left and count taken updated. */
static void plan_round(allocation *a, double budget, int round)
{
    double c = scale_for(a, budget);
    int left = ADAPTIVE_ROUNDS - round + 1;
    for (size_t q = 0; q < a->pixels; q++) {
        pixel_plan *pp = &a->pp[q];
        st_u32 more = target_at(a, q, c) - pp->taken;
        pp->m = left == 1 ? more : (more + left - 1) / left;
        pp->scale = 0.0f;
        if (pp->m == 0)
            continue;
        double w = pp->m == more ? pp->rest : pp->rest * pp->m / more;
        pp->scale = (float)(pp->rest / more);
        pp->rest = pp->m == more ? 0.0 : pp->rest - w;
        pp->taken += pp->m;
    }
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

/* The pixels by falling count this round, into rk. */
static void rank_pixels(const pixel_plan *pp, size_t n, ranked *rk)
{
    for (size_t q = 0; q < n; q++)
        rk[q] = (ranked){pp[q].m, (st_u32)q};
    qsort(rk, n, sizeof *rk, by_count);
}

/* To the device: the samples each pixel had before this round (pilot +
 * taken - m) into pixel_spp, the weight of its samples into splat_scale,
 * the ranking into active (rk NULL: pixel_spp alone, the final counts). */
static st_status upload_round(st_renderer *r, st_wave *w, const pixel_plan *pp, st_u32 pilot,
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
        u[q] = pilot + pp[q].taken - (rk ? pp[q].m : 0);
        f[q] = pp[q].scale;
    }
    st_status rc =
        st_device_buffer_write(r->dev, w->b[ST_WAVE_pixel_spp], n * sizeof *u, u, err);
    if (rc == ST_OK && rk)
        rc = st_device_buffer_write(r->dev, w->b[ST_WAVE_splat_scale], n * sizeof *f, f, err);
    for (size_t q = 0; rc == ST_OK && rk && q < n; q++)
        u[q] = rk[q].pixel;
    if (rc == ST_OK && rk)
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

/* `total` items of the pilot or of a round, in waves, each wave's
 * moments taken. */
static st_status run_items(st_renderer *r, st_params *p, st_wave *w, const st_render_options *o,
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

/* The error estimates of every pixel, into e. */
static st_status estimate(st_renderer *r, st_params *p, st_wave *w, float *e, st_error *err)
{
    st_status rc = launch(r, ST_K_ADAPTIVE_ESTIMATE, p, w, err);
    if (rc == ST_OK)
        rc = st_device_buffer_read(r->dev, w->b[ST_WAVE_splat_scale], w->pixels * sizeof *e, e,
                                   err);
    return rc;
}

/* A round's samples: passes over the ranking. A pass gives the first
 * `count` pixels (all with m >= hi) their samples lo .. hi - 1 of the
 * round; a pixel leaves the list once its m is reached. */
static st_status run_round(st_renderer *r, st_params *p, st_wave *w, const st_render_options *o,
                           const ranked *rk, st_progress_state *pr, st_render_stats *st,
                           st_render_items_fn items, st_error *err)
{
    st_status rc = ST_OK;
    st_u32 lo = 0;
    for (size_t j = w->pixels; rc == ST_OK && j-- > 0;) {
        st_u32 hi = rk[j].m, count = (st_u32)(j + 1);
        if (hi == lo)
            continue;
        p->adaptive_count = count;
        p->adaptive_base = lo;
        rc = run_items(r, p, w, o, (st_u64)count * (hi - lo), pr, items, err);
        st->samples += (st_u64)count * (hi - lo);
        lo = hi;
    }
    p->adaptive_count = 0;
    return rc;
}

/* Step 2: the rounds, each planned from the estimates of all samples
 * before it. */
static st_status run_rounds(st_renderer *r, st_params *p, st_wave *w, const st_render_options *o,
                            st_u32 pilot, st_u32 max_spp, st_progress_state *pr,
                            st_render_stats *st, st_render_items_fn items, st_error *err)
{
    size_t n = w->pixels;
    float *e = malloc(n * sizeof *e);
    pixel_plan *pp = calloc(n, sizeof *pp);
    ranked *rk = malloc(n * sizeof *rk);
    st_status rc = ST_OK;
    if (!e || !pp || !rk)
        rc = st_fail(err, ST_ERR_NOMEM, "out of memory for the adaptive plan");
    double x = o->noise_threshold;
    allocation a = {e, pp, n, 0, (double)(max_spp - pilot), x * x};
    for (size_t q = 0; rc == ST_OK && q < n; q++)
        pp[q].rest = 1.0;
    for (int round = 1; rc == ST_OK && round <= ADAPTIVE_ROUNDS; round++) {
        rc = estimate(r, p, w, e, err); /* after the pilot: moves its film aside */
        p->adaptive_scaled = 1;
        if (rc != ST_OK)
            break;
        plan_round(&a, (double)(o->spp - pilot) * (double)n, round);
        rank_pixels(pp, n, rk);
        rc = upload_round(r, w, pp, pilot, rk, err);
        if (rc == ST_OK)
            rc = run_round(r, p, w, o, rk, pr, st, items, err);
    }
    p->adaptive_scaled = 0;
    if (rc == ST_OK)
        rc = upload_round(r, w, pp, pilot, NULL, err); /* the spp map */
    free(rk);
    free(pp);
    free(e);
    return rc;
}

/* ---- QMC samplers (sobol, halton) -------------------------------------------
 * A pixel's samples 0 .. 2^k - 1 of such a sequence are a net (Sobol') or a
 * Halton prefix, and neither sampler's sample s of a pixel depends on the
 * render's spp, so a pixel's plain mean over any 2^k prefix converges as
 * the uniform render's does. The pilot is the uniform render's own first
 * N0 samples (a power of two); from it, an image-level choice: where the
 * predicted error of the adaptive counts is not clearly below the uniform
 * render's, the render goes on to the uniform one, bit for bit. */

/* a: a pixel's error is taken to fall as T^-a with its count T. Scrambled
 * nets reach T^-3/4 at a pixel with an edge and T^-3/2 where the pixel is
 * smooth (Owen 1997; T^-1/2 would be plain Monte Carlo); a = 1 lies between,
 * and measured best of 3/4, 1, 5/4 and 3/2 on the built-in scenes together
 * (3/4 gave the smooth pixels too few samples: zone plate 64 x 48, 64 spp,
 * 1.18x uniform's RMSE; 5/4 and 3/2 too many: the Cornell box lost
 * a third of its gain). */
#define QMC_EXPONENT 1.0
/* Adapt only where the predicted squared error is below this share of the
 * uniform render's (the prediction is rough; near 1 it would be a coin). */
#define QMC_MARGIN 0.8

int st_render_adaptive_qmc(const st_render_options *o)
{
    return o->adaptive && (o->sampler == ST_SAMPLER_SOBOL || o->sampler == ST_SAMPLER_HALTON);
}

st_u32 st_render_adaptive_qmc_pilot(const st_render_options *o)
{
    st_u32 pilot, max_spp, n = 1;
    st_render_adaptive_counts(o, &pilot, &max_spp);
    while (2 * n <= pilot)
        n *= 2;
    return n;
}

/* Each pixel's error estimate e, as adaptive_estimate's (the per-sample
 * spread over (μ² + ε²)^(γ/2)) but pooled over the pixels within the
 * filter's reach (radius rounded up) rather than 3 x 3: a pixel's samples
 * reach that far, and a pixel of few samples beside an edge makes its
 * neighbours across the edge noisy through the filter's weights. */
static st_status qmc_estimate(st_renderer *r, st_wave *w, const st_params *p, float *e,
                              st_error *err)
{
    size_t n = w->pixels;
    st_pixel *m = malloc(n * sizeof *m);
    if (!m)
        return st_fail(err, ST_ERR_NOMEM, "out of memory for the adaptive plan");
    st_status rc = st_device_buffer_read(r->dev, w->b[ST_WAVE_moments], n * sizeof *m, m, err);
    int wd = (int)p->width, ht = (int)p->height, rad = 2 * (int)ceil(p->filter.radius);
    for (int y = 0; rc == ST_OK && y < ht; y++)
        for (int x = 0; x < wd; x++) {
            double s = 0, s2 = 0, k = 0;
            for (int v = y - rad; v <= y + rad; v++)
                for (int u = x - rad; u <= x + rad; u++)
                    if (u >= 0 && u < wd && v >= 0 && v < ht) {
                        const st_pixel *q = &m[(size_t)v * wd + u];
                        s += q->rgb[0], s2 += q->rgb[1], k += q->weight;
                    }
            double mean = k > 0 ? s / k : 0, var = k > 1 ? fmax(s2 / k - mean * mean, 0) : 0;
            double eps2 = ST_ADAPTIVE_EPS * ST_ADAPTIVE_EPS;
            e[(size_t)y * wd + x] =
                (float)(sqrt(var) / pow(mean * mean + eps2, 0.5 * ST_ADAPTIVE_GAMMA));
        }
    free(m);
    return rc;
}

/* The inputs of a QMC allocation. */
typedef struct qmc_plan {
    const float *e;
    size_t pixels;
    st_u32 pilot, cap, spp;
    double x; /* noise threshold, 0: none */
} qmc_plan;

/* Pixel q's count at scale c: the power of two nearest (in log) to
 * c e^(1 / (a + ½)),
 * the count that minimises Σ e² T^-2a at a fixed Σ T, at most the cap and,
 * with a threshold X, at most the count where e T^-a reaches X. */
static st_u32 qmc_count(const qmc_plan *a, size_t q, double c)
{
    double e = a->e[q], t = c * pow(e, 1.0 / (QMC_EXPONENT + 0.5));
    if (a->x > 0) {
        double need = pow(e / a->x, 1.0 / QMC_EXPONENT);
        t = need < t ? need : t;
    }
    st_u32 n = 1;
    while ((st_u64)2 * n <= a->cap && n * sqrt(2.0) < t)
        n *= 2;
    return n;
}

static double qmc_total(const qmc_plan *a, double c, st_u32 *count)
{
    double sum = 0;
    for (size_t q = 0; q < a->pixels; q++)
        sum += count[q] = qmc_count(a, q, c);
    return sum;
}

/* The counts of the largest scale that fits the budget into count;
 * returns the predicted squared error of those counts over the uniform
 * render's, Σ e² T^-2a / Σ e² spp^-2a. */
static double qmc_allocate(const qmc_plan *a, st_u32 *count)
{
    double budget = (double)(a->spp - a->pilot) * (double)a->pixels, lo = 0, hi = 1;
    while (qmc_total(a, hi, count) <= budget && hi < 1e30)
        lo = hi, hi *= 2;
    for (int k = 0; k < 64; k++) {
        double mid = 0.5 * (lo + hi);
        *(qmc_total(a, mid, count) <= budget ? &lo : &hi) = mid;
    }
    qmc_total(a, lo, count);
    double adapted = 0, uniform = 0;
    for (size_t q = 0; q < a->pixels; q++) {
        double e2 = (double)a->e[q] * a->e[q];
        adapted += e2 * pow(count[q], -2.0 * QMC_EXPONENT);
        uniform += e2 * pow(a->spp, -2.0 * QMC_EXPONENT);
    }
    return uniform > 0 ? adapted / uniform : 1.0;
}

/* Samples 0 .. T - 1 of every pixel, each of weight 1 / T, into the film
 * emptied of the pilot's, resolved against it as the random sampler's
 * rounds are (adaptive.cl, later_value). The pilot's samples are traced
 * again (and counted again): the pilot film holds them at weight 1, and a
 * pixel's plain mean needs them at 1 / T, spread by the filter into the
 * pixels round it. */
static st_status qmc_adapt(st_renderer *r, st_params *p, st_wave *w, const st_render_options *o,
                           const st_u32 *count, pixel_plan *pp, ranked *rk,
                           st_progress_state *pr, st_render_stats *st, st_render_items_fn items,
                           st_error *err)
{
    size_t n = w->pixels;
    st_status rc = launch(r, ST_K_ADAPTIVE_ESTIMATE, p, w, err); /* moves the pilot's film aside */
    for (size_t q = 0; q < n; q++) {
        pp[q].m = pp[q].taken = count[q];
        pp[q].scale = 1.0f / (float)count[q];
    }
    rank_pixels(pp, n, rk);
    if (rc == ST_OK)
        rc = upload_round(r, w, pp, 0, rk, err);
    p->adaptive_scaled = 1;
    if (rc == ST_OK)
        rc = run_round(r, p, w, o, rk, pr, st, items, err);
    p->adaptive_scaled = 0;
    if (rc == ST_OK)
        rc = upload_round(r, w, pp, 0, NULL, err); /* the spp map */
    if (rc == ST_OK)
        rc = launch(r, ST_K_ADAPTIVE_BLEND, p, w, err);
    return rc;
}

/* The uniform render's samples N0 .. spp - 1 of every pixel, after its
 * pilot: the uniform render itself. */
static st_status qmc_uniform(st_renderer *r, st_params *p, st_wave *w, const st_render_options *o,
                             st_u32 pilot, pixel_plan *pp, st_progress_state *pr,
                             st_render_stats *st, st_render_items_fn items, st_error *err)
{
    size_t n = w->pixels;
    st->adaptive_uniform = 1;
    st->samples = (st_u64)o->spp * n;
    for (size_t q = 0; q < n; q++)
        pp[q].taken = o->spp - pilot;
    st_status rc = upload_round(r, w, pp, pilot, NULL, err); /* the spp map */
    if (rc == ST_OK)
        rc = items(r, p, w, o, (st_u64)pilot * n, (st_u64)(o->spp - pilot) * n, pr, err);
    return rc;
}

/* A QMC sampler's adaptive render: the pilot, the counts, and either the
 * adaptive samples or the rest of the uniform render. */
static st_status run_qmc(st_renderer *r, st_params *p, st_wave *w, const st_render_options *o,
                         st_progress_state *pr, st_render_stats *st, st_render_items_fn items,
                         st_error *err)
{
    size_t n = w->pixels;
    st_u32 pilot = st_render_adaptive_qmc_pilot(o), random_pilot, cap;
    st_render_adaptive_counts(o, &random_pilot, &cap);
    float *e = malloc(n * sizeof *e);
    st_u32 *count = malloc(n * sizeof *count);
    pixel_plan *pp = calloc(n, sizeof *pp);
    ranked *rk = malloc(n * sizeof *rk);
    st_status rc = e && count && pp && rk
                       ? run_items(r, p, w, o, (st_u64)pilot * n, pr, items, err)
                       : st_fail(err, ST_ERR_NOMEM, "out of memory for the adaptive plan");
    st->samples = (st_u64)pilot * n;
    if (rc == ST_OK)
        rc = qmc_estimate(r, w, p, e, err);
    qmc_plan a = {e, n, pilot, cap, o->spp, o->noise_threshold};
    /* with a threshold the counts stop where it is reached, cheaper than
     * uniform by design: no choice to make */
    if (rc == ST_OK && (qmc_allocate(&a, count) < QMC_MARGIN || a.x > 0))
        rc = qmc_adapt(r, p, w, o, count, pp, rk, pr, st, items, err);
    else if (rc == ST_OK)
        rc = qmc_uniform(r, p, w, o, pilot, pp, pr, st, items, err);
    free(rk);
    free(pp);
    free(count);
    free(e);
    return rc;
}

st_status st_render_adaptive(st_renderer *r, st_params *p, st_wave *w,
                             const st_render_options *o, st_u64 total, st_progress_state *pr,
                             st_render_stats *st, st_render_items_fn items, st_error *err)
{
    st_u32 pilot, max_spp;
    st_render_adaptive_counts(o, &pilot, &max_spp);
    st_status rc = ST_OK;
    for (int k = ST_K_ADAPTIVE_MOMENTS; k <= ST_K_ADAPTIVE_BLEND && rc == ST_OK; k++)
        rc = st_wave_bind_film(r->kernel[k], p, w, err);
    p->adaptive_scaled = 0;
    if (rc == ST_OK && st_render_adaptive_qmc(o))
        return run_qmc(r, p, w, o, pr, st, items, err);
    if (rc == ST_OK)
        rc = run_items(r, p, w, o, total, pr, items, err);
    st->samples = total;
    if (rc == ST_OK)
        rc = run_rounds(r, p, w, o, pilot, max_spp, pr, st, items, err);
    if (rc == ST_OK)
        rc = launch(r, ST_K_ADAPTIVE_BLEND, p, w, err);
    return rc;
}
