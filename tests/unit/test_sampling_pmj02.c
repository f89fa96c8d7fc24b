/* test_sampling_pmj02.c — guards the pmj02 sampler: its tables (src/sampling/pmj02.c,
 * st_sampling_pmj02) and the values st_sample_dim (kernels/sample/samplers.h) reads
 * from them, which the kernels and `strata pattern` share.
 *
 * Independent check, from the definition of a (0,m,2)-net: a point set of
 * 2^m points in [0,1)^2 is one when every elementary interval
 * [a 2^-i, (a+1) 2^-i) x [b 2^-(m-i), (b+1) 2^-(m-i)), of every shape
 * i = 0..m, holds exactly one point. The intervals are found from the
 * points' values (floor of x 2^i in double, exact for these floats and
 * 32-bit fractions) and counted, not taken from the generator's indexing. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "st_shared.h"
#include "rng.h"
#include "samplers.h"
#include "st_sampling.h"

/* 1 when the n = 2^m points (x, y) at xy[stride k], xy[stride k + 1] are a
 * (0,m,2)-net; otherwise names the first overfull interval in *why. */
static int is_net(const double *xy, st_u32 m, char *why, size_t len)
{
    size_t n = (size_t)1 << m;
    unsigned *count = malloc(n * sizeof *count);
    assert_non_null(count);
    for (st_u32 i = 0; i <= m; i++) {
        memset(count, 0, n * sizeof *count);
        for (size_t k = 0; k < n; k++) {
            size_t a = (size_t)floor(xy[2 * k] * ldexp(1.0, (int)i));
            size_t b = (size_t)floor(xy[2 * k + 1] * ldexp(1.0, (int)(m - i)));
            size_t cell = (a << (m - i)) + b;
            if (a >= ((size_t)1 << i) || b >= ((size_t)1 << (m - i)) || ++count[cell] > 1) {
                snprintf(why, len, "2^%u points: interval (%zu, %zu) of shape 2^-%u x 2^-%u "
                         "holds two (point %zu)", m, a, b, i, m - i, k);
                free(count);
                return 0;
            }
        }
    }
    free(count);
    return 1; /* 2^m points in 2^m intervals per shape, none holding two */
}

static st_u32 *tables(st_u32 log2n, st_u32 sets, st_u32 seed)
{
    st_u32 *t = NULL;
    st_error err = {0};
    if (st_sampling_pmj02(log2n, sets, seed, &t, &err) != ST_OK)
        fail_msg("%s", err.msg);
    return t;
}

/* Every 2^m prefix (m = 0..log2n) of every set is a (0,m,2)-net, for
 * several seeds: all ST_PMJ02_SETS sets at 2^10, two at the full 2^12. */
static void every_prefix_is_a_net(void **state)
{
    (void)state;
    const st_u32 seeds[] = {0, 1, 7, 123456789};
    for (size_t q = 0; q < 4; q++)
        for (st_u32 log2n = 10; log2n <= ST_PMJ02_MAX_LOG2; log2n += ST_PMJ02_MAX_LOG2 - 10) {
            st_u32 sets = log2n == 10 ? ST_PMJ02_SETS : 2u, n = 1u << log2n;
            st_u32 *t = tables(log2n, sets, seeds[q]);
            double *xy = malloc(2 * sizeof *xy * n);
            assert_non_null(xy);
            for (st_u32 set = 0; set < sets; set++) {
                for (st_u32 k = 0; k < 2 * n; k++)
                    xy[k] = ldexp((double)t[2 * (size_t)set * n + k], -32);
                for (st_u32 m = 0; m <= log2n; m++) {
                    char why[160];
                    if (!is_net(xy, m, why, sizeof why))
                        fail_msg("seed %u set %u: %s", seeds[q], set, why);
                }
            }
            free(xy);
            free(t);
        }
}

/* The same seed gives the same tables; a shorter table is the prefix of a
 * longer one; another seed or another set gives other points. */
static void tables_deterministic_and_progressive(void **state)
{
    (void)state;
    st_u32 *a = tables(9, 4, 5), *b = tables(9, 4, 5), *c = tables(6, 4, 5), *d = tables(9, 4, 6);
    assert_memory_equal(a, b, sizeof(st_u32) * 2 * 4 * 512);
    for (st_u32 set = 0; set < 4; set++)
        assert_memory_equal(a + 2 * 512 * set, c + 2 * 64 * set, sizeof(st_u32) * 2 * 64);
    assert_memory_not_equal(a, d, sizeof(st_u32) * 2 * 512);
    assert_memory_not_equal(a, a + 2 * 512, sizeof(st_u32) * 2 * 512);
    free(a);
    free(b);
    free(c);
    free(d);
}

static void bad_arguments_refused(void **state)
{
    (void)state;
    st_u32 *t = (st_u32 *)&t;
    st_error err = {0};
    assert_int_equal(st_sampling_pmj02(ST_PMJ02_MAX_LOG2 + 1, 1, 0, &t, &err), ST_ERR_USAGE);
    assert_null(t);
    assert_int_equal(st_sampling_pmj02(4, 0, 0, &t, &err), ST_ERR_USAGE);
    assert_int_equal(st_sampling_pmj02(4, ST_PMJ02_SETS + 1, 0, &t, &err), ST_ERR_USAGE);
    assert_int_equal(st_sampling_pmj02(4, 1, 0, NULL, &err), ST_ERR_USAGE);
    /* the renderer's limit: spp up to the table size */
    assert_int_equal(st_sampler_check(ST_SAMPLER_PMJ02, 64, 64, 1u << ST_PMJ02_MAX_LOG2, &err),
                     ST_OK);
    assert_int_equal(st_sampler_check(ST_SAMPLER_PMJ02, 64, 64, (1u << ST_PMJ02_MAX_LOG2) + 1,
                                      &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "pmj02"));
}

/* Mean toroidal nearest-neighbour distance x sqrt(n) of the n points of one
 * set (32-bit fractions), by comparing every pair. */
static double mean_nearest(const st_u32 *w, st_u32 n)
{
    double total = 0;
    for (st_u32 i = 0; i < n; i++) {
        double best = INFINITY;
        for (st_u32 j = 0; j < n; j++) {
            if (j == i)
                continue;
            double dx = fabs(ldexp((double)w[2 * i] - w[2 * j], -32));
            double dy = fabs(ldexp((double)w[2 * i + 1] - w[2 * j + 1], -32));
            dx = fmin(dx, 1 - dx);
            dy = fmin(dy, 1 - dy);
            best = fmin(best, dx * dx + dy * dy);
        }
        total += sqrt(best);
    }
    return total / n * sqrt((double)n);
}

/* pmj02bn (st_sampling_pmj02bn): every 2^m prefix of every set is still a
 * (0,m,2)-net, and choosing the farthest of the free candidates spreads the
 * points: over 16 sets, the mean nearest-neighbour distance x sqrt(n) is
 * above pmj02's at each of 4..64 points, by 0.03 on average (measured, two
 * seeds: +0.05..+0.24 at 4 and 8 points, +0.02..+0.08 at 16..64; the gap
 * closes towards 256 points, where the net leaves few free cells to choose
 * from). */
static void pmj02bn_nets_and_spread(void **state)
{
    (void)state;
    st_u32 *bn = NULL, *plain = tables(10, ST_PMJ02_SETS, 3);
    st_error err = {0};
    if (st_sampling_pmj02bn(10, ST_PMJ02_SETS, 3, &bn, &err) != ST_OK)
        fail_msg("%s", err.msg);
    st_u32 n = 1u << 10;
    double *xy = malloc(2 * sizeof *xy * n);
    assert_non_null(xy);
    for (st_u32 set = 0; set < ST_PMJ02_SETS; set++) {
        for (st_u32 k = 0; k < 2 * n; k++)
            xy[k] = ldexp((double)bn[2 * (size_t)set * n + k], -32);
        for (st_u32 m = 0; m <= 10; m++) {
            char why[160];
            if (!is_net(xy, m, why, sizeof why))
                fail_msg("pmj02bn set %u: %s", set, why);
        }
    }
    free(xy);
    double gain = 0;
    for (st_u32 m = 2; m <= 6; m++) {
        double a = 0, b = 0;
        for (st_u32 set = 0; set < ST_PMJ02_SETS; set++) { /* a 2^m prefix of each set */
            st_u32 *pb = malloc(sizeof(st_u32) * 2 << m), *pp = malloc(sizeof(st_u32) * 2 << m);
            assert_true(pb && pp);
            memcpy(pb, bn + 2 * (size_t)set * n, sizeof(st_u32) * 2 << m);
            memcpy(pp, plain + 2 * (size_t)set * n, sizeof(st_u32) * 2 << m);
            b += mean_nearest(pb, 1u << m) / ST_PMJ02_SETS;
            a += mean_nearest(pp, 1u << m) / ST_PMJ02_SETS;
            free(pb);
            free(pp);
        }
        printf("# %u points: mean nearest x sqrt(n) pmj02 %.3f, pmj02bn %.3f\n", 1u << m, a, b);
        if (!(b > a))
            fail_msg("%u points: pmj02bn %.3f not above pmj02 %.3f", 1u << m, b, a);
        gain += (b - a) / 5;
    }
    if (!(gain >= 0.03))
        fail_msg("pmj02bn above pmj02 by %.3f on average, not 0.03", gain);
    free(bn);
    free(plain);
    assert_int_equal(st_sampler_lookup("pmj02bn"), ST_SAMPLER_PMJ02BN);
    assert_int_equal(st_sampler_check(ST_SAMPLER_PMJ02BN, 64, 64, (1u << ST_PMJ02_MAX_LOG2) + 1,
                                      &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "pmj02bn"));
}

/* What the renderer reads (st_sample_dim with the tables, as generate.cl and
 * shade.cl call it): in every pixel, for spp = 2^m, the spp samples of the
 * pixel pair and of the next two pairs are each a (0,m,2)-net; pixels that
 * share a set still get different points. */
static void renderer_pairs_are_nets(void **state)
{
    (void)state;
    for (st_u32 m = 0; m <= 8; m += 2) {
        st_u32 spp = 1u << m;
        st_params p;
        memset(&p, 0, sizeof p);
        p.width = 5;
        p.height = 4;
        p.spp = spp;
        p.seed = 9;
        p.sampler = ST_SAMPLER_PMJ02;
        st_sampler_prepare(&p);
        st_u32 *t = tables(m, ST_PMJ02_SETS, p.seed);
        double *xy = malloc(2 * sizeof *xy * spp);
        assert_non_null(xy);
        float first[20];
        for (st_u32 pixel = 0; pixel < 20; pixel++)
            for (st_u32 pair = 0; pair < 3; pair++) {
                for (st_u32 s = 0; s < spp; s++) {
                    st_sample_id id = st_sample_begin(&p, pixel % 5, pixel / 5, s);
                    id.pmj02 = t;
                    xy[2 * s] = st_sample_dim(&p, &id, 2 * pair);
                    xy[2 * s + 1] = st_sample_dim(&p, &id, 2 * pair + 1);
                }
                char why[160];
                if (!is_net(xy, m, why, sizeof why))
                    fail_msg("spp %u pixel %u pair %u: %s", spp, pixel, pair, why);
                if (pair == 0)
                    first[pixel] = (float)xy[0];
            }
        for (st_u32 pixel = 1; pixel < 20; pixel++)
            for (st_u32 o = 0; o < pixel; o++)
                if (first[pixel] == first[o])
                    fail_msg("spp %u: pixels %u and %u start at the same x", spp, o, pixel);
        free(xy);
        free(t);
    }
}

/* pmj02bn's pixel dimensions as the renderer reads them (st_sample_dim
 * with st_sampling_pmj02bn_tables, as pbrt-v4 sorts its tile): for spp =
 * 2^m (m = 0..12) and each pixel of a 70 x 3 strip (past the largest
 * tile, 64 pixels across, so the tile repeats), every 2^k prefix (k <= m) of
 * the pixel's samples is a (0,k,2)-net, read unrotated: the same points
 * wherever the tile repeats. Before, each pixel's samples were rotated on
 * the torus and prefixes of 4 or more points were not nets. */
static void pmj02bn_pixel_prefixes_are_nets(void **state)
{
    (void)state;
    for (st_u32 m = 0; m <= 12; m++) {
        st_u32 spp = 1u << m, log2t = (12u - ((m + 1u) & ~1u)) / 2u, side = 1u << log2t;
        st_params p;
        memset(&p, 0, sizeof p);
        p.width = 70;
        p.height = 3;
        p.spp = spp;
        p.seed = 5;
        p.sampler = ST_SAMPLER_PMJ02BN;
        st_sampler_prepare(&p);
        st_u32 *t = NULL;
        size_t words = 0;
        st_error err = {0};
        if (st_sampling_pmj02bn_tables(spp, p.seed, &t, &words, &err) != ST_OK)
            fail_msg("%s", err.msg);
        double *xy = malloc(2 * sizeof *xy * spp);
        assert_non_null(xy);
        st_u32 pixels = m >= 8 ? 3u : 70u * 3u; /* the large counts: a few pixels */
        for (st_u32 pixel = 0; pixel < pixels; pixel++) {
            st_u32 x = pixel % 70, y = pixel / 70;
            for (st_u32 s = 0; s < spp; s++) {
                st_sample_id id = st_sample_begin(&p, x, y, s);
                id.pmj02 = t;
                xy[2 * s] = st_sample_dim(&p, &id, 0);
                xy[2 * s + 1] = st_sample_dim(&p, &id, 1);
            }
            for (st_u32 k = 0; k <= m; k++) {
                char why[160];
                if (!is_net(xy, k, why, sizeof why))
                    fail_msg("spp %u pixel (%u, %u), prefix %u: %s", spp, x, y, 1u << k, why);
            }
            for (st_u32 s = 0; x >= side && s < spp; s++) { /* the tile repeats, unrotated */
                st_sample_id same = st_sample_begin(&p, x % side, y, s);
                same.pmj02 = t;
                assert_true(xy[2 * s] == st_sample_dim(&p, &same, 0));
            }
        }
        free(xy);
        free(t);
    }
}

/* `strata pattern --sampler pmj02` shows the renderer's pixel dimensions:
 * st_sampling_pattern's points are st_sample_dim's at pixel (0, 0), read from
 * the tables the renderer makes for spp = count (render.c: ST_PMJ02_SETS
 * sets of 2^ceil(log2 spp) points from the seed); 1024 points: a net. */
static void pattern_shows_the_renderer_points(void **state)
{
    (void)state;
    const st_u32 counts[] = {1024, 100};
    for (int c = 0; c < 2; c++) {
        st_u32 n = 0, count = counts[c], log2n = count == 1024 ? 10u : 7u;
        float *pts = NULL;
        st_error err = {0};
        if (st_sampling_pattern(ST_SAMPLER_PMJ02, count, 4, 3, 1, &pts, &n, &err) != ST_OK)
            fail_msg("%s", err.msg);
        assert_int_equal(n, count);
        st_params p;
        memset(&p, 0, sizeof p);
        p.width = p.height = 1;
        p.spp = count;
        p.seed = 3;
        p.sampler = ST_SAMPLER_PMJ02;
        st_sampler_prepare(&p);
        st_u32 *t = tables(log2n, ST_PMJ02_SETS, 3);
        double *xy = malloc(2 * sizeof *xy * count);
        assert_non_null(xy);
        for (st_u32 s = 0; s < count; s++) {
            st_sample_id id = st_sample_begin(&p, 0, 0, s);
            id.pmj02 = t;
            for (st_u32 d = 0; d < 4; d++)
                if (pts[4 * s + d] != st_sample_dim(&p, &id, d))
                    fail_msg("count %u point %u dim %u: pattern %a, renderer %a", count, s, d,
                             (double)pts[4 * s + d], (double)st_sample_dim(&p, &id, d));
            xy[2 * s] = pts[4 * s];
            xy[2 * s + 1] = pts[4 * s + 1];
        }
        char why[160];
        if (count == 1024 && !is_net(xy, 10, why, sizeof why))
            fail_msg("pattern: %s", why);
        free(xy);
        free(t);
        free(pts);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(every_prefix_is_a_net),
        cmocka_unit_test(pmj02bn_nets_and_spread),
        cmocka_unit_test(tables_deterministic_and_progressive),
        cmocka_unit_test(bad_arguments_refused),
        cmocka_unit_test(renderer_pairs_are_nets),
        cmocka_unit_test(pmj02bn_pixel_prefixes_are_nets),
        cmocka_unit_test(pattern_shows_the_renderer_points),
    };
    return cmocka_run_group_tests_name("pmj02", tests, NULL, NULL);
}
