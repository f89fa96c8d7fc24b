/* pixel_tile.c — the tiles the tiled samplers render from (st_sampling.h:
 * st_sampling_pixel_tile): a torus of side x side pixels holding exactly spp
 * points in every pixel, blue noise across pixel borders.
 *
 * The tile is built in spp passes; each pass adds one point inside every
 * pixel, so after pass s every pixel holds s + 1 points. Distances are
 * measured to every point already placed, in any pixel, toroidally across
 * the tile, so the spacing does not see the pixel grid. Best-candidate is
 * Mitchell's (1991) rule: point n is the farthest from its nearest
 * neighbour of m(n) = k n (capped) uniform candidates, drawn over the pixels
 * that have no point yet in this pass, so, as in Mitchell's, the largest
 * gap anywhere is filled next, and the candidate's pixel then closes for the
 * pass (every pixel its spp). An earlier rule that visited the pixels in a
 * random order with 4 (pass + 1) candidates each left a smallest distance of
 * about 0.3 of the spacing, and with at most 64 candidates turned random at
 * high spp. Poisson disk visits the pixels in a random order and takes the
 * first uniform dart inside the pixel that is at least r from every point
 * (Cook 1986's dart throwing), and retries the whole tile with a smaller r
 * when a pixel refuses ST_PIXEL_TILE_DARTS darts in a row.
 *
 * Invariant: coordinates are integers on the lattice 2^-16 pixel (exact
 * floats), distances are exact 64-bit integers on that lattice, so the
 * minimum distance the tests measure on the output is the one decided on. */
#include "sampling_int.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#define PT_BITS 16
#define PT_NONE 0xffffffffu

/* Points in placement order, and a search grid of g x g cells (sub x sub per
 * pixel, sub a power of two so cell edges are lattice points) whose points
 * are chained through next[]. */
typedef struct pt_state {
    st_u32 side, spp, sub, g, n;
    st_u32 shift; /* PT_BITS - log2(sub): lattice to cell */
    st_i64 extent;  /* side << PT_BITS: the torus' period */
    st_i32 (*xy)[2]; /* placement order */
    st_u32 *pixel;   /* each point's pixel (row-major) */
    st_u32 *head, *next;
} pt_state;

static st_u32 pt_uniform(st_u64 *rng, st_u32 n)
{
    return (st_u32)(((splitmix64(rng) >> 32) * (st_u64)n) >> 32);
}

static st_i64 pt_axis(st_i64 d, st_i64 extent)
{
    d = d < 0 ? -d : d;
    return d > extent / 2 ? extent - d : d;
}

static st_u32 pt_cell(const pt_state *s, st_i32 x, st_i32 y)
{
    return ((st_u32)y >> s->shift) * s->g + ((st_u32)x >> s->shift);
}

/* Lowers *best by the points of cell c; 1 once one is at d2 <= beat. */
static int pt_scan(const pt_state *s, st_u32 c, st_i32 x, st_i32 y, st_i64 beat, st_i64 *best)
{
    for (st_u32 i = s->head[c]; i != PT_NONE; i = s->next[i]) {
        st_i64 dx = pt_axis(s->xy[i][0] - x, s->extent), dy = pt_axis(s->xy[i][1] - y, s->extent);
        st_i64 d2 = dx * dx + dy * dy;
        if (d2 < *best) {
            *best = d2;
            if (d2 <= beat)
                return 1;
        }
    }
    return 0;
}

/* Squared toroidal distance from (x,y) to the nearest point, or a value >=
 * limit when none is nearer than limit; returns early with a value <= beat
 * once a point that near is found. Rings of cells outwards: the points of
 * ring k >= 1 are at least k - 1 cell widths away. */
static st_i64 pt_nearest(const pt_state *s, st_i32 x, st_i32 y, st_i64 beat, st_i64 limit)
{
    st_u32 c = pt_cell(s, x, y), cx = c % s->g, cy = c / s->g;
    st_i64 w = s->extent / s->g, best = INT64_MAX;
    for (st_i64 ring = 0;; ++ring) {
        st_i64 lb = ring < 1 ? 0 : (ring - 1) * w;
        if (lb * lb >= best || lb * lb >= limit)
            return best;
        for (st_i64 dy = -ring; dy <= ring; ++dy) {
            st_i64 step = (dy == -ring || dy == ring) ? 1 : 2 * ring; /* the ring's border */
            st_u32 ry = wrap_index((st_i64)cy + dy % s->g, s->g);
            for (st_i64 dx = -ring; dx <= ring; dx += step) {
                st_u32 rx = wrap_index((st_i64)cx + dx % s->g, s->g);
                if (pt_scan(s, ry * s->g + rx, x, y, beat, &best))
                    return best;
            }
        }
        if (2 * ring + 1 >= (st_i64)s->g)
            return best;
    }
}

static void pt_add(pt_state *s, st_u32 pixel, st_i32 x, st_i32 y)
{
    st_u32 c = pt_cell(s, x, y);
    s->xy[s->n][0] = x;
    s->xy[s->n][1] = y;
    s->pixel[s->n] = pixel;
    s->next[s->n] = s->head[c];
    s->head[c] = s->n++;
}

/* A uniform lattice point inside pixel p. */
static void pt_draw(const pt_state *s, st_u32 p, st_u64 *rng, st_i32 *x, st_i32 *y)
{
    st_u64 r = splitmix64(rng);
    *x = (st_i32)(((p % s->side) << PT_BITS) | (st_u32)(r & 0xffffu));
    *y = (st_i32)(((p / s->side) << PT_BITS) | (st_u32)((r >> 16) & 0xffffu));
}

/* Mitchell's candidate count for point n (0-based) of the tile: k n, at
 * least 1, at most the cap (st_sampling.h names k and the cap and why). */
static st_u64 pt_candidates(st_u32 n)
{
    st_u64 m = (st_u64)ST_PIXEL_TILE_K * n;
    return m < 1 ? 1 : m > ST_PIXEL_TILE_MAX_M ? ST_PIXEL_TILE_MAX_M : m;
}

/* Best-candidate: of m(n) candidates drawn uniformly over the pixels still
 * open in this pass (open[0..*nopen), each a pixel index), the one farthest
 * from its nearest point; its pixel is closed for the pass. */
static void pt_best_candidate(pt_state *s, st_u32 *open, st_u32 *nopen, st_u64 *rng)
{
    st_u64 m = pt_candidates(s->n);
    st_i64 best = -1;
    st_i32 bx = 0, by = 0;
    st_u32 bi = 0;
    for (st_u64 j = 0; j < m; j++) {
        st_u32 i = pt_uniform(rng, *nopen);
        st_i32 x, y;
        pt_draw(s, open[i], rng, &x, &y);
        st_i64 d2 = pt_nearest(s, x, y, best, INT64_MAX);
        if (d2 > best) {
            best = d2;
            bx = x;
            by = y;
            bi = i;
        }
    }
    pt_add(s, open[bi], bx, by);
    open[bi] = open[--*nopen];
}

/* Poisson disk: the first dart inside pixel p at distance >= r (r2 = r^2)
 * from every point; 0 when ST_PIXEL_TILE_DARTS darts all fail. */
static int pt_dart(pt_state *s, st_u32 p, st_i64 r2, st_u64 *rng)
{
    for (st_u32 t = 0; t < ST_PIXEL_TILE_DARTS; t++) {
        st_i32 x, y;
        pt_draw(s, p, rng, &x, &y);
        if (pt_nearest(s, x, y, r2 - 1, r2) >= r2) {
            pt_add(s, p, x, y);
            return 1;
        }
    }
    return 0;
}

/* One try at the whole tile (r2 < 0: best-candidate); 0 when a dart failed. */
static int pt_fill(pt_state *s, st_i64 r2, st_u32 *order, st_u64 *rng)
{
    st_u32 pixels = s->side * s->side;
    s->n = 0;
    for (st_u32 c = 0; c < s->g * s->g; c++)
        s->head[c] = PT_NONE;
    for (st_u32 pass = 0; pass < s->spp; pass++) {
        for (st_u32 i = 0; i < pixels; i++)
            order[i] = i;
        if (r2 < 0) { /* best-candidate: order is the list of open pixels */
            for (st_u32 open = pixels; open > 0;)
                pt_best_candidate(s, order, &open, rng);
            continue;
        }
        for (st_u32 i = pixels; i > 1; i--) { /* a fresh random pixel order (Fisher-Yates) */
            st_u32 j = pt_uniform(rng, i), t = order[i - 1];
            order[i - 1] = order[j];
            order[j] = t;
        }
        for (st_u32 i = 0; i < pixels; i++)
            if (!pt_dart(s, order[i], r2, rng))
                return 0;
    }
    return 1;
}

/* Point j of the output: sample j / side^2 of pixel j mod side^2, in pixels. */
static float *pt_output(const pt_state *s)
{
    st_u32 pixels = s->side * s->side, *seen = calloc(pixels, sizeof *seen);
    float *out = malloc(2 * (size_t)s->n * sizeof *out);
    if (seen && out)
        for (st_u32 i = 0; i < s->n; i++) {
            size_t j = (size_t)seen[s->pixel[i]]++ * pixels + s->pixel[i];
            out[2 * j] = (float)s->xy[i][0] * 0x1p-16f;
            out[2 * j + 1] = (float)s->xy[i][1] * 0x1p-16f;
        }
    free(seen);
    if (!seen) {
        free(out);
        return NULL;
    }
    return out;
}

static void pt_free(pt_state *s)
{
    free(s->xy);
    free(s->pixel);
    free(s->head);
    free(s->next);
}

static st_status pt_alloc(pt_state *s, st_u32 side, st_u32 spp, st_error *err)
{
    size_t n = (size_t)side * side * spp;
    s->side = side;
    s->spp = spp;
    s->extent = (st_i64)side << PT_BITS;
    s->shift = PT_BITS;
    for (s->sub = 1; s->sub * s->sub * 2 < spp; s->sub *= 2) /* ~2 points per cell at the end */
        s->shift--;
    s->g = side * s->sub;
    s->xy = malloc(n * sizeof *s->xy);
    s->pixel = malloc(n * sizeof *s->pixel);
    s->next = malloc(n * sizeof *s->next);
    s->head = malloc((size_t)s->g * s->g * sizeof *s->head);
    if (!s->xy || !s->pixel || !s->next || !s->head) {
        pt_free(s);
        return st_fail(err, ST_ERR_NOMEM, "pixel tile: out of memory for %zu points", n);
    }
    return ST_OK;
}

st_status st_sampling_pixel_tile(st_u32 sampler, st_u32 side, st_u32 spp, st_u32 seed,
                                 float **points, float *radius, st_error *err)
{
    if (points)
        *points = NULL;
    if (!points || !ST_SAMPLER_IS_TILED(sampler))
        return st_fail(err, ST_ERR_USAGE, "pixel tile: NULL output or not a tiled sampler");
    if (side < 1 || spp < 1 || (st_u64)side * side * spp > ST_PIXEL_TILE_MAX_POINTS ||
        side > 1024)
        return st_fail(err, ST_ERR_USAGE,
                       "pixel tile: %u x %u pixels at %u spp: need 1..1024 pixels a side and "
                       "at most %u points", side, side, spp, ST_PIXEL_TILE_MAX_POINTS);
    pt_state s = {0};
    if (pt_alloc(&s, side, spp, err) != ST_OK)
        return err ? err->status : ST_ERR_NOMEM;
    st_u32 *order = malloc((size_t)side * side * sizeof *order);
    st_u64 rng = (st_u64)seed;
    /* Poisson: r^2 = ST_PIXEL_TILE_PACKING / spp pixels^2, shrunk by 1/16 per retry
     * (it reaches 0, where every dart fits, so the loop ends) */
    st_i64 r = -1;
    if (sampler == ST_SAMPLER_POISSON)
        r = (st_i64)(sqrt(ST_PIXEL_TILE_PACKING / spp) * (1 << PT_BITS));
    while (order && !pt_fill(&s, r < 0 ? -1 : r * r, order, &rng))
        r -= r / 16 > 0 ? r / 16 : 1;
    if (radius)
        *radius = r < 0 ? 0.0f : (float)r * 0x1p-16f;
    *points = order ? pt_output(&s) : NULL;
    free(order);
    pt_free(&s);
    if (!*points)
        return st_fail(err, ST_ERR_NOMEM, "pixel tile: out of memory");
    return ST_OK;
}

st_status st_sampling_pad_tables(st_u32 sampler, st_u32 spp, st_u32 seed, st_u32 **words,
                                 st_u32 *count, st_error *err)
{
    if (words)
        *words = NULL;
    if (!words || !count || !ST_SAMPLER_IS_TILED(sampler) || spp < 1)
        return st_fail(err, ST_ERR_USAGE, "pad tables: NULL output, spp 0 or not a tiled sampler");
    st_u32 n = spp < ST_PAD_MAX_POINTS ? spp : ST_PAD_MAX_POINTS;
    st_u32 *out = malloc(sizeof(st_u32) * 2 * ST_PMJ02_SETS * (size_t)n);
    if (!out)
        return st_fail(err, ST_ERR_NOMEM, "pad tables: out of memory for %u points", n);
    for (st_u32 q = 0; q < ST_PMJ02_SETS; q++) {
        st_u64 state = ((st_u64)seed << 32) | q; /* one stream per (seed, set) */
        float *pts = NULL;
        st_status rc = st_sampling_pixel_tile(sampler, 1, n, (st_u32)splitmix64(&state), &pts,
                                              NULL, err);
        if (rc != ST_OK) {
            free(out);
            return rc;
        }
        /* x in [0, 1) on the 2^-16 lattice: x 2^32 is an exact integer */
        for (st_u32 j = 0; j < 2 * n; j++)
            out[2 * (size_t)q * n + j] = (st_u32)((double)pts[j] * 4294967296.0);
        free(pts);
    }
    *words = out;
    *count = n;
    return ST_OK;
}
