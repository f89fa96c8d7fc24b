/* samplers.h — sample positions of every sampler, as pure functions shared by
 * the kernels (generate_rays, shade_hits) and the host (strata pattern, the
 * tests), so that what the laboratory measures is what renders.
 *
 * Dimensions: 0 and 1 are the position inside the pixel; 2, 3, ... feed the
 * integrator (light and BSDF samples; see shade.cl and integrator.h). A sampler's values are a
 * pure function of (params, pixel, sample index, dimension).
 *
 * Definitions (the lecture; pbr-book 4ed ch. 8):
 *   radical inverse  Φ_b(n) = Σ_i d_i b^(-i), n = Σ_i d_i b^(i-1)
 *   Halton           x_i = (Φ2(i), Φ3(i), Φ5(i), ...)
 *   Hammersley       x_i = (i/N, Φ2(i), Φ3(i), ...)
 *   stratified       one jittered point per cell of an nx x ny grid
 * A float result is the largest float <= the exact value, so results stay in
 * [0, 1) and the unscrambled sequences equal the definition to the last bit.
 * Tests: test_sampling_kernels.c. */
#ifndef ST_SAMPLERS_H
#define ST_SAMPLERS_H

#include "rng.h"
#include "sobol_table.h"

#define ST_PRIME_COUNT 64u
ST_CONSTANT st_u32 st_primes[ST_PRIME_COUNT] = {
    2,   3,   5,   7,   11,  13,  17,  19,  23,  29,  31,  37,  41,  43,  47,  53,
    59,  61,  67,  71,  73,  79,  83,  89,  97,  101, 103, 107, 109, 113, 127, 131,
    137, 139, 149, 151, 157, 163, 167, 173, 179, 181, 191, 193, 197, 199, 211, 223,
    227, 229, 233, 239, 241, 251, 257, 263, 269, 271, 277, 281, 283, 293, 307, 311};

/* num/den rounded to a float, down (up = 0: the largest float <= num/den) or
 * up (up = 1: the smallest float >= num/den), for 0 <= num < den < 2^62:
 * binary long division to 24 significant bits (the float mantissa), exact in
 * integers; a remainder left over means num/den lies strictly between q and
 * q + 1 units of the last place. */
ST_FN st_f32 st_ratio_round(st_u64 num, st_u64 den, st_u32 up)
{
    if (num == 0)
        return 0.0f;
    st_i32 e = (st_i32)ST_CLZ64(num) - (st_i32)ST_CLZ64(den);
    num <<= e;
    if (num < den) {
        num <<= 1;
        e++;
    }
    /* den <= num < 2 den: the value is (num/den) * 2^-e with num/den in [1, 2). */
    st_u32 q = 0;
    for (st_u32 i = 0; i < 24u; i++) {
        q <<= 1;
        if (num >= den) {
            q |= 1u;
            num -= den;
        }
        num <<= 1;
    }
    if (up && num != 0u)
        q++; /* 2^24 at most: still exact in a float */
    return ST_LDEXPF((st_f32)q, -(e + 23));
}

ST_FN st_f32 st_ratio_floor(st_u64 num, st_u64 den)
{
    return st_ratio_round(num, den, 0u);
}

ST_FN st_f32 st_ratio_ceil(st_u64 num, st_u64 den)
{
    return st_ratio_round(num, den, 1u);
}

/* Largest float <= bits * 2^-32: keep the 24 leading significant bits. */
ST_FN st_f32 st_bits_to_unit(st_u32 bits)
{
    st_u32 lz = ST_CLZ32(bits);
    if (lz < 8u)
        bits &= ~((1u << (8u - lz)) - 1u);
    return (st_f32)bits * 2.3283064365386963e-10f; /* 2^-32 */
}

ST_FN st_u32 st_reverse_bits(st_u32 x)
{
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
    return (x >> 16) | (x << 16);
}

/* Φ_b(n), exact (see the file comment), for n < 2^32 and b <= 311. */
ST_FN st_f32 st_radical_inverse(st_u32 base, st_u32 n)
{
    if (base == 2u)
        return st_bits_to_unit(st_reverse_bits(n));
    st_u64 rev = 0, den = 1;
    while (n) {
        st_u32 next = n / base;
        rev = rev * base + (n - next * base);
        den *= base;
        n = next;
    }
    return st_ratio_floor(rev, den);
}

/* A pseudo-random permutation of [0, n) evaluated at i (n >= 1): Kensler's
 * hash-based permutation (A. Kensler, "Correlated Multi-Jittered Sampling",
 * Pixar TM 13-01, 2013, §3; pbrt-v4's PermutationElement), with the key hashed
 * first. Invertible steps on the bits below the next power of two (xor with key
 * bits, multiplication by odd constants, xor-shifts of the masked value) are
 * applied until the value falls below n ("cycle walking", Black & Rogaway,
 * "Ciphers with Arbitrary Finite Domains", CT-RSA 2002), then the result is
 * rotated by the key. Every step mixes in key bits, so different keys give
 * different permutations (an earlier version drew each key from only a few
 * hundred permutations at n = 16: test_sampling_kernels.c permute_*). */
ST_FN st_u32 st_permute(st_u32 i, st_u32 n, st_u32 key)
{
    if (n <= 1u)
        return 0u;
    st_u32 w = n - 1u;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    st_u32 p = st_hash32(key);
    do {
        i ^= p;
        i *= 0xe170893du;
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i *= 0x0929eb3fu;
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i *= 1u | p >> 27;
        i *= 0x6935fa69u;
        i ^= (i & w) >> 11;
        i *= 0x74dcb303u;
        i ^= (i & w) >> 2;
        i *= 0x9e501cc3u;
        i ^= (i & w) >> 2;
        i *= 0xc860a3dfu;
        i &= w;
        i ^= i >> 5;
    } while (i >= n);
    return (i + p) % n;
}

/* Scrambled radical inverses (Braaten & Weller 1979; pbrt-v4's
 * DigitPermutation): digit position k goes through the affine permutation
 * d -> (a d + c) mod b of [0, b), a in 1..b-1 and c in 0..b-1 drawn from
 * (key, k). Affine maps are all 2 permutations of base 2 and all 6 of base 3,
 * a random subset beyond; each is a bijection per digit, so every elementary
 * interval still holds the same number of points. Digits past n's own are
 * zeros permuted too, taken until they cannot change 24 bits (b^k >= 2^24).
 * The result keeps 24 fraction bits: floor(x 2^24) 2^-24, so it is < 1 (the
 * exact rounding of st_radical_inverse is for the unscrambled definition;
 * here it would cost a long division per dimension). In base 2 the only
 * affine maps are d -> d xor c: the digits are the reversed bits of n xored
 * with one random word. */

/* The hash that draws digit position k's permutation from key. */
ST_HOT st_u32 st_digit_hash(st_u32 key, st_u32 k)
{
    return st_hash32(key ^ (k * 0x9e3779b9u));
}

/* The permutation's c in 0..b-1 from its hash, by multiply-shift (no
 * division): the image of the digit 0. */
ST_HOT st_u32 st_digit_offset(st_u32 base, st_u32 h)
{
    return ((h & 0xffffu) * base) >> 16;
}

/* The image of digit d at position k under the affine permutation that key
 * draws (st_sampling_halton_tables tabulates it). */
ST_HOT st_u32 st_scrambled_digit(st_u32 base, st_u32 key, st_u32 k, st_u32 d)
{
    st_u32 h = st_digit_hash(key, k), a = 1u + (((h >> 16) * (base - 1u)) >> 16);
    return (a * d + st_digit_offset(base, h)) % base;
}

/* rev / den as 24 fraction bits, rounded down: rev < den, both kept in 40
 * bits so that rev 2^24 stays below 2^64. */
ST_FN st_f32 st_digits_to_unit(st_u64 rev, st_u64 den)
{
    while (den >= (1ul << 40)) {
        rev >>= 8;
        den >>= 8;
    }
    return (st_f32)((rev << 24) / den) * 5.9604644775390625e-8f; /* 2^-24 */
}

/* Φ_b(n) with random digit permutations: the definition, hashing per digit
 * (the pixel dimensions, whose key is per pixel, and the reference that
 * the tables of st_radical_inverse_permuted must equal). The digits past
 * n's own are zeros: their images are the permutations' c, without a
 * multiply or a division. Forced inline so that Halton's dimension 1 (base
 * 3) divides by a constant. */
ST_HOT st_f32 st_radical_inverse_scrambled_at(st_u32 base, st_u32 n, st_u32 key)
{
    if (base == 2u)
        return (st_f32)((st_reverse_bits(n) ^ st_hash32(key)) >> 8) * 5.9604644775390625e-8f;
    st_u64 rev = 0, den = 1;
    st_u32 k = 0;
    for (; n != 0u; k++) {
        st_u32 next = n / base;
        rev = rev * base + st_scrambled_digit(base, key, k, n - next * base);
        den *= base;
        n = next;
    }
    for (; den < (1ul << 24); k++) {
        rev = rev * base + st_digit_offset(base, st_digit_hash(key, k));
        den *= base;
    }
    return st_digits_to_unit(rev, den);
}

ST_FN st_f32 st_radical_inverse_scrambled(st_u32 base, st_u32 n, st_u32 key)
{
    return st_radical_inverse_scrambled_at(base, n, key);
}

/* The digit positions st_radical_inverse_scrambled reaches in base b >= 3
 * for a 32-bit n: the digits of 2^32 - 1, the most any n has (b^K >
 * 2^32 - 1 >= b^(K-1)); b^K >= 2^24 too, so the zeros taken past n's own
 * digits stay among them. */
ST_FN st_u32 st_scrambled_digit_count(st_u32 base)
{
    st_u32 k = 0;
    for (st_u64 v = 1; v <= 0xffffffffull; v *= base)
        k++;
    return k;
}

/* n / b for every 32-bit n by a multiply and a shift, floor((n m + add)
 * 2^-s), with m, add and s from st_division_constants (made on the host and
 * stored with the tables, so no division per call). */
ST_HOT st_u32 st_divide_by_constants(st_u32 n, st_u32 m, st_u32 add, st_u32 s)
{
    return (st_u32)(((st_u64)n * m + add) >> s);
}

/* st_divide_by_constants' constants for the divisor b (3 <= b < 2^31, not
 * a power of two): s = 32 + floor(log2 b). Rounding 2^s / b up to m (error
 * e = m b - 2^s) gives n m 2^-s = n/b + n e / (b 2^s), which stays below
 * floor(n/b) + 1 while n e < 2^s, so for every n < 2^32 where e <=
 * 2^(s-32); otherwise rounding down (f = 2^s - m b = b - e < 2^(s-32),
 * as b < 2^(s-31)) and adding m, (n + 1) m 2^-s = (n + 1)/b - (n + 1) f /
 * (b 2^s), lies in [floor(n/b), floor(n/b) + 1) (Robison, "N-bit unsigned
 * division via N-bit multiply-add", ARITH 2005). m < 2^32 and n m + m <=
 * 2^32 m, so nothing overflows 64 bits. */
ST_FN void st_division_constants(st_u32 b, st_u32 *m, st_u32 *add, st_u32 *s)
{
    st_u32 l = 31u - ST_CLZ32(b);
    st_u64 p = 1ull << (32u + l), up = p / b + 1u;
    *s = 32u + l;
    if (up * b - p <= (1ull << l)) {
        *m = (st_u32)up;
        *add = 0u;
    } else {
        *m = (st_u32)(p / b);
        *add = *m;
    }
}

/* st_radical_inverse_scrambled(base, n, key) read from the table of its
 * digit permutations: perm[k b + d] = st_scrambled_digit(base, key, k, d)
 * for k < st_scrambled_digit_count(base) (st_sampling_halton_tables), so
 * no hash and no modulo per digit, and n / base by st_divide_by_constants
 * with (m, add, s) = st_division_constants(base); equal to the hashing
 * definition for every n (test_sampling_kernels.c halton_tables_*). */
ST_FN st_f32 st_radical_inverse_permuted(st_u32 base, st_u32 n, const ST_GLOBAL st_u16 *perm,
                                         st_u32 m, st_u32 add, st_u32 s)
{
    st_u64 rev = 0, den = 1;
    for (; n != 0u; perm += base) {
        st_u32 next = st_divide_by_constants(n, m, add, s);
        rev = rev * base + perm[n - next * base];
        den *= base;
        n = next;
    }
    for (; den < (1ul << 24); perm += base) {
        rev = rev * base + perm[0];
        den *= base;
    }
    return st_digits_to_unit(rev, den);
}

/* Nested uniform (Owen) scrambling of a base-2 digit string held with its
 * first digit in the most significant bit, by the hash of Burley, "Practical
 * Hash-based Owen Scrambling", JCGT 9(4), 2020 (after Laine & Karras 2011):
 * each output bit depends only on the bits above it, so every elementary
 * interval is mapped to an elementary interval (stratification survives). */
ST_FN st_u32 st_owen_scramble(st_u32 v, st_u32 seed)
{
    v = st_reverse_bits(v);
    v += seed;
    v ^= v * 0x6c50b47cu;
    v ^= v * 0xb82f1e52u;
    v ^= v * 0xc7afe638u;
    v ^= v * 0x8d22f6e6u;
    return st_reverse_bits(v);
}

/* Sobol' (0,2)-sequence: dimension 0 is the van der Corput sequence (bit
 * reversal), dimension 1 uses the generator matrix of the primitive polynomial
 * x + 1 (direction numbers v_j = v_{j-1} xor v_{j-1} >> 1; Sobol' 1967). Bits
 * of the result: first digit in the most significant bit. */
ST_FN st_u32 st_sobol_bits(st_u32 i, st_u32 dim)
{
    if (dim == 0u)
        return st_reverse_bits(i);
    st_u32 r = 0, v = 0x80000000u;
    for (; i; i >>= 1, v ^= v >> 1)
        if (i & 1u)
            r ^= v;
    return r;
}

/* Dimension dim (< ST_SOBOL_DIMS) of the Sobol' sequence at index i as 32
 * bits, first digit in the most significant bit: the product of the
 * generator matrix (Joe and Kuo's direction numbers, sobol_table.h) with the
 * bits of i over GF(2). */
ST_FN st_u32 st_sobol_sample_bits(st_u32 i, st_u32 dim)
{
    st_u32 r = 0;
    for (st_u32 k = 0; i; i >>= 1, k++)
        if (i & 1u)
            r ^= st_sobol_matrix[dim * 32u + k];
    return r;
}

/* The h with sum over k of h_k cols[k] = t over GF(2), for n <= 16 linearly
 * independent n-bit columns (Gaussian elimination: each column is reduced
 * by the pivots found so far, remembering which columns it combines). */
ST_FN st_u32 st_gf2_solve(const st_u32 *cols, st_u32 n, st_u32 t)
{
    st_u32 piv[16], tag[16];
    for (st_u32 b = 0; b < n; b++)
        piv[b] = 0u;
    for (st_u32 k = 0; k < n; k++) {
        st_u32 v = cols[k], g = 1u << k;
        for (st_u32 b = n; b-- > 0u;) {
            if (!((v >> b) & 1u))
                continue;
            if (!piv[b]) {
                piv[b] = v;
                tag[b] = g;
                break;
            }
            v ^= piv[b];
            g ^= tag[b];
        }
    }
    st_u32 h = 0;
    for (st_u32 b = n; b-- > 0u;)
        if (((t >> b) & 1u) && piv[b]) {
            t ^= piv[b];
            h ^= tag[b];
        }
    return h;
}

/* Global Sobol' (pbrt-v4's SobolSampler): the image is covered by a 2^m x
 * 2^m grid of pixels (m = p->sobol_log2, 2^m >= width and height), and
 * sample s of pixel (px, py) is the s-th index i of the whole sequence whose
 * first two dimensions, scaled by 2^m, fall in that pixel. The 2^2m indices
 * from s 2^2m on form a (0,2m,2)-net, so each pixel holds exactly one, with
 * low bits L: dimension 0 is the bit reversal, so bits 0..m-1 of L are px
 * reversed; bits m..2m-1 solve the m x m system that the top m digits of
 * dimension 1 equal py. */
ST_FN st_u32 st_sobol_global_index(st_u32 m, st_u32 px, st_u32 py, st_u32 s)
{
    if (m == 0u)
        return s;
    st_u32 lo = st_reverse_bits(px) >> (32u - m);
    st_u32 base = (st_u32)((st_u64)s << (2u * m)) | lo;
    st_u32 t = py ^ (st_sobol_sample_bits(base, 1u) >> (32u - m)), cols[16];
    for (st_u32 k = 0; k < m; k++)
        cols[k] = st_sobol_matrix[32u + m + k] >> (32u - m);
    return base | (st_gf2_solve(cols, m, t) << m);
}

/* Morton code of (x, y) < 2^16: bits of x at even, of y at odd positions. */
ST_FN st_u32 st_morton2(st_u32 x, st_u32 y)
{
    st_u32 v[2] = {x, y};
    for (int k = 0; k < 2; k++) {
        st_u32 a = v[k] & 0xffffu;
        a = (a | (a << 8)) & 0x00ff00ffu;
        a = (a | (a << 4)) & 0x0f0f0f0fu;
        a = (a | (a << 2)) & 0x33333333u;
        v[k] = (a | (a << 1)) & 0x55555555u;
    }
    return v[0] | (v[1] << 1);
}

/* The 24 permutations of {0,1,2,3}, 2 bits per image: entry q maps d to
 * (st_perm4[q] >> 2d) & 3. */
ST_CONSTANT st_u32 st_perm4[24] = {
    0xe4u, 0xb4u, 0xd8u, 0x78u, 0x9cu, 0x6cu, 0xe1u, 0xb1u, 0xc9u, 0x39u, 0x8du, 0x2du,
    0xd2u, 0x72u, 0xc6u, 0x36u, 0x4eu, 0x1eu, 0x93u, 0x63u, 0x87u, 0x27u, 0x4bu, 0x1bu};

/* ceil(log2(n)) for n >= 1. */
ST_FN st_u32 st_log2_ceil(st_u32 n)
{
    return n <= 1u ? 0u : 32u - ST_CLZ32(n - 1u);
}

/* ZSobol (Ahmed and Wonka, "Screen-Space Blue-Noise Diffusion of Monte Carlo
 * Sampling Error via Hierarchical Ordering of Pixels", SIGGRAPH Asia 2020;
 * pbrt-v4's default ZSobolSampler): the pixels in Morton (Z) order take
 * consecutive blocks of 2^l indices (l = ceil(log2 spp)) of one (0,2)-
 * sequence, and every base-4 digit of the index is permuted by a hash of the
 * digits above it and of the pair of dimensions `pair`, so that neighbouring
 * pixels get well-spread parts of the sequence (the error becomes blue
 * noise) while each pixel keeps an aligned block: its 2^l samples of a pair
 * of dimensions are a (0,l,2)-net. With l odd, the lowest bit is flipped by
 * the hash instead. */
ST_FN st_u32 st_zsobol_index(const st_params *p, st_u32 px, st_u32 py, st_u32 s, st_u32 pair)
{
    st_u32 l = st_log2_ceil(p->spp), odd = l & 1u;
    st_u32 z = (st_morton2(px, py) << l) | s, key = 0x55555555u * (pair + 1u) ^ p->seed;
    st_u32 digits = p->sobol_log2 + (l + 1u) / 2u, index = 0;
    for (st_u32 i = digits; i-- > odd;) {
        st_u32 shift = 2u * i - odd, d = (z >> shift) & 3u;
        st_u32 above = shift + 2u < 32u ? z >> (shift + 2u) : 0u;
        st_u32 q = st_hash32(above ^ st_hash32(key ^ shift)) % 24u;
        index |= ((st_perm4[q] >> (2u * d)) & 3u) << shift;
    }
    if (odd)
        index |= (z & 1u) ^ (st_hash32((z >> 1) ^ st_hash32(key)) & 1u);
    return index;
}

/* ---- per-pixel samplers ----------------------------------------------------- */

/* The most nearly square factorisation nx * ny = n with nx <= ny. */
ST_FN void st_stratified_grid(st_u32 n, st_u32 *nx, st_u32 *ny)
{
    st_u32 x = (st_u32)sqrt((float)n);
    while (x > 1u && n % x != 0u)
        x--;
    if (x == 0u)
        x = 1u;
    *nx = x;
    *ny = n / x;
}

/* The sampler fields of st_params (stratified grid, Halton scales) are
 * filled on the host by st_sampler_prepare (src/sampling/sampler.c). */

/* The samplers that read a per-pixel scramble key in every dimension
 * (st_sample_id.pixel_key); Halton and global Sobol' read one only in the
 * two pixel dimensions, and derive it there (st_pixel_key). */
#define ST_SAMPLER_KEYED_PER_PIXEL(s)                                                      \
    ((s) == ST_SAMPLER_STRATIFIED || (s) == ST_SAMPLER_HAMMERSLEY ||                        \
     (s) == ST_SAMPLER_PADDED_SOBOL || (s) == ST_SAMPLER_JOINT_STRATIFIED ||                \
     (s) == ST_SAMPLER_PMJ02 || (s) == ST_SAMPLER_PMJ02BN || ST_SAMPLER_IS_TILED(s))
/* The samplers whose sample s of a pixel is another index of one sequence
 * across the image (st_sample_id.index). */
#define ST_SAMPLER_GLOBAL_INDEX(s) ((s) == ST_SAMPLER_HALTON || (s) == ST_SAMPLER_SOBOL)

/* The per-pixel scramble key of pixel `pixel`. */
ST_FN st_u32 st_pixel_key(const st_params *p, st_u32 pixel)
{
    return st_hash32(st_rng_key(p->seed, pixel, 0xffffffffu));
}

/* One sample's identity, computed once and passed to st_sample_dim. */
typedef struct st_sample_id {
    st_u32 pixel, sample, key; /* key: st_rng_key(seed, pixel, sample) */
    st_u32 pixel_key;          /* st_pixel_key where ST_SAMPLER_KEYED_PER_PIXEL, else 0 */
    st_u32 index;              /* Halton, global Sobol': index of this sample in the sequence */
    st_u32 px, py;             /* the pixel (ZSobol's Morton code) */
    /* the sampler's tables: pmj02's (st_sampling_pmj02), the tiled samplers'
     * pads, or Halton's digit permutations (read where p->halton_tables);
     * NULL: none given */
    const ST_GLOBAL st_u32 *pmj02;
} st_sample_id;

/* The key of a pixel's pair of dimensions (dim / 2): the samplers that
 * shuffle or scramble per (pixel, pair) draw from it. */
ST_FN st_u32 st_pair_key(st_u32 pixel_key, st_u32 dim)
{
    return st_hash32(pixel_key ^ st_hash32(dim >> 1));
}

/* The dimensions a sampler leaves to the counter hash (past its own). */
ST_FN st_f32 st_hashed_dim(const st_sample_id *id, st_u32 dim)
{
    return st_rng_unit(id->key, dim);
}

/* Reverses the first `digits` base-b digits of x (the inverse of the radical
 * inverse on those digits). */
ST_FN st_u32 st_inverse_radical_inverse(st_u32 x, st_u32 base, st_u32 digits)
{
    st_u32 index = 0;
    for (st_u32 i = 0; i < digits; i++) {
        st_u32 next = x / base;
        index = index * base + (x - next * base);
        x = next;
    }
    return index;
}

/* The multiplicative inverse of a modulo m (a and m coprime), by the
 * extended Euclidean algorithm. */
ST_FN st_u32 st_mult_inverse(st_u32 a, st_u32 m)
{
    st_i64 t = 0, nt = 1, r = m, nr = a % m;
    while (nr != 0) {
        st_i64 q = r / nr, tmp = t - q * nt;
        t = nt;
        nt = tmp;
        tmp = r - q * nr;
        r = nr;
        nr = tmp;
    }
    if (t < 0)
        t += m;
    return (st_u32)t;
}

/* Halton's constants of a render (st_params.halton_*, made on the host by
 * st_sampler_prepare): the pixel scales 2^e2 >= width and 3^e3 >= height
 * (each capped at ST_HALTON_MAX_RESOLUTION) make the first two dimensions
 * land one index per pixel per stride; the inverses solve the Chinese
 * remainder problem of st_halton_index. */
ST_FN void st_halton_setup(st_params *p)
{
    st_u32 s2 = 1, e2 = 0, s3 = 1, e3 = 0;
    st_u32 rx = p->width < ST_HALTON_MAX_RESOLUTION ? p->width : ST_HALTON_MAX_RESOLUTION;
    st_u32 ry = p->height < ST_HALTON_MAX_RESOLUTION ? p->height : ST_HALTON_MAX_RESOLUTION;
    while (s2 < rx) {
        s2 *= 2u;
        e2++;
    }
    while (s3 < ry) {
        s3 *= 3u;
        e3++;
    }
    p->halton_exp2 = e2;
    p->halton_exp3 = e3;
    p->halton_stride = s2 * s3;
    p->halton_inv2 = s2 > 1u ? st_mult_inverse(s3 % s2, s2) : 0u;
    p->halton_inv3 = s3 > 1u ? st_mult_inverse(s2 % s3, s3) : 0u;
}

/* Halton index of the pixel's sample: the first two dimensions, scaled by 2^e2
 * and 3^e3, fall in pixel (px mod 128, py mod 128); solved by the Chinese
 * remainder theorem as pbrt-v4's HaltonSampler::StartPixelSample does. */
ST_FN st_u32 st_halton_index(const st_params *p, st_u32 px, st_u32 py, st_u32 s)
{
    st_u32 stride = p->halton_stride;
    if (stride <= 1u)
        return s;
    st_u32 s2 = 1u << p->halton_exp2, s3 = stride / s2;
    st_u32 d2 = st_inverse_radical_inverse(px % ST_HALTON_MAX_RESOLUTION, 2u, p->halton_exp2);
    st_u32 d3 = st_inverse_radical_inverse(py % ST_HALTON_MAX_RESOLUTION, 3u, p->halton_exp3);
    st_u64 h = (st_u64)d2 * s3 * p->halton_inv2 + (st_u64)d3 * s2 * p->halton_inv3;
    return (st_u32)(h % stride) + s * stride;
}

/* The key of Halton's scrambled dimension dim >= 2: one per render and
 * dimension (the pixel dimensions' keys are per pixel: st_halton_dim). */
ST_FN st_u32 st_halton_key(st_u32 seed, st_u32 dim)
{
    return st_hash32(seed ^ st_hash32(dim));
}

/* Halton's digit permutation tables (st_sampling_halton_tables), 32-bit
 * words: word d < ST_PRIME_COUNT is where dimension d's table starts,
 * counted in 16-bit entries from the first word (0 for the pixel
 * dimensions, which have none), words ST_PRIME_COUNT + d, 2 ST_PRIME_COUNT
 * + d and 3 ST_PRIME_COUNT + d its base's st_division_constants m, add
 * and s; the tables follow, 16-bit entries, entry k b + d of dimension
 * dim's the image of digit d at position k under st_halton_key(seed, dim)
 * (st_radical_inverse_permuted). */
#define ST_HALTON_TABLE_HEADER (4u * ST_PRIME_COUNT)

/* Dimension dim (>= 2) of Halton at index n from the tables t. */
ST_FN st_f32 st_halton_permuted(const ST_GLOBAL st_u32 *t, st_u32 dim, st_u32 n)
{
    return st_radical_inverse_permuted(st_primes[dim], n, (const ST_GLOBAL st_u16 *)t + t[dim],
                                       t[ST_PRIME_COUNT + dim], t[2u * ST_PRIME_COUNT + dim],
                                       t[3u * ST_PRIME_COUNT + dim]);
}

/* Halton (pbrt-v4's HaltonSampler): dimension d is the radical inverse in
 * the d-th prime of the sample's index in the sequence (st_halton_index),
 * the pixel dimensions with the pixel's digits shifted out; scrambled,
 * the pixel dimensions per pixel and the others per render, from the
 * render's tables (id->pmj02, where p->halton_tables) or hashed. */
ST_FN st_f32 st_halton_dim(const st_params *p, const st_sample_id *id, st_u32 dim)
{
    if (dim >= ST_PRIME_COUNT)
        return st_hashed_dim(id, dim);
    st_u32 n = id->index;
    if (dim == 0u)
        n >>= p->halton_exp2;
    else if (dim == 1u)
        n /= p->halton_stride >> p->halton_exp2;
    if (!p->scramble)
        return st_radical_inverse(st_primes[dim], n);
    if (dim < 2u) { /* each base spelled out: its divisions by a constant */
        st_u32 key = st_pair_key(st_pixel_key(p, id->pixel), dim) ^ dim;
        return dim == 0u ? st_radical_inverse_scrambled_at(2u, n, key)
                         : st_radical_inverse_scrambled_at(3u, n, key);
    }
    if (p->halton_tables)
        return st_halton_permuted(id->pmj02, dim, n);
    return st_radical_inverse_scrambled(st_primes[dim], n, st_halton_key(p->seed, dim));
}

/* Sample s of the pixel with index pixel = py * width + px. */
ST_FN st_sample_id st_sample_begin_at(const st_params *p, st_u32 pixel, st_u32 px, st_u32 py,
                                      st_u32 s)
{
    st_sample_id id;
    id.pixel = pixel;
    id.sample = s;
    id.key = st_rng_key(p->seed, id.pixel, s);
    /* only for the samplers that read it: a per-pixel key is four hashes */
    id.pixel_key = ST_SAMPLER_KEYED_PER_PIXEL(p->sampler) ? st_pixel_key(p, pixel) : 0u;
    id.index = p->sampler == ST_SAMPLER_HALTON  ? st_halton_index(p, px, py, s)
               : p->sampler == ST_SAMPLER_SOBOL ? st_sobol_global_index(p->sobol_log2, px, py, s)
                                                : s;
    id.px = px;
    id.py = py;
    id.pmj02 = 0;
    return id;
}

/* Sample s of pixel (px, py). */
ST_FN st_sample_id st_sample_begin(const st_params *p, st_u32 px, st_u32 py, st_u32 s)
{
    return st_sample_begin_at(p, py * p->width + px, px, py, s);
}

/* What the sample record carries of id besides its key (st_sample.word):
 * the index in the sequence, or the pixel key, whichever the sampler reads
 * (no sampler reads both). */
ST_FN st_u32 st_sample_word(const st_params *p, const st_sample_id *id)
{
    return ST_SAMPLER_GLOBAL_INDEX(p->sampler) ? id->index : id->pixel_key;
}

/* Sample s of the pixel with index `pixel` again, from the key and word
 * that st_sample_begin made (carried in st_sample): nothing is hashed or
 * solved again; only ZSobol and pmj02bn (its pixel tile), which read
 * (px, py), split the pixel's index
 * (the others get (0, 0), which they never read: a 32-bit divide per hit
 * was measurable). The same identity as st_sample_begin's (test_sampling_kernels.c);
 * pmj02 is not set. Forced inline: a returned struct stayed in memory. */
ST_HOT st_sample_id st_sample_resume(const st_params *p, st_u32 pixel, st_u32 s, st_u32 key,
                                     st_u32 word)
{
    st_sample_id id;
    id.pixel = pixel;
    id.sample = s;
    id.key = key;
    id.pixel_key = ST_SAMPLER_KEYED_PER_PIXEL(p->sampler) ? word : 0u;
    id.index = ST_SAMPLER_GLOBAL_INDEX(p->sampler) ? word : s;
    id.px = 0u;
    id.py = 0u;
    if (p->sampler == ST_SAMPLER_ZSOBOL || p->sampler == ST_SAMPLER_PMJ02BN) {
        id.px = pixel % p->width;
        id.py = pixel / p->width;
    }
    id.pmj02 = 0;
    return id;
}

/* Position cell + jitter of [0, 1) cut in n equal cells, kept inside the cell. */
ST_FN st_f32 st_cell_coord(st_u32 cell, st_u32 n, st_f32 jitter)
{
    st_f32 x = ((st_f32)cell + jitter) / (st_f32)n;
    /* Far from both edges no rounding can cross one: the computed position t
     * within the cell errs by a few units of 2^-24 (cell + 1), well inside
     * the margin 2^-20 (cell + 2); only the rare near-edge x take the exact
     * (and slower: two long divisions) clamp below. */
    st_f32 t = x * (st_f32)n - (st_f32)cell, margin = 9.5367431640625e-7f * ((st_f32)cell + 2.0f);
    if (t > margin && t < 1.0f - margin)
        return x;
    /* The roundings of cell + jitter and of the quotient can move x a float
     * past either edge of its cell; keep it among the floats of [cell/n,
     * (cell+1)/n): lo the smallest float >= cell/n, hi a float below
     * (cell+1)/n (the largest <= (cell+1)/n - 2^-32/n), both exact. */
    st_f32 lo = st_ratio_ceil(cell, n);
    st_f32 hi = st_ratio_floor((((st_u64)cell + 1u) << 32) - 1u, (st_u64)n << 32);
    return x < lo ? lo : (x > hi ? hi : x);
}

/* Jittered (or centred) coordinate `axis` of a 2-D stratum grid whose cell
 * order is shuffled by key (pbrt pads dimensions the same way). */
ST_FN st_f32 st_stratified_coord(const st_params *p, const st_sample_id *id, st_u32 dim,
                                 st_u32 key, st_f32 jitter)
{
    st_u32 s = id->sample;
    if (key != 0u)
        s = st_permute(s, p->spp, key);
    st_u32 cell = (dim & 1u) ? s / p->strat_nx : s % p->strat_nx;
    st_u32 n = (dim & 1u) ? p->strat_ny : p->strat_nx;
    return st_cell_coord(cell < n ? cell : n - 1u, n, jitter);
}

/* Orthogonal-array stratification (Owen, "Orthogonal arrays for computer
 * experiments, integration and visualization", Statistica Sinica 1992; Bush's
 * construction): for spp = q^2 with q an odd prime or a power of two >= 4,
 * sample s = a + q b gets the symbols (a, b, a + b, a + x b) of GF(q) in
 * dimensions 0..3 (x = 2: the element x of GF(2^k), or the integer 2 mod q).
 * Any two of the four columns take every pair of symbols exactly once
 * (strength 2), so the pixel pair, the light pair and every pixel-light pair
 * are each stratified on a q x q grid. Each column's symbols go through a
 * random permutation per pixel, then a jitter within the stratum. Returns
 * the stratum of dimension dim (< 4), or q (no array) when spp is not such a
 * square. */
ST_FN st_u32 st_oa_symbol(const st_params *p, const st_sample_id *id, st_u32 dim)
{
    st_u32 q = p->strat_nx, k = 31u - ST_CLZ32(q);
    if (q != p->strat_ny || q < 3u)
        return q;
    st_u32 pow2 = (q & (q - 1u)) == 0u;
    if (pow2 && k > 8u)
        return q;
    for (st_u32 d = 2u; !pow2 && d * d <= q; d++)
        if (q % d == 0u)
            return q;
    st_u32 a = id->sample % q, b = id->sample / q, c;
    if (dim == 0u)
        c = a;
    else if (dim == 1u)
        c = b;
    else if (dim == 2u)
        c = pow2 ? a ^ b : (a + b) % q;
    else if (pow2) { /* a + x b in GF(2^k) modulo a primitive polynomial */
        const st_u32 poly[9] = {0u, 0u, 0x7u, 0xbu, 0x13u, 0x25u, 0x43u, 0x83u, 0x11du};
        st_u32 xb = b << 1;
        c = a ^ (xb & q ? xb ^ poly[k] : xb);
    } else
        c = (a + 2u * b) % q;
    return st_permute(c, q, st_hash32(id->pixel_key ^ 0x0a0a0a0au ^ dim));
}

/* Uniform: the pixel's centre in the pixel dimensions, hashed past them. */
ST_FN st_f32 st_uniform_dim(const st_params *p, const st_sample_id *id, st_u32 dim)
{
    return dim < 2u ? st_stratified_coord(p, id, dim, 0u, 0.5f) : st_hashed_dim(id, dim);
}

/* Stratified: jittered strata in every pair of dimensions, the strata of
 * pairs past the pixel's shuffled per (pixel, pair). */
ST_FN st_f32 st_stratified_dim(const st_params *p, const st_sample_id *id, st_u32 dim)
{
    return st_stratified_coord(p, id, dim,
                               (p->scramble || dim >= 2u) ? st_pair_key(id->pixel_key, dim) : 0u,
                               st_rng_unit(id->key, dim));
}

/* Hammersley: i / N in the first dimension, the radical inverses of i in
 * the primes after it; scrambled, a Cranley-Patterson rotation of the first
 * and per-pixel digit permutations of the others. */
ST_FN st_f32 st_hammersley_dim(const st_params *p, const st_sample_id *id, st_u32 dim)
{
    if (dim == 0u) {
        if (!p->scramble)
            return st_ratio_floor(id->sample, p->spp);
        /* rotation by u = U 2^-24, which keeps one point per 1/N: (i/N + u)
         * mod 1 = ((i 2^24 + U N) mod N 2^24) / N 2^24, exact in integers
         * and then rounded down like every value here (a float sum could
         * carry a point a float past either edge of 1/N) */
        st_u64 den = (st_u64)p->spp << 24;
        st_u64 num = ((st_u64)id->sample << 24) + (st_u64)(st_hash32(id->pixel_key) >> 8) * p->spp;
        return st_ratio_floor(num % den, den);
    }
    if (dim > ST_PRIME_COUNT)
        return st_hashed_dim(id, dim);
    if (!p->scramble)
        return st_radical_inverse(st_primes[dim - 1u], id->sample);
    return st_radical_inverse_scrambled(st_primes[dim - 1u], id->sample,
                                        st_hash32(id->pixel_key ^ dim));
}

/* Padded Sobol' (pbrt's PaddedSobolSampler): the (0,2)-sequence in each
 * pair, the index shuffled per (pixel, pair) past the pixel's pair, each
 * pair Owen-scrambled. */
ST_FN st_f32 st_padded_sobol_dim(const st_params *p, const st_sample_id *id, st_u32 dim)
{
    st_u32 key = st_pair_key(id->pixel_key, dim);
    st_u32 i = dim < 2u ? id->sample : st_permute(id->sample, p->spp, key);
    st_u32 bits = st_sobol_bits(i, dim & 1u);
    if (p->scramble || dim >= 2u)
        bits = st_owen_scramble(bits, st_hash32(key ^ (dim & 1u)));
    return st_bits_to_unit(bits);
}

/* Global Sobol' (pbrt-v4's SobolSampler): the sample's index in one
 * sequence over the image (st_sobol_global_index); the pixel dimensions
 * are its digits past the m-th. */
ST_FN st_f32 st_sobol_dim(const st_params *p, const st_sample_id *id, st_u32 dim)
{
    if (dim >= ST_SOBOL_DIMS)
        return st_hashed_dim(id, dim);
    st_u32 bits = st_sobol_sample_bits(id->index, dim);
    if (dim < 2u) {
        bits <<= p->sobol_log2;
        /* Owen-scrambled per pixel (pbrt leaves them: its box filter takes
         * the edge, ours does not, and index 0 sits on it) */
        if (p->scramble)
            bits = st_owen_scramble(bits, st_pair_key(st_pixel_key(p, id->pixel), dim) ^ dim);
        return st_bits_to_unit(bits);
    }
    if (p->scramble)
        bits = st_owen_scramble(bits, st_hash32(p->seed ^ st_hash32(dim)));
    return st_bits_to_unit(bits);
}

/* Joint (correlated multi-jittered) stratification: the pixel and light
 * pairs from one orthogonal array, the other pairs stratified. */
ST_FN st_f32 st_joint_stratified_dim(const st_params *p, const st_sample_id *id, st_u32 dim)
{
    if (dim < 4u) {
        st_u32 c = st_oa_symbol(p, id, dim);
        if (c < p->strat_nx)
            return st_cell_coord(c, p->strat_nx, st_rng_unit(id->key, dim));
    }
    return st_stratified_coord(p, id, dim, st_pair_key(id->pixel_key, dim),
                               st_rng_unit(id->key, dim));
}

/* ZSobol' (pbrt-v4's ZSobolSampler): Sobol' at the Morton index of the
 * pixel and sample, shuffled per pair. */
ST_FN st_f32 st_zsobol_dim(const st_params *p, const st_sample_id *id, st_u32 dim)
{
    st_u32 bits = st_sobol_bits(st_zsobol_index(p, id->px, id->py, id->sample, dim >> 1), dim & 1u);
    if (p->scramble)
        bits = st_owen_scramble(bits, st_hash32(p->seed ^ st_hash32(dim ^ 0x2a5e5u)));
    return st_bits_to_unit(bits);
}

/* pmj02bn's pixel dimensions (pbrt-v4's PMJ02BNSampler::GetPixel2D): the
 * pixel's own points of the sorted tile (st_sampling_pmj02bn_tables: T x T
 * pixels of S = 4^ceil(log4 spp) points each, after the sets), at the
 * pixel's position in the tile, read as they are: every 2^m prefix is a
 * (0,m,2)-net of the pixel and the tile is blue noise across pixels, which
 * a rotation would scatter. */
ST_FN st_u32 st_pmj02bn_pixel_word(const st_params *p, const st_sample_id *id, st_u32 dim)
{
    st_u32 log2n = st_log2_ceil(p->spp), log2s = (log2n + 1u) & ~1u;
    st_u32 log2t = (ST_PMJ02_MAX_LOG2 - log2s) / 2u, mask = (1u << log2t) - 1u;
    st_u32 cell = ((id->py & mask) << log2t) | (id->px & mask);
    st_u32 at = (ST_PMJ02_SETS << log2n) + (cell << log2s) + id->sample;
    return id->pmj02[2u * at + (dim & 1u)];
}

/* pmj02 and pmj02bn (pbrt-v4's PMJ02BNSampler; pmj02bn's tables are blue
 * noise too, st_sampling_pmj02bn; pmj02's are not): each pair of
 * dimensions reads one of the ST_PMJ02_SETS sequences of 2^ceil(log2 spp)
 * points, chosen by a hash of (pixel, pair); the pixel pair at the sample
 * index (pmj02bn's from its pixel tile instead: st_pmj02bn_pixel_word),
 * later pairs at an index permuted per (pixel, pair) so that pairs do not
 * correlate. A random digital shift per (pixel, pair) (the xor of the
 * digits with one random word, which maps elementary intervals onto
 * elementary intervals) keeps every 2^m prefix a (0,m,2)-net and keeps
 * pixels that share a sequence apart. pmj02bn's later pairs shift on the
 * torus instead (the addition of the word mod 2^32, pbrt-v4's
 * Cranley-Patterson rotation), which keeps their blue noise (every
 * distance) and their stratification up to one interval's wrap. No tables
 * (a host caller that gave none): hashed. */
ST_FN st_f32 st_pmj02_dim(const st_params *p, const st_sample_id *id, st_u32 dim)
{
    if (!id->pmj02)
        return st_hashed_dim(id, dim);
    int bn = p->sampler == ST_SAMPLER_PMJ02BN;
    if (bn && dim < 2u)
        return st_bits_to_unit(st_pmj02bn_pixel_word(p, id, dim));
    st_u32 key = st_pair_key(id->pixel_key, dim), set = st_hash32(key ^ 0x706d6a32u) % ST_PMJ02_SETS;
    st_u32 i = dim < 2u ? id->sample : st_permute(id->sample, p->spp, key);
    st_u32 at = (set << st_log2_ceil(p->spp)) + i;
    st_u32 word = id->pmj02[2u * at + (dim & 1u)], shift = st_hash32(key ^ (dim & 1u));
    return st_bits_to_unit(bn ? word + shift : word ^ shift);
}

/* Poisson disk and best candidate past the film's dimensions (which the
 * tile gives: generate.cl): one of the sampler's own one-pixel tiles per
 * (pixel, pair), read at the sample index permuted per (pixel, pair),
 * shifted on the torus (the addition of a random word mod 2^32) per
 * (pixel, pair) and per block of n samples (st_sampling_pad_tables). No
 * tables (a host caller that gave none): hashed. */
ST_FN st_f32 st_tiled_pad_dim(const st_params *p, const st_sample_id *id, st_u32 dim)
{
    if (!id->pmj02 || dim < 2u)
        return st_hashed_dim(id, dim);
    st_u32 key = st_pair_key(id->pixel_key, dim), set = st_hash32(key ^ 0x70616473u) % ST_PMJ02_SETS;
    st_u32 n = p->spp < ST_PAD_MAX_POINTS ? p->spp : ST_PAD_MAX_POINTS;
    st_u32 i = st_permute(id->sample, p->spp, key), j = i % n;
    st_u32 shift = st_hash32(key ^ st_hash32(i / n) ^ (dim & 1u));
    return st_bits_to_unit(id->pmj02[2u * (set * n + j) + (dim & 1u)] + shift);
}

/* Dimension `dim` of sample id, in [0, 1), for every sampler: the dispatch
 * to each sampler's own function (st_sample_dim). */
ST_COLD st_f32 st_sample_dim_any(const st_params *p, const st_sample_id *id, st_u32 dim)
{
    switch (p->sampler) {
    case ST_SAMPLER_UNIFORM: return st_uniform_dim(p, id, dim);
    case ST_SAMPLER_STRATIFIED: return st_stratified_dim(p, id, dim);
    case ST_SAMPLER_HALTON: return st_halton_dim(p, id, dim);
    case ST_SAMPLER_HAMMERSLEY: return st_hammersley_dim(p, id, dim);
    case ST_SAMPLER_PADDED_SOBOL: return st_padded_sobol_dim(p, id, dim);
    case ST_SAMPLER_SOBOL: return st_sobol_dim(p, id, dim);
    case ST_SAMPLER_JOINT_STRATIFIED: return st_joint_stratified_dim(p, id, dim);
    case ST_SAMPLER_ZSOBOL: return st_zsobol_dim(p, id, dim);
    case ST_SAMPLER_PMJ02:
    case ST_SAMPLER_PMJ02BN: return st_pmj02_dim(p, id, dim);
    case ST_SAMPLER_POISSON:
    case ST_SAMPLER_BEST_CANDIDATE: return st_tiled_pad_dim(p, id, dim);
    default: return st_hashed_dim(id, dim);
    }
}

/* Dimension `dim` of sample id, in [0, 1): the random sampler's hash inline,
 * the others through st_sample_dim_any with a copy of id. On PoCL the call
 * stays a call, and handing it the caller's own id would keep that id in
 * memory, stored per work-item, even where the call is never made. */
ST_HOT st_f32 st_sample_dim(const st_params *p, const st_sample_id *id, st_u32 dim)
{
    if (p->sampler == ST_SAMPLER_RANDOM)
        return st_rng_unit(id->key, dim);
    st_sample_id copy = *id;
    return st_sample_dim_any(p, &copy, dim);
}

#endif
