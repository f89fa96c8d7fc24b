/* samplers.c — host-side tile generators of the sampling module: Poisson disk
 * (Bridson 2007) and best-candidate (Mitchell 1991) points on the unit torus.
 *
 * Invariant: every point returned lies in [0,1)^2 as a float, and every
 * distance the algorithms test is computed in double from those very floats,
 * so what the tests measure on the output is exactly what the generator
 * decided on. Random numbers come from one splitmix64 stream per call, so a
 * (count, seed) pair always gives the same tile. See include/st_sampling.h. */
#include "st_sampling.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- random numbers ------------------------------------------------------ */

/* splitmix64 (Steele, Lea, Flood, "Fast Splittable Pseudorandom Number
 * Generators", OOPSLA 2014; constants as in Vigna's splitmix64.c). */
static st_u64 splitmix64(st_u64 *state)
{
    st_u64 z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* Top 24 bits times 2^-24: a float in [0,1), every value exact. */
static float unit_float(st_u64 *state)
{
    return (float)(splitmix64(state) >> 40) * 0x1p-24f;
}

/* Uniform integer in [0, n), n < 2^32 (multiply-shift, bias < n / 2^32). */
static st_u32 uniform_index(st_u64 *state, st_u32 n)
{
    return (st_u32)(((splitmix64(state) >> 32) * (st_u64)n) >> 32);
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

/* Wraps a double onto [0,1) and rounds it to a float still in [0,1). */
static float wrap_unit(double v)
{
    v = v < 0.0 ? v + 1.0 : (v >= 1.0 ? v - 1.0 : v); /* |offset| < 2r < 1 */
    float f = (float)v;
    return f >= 1.0f ? 0.0f : f;
}

static st_u32 cell_of(float v, st_u32 g)
{
    st_u32 i = (st_u32)((double)v * g);
    return i < g ? i : g - 1;
}

static st_status check_count(st_u32 count, st_u32 max, const char *what, st_error *err)
{
    if (count == 0)
        return st_fail(err, ST_ERR_USAGE, "%s: point count must be at least 1", what);
    if (count > max)
        return st_fail(err, ST_ERR_USAGE, "%s: point count %u exceeds the limit %u", what,
                       count, max);
    return ST_OK;
}

/* ---- Poisson disk (Bridson) ------------------------------------------------ */

/* One Bridson run at a fixed radius. The grid has g x g cells of width
 * 1/g < r/sqrt(2), so a cell holds at most one point; cells store the point's
 * coordinates (NaN marks an empty cell) so a neighbour test reads one cache
 * line per grid row. Points within r of a candidate lie in the 5 x 5 cells
 * around it because r*g < sqrt(2) + r < 2 whenever g > 5 (for g <= 5 the 5 x 5
 * block covers the whole torus). */
typedef struct poisson_run {
    double r, r2;
    st_u32 g;
    float *cells;   /* 2 * g * g: x,y or NaN,NaN */
    st_u32 *order;  /* cell index of each point in generation order */
    st_u32 *active; /* cell indices of active points */
    st_u32 count, active_n, capacity;
    st_i64 offset[25];   /* float offsets of NEIGHBOURS[i] in an unwrapped block */
    double dirs[256][2]; /* cos, sin of 2*pi*i/256 */
} poisson_run;

/* Cell offsets of the 5 x 5 block, nearest first so rejections come early. */
static const signed char NEIGHBOURS[25][2] = {
    {0, 0},   {1, 0},  {-1, 0}, {0, 1},   {0, -1}, {1, 1},  {-1, 1},  {1, -1}, {-1, -1},
    {2, 0},   {-2, 0}, {0, 2},  {0, -2},  {2, 1},  {2, -1}, {-2, 1},  {-2, -1}, {1, 2},
    {-1, 2},  {1, -2}, {-1, -2}, {2, 2},  {-2, 2}, {2, -2}, {-2, -2}};

/* i mod g for i a few cells outside [0, g) (no division: this is hot). */
static st_u32 wrap_index(st_i64 i, st_u32 g)
{
    while (i < 0)
        i += g;
    while (i >= (st_i64)g)
        i -= g;
    return (st_u32)i;
}

/* 1 when a stored cell point is closer than r to (x,y). An empty cell holds
 * NaN, whose comparisons are false: no branch on occupancy (a third of the
 * cells are full, so such a branch is a coin toss the predictor loses). */
static int too_close(const float *c, double x, double y, double r2)
{
    double dx = fabs(c[0] - x), dy = fabs(c[1] - y);
    dx = dx > 0.5 ? 1.0 - dx : dx;
    dy = dy > 0.5 ? 1.0 - dy : dy;
    return dx * dx + dy * dy < r2;
}

/* Plain (not toroidal) closeness: valid when the 5 x 5 block does not wrap,
 * since then every difference is under 3 cells < 1/2. */
static int too_close_flat(const float *c, double x, double y, double r2)
{
    double dx = c[0] - x, dy = c[1] - y;
    return dx * dx + dy * dy < r2;
}

/* Slow path near the tile's edges: cell indices and distances wrap. */
static int poisson_fits_wrapped(const poisson_run *run, double x, double y, st_u32 ix, st_u32 iy)
{
    st_u32 g = run->g, cols[5], rows[5];
    for (int d = -2; d <= 2; ++d) {
        cols[d + 2] = wrap_index((st_i64)ix + d, g);
        rows[d + 2] = wrap_index((st_i64)iy + d, g);
    }
    int hit = 0;
    for (int i = 0; i < 25; ++i) {
        const float *c = run->cells + 2 * ((size_t)rows[NEIGHBOURS[i][1] + 2] * g +
                                          cols[NEIGHBOURS[i][0] + 2]);
        hit |= too_close(c, x, y, run->r2);
    }
    return !hit;
}

/* 1 when no stored point is closer than r to (x,y) (toroidally). */
static int poisson_fits(const poisson_run *run, float x, float y)
{
    st_u32 g = run->g, ix = cell_of(x, g), iy = cell_of(y, g);
    if (ix < 2 || iy < 2 || ix + 2 >= g || iy + 2 >= g)
        return poisson_fits_wrapped(run, x, y, ix, iy);
    const float *base = run->cells + 2 * ((size_t)iy * g + ix);
    int hit = 0;
    for (int i = 0; i < 25; ++i) {
        hit |= too_close_flat(base + run->offset[i], x, y, run->r2);
        if ((i == 4 || i == 8) && hit) /* 86% of rejections are decided by */
            return 0;                   /* the first 5 cells, 97% by the first 9 */
    }
    return !hit;
}

static void poisson_insert(poisson_run *run, float x, float y)
{
    st_u32 cell = cell_of(y, run->g) * run->g + cell_of(x, run->g);
    run->cells[2 * (size_t)cell] = x;
    run->cells[2 * (size_t)cell + 1] = y;
    run->order[run->count++] = cell;
    run->active[run->active_n++] = cell;
}

/* Draws an offset uniform (by area) in the annulus r <= |d| < 2r, as
 * Bridson asks: radius r*sqrt(1 + 3u) inverts the area CDF
 * (rho^2 - r^2) / (3 r^2); angle 2*pi*v. One splitmix64 output gives u and v,
 * 32 bits each. cos/sin of the angle come from a 256-entry table at the top 8
 * bits of v and the angle-addition formula with Taylor series for the rest
 * (d < 2*pi/256: truncation error d^5/120 < 1e-10). Measured here, this is
 * about 40% faster than rejection from the square [-2r,2r)^2, whose 41%
 * rejection branch the predictor keeps losing, and than sinf/cosf. */
static void annulus_offset(const poisson_run *run, st_u64 *rng, double *dx, double *dy)
{
    st_u64 z = splitmix64(rng);
    double u = (double)(z & 0xffffffffu) * 0x1p-32;
    st_u32 v = (st_u32)(z >> 32);
    const double *cs = run->dirs[v >> 24];
    double d = (double)(v & 0xffffffu) * (6.283185307179586 * 0x1p-32), d2 = d * d;
    double cd = 1.0 - d2 * (0.5 - d2 * (1.0 / 24.0)), sd = d * (1.0 - d2 * (1.0 / 6.0));
    double rho = run->r * sqrt(1.0 + 3.0 * u);
    *dx = rho * (cs[0] * cd - cs[1] * sd);
    *dy = rho * (cs[1] * cd + cs[0] * sd);
}

/* Runs Bridson's loop until the active list is empty (Bridson 2007, step 2). */
static void poisson_fill(poisson_run *run, st_u64 *rng)
{
    poisson_insert(run, unit_float(rng), unit_float(rng));
    while (run->active_n > 0) {
        st_u32 a = uniform_index(rng, run->active_n);
        const float *p = run->cells + 2 * (size_t)run->active[a];
        int placed = 0;
        for (st_u32 t = 0; t < ST_POISSON_K && !placed; ++t) {
            double dx, dy;
            annulus_offset(run, rng, &dx, &dy);
            float x = wrap_unit(p[0] + dx), y = wrap_unit(p[1] + dy);
            if (poisson_fits(run, x, y)) {
                poisson_insert(run, x, y);
                placed = 1;
            }
        }
        if (!placed) /* k failures: retire the point (swap with the last) */
            run->active[a] = run->active[--run->active_n];
    }
}

static void poisson_run_free(poisson_run *run)
{
    free(run->cells);
    free(run->order);
    free(run->active);
    memset(run, 0, sizeof *run);
}

/* One complete run at radius r; on success run holds the tile. */
static st_status poisson_run_at(poisson_run *run, double r, st_u32 seed, st_error *err)
{
    memset(run, 0, sizeof *run);
    run->r = r;
    run->r2 = r * r;
    run->g = (st_u32)floor(1.4142135623730951 / r) + 1u; /* cell 1/g < r/sqrt(2), strictly */
    for (int i = 0; i < 25; ++i)
        run->offset[i] = 2 * ((st_i64)NEIGHBOURS[i][1] * run->g + NEIGHBOURS[i][0]);
    for (int i = 0; i < 256; ++i) {
        run->dirs[i][0] = cos(6.283185307179586 * i / 256.0);
        run->dirs[i][1] = sin(6.283185307179586 * i / 256.0);
    }
    size_t cells = (size_t)run->g * run->g;
    run->capacity = (st_u32)cells; /* at most one point per cell */
    run->cells = malloc(2 * cells * sizeof *run->cells);
    run->order = malloc((size_t)run->capacity * sizeof *run->order);
    run->active = malloc((size_t)run->capacity * sizeof *run->active);
    if (!run->cells || !run->order || !run->active) {
        poisson_run_free(run);
        return st_fail(err, ST_ERR_NOMEM, "poisson tile: out of memory for a %u x %u grid",
                       (unsigned)sqrt((double)cells), (unsigned)sqrt((double)cells));
    }
    for (size_t i = 0; i < 2 * cells; ++i)
        run->cells[i] = NAN;
    st_u64 rng = 0x504f4953534f4e00ull ^ (st_u64)seed; /* "POISSON" domain */
    poisson_fill(run, &rng);
    return ST_OK;
}

/* Largest float not above r, so "every pair is >= *radius" holds for the
 * reported float too. */
static float float_floor(double r)
{
    float f = (float)r;
    return (double)f > r ? nextafterf(f, 0.0f) : f;
}

static st_status poisson_output(const poisson_run *run, float **points, st_error *err)
{
    float *out = malloc(2 * (size_t)run->count * sizeof *out);
    if (!out)
        return st_fail(err, ST_ERR_NOMEM, "poisson tile: out of memory for %u points",
                       run->count);
    for (st_u32 i = 0; i < run->count; ++i) {
        out[2 * i] = run->cells[2 * (size_t)run->order[i]];
        out[2 * i + 1] = run->cells[2 * (size_t)run->order[i] + 1];
    }
    *points = out;
    return ST_OK;
}

st_status st_sampling_poisson_tile(st_u32 target_count, st_u32 seed, float **points,
                                   st_u32 *count, float *radius, st_error *err)
{
    if (points)
        *points = NULL;
    if (!points || !count)
        return st_fail(err, ST_ERR_USAGE, "poisson tile: NULL output pointer");
    if (check_count(target_count, ST_POISSON_MAX_COUNT, "poisson tile", err) != ST_OK)
        return err ? err->status : ST_ERR_USAGE;

    /* Radius from the packing density, then rescale: N ~ c / r^2, so the
     * radius that gives the target is r * sqrt(count / target). */
    double r = sqrt(ST_POISSON_PACKING / target_count);
    poisson_run best = {0};
    double best_miss = INFINITY;
    for (int it = 0; it < 7; ++it) {
        poisson_run run;
        if (poisson_run_at(&run, r, seed, err) != ST_OK) {
            poisson_run_free(&best);
            return err ? err->status : ST_ERR_NOMEM;
        }
        double miss = fabs((double)run.count - target_count);
        double ratio = (double)run.count / target_count;
        if (miss < best_miss) {
            poisson_run_free(&best);
            best = run;
            best_miss = miss;
        } else {
            poisson_run_free(&run);
        }
        if (best_miss <= 0.01 * target_count)
            break;
        r *= sqrt(ratio);
    }
    st_status s = poisson_output(&best, points, err);
    if (s == ST_OK) {
        *count = best.count;
        if (radius)
            *radius = float_floor(best.r);
    }
    poisson_run_free(&best);
    return s;
}

/* ---- best candidate (Mitchell) --------------------------------------------- */

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
