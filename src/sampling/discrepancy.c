/* discrepancy.c — how uniformly a point set covers the unit cube: the exact
 * star discrepancy in 2-D and the L2-star discrepancy in any dimension.
 *
 * Spec: the lecture's definition, D_N = sup over origin-anchored boxes
 * B = [0,a) x [0,b) of |#{x_i in B}/N - area(B)| (closed boxes as limits).
 * Invariant: both functions read the points only; counts are exact integers
 * and every box the sup can be attained at is visited, so the result is exact
 * up to double rounding of a*b - count/N. Tests: tests/unit/test_sampling_point_sets.c
 * star_discrepancy_*, l2_star_*. */
#include "st_sampling.h"

#include <math.h>
#include <stdlib.h>

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* Index of v in the sorted distinct values u[0..m) (v is present). */
static st_u32 rank_of(const float *u, st_u32 m, float v)
{
    st_u32 lo = 0, hi = m;
    while (hi - lo > 1) {
        st_u32 mid = lo + (hi - lo) / 2;
        if (u[mid] <= v)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

typedef struct point_rank {
    float x;
    st_u32 ry; /* rank of y among the distinct y values */
} point_rank;

static int cmp_point_rank(const void *a, const void *b)
{
    return cmp_float(&((const point_rank *)a)->x, &((const point_rank *)b)->x);
}

/* One sweep step at a = x-value `a`. hist[r] counts points with x < a (open)
 * or x <= a (closed) and y of rank r; u[0..m) are the distinct y values, and
 * u[m] = 1 closes the list. Deficit a*b - #open/N over b in u[0..m];
 * excess #closed/N - a*b over b in u[0..m). */
static double sweep_deficit(const st_u32 *hist, const float *u, st_u32 m, double a, double n)
{
    double worst = 0.0, below = 0.0; /* points with y < u[r] */
    for (st_u32 r = 0; r <= m; ++r) {
        double d = a * u[r] - below / n;
        if (d > worst)
            worst = d;
        if (r < m)
            below += hist[r];
    }
    return worst;
}

static double sweep_excess(const st_u32 *hist, const float *u, st_u32 m, double a, double n)
{
    double worst = 0.0, upto = 0.0; /* points with y <= u[r] */
    for (st_u32 r = 0; r < m; ++r) {
        upto += hist[r];
        double d = upto / n - a * u[r];
        if (d > worst)
            worst = d;
    }
    return worst;
}

/* Exact D*_N in 2-D by a sweep over x (see st_sampling.h for the critical
 * boxes). Sorting is O(N log N); each of the <= N+1 sweep positions scans the
 * <= N+1 y values, so O(N^2) in all: about 17 M steps for N = 4096. */
double st_star_discrepancy_2d(const float *pts, st_u32 n)
{
    if (!pts || n == 0)
        return NAN;
    point_rank *p = malloc((size_t)n * sizeof *p);
    float *u = malloc(((size_t)n + 1) * sizeof *u);
    st_u32 *hist = calloc((size_t)n + 1, sizeof *hist);
    double result = NAN;
    if (!p || !u || !hist)
        goto done;

    for (st_u32 i = 0; i < n; ++i)
        u[i] = pts[2 * i + 1];
    qsort(u, n, sizeof *u, cmp_float);
    st_u32 m = 0; /* distinct y values */
    for (st_u32 i = 0; i < n; ++i)
        if (m == 0 || u[i] != u[m - 1])
            u[m++] = u[i];
    u[m] = 1.0f;
    for (st_u32 i = 0; i < n; ++i) {
        p[i].x = pts[2 * i];
        p[i].ry = rank_of(u, m, pts[2 * i + 1]);
    }
    qsort(p, n, sizeof *p, cmp_point_rank);

    double worst = 0.0, dn = n;
    for (st_u32 i = 0; i < n;) {
        double a = p[i].x;
        double d = sweep_deficit(hist, u, m, a, dn); /* open: x < a */
        if (d > worst)
            worst = d;
        for (; i < n && p[i].x == (float)a; ++i) /* the whole group x == a */
            hist[p[i].ry]++;
        d = sweep_excess(hist, u, m, a, dn); /* closed: x <= a */
        if (d > worst)
            worst = d;
    }
    double d = sweep_deficit(hist, u, m, 1.0, dn); /* a = 1 */
    result = d > worst ? d : worst;
done:
    free(p);
    free(u);
    free(hist);
    return result;
}

/* Warnock's closed form of the L2-star discrepancy (see st_sampling.h). The
 * double sum is symmetric: the diagonal plus twice the upper triangle. */
double st_l2_star_discrepancy(const float *pts, st_u32 n, st_u32 dims)
{
    if (!pts || n == 0 || dims == 0)
        return NAN;
    double single = 0.0, pairs = 0.0;
    for (st_u32 i = 0; i < n; ++i) {
        const float *xi = pts + (size_t)i * dims;
        double prod = 1.0, diag = 1.0;
        for (st_u32 k = 0; k < dims; ++k) {
            prod *= 1.0 - (double)xi[k] * xi[k];
            diag *= 1.0 - (double)xi[k];
        }
        single += prod;
        double row = 0.0;
        for (st_u32 j = i + 1; j < n; ++j) {
            const float *xj = pts + (size_t)j * dims;
            double q = 1.0;
            for (st_u32 k = 0; k < dims; ++k)
                q *= 1.0 - (double)(xi[k] > xj[k] ? xi[k] : xj[k]);
            row += q;
        }
        pairs += diag + 2.0 * row;
    }
    double dn = n;
    double t2 = pow(3.0, -(double)dims) - pow(2.0, 1.0 - dims) / dn * single + pairs / (dn * dn);
    return sqrt(t2 > 0.0 ? t2 : 0.0); /* rounding can leave -1e-17 for tiny T */
}
