/* test_sampling_point_sets.c — guards the host side of the sampling module
 * (src/sampling/poisson_disk.c, src/sampling/best_candidate.c, src/sampling/discrepancy.c, src/sampling/spectrum.c).
 *
 * Expected values are derived independently of the code under test: minimum
 * distances by brute force over the 9 periodic images of the tile (not the
 * min-image formula the generator uses), best-candidate by a brute-force
 * re-implementation of Mitchell's definition, star discrepancy by counting
 * points in explicit open boxes and by the closed forms quoted in the brief,
 * L2-star by exact piecewise integration of its defining integral and by the
 * midpoint rule, the periodogram by sin/cos per term. Every tolerance is
 * stated where it is used. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "st_sampling.h"

/* ---- helpers ------------------------------------------------------------- */

/* cmocka 1.1's assert_float_equal compares floats; these checks need doubles. */
#define assert_near(a, b, tol) assert_near_at((a), (b), (tol), __FILE__, __LINE__)
static void assert_near_at(double a, double b, double tol, const char *file, int line)
{
    if (!(fabs(a - b) <= tol)) {
        print_error("%.17g != %.17g (|diff| %.3g > %.3g)\n", a, b, fabs(a - b), tol);
        _fail(file, line);
    }
}

/* splitmix64, written out again from Steele, Lea & Flood (OOPSLA 2014). */
static uint64_t mix_next(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static float mix_unit(uint64_t *s)
{
    return (float)(mix_next(s) >> 40) / 16777216.0f;
}

static float *random_points(uint32_t n, uint32_t dims, uint64_t seed)
{
    float *p = malloc((size_t)n * dims * sizeof *p);
    assert_non_null(p);
    for (size_t i = 0; i < (size_t)n * dims; ++i)
        p[i] = mix_unit(&seed);
    return p;
}

/* Smallest Euclidean distance from point a to the 9 periodic copies of b. */
static double image_distance(const float *a, const float *b)
{
    double best = INFINITY;
    for (int sx = -1; sx <= 1; ++sx)
        for (int sy = -1; sy <= 1; ++sy) {
            double dx = (double)a[0] - ((double)b[0] + sx), dy = (double)a[1] - ((double)b[1] + sy);
            double d = sqrt(dx * dx + dy * dy);
            best = d < best ? d : best;
        }
    return best;
}

static double min_pair_distance(const float *p, uint32_t n)
{
    double best = INFINITY;
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = i + 1; j < n; ++j) {
            double d = image_distance(p + 2 * i, p + 2 * j);
            best = d < best ? d : best;
        }
    return best;
}

static void assert_in_unit_square(const float *p, uint32_t n)
{
    for (uint32_t i = 0; i < 2 * n; ++i) {
        assert_true(p[i] >= 0.0f);
        assert_true(p[i] < 1.0f);
    }
}

/* Radical inverse in base 2 by digit expansion (lecture: Phi_b(n) = 0.d1 d2 ...). */
static double radical_inverse2(uint32_t i)
{
    double v = 0.0, scale = 0.5;
    for (; i; i >>= 1, scale *= 0.5)
        v += (i & 1) * scale;
    return v;
}

static float *hammersley(uint32_t n)
{
    float *p = malloc(2 * (size_t)n * sizeof *p);
    assert_non_null(p);
    for (uint32_t i = 0; i < n; ++i) {
        p[2 * i] = (float)((double)i / n);
        p[2 * i + 1] = (float)radical_inverse2(i);
    }
    return p;
}

/* ---- Poisson disk ---------------------------------------------------------- */

/* Every pair is at least the reported radius apart on the torus: checked
 * against all 9 periodic images, so the tile also repeats without a seam. */
static void poisson_tile_min_distance_is_radius_across_seams(void **state)
{
    (void)state;
    st_error err = {0};
    const uint32_t targets[] = {64, 1000, 3000};
    for (int t = 0; t < 3; ++t) {
        float *p = NULL, r = 0.0f;
        uint32_t n = 0;
        assert_int_equal(st_sampling_poisson_tile(targets[t], 11u + t, &p, &n, &r, &err), ST_OK);
        assert_in_unit_square(p, n);
        double d = min_pair_distance(p, n);
        assert_true(d >= r);
        assert_true(d < 1.2 * r); /* and the radius is not loose */
        free(p);
    }
}

/* Counts land within 2% of the target for targets >= 256 (measured <= 1%). */
static void poisson_tile_count_near_target(void **state)
{
    (void)state;
    st_error err = {0};
    const uint32_t targets[] = {256, 1024, 4096, 16384};
    for (int t = 0; t < 4; ++t)
        for (uint32_t seed = 0; seed < 3; ++seed) {
            float *p = NULL;
            uint32_t n = 0;
            assert_int_equal(st_sampling_poisson_tile(targets[t], seed, &p, &n, NULL, &err), ST_OK);
            assert_true(fabs((double)n - targets[t]) <= 0.02 * targets[t]);
            free(p);
        }
}

/* Bridson's output is nearly maximal: on a 128 x 128 probe grid, under 1% of
 * the probes are r or more from every point (measured ~0.1%), and no probe is
 * 1.5 r away (measured <= 1.14 r): no room is left for a whole disk. */
static void poisson_tile_nearly_maximal(void **state)
{
    (void)state;
    st_error err = {0};
    float *p = NULL, r = 0.0f;
    uint32_t n = 0;
    assert_int_equal(st_sampling_poisson_tile(1024, 5, &p, &n, &r, &err), ST_OK);
    int uncovered = 0;
    double worst = 0.0;
    for (int i = 0; i < 128; ++i)
        for (int j = 0; j < 128; ++j) {
            float q[2] = {(i + 0.5f) / 128.0f, (j + 0.5f) / 128.0f};
            double m = INFINITY;
            for (uint32_t k = 0; k < n; ++k) {
                double d = image_distance(q, p + 2 * k);
                m = d < m ? d : m;
            }
            uncovered += m >= r;
            worst = m > worst ? m : worst;
        }
    assert_true(uncovered < 0.01 * 128 * 128);
    assert_true(worst < 1.5 * r);
    free(p);
}

static void poisson_tile_deterministic_per_seed(void **state)
{
    (void)state;
    st_error err = {0};
    float *a = NULL, *b = NULL, *c = NULL, ra, rb, rc;
    uint32_t na, nb, nc;
    assert_int_equal(st_sampling_poisson_tile(500, 42, &a, &na, &ra, &err), ST_OK);
    assert_int_equal(st_sampling_poisson_tile(500, 42, &b, &nb, &rb, &err), ST_OK);
    assert_int_equal(st_sampling_poisson_tile(500, 43, &c, &nc, &rc, &err), ST_OK);
    assert_int_equal(na, nb);
    assert_true(ra == rb);
    assert_memory_equal(a, b, 2 * (size_t)na * sizeof *a);
    assert_true(na != nc || memcmp(a, c, 2 * (size_t)na * sizeof *a) != 0);
    free(a);
    free(b);
    free(c);
}

/* Tiny targets still work: one point cannot be less than one. */
static void poisson_tile_tiny_targets(void **state)
{
    (void)state;
    st_error err = {0};
    for (uint32_t t = 1; t <= 8; ++t) {
        float *p = NULL, r = 0.0f;
        uint32_t n = 0;
        assert_int_equal(st_sampling_poisson_tile(t, 3, &p, &n, &r, &err), ST_OK);
        assert_true(n >= 1);
        assert_in_unit_square(p, n);
        assert_true(n < 2 || min_pair_distance(p, n) >= r);
        free(p);
    }
}

/* A Poisson-disk set has little power at low frequencies (the dark ring of
 * Mitchell 1991 / Ulichney 1987): for N ~ 1024 the radial mean of P over
 * 2 <= |k| <= 10 (4 seeds) is below 0.2 (measured ~0.075); a uniform random
 * set gives ~1 there. */
static void poisson_tile_spectrum_has_dark_ring(void **state)
{
    (void)state;
    st_error err = {0};
    const uint32_t kmax = 16, w = 2 * kmax + 1;
    double *power = calloc((size_t)w * w, sizeof *power), radial[17];
    uint32_t counts[17];
    assert_non_null(power);
    for (uint32_t seed = 0; seed < 4; ++seed) {
        float *p = NULL;
        uint32_t n = 0;
        assert_int_equal(st_sampling_poisson_tile(1024, seed, &p, &n, NULL, &err), ST_OK);
        assert_int_equal(st_spectrum_periodogram(p, n, 2, kmax, power, &err), ST_OK);
        free(p);
    }
    st_spectrum_radial(power, kmax, radial, counts);
    double low = 0.0, weight = 0.0;
    for (int b = 2; b <= 10; ++b) {
        low += radial[b] * counts[b];
        weight += counts[b];
    }
    assert_true(low / weight / 4.0 < 0.2);
    free(power);
}

static void poisson_tile_rejects_bad_arguments(void **state)
{
    (void)state;
    float *p = (float *)&p; /* must come back NULL */
    uint32_t n = 0;
    st_error err = {0};
    assert_int_equal(st_sampling_poisson_tile(0, 1, &p, &n, NULL, &err), ST_ERR_USAGE);
    assert_null(p);
    assert_true(strlen(err.msg) > 0);
    st_error_clear(&err);
    assert_int_equal(st_sampling_poisson_tile(ST_POISSON_MAX_COUNT + 1, 1, &p, &n, NULL, &err),
                     ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "exceeds"));
    st_error_clear(&err);
    assert_int_equal(st_sampling_poisson_tile(10, 1, NULL, &n, NULL, &err), ST_ERR_USAGE);
    st_error_clear(&err);
    assert_int_equal(st_sampling_poisson_tile(10, 1, &p, NULL, NULL, &err), ST_ERR_USAGE);
}

/* ---- best candidate ---------------------------------------------------------- */

static double torus_d2_ref(double ax, double ay, double bx, double by)
{
    double dx = fabs(ax - bx), dy = fabs(ay - by);
    dx = dx < 1.0 - dx ? dx : 1.0 - dx;
    dy = dy < 1.0 - dy ? dy : 1.0 - dy;
    return dx * dx + dy * dy;
}

/* Mitchell's definition by brute force, from the stream documented in the
 * header: point n is the candidate (first one on ties) of the m(n) drawn whose
 * nearest existing point is farthest. */
static float *best_candidate_reference(uint32_t count, uint32_t seed)
{
    float *p = malloc(2 * (size_t)count * sizeof *p);
    assert_non_null(p);
    uint64_t s = seed;
    for (uint32_t n = 0; n < count; ++n) {
        uint64_t m = (uint64_t)ST_BEST_CANDIDATE_K * n;
        m = m < 1 ? 1 : (m > ST_BEST_CANDIDATE_MAX_M ? ST_BEST_CANDIDATE_MAX_M : m);
        double best = -1.0;
        for (uint64_t j = 0; j < m; ++j) {
            float x = mix_unit(&s), y = mix_unit(&s);
            double near = INFINITY;
            for (uint32_t i = 0; i < n; ++i) {
                double d2 = torus_d2_ref(p[2 * i], p[2 * i + 1], x, y);
                near = d2 < near ? d2 : near;
            }
            if (near > best) {
                best = near;
                p[2 * n] = x;
                p[2 * n + 1] = y;
            }
        }
    }
    return p;
}

/* The grid-accelerated generator equals the brute-force definition bit for
 * bit (its early exits and ring bounds lose nothing). */
static void best_candidate_equals_brute_force_definition(void **state)
{
    (void)state;
    st_error err = {0};
    const uint32_t counts[] = {1, 2, 37, 700};
    for (int t = 0; t < 4; ++t) {
        float *p = NULL, *q = best_candidate_reference(counts[t], 9u + t);
        assert_int_equal(st_sampling_best_candidate_tile(counts[t], 9u + t, &p, &err), ST_OK);
        assert_memory_equal(p, q, 2 * (size_t)counts[t] * sizeof *p);
        free(p);
        free(q);
    }
}

/* Well spaced: relative to the hexagonal spacing d_hex = sqrt(2/(sqrt(3) N)),
 * the smallest nearest-neighbour distance of 4096 points is > 0.6 (measured
 * 0.694) and the mean > 0.78 (measured 0.824). Uniform random points have a
 * smallest one near 0.01 and a mean near 0.5. */
static void best_candidate_well_spaced(void **state)
{
    (void)state;
    st_error err = {0};
    const uint32_t n = 4096;
    float *p = NULL;
    assert_int_equal(st_sampling_best_candidate_tile(n, 1, &p, &err), ST_OK);
    assert_in_unit_square(p, n);
    double dhex = sqrt(2.0 / (sqrt(3.0) * n)), smallest = INFINITY, sum = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
        double m = INFINITY;
        for (uint32_t j = 0; j < n; ++j)
            if (j != i) {
                double d = image_distance(p + 2 * i, p + 2 * j);
                m = d < m ? d : m;
            }
        sum += m;
        smallest = m < smallest ? m : smallest;
    }
    assert_true(smallest / dhex > 0.6);
    assert_true(sum / n / dhex > 0.78);
    free(p);
}

/* Progressive: a shorter tile is a prefix of a longer one (same seed). */
static void best_candidate_prefix_of_longer_tile(void **state)
{
    (void)state;
    st_error err = {0};
    float *a = NULL, *b = NULL;
    assert_int_equal(st_sampling_best_candidate_tile(300, 7, &a, &err), ST_OK);
    assert_int_equal(st_sampling_best_candidate_tile(1200, 7, &b, &err), ST_OK);
    assert_memory_equal(a, b, 600 * sizeof *a);
    free(a);
    free(b);
}

static void best_candidate_rejects_bad_arguments(void **state)
{
    (void)state;
    float *p = (float *)&p;
    st_error err = {0};
    assert_int_equal(st_sampling_best_candidate_tile(0, 1, &p, &err), ST_ERR_USAGE);
    assert_null(p);
    assert_true(strlen(err.msg) > 0);
    st_error_clear(&err);
    assert_int_equal(st_sampling_best_candidate_tile(ST_BEST_CANDIDATE_MAX_COUNT + 1, 1, &p, &err),
                     ST_ERR_USAGE);
    st_error_clear(&err);
    assert_int_equal(st_sampling_best_candidate_tile(5, 1, NULL, &err), ST_ERR_USAGE);
}

/* ---- star discrepancy ------------------------------------------------------- */

/* By hand: one point (x, y). The worst boxes are the closed box at the point
 * (1 - xy), and the open boxes [0,x) x [0,1) and [0,1) x [0,y) (x and y). */
static void star_discrepancy_single_point_by_hand(void **state)
{
    (void)state;
    const float pts[][2] = {{0.5f, 0.5f}, {0.0f, 0.0f}, {0.25f, 0.75f}, {0.9f, 0.95f}};
    for (int i = 0; i < 4; ++i) {
        double x = pts[i][0], y = pts[i][1];
        double want = fmax(1.0 - x * y, fmax(x, y));
        assert_near(st_star_discrepancy_2d(pts[i], 1), want, 1e-12);
    }
}

/* By hand: the 2 x 2 centred grid {1/4, 3/4}^2. Closed boxes: [0,1/4]^2 holds
 * 1/4 of the points on 1/16 of the area (excess 3/16), [0,3/4] x [0,1/4]
 * 2/4 on 3/16 (5/16), [0,3/4]^2 all of them on 9/16 (7/16). Open boxes:
 * [0,3/4) x [0,1) holds 2/4 on 3/4 (deficit 1/4), [0,1/4) x [0,1) none on
 * 1/4 (1/4). D* = 7/16. */
static void star_discrepancy_centred_grid_by_hand(void **state)
{
    (void)state;
    const float pts[8] = {0.25f, 0.25f, 0.75f, 0.25f, 0.25f, 0.75f, 0.75f, 0.75f};
    assert_near(st_star_discrepancy_2d(pts, 4), 7.0 / 16.0, 1e-12);
}

/* Brute force over explicit open boxes [0,a) x [0,b), a and b taken from the
 * coordinates, the next float above them (closed boxes, up to 2^-24 of
 * area) and 1. Its value lies in [D* - 1e-6, D*]. The sets sit on a 1/8
 * lattice, so coordinates repeat (ties), and include 0. */
static double star_brute_force(const float *p, uint32_t n)
{
    double worst = 0.0;
    for (uint32_t i = 0; i <= n; ++i)
        for (int ai = 0; ai < 2; ++ai)
            for (uint32_t j = 0; j <= n; ++j)
                for (int bj = 0; bj < 2; ++bj) {
                    float a = i == n ? 1.0f : p[2 * i], b = j == n ? 1.0f : p[2 * j + 1];
                    if (ai)
                        a = nextafterf(a, 2.0f);
                    if (bj)
                        b = nextafterf(b, 2.0f);
                    if (a > 1.0f || b > 1.0f)
                        continue;
                    uint32_t inside = 0;
                    for (uint32_t k = 0; k < n; ++k)
                        inside += p[2 * k] < a && p[2 * k + 1] < b;
                    double d = fabs((double)inside / n - (double)a * b);
                    worst = d > worst ? d : worst;
                }
    return worst;
}

static void star_discrepancy_matches_brute_force(void **state)
{
    (void)state;
    uint64_t s = 77;
    for (uint32_t n = 1; n <= 40; n += 3) {
        float *p = malloc(2 * (size_t)n * sizeof *p);
        assert_non_null(p);
        for (uint32_t i = 0; i < 2 * n; ++i)
            p[i] = (float)(mix_next(&s) % 8) / 8.0f;
        double exact = st_star_discrepancy_2d(p, n), brute = star_brute_force(p, n);
        assert_true(brute <= exact + 1e-12);
        assert_true(brute >= exact - 1e-6);
        free(p);
        p = random_points(n, 2, 1000 + n); /* and without ties */
        exact = st_star_discrepancy_2d(p, n);
        brute = star_brute_force(p, n);
        assert_true(brute <= exact + 1e-12);
        assert_true(brute >= exact - 1e-6);
        free(p);
    }
}

/* Unscrambled Hammersley (i/N, Phi_2(i)): D*_256 = 0.016052 and
 * D*_1024 = 0.004665 (closed-form values quoted in the brief, 6 decimals). */
static void star_discrepancy_hammersley_closed_form(void **state)
{
    (void)state;
    float *p = hammersley(256);
    assert_near(st_star_discrepancy_2d(p, 256), 0.016052, 5e-7);
    free(p);
    p = hammersley(1024);
    assert_near(st_star_discrepancy_2d(p, 1024), 0.004665, 5e-7);
    free(p);
}

/* The O(N^2) sweep handles N = 4096 (timed in the report, not here) and a
 * random set is far worse than Hammersley of the same size. */
static void star_discrepancy_random_worse_than_hammersley(void **state)
{
    (void)state;
    float *h = hammersley(4096), *r = random_points(4096, 2, 5);
    double dh = st_star_discrepancy_2d(h, 4096), dr = st_star_discrepancy_2d(r, 4096);
    assert_true(dh > 0.0 && dh < 0.002);
    assert_true(dr > 3.0 * dh);
    assert_true(isnan(st_star_discrepancy_2d(h, 0)));
    assert_true(isnan(st_star_discrepancy_2d(NULL, 4)));
    free(h);
    free(r);
}

/* ---- L2-star discrepancy ---------------------------------------------------- */

/* T^2 = integral over [0,1]^2 of (#{x_i < t}/N - t1 t2)^2, integrated exactly:
 * on each cell of the grid cut by the point coordinates the count c is
 * constant and the integrand a polynomial. */
static double l2_star_piecewise_2d(const float *p, uint32_t n)
{
    double *xs = malloc((n + 2) * sizeof *xs), *ys = malloc((n + 2) * sizeof *ys);
    assert_non_null(xs);
    assert_non_null(ys);
    for (uint32_t i = 0; i < n; ++i) {
        xs[i] = p[2 * i];
        ys[i] = p[2 * i + 1];
    }
    xs[n] = ys[n] = 0.0;
    xs[n + 1] = ys[n + 1] = 1.0;
    /* insertion sort: n is tiny */
    for (uint32_t i = 1; i < n + 2; ++i)
        for (uint32_t j = i; j > 0 && xs[j - 1] > xs[j]; --j) {
            double t = xs[j];
            xs[j] = xs[j - 1];
            xs[j - 1] = t;
        }
    for (uint32_t i = 1; i < n + 2; ++i)
        for (uint32_t j = i; j > 0 && ys[j - 1] > ys[j]; --j) {
            double t = ys[j];
            ys[j] = ys[j - 1];
            ys[j - 1] = t;
        }
    double total = 0.0;
    for (uint32_t i = 0; i + 1 < n + 2; ++i)
        for (uint32_t j = 0; j + 1 < n + 2; ++j) {
            double s0 = xs[i], s1 = xs[i + 1], t0 = ys[j], t1 = ys[j + 1];
            if (s1 <= s0 || t1 <= t0)
                continue;
            uint32_t c = 0; /* x_k < s for s in (s0, s1)  <=>  x_k <= s0 */
            for (uint32_t k = 0; k < n; ++k)
                c += p[2 * k] <= s0 && p[2 * k + 1] <= t0;
            double q = (double)c / n;
            total += q * q * (s1 - s0) * (t1 - t0) -
                     2.0 * q * (s1 * s1 - s0 * s0) / 2.0 * (t1 * t1 - t0 * t0) / 2.0 +
                     (s1 * s1 * s1 - s0 * s0 * s0) / 3.0 * (t1 * t1 * t1 - t0 * t0 * t0) / 3.0;
        }
    free(xs);
    free(ys);
    return sqrt(total);
}

static void l2_star_equals_exact_integral_2d(void **state)
{
    (void)state;
    for (uint32_t n = 1; n <= 12; ++n) {
        float *p = random_points(n, 2, 300 + n);
        assert_near(st_l2_star_discrepancy(p, n, 2), l2_star_piecewise_2d(p, n), 1e-12);
        free(p);
    }
}

/* Midpoint rule on a G^d grid of the defining integral. Its error comes
 * from the cells the count jumps in: O(1/G), so G = 2^20 (d = 1, tol 1e-5),
 * 1024 (d = 2, tol 2e-3) and 96 (d = 3, tol 2e-2); measured errors are
 * several times smaller. */
static double l2_star_midpoint(const float *p, uint32_t n, uint32_t d, uint32_t g)
{
    double total = 0.0;
    uint64_t cells = 1;
    for (uint32_t k = 0; k < d; ++k)
        cells *= g;
    for (uint64_t c = 0; c < cells; ++c) {
        double t[3], vol = 1.0;
        uint64_t r = c;
        for (uint32_t k = 0; k < d; ++k, r /= g) {
            t[k] = ((double)(r % g) + 0.5) / g;
            vol *= t[k];
        }
        uint32_t inside = 0;
        for (uint32_t i = 0; i < n; ++i) {
            int in = 1;
            for (uint32_t k = 0; k < d; ++k)
                in &= p[i * d + k] < t[k];
            inside += in;
        }
        double e = (double)inside / n - vol;
        total += e * e;
    }
    return sqrt(total / cells);
}

static void l2_star_matches_numerical_integration(void **state)
{
    (void)state;
    float *p = random_points(5, 1, 1);
    assert_near(st_l2_star_discrepancy(p, 5, 1), l2_star_midpoint(p, 5, 1, 1u << 20), 1e-5);
    free(p);
    p = random_points(4, 2, 2);
    assert_near(st_l2_star_discrepancy(p, 4, 2), l2_star_midpoint(p, 4, 2, 1024), 2e-3);
    free(p);
    p = random_points(3, 3, 3);
    assert_near(st_l2_star_discrepancy(p, 3, 3), l2_star_midpoint(p, 3, 3, 96), 2e-2);
    free(p);
}

/* Closed form in 1-D: the centred points (2i-1)/(2N) have T_N = 1/(sqrt(12) N). */
static void l2_star_centred_1d_closed_form(void **state)
{
    (void)state;
    const uint32_t n = 64;
    float p[64];
    for (uint32_t i = 0; i < n; ++i)
        p[i] = (float)((2.0 * i + 1.0) / (2.0 * n));
    assert_near(st_l2_star_discrepancy(p, n, 1), 1.0 / (sqrt(12.0) * n), 1e-9);
    assert_true(isnan(st_l2_star_discrepancy(p, 0, 1)));
    assert_true(isnan(st_l2_star_discrepancy(p, n, 0)));
}

/* ---- spectrum ------------------------------------------------------------------- */

static void spectrum_single_point_is_one_everywhere(void **state)
{
    (void)state;
    st_error err = {0};
    const uint32_t kmax = 20, w = 2 * kmax + 1;
    const float pt[2] = {0.3141f, 0.7777f};
    double *power = calloc((size_t)w * w, sizeof *power);
    assert_non_null(power);
    assert_int_equal(st_spectrum_periodogram(pt, 1, 2, kmax, power, &err), ST_OK);
    for (uint32_t i = 0; i < w * w; ++i)
        assert_near(power[i], 1.0, 1e-12);
    free(power);
}

/* An m x m grid of cell centres: F(k) = sum exp(-2 pi i k.x) is N (times a
 * phase of modulus 1) when both kx and ky are multiples of m, and 0 otherwise,
 * so P = N at those spikes and 0 elsewhere (tolerance 1e-6; m = 16 is a power
 * of two so the float coordinates are exact). */
static void spectrum_grid_spikes_at_multiples_of_m(void **state)
{
    (void)state;
    st_error err = {0};
    const uint32_t m = 16, n = m * m, kmax = 40, w = 2 * kmax + 1;
    float *p = malloc(2 * n * sizeof *p);
    double *power = calloc((size_t)w * w, sizeof *power);
    assert_non_null(p);
    assert_non_null(power);
    for (uint32_t j = 0; j < m; ++j)
        for (uint32_t i = 0; i < m; ++i) {
            p[2 * (j * m + i)] = (i + 0.5f) / m;
            p[2 * (j * m + i) + 1] = (j + 0.5f) / m;
        }
    assert_int_equal(st_spectrum_periodogram(p, n, 2, kmax, power, &err), ST_OK);
    for (uint32_t r = 0; r < w; ++r)
        for (uint32_t c = 0; c < w; ++c) {
            int kx = (int)c - (int)kmax, ky = (int)r - (int)kmax;
            double want = (kx % (int)m == 0 && ky % (int)m == 0) ? (double)n : 0.0;
            assert_near(power[r * w + c], want, 1e-6);
        }
    free(p);
    free(power);
}

/* Against sin/cos per term (no recurrence, no symmetry), relative 1e-9. */
static void spectrum_matches_direct_sum(void **state)
{
    (void)state;
    st_error err = {0};
    const uint32_t n = 50, kmax = 9, w = 2 * kmax + 1;
    float *p = random_points(n, 2, 8);
    double *power = calloc((size_t)w * w, sizeof *power);
    assert_non_null(power);
    assert_int_equal(st_spectrum_periodogram(p, n, 2, kmax, power, &err), ST_OK);
    for (int ky = -(int)kmax; ky <= (int)kmax; ++ky)
        for (int kx = -(int)kmax; kx <= (int)kmax; ++kx) {
            double re = 0.0, im = 0.0;
            for (uint32_t j = 0; j < n; ++j) {
                double phase = kx * (double)p[2 * j] + ky * (double)p[2 * j + 1];
                double a = -2.0 * 3.14159265358979323846 * phase;
                re += cos(a);
                im += sin(a);
            }
            double want = (re * re + im * im) / n;
            double got = power[(size_t)(ky + (int)kmax) * w + (size_t)(kx + (int)kmax)];
            assert_near(got, want, 1e-9 * (want > 1.0 ? want : 1.0));
        }
    free(p);
    free(power);
}

/* Uniform random points: E[P(k)] = 1 for every integer k != 0. The mean over
 * the 4224 frequencies k != 0 of [-32,32]^2 (2112 independent since
 * P(-k) = P(k), each ~ exponential with sd 1) has sd ~ 0.022: tolerance 0.1
 * (4.5 sd). Calling twice adds (+=): the array doubles exactly. */
static void spectrum_random_mean_is_one_and_accumulates(void **state)
{
    (void)state;
    st_error err = {0};
    const uint32_t n = 1024, kmax = 32, w = 2 * kmax + 1;
    float *p = random_points(n, 3, 21); /* stride 3: the third float is ignored */
    double *power = calloc((size_t)w * w, sizeof *power);
    assert_non_null(power);
    assert_int_equal(st_spectrum_periodogram(p, n, 3, kmax, power, &err), ST_OK);
    double sum = 0.0;
    for (uint32_t i = 0; i < w * w; ++i)
        if (i != kmax * w + kmax)
            sum += power[i];
    assert_near(sum / (w * w - 1), 1.0, 0.1);
    assert_near(power[kmax * w + kmax], (double)n, 1e-9); /* DC: N^2 / N */
    double first = power[3 * w + 5];
    assert_int_equal(st_spectrum_periodogram(p, n, 3, kmax, power, &err), ST_OK);
    assert_true(power[3 * w + 5] == 2.0 * first);
    free(p);
    free(power);
}

/* Radial average: on P == 1 every bin is 1, and the counts equal a direct
 * count of the integer k in the square with round(|k|) == b. */
static void spectrum_radial_bins_by_rounded_norm(void **state)
{
    (void)state;
    const uint32_t kmax = 12, w = 2 * kmax + 1;
    double power[25 * 25], radial[13];
    uint32_t counts[13];
    for (uint32_t i = 0; i < w * w; ++i)
        power[i] = 1.0;
    st_spectrum_radial(power, kmax, radial, counts);
    for (uint32_t b = 0; b <= kmax; ++b) {
        uint32_t want = 0;
        for (int ky = -12; ky <= 12; ++ky)
            for (int kx = -12; kx <= 12; ++kx) {
                double norm = sqrt((double)(kx * kx + ky * ky));
                want += norm >= b - 0.5 && norm < b + 0.5;
            }
        assert_int_equal(counts[b], want);
        assert_near(radial[b], 1.0, 1e-15);
    }
    assert_int_equal(counts[0], 1);
    assert_int_equal(counts[1], 8); /* (±1,0), (0,±1), (±1,±1): |k| = 1, 1.414 */
    /* a ramp P = |k|^2 averages to the mean |k|^2 of the ring */
    for (uint32_t r = 0; r < w; ++r)
        for (uint32_t c = 0; c < w; ++c) {
            double kx = (double)c - 12, ky = (double)r - 12;
            power[r * w + c] = kx * kx + ky * ky;
        }
    st_spectrum_radial(power, kmax, radial, counts);
    assert_near(radial[1], (4 * 1.0 + 4 * 2.0) / 8.0, 1e-12);
}

static void spectrum_rejects_bad_arguments(void **state)
{
    (void)state;
    st_error err = {0};
    float pt[2] = {0.5f, 0.5f};
    double power[9] = {0};
    assert_int_equal(st_spectrum_periodogram(NULL, 1, 2, 1, power, &err), ST_ERR_USAGE);
    st_error_clear(&err);
    assert_int_equal(st_spectrum_periodogram(pt, 0, 2, 1, power, &err), ST_ERR_USAGE);
    st_error_clear(&err);
    assert_int_equal(st_spectrum_periodogram(pt, 1, 1, 1, power, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "stride"));
    st_error_clear(&err);
    assert_int_equal(st_spectrum_periodogram(pt, 1, 2, ST_SPECTRUM_KMAX_MAX + 1, power, &err),
                     ST_ERR_USAGE);
    st_error_clear(&err);
    assert_int_equal(st_spectrum_periodogram(pt, 1, 2, 1, NULL, &err), ST_ERR_USAGE);
    for (int i = 0; i < 9; ++i)
        assert_true(power[i] == 0.0); /* failed calls add nothing */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(poisson_tile_min_distance_is_radius_across_seams),
        cmocka_unit_test(poisson_tile_count_near_target),
        cmocka_unit_test(poisson_tile_nearly_maximal),
        cmocka_unit_test(poisson_tile_deterministic_per_seed),
        cmocka_unit_test(poisson_tile_tiny_targets),
        cmocka_unit_test(poisson_tile_spectrum_has_dark_ring),
        cmocka_unit_test(poisson_tile_rejects_bad_arguments),
        cmocka_unit_test(best_candidate_equals_brute_force_definition),
        cmocka_unit_test(best_candidate_well_spaced),
        cmocka_unit_test(best_candidate_prefix_of_longer_tile),
        cmocka_unit_test(best_candidate_rejects_bad_arguments),
        cmocka_unit_test(star_discrepancy_single_point_by_hand),
        cmocka_unit_test(star_discrepancy_centred_grid_by_hand),
        cmocka_unit_test(star_discrepancy_matches_brute_force),
        cmocka_unit_test(star_discrepancy_hammersley_closed_form),
        cmocka_unit_test(star_discrepancy_random_worse_than_hammersley),
        cmocka_unit_test(l2_star_equals_exact_integral_2d),
        cmocka_unit_test(l2_star_matches_numerical_integration),
        cmocka_unit_test(l2_star_centred_1d_closed_form),
        cmocka_unit_test(spectrum_single_point_is_one_everywhere),
        cmocka_unit_test(spectrum_grid_spikes_at_multiples_of_m),
        cmocka_unit_test(spectrum_matches_direct_sum),
        cmocka_unit_test(spectrum_random_mean_is_one_and_accumulates),
        cmocka_unit_test(spectrum_radial_bins_by_rounded_norm),
        cmocka_unit_test(spectrum_rejects_bad_arguments),
    };
    return cmocka_run_group_tests_name("sampling", tests, NULL, NULL);
}
