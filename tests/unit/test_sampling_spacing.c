/* test_sampling_spacing.c — guards st_min_distance_2d (src/sampling/spacing.c), the smallest
 * distance between two points that `strata pattern --discrepancy` reports.
 *
 * Independent checks: against every pair compared here (plain and on the
 * torus) for random sets of many sizes, clustered sets (where the grid
 * search cannot decide and must fall back) and sets with duplicates; exact
 * values for lattices (a k x k grid of cell centres: 1/k both ways; 3 x 3
 * points 0.5 apart, which only the fallback sees; two points at 0.05 and
 * 0.95: 0.9 plain, 0.1 on the torus). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>

#include "st_sampling.h"

static double brute(const float *p, st_u32 n, int torus)
{
    double best = INFINITY;
    for (st_u32 i = 0; i < n; i++)
        for (st_u32 j = i + 1; j < n; j++) {
            double dx = fabs((double)p[2 * i] - p[2 * j]), dy = fabs((double)p[2 * i + 1] - p[2 * j + 1]);
            if (torus) {
                dx = fmin(dx, 1.0 - dx);
                dy = fmin(dy, 1.0 - dy);
            }
            best = fmin(best, sqrt(dx * dx + dy * dy));
        }
    return best;
}

/* xorshift32 in [0, 1): a stream of this test's own. */
static float unit(st_u32 *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return (float)(*s >> 8) * 0x1p-24f;
}

static void min_distance_equals_every_pair(void **state)
{
    (void)state;
    st_u32 seed = 12345u;
    const st_u32 sizes[] = {2, 3, 8, 9, 10, 50, 257, 1000, 3000};
    float *p = malloc(sizeof(float) * 2 * 3000);
    for (size_t t = 0; t < sizeof sizes / sizeof *sizes; t++)
        for (int kind = 0; kind < 3; kind++) {
            st_u32 n = sizes[t];
            for (st_u32 i = 0; i < 2 * n; i++) {
                float u = unit(&seed);
                /* 0: uniform; 1: all in a corner 1/20 wide; 2: 0.02 apart on a
                 * diagonal (no two in one cell of the grid's neighbourhood) */
                p[i] = kind == 0 ? u : kind == 1 ? 0.95f + 0.05f * u : (float)(i / 2) / n;
            }
            if (kind == 0 && n > 3)
                p[2 * (n - 1)] = p[0], p[2 * (n - 1) + 1] = p[1]; /* a duplicate: 0 */
            for (int torus = 0; torus < 2; torus++) {
                double got = st_min_distance_2d(p, n, torus), want = brute(p, n, torus);
                if (!(got == want))
                    fail_msg("n %u kind %d torus %d: %.9g, every pair %.9g", n, kind, torus, got,
                             want);
            }
        }
    free(p);
}

static void min_distance_of_lattices(void **state)
{
    (void)state;
    float *p = malloc(sizeof(float) * 2 * 64 * 64);
    for (st_u32 k = 3; k <= 64; k *= 2) {
        for (st_u32 i = 0; i < k * k; i++) {
            p[2 * i] = ((float)(i % k) + 0.5f) / (float)k;
            p[2 * i + 1] = ((float)(i / k) + 0.5f) / (float)k;
        }
        assert_true(fabs(st_min_distance_2d(p, k * k, 0) - 1.0 / k) < 1e-6);
        assert_true(fabs(st_min_distance_2d(p, k * k, 1) - 1.0 / k) < 1e-6);
    }
    /* 3 x 3 points 0.5 apart, corners included: farther apart than the
     * grid's cell (1/3), so only the fallback finds 0.5; on the torus x = 1
     * is x = 0 */
    float sparse[18];
    for (int i = 0; i < 9; i++) {
        sparse[2 * i] = 0.5f * (float)(i % 3);
        sparse[2 * i + 1] = 0.5f * (float)(i / 3);
    }
    assert_true(st_min_distance_2d(sparse, 9, 0) == 0.5);
    assert_true(st_min_distance_2d(sparse, 9, 1) == 0.0);
    float two[4] = {0.05f, 0.5f, 0.95f, 0.5f};
    assert_true(fabs(st_min_distance_2d(two, 2, 0) - 0.9) < 1e-6);
    assert_true(fabs(st_min_distance_2d(two, 2, 1) - 0.1) < 1e-6);
    assert_true(isnan(st_min_distance_2d(two, 1, 0)));
    assert_true(isnan(st_min_distance_2d(NULL, 2, 0)));
    free(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(min_distance_equals_every_pair),
        cmocka_unit_test(min_distance_of_lattices),
    };
    return cmocka_run_group_tests_name("spacing", tests, NULL, NULL);
}
