/* spacing.c — the smallest distance between two points of a 2-D pattern
 * (st_sampling.h: st_min_distance_2d), the measure of blue-noise patterns
 * Mitchell (1991) and the lecture compare: best-candidate and Poisson disk
 * keep it near the spacing of a hexagonal lattice, random points let it fall
 * towards 0 as N grows.
 *
 * A grid of g x g cells of width 1/g: the nearest pair is searched among
 * the points of each cell and its 8 neighbours, which finds it whenever it
 * is at most one cell width apart; a larger answer (few points, or all in a
 * corner) falls back to comparing every pair, so the result is always the
 * brute-force minimum. */
#include "st_sampling.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

/* Squared distance, per axis the shorter way round the unit torus if torus. */
static double pair_d2(const float *a, const float *b, int torus)
{
    double dx = fabs((double)a[0] - b[0]), dy = fabs((double)a[1] - b[1]);
    if (torus) {
        dx = dx > 0.5 ? 1.0 - dx : dx;
        dy = dy > 0.5 ? 1.0 - dy : dy;
    }
    return dx * dx + dy * dy;
}

static double brute_force_d2(const float *pts, st_u32 n, int torus)
{
    double best = INFINITY;
    for (st_u32 i = 0; i < n; i++)
        for (st_u32 j = i + 1; j < n; j++) {
            double d2 = pair_d2(pts + 2 * i, pts + 2 * j, torus);
            best = d2 < best ? d2 : best;
        }
    return best;
}

static st_u32 cell_index(float v, st_u32 g)
{
    double c = floor((double)v * g);
    return c < 0.0 ? 0u : c >= g ? g - 1u : (st_u32)c;
}

/* The grid's search: the least squared distance between a point and the
 * points of its own and the 8 neighbouring cells (wrapped on the torus),
 * head/next chaining the points of each cell. */
static double grid_d2(const float *pts, st_u32 n, int torus, st_u32 g, const st_u32 *head,
                      const st_u32 *next, const st_u32 *cell)
{
    double best = INFINITY;
    for (st_u32 i = 0; i < n; i++) {
        st_i64 cx = cell[i] % g, cy = cell[i] / g;
        for (st_i64 dy = -1; dy <= 1; dy++)
            for (st_i64 dx = -1; dx <= 1; dx++) {
                st_i64 x = cx + dx, y = cy + dy;
                if (torus) {
                    x = (x + g) % g;
                    y = (y + g) % g;
                } else if (x < 0 || y < 0 || x >= g || y >= g) {
                    continue;
                }
                for (st_u32 j = head[y * g + x]; j != UINT32_MAX; j = next[j])
                    if (j > i) {
                        double d2 = pair_d2(pts + 2 * i, pts + 2 * j, torus);
                        best = d2 < best ? d2 : best;
                    }
            }
    }
    return best;
}

double st_min_distance_2d(const float *pts, st_u32 n, int torus)
{
    if (!pts || n < 2)
        return NAN;
    /* about one point per cell; three cells a side at least, so that the
     * 3 x 3 neighbourhood on the torus holds no cell twice */
    st_u32 g = (st_u32)sqrt((double)n);
    if (g < 3)
        return sqrt(brute_force_d2(pts, n, torus));
    st_u32 *head = malloc(sizeof(st_u32) * (size_t)g * g);
    st_u32 *next = malloc(sizeof(st_u32) * (size_t)n), *cell = malloc(sizeof(st_u32) * (size_t)n);
    double best = NAN;
    if (head && next && cell) {
        for (size_t c = 0; c < (size_t)g * g; c++)
            head[c] = UINT32_MAX;
        for (st_u32 i = 0; i < n; i++) {
            cell[i] = cell_index(pts[2 * i + 1], g) * g + cell_index(pts[2 * i], g);
            next[i] = head[cell[i]];
            head[cell[i]] = i;
        }
        best = grid_d2(pts, n, torus, g, head, next, cell);
        /* a pair farther apart than a cell may have a nearer one two cells away */
        if (!(best <= 1.0 / ((double)g * g)))
            best = brute_force_d2(pts, n, torus);
        best = sqrt(best);
    }
    free(head);
    free(next);
    free(cell);
    return best;
}
