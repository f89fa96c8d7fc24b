/* pmj02.c — the point tables of the pmj02 sampler (st_sampling.h:
 * st_sampling_pmj02): progressive multi-jittered (0,2) sequences after
 * Christensen, Kensler and Kilpatrick, "Progressive Multi-Jittered Sample
 * Sequences", EGSR 2018, §5.
 *
 * A sequence grows by doubling. From N = 4^k points (one in each cell of a
 * 2^k x 2^k grid) each point s gets a partner N + s in the diagonally
 * opposite sub-quadrant of its cell; from N = 2 * 4^k points (two diagonal
 * sub-quadrants taken in every cell) the two points N + s and 3N/2 + s take
 * the remaining two sub-quadrants of point s's cell, in a random order.
 * Inside its sub-quadrant a new point must fall in an elementary interval of
 * the 2N-point prefix that no point holds yet, in every one of the shapes
 * 2^-i x 2^-(m-i) (2N = 2^m): then every power-of-two prefix is a
 * (0,m,2)-net. The paper throws random candidates until one fits; here
 * after PMJ_DARTS misses every free cell of the sub-quadrant at the finest
 * level is counted and one is drawn uniformly, and a level with no free
 * cell left for some point is thrown again (never seen at 2^12 points).
 *
 * pmj02bn (the paper's §6, pbrt-v4's "pmj02bn"): the same construction,
 * but a new point is the best of up to ST_PMJ02BN_CANDIDATES free darts of
 * its sub-quadrant, the one farthest (toroidally) from every point placed
 * so far: best-candidate within the net's constraints, so the sequence is
 * blue noise as well as a (0,2)-sequence. pmj02 takes the first free dart.
 * Its pixel dimensions come from one more sequence sorted into a tile of
 * pixels (st_sampling_pmj02bn_tables), as pbrt-v4's
 * GetSortedPMJ02BNPixelSamples sorts its 65536-point table: the 2^m prefix
 * of a sequence of T² S points holds 2^m / T² points in each pixel of the
 * tile, a (0,m - 2 log2 T, 2)-net of it (its elementary intervals are the
 * sequence's), so each pixel's points in sequence order are nets at every
 * power-of-two prefix, unrotated.
 *
 * Invariant: coordinates are 32-bit binary fractions (first digit in the
 * most significant bit), so the interval of a point is exact integer work
 * and a digit-wise xor (the sampler's per-pixel shift) keeps every net. */
#include "sampling_int.h"
#include "rng.h"
#include "samplers.h"

#include <stdlib.h>
#include <string.h>

#define PMJ_DARTS 256u
#define PMJ_LEVEL_TRIES 64u

typedef struct pmj_state {
    st_u32 *xy;         /* x, y of each point */
    unsigned char *occ; /* per shape i (rows of 2^log2n): intervals held at this level */
    st_u32 log2n;
    st_u64 rng;
    st_u32 candidates;  /* free darts compared per point: 1 (pmj02) or more (pmj02bn) */
    st_u32 *placed, nplaced; /* the points placed so far at this level, in order */
} pmj_state;

/* The top `bits` digits of v. */
static st_u32 pmj_top(st_u32 v, st_u32 bits)
{
    return bits ? v >> (32u - bits) : 0u;
}

/* Index of the interval of shape 2^-i x 2^-(m-i) holding (x, y), in row i. */
static size_t pmj_cell(const pmj_state *s, st_u32 x, st_u32 y, st_u32 i, st_u32 m)
{
    return ((size_t)i << s->log2n) + (((size_t)pmj_top(x, i) << (m - i)) | pmj_top(y, m - i));
}

static int pmj_is_free(const pmj_state *s, st_u32 x, st_u32 y, st_u32 m)
{
    for (st_u32 i = 0; i <= m; i++)
        if (s->occ[pmj_cell(s, x, y, i, m)])
            return 0;
    return 1;
}

static void pmj_set(pmj_state *s, st_u32 k, st_u32 x, st_u32 y, st_u32 m)
{
    s->xy[2 * k] = x;
    s->xy[2 * k + 1] = y;
    s->placed[s->nplaced++] = k;
    for (st_u32 i = 0; i <= m; i++)
        s->occ[pmj_cell(s, x, y, i, m)] = 1;
}

/* Distance per axis the shorter way round the torus of 32-bit fractions. */
static double pmj_axis(st_u32 a, st_u32 b)
{
    st_u32 d = a - b; /* mod 2^32 */
    return (double)(d < 0x80000000u ? d : 0u - d);
}

/* Squared toroidal distance (units 2^-32) from (x, y) to the nearest point
 * placed so far; the largest double when none is. */
static double pmj_nearest(const pmj_state *s, st_u32 x, st_u32 y)
{
    double best = 1.7976931348623157e308;
    for (st_u32 j = 0; j < s->nplaced; j++) {
        st_u32 k = s->placed[j];
        double dx = pmj_axis(x, s->xy[2 * k]), dy = pmj_axis(y, s->xy[2 * k + 1]);
        double d2 = dx * dx + dy * dy;
        best = d2 < best ? d2 : best;
    }
    return best;
}

/* Places point k in the box whose first `fix` digits of x and y are those of
 * bx, by, free at level m (prefix 2^m): of the first s->candidates free
 * darts (of PMJ_DARTS), the one farthest from the points placed so far (the
 * first wins ties); 0 when no free cell is left. */
static int pmj_place(pmj_state *s, st_u32 k, st_u32 bx, st_u32 by, st_u32 fix, st_u32 m)
{
    st_u32 low = 0xffffffffu >> fix, found = 0, best_x = 0, best_y = 0;
    double best = -1.0;
    for (st_u32 t = 0; t < PMJ_DARTS && found < s->candidates; t++) {
        st_u64 r = splitmix64(&s->rng);
        st_u32 x = bx | ((st_u32)r & low), y = by | ((st_u32)(r >> 32) & low);
        if (!pmj_is_free(s, x, y, m))
            continue;
        double d2 = s->candidates > 1u ? pmj_nearest(s, x, y) : 0.0;
        if (found++ == 0 || d2 > best) {
            best = d2;
            best_x = x;
            best_y = y;
        }
    }
    if (found) {
        pmj_set(s, k, best_x, best_y, m);
        return 1;
    }
    /* every cell of side 2^-m in the box; one free cell drawn uniformly
     * (reservoir sampling), then a uniform point inside it */
    st_u32 side = 1u << (m - fix), seen = 0, cx = 0, cy = 0;
    for (st_u32 a = 0; a < side; a++)
        for (st_u32 b = 0; b < side; b++) {
            st_u32 x = bx | (a << (32u - m)), y = by | (b << (32u - m));
            if (pmj_is_free(s, x, y, m) && (splitmix64(&s->rng) >> 32) * ++seen >> 32 == 0) {
                cx = x;
                cy = y;
            }
        }
    if (!seen)
        return 0;
    st_u64 r = splitmix64(&s->rng);
    st_u32 fine = m < 32u ? 0xffffffffu >> m : 0u;
    pmj_set(s, k, cx | ((st_u32)r & fine), cy | ((st_u32)(r >> 32) & fine), m);
    return 1;
}

/* Doubles the first 2^(m-1) points to 2^m; 0 when a point found no room. */
static int pmj_level(pmj_state *s, st_u32 m)
{
    st_u32 n = 1u << (m - 1u), k = (m - 1u) / 2u, fix = k + 1u;
    st_u32 flip = 0x80000000u >> k, keep = ~(0xffffffffu >> fix);
    memset(s->occ, 0, ((size_t)s->log2n + 1u) << s->log2n);
    s->nplaced = 0;
    for (st_u32 j = 0; j < n; j++)
        pmj_set(s, j, s->xy[2 * j], s->xy[2 * j + 1], m);
    if ((m - 1u) % 2u == 0u) { /* n = 4^k: the diagonally opposite sub-quadrant */
        for (st_u32 j = 0; j < n; j++)
            if (!pmj_place(s, n + j, (s->xy[2 * j] & keep) ^ flip, (s->xy[2 * j + 1] & keep) ^ flip,
                           fix, m))
                return 0;
        return 1;
    }
    for (st_u32 j = 0; j < n / 2u; j++) { /* n = 2 4^k: the two sub-quadrants left */
        st_u32 x = s->xy[2 * j] & keep, y = s->xy[2 * j + 1] & keep;
        st_u32 fx = (splitmix64(&s->rng) & 1u) ? flip : 0u, fy = flip ^ fx;
        if (!pmj_place(s, n + j, x ^ fx, y ^ fy, fix, m) ||
            !pmj_place(s, n + n / 2u + j, x ^ fy, y ^ fx, fix, m))
            return 0;
    }
    return 1;
}

/* One sequence of 2^log2n points into xy; its stream is (seed, set) alone,
 * and a level is thrown again on its own, so a longer table starts with the
 * same points. */
static st_status pmj_sequence(pmj_state *s, st_u32 seed, st_u32 set, st_error *err)
{
    s->rng = ((st_u64)seed << 32 | set) * 0x9e3779b97f4a7c15ull;
    st_u64 r = splitmix64(&s->rng);
    s->xy[0] = (st_u32)r;
    s->xy[1] = (st_u32)(r >> 32);
    for (st_u32 m = 1; m <= s->log2n; m++) {
        st_u32 tries = 0;
        while (!pmj_level(s, m))
            if (++tries == PMJ_LEVEL_TRIES)
                return st_fail(err, ST_ERR_CHECK, "pmj02: no (0,%u,2)-net extension found "
                               "for set %u of seed %u", m, set, seed);
    }
    return ST_OK;
}

/* Sets first .. first + sets - 1 of pmj02 (candidates 1) or pmj02bn. */
static st_status pmj_tables_from(st_u32 log2n, st_u32 first, st_u32 sets, st_u32 seed,
                                 st_u32 candidates, st_u32 **points, st_error *err)
{
    size_t n = (size_t)1 << log2n;
    pmj_state s = {0};
    s.log2n = log2n;
    s.candidates = candidates;
    s.xy = malloc(2 * n * sizeof *s.xy * sets);
    s.occ = malloc(((size_t)log2n + 1u) << log2n);
    s.placed = malloc(n * sizeof *s.placed);
    st_u32 *out = s.xy;
    if (!out || !s.occ || !s.placed) {
        free(out);
        free(s.occ);
        free(s.placed);
        return st_fail(err, ST_ERR_NOMEM, "pmj02: out of memory for %u sets of %zu points",
                       sets, n);
    }
    st_status rc = ST_OK;
    for (st_u32 set = 0; set < sets && rc == ST_OK; set++) {
        s.xy = out + 2 * n * set;
        rc = pmj_sequence(&s, seed, first + set, err);
    }
    free(s.occ);
    free(s.placed);
    if (rc != ST_OK) {
        free(out);
        return rc;
    }
    *points = out;
    return ST_OK;
}

/* The tables of pmj02 (candidates 1) or pmj02bn. */
static st_status pmj_tables(st_u32 log2n, st_u32 sets, st_u32 seed, st_u32 candidates,
                            st_u32 **points, st_error *err)
{
    if (points)
        *points = NULL;
    if (!points || log2n > ST_PMJ02_MAX_LOG2 || sets < 1u || sets > ST_PMJ02_SETS)
        return st_fail(err, ST_ERR_USAGE, "pmj02: 2^%u points x %u sets: need at most 2^%u "
                       "points and 1..%u sets", log2n, sets, ST_PMJ02_MAX_LOG2, ST_PMJ02_SETS);
    return pmj_tables_from(log2n, 0u, sets, seed, candidates, points, err);
}

st_status st_sampling_pmj02(st_u32 log2n, st_u32 sets, st_u32 seed, st_u32 **points,
                            st_error *err)
{
    return pmj_tables(log2n, sets, seed, 1u, points, err);
}

st_status st_sampling_pmj02bn(st_u32 log2n, st_u32 sets, st_u32 seed, st_u32 **points,
                              st_error *err)
{
    return pmj_tables(log2n, sets, seed, ST_PMJ02BN_CANDIDATES, points, err);
}

st_status st_sampling_pmj02bn_tables(st_u32 spp, st_u32 seed, st_u32 **points, size_t *words,
                                     st_error *err)
{
    if (points)
        *points = NULL;
    if (!points || !words || spp < 1u || spp > (1u << ST_PMJ02_MAX_LOG2))
        return st_fail(err, ST_ERR_USAGE, "pmj02bn: spp %u: need 1..%u", spp,
                       1u << ST_PMJ02_MAX_LOG2);
    st_u32 log2n = st_log2_ceil(spp), log2s = (log2n + 1u) & ~1u;
    st_u32 log2t = (ST_PMJ02_MAX_LOG2 - log2s) / 2u, tile = 1u << ST_PMJ02_MAX_LOG2;
    size_t sets = (size_t)ST_PMJ02_SETS << log2n;
    st_u32 *seq = NULL, *out = NULL, *filled = NULL;
    st_status rc = pmj_tables(log2n, ST_PMJ02_SETS, seed, ST_PMJ02BN_CANDIDATES, &out, err);
    /* the tile's sequence: stream ST_PMJ02_SETS of the seed, past the sets' */
    if (rc == ST_OK)
        rc = pmj_tables_from(ST_PMJ02_MAX_LOG2, ST_PMJ02_SETS, 1u, seed, ST_PMJ02BN_CANDIDATES,
                             &seq, err);
    st_u32 *all = rc == ST_OK ? realloc(out, 2 * sizeof *out * (sets + tile)) : NULL;
    filled = rc == ST_OK ? calloc((size_t)1 << (2u * log2t), sizeof *filled) : NULL;
    if (rc == ST_OK && (!all || !filled))
        rc = st_fail(err, ST_ERR_NOMEM, "pmj02bn: out of memory for the pixel tile");
    if (all)
        out = all;
    for (st_u32 j = 0; rc == ST_OK && j < tile; j++) {
        st_u32 x = seq[2 * j], y = seq[2 * j + 1];
        size_t px = log2t ? x >> (32u - log2t) : 0u, py = log2t ? y >> (32u - log2t) : 0u;
        size_t cell = (py << log2t) + px, at = sets + (cell << log2s) + filled[cell]++;
        out[2 * at] = x << log2t; /* the fraction of the pixel */
        out[2 * at + 1] = y << log2t;
    }
    free(seq);
    free(filled);
    if (rc != ST_OK) {
        free(out);
        return rc;
    }
    *points = out;
    *words = 2 * (sets + tile);
    return ST_OK;
}
