/* test_sampling_kernels.c — guards kernels/sample/samplers.h and kernels/shared/rng.h, the sample
 * positions that the kernels and `strata pattern` share.
 *
 * Expected values are derived here, independently of the headers:
 *   - the radical inverse Φ_b(n) = Σ d_i b^(-i) (n = Σ d_i b^(i-1); the lecture) is
 *     formed as an exact rational num / b^k from n's digits, and the float the
 *     header returns must be the largest float <= that rational. Comparisons are
 *     exact, in unsigned __int128 integer arithmetic: no floating tolerance.
 *   - Halton x_i = (Φ2(i), Φ3(i), Φ5(i), ...), Hammersley x_i = (i/N, Φ2(i), ...);
 *     the Halton pixel mapping is pbrt-v4's HaltonSampler (Pharr, Jakob, Humphreys,
 *     "Physically Based Rendering", 4th ed., §8.6.2): Φ2(h) 2^e2 falls in pixel
 *     column px mod 128 and Φ3(h) 3^e3 in row py mod 128.
 *   - stratification is counted point by point (floor(x n) is exact in double
 *     for a float x and n < 2^29); nets are counted over every elementary interval.
 *     Interval edges that are floats (powers of two, the stratified grid, which
 *     clamps) are exact; where an edge c/n is not a float, a value the header
 *     rounds down (the largest float <= its exact value) may sit one float below
 *     it, and only that is allowed (assert_one_per_interval).
 *   - the random numbers face a chi-square test (64 bins, 10^6 draws, critical
 *     values of χ²(63) at p = 0.001 in each tail) and a correlation test (stated
 *     below). The inputs are fixed, so each statistical test is deterministic.
 * A "pattern" is what `strata pattern --sampler X --count N` prints: pixel (0, 0)
 * of a 1 x 1 image with spp = N. */
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

typedef unsigned __int128 u128;

/* ---- exact rationals ------------------------------------------------------- */

static int bit_length(u128 x)
{
    int n = 0;
    while (x) {
        x >>= 1;
        n++;
    }
    return n;
}

/* x << s, failing the test rather than overflowing 128 bits. */
static u128 shl_checked(u128 x, int s)
{
    if (x == 0)
        return 0;
    if (bit_length(x) + s > 127)
        fail_msg("exact arithmetic out of range: %d-bit value << %d", bit_length(x), s);
    return x << s;
}

static u128 mul_checked(u128 a, u128 b)
{
    if (a != 0 && b != 0 && bit_length(a) + bit_length(b) > 127)
        fail_msg("exact arithmetic out of range: %d bits x %d bits", bit_length(a),
                 bit_length(b));
    return a * b;
}

/* sign(f - num/den), exactly, for finite f >= 0 and den > 0. f is a double so
 * that sums of two adjacent floats (exact in double) can be compared too. */
static int cmp_real_ratio(double f, u128 num, u128 den)
{
    if (f == 0.0)
        return num ? -1 : 0;
    int ex;
    double fr = frexp(f, &ex); /* f = fr 2^ex, fr in [0.5, 1) */
    uint64_t m = (uint64_t)ldexp(fr, 53);
    int e = ex - 53;
    while (!(m & 1u)) { /* f = m 2^e with m odd: fewest bits */
        m >>= 1;
        e++;
    }
    u128 lhs, rhs;
    if (e >= 0) {
        lhs = mul_checked(shl_checked(m, e), den);
        rhs = num;
    } else {
        lhs = mul_checked(m, den);
        rhs = shl_checked(num, -e);
    }
    return lhs < rhs ? -1 : lhs > rhs ? 1 : 0;
}

/* The largest float <= num/den (0 <= num/den < 2), found by stepping float by
 * float from an estimate and checking each step exactly. */
static float floor_float(u128 num, u128 den)
{
    float f = (float)((double)num / (double)den);
    while (f > 0.0f && cmp_real_ratio(f, num, den) > 0)
        f = nextafterf(f, 0.0f);
    while (cmp_real_ratio(nextafterf(f, 4.0f), num, den) <= 0)
        f = nextafterf(f, 4.0f);
    return f;
}

/* The float nearest to num/den, ties to even (IEEE round to nearest). */
static float nearest_float(u128 num, u128 den)
{
    float lo = floor_float(num, den), hi = nextafterf(lo, 4.0f);
    if (cmp_real_ratio(lo, num, den) == 0)
        return lo;
    int c = cmp_real_ratio((double)lo + (double)hi, 2 * num, den); /* midpoint vs value */
    if (c > 0)
        return lo;
    if (c < 0)
        return hi;
    int e;
    uint32_t mant = (uint32_t)ldexpf(frexpf(lo, &e), 24);
    return (mant & 1u) ? hi : lo;
}

/* Φ_b(n) = Σ_{i=1..k} d_i b^(-i) = (Σ d_i b^(k-i)) / b^k, d_1 the least
 * significant base-b digit of n, k the number of digits. */
static void exact_radical_inverse(uint32_t b, uint64_t n, u128 *num, u128 *den)
{
    uint32_t d[72];
    int k = 0;
    for (uint64_t x = n; x != 0; x /= b)
        d[k++] = (uint32_t)(x % b);
    u128 bk = 1;
    for (int i = 0; i < k; i++)
        bk *= b;
    u128 sum = 0, weight = bk;
    for (int i = 0; i < k; i++) {
        weight /= b; /* b^(k-1-i): weight of d_(i+1) */
        sum += (u128)d[i] * weight;
    }
    *num = sum;
    *den = bk;
}

static float expected_radical_inverse(uint32_t b, uint64_t n)
{
    u128 num, den;
    exact_radical_inverse(b, n, &num, &den);
    return floor_float(num, den);
}

/* The i-th prime (i < 64), found by trial division (not read from the header). */
static uint32_t nth_prime(uint32_t i)
{
    static uint32_t table[64];
    if (!table[63])
        for (uint32_t c = 2, count = 0; count < 64; c++) {
            uint32_t d = 2;
            while (d * d <= c && c % d)
                d++;
            if (d * d > c)
                table[count++] = c;
        }
    return table[i];
}

#define assert_float_same(got, want, ...)                                                  \
    do {                                                                                   \
        float g_ = (got), w_ = (want);                                                     \
        if (!(g_ == w_)) {                                                                 \
            char where_[160];                                                              \
            snprintf(where_, sizeof where_, __VA_ARGS__);                                  \
            fail_msg("%s: got %.9g (%a), expected %.9g (%a)", where_, (double)g_,          \
                     (double)g_, (double)w_, (double)w_);                                  \
        }                                                                                  \
    } while (0)

/* xorshift32 (Marsaglia, "Xorshift RNGs", J. Stat. Software 2003): test inputs only. */
static uint32_t next_random(uint32_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return *s;
}

/* ---- patterns --------------------------------------------------------------- */

static st_params image_params(uint32_t sampler, uint32_t w, uint32_t h, uint32_t spp,
                              uint32_t scramble, uint32_t seed)
{
    st_params p;
    memset(&p, 0, sizeof p);
    p.width = w;
    p.height = h;
    p.spp = spp;
    p.sampler = sampler;
    p.scramble = scramble;
    p.seed = seed;
    st_sampler_prepare(&p);
    return p;
}

static st_params pattern_params(uint32_t sampler, uint32_t count, uint32_t scramble,
                                uint32_t seed)
{
    return image_params(sampler, 1, 1, count, scramble, seed);
}

static float sample_value(const st_params *p, uint32_t px, uint32_t py, uint32_t s,
                          uint32_t dim)
{
    st_sample_id id = st_sample_begin(p, px, py, s);
    return st_sample_dim(p, &id, dim);
}

static float pattern_value(const st_params *p, uint32_t i, uint32_t dim)
{
    return sample_value(p, 0, 0, i, dim);
}

/* floor(x n), exact: x has 24 significant bits, n < 2^29, the product fits a double. */
static uint32_t cell_of(float x, uint32_t n)
{
    return (uint32_t)floor((double)x * (double)n);
}

/* ---- radical inverse -------------------------------------------------------- */

static void radical_inverse_check(uint32_t b, uint64_t n)
{
    float got = st_radical_inverse(b, (st_u32)n);
    u128 num, den;
    exact_radical_inverse(b, n, &num, &den);
    /* r <= v < nextafter(r, 2): r is the largest float <= v */
    if (!(cmp_real_ratio(got, num, den) <= 0 && cmp_real_ratio(nextafterf(got, 2.0f), num, den) > 0))
        fail_msg("Φ_%u(%llu) = %a is not the largest float <= %llu/%llu", b,
                 (unsigned long long)n, (double)got, (unsigned long long)num,
                 (unsigned long long)den);
}

static void radical_inverse_is_largest_float_below_exact(void **state)
{
    (void)state;
    static const uint64_t large[] = {4294967295u, 4294967294u, 2147483648u, 2147483647u,
                                     3486784401u /* 3^20 */, 1220703125u /* 5^13 */,
                                     3221225472u, 0xdeadbeefu, 1234567891u, 4000000000u};
    for (uint32_t i = 0; i < 16; i++) {
        uint32_t b = nth_prime(i);
        assert_int_equal(b, st_primes[i]);
        for (uint64_t n = 0; n <= 5000; n++)
            radical_inverse_check(b, n);
    }
    /* every base the header holds, at large n and at pseudo-random n */
    uint32_t seed = 2463534242u;
    for (uint32_t i = 0; i < ST_PRIME_COUNT; i++) {
        uint32_t b = nth_prime(i);
        assert_int_equal(b, st_primes[i]);
        for (size_t j = 0; j < sizeof large / sizeof large[0]; j++)
            radical_inverse_check(b, large[j]);
        for (int j = 0; j < 2000; j++)
            radical_inverse_check(b, next_random(&seed));
    }
}

/* Φ2(n) is n's bits mirrored about the binary point: 32 reversed bits over 2^32. */
static void radical_inverse_base2_equals_bit_reversal(void **state)
{
    (void)state;
    uint32_t seed = 88172645u;
    for (uint64_t j = 0; j < 200000; j++) {
        uint32_t n = j < 100000 ? (uint32_t)j : next_random(&seed);
        uint32_t rev = 0;
        for (int bit = 0; bit < 32; bit++)
            rev |= ((n >> bit) & 1u) << (31 - bit);
        assert_int_equal(st_reverse_bits(n), rev);
        assert_float_same(st_radical_inverse(2, n), floor_float(rev, (u128)1 << 32), "Φ2(%u)", n);
    }
    assert_float_same(st_radical_inverse(2, 0xffffffffu), 0x1.fffffep-1f, "Φ2(2^32-1)");
}

/* st_ratio_floor(num, den) is the largest float <= num/den for num < den < 2^62,
 * st_ratio_ceil(num, den) the smallest float >= it. */
static void ratio_floor_ceil_bracket_exact_value(void **state)
{
    (void)state;
    uint32_t seed = 1u;
    for (int j = 0; j < 200000; j++) {
        uint64_t den = ((uint64_t)next_random(&seed) << 32 | next_random(&seed)) >> (2 + j % 60);
        if (den < 2)
            den = 2;
        uint64_t num = ((uint64_t)next_random(&seed) << 32 | next_random(&seed)) % den;
        assert_float_same(st_ratio_floor(num, den), floor_float(num, den), "%llu/%llu",
                          (unsigned long long)num, (unsigned long long)den);
    }
    /* st_ratio_ceil: the smallest float >= num/den, the floor itself when exact */
    for (int j = 0; j < 100000; j++) {
        uint64_t den = (next_random(&seed) >> (j % 31)) + 2;
        uint64_t num = j % 3 ? next_random(&seed) % den : (den >> (j % 5)) & ~1ull;
        float lo = floor_float(num, den);
        float want = cmp_real_ratio(lo, num, den) == 0 ? lo : nextafterf(lo, 2.0f);
        assert_float_same(st_ratio_ceil(num, den), want, "ceil %llu/%llu",
                          (unsigned long long)num, (unsigned long long)den);
    }
    assert_float_same(st_ratio_ceil(1, 2), 0.5f, "ceil 1/2");
    assert_float_same(st_ratio_ceil(1, 3), 0x1.555556p-2f, "ceil 1/3");
    assert_float_same(st_ratio_floor(0, 7), 0.0f, "0/7");
    assert_float_same(st_ratio_floor((1ull << 62) - 2, (1ull << 62) - 1), 0x1.fffffep-1f,
                      "(2^62-2)/(2^62-1)");
}

/* st_bits_to_unit(x) is the largest float <= x / 2^32. */
static void bits_to_unit_is_largest_float_below(void **state)
{
    (void)state;
    uint32_t seed = 7u;
    for (int j = 0; j < 300000; j++) {
        uint32_t x = j < 1000 ? (uint32_t)j : j < 2000 ? 0xffffffffu - (uint32_t)j
                                                      : next_random(&seed) >> (j % 32);
        assert_float_same(st_bits_to_unit(x), floor_float(x, (u128)1 << 32), "bits %08x", x);
    }
}

/* ---- Halton and Hammersley patterns ------------------------------------------ */

static void halton_pattern_equals_radical_inverses(void **state)
{
    (void)state;
    const uint32_t count = 4096;
    st_params p = pattern_params(ST_SAMPLER_HALTON, count, 0, 12345);
    for (uint32_t i = 0; i < count; i++)
        for (uint32_t d = 0; d < 8; d++)
            assert_float_same(pattern_value(&p, i, d), expected_radical_inverse(nth_prime(d), i),
                              "halton point %u dim %u", i, d);
}

static void hammersley_pattern_equals_definition(void **state)
{
    (void)state;
    static const uint32_t counts[] = {1000, 4096, 7};
    for (size_t c = 0; c < sizeof counts / sizeof counts[0]; c++) {
        uint32_t n = counts[c];
        st_params p = pattern_params(ST_SAMPLER_HAMMERSLEY, n, 0, 99);
        for (uint32_t i = 0; i < n; i++) {
            assert_float_same(pattern_value(&p, i, 0), floor_float(i, n), "hammersley %u/%u", i, n);
            for (uint32_t d = 1; d < 8; d++)
                assert_float_same(pattern_value(&p, i, d),
                                  expected_radical_inverse(nth_prime(d - 1), i),
                                  "hammersley N=%u point %u dim %u", n, i, d);
        }
    }
}

/* floor(Φ_b(h) b^e) and the fraction (Φ_b(h) b^e mod 1) as an exact rational. */
static uint64_t scaled_digits(uint32_t b, uint32_t e, uint64_t h, u128 *frac_num, u128 *den)
{
    u128 num, be = 1;
    exact_radical_inverse(b, h, &num, den);
    for (uint32_t i = 0; i < e; i++)
        be *= b;
    u128 scaled = num * be;
    *frac_num = scaled % *den;
    return (uint64_t)(scaled / *den);
}

static uint32_t smallest_exponent(uint32_t b, uint32_t res)
{
    uint32_t e = 0;
    for (uint64_t s = 1; s < res; s *= b)
        e++;
    return e;
}

/* For every pixel of a w x h image and several sample indices s, the Halton
 * index h of (pixel, s) puts Φ2(h) 2^e2 in [px mod 128, px mod 128 + 1) and
 * Φ3(h) 3^e3 in [py mod 128, py mod 128 + 1), where 2^e2 >= min(w, 128) and
 * 3^e3 >= min(h, 128) are the smallest such powers; the sampler's pixel
 * dimensions are the fractional parts, dims >= 2 are Φ5(h), Φ7(h), ...;
 * distinct s give distinct h and distinct pixels of a 128 x 128 tile too. */
static void halton_index_check_image(uint32_t w, uint32_t hgt)
{
    static const uint32_t samples[] = {0, 1, 2, 7, 100, 1000};
    st_params p = image_params(ST_SAMPLER_HALTON, w, hgt, 1024, 0, 5);
    uint32_t e2 = smallest_exponent(2, w < 128 ? w : 128);
    uint32_t e3 = smallest_exponent(3, hgt < 128 ? hgt : 128);
    assert_int_equal(p.halton_exp2, e2);
    assert_int_equal(p.halton_exp3, e3);
    uint64_t stride = (1ull << e2);
    for (uint32_t i = 0; i < e3; i++)
        stride *= 3;
    /* tile[(py%128) * 128 + px%128] = h of sample 0, to check that distinct
     * residues give distinct indices */
    uint32_t *tile = malloc(128 * 128 * sizeof *tile);
    uint8_t *used = calloc(stride, 1);
    assert_non_null(tile);
    assert_non_null(used);
    for (uint32_t py = 0; py < hgt; py++)
        for (uint32_t px = 0; px < w; px++) {
            uint32_t hs[sizeof samples / sizeof samples[0]];
            for (size_t k = 0; k < sizeof samples / sizeof samples[0]; k++) {
                uint32_t s = samples[k];
                uint32_t h = st_halton_index(&p, px, py, s);
                hs[k] = h;
                u128 f2, d2, f3, d3;
                uint64_t col = scaled_digits(2, e2, h, &f2, &d2);
                uint64_t row = scaled_digits(3, e3, h, &f3, &d3);
                if (col != px % 128 || row != py % 128)
                    fail_msg("%ux%u pixel (%u,%u) sample %u: h=%u lands in (%llu,%llu)", w, hgt,
                             px, py, s, h, (unsigned long long)col, (unsigned long long)row);
                if (h / stride != s)
                    fail_msg("pixel (%u,%u): h=%u is not in sample %u's block", px, py, h, s);
                st_sample_id id = st_sample_begin(&p, px, py, s);
                assert_int_equal(id.index, h);
                assert_float_same(st_sample_dim(&p, &id, 0), floor_float(f2, d2),
                                  "%ux%u (%u,%u) s=%u dim 0", w, hgt, px, py, s);
                assert_float_same(st_sample_dim(&p, &id, 1), floor_float(f3, d3),
                                  "%ux%u (%u,%u) s=%u dim 1", w, hgt, px, py, s);
                if (k < 3)
                    for (uint32_t d = 2; d < 8; d++)
                        assert_float_same(st_sample_dim(&p, &id, d),
                                          expected_radical_inverse(nth_prime(d), h),
                                          "%ux%u (%u,%u) s=%u dim %u", w, hgt, px, py, s, d);
            }
            for (size_t a = 0; a < sizeof hs / sizeof hs[0]; a++)
                for (size_t b = a + 1; b < sizeof hs / sizeof hs[0]; b++)
                    assert_int_not_equal(hs[a], hs[b]);
            uint32_t t = (py % 128) * 128 + px % 128;
            if (px < 128 && py < 128) {
                tile[t] = hs[0];
                if (used[hs[0]])
                    fail_msg("%ux%u pixel (%u,%u): index %u already used", w, hgt, px, py, hs[0]);
                used[hs[0]] = 1;
            } else {
                assert_int_equal(hs[0], tile[t]); /* the pattern repeats every 128 */
            }
        }
    free(tile);
    free(used);
}

static void halton_index_lands_in_its_pixel(void **state)
{
    (void)state;
    halton_index_check_image(64, 48);
    halton_index_check_image(200, 130);
    halton_index_check_image(128, 128);
    halton_index_check_image(7, 5);
    halton_index_check_image(1, 48);
    halton_index_check_image(64, 1);
    halton_index_check_image(1, 1);
}

/* Large sample indices: h = s * stride + offset stays below 2^32 unwrapped. */
static void halton_index_large_samples_in_pixel(void **state)
{
    (void)state;
    st_params p = image_params(ST_SAMPLER_HALTON, 200, 130, 1, 0, 5);
    uint64_t stride = p.halton_stride;
    assert_int_equal(stride, 128 * 243);
    uint32_t top = (uint32_t)(0xffffffffull / stride) - 1;
    static const uint32_t pix[][2] = {{0, 0}, {199, 129}, {127, 127}, {128, 0}, {3, 100}};
    for (size_t k = 0; k < 5; k++)
        for (uint32_t s = top - 3; s <= top; s++) {
            uint32_t px = pix[k][0], py = pix[k][1];
            uint32_t h = st_halton_index(&p, px, py, s);
            assert_true(h / stride == s);
            u128 f, d;
            assert_int_equal(scaled_digits(2, 7, h, &f, &d), px % 128);
            assert_int_equal(scaled_digits(3, 5, h, &f, &d), py % 128);
        }
}

/* ---- stratified and uniform ----------------------------------------------------- */

/* The most nearly square nx * ny = n with nx <= ny, by brute force. */
static void stratified_grid_is_most_square_factorisation(void **state)
{
    (void)state;
    for (uint32_t n = 1; n <= 5000; n++) {
        uint32_t best = 1;
        for (uint32_t x = 1; x * x <= n; x++)
            if (n % x == 0)
                best = x;
        st_u32 nx, ny;
        st_stratified_grid(n, &nx, &ny);
        if (nx != best || ny != n / best)
            fail_msg("grid(%u) = %ux%u, expected %ux%u", n, nx, ny, best, n / best);
    }
}

/* One point in each of the nx x ny strata, for the pixel pair (0, 1) and the
 * padded pairs (2, 3), (4, 5), for every pixel of a small image and several seeds. */
static void stratified_one_point_per_stratum(void **state)
{
    (void)state;
    static const uint32_t cases[][3] = {{16, 4, 4}, {12, 3, 4}, {7, 1, 7}, {64, 8, 8}, {1, 1, 1}};
    static const uint32_t seeds[] = {1, 7, 123456};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++)
        for (uint32_t scramble = 0; scramble < 2; scramble++)
            for (size_t sd = 0; sd < 3; sd++) {
                uint32_t spp = cases[c][0], nx = cases[c][1], ny = cases[c][2];
                st_params p = image_params(ST_SAMPLER_STRATIFIED, 3, 2, spp, scramble, seeds[sd]);
                assert_int_equal(p.strat_nx, nx);
                assert_int_equal(p.strat_ny, ny);
                for (uint32_t pix = 0; pix < 6; pix++)
                    for (uint32_t d = 0; d < 6; d += 2) {
                        uint32_t hits[64] = {0};
                        for (uint32_t s = 0; s < spp; s++) {
                            float x = sample_value(&p, pix % 3, pix / 3, s, d);
                            float y = sample_value(&p, pix % 3, pix / 3, s, d + 1);
                            assert_true(x >= 0.0f && x < 1.0f && y >= 0.0f && y < 1.0f);
                            hits[cell_of(y, ny) * nx + cell_of(x, nx)]++;
                        }
                        for (uint32_t k = 0; k < spp; k++)
                            if (hits[k] != 1)
                                fail_msg("spp %u scramble %u seed %u pixel %u dims (%u,%u): "
                                         "stratum %u holds %u points",
                                         spp, scramble, seeds[sd], pix, d, d + 1, k, hits[k]);
                    }
            }
}

/* The coordinate stays inside its cell for the extreme jitters, the 64
 * smallest and 64 largest values st_rng_unit can return (k 2^-24): rounding of
 * cell + jitter and of the division must not carry it over either edge. */
static void stratified_coord_stays_in_cell_at_extreme_jitter(void **state)
{
    (void)state;
    for (uint32_t n = 1; n <= 64; n++) {
        st_params p = image_params(ST_SAMPLER_STRATIFIED, 1, 1, n, 0, 1);
        for (uint32_t s = 0; s < n; s++) {
            st_sample_id id = st_sample_begin(&p, 0, 0, s);
            for (uint32_t d = 0; d < 2; d++)
                for (uint32_t j = 0; j < 128; j++) {
                    uint32_t k = j < 64 ? j : (1u << 24) - 128 + j;
                    float jitter = ldexpf((float)k, -24);
                    uint32_t cell = d ? s / p.strat_nx : s % p.strat_nx;
                    uint32_t cells = d ? p.strat_ny : p.strat_nx;
                    float x = st_stratified_coord(&p, &id, d, 0u, jitter);
                    if (cell_of(x, cells) != cell)
                        fail_msg("spp %u sample %u dim %u jitter %a: x = %a is in cell %u of "
                                 "%u, expected %u",
                                 n, s, d, (double)jitter, (double)x, cell_of(x, cells), cells,
                                 cell);
                }
        }
    }
}

/* The jitter is uniform within the cell: the offsets x n - cell of 64 x 64
 * pixels x 16 samples (65536 values per dimension), in 16 bins, give a
 * chi-square below 37.697, the 0.999 quantile of χ²(15); centred or
 * corner points would give about 983040. */
static void stratified_jitter_uniform_within_cell(void **state)
{
    (void)state;
    for (uint32_t scramble = 0; scramble < 2; scramble++) {
        st_params p = image_params(ST_SAMPLER_STRATIFIED, 64, 64, 16, scramble, 9);
        for (uint32_t d = 0; d < 4; d++) {
            uint32_t bins[16] = {0}, n = 0;
            for (uint32_t pix = 0; pix < 64 * 64; pix++)
                for (uint32_t s = 0; s < 16; s++) {
                    double x = (double)sample_value(&p, pix % 64, pix / 64, s, d) * 4.0;
                    bins[(uint32_t)((x - floor(x)) * 16.0)]++;
                    n++;
                }
            double expect = n / 16.0, chi = 0.0;
            for (int b = 0; b < 16; b++)
                chi += (bins[b] - expect) * (bins[b] - expect) / expect;
            if (!(chi < 37.697))
                fail_msg("scramble %u dim %u: offsets in the cell give chi-square %.1f", scramble,
                         d, chi);
        }
    }
}

/* Uniform: the pixel dimensions are the cell centres (c + 1/2)/n, correctly rounded. */
static void uniform_pattern_is_cell_centres(void **state)
{
    (void)state;
    static const uint32_t counts[] = {16, 12, 7, 1, 100};
    for (size_t c = 0; c < sizeof counts / sizeof counts[0]; c++) {
        st_params p = pattern_params(ST_SAMPLER_UNIFORM, counts[c], 1, 3);
        uint32_t nx = p.strat_nx, ny = p.strat_ny;
        uint32_t hits[100] = {0};
        for (uint32_t s = 0; s < counts[c]; s++) {
            float x = pattern_value(&p, s, 0), y = pattern_value(&p, s, 1);
            uint32_t cx = cell_of(x, nx), cy = cell_of(y, ny);
            hits[cy * nx + cx]++;
            assert_float_same(x, nearest_float(2 * cx + 1, 2 * nx), "uniform %u point %u x",
                              counts[c], s);
            assert_float_same(y, nearest_float(2 * cy + 1, 2 * ny), "uniform %u point %u y",
                              counts[c], s);
        }
        for (uint32_t k = 0; k < counts[c]; k++)
            assert_int_equal(hits[k], 1);
    }
}

/* ---- permutations ------------------------------------------------------------------ */

static void permute_is_bijection(void **state)
{
    (void)state;
    static const uint32_t ns[] = {1, 2, 3, 5, 16, 17, 100, 1000, 4097};
    static const uint32_t keys[] = {0, 1, 2, 0xdeadbeefu, 12345, 0xffffffffu, 0x80000000u};
    for (size_t a = 0; a < sizeof ns / sizeof ns[0]; a++)
        for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++) {
            uint32_t n = ns[a];
            uint8_t *seen = calloc(n, 1);
            assert_non_null(seen);
            for (uint32_t i = 0; i < n; i++) {
                uint32_t v = st_permute(i, n, keys[k]);
                if (v >= n || seen[v])
                    fail_msg("permute(%u, n=%u, key=%x) = %u: out of range or repeated", i, n,
                             keys[k], v);
                seen[v] = 1;
            }
            free(seen);
        }
}

/* Different keys give different permutations: pairwise distinct for 64 keys
 * when n = 17, 100, 1000; at n = 16 (a power of two, where hash-based
 * permutations are most constrained) at least 3/4 of 4096 keys give distinct
 * permutations (uniformly random ones would give about 4094; Kensler's family
 * about 3600); for n = 2, 3, 5 every one of the n! permutations appears among
 * 20000 keys. */
static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static void permute_keys_give_different_permutations(void **state)
{
    (void)state;
    static const uint32_t ns[] = {17, 100, 1000};
    enum { KEYS = 64 };
    for (size_t a = 0; a < sizeof ns / sizeof ns[0]; a++) {
        uint32_t n = ns[a];
        uint32_t *perm = malloc((size_t)KEYS * n * sizeof *perm);
        assert_non_null(perm);
        for (uint32_t k = 0; k < KEYS; k++)
            for (uint32_t i = 0; i < n; i++)
                perm[k * n + i] = st_permute(i, n, k * 0x9e3779b9u);
        for (uint32_t k = 0; k < KEYS; k++)
            for (uint32_t l = k + 1; l < KEYS; l++)
                if (!memcmp(perm + k * n, perm + l * n, n * sizeof *perm))
                    fail_msg("n=%u: keys %u and %u give the same permutation", n, k, l);
        free(perm);
    }
    static uint64_t code16[4096]; /* a permutation of 16 as 16 hex digits */
    for (uint32_t k = 0; k < 4096; k++) {
        code16[k] = 0;
        for (uint32_t i = 0; i < 16; i++)
            code16[k] = code16[k] << 4 | st_permute(i, 16, k);
    }
    qsort(code16, 4096, sizeof code16[0], cmp_u64);
    uint32_t distinct16 = 1;
    for (uint32_t k = 1; k < 4096; k++)
        distinct16 += code16[k] != code16[k - 1];
    if (distinct16 < 3072)
        fail_msg("n=16: 4096 keys give only %u distinct permutations", distinct16);
    static const uint32_t small[] = {2, 3, 5};
    for (size_t a = 0; a < 3; a++) {
        uint32_t n = small[a], fact = 1;
        for (uint32_t i = 2; i <= n; i++)
            fact *= i;
        uint8_t seen[3125] = {0}; /* permutation as a base-n number */
        uint32_t distinct = 0;
        for (uint32_t k = 0; k < 20000; k++) {
            uint32_t code = 0;
            for (uint32_t i = 0; i < n; i++)
                code = code * n + st_permute(i, n, k);
            distinct += !seen[code];
            seen[code] = 1;
        }
        if (distinct != fact)
            fail_msg("n=%u: %u of %u permutations appear over 20000 keys", n, distinct, fact);
    }
}

/* Over keys, each i is sent everywhere equally often: Pearson's chi-square of
 * st_permute(i, n, key) over 10^5 keys, for i = 0 and i = n - 1, below the
 * 0.999 quantile of χ²(n - 1) (a biased permutation family, e.g. one that
 * favours the identity, fails by orders of magnitude). */
static void permute_uniform_over_keys(void **state)
{
    (void)state;
    static const uint32_t ns[] = {2, 3, 5, 7, 12, 17, 100};
    static const double crit[] = {10.828, 13.816, 18.467, 22.458, 31.264, 39.252, 148.23};
    for (size_t a = 0; a < sizeof ns / sizeof ns[0]; a++) {
        uint32_t n = ns[a];
        for (uint32_t i = 0; i < n; i += n - 1) {
            uint32_t count[100] = {0};
            const uint32_t keys = 100000;
            for (uint32_t k = 0; k < keys; k++)
                count[st_permute(i, n, k)]++;
            double expect = (double)keys / n, chi = 0.0;
            for (uint32_t v = 0; v < n; v++)
                chi += (count[v] - expect) * (count[v] - expect) / expect;
            if (!(chi < crit[a]))
                fail_msg("n=%u: image of %u over keys: chi-square %.1f, limit %.3f (%u dof)", n, i,
                         chi, crit[a], n - 1);
        }
    }
}

/* ---- Sobol' -------------------------------------------------------------------------- */

/* Each elementary interval [a/2^i, (a+1)/2^i) x [b/2^j, (b+1)/2^j), i + j = m,
 * holds exactly one of the 2^m points: a (0, m, 2)-net in base 2. */
static void assert_net(const float *x, const float *y, uint32_t m, const char *what)
{
    uint32_t n = 1u << m;
    uint32_t *count = malloc(n * sizeof *count);
    assert_non_null(count);
    for (uint32_t i = 0; i <= m; i++) {
        memset(count, 0, n * sizeof *count);
        for (uint32_t k = 0; k < n; k++)
            count[(cell_of(x[k], 1u << i) << (m - i)) | cell_of(y[k], 1u << (m - i))]++;
        for (uint32_t c = 0; c < n; c++)
            if (count[c] != 1)
                fail_msg("%s: m=%u, intervals 2^-%u x 2^-%u: cell %u holds %u points", what, m,
                         i, m - i, c, count[c]);
    }
    free(count);
}

/* Dimension 1 from its definition: polynomial x + 1 (degree 1, a = 0), m_1 = 1,
 * m_k = 2 m_(k-1) xor m_(k-1), v_k = m_k / 2^k; x_i = xor of v_k over the set
 * bits k of i (Sobol' 1967; Joe & Kuo, "Constructing Sobol sequences with better
 * two-dimensional projections", SIAM J. Sci. Comput. 2008, dimension 2). */
static uint32_t sobol_dim1_reference(uint32_t i)
{
    uint64_t m = 1, x = 0;
    for (uint32_t k = 1; k <= 32; k++) {
        if (i >> (k - 1) & 1u)
            x ^= m << (32 - k);
        m = (m << 1) ^ m;
    }
    return (uint32_t)x;
}

static void sobol_equals_direction_numbers(void **state)
{
    (void)state;
    static const float first[8] = {0.0f, 0.5f, 0.75f, 0.25f, 0.625f, 0.125f, 0.375f, 0.875f};
    for (uint32_t i = 0; i < 8; i++)
        assert_float_same(st_bits_to_unit(st_sobol_bits(i, 1)), first[i], "sobol dim 1 point %u", i);
    uint32_t seed = 3u;
    for (uint32_t j = 0; j < 300000; j++) {
        uint32_t i = j < 100000 ? j : next_random(&seed);
        assert_int_equal(st_sobol_bits(i, 1), sobol_dim1_reference(i));
        assert_int_equal(st_sobol_bits(i, 0), st_reverse_bits(i));
    }
    st_params p = pattern_params(ST_SAMPLER_PADDED_SOBOL, 1024, 0, 17);
    for (uint32_t i = 0; i < 1024; i++) {
        assert_float_same(pattern_value(&p, i, 0), floor_float(st_reverse_bits(i), (u128)1 << 32),
                          "sobol pattern %u dim 0", i);
        assert_float_same(pattern_value(&p, i, 1),
                          floor_float(sobol_dim1_reference(i), (u128)1 << 32),
                          "sobol pattern %u dim 1", i);
    }
}

static void sobol_check_nets(uint32_t scramble, uint32_t seed, uint32_t px, uint32_t py)
{
    float x[1024], y[1024];
    char what[96];
    for (uint32_t m = 0; m <= 10; m++) {
        /* the pixel pair, from a pattern with more points than the net */
        st_params p = image_params(ST_SAMPLER_PADDED_SOBOL, 4, 4, 4096, scramble, seed);
        for (uint32_t k = 0; k < (1u << m); k++) {
            x[k] = sample_value(&p, px, py, k, 0);
            y[k] = sample_value(&p, px, py, k, 1);
        }
        snprintf(what, sizeof what, "sobol scramble %u seed %u pixel (%u,%u) dims 0,1", scramble,
                 seed, px, py);
        assert_net(x, y, m, what);
        /* padded pairs: the index is shuffled within spp = 2^m, then Owen-scrambled */
        st_params q = image_params(ST_SAMPLER_PADDED_SOBOL, 4, 4, 1u << m, scramble, seed);
        for (uint32_t d = 2; d < 6; d += 2) {
            for (uint32_t k = 0; k < (1u << m); k++) {
                x[k] = sample_value(&q, px, py, k, d);
                y[k] = sample_value(&q, px, py, k, d + 1);
            }
            snprintf(what, sizeof what, "sobol scramble %u seed %u pixel (%u,%u) dims %u,%u",
                     scramble, seed, px, py, d, d + 1);
            assert_net(x, y, m, what);
        }
    }
}

static void sobol_pattern_is_0m2_net(void **state)
{
    (void)state;
    sobol_check_nets(0, 1, 0, 0);
    sobol_check_nets(0, 2, 3, 1);
}

static void sobol_owen_scrambled_is_0m2_net(void **state)
{
    (void)state;
    sobol_check_nets(1, 1, 0, 0);
    sobol_check_nets(1, 2, 0, 0);
    sobol_check_nets(1, 2, 3, 1);
    sobol_check_nets(1, 0xdeadbeefu, 2, 2);
}

/* Every value of dims 0..5 of the first 256 points changes with the seed and
 * with the pixel (equal 24-bit values by chance: probability 2^-24 each). */
static void assert_differs(uint32_t sampler, uint32_t dims, uint32_t w, uint32_t h,
                           const uint32_t a[3], const uint32_t b[3])
{
    st_params pa = image_params(sampler, w, h, 256, 1, a[0]);
    st_params pb = image_params(sampler, w, h, 256, 1, b[0]);
    for (uint32_t s = 0; s < 256; s++)
        for (uint32_t d = 0; d < dims; d++) {
            float va = sample_value(&pa, a[1], a[2], s, d);
            float vb = sample_value(&pb, b[1], b[2], s, d);
            if (va == vb)
                fail_msg("sampler %u: (seed %u, pixel %u,%u) and (seed %u, pixel %u,%u) agree at "
                         "sample %u dim %u: %a",
                         sampler, a[0], a[1], a[2], b[0], b[1], b[2], s, d, (double)va);
        }
}

static void sobol_scrambled_differs_by_seed_and_pixel(void **state)
{
    (void)state;
    const uint32_t base[3] = {1, 0, 0}, seed2[3] = {2, 0, 0}, right[3] = {1, 1, 0},
                   below[3] = {1, 0, 1}, far[3] = {1, 3, 3};
    assert_differs(ST_SAMPLER_PADDED_SOBOL, 6, 4, 4, base, seed2);
    assert_differs(ST_SAMPLER_PADDED_SOBOL, 6, 4, 4, base, right);
    assert_differs(ST_SAMPLER_PADDED_SOBOL, 6, 4, 4, base, below);
    assert_differs(ST_SAMPLER_PADDED_SOBOL, 6, 4, 4, right, far);
}

/* ---- scrambled Halton and Hammersley --------------------------------------------- */

/* Global Sobol': for every sample s, the pixels of a W x H image take
 * distinct indices of the block [s 4^m, (s+1) 4^m), and index i's first two
 * dimensions, scaled by 2^m, fall in its pixel. Checked against the inverse
 * map built by brute force: every index of the block, its pixel read off the
 * top m digits of dimensions 0 and 1. */
static void sobol_global_index_lands_in_its_pixel(void **state)
{
    (void)state;
    uint32_t sizes[][3] = {{1, 1, 64}, {8, 8, 16}, {13, 7, 8}, {64, 33, 4}};
    for (int t = 0; t < 4; t++) {
        st_params p = image_params(ST_SAMPLER_SOBOL, sizes[t][0], sizes[t][1], sizes[t][2], 0, 0);
        uint32_t m = p.sobol_log2, block = 1u << (2 * m);
        assert_true((1u << m) >= sizes[t][0] && (1u << m) >= sizes[t][1]);
        assert_true(m == 0 || (1u << (m - 1)) < sizes[t][0] || (1u << (m - 1)) < sizes[t][1]);
        uint32_t *owner = malloc(block * sizeof *owner);
        for (uint32_t s = 0; s < p.spp; s++) {
            for (uint32_t k = 0; k < block; k++) {
                uint32_t i = s * block + k, top = m ? 32 - m : 31;
                uint32_t x = m ? st_sobol_sample_bits(i, 0) >> top : 0;
                uint32_t y = m ? st_sobol_sample_bits(i, 1) >> top : 0;
                owner[(y << m) | x] = i;
            }
            for (uint32_t py = 0; py < p.height; py++)
                for (uint32_t px = 0; px < p.width; px++) {
                    st_sample_id id = st_sample_begin(&p, px, py, s);
                    if (id.index != owner[(py << m) | px])
                        fail_msg("%ux%u sample %u pixel (%u,%u): index %u, expected %u",
                                 p.width, p.height, s, px, py, id.index, owner[(py << m) | px]);
                    float u = st_sample_dim(&p, &id, 0), v = st_sample_dim(&p, &id, 1);
                    assert_true(u >= 0.0f && u < 1.0f && v >= 0.0f && v < 1.0f);
                }
        }
        free(owner);
    }
}

/* Global Sobol': every dimension, unscrambled and Owen-scrambled, puts one
 * of its first 2^m points in each interval [k 2^-m, (k+1) 2^-m) (each
 * generator matrix is upper triangular with unit diagonal, and Owen
 * scrambling maps elementary intervals onto elementary intervals). Equality
 * with scipy in every dimension is tests/cli/test_sobol_scipy.sh. */
static void sobol_global_dimensions_stratified(void **state)
{
    (void)state;
    uint8_t seen[1024];
    for (uint32_t scramble = 0; scramble < 2; scramble++) {
        st_params p = pattern_params(ST_SAMPLER_SOBOL, 1024, scramble, 5);
        for (uint32_t d = 0; d < ST_SOBOL_DIMS; d++)
            for (uint32_t m = 0; m <= 10; m += 5) {
                memset(seen, 0, sizeof seen);
                for (uint32_t k = 0; k < (1u << m); k++) {
                    uint32_t c = cell_of(pattern_value(&p, k, d), 1u << m);
                    if (seen[c]++)
                        fail_msg("scramble %u dim %u m %u: interval %u twice", scramble, d, m, c);
                }
            }
    }
}

/* ZSobol: in every pixel, with spp = 2^m, each pair of dimensions of the
 * pixel's samples is a (0,m,2)-net (the pixel holds an aligned block of the
 * (0,2)-sequence, its digits permuted, Owen-scrambled or not); for spp not a
 * power of two the samples are still distinct. */
static void zsobol_pixel_pairs_are_nets(void **state)
{
    (void)state;
    float x[256], y[256];
    char what[96];
    for (uint32_t scramble = 0; scramble < 2; scramble++)
        for (uint32_t m = 0; m <= 8; m++) {
            st_params p = image_params(ST_SAMPLER_ZSOBOL, 5, 3, 1u << m, scramble, 7);
            for (uint32_t pix = 0; pix < 15; pix++)
                for (uint32_t d = 0; d < 6; d += 2) {
                    for (uint32_t k = 0; k < (1u << m); k++) {
                        x[k] = sample_value(&p, pix % 5, pix / 5, k, d);
                        y[k] = sample_value(&p, pix % 5, pix / 5, k, d + 1);
                    }
                    snprintf(what, sizeof what, "zsobol scramble %u pixel %u dims %u,%u",
                             scramble, pix, d, d + 1);
                    assert_net(x, y, m, what);
                }
        }
}

/* ZSobol's index: a bijection of [0, 2^(2m + l)) (every pixel's block, every
 * sample, one index each), for an odd and an even l. */
static void zsobol_index_is_bijection(void **state)
{
    (void)state;
    uint32_t spps[2] = {8, 16};
    for (int t = 0; t < 2; t++) {
        st_params p = image_params(ST_SAMPLER_ZSOBOL, 8, 8, spps[t], 1, 3);
        uint32_t n = 64 * spps[t];
        uint8_t *seen = calloc(n, 1);
        for (uint32_t pix = 0; pix < 64; pix++)
            for (uint32_t s = 0; s < spps[t]; s++) {
                uint32_t i = st_zsobol_index(&p, pix % 8, pix / 8, s, 3);
                assert_true(i < n && !seen[i]);
                seen[i] = 1;
            }
        free(seen);
    }
}

/* joint-stratified: for spp = q^2 (q = 3, 4, 5, 7, 8, 16), every pair of
 * dimensions among 0..3 (pixel x, y, light u, v) puts exactly one of a
 * pixel's samples in each cell of the q x q grid: an orthogonal array of
 * strength 2. For spp = 12 (no array) the pixel pair is still stratified. */
static void joint_stratified_pairs_are_stratified(void **state)
{
    (void)state;
    uint32_t qs[6] = {3, 4, 5, 7, 8, 16};
    uint8_t seen[256];
    float v[4][256];
    for (int t = 0; t < 6; t++) {
        uint32_t q = qs[t];
        st_params p = image_params(ST_SAMPLER_JOINT_STRATIFIED, 3, 2, q * q, 1, 9);
        for (uint32_t pix = 0; pix < 6; pix++) {
            for (uint32_t s = 0; s < q * q; s++)
                for (uint32_t d = 0; d < 4; d++)
                    v[d][s] = sample_value(&p, pix % 3, pix / 3, s, d);
            for (uint32_t i = 0; i < 4; i++)
                for (uint32_t j = i + 1; j < 4; j++) {
                    memset(seen, 0, sizeof seen);
                    for (uint32_t s = 0; s < q * q; s++) {
                        uint32_t c = cell_of(v[i][s], q) * q + cell_of(v[j][s], q);
                        if (seen[c]++)
                            fail_msg("q %u pixel %u dims %u,%u: cell %u twice", q, pix, i, j, c);
                    }
                }
        }
    }
    st_params p = image_params(ST_SAMPLER_JOINT_STRATIFIED, 1, 1, 12, 1, 9);
    memset(seen, 0, sizeof seen);
    for (uint32_t s = 0; s < 12; s++) {
        uint32_t c = cell_of(sample_value(&p, 0, 0, s, 0), p.strat_nx) * p.strat_ny +
                     cell_of(sample_value(&p, 0, 0, s, 1), p.strat_ny);
        assert_false(seen[c]++);
    }
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

/* The n values x[] hold one point per interval [c/n, (c+1)/n). Each value is
 * the largest float <= an exact value (samplers.h), so where an edge c/n is not
 * a float (n not a power of two) a value just above the edge may round to the
 * float just below it: sorted, the value of rank c lies in interval c, or (with
 * allow_below) one float below it. Powers of two: exact, no allowance. */
static void assert_one_per_interval(float *x, uint32_t n, int allow_below, const char *what)
{
    qsort(x, n, sizeof *x, cmp_float);
    for (uint32_t c = 0; c < n; c++) {
        uint32_t cell = cell_of(x[c], n);
        if (cell == c)
            continue;
        if (allow_below && cell + 1 == c && cell_of(nextafterf(x[c], 2.0f), n) == c)
            continue;
        fail_msg("%s: %u points, the point of rank %u is %a, in interval %u", what, n, c,
                 (double)x[c], cell);
    }
}

/* The first b^k values of dimension d hold one point per interval of length
 * b^-k, k = 1..kmax. */
static void assert_stratified_1d(const st_params *p, uint32_t px, uint32_t py, uint32_t d,
                                 uint32_t b, uint32_t kmax)
{
    uint32_t n = 1;
    char what[128];
    for (uint32_t k = 1; k <= kmax; k++) {
        n *= b;
        float *x = malloc(n * sizeof *x);
        assert_non_null(x);
        for (uint32_t s = 0; s < n; s++)
            x[s] = sample_value(p, px, py, s, d);
        snprintf(what, sizeof what, "sampler %u seed %u pixel (%u,%u) dim %u base %u",
                 p->sampler, p->seed, px, py, d, b);
        assert_one_per_interval(x, n, b != 2, what);
        free(x);
    }
}

static void halton_scrambled_keeps_stratification(void **state)
{
    (void)state;
    static const uint32_t seeds[] = {1, 2, 0xabcdef};
    for (size_t s = 0; s < 3; s++) {
        st_params p = pattern_params(ST_SAMPLER_HALTON, 4096, 1, seeds[s]);
        assert_stratified_1d(&p, 0, 0, 0, 2, 12);
        assert_stratified_1d(&p, 0, 0, 1, 3, 7);
        assert_stratified_1d(&p, 0, 0, 2, 5, 5);
        assert_stratified_1d(&p, 0, 0, 3, 7, 4);
        /* per pixel of an image: consecutive samples of one pixel */
        st_params q = image_params(ST_SAMPLER_HALTON, 64, 48, 4096, 1, seeds[s]);
        assert_stratified_1d(&q, 5, 7, 0, 2, 8);
        assert_stratified_1d(&q, 63, 47, 0, 2, 8);
        assert_stratified_1d(&q, 5, 7, 1, 3, 5);
        assert_stratified_1d(&q, 63, 47, 1, 3, 5);
        assert_stratified_1d(&q, 5, 7, 2, 5, 3);
    }
}

static void hammersley_scrambled_keeps_stratification(void **state)
{
    (void)state;
    static const uint32_t seeds[] = {1, 2, 0xabcdef};
    for (size_t s = 0; s < 3; s++) {
        st_params p = pattern_params(ST_SAMPLER_HAMMERSLEY, 4096, 1, seeds[s]);
        assert_stratified_1d(&p, 0, 0, 1, 2, 12);
        assert_stratified_1d(&p, 0, 0, 2, 3, 7);
        assert_stratified_1d(&p, 0, 0, 3, 5, 5);
        st_params q = image_params(ST_SAMPLER_HAMMERSLEY, 5, 5, 4096, 1, seeds[s]);
        assert_stratified_1d(&q, 4, 3, 1, 2, 12);
        assert_stratified_1d(&q, 4, 3, 2, 3, 7);
    }
}

/* Dimension 0 of scrambled Hammersley, i/N rotated by a per-pixel u
 * (Cranley-Patterson), still holds one point per interval of 1/N, in every
 * pixel of a 100 x 100 image with N = 999 and of a 20 x 20 image with N = 4096
 * and N = 7. (A float sum i/N + u, wrapped by subtracting 1, can carry a point
 * 2^-25 past an edge: about one pixel in 5000 at N = 999, hence the many.) */
static void hammersley_rotation_one_point_per_interval(void **state)
{
    (void)state;
    static const uint32_t cases[][3] = {{999, 100, 100}, {4096, 20, 20}, {7, 20, 20}};
    static float x[4096];
    char what[96];
    for (size_t c = 0; c < 3; c++) {
        uint32_t n = cases[c][0], w = cases[c][1], h = cases[c][2];
        st_params r = image_params(ST_SAMPLER_HAMMERSLEY, w, h, n, 1, 3);
        for (uint32_t pix = 0; pix < w * h; pix++) {
            for (uint32_t i = 0; i < n; i++)
                x[i] = sample_value(&r, pix % w, pix / w, i, 0);
            snprintf(what, sizeof what, "hammersley N=%u pixel %u dim 0", n, pix);
            assert_one_per_interval(x, n, (n & (n - 1)) != 0, what);
        }
    }
}

static void halton_hammersley_scrambled_differ_by_seed_and_pixel(void **state)
{
    (void)state;
    const uint32_t base[3] = {1, 0, 0}, seed2[3] = {2, 0, 0};
    assert_differs(ST_SAMPLER_HALTON, 8, 1, 1, base, seed2);
    assert_differs(ST_SAMPLER_HAMMERSLEY, 8, 1, 1, base, seed2);
    const uint32_t hp[3] = {1, 1, 2}, hq[3] = {1, 2, 1};
    assert_differs(ST_SAMPLER_HAMMERSLEY, 8, 4, 4, hp, hq);
    assert_differs(ST_SAMPLER_HAMMERSLEY, 8, 4, 4, base, hq);
    /* Halton in an 8 x 1 image: dim 0 of pixel px is Φ2(s) for every px when
     * unscrambled (the pixel is in the index's low digits), so only the
     * per-pixel scramble can make pixels differ there */
    st_params u = image_params(ST_SAMPLER_HALTON, 8, 1, 256, 0, 1);
    st_params v = image_params(ST_SAMPLER_HALTON, 8, 1, 256, 1, 1);
    for (uint32_t s = 0; s < 256; s++)
        for (uint32_t px = 1; px < 8; px++) {
            assert_float_same(sample_value(&u, px, 0, s, 0), sample_value(&u, 0, 0, s, 0),
                              "unscrambled halton dim 0 sample %u pixel %u", s, px);
            if (sample_value(&v, px, 0, s, 0) == sample_value(&v, 0, 0, s, 0))
                fail_msg("scrambled halton dim 0 sample %u: pixels 0 and %u agree", s, px);
        }
}

/* ---- scrambled Halton's digit tables ------------------------------------------- */

/* The scrambled radical inverse spelled out here from its definition
 * (samplers.h's file comment on scrambled radical inverses): the base-b
 * digits of n, least significant first, padded with zeros to K digits
 * (K: n's digit count, at least the smallest k with b^k >= 2^24); digit k
 * mapped by d -> (a d + c) mod b with h = lowbias32(key xor k 0x9e3779b9),
 * a = 1 + floor(hi16(h) (b-1) / 2^16), c = floor(lo16(h) b / 2^16); the
 * digits read as the fraction rev / b^K, both cut by 8 bits at a time until
 * b^K < 2^40, then floor(rev 2^24 / den) 2^-24. */
static uint32_t lowbias32(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

static float scrambled_definition(uint32_t b, uint32_t n, uint32_t key)
{
    u128 rev = 0, den = 1;
    for (uint32_t k = 0; n != 0 || den < (1u << 24); k++) {
        uint32_t h = lowbias32(key ^ (k * 0x9e3779b9u));
        uint32_t a = 1 + (uint32_t)(((uint64_t)(h >> 16) * (b - 1)) >> 16);
        uint32_t c = (uint32_t)(((uint64_t)(h & 0xffffu) * b) >> 16);
        rev = rev * b + (a * (n % b) + c) % b;
        den *= b;
        n /= b;
    }
    while (den >= ((u128)1 << 40)) {
        rev >>= 8;
        den >>= 8;
    }
    return (float)(uint32_t)((rev << 24) / den) * 0x1p-24f;
}

/* The indices the comparisons visit in base b: the first ones, every power
 * of b and its neighbours (where the digit count changes), the last ones
 * below 2^32 (the most digits) and pseudo-random ones. */
static uint32_t table_test_indices(uint32_t b, uint32_t *out)
{
    uint32_t m = 0, seed = 0x9e3779b9u ^ b;
    for (uint32_t n = 0; n < 300; n++)
        out[m++] = n;
    for (uint64_t v = b; v <= 0xffffffffull; v *= b) {
        out[m++] = (uint32_t)(v - 1);
        out[m++] = (uint32_t)v;
        if (v < 0xffffffffull)
            out[m++] = (uint32_t)(v + 1);
    }
    for (uint32_t j = 0; j < 300; j++)
        out[m++] = 0xffffffffu - j;
    for (uint32_t j = 0; j < 700; j++)
        out[m++] = next_random(&seed);
    return m;
}

/* st_divide_by_constants with st_division_constants(b) is n / b for every
 * prime base of the tables and for every odd b < 4096 (whichever rounding
 * each needs), checked at n = 0..2^16, at both sides of every multiple of b
 * within 2^16 of 2^32 (where a multiplier's error is largest), and at
 * pseudo-random n. */
static void division_constants_divide_exactly(void **state)
{
    (void)state;
    uint32_t seed = 0x2545f491u;
    for (uint32_t b = 3; b < 4096; b += 2) {
        uint32_t m, add, s;
        st_division_constants(b, &m, &add, &s);
        for (uint32_t n = 0; n <= 65536; n++)
            if (st_divide_by_constants(n, m, add, s) != n / b)
                fail_msg("b %u: %u / b gave %u", b, n, st_divide_by_constants(n, m, add, s));
        for (uint64_t q = (0xffffffffull - 65536) / b; q * b <= 0xffffffffull + 1; q++)
            for (int64_t dn = -1; dn <= 0; dn++) {
                uint64_t n = q * b + dn;
                if (n <= 0xffffffffull &&
                    st_divide_by_constants((uint32_t)n, m, add, s) != (uint32_t)(n / b))
                    fail_msg("b %u: %llu / b gave %u", b, (unsigned long long)n,
                             st_divide_by_constants((uint32_t)n, m, add, s));
            }
        for (int j = 0; j < 2000; j++) {
            uint32_t n = next_random(&seed);
            if (st_divide_by_constants(n, m, add, s) != n / b)
                fail_msg("b %u: %u / b gave %u", b, n, st_divide_by_constants(n, m, add, s));
        }
    }
}

/* Each dimension 2..63's table holds one row of b entries per digit
 * position a 32-bit index reaches (the digits of 2^32 - 1, counted here),
 * each row a permutation of 0..b-1; the tables lie in order, one after the
 * other, inside the words returned. */
static void halton_tables_layout(void **state)
{
    (void)state;
    uint32_t *w = NULL;
    size_t words = 0;
    assert_int_equal(st_sampling_halton_tables(77, &w, &words, NULL), ST_OK);
    const uint16_t *e = (const uint16_t *)w;
    size_t next = 2u * ST_HALTON_TABLE_HEADER;
    assert_int_equal(ST_HALTON_TABLE_HEADER, 256);
    for (uint32_t dim = 2; dim < 64; dim++) {
        uint32_t b = nth_prime(dim), digits = 0;
        for (uint64_t v = 0xffffffffull; v; v /= b)
            digits++;
        assert_int_equal(w[dim], next);
        uint32_t m, add, sh;
        st_division_constants(b, &m, &add, &sh);
        assert_int_equal(w[64 + dim], m);
        assert_int_equal(w[128 + dim], add);
        assert_int_equal(w[192 + dim], sh);
        for (uint32_t k = 0; k < digits; k++) {
            uint8_t seen[320] = {0};
            for (uint32_t d = 0; d < b; d++) {
                uint32_t img = e[w[dim] + k * b + d];
                if (img >= b || seen[img])
                    fail_msg("dim %u (base %u) digit position %u: %u -> %u repeats or is out "
                             "of range", dim, b, k, d, img);
                seen[img] = 1;
            }
        }
        next += (size_t)digits * b;
    }
    assert_int_equal(words, (next + 1) / 2);
    free(w);
}

/* The tables give the hashing definition's value bit for bit: the header's
 * reference function and the definition spelled out above, for every
 * dimension 2..63, several seeds, and indices up to 2^32 - 1. */
static void halton_tables_equal_hashing_definition(void **state)
{
    (void)state;
    static const uint32_t seeds[] = {0, 1, 0xdeadbeefu, 12345, 0xffffffffu};
    static uint32_t idx[3000];
    for (size_t t = 0; t < sizeof seeds / sizeof seeds[0]; t++) {
        uint32_t *w = NULL;
        size_t words = 0;
        assert_int_equal(st_sampling_halton_tables(seeds[t], &w, &words, NULL), ST_OK);
        for (uint32_t dim = 2; dim < 64; dim++) {
            uint32_t b = nth_prime(dim), key = lowbias32(seeds[t] ^ lowbias32(dim));
            uint32_t m = table_test_indices(b, idx);
            for (uint32_t j = 0; j < m; j++) {
                float want = scrambled_definition(b, idx[j], key);
                assert_float_same(st_radical_inverse_scrambled(b, idx[j], key), want,
                                  "hashing, seed %u dim %u n %u", seeds[t], dim, idx[j]);
                assert_float_same(st_halton_permuted(w, dim, idx[j]), want,
                                  "tables, seed %u dim %u n %u", seeds[t], dim, idx[j]);
            }
        }
        free(w);
    }
}

/* st_halton_dim with the render's tables (as generate.cl and shade.cl read
 * them) equals it without (hashing) in every dimension, the pixel ones
 * included, and those equal the definition with the pixel's key: images
 * whose indices reach far (large spp) and the pattern's 1 x 1 image. */
static void halton_dims_with_tables_equal_hashing(void **state)
{
    (void)state;
    static const uint32_t sizes[][3] = {{64, 48, 4096}, {1, 1, 65536}, {200, 130, 1000}};
    for (size_t t = 0; t < 3; t++)
        for (uint32_t seed = 3; seed < 5; seed++) {
            st_params hashed = image_params(ST_SAMPLER_HALTON, sizes[t][0], sizes[t][1],
                                            sizes[t][2], 1, seed);
            st_params tabled = hashed;
            uint32_t *w = NULL;
            size_t words = 0;
            assert_int_equal(st_sampling_halton_tables(seed, &w, &words, NULL), ST_OK);
            tabled.halton_tables = 1;
            uint32_t rs = seed * 7919u;
            for (uint32_t j = 0; j < 400; j++) {
                uint32_t px = next_random(&rs) % hashed.width, py = next_random(&rs) % hashed.height;
                uint32_t s = j < 4 ? j : (j < 8 ? hashed.spp - 1 - (j - 4) : next_random(&rs) % hashed.spp);
                st_sample_id a = st_sample_begin(&hashed, px, py, s);
                st_sample_id b = st_sample_begin(&tabled, px, py, s);
                b.pmj02 = w;
                for (uint32_t d = 0; d < 70; d++)
                    assert_float_same(st_sample_dim(&tabled, &b, d), st_sample_dim(&hashed, &a, d),
                                      "%ux%u seed %u pixel (%u,%u) s %u dim %u", hashed.width,
                                      hashed.height, seed, px, py, s, d);
                uint32_t n0 = a.index >> hashed.halton_exp2;
                uint32_t n1 = a.index / (hashed.halton_stride >> hashed.halton_exp2);
                uint32_t pk = st_pixel_key(&hashed, a.pixel);
                assert_float_same(st_sample_dim(&hashed, &a, 1),
                                  scrambled_definition(3, n1, st_pair_key(pk, 1) ^ 1u),
                                  "pixel dim 1, pixel (%u,%u) s %u", px, py, s);
                float d0 = (float)((st_reverse_bits(n0) ^ lowbias32(st_pair_key(pk, 0))) >> 8) *
                           0x1p-24f;
                assert_float_same(st_sample_dim(&hashed, &a, 0), d0, "pixel dim 0, (%u,%u) s %u",
                                  px, py, s);
            }
            free(w);
        }
}

/* Every sampler, scrambled or not, gives values in [0, 1) in every dimension,
 * including dimensions past the prime table (random fallback). */
static void samplers_values_in_unit_interval(void **state)
{
    (void)state;
    static const uint32_t counts[] = {1, 7, 16, 100};
    for (uint32_t sampler = 0; sampler < ST_SAMPLER_COUNT; sampler++)
        for (uint32_t scramble = 0; scramble < 2; scramble++)
            for (size_t c = 0; c < 4; c++) {
                st_params p = image_params(sampler, 3, 3, counts[c], scramble, 42);
                for (uint32_t pix = 0; pix < 9; pix++)
                    for (uint32_t s = 0; s < counts[c]; s++)
                        for (uint32_t d = 0; d < 70; d++) {
                            float x = sample_value(&p, pix % 3, pix / 3, s, d);
                            if (!(x >= 0.0f && x < 1.0f))
                                fail_msg("sampler %u scramble %u pixel %u sample %u dim %u: %a",
                                         sampler, scramble, pix, s, d, (double)x);
                            /* a pure function: the same arguments, the same value */
                            assert_float_same(sample_value(&p, pix % 3, pix / 3, s, d), x,
                                              "repeat");
                        }
            }
}

/* st_sample_resume, which shade uses, resumes every sampler's sample from
 * the key and word that generate carried in the sample record (st_sample):
 * the same identity as st_sample_begin's, and the same value in every
 * dimension, the two pixel dimensions included, with and without
 * scrambling (pmj02 and pmj02bn with their tables). */
static void sample_resume_matches_begin(void **state)
{
    (void)state;
    const uint32_t w = 5, h = 3, spp = 16;
    st_u32 *pmj02 = NULL, *bn = NULL;
    size_t words = 0;
    st_error err = {0};
    if (st_sampling_pmj02(4, ST_PMJ02_SETS, 7, &pmj02, &err) != ST_OK ||
        st_sampling_pmj02bn_tables(spp, 7, &bn, &words, &err) != ST_OK)
        fail_msg("%s", err.msg);
    for (uint32_t sampler = 0; sampler < ST_SAMPLER_COUNT; sampler++)
        for (uint32_t scramble = 0; scramble < 2; scramble++) {
            st_params p = image_params(sampler, w, h, spp, scramble, 7);
            st_u32 *tables = sampler == ST_SAMPLER_PMJ02BN ? bn : pmj02;
            for (uint32_t pix = 0; pix < w * h; pix++)
                for (uint32_t s = 0; s < spp; s++) {
                    st_sample_id a = st_sample_begin(&p, pix % w, pix / w, s);
                    st_sample_id b =
                        st_sample_resume(&p, pix, s, a.key, st_sample_word(&p, &a));
                    a.pmj02 = b.pmj02 = tables;
                    assert_int_equal(a.pixel, b.pixel);
                    assert_int_equal(a.sample, b.sample);
                    assert_int_equal(a.key, b.key);
                    assert_int_equal(a.pixel_key, b.pixel_key);
                    assert_int_equal(a.index, b.index);
                    for (uint32_t d = 0; d < 24; d++)
                        if (st_sample_dim(&p, &a, d) != st_sample_dim(&p, &b, d))
                            fail_msg("sampler %u scramble %u pixel %u sample %u dim %u",
                                     sampler, scramble, pix, s, d);
                }
        }
    free(pmj02);
    free(bn);
}

/* Tiled samplers pad their later dimensions with their own pattern
 * (st_sampling_pad_tables): in every pixel and every pair of dimensions
 * past the film's, the spp samples are a toroidal shift of one of the
 * sampler's one-pixel tiles, so their smallest toroidal distance x sqrt(spp)
 * is that of a blue-noise pattern (best-candidate and Poisson: >= 0.5,
 * measured 0.55..0.8), where the random hash these dimensions took before
 * gives about 0.66 / sqrt(spp) (0.08 at 64 spp; 0.5 fails it at 16 and 64
 * spp for nearly every pixel). Pairs and pixels differ (a sample's light
 * pair is not its BSDF pair); every value lies in [0, 1). Without tables
 * (a host caller that gives none) the hash stands. */
static void tiled_samplers_pad_with_their_pattern(void **state)
{
    (void)state;
    const uint32_t samplers[2] = {ST_SAMPLER_BEST_CANDIDATE, ST_SAMPLER_POISSON};
    const uint32_t spps[3] = {16, 64, 1500};
    float *xy = malloc(sizeof(float) * 2 * 1500);
    for (int k = 0; k < 2; k++)
        for (int q = 0; q < 3; q++) {
            uint32_t spp = spps[q], n = spp < ST_PAD_MAX_POINTS ? spp : ST_PAD_MAX_POINTS;
            st_u32 *words = NULL, count = 0;
            st_error err = {0};
            if (st_sampling_pad_tables(samplers[k], spp, 3, &words, &count, &err) != ST_OK)
                fail_msg("%s", err.msg);
            assert_int_equal(count, n);
            st_params p = image_params(samplers[k], 6, 5, spp, 1, 3);
            double worst = INFINITY;
            for (uint32_t pix = 0; pix < 30; pix += 7)
                for (uint32_t d = 2; d < 10; d += 2) {
                    /* n samples of a block: one shifted set (past n, a block) */
                    for (uint32_t s = 0; s < n; s++) {
                        st_sample_id id = st_sample_begin(&p, pix % 6, pix / 6, s);
                        id.pmj02 = words;
                        xy[2 * s] = st_sample_dim(&p, &id, d);
                        xy[2 * s + 1] = st_sample_dim(&p, &id, d + 1);
                        assert_true(xy[2 * s] >= 0.0f && xy[2 * s] < 1.0f);
                        assert_true(xy[2 * s + 1] >= 0.0f && xy[2 * s + 1] < 1.0f);
                        st_sample_id other = st_sample_begin(&p, pix % 6, pix / 6, s);
                        other.pmj02 = NULL; /* without tables: the random hash */
                        assert_true(st_sample_dim(&p, &other, d) == st_rng_unit(other.key, d));
                    }
                    if (spp == n) { /* a permutation of one set, shifted: its spacing */
                        double md = st_min_distance_2d(xy, n, 1) * sqrt((double)n);
                        worst = md < worst ? md : worst;
                    }
                    st_sample_id a = st_sample_begin(&p, pix % 6, pix / 6, 0);
                    a.pmj02 = words;
                    assert_true(st_sample_dim(&p, &a, d) != st_sample_dim(&p, &a, d + 2));
                }
            if (spp == n && !(worst >= 0.5))
                fail_msg("%s spp %u: smallest toroidal distance x sqrt(spp) %.3f",
                         st_sampler_names[samplers[k]], spp, worst);
            free(words);
        }
    free(xy);
}

/* ---- rng ------------------------------------------------------------------------------ */

static void rng_unit_in_range(void **state)
{
    (void)state;
    assert_float_same(st_u32_to_unit(0u), 0.0f, "u32 0");
    assert_float_same(st_u32_to_unit(255u), 0.0f, "u32 255");
    assert_float_same(st_u32_to_unit(256u), 0x1p-24f, "u32 256");
    assert_float_same(st_u32_to_unit(0xffffffffu), 0x1.fffffep-1f, "u32 max");
    for (uint32_t j = 0; j < 1000000; j++) {
        float u = st_rng_unit(st_rng_key(j % 7, j, j / 3), j % 13);
        assert_true(u >= 0.0f && u < 1.0f);
    }
}

/* Pearson's chi-square over 64 equal bins of [0, 1), 10^6 draws: 63 degrees of
 * freedom; the statistic must lie between the 0.001 and 0.999 quantiles of
 * χ²(63), 33.906 and 103.442 (too uniform fails as well as too clumped). */
static double chi_square(float (*draw)(uint32_t), uint32_t n)
{
    uint32_t bins[64] = {0};
    for (uint32_t j = 0; j < n; j++)
        bins[cell_of(draw(j), 64)]++;
    double expect = n / 64.0, chi = 0.0;
    for (int b = 0; b < 64; b++)
        chi += (bins[b] - expect) * (bins[b] - expect) / expect;
    return chi;
}

static float draw_over_pixels_samples(uint32_t j)
{
    return st_rng_unit(st_rng_key(1u, j % 4096u, j / 4096u), 3u);
}

static float draw_over_dims(uint32_t j)
{
    return st_rng_unit(st_rng_key(7u, 12u, 5u), j);
}

static float draw_over_seeds(uint32_t j)
{
    return st_rng_unit(st_rng_key(j, 0u, 0u), 0u);
}

static void rng_chi_square_uniform(void **state)
{
    (void)state;
    float (*draws[3])(uint32_t) = {draw_over_pixels_samples, draw_over_dims, draw_over_seeds};
    for (int k = 0; k < 3; k++) {
        double chi = chi_square(draws[k], 1000000u);
        if (!(chi > 33.906 && chi < 103.442))
            fail_msg("stream %d: chi-square %.2f outside [33.906, 103.442]", k, chi);
    }
}

/* Streams that differ in one of (seed, pixel, sample, dim) are uncorrelated:
 * Pearson's r over N = 10^5 pairs. Under independence r has standard deviation
 * 1/sqrt(N) = 0.0032; the tolerance |r| < 0.02 is 6.3 of them. The streams are
 * also not shifted copies of each other (lag-1 r as well). */
typedef struct rng_args { uint32_t seed, pixel, sample, dim; } rng_args;

static float stream_value(rng_args a, uint32_t j)
{
    /* the stream runs over the sample index (or the pixel, when sample is fixed) */
    if (a.sample == 0xffffffffu)
        return st_rng_unit(st_rng_key(a.seed, a.pixel, j), a.dim);
    return st_rng_unit(st_rng_key(a.seed, j, a.sample), a.dim);
}

static double correlation(rng_args a, rng_args b, uint32_t lag)
{
    const uint32_t n = 100000;
    double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
    for (uint32_t j = 0; j < n; j++) {
        double x = stream_value(a, j), y = stream_value(b, j + lag);
        sa += x;
        sb += y;
        saa += x * x;
        sbb += y * y;
        sab += x * y;
    }
    double cov = sab / n - (sa / n) * (sb / n);
    return cov / sqrt((saa / n - (sa / n) * (sa / n)) * (sbb / n - (sb / n) * (sb / n)));
}

static void rng_streams_uncorrelated(void **state)
{
    (void)state;
    const uint32_t over_samples = 0xffffffffu;
    const rng_args pairs[][2] = {
        {{1, 5, over_samples, 0}, {2, 5, over_samples, 0}}, /* seed */
        {{1, 5, over_samples, 0}, {1, 6, over_samples, 0}}, /* pixel */
        {{1, 5, over_samples, 0}, {1, 5, over_samples, 1}}, /* dim */
        {{1, 5, over_samples, 0}, {1, 5, over_samples, 2}},
        {{0, 0, over_samples, 0}, {1, 0, over_samples, 0}},
        {{1, 0, 0, 0}, {1, 0, 1, 0}}, /* sample (stream over pixels) */
        {{1, 0, 0, 4}, {1, 0, 2, 4}},
    };
    for (size_t k = 0; k < sizeof pairs / sizeof pairs[0]; k++)
        for (uint32_t lag = 0; lag < 2; lag++) {
            double r = correlation(pairs[k][0], pairs[k][1], lag);
            if (!(fabs(r) < 0.02))
                fail_msg("pair %zu lag %u: correlation %.4f, |r| must be < 0.02", k, lag, r);
        }
    /* a stream against itself, one step later */
    double r = correlation(pairs[0][0], pairs[0][0], 1);
    if (!(fabs(r) < 0.02))
        fail_msg("lag-1 autocorrelation %.4f, |r| must be < 0.02", r);
}

/* Streams that differ in one argument are not shifted copies of each other
 * (as with a key like sample + 4096 pixel): of 10^5 32-bit values of one
 * stream, how many occur in the other? Independent streams share about
 * 10^10 / 2^32 = 2.3; the limit is 20. */
static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

static void rng_streams_share_no_values(void **state)
{
    (void)state;
    enum { N = 100000 };
    static uint32_t a[N], b[N];
    /* (seed, pixel, sample over j, dim) against one argument changed */
    const uint32_t base[4] = {1, 5, 0, 0};
    const uint32_t other[][4] = {{2, 5, 0, 0}, {1, 6, 0, 0}, {1, 5, 0, 1}, {1, 5 + 4096, 0, 0},
                                 {1, 5, 0, 2}, {1 + 4096, 5, 0, 0}};
    for (uint32_t j = 0; j < N; j++)
        a[j] = st_rng_u32(st_rng_key(base[0], base[1], j), base[3]);
    qsort(a, N, sizeof *a, cmp_u32);
    for (size_t k = 0; k < sizeof other / sizeof other[0]; k++) {
        for (uint32_t j = 0; j < N; j++)
            b[j] = st_rng_u32(st_rng_key(other[k][0], other[k][1], j), other[k][3]);
        qsort(b, N, sizeof *b, cmp_u32);
        uint32_t shared = 0;
        for (size_t i = 0, l = 0; i < N && l < N;) {
            if (a[i] < b[l])
                i++;
            else if (a[i] > b[l])
                l++;
            else {
                shared++;
                i++;
                l++;
            }
        }
        if (shared > 20)
            fail_msg("streams (seed %u, pixel %u, dim %u) and (%u, %u, %u) share %u values", base[0],
                     base[1], base[3], other[k][0], other[k][1], other[k][3], shared);
    }
}

/* The mixing function avalanches (Wellons' criterion): flipping input bit i
 * flips output bit j with probability 1/2. Over 10^5 random inputs each of the
 * 32 x 32 frequencies has standard deviation 0.0016; the limit |p - 1/2| <
 * 0.01 is 6 of them (lowbias32 measures 0.0055 at worst; dropping one of its
 * multiplications gives 0.5). */
static void rng_hash_avalanche(void **state)
{
    (void)state;
    static uint32_t flips[32][32];
    uint32_t seed = 5u;
    const uint32_t n = 100000;
    for (uint32_t k = 0; k < n; k++) {
        uint32_t x = next_random(&seed), y = st_hash32(x);
        for (int i = 0; i < 32; i++) {
            uint32_t d = y ^ st_hash32(x ^ (1u << i));
            for (int j = 0; j < 32; j++)
                flips[i][j] += (d >> j) & 1u;
        }
    }
    for (int i = 0; i < 32; i++)
        for (int j = 0; j < 32; j++) {
            double pr = flips[i][j] / (double)n;
            if (!(fabs(pr - 0.5) < 0.01))
                fail_msg("input bit %d flips output bit %d with probability %.4f", i, j, pr);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(tiled_samplers_pad_with_their_pattern),
        cmocka_unit_test(radical_inverse_is_largest_float_below_exact),
        cmocka_unit_test(radical_inverse_base2_equals_bit_reversal),
        cmocka_unit_test(ratio_floor_ceil_bracket_exact_value),
        cmocka_unit_test(bits_to_unit_is_largest_float_below),
        cmocka_unit_test(halton_pattern_equals_radical_inverses),
        cmocka_unit_test(hammersley_pattern_equals_definition),
        cmocka_unit_test(halton_index_lands_in_its_pixel),
        cmocka_unit_test(halton_index_large_samples_in_pixel),
        cmocka_unit_test(stratified_grid_is_most_square_factorisation),
        cmocka_unit_test(stratified_one_point_per_stratum),
        cmocka_unit_test(stratified_coord_stays_in_cell_at_extreme_jitter),
        cmocka_unit_test(stratified_jitter_uniform_within_cell),
        cmocka_unit_test(uniform_pattern_is_cell_centres),
        cmocka_unit_test(permute_is_bijection),
        cmocka_unit_test(permute_keys_give_different_permutations),
        cmocka_unit_test(permute_uniform_over_keys),
        cmocka_unit_test(sobol_equals_direction_numbers),
        cmocka_unit_test(sobol_pattern_is_0m2_net),
        cmocka_unit_test(sobol_owen_scrambled_is_0m2_net),
        cmocka_unit_test(sobol_scrambled_differs_by_seed_and_pixel),
        cmocka_unit_test(sobol_global_index_lands_in_its_pixel),
        cmocka_unit_test(sobol_global_dimensions_stratified),
        cmocka_unit_test(zsobol_pixel_pairs_are_nets),
        cmocka_unit_test(zsobol_index_is_bijection),
        cmocka_unit_test(joint_stratified_pairs_are_stratified),
        cmocka_unit_test(halton_scrambled_keeps_stratification),
        cmocka_unit_test(hammersley_scrambled_keeps_stratification),
        cmocka_unit_test(hammersley_rotation_one_point_per_interval),
        cmocka_unit_test(halton_hammersley_scrambled_differ_by_seed_and_pixel),
        cmocka_unit_test(division_constants_divide_exactly),
        cmocka_unit_test(halton_tables_layout),
        cmocka_unit_test(halton_tables_equal_hashing_definition),
        cmocka_unit_test(halton_dims_with_tables_equal_hashing),
        cmocka_unit_test(samplers_values_in_unit_interval),
        cmocka_unit_test(sample_resume_matches_begin),
        cmocka_unit_test(rng_unit_in_range),
        cmocka_unit_test(rng_chi_square_uniform),
        cmocka_unit_test(rng_streams_uncorrelated),
        cmocka_unit_test(rng_streams_share_no_values),
        cmocka_unit_test(rng_hash_avalanche),
    };
    return cmocka_run_group_tests_name("samplers", tests, NULL, NULL);
}
