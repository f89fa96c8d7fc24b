/* best_candidate.c — the best-candidate tile generator of the sampling module
 * (Mitchell 1991) on the unit torus (st_sampling.h:
 * st_sampling_best_candidate_tile).
 *
 * Invariant: every point returned lies in [0,1)^2 as a float, and every
 * distance the algorithm compares is computed in double from those very
 * floats, so the grid-accelerated result equals the brute-force definition. */
#include "sampling_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Top 24 bits times 2^-24: a float in [0,1), every value exact. */
static float unit_float(st_u64 *state)
{
    return (float)(splitmix64(state) >> 40) * 0x1p-24f;
}

/* Squared toroidal distance on the unit torus between (ax,ay) and (bx,by):
 * per axis min(|a-b|, 1-|a-b|). Differences of floats are exact in double. */
static double torus_d2(double ax, double ay, double bx, double by)
{
    double dx = fabs(ax - bx), dy = fabs(ay - by);
    if (dx > 0.5)
        dx = 1.0 - dx;
    if (dy > 0.5)
        dy = 1.0 - dy;
    return dx * dx + dy * dy;
}

static st_u32 cell_of(float v, st_u32 g)
{
    st_u32 i = (st_u32)((double)v * g);
    return i < g ? i : g - 1;
}


/* Points so far (insertion order) plus a uniform grid of g x g cells. A cell
 * is one 64-byte cache line holding up to BC_SLOTS points inline; further
 * points of a crowded cell go on a linked list through next[] (rare). The
 * grid is rebuilt at twice the resolution when the points reach 4 per cell,
 * so cells hold 1..4 points on average and a rejected candidate usually costs
 * one cache line. (A plain linked-list grid was 2-3x slower here: every point
 * visited was a cache miss.) */
#define BC_SLOTS 7
#define BC_NONE 0xffffffffu

typedef struct bc_cell {
    float xy[BC_SLOTS][2];
    st_u32 count;    /* points in the cell, inline and overflow */
    st_u32 overflow; /* first point index past the inline slots, or BC_NONE */
} bc_cell;
ST_STATIC_ASSERT(sizeof(bc_cell) == 64, "bc_cell: one cache line");

typedef struct bc_state {
    float *pts; /* 2 * capacity, insertion order */
    st_u32 *next;
    bc_cell *cells;
    st_u32 n, g;
} bc_state;

static void bc_link(bc_state *s, st_u32 i)
{
    float x = s->pts[2 * i], y = s->pts[2 * i + 1];
    bc_cell *c = &s->cells[(size_t)cell_of(y, s->g) * s->g + cell_of(x, s->g)];
    if (c->count < BC_SLOTS) {
        c->xy[c->count][0] = x;
        c->xy[c->count][1] = y;
    } else {
        s->next[i] = c->overflow;
        c->overflow = i;
    }
    c->count++;
}

static st_status bc_regrid(bc_state *s, st_u32 g, st_error *err)
{
    bc_cell *cells = aligned_alloc(64, (size_t)g * g * sizeof *cells);
    if (!cells)
        return st_fail(err, ST_ERR_NOMEM, "best-candidate tile: out of memory for a %u x %u grid",
                       g, g);
    free(s->cells);
    s->cells = cells;
    s->g = g;
    for (size_t c = 0; c < (size_t)g * g; ++c) {
        cells[c].count = 0;
        cells[c].overflow = BC_NONE;
    }
    for (st_u32 i = 0; i < s->n; ++i)
        bc_link(s, i);
    return ST_OK;
}

/* Lowers *best by the points of one cell; 1 when it fell to <= beat. */
static int bc_scan_cell(const bc_state *s, const bc_cell *c, double x, double y, double beat,
                        double *best)
{
    st_u32 inline_n = c->count < BC_SLOTS ? c->count : BC_SLOTS;
    for (st_u32 j = 0; j < inline_n; ++j) {
        double d2 = torus_d2(c->xy[j][0], c->xy[j][1], x, y);
        if (d2 < *best) {
            *best = d2;
            if (d2 <= beat)
                return 1;
        }
    }
    for (st_u32 i = c->overflow; i != BC_NONE; i = s->next[i]) {
        double d2 = torus_d2(s->pts[2 * i], s->pts[2 * i + 1], x, y);
        if (d2 < *best) {
            *best = d2;
            if (d2 <= beat)
                return 1;
        }
    }
    return 0;
}

static double min4(double a, double b, double c, double d)
{
    double ab = a < b ? a : b, cd = c < d ? c : d;
    return ab < cd ? ab : cd;
}

/* Squared toroidal distance from (x,y) to the nearest point, searched ring by
 * ring of cells outwards. Ring s holds the cells at Chebyshev cell distance s;
 * its points are at least (s-1)/g + e away, e = distance from (x,y) to its own
 * cell's edges. Returns early with a value <= beat once a point that close is
 * found: such a candidate cannot win. */
static double bc_nearest_d2(const bc_state *s, float x, float y, double beat)
{
    st_u32 g = s->g, ix = cell_of(x, g), iy = cell_of(y, g);
    double cell = 1.0 / g, fx = x - ix * cell, fy = y - iy * cell;
    double e = min4(fx, cell - fx, fy, cell - fy);
    double best = INFINITY;
    for (st_i64 ring = 0;; ++ring) {
        double lb = ring == 0 ? 0.0 : (ring - 1) * cell + e;
        if (lb * lb >= best)
            return best;
        for (st_i64 dy = -ring; dy <= ring; ++dy) {
            st_i64 step = (dy == -ring || dy == ring) ? 1 : 2 * ring; /* ring border only */
            st_u32 cy = wrap_index(iy + dy % g, g);
            for (st_i64 dx = -ring; dx <= ring; dx += step) {
                st_u32 cx = wrap_index(ix + dx % g, g);
                if (bc_scan_cell(s, &s->cells[(size_t)cy * g + cx], x, y, beat, &best))
                    return best;
            }
        }
        if (2 * ring + 1 >= (st_i64)g) /* every cell visited */
            return best;
    }
}

static st_u32 bc_candidates(st_u32 n)
{
    st_u64 m = (st_u64)ST_BEST_CANDIDATE_K * n;
    if (m < 1)
        m = 1;
    return m > ST_BEST_CANDIDATE_MAX_M ? ST_BEST_CANDIDATE_MAX_M : (st_u32)m;
}

/* Adds point n: the best of m(n) candidates (Mitchell 1991). */
static void bc_add_point(bc_state *s, st_u64 *rng)
{
    float bx = 0.0f, by = 0.0f;
    double best = -1.0;
    for (st_u32 j = bc_candidates(s->n); j > 0; --j) {
        float x = unit_float(rng), y = unit_float(rng);
        double d2 = bc_nearest_d2(s, x, y, best);
        if (d2 > best) {
            best = d2;
            bx = x;
            by = y;
        }
    }
    s->pts[2 * s->n] = bx;
    s->pts[2 * s->n + 1] = by;
    bc_link(s, s->n++);
}

st_status st_sampling_best_candidate_tile(st_u32 count, st_u32 seed, float **points,
                                          st_error *err)
{
    if (points)
        *points = NULL;
    if (!points)
        return st_fail(err, ST_ERR_USAGE, "best-candidate tile: NULL output pointer");
    if (check_count(count, ST_BEST_CANDIDATE_MAX_COUNT, "best-candidate tile", err) != ST_OK)
        return err ? err->status : ST_ERR_USAGE;

    bc_state s = {0};
    st_status status = ST_OK;
    s.pts = malloc(2 * (size_t)count * sizeof *s.pts);
    s.next = malloc((size_t)count * sizeof *s.next);
    if (!s.pts || !s.next) {
        status = st_fail(err, ST_ERR_NOMEM, "best-candidate tile: out of memory for %u points",
                         count);
        goto done;
    }
    if ((status = bc_regrid(&s, 1, err)) != ST_OK)
        goto done;
    st_u64 rng = (st_u64)seed;
    while (s.n < count) {
        if (s.n >= 4ull * s.g * s.g && (status = bc_regrid(&s, 2 * s.g, err)) != ST_OK)
            goto done;
        bc_add_point(&s, &rng);
    }
    *points = s.pts;
    s.pts = NULL;
done:
    free(s.pts);
    free(s.next);
    free(s.cells);
    return status;
}
