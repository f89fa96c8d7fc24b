/* poisson_disk.c — the Poisson-disk tile generator of the sampling module
 * (Bridson 2007) on the unit torus (st_sampling.h: st_sampling_poisson_tile).
 *
 * Invariant: every point returned lies in [0,1)^2 as a float, and every
 * distance the algorithm tests is computed exactly from those very floats (as
 * 64-bit integers on the 2^-24 lattice), so what the tests measure on the
 * output is exactly what the generator decided on. */
#include "sampling_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Uniform integer in [0, n), n < 2^32 (multiply-shift, bias < n / 2^32). */
static st_u32 uniform_index(st_u64 *state, st_u32 n)
{
    return (st_u32)(((splitmix64(state) >> 32) * (st_u64)n) >> 32);
}

/* Coordinates live on the lattice 2^-24 Z, stored as integers k in [0, 2^24):
 * every such k * 2^-24 is an exact float, wrap-around is a mask, and a
 * squared distance in units of 2^-48 is an exact 64-bit integer, the very
 * value double arithmetic gets from the returned floats. So "no two points
 * closer than r" is decided exactly, and tests measuring the output in double
 * reach the same verdict. */
#define FIX_BITS 24
#define FIX_ONE (1 << FIX_BITS)
#define FIX_MASK (FIX_ONE - 1)
#define FIX_EMPTY 0x40000000 /* empty cell: ~2^30 away from any point */

/* One Bridson run at a fixed radius. The grid has g x g cells of width
 * 1/g < r/sqrt(2), so a cell holds at most one point; cells store the point's
 * coordinates so a neighbour test reads one cache line per grid row. Points
 * within r of a candidate lie in the 5 x 5 cells around it, because
 * r*g < sqrt(2) + r < 2 whenever g > 5 (for g <= 5 the block covers the
 * whole torus).
 * The grid is stored with a border of 2 ghost cells on every side (pitch
 * g + 4): for g >= 7 a point near an edge is also written, shifted by +-1,
 * into the ghost cells across the seam, so every 5 x 5 block is contiguous
 * and plain differences are toroidal ones (the block spans < 1/2). Tiny grids
 * (g < 7) take a slow path with explicit wrapping instead. */
typedef struct poisson_run {
    double r;          /* a float value, so r^2 * 2^48 is exact */
    st_i64 r2;         /* ceil(r^2 * 2^48): too close iff d2 < r2 */
    st_u32 g, pitch;   /* cells per side; g + 4 */
    st_i32 *cells;     /* 2 * pitch^2: x,y or FIX_EMPTY */
    st_u32 *order;     /* (padded) cell index of each point in generation order */
    st_u32 *active;    /* (padded) cell indices of active points */
    st_u32 count, active_n, capacity;
    int failed;        /* out of memory while growing order/active */
    double dirs[1024][2]; /* cos, sin of 2*pi*i/1024 */
} poisson_run;

/* Cell offsets of the 5 x 5 block. */
static const signed char NEIGHBOURS[25][2] = {
    {0, 0},   {1, 0},  {-1, 0}, {0, 1},   {0, -1}, {1, 1},  {-1, 1},  {1, -1}, {-1, -1},
    {2, 0},   {-2, 0}, {0, 2},  {0, -2},  {2, 1},  {2, -1}, {-2, 1},  {-2, -1}, {1, 2},
    {-1, 2},  {1, -2}, {-1, -2}, {2, 2},  {-2, 2}, {2, -2}, {-2, -2}};

static st_u32 fix_cell(st_i32 k, st_u32 g)
{
    return (st_u32)(((st_u64)k * g) >> FIX_BITS); /* floor(k 2^-24 g), < g */
}

/* Plain squared distance: right inside a ghost-padded 5 x 5 block when
 * g >= 7, since every difference is then under 3 cells < 1/2. An empty cell's
 * FIX_EMPTY makes d2 ~ 2^60: never too close. Branch-free: a third of the
 * cells are full, a coin toss the branch predictor would lose. */
static st_i64 flat_d2(const st_i32 *c, st_i32 x, st_i32 y)
{
    st_i64 dx = c[0] - x, dy = c[1] - y;
    return dx * dx + dy * dy;
}

static st_i64 torus_fix(st_i32 a, st_i32 b)
{
    st_i32 d = a > b ? a - b : b - a;
    return d > FIX_ONE / 2 ? FIX_ONE - d : d;
}

/* Slow path for tiny grids (g < 7): wrapped cells, toroidal distances. */
static int poisson_fits_wrapped(const poisson_run *run, st_i32 x, st_i32 y, st_u32 ix, st_u32 iy)
{
    st_u32 g = run->g;
    for (int i = 0; i < 25; ++i) {
        st_u32 cx = wrap_index((st_i64)ix + NEIGHBOURS[i][0], g);
        st_u32 cy = wrap_index((st_i64)iy + NEIGHBOURS[i][1], g);
        const st_i32 *c = run->cells + 2 * ((size_t)(cy + 2) * run->pitch + cx + 2);
        if (c[0] == FIX_EMPTY)
            continue;
        st_i64 dx = torus_fix(c[0], x), dy = torus_fix(c[1], y);
        if (dx * dx + dy * dy < run->r2)
            return 0;
    }
    return 1;
}

/* 1 when no stored point is closer than r to (x,y) (toroidally). The 5 x 5
 * block is tested in three straight-line groups, nearest cells first: the 5
 * of the centre cross decide 86% of the rejections, the 3 x 3 block 97%
 * (measured). `|` rather than `||` keeps each group free of branches. */
#define TOO_CLOSE(row, dx) (flat_d2((row) + 2 * (dx), x, y) < r2)
static int poisson_fits(const poisson_run *run, st_i32 x, st_i32 y)
{
    st_u32 g = run->g, ix = fix_cell(x, g), iy = fix_cell(y, g);
    if (g < 7)
        return poisson_fits_wrapped(run, x, y, ix, iy);
    const st_i64 r2 = run->r2;
    const size_t row = 2 * (size_t)run->pitch;
    const st_i32 *c0 = run->cells + 2 * ((size_t)(iy + 2) * run->pitch + ix + 2);
    const st_i32 *n1 = c0 - row, *p1 = c0 + row, *n2 = n1 - row, *p2 = p1 + row;
    if (TOO_CLOSE(c0, 0) | TOO_CLOSE(c0, 1) | TOO_CLOSE(c0, -1) | TOO_CLOSE(p1, 0) |
        TOO_CLOSE(n1, 0))
        return 0;
    if (TOO_CLOSE(p1, 1) | TOO_CLOSE(p1, -1) | TOO_CLOSE(n1, 1) | TOO_CLOSE(n1, -1))
        return 0;
    return !(TOO_CLOSE(c0, 2) | TOO_CLOSE(c0, -2) | TOO_CLOSE(p2, 0) | TOO_CLOSE(n2, 0) |
             TOO_CLOSE(p1, 2) | TOO_CLOSE(p1, -2) | TOO_CLOSE(n1, 2) | TOO_CLOSE(n1, -2) |
             TOO_CLOSE(p2, 1) | TOO_CLOSE(p2, -1) | TOO_CLOSE(n2, 1) | TOO_CLOSE(n2, -1) |
             TOO_CLOSE(p2, 2) | TOO_CLOSE(p2, -2) | TOO_CLOSE(n2, 2) | TOO_CLOSE(n2, -2));
}
#undef TOO_CLOSE

static void poisson_store(poisson_run *run, st_i64 i, st_i64 j, st_i32 x, st_i32 y)
{
    st_i32 *c = run->cells + 2 * ((size_t)(j + 2) * run->pitch + (size_t)(i + 2));
    c[0] = x;
    c[1] = y;
}

/* Room for one more point in order[] and active[] (grown by half). */
static int poisson_reserve(poisson_run *run)
{
    if (run->count < run->capacity)
        return 1;
    st_u64 cap = run->capacity + run->capacity / 2 + 64;
    if (cap > (st_u64)run->g * run->g) /* at most one point per cell */
        cap = (st_u64)run->g * run->g;
    st_u32 *order = realloc(run->order, cap * sizeof *order);
    if (order)
        run->order = order;
    st_u32 *active = order ? realloc(run->active, cap * sizeof *active) : NULL;
    if (!order || !active) {
        run->failed = 1;
        return 0;
    }
    run->active = active;
    run->capacity = (st_u32)cap;
    return 1;
}

/* Stores a point in its cell and, for g >= 7, in the ghost cells across the
 * seams (coordinates shifted by one tile, 2^24). 0 when out of memory. */
static int poisson_insert(poisson_run *run, st_i32 x, st_i32 y)
{
    if (!poisson_reserve(run))
        return 0;
    st_i64 g = run->g, i = fix_cell(x, run->g), j = fix_cell(y, run->g);
    st_i64 gi = i < 2 ? i + g : (i >= g - 2 ? i - g : i); /* ghost column, or i */
    st_i64 gj = j < 2 ? j + g : (j >= g - 2 ? j - g : j);
    st_i32 gx = gi > i ? x + FIX_ONE : x - FIX_ONE; /* the copy's coordinates */
    st_i32 gy = gj > j ? y + FIX_ONE : y - FIX_ONE;
    poisson_store(run, i, j, x, y);
    if (g >= 7) {
        if (gi != i)
            poisson_store(run, gi, j, gx, y);
        if (gj != j)
            poisson_store(run, i, gj, x, gy);
        if (gi != i && gj != j)
            poisson_store(run, gi, gj, gx, gy);
    }
    st_u32 cell = (st_u32)((j + 2) * run->pitch + i + 2);
    run->order[run->count++] = cell;
    run->active[run->active_n++] = cell;
    return 1;
}

/* Draws an offset uniform (by area) in the annulus r <= |d| < 2r, as Bridson
 * asks, in units of 2^-24: radius r*sqrt(1 + 3u) inverts the area CDF
 * (rho^2 - r^2) / (3 r^2); angle 2*pi*v. One splitmix64 output gives u and v,
 * 32 bits each. cos/sin of the angle come from a 1024-entry table at the top
 * 10 bits of v and the angle-addition formula with cos d ~ 1 - d^2/2,
 * sin d ~ d for the rest (d < 2*pi/1024: error < d^3/6 = 4e-8 of the radius,
 * under one lattice step). Measured here, this is about 40% faster than
 * rejection from the square [-2r,2r)^2, whose 41% rejection branch the
 * predictor keeps losing, and than sinf/cosf. The offset is truncated to the
 * lattice; the fit test decides on that position. */
static void annulus_offset(const poisson_run *run, st_u64 *rng, st_i32 *dx, st_i32 *dy)
{
    st_u64 z = splitmix64(rng);
    double u = (double)(z & 0xffffffffu) * 0x1p-32;
    st_u32 v = (st_u32)(z >> 32);
    const double *cs = run->dirs[v >> 22];
    double d = (double)(v & 0x3fffffu) * (6.283185307179586 * 0x1p-32);
    double cd = 1.0 - 0.5 * d * d;
    double rho = run->r * 0x1p24 * sqrt(1.0 + 3.0 * u);
    *dx = (st_i32)(rho * (cs[0] * cd - cs[1] * d));
    *dy = (st_i32)(rho * (cs[1] * cd + cs[0] * d));
}

/* Runs Bridson's loop until the active list is empty (Bridson 2007, step 2).
 * 0 when out of memory. */
static int poisson_fill(poisson_run *run, st_u64 *rng)
{
    if (!poisson_insert(run, (st_i32)(splitmix64(rng) >> 40), (st_i32)(splitmix64(rng) >> 40)))
        return 0;
    while (run->active_n > 0) {
        st_u32 a = uniform_index(rng, run->active_n);
        const st_i32 *p = run->cells + 2 * (size_t)run->active[a];
        int placed = 0;
        for (st_u32 t = 0; t < ST_POISSON_K && !placed; ++t) {
            st_i32 dx, dy;
            annulus_offset(run, rng, &dx, &dy);
            st_i32 x = (p[0] + dx) & FIX_MASK, y = (p[1] + dy) & FIX_MASK; /* wrap */
            if (poisson_fits(run, x, y)) {
                if (!poisson_insert(run, x, y))
                    return 0;
                placed = 1;
            }
        }
        if (!placed) /* k failures: retire the point (swap with the last) */
            run->active[a] = run->active[--run->active_n];
    }
    return 1;
}

/* The run's points as floats in generation order (exact: k * 2^-24). */
static float *poisson_points(const poisson_run *run)
{
    float *out = malloc(2 * (size_t)run->count * sizeof *out);
    for (st_u32 i = 0; out && i < run->count; ++i) {
        const st_i32 *c = run->cells + 2 * (size_t)run->order[i];
        out[2 * i] = (float)c[0] * 0x1p-24f;
        out[2 * i + 1] = (float)c[1] * 0x1p-24f;
    }
    return out;
}

/* One complete run at radius r (rounded to a float); on success *points holds
 * its tile (malloc'ed) and *count, *used_r its size and exact radius. */
static st_status poisson_run_at(double r, st_u32 seed, float **points, st_u32 *count,
                                float *used_r, st_error *err)
{
    static const poisson_run zero;
    poisson_run *run = malloc(sizeof *run); /* 16 KiB of direction table: not on the stack */
    if (!run)
        return st_fail(err, ST_ERR_NOMEM, "poisson tile: out of memory");
    *run = zero;
    run->r = (float)r;
    run->r2 = (st_i64)ceil(run->r * run->r * 0x1p48);
    run->g = (st_u32)floor(1.4142135623730951 / run->r) + 1u; /* 1/g < r/sqrt(2) */
    run->pitch = run->g + 4;
    for (int i = 0; i < 1024; ++i) {
        run->dirs[i][0] = cos(6.283185307179586 * i / 1024.0);
        run->dirs[i][1] = sin(6.283185307179586 * i / 1024.0);
    }
    size_t padded = (size_t)run->pitch * run->pitch;
    st_status status = ST_OK;
    run->cells = malloc(2 * padded * sizeof *run->cells);
    if (run->cells) {
        for (size_t i = 0; i < 2 * padded; ++i)
            run->cells[i] = FIX_EMPTY;
        st_u64 rng = 0x504f4953534f4e00ull ^ (st_u64)seed; /* "POISSON" domain */
        if (poisson_fill(run, &rng) && (*points = poisson_points(run)) != NULL) {
            *count = run->count;
            *used_r = (float)run->r;
        } else {
            status = ST_ERR_NOMEM;
        }
    } else {
        status = ST_ERR_NOMEM;
    }
    if (status != ST_OK)
        st_fail(err, status, "poisson tile: out of memory for a %u x %u grid", run->g, run->g);
    free(run->cells);
    free(run->order);
    free(run->active);
    free(run);
    return status;
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
     * radius that gives the target is r * sqrt(count / target). Up to 7 runs
     * until within 1% (or one point); the closest is kept. */
    double r = sqrt(ST_POISSON_PACKING / target_count);
    float *best = NULL, best_r = 0.0f;
    st_u32 best_n = 0;
    double best_miss = INFINITY;
    double tolerance = 0.01 * target_count > 1.0 ? 0.01 * target_count : 1.0;
    for (int it = 0; it < 7 && best_miss > tolerance; ++it) {
        float *pts = NULL, used_r = 0.0f;
        st_u32 n = 0;
        if (poisson_run_at(r, seed, &pts, &n, &used_r, err) != ST_OK) {
            free(best);
            return err ? err->status : ST_ERR_NOMEM;
        }
        double miss = fabs((double)n - target_count);
        if (miss < best_miss) {
            free(best);
            best = pts;
            best_n = n;
            best_r = used_r;
            best_miss = miss;
        } else {
            free(pts);
        }
        r *= sqrt((double)n / target_count);
    }
    *points = best;
    *count = best_n;
    if (radius)
        *radius = best_r; /* exact: every pair is at least this far apart */
    return ST_OK;
}

