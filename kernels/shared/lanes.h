/* lanes.h — the lane vocabulary: n values of a type processed as one, the
 * only file that spells OpenCL's vector types for lanes.
 *
 * A stage that works on several values at once (a packet's rays, a wide
 * node's boxes, a leaf's triangles) is written once over ST_VEC(T, n) and
 * the helpers below, and compiled at the widths it needs. Width 1 is plain
 * C: a GPU's kernels run it one item per work-item, its SIMT hardware making
 * the lanes. Widths 4, 8 and 16 are OpenCL C vectors, which PoCL keeps in
 * SSE, AVX2 and AVX-512 registers (its own vectoriser widens only scalar
 * code over separate arrays, so a CPU's lanes have to be written out). The
 * host's C11 has every width too, as GCC's (and clang's) vector extension,
 * whose operators work lane by lane as OpenCL's do, so that the host runs
 * the kernels' own text at the kernels' widths (a wide node's boxes, a
 * leaf's triangles) and the tests compare that text, not a copy of it.
 *
 * ST_W is the width of the stages that take several items per work-item
 * (packets of rays, kernels/geom/packet.h): chosen per device by the host
 * (st_device_default_lanes, src/device/device.c; --lanes) and passed as -DST_W=n; 1 where it is not
 * given (the host's C, whose stages run one item at a time). ST_BVH_WIDTH (a
 * wide node's boxes) and ST_LEAF_MAX (a leaf's triangles) are widths of the
 * tree's layout, fixed whatever ST_W.
 *
 * Masks: a comparison of vectors gives -1 (true) or 0 per lane, of scalars 1
 * or 0; the helpers below accept both, so that the same text is right at
 * every width. Use ST_ANY, ST_SELECT and ST_MASK_BITS on masks, never
 * OpenCL's any() or ~ on a width-1 mask (any(1) is 0: it reads the sign
 * bit), nor ! on a vector mask (the host's C has none: m == 0 instead).
 * Lanes of one value are ST_SPLAT, lanes of listed values ST_LIT: the host's
 * C casts no scalar to a vector and writes vector literals in braces. */
#ifndef ST_LANES_H
#define ST_LANES_H

#ifndef ST_W
#define ST_W 1
#endif
#if ST_W != 1 && ST_W != 4 && ST_W != 8 && ST_W != 16
#error "ST_W must be 1, 4, 8 or 16"
#endif
#if ST_W != 1 && !defined(__OPENCL_VERSION__)
#error "the host's stages run width 1 only (its other widths are ST_N's: ST_VEC)"
#endif
/* A vector wider than the device's registers (16 lanes without AVX-512)
 * passed between functions has another calling convention than the one
 * the device's own libraries use, and clang warns of it at each such call
 * (-Wpsabi). Within one program, as every kernel function is, the
 * convention is the program's own, so nothing changes; the 16-lane mask
 * helpers below, which the lane probe (lanes_probe.cl) uses at every
 * width, would otherwise put "warnings generated" on a user's terminal at
 * every first compile, and --lanes 16 hundreds of them. */
#if defined(__OPENCL_VERSION__) && defined(__clang__)
#pragma clang diagnostic ignored "-Wpsabi"
#endif
/* The host's vectors wider than its build's registers (8 and 16 lanes
 * without AVX) are passed likewise between functions of one file, all of
 * them static, so GCC's note that their convention differs is moot. */
#if !defined(__OPENCL_VERSION__) && defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

/* The host's vector types, under OpenCL's names (GCC's vector extension:
 * + - * / and comparisons lane by lane, a comparison giving -1 or 0 per
 * lane as an int vector, v[j] a lane). */
#ifndef __OPENCL_VERSION__
#include <math.h>
#include <string.h>
#define ST_HOST_VECTORS(T, name)                                                           \
    typedef T name##4 __attribute__((vector_size(4 * sizeof(T))));                         \
    typedef T name##8 __attribute__((vector_size(8 * sizeof(T))));                         \
    typedef T name##16 __attribute__((vector_size(16 * sizeof(T))));
ST_HOST_VECTORS(float, float)
ST_HOST_VECTORS(int, int)
ST_HOST_VECTORS(unsigned, uint)
#undef ST_HOST_VECTORS
#endif

#define ST_CAT(a, b) ST_CAT_(a, b)
#define ST_CAT_(a, b) a##b

/* n lanes of the scalar type T (float, int, uint). */
#define ST_VEC(T, n) ST_CAT(ST_VEC_, n)(T)
#define ST_VEC_1(T) T
#define ST_VEC_4(T) T##4
#define ST_VEC_8(T) T##8
#define ST_VEC_16(T) T##16

/* n (a number, not a macro) lanes of the value x, of scalar type T (OpenCL C's cast of a scalar to
 * a vector; the host's broadcast, x - 0 in every lane being x itself, its
 * sign and NaN included), and n lanes of the n values listed. */
#define ST_SPLAT(T, n, x) ST_CAT(ST_SPLAT_, n)(T, x)
#define ST_SPLAT_1(T, x) ((T)(x))
#ifdef __OPENCL_VERSION__
#define ST_SPLAT_4(T, x) ((T##4)(x))
#define ST_SPLAT_8(T, x) ((T##8)(x))
#define ST_SPLAT_16(T, x) ((T##16)(x))
#define ST_LIT(T, n, ...) ((T##n)(__VA_ARGS__))
#else
#define ST_SPLAT_4(T, x) ((T)(x) - (T##4){0})
#define ST_SPLAT_8(T, x) ((T)(x) - (T##8){0})
#define ST_SPLAT_16(T, x) ((T)(x) - (T##16){0})
#define ST_LIT(T, n, ...) ((T##n){__VA_ARGS__})
#endif

/* The lanes at p[0 .. n), and stored there. */
#define ST_VLOAD(n, p) ST_CAT(ST_VLOAD_, n)(p)
#define ST_VLOAD_1(p) (*(p))
#define ST_VSTORE(n, v, p) ST_CAT(ST_VSTORE_, n)(v, p)
#define ST_VSTORE_1(v, p) (*(p) = (v))
#ifdef __OPENCL_VERSION__
#define ST_VLOAD_4(p) vload4(0, p)
#define ST_VLOAD_8(p) vload8(0, p)
#define ST_VLOAD_16(p) vload16(0, p)
#define ST_VSTORE_4(v, p) vstore4(v, 0, p)
#define ST_VSTORE_8(v, p) vstore8(v, 0, p)
#define ST_VSTORE_16(v, p) vstore16(v, 0, p)
#else
/* The host's: n values of p's type (its qualifiers dropped: *p + 0), as
 * vload and vstore, whatever p's alignment. */
#define ST_HOST_VLOAD(n, p)                                                                \
    ({                                                                                     \
        __typeof__(*(p) + 0) st_vl_ __attribute__((vector_size(n * sizeof(*(p)))));        \
        memcpy(&st_vl_, (p), sizeof st_vl_);                                               \
        st_vl_;                                                                            \
    })
#define ST_HOST_VSTORE(v, p)                                                               \
    do {                                                                                   \
        __typeof__(v) st_vs_ = (v);                                                        \
        memcpy((p), &st_vs_, sizeof st_vs_);                                               \
    } while (0)
#define ST_VLOAD_4(p) ST_HOST_VLOAD(4, p)
#define ST_VLOAD_8(p) ST_HOST_VLOAD(8, p)
#define ST_VLOAD_16(p) ST_HOST_VLOAD(16, p)
#define ST_VSTORE_4(v, p) ST_HOST_VSTORE(v, p)
#define ST_VSTORE_8(v, p) ST_HOST_VSTORE(v, p)
#define ST_VSTORE_16(v, p) ST_HOST_VSTORE(v, p)
#endif

/* Each lane of v converted to the scalar type T (float, int), as a C cast
 * does (float to int truncates): n lanes of T. */
#define ST_CONVERT(T, n, v) ST_CAT(ST_CONVERT_, n)(T, v)
#define ST_CONVERT_1(T, v) ((T)(v))
#ifdef __OPENCL_VERSION__
#define ST_CONVERT_4(T, v) convert_##T##4(v)
#define ST_CONVERT_8(T, v) convert_##T##8(v)
#define ST_CONVERT_16(T, v) convert_##T##16(v)
#else
#define ST_CONVERT_4(T, v) __builtin_convertvector(v, T##4)
#define ST_CONVERT_8(T, v) __builtin_convertvector(v, T##8)
#define ST_CONVERT_16(T, v) __builtin_convertvector(v, T##16)
#endif

/* Where the device's compiler is clang for x86 (PoCL's CPU devices), a
 * vector mask's lanes become bits in one instruction, movmskps: LLVM 15 makes
 * the portable or-reduction below (st_mask_bits_or<n>) seven or eight
 * instructions, and the traversal asks for a node's and a leaf's bits at
 * every step (trace_rays ran about 5 % fewer instructions with it).
 * Elsewhere (GPUs, Oclgrind) the portable form; tests/device/test_lanes.c
 * checks both against the bits they stand for. */
#if defined(__OPENCL_VERSION__) && defined(__AVX__) && defined(__has_builtin)
#if __has_builtin(__builtin_ia32_movmskps) && __has_builtin(__builtin_ia32_movmskps256)
#define ST_MOVMSK 1
#endif
#endif

/* Whether any lane of mask m is set. */
#define ST_ANY(n, m) ST_CAT(ST_ANY_, n)(m)
#define ST_ANY_1(m) ((m) != 0)
#if defined(ST_MOVMSK) || !defined(__OPENCL_VERSION__)
#define ST_ANY_4(m) (st_mask_bits4(m) != 0u)
#define ST_ANY_8(m) (st_mask_bits8(m) != 0u)
#define ST_ANY_16(m) (st_mask_bits16(m) != 0u)
#else
#define ST_ANY_4(m) any(m)
#define ST_ANY_8(m) any(m)
#define ST_ANY_16(m) any(m)
#endif

/* Per lane: b where mask m is set, else a (OpenCL's select). */
#define ST_SELECT(n, a, b, m) ST_CAT(ST_SELECT_, n)(a, b, m)
#define ST_SELECT_1(a, b, m) ((m) ? (b) : (a))
#ifdef __OPENCL_VERSION__
#define ST_SELECT_4(a, b, m) select(a, b, m)
#define ST_SELECT_8(a, b, m) select(a, b, m)
#define ST_SELECT_16(a, b, m) select(a, b, m)
#else
/* The host's select: each lane's bits from b where m's sign bit is set
 * (as OpenCL's select reads a vector mask), else from a. */
#define ST_HOST_SELECT(n, a, b, m)                                                         \
    ({                                                                                     \
        __typeof__(a) st_sa_ = (a), st_sb_ = (b);                                          \
        int##n st_sm_ = (m) < 0;                                                           \
        (__typeof__(a))(((int##n)st_sa_ & ~st_sm_) | ((int##n)st_sb_ & st_sm_));           \
    })
#define ST_SELECT_4(a, b, m) ST_HOST_SELECT(4, a, b, m)
#define ST_SELECT_8(a, b, m) ST_HOST_SELECT(8, a, b, m)
#define ST_SELECT_16(a, b, m) ST_HOST_SELECT(16, a, b, m)
#endif

/* The lanes 0, 1, .., n - 1 (an int vector). */
#define ST_IOTA(n) ST_CAT(ST_IOTA_, n)
#define ST_IOTA_1 0
#define ST_IOTA_4 ST_LIT(int, 4, 0, 1, 2, 3)
#define ST_IOTA_8 ST_LIT(int, 8, 0, 1, 2, 3, 4, 5, 6, 7)
#define ST_IOTA_16 ST_LIT(int, 16, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15)

/* Lane j's bit, 1 << j, per lane. */
#define ST_LANE_BIT(n) ST_CAT(ST_LANE_BIT_, n)
#define ST_LANE_BIT_4 ST_LIT(int, 4, 1, 2, 4, 8)
#define ST_LANE_BIT_8 ST_LIT(int, 8, 1, 2, 4, 8, 16, 32, 64, 128)
#define ST_LANE_BIT_16                                                                             \
    ST_LIT(int, 16, 1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384, 32768)

/* Mask m as bits, lane j -> bit j (lanes set: m != 0), and bits b as a mask
 * of n lanes (-1 or 0 per lane; 1 or 0 at width 1). */
#define ST_MASK_BITS(n, m) ST_CAT(st_mask_bits, n)(m)
#define ST_BITS_MASK(n, b) ST_CAT(ST_BITS_MASK_, n)(b)
#define ST_BITS_MASK_1(b) (((b) & 1u) != 0u)
#define ST_BITS_MASK_4(b) ((ST_SPLAT(int, 4, (int)(b)) & ST_LANE_BIT_4) != 0)
#define ST_BITS_MASK_8(b) ((ST_SPLAT(int, 8, (int)(b)) & ST_LANE_BIT_8) != 0)
#define ST_BITS_MASK_16(b) ((ST_SPLAT(int, 16, (int)(b)) & ST_LANE_BIT_16) != 0)

/* The bits of float lanes as int lanes, and back (vector widths only; the
 * host's cast between vectors of one size keeps the bits). */
#ifdef __OPENCL_VERSION__
#define ST_AS_INT(n, v) ST_CAT(as_int, n)(v)
#define ST_AS_FLOAT(n, v) ST_CAT(as_float, n)(v)
#else
#define ST_AS_INT(n, v) ((ST_VEC(int, n))(v))
#define ST_AS_FLOAT(n, v) ((ST_VEC(float, n))(v))
#endif

/* The largest and the least of a vector's lanes, halving the vector (a
 * NaN lane loses to a number, as in fmax and fmin). */
#define ST_HMAX(n, v) ST_CAT(st_hmax, n)(v)
#define ST_HMIN(n, v) ST_CAT(st_hmin, n)(v)

static inline unsigned st_mask_bits1(int m) { return m != 0 ? 1u : 0u; }
static inline float st_hmax1(float v) { return v; }
static inline float st_hmin1(float v) { return v; }
#ifdef __OPENCL_VERSION__
static inline float st_hmax4(float4 v)
{
    float2 a = fmax(v.lo, v.hi);
    return fmax(a.x, a.y);
}
static inline float st_hmax8(float8 v) { return st_hmax4(fmax(v.lo, v.hi)); }
/* A 16-wide vector's halves are taken through a private array: Oclgrind
 * reads the .lo and .hi of a 16-wide vector as uninitialised (its shadow
 * of that shuffle), and PoCL's compiler makes the same instructions of
 * either form (the kernels' instruction counts are equal). */
static inline float st_hmax16(float16 v)
{
    float a[16];
    vstore16(v, 0, a);
    return st_hmax8(fmax(vload8(0, a), vload8(1, a)));
}
static inline float st_hmin4(float4 v)
{
    float2 a = fmin(v.lo, v.hi);
    return fmin(a.x, a.y);
}
static inline float st_hmin8(float8 v) { return st_hmin4(fmin(v.lo, v.hi)); }
static inline float st_hmin16(float16 v)
{
    float a[16];
    vstore16(v, 0, a);
    return st_hmin8(fmin(vload8(0, a), vload8(1, a)));
}
/* The lanes of a vector mask (-1 or 0) as bits: each lane keeps its own
 * bit, then the halves are or-ed together down to one int. */
static inline unsigned st_mask_bits_or4(int4 m)
{
    int4 b = m & ST_LANE_BIT_4;
    int2 o = b.lo | b.hi;
    return (unsigned)(o.x | o.y);
}
static inline unsigned st_mask_bits_or8(int8 m)
{
    int8 b = m & ST_LANE_BIT_8;
    int4 s = b.lo | b.hi;
    int2 o = s.lo | s.hi;
    return (unsigned)(o.x | o.y);
}
static inline unsigned st_mask_bits_or16(int16 m)
{
    int b[16];
    vstore16(m & ST_LANE_BIT_16, 0, b);
    int8 s = vload8(0, b) | vload8(1, b);
    int4 q = s.lo | s.hi;
    int2 o = q.lo | q.hi;
    return (unsigned)(o.x | o.y);
}
/* The same bits as the lanes' sign bits (ST_MOVMSK above), where it can. */
#ifdef ST_MOVMSK
static inline unsigned st_mask_bits4(int4 m)
{
    return (unsigned)__builtin_ia32_movmskps(as_float4(m));
}
static inline unsigned st_mask_bits8(int8 m)
{
    return (unsigned)__builtin_ia32_movmskps256(as_float8(m));
}
static inline unsigned st_mask_bits16(int16 m)
{
    return st_mask_bits8(m.lo) | st_mask_bits8(m.hi) << 8;
}
#else
static inline unsigned st_mask_bits4(int4 m) { return st_mask_bits_or4(m); }
static inline unsigned st_mask_bits8(int8 m) { return st_mask_bits_or8(m); }
static inline unsigned st_mask_bits16(int16 m) { return st_mask_bits_or16(m); }
#endif
#else
/* The host's, lane by lane: the same bits and extremes as the device's
 * (the extremes halving the vector as they do, so that of a -0 and a +0
 * the same one is kept). */
#define ST_HOST_HALVING(name, f, n)                                                        \
    static inline float name##n(float##n v)                                                \
    {                                                                                      \
        for (int h = n / 2; h > 0; h /= 2)                                                 \
            for (int j = 0; j < h; ++j)                                                    \
                v[j] = f(v[j], v[j + h]);                                                  \
        return v[0];                                                                       \
    }
#define ST_HOST_LANES(n)                                                                   \
    static inline unsigned st_mask_bits##n(int##n m)                                       \
    {                                                                                      \
        unsigned b = 0u;                                                                   \
        for (int j = 0; j < n; ++j)                                                        \
            b |= (m[j] != 0 ? 1u : 0u) << j;                                               \
        return b;                                                                          \
    }                                                                                      \
    ST_HOST_HALVING(st_hmax, fmaxf, n)                                                     \
    ST_HOST_HALVING(st_hmin, fminf, n)
ST_HOST_LANES(4)
ST_HOST_LANES(8)
ST_HOST_LANES(16)
#undef ST_HOST_LANES
#undef ST_HOST_HALVING
#endif

/* A 3-vector in n lanes: x, y and z each n wide (st_v3x<n>), defined for
 * every width, passed by value so that the compiler keeps its lanes in
 * registers (as private arrays PoCL kept them on the stack). */
#define ST_DEFINE_V3X(n)                                                                   \
    typedef struct ST_CAT(st_v3x, n) {                                                     \
        ST_VEC(float, n) x, y, z;                                                          \
    } ST_CAT(st_v3x, n);
ST_DEFINE_V3X(1)
ST_DEFINE_V3X(4)
ST_DEFINE_V3X(8)
ST_DEFINE_V3X(16)

/* The stages' lanes, ST_W of them: a float, an int (a mask: see the top),
 * an unsigned int and a 3-vector per lane. */
typedef ST_VEC(float, ST_W) st_lf;
typedef ST_VEC(int, ST_W) st_li;
#ifdef __OPENCL_VERSION__
typedef ST_VEC(uint, ST_W) st_lu;
#else
typedef unsigned st_lu;
#endif
typedef ST_CAT(st_v3x, ST_W) st_lv3;

/* Lanes of the value c. */
#define ST_LF(c) ((st_lf)(c))

/* The float functions of lanes, by their names in C and in OpenCL C (whose
 * forms are overloaded for vectors). The accurate sine, not native_:
 * PoCL's native_sin of a vector differs from its scalar one in the last
 * bits, and a lane must compute at every width what it computes at width 1. */
#ifndef __OPENCL_VERSION__
#include <math.h>
#define ST_SQRTF(x) sqrtf(x)
#define ST_COSF(x) cosf(x)
#define ST_SINF(x) sinf(x)
#define ST_FMAXF(a, b) fmaxf(a, b)
#define ST_FMINF(a, b) fminf(a, b)
#define ST_FABSF(x) fabsf(x)
#define ST_POWF(x, y) powf(x, y)
#define ST_EXPF(x) expf(x)
#else
#define ST_SQRTF(x) sqrt(x)
#define ST_COSF(x) cos(x)
#define ST_SINF(x) sin(x)
#define ST_FMAXF(a, b) fmax(a, b)
#define ST_FMINF(a, b) fmin(a, b)
#define ST_FABSF(x) fabs(x)
#define ST_POWF(x, y) pow(x, y)
#define ST_EXPF(x) exp(x)
#endif

/* Lanes of floats from unsigned ints, rounded to nearest (convert_float). */
#define ST_TO_FLOAT(n, x) ST_CAT(ST_TO_FLOAT_, n)(x)
#define ST_TO_FLOAT_1(x) ((float)(x))
#define ST_TO_FLOAT_4(x) ST_CONVERT_4(float, x)
#define ST_TO_FLOAT_8(x) ST_CONVERT_8(float, x)
#define ST_TO_FLOAT_16(x) ST_CONVERT_16(float, x)

/* 3-vectors of lanes: float3's arithmetic, lane by lane. Each is one
 * statement, so that a lane computes the same at every width (OpenCL
 * contracts a * b + c into fma within a statement, alike at every width). */
static inline st_lv3 st_lv3_make(st_lf x, st_lf y, st_lf z)
{
    st_lv3 v = {x, y, z};
    return v;
}
static inline st_lv3 st_lv3_add(st_lv3 a, st_lv3 b)
{
    return st_lv3_make(a.x + b.x, a.y + b.y, a.z + b.z);
}
static inline st_lv3 st_lv3_sub(st_lv3 a, st_lv3 b)
{
    return st_lv3_make(a.x - b.x, a.y - b.y, a.z - b.z);
}
static inline st_lv3 st_lv3_mul(st_lv3 a, st_lv3 b)
{
    return st_lv3_make(a.x * b.x, a.y * b.y, a.z * b.z);
}
static inline st_lv3 st_lv3_scale(st_lv3 a, st_lf s)
{
    return st_lv3_make(a.x * s, a.y * s, a.z * s);
}
static inline st_lv3 st_lv3_div(st_lv3 a, st_lf s)
{
    return st_lv3_make(a.x / s, a.y / s, a.z / s);
}
static inline st_lv3 st_lv3_neg(st_lv3 a) { return st_lv3_make(-a.x, -a.y, -a.z); }
static inline st_lf st_lv3_dot(st_lv3 a, st_lv3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
/* a + b s: a point along a ray, or a step along a normal. */
static inline st_lv3 st_lv3_along(st_lv3 a, st_lv3 b, st_lf s)
{
    return st_lv3_make(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s);
}
/* a in the lanes of mask m, b in the others. */
static inline st_lv3 st_lv3_select(st_lv3 b, st_lv3 a, st_li m)
{
    return st_lv3_make(ST_SELECT(ST_W, b.x, a.x, m), ST_SELECT(ST_W, b.y, a.y, m),
                       ST_SELECT(ST_W, b.z, a.z, m));
}

#endif
