/* test_sampling_pixel_tile.c — guards st_sampling_pixel_tile (src/sampling/pixel_tile.c), the
 * tile the tiled samplers render from.
 *
 * Independent checks: point j lies in pixel j mod side^2 (floor of its
 * coordinates); Poisson's minimum distance by brute force over the 9
 * periodic images (not the generator's ring search); best-candidate against
 * a brute-force re-implementation of its definition (every candidate against
 * every point, same random stream); spacing against jittered sampling. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sampling_int.h"

static float *tile(st_u32 sampler, st_u32 side, st_u32 spp, st_u32 seed, float *radius)
{
    float *p = NULL;
    st_error err = {0};
    if (st_sampling_pixel_tile(sampler, side, spp, seed, &p, radius, &err) != ST_OK)
        fail_msg("%s", err.msg);
    return p;
}

/* Smallest distance between points i and j over the 9 periodic images. */
static double image_distance(const float *a, const float *b, double side)
{
    double best = INFINITY;
    for (int ox = -1; ox <= 1; ox++)
        for (int oy = -1; oy <= 1; oy++) {
            double dx = a[0] - (b[0] + ox * side), dy = a[1] - (b[1] + oy * side);
            best = fmin(best, sqrt(dx * dx + dy * dy));
        }
    return best;
}

static const st_u32 SIZES[][2] = {{1, 1}, {1, 5}, {2, 3}, {3, 2}, {8, 4}, {16, 1}, {5, 9}};

/* Every pixel holds exactly spp points: point j in pixel j mod side^2. */
static void every_pixel_gets_exactly_spp(void **state)
{
    (void)state;
    st_u32 samplers[2] = {ST_SAMPLER_POISSON, ST_SAMPLER_BEST_CANDIDATE};
    for (int s = 0; s < 2; s++)
        for (size_t t = 0; t < sizeof SIZES / sizeof *SIZES; t++) {
            st_u32 side = SIZES[t][0], spp = SIZES[t][1], pixels = side * side;
            float *p = tile(samplers[s], side, spp, 7, NULL);
            for (st_u32 j = 0; j < pixels * spp; j++) {
                float x = p[2 * j], y = p[2 * j + 1];
                st_u32 pix = j % pixels;
                if (!(x >= 0.0f && y >= 0.0f && (st_u32)x == pix % side &&
                      (st_u32)y == pix / side))
                    fail_msg("sampler %u side %u spp %u point %u (%g, %g) not in pixel %u",
                             samplers[s], side, spp, j, (double)x, (double)y, pix);
            }
            free(p);
        }
}

/* Poisson: no two points closer than the radius returned, measured by brute
 * force; the radius stays within 3 retries of its start sqrt(0.5 / spp)
 * ((15/16)^3 = 0.82; measured: 0.82 at 1 spp, 1 at 16 spp). */
static void poisson_min_distance_is_radius(void **state)
{
    (void)state;
    st_u32 sizes[][2] = {{32, 1}, {8, 16}, {3, 2}};
    for (int t = 0; t < 3; t++) {
        st_u32 side = sizes[t][0], spp = sizes[t][1], n = side * side * spp;
        float r;
        float *p = tile(ST_SAMPLER_POISSON, side, spp, 3, &r);
        assert_true(r >= 0.8 * sqrt(0.5 / spp) && r <= sqrt(0.5 / spp));
        double smallest = INFINITY;
        for (st_u32 i = 0; i < n; i++)
            for (st_u32 j = i + 1; j < n; j++)
                smallest = fmin(smallest, image_distance(p + 2 * i, p + 2 * j, side));
        if (!(smallest >= r))
            fail_msg("side %u spp %u: closest pair %.6f < radius %.6f", side, spp, smallest,
                     (double)r);
        free(p);
    }
}

/* The definition, by brute force: the same random stream (per candidate
 * one splitmix64 output for the open pixel, (output >> 32) times the open
 * count >> 32, then one for the point: x from bits 0-15, y from bits 16-31
 * on the 2^-16 lattice), m(n) = min(max(1, k n), cap) candidates for point
 * n, nearest point by a full scan over the 9 periodic images, the open list
 * 0..side^2-1 at each pass' start with the chosen pixel replaced by the
 * list's last. */
static float *best_candidate_reference(st_u32 side, st_u32 spp, st_u32 seed)
{
    st_u32 pixels = side * side, n = 0, *open = malloc(pixels * sizeof *open);
    float *placed = malloc(2 * sizeof(float) * pixels * spp);
    float *out = malloc(2 * sizeof(float) * pixels * spp);
    st_u64 rng = seed;
    for (st_u32 pass = 0; pass < spp; pass++) {
        for (st_u32 i = 0; i < pixels; i++)
            open[i] = i;
        for (st_u32 nopen = pixels; nopen > 0; nopen--) {
            st_u64 m = (st_u64)ST_PIXEL_TILE_K * n;
            m = m < 1 ? 1 : m > ST_PIXEL_TILE_MAX_M ? ST_PIXEL_TILE_MAX_M : m;
            double best = -1.0;
            float b[2] = {0, 0};
            st_u32 bi = 0;
            for (st_u64 c = 0; c < m; c++) {
                st_u32 i = (st_u32)(((splitmix64(&rng) >> 32) * (st_u64)nopen) >> 32);
                st_u32 pix = open[i];
                st_u64 r = splitmix64(&rng);
                float q[2] = {(float)(pix % side) + (float)(r & 0xffffu) * 0x1p-16f,
                              (float)(pix / side) + (float)((r >> 16) & 0xffffu) * 0x1p-16f};
                double d = INFINITY;
                for (st_u32 k = 0; k < n; k++)
                    d = fmin(d, image_distance(q, placed + 2 * k, side));
                if (d > best) {
                    best = d;
                    memcpy(b, q, sizeof b);
                    bi = i;
                }
            }
            memcpy(placed + 2 * n++, b, sizeof b);
            memcpy(out + 2 * ((size_t)pass * pixels + open[bi]), b, sizeof b);
            open[bi] = open[nopen - 1];
        }
    }
    free(open);
    free(placed);
    return out;
}

static void best_candidate_equals_brute_force_definition(void **state)
{
    (void)state;
    st_u32 sizes[][2] = {{1, 3}, {4, 3}, {5, 2}, {7, 1}};
    for (int t = 0; t < 4; t++) {
        st_u32 side = sizes[t][0], spp = sizes[t][1];
        float *p = tile(ST_SAMPLER_BEST_CANDIDATE, side, spp, 11u + t, NULL);
        float *q = best_candidate_reference(side, spp, 11u + t);
        assert_memory_equal(p, q, 2 * sizeof(float) * side * side * spp);
        free(p);
        free(q);
    }
}

/* Blue noise across pixels: relative to the spacing 1/sqrt(spp) pixel, the
 * smallest nearest-neighbour distance of best-candidate is above 0.5 and the
 * mean above 0.8 (Mitchell's pattern without pixels: 0.75 and 0.89; the
 * earlier rule of 4 (pass + 1) candidates in a pixel at a time: 0.3 and
 * 0.77), and Poisson's above 0.55 and 0.72 (measured 0.58..0.71,
 * 0.74..0.81); jittered points, one per pixel independently, have a mean
 * near 0.5 and a smallest near 0.02 at 1024 points. */
static void well_spaced_across_pixels(void **state)
{
    (void)state;
    st_u32 sizes[][2] = {{32, 1}, {8, 16}};
    st_u32 samplers[2] = {ST_SAMPLER_POISSON, ST_SAMPLER_BEST_CANDIDATE};
    double min_smallest[2] = {0.55, 0.5}, min_mean[2] = {0.72, 0.8};
    for (int s = 0; s < 2; s++)
        for (int t = 0; t < 2; t++) {
            st_u32 side = sizes[t][0], spp = sizes[t][1], n = side * side * spp;
            float *p = tile(samplers[s], side, spp, 1, NULL);
            double smallest = INFINITY, sum = 0.0, spacing = 1.0 / sqrt(spp);
            for (st_u32 i = 0; i < n; i++) {
                double m = INFINITY;
                for (st_u32 j = 0; j < n; j++)
                    if (j != i)
                        m = fmin(m, image_distance(p + 2 * i, p + 2 * j, side));
                sum += m;
                smallest = fmin(smallest, m);
            }
            if (!(smallest / spacing > min_smallest[s] && sum / n / spacing > min_mean[s]))
                fail_msg("sampler %u side %u spp %u: smallest %.3f mean %.3f", samplers[s],
                         side, spp, smallest / spacing, sum / n / spacing);
            free(p);
        }
}

static void deterministic_per_seed_and_rejects_bad_arguments(void **state)
{
    (void)state;
    float *a = tile(ST_SAMPLER_POISSON, 6, 2, 4, NULL), *b = tile(ST_SAMPLER_POISSON, 6, 2, 4, NULL);
    float *c = tile(ST_SAMPLER_POISSON, 6, 2, 5, NULL);
    assert_memory_equal(a, b, sizeof(float) * 2 * 72);
    assert_memory_not_equal(a, c, sizeof(float) * 2 * 72);
    free(a);
    free(b);
    free(c);
    float *p = NULL;
    st_error err = {0};
    assert_int_equal(st_sampling_pixel_tile(ST_SAMPLER_HALTON, 4, 1, 0, &p, NULL, &err),
                     ST_ERR_USAGE);
    assert_int_equal(st_sampling_pixel_tile(ST_SAMPLER_POISSON, 0, 1, 0, &p, NULL, &err),
                     ST_ERR_USAGE);
    assert_int_equal(st_sampling_pixel_tile(ST_SAMPLER_POISSON, 4, 0, 0, &p, NULL, &err),
                     ST_ERR_USAGE);
    assert_int_equal(st_sampling_pixel_tile(ST_SAMPLER_BEST_CANDIDATE, 1024, 8, 0, &p, NULL, &err),
                     ST_ERR_USAGE);
    assert_null(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(every_pixel_gets_exactly_spp),
        cmocka_unit_test(poisson_min_distance_is_radius),
        cmocka_unit_test(best_candidate_equals_brute_force_definition),
        cmocka_unit_test(well_spaced_across_pixels),
        cmocka_unit_test(deterministic_per_seed_and_rejects_bad_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
