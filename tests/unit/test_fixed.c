/* test_fixed.c — guards kernels/shared/fixed.h, the 64-bit fixed-point film sums.
 *
 * A value v is stored as round(v 2^24), ties to even. The expected integer is
 * computed here exactly from v's mantissa and exponent (frexpf), with the
 * round-half-even rule written out, and compared bit for bit; the round trip
 * |st_fixed_from_float(v) / 2^24 - v| <= 2^-25 is checked in exact integers.
 * Headroom is checked in exact 128-bit integers: ST_FIXED_MAX_SPLATS splats of
 * the largest value, ±ST_SPLAT_MAX, must fit a signed 64-bit sum. Finally the
 * test shows why the film sums integers: the same values summed as floats in
 * two orders give two answers, while the fixed-point sums agree. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>

#include "st_shared.h"
#include "fixed.h"

typedef __int128 i128;

/* xorshift32 (Marsaglia, "Xorshift RNGs", J. Stat. Software 2003): test inputs only. */
static uint32_t next_random(uint32_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return *s;
}

/* round(v 2^24), ties to even, from v = ±m 2^e exactly (m < 2^24 an integer). */
static int64_t expected_fixed(float v)
{
    if (v == 0.0f)
        return 0;
    int ex;
    float fr = frexpf(fabsf(v), &ex);          /* |v| = fr 2^ex, fr in [0.5, 1) */
    int64_t m = (int64_t)ldexpf(fr, 24);        /* |v| = m 2^(ex - 24) */
    int shift = ex - 24 + ST_FIXED_SHIFT;       /* |v| 2^24 = m 2^shift */
    int64_t q;
    if (shift >= 0) {
        q = m << shift;
    } else if (shift < -40) {
        q = 0; /* below 2^-16 units: rounds to 0 */
    } else {
        int s = -shift;
        int64_t floor_q = m >> s, rem = m & (((int64_t)1 << s) - 1), half = (int64_t)1 << (s - 1);
        q = floor_q + (rem > half || (rem == half && (floor_q & 1)));
    }
    return v < 0 ? -q : q;
}

/* A random float ±m 2^e with |v| <= ST_SPLAT_MAX, e spread over -40..16. */
static float random_value(uint32_t *s)
{
    float m = (float)(next_random(s) >> 8) * 0x1p-24f; /* [0, 1) */
    int e = (int)(next_random(s) % 57) - 40;
    float v = ldexpf(m, e);
    return (next_random(s) & 1u) ? -v : v;
}

static void fixed_round_trip_within_half_unit(void **state)
{
    (void)state;
    uint32_t seed = 2463534242u;
    for (int j = 0; j < 1000000; j++) {
        float v = random_value(&seed);
        int64_t got = st_fixed_from_float(v);
        if (got != expected_fixed(v))
            fail_msg("fixed(%a) = %lld, expected %lld", (double)v, (long long)got,
                     (long long)expected_fixed(v));
        /* |got - v 2^24| <= 1/2, i.e. |got/2^24 - v| <= 2^-25, in exact integers:
         * with |v| 2^24 = m 2^-s, that is 2 |got| 2^s - 2m in [-2^s, 2^s] */
        if (v == 0.0f) {
            assert_true(got == 0);
            continue;
        }
        int ex;
        int64_t m = (int64_t)ldexpf(frexpf(fabsf(v), &ex), 24);
        int s = -(ex - 24 + ST_FIXED_SHIFT);
        if (s <= 0) {
            assert_true(got == (v < 0 ? -(m << -s) : (m << -s))); /* an integer number of units */
        } else if (s < 80) {
            i128 diff = 2 * ((i128)(got < 0 ? -got : got) << s) - 2 * (i128)m;
            i128 bound = (i128)1 << s;
            if (!(diff >= -bound && diff <= bound))
                fail_msg("fixed(%a) = %lld is more than 2^-25 away", (double)v, (long long)got);
        }
    }
    /* the extremes */
    assert_true(st_fixed_from_float(ST_SPLAT_MAX) == (int64_t)1 << 40);
    assert_true(st_fixed_from_float(-ST_SPLAT_MAX) == -((int64_t)1 << 40));
    assert_true(st_fixed_from_float(0x1p-24f) == 1);
    assert_true(st_fixed_from_float(0x1p-26f) == 0);
}

/* Multiples of 2^-24 (with at most 24 significant bits) are stored exactly. */
static void fixed_exact_for_multiples_of_unit(void **state)
{
    (void)state;
    uint32_t seed = 99u;
    for (int j = 0; j < 200000; j++) {
        int64_t k = (int64_t)(next_random(&seed) >> 8) << (next_random(&seed) % 17); /* < 2^40 */
        if (j & 1)
            k = -k;
        float v = ldexpf((float)k, -24); /* exact: k has at most 24 significant bits */
        assert_true(st_fixed_from_float(v) == k);
        assert_true((double)st_fixed_from_float(v) / ST_FIXED_SCALE == (double)v);
    }
}

/* Halfway cases go to the even integer: 0.5 -> 0, 1.5 -> 2, 2.5 -> 2, -0.5 -> 0... */
static void fixed_ties_round_to_even(void **state)
{
    (void)state;
    for (int64_t k = -4096; k < 4096; k++) {
        float v = ldexpf((float)(2 * k + 1), -25); /* (k + 1/2) units, exact */
        int64_t even = (k % 2 == 0) ? k : k + 1;   /* k or k + 1, whichever is even */
        if (st_fixed_from_float(v) != even)
            fail_msg("fixed(%a) = %lld, expected %lld (ties to even)", (double)v,
                     (long long)st_fixed_from_float(v), (long long)even);
    }
    assert_true(st_fixed_from_float(0x1p-25f) == 0);
    assert_true(st_fixed_from_float(0x3p-25f) == 2);
    assert_true(st_fixed_from_float(0x5p-25f) == 2);
    assert_true(st_fixed_from_float(-0x1p-25f) == 0);
    assert_true(st_fixed_from_float(-0x3p-25f) == -2);
    /* the largest tie a float can hold: 0.5 - 2^-25 = (2^23 - 1/2) units -> 2^23 */
    assert_true(st_fixed_from_float(0x1.fffffep-2f) == (1 << 23));
}

/* Clamping at ±ST_SPLAT_MAX: values inside (including the bounds) pass
 * unchanged and unflagged; values beyond, and infinities, are clamped and
 * flagged. The flag is sticky: it is only ever set, never cleared. */
static void fixed_clamp_flags_only_when_clamping(void **state)
{
    (void)state;
    const float inside[] = {0.0f, -0.0f, 1.0f, -1.0f, 1e-30f, ST_SPLAT_MAX, -ST_SPLAT_MAX,
                            nextafterf(ST_SPLAT_MAX, 0.0f), 12345.678f};
    for (size_t i = 0; i < sizeof inside / sizeof inside[0]; i++) {
        st_u32 flag = 0;
        assert_true(st_fixed_clamp(inside[i], &flag) == inside[i]);
        assert_int_equal(flag, 0);
        flag = 1;
        (void)st_fixed_clamp(inside[i], &flag);
        assert_int_equal(flag, 1);
    }
    const float above[] = {nextafterf(ST_SPLAT_MAX, INFINITY), 65537.0f, 1e30f, INFINITY};
    for (size_t i = 0; i < sizeof above / sizeof above[0]; i++) {
        st_u32 flag = 0;
        assert_true(st_fixed_clamp(above[i], &flag) == ST_SPLAT_MAX);
        assert_int_equal(flag, 1);
        flag = 0;
        assert_true(st_fixed_clamp(-above[i], &flag) == -ST_SPLAT_MAX);
        assert_int_equal(flag, 1);
    }
    /* every clamped value converts to exactly ±2^40 units */
    st_u32 flag = 0;
    assert_true(st_fixed_from_float(st_fixed_clamp(1e30f, &flag)) == (int64_t)1 << 40);
}

/* ST_FIXED_MAX_SPLATS splats of ±ST_SPLAT_MAX fit a signed 64-bit sum; twice as
 * many would not. Exact in 128-bit integers. */
static void fixed_headroom_max_splats_fit_int64(void **state)
{
    (void)state;
    i128 unit_max = st_fixed_from_float(ST_SPLAT_MAX); /* 2^40 */
    i128 splats = (i128)ST_FIXED_MAX_SPLATS;
    assert_true((double)splats == ST_FIXED_MAX_SPLATS); /* an integer */
    i128 top = splats * unit_max, bottom = -splats * unit_max;
    if (!(top <= INT64_MAX && bottom >= INT64_MIN))
        fail_msg("%.0f splats of %g sum to %.0f units: past INT64_MAX = %lld",
                 ST_FIXED_MAX_SPLATS, (double)ST_SPLAT_MAX, (double)top, (long long)INT64_MAX);
    assert_true(2 * splats * unit_max > INT64_MAX);
    /* the bound is tight to within a factor of two: the comment's 2^23 */
    assert_true(ST_FIXED_MAX_SPLATS >= 0x1p22);
}

/* Floats added in two orders differ; the fixed-point sums of the same values
 * agree (integer addition is associative), which is why the film sums
 * integers with atom_add rather than floats in arrival order. */
static void fixed_sum_independent_of_order(void **state)
{
    (void)state;
    enum { N = 4096 };
    static float v[N];
    uint32_t seed = 12345u;
    for (int i = 0; i < N; i++)
        v[i] = random_value(&seed);
    v[0] = ST_SPLAT_MAX; /* a large value absorbs small ones in float */
    float fwd = 0.0f, rev = 0.0f, shuffled = 0.0f;
    int64_t ifwd = 0, irev = 0, ishuf = 0;
    for (int i = 0; i < N; i++) {
        fwd += v[i];
        ifwd += st_fixed_from_float(v[i]);
    }
    for (int i = N - 1; i >= 0; i--) {
        rev += v[i];
        irev += st_fixed_from_float(v[i]);
    }
    /* a shuffle: i -> i * 1031 mod 4096 (1031 odd, so a bijection) */
    for (int i = 0; i < N; i++) {
        shuffled += v[(i * 1031) % N];
        ishuf += st_fixed_from_float(v[(i * 1031) % N]);
    }
    if (fwd == rev && fwd == shuffled)
        fail_msg("float sums agree in every order (%a): the demonstration needs other values",
                 (double)fwd);
    assert_true(ifwd == irev);
    assert_true(ifwd == ishuf);
}

/* The splat's four sums: w L per channel and w, each clamped. The weight is
 * clamped like the values (a huge weight once added unclamped and wrapped
 * Σf), NaN (0 x inf) adds 0 and flags, and ST_FIXED_MAX_SPLATS splats of the
 * largest weight still fit: exact in 128-bit integers. */
static void fixed_splat_clamps_weight_and_values(void **state)
{
    (void)state;
    st_i64 v[4];
    st_u32 flag = 0;
    st_fixed_splat(0.5f, 2.0f, -4.0f, 0.0f, v, &flag);
    assert_int_equal(flag, 0);
    assert_true(v[0] == 1 << 24 && v[1] == -(2 << 24) && v[2] == 0 && v[3] == 1 << 23);
    const float huge[] = {65537.0f, 2.6e5f, 1e30f, INFINITY};
    for (size_t i = 0; i < sizeof huge / sizeof huge[0]; i++)
        for (int sign = -1; sign <= 1; sign += 2) {
            flag = 0;
            st_fixed_splat(sign * huge[i], 1.0f, 0.0f, -1.0f, v, &flag);
            assert_int_equal(flag, 1);
            assert_true(v[3] == sign * ((int64_t)1 << 40));
            assert_true(v[0] == sign * ((int64_t)1 << 40) && v[2] == -v[0]);
            i128 sum = (i128)ST_FIXED_MAX_SPLATS * v[3];
            assert_true(sum <= INT64_MAX && sum >= INT64_MIN);
        }
    flag = 0;
    st_fixed_splat(INFINITY, 0.0f, 1.0f, 1.0f, v, &flag); /* inf x 0 is NaN */
    assert_int_equal(flag, 1);
    assert_true(v[0] == 0 && v[1] == (int64_t)1 << 40 && v[3] == (int64_t)1 << 40);
    flag = 0;
    st_fixed_splat(NAN, 1.0f, 1.0f, 1.0f, v, &flag);
    assert_int_equal(flag, 1);
    assert_true(v[0] == 0 && v[1] == 0 && v[2] == 0 && v[3] == 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fixed_round_trip_within_half_unit),
        cmocka_unit_test(fixed_exact_for_multiples_of_unit),
        cmocka_unit_test(fixed_ties_round_to_even),
        cmocka_unit_test(fixed_clamp_flags_only_when_clamping),
        cmocka_unit_test(fixed_headroom_max_splats_fit_int64),
        cmocka_unit_test(fixed_sum_independent_of_order),
        cmocka_unit_test(fixed_splat_clamps_weight_and_values),
    };
    return cmocka_run_group_tests_name("fixed", tests, NULL, NULL);
}
