/* order.h — the key by which order.cl sorts a wave's rays before a trace
 * (the plan's ST_PLAN_ORDER: src/render/plan.c), shared with the host's
 * tests. Rays whose keys are equal start in the same cell of the wave's
 * origins and point into the same cell of its directions, so that traced
 * one after the other they visit the same nodes and leaves, which then come
 * from the caches instead of memory: the wave's rays as a stream sorted for
 * coherence (Pharr et al., "Rendering complex scenes with memory-coherent
 * ray tracing", SIGGRAPH 1997; Eisenacher et al., "Sorted deferred
 * shading", EGSR 2013, sort by origin cell and direction the same way).
 *
 * The key of ST_ORDER_KEY_BITS bits: the origin's cell in a grid of
 * 4 x 4 x 4 over the wave's origins (their bounds), then the direction's in
 * a grid of 32 x 32 over the bounds of the wave's directions in the
 * octahedral map of the sphere (Meyer et al., "On floating-point normal
 * vectors", EGSR 2010), each grid's coordinates interleaved bit by bit (a
 * Morton order). Within the bounds each cell is as fine as the key allows,
 * and the camera rays of a pinhole, which share one origin, spend every bit
 * on a grid of 256 x 256 directions: traced in that order, neighbours in
 * the image follow each other. Only the order of the trace follows from
 * it, never a result. */
#ifndef ST_ORDER_H
#define ST_ORDER_H

#ifndef __OPENCL_VERSION__
#include "st_shared.h"
#endif
#include "lanes.h"


/* The octahedral coordinates of the lanes' directions d (nonzero):
 * d / (|x| + |y| + |z|) projected onto z = 0, its lower half folded over the
 * diagonals, so that the sphere maps onto the square [-1, 1]^2 with nearby
 * directions nearby. */
ST_FN void st_order_octahedral(st_lv3 d, st_lf *x, st_lf *y)
{
    st_lf l1 = ST_FABSF(d.x) + ST_FABSF(d.y) + ST_FABSF(d.z);
    st_lf px = d.x / l1, py = d.y / l1;
    st_lf fx = ST_LF(1.0f) - ST_FABSF(py), fy = ST_LF(1.0f) - ST_FABSF(px);
    fx = ST_SELECT(ST_W, fx, -fx, px < ST_LF(0.0f));
    fy = ST_SELECT(ST_W, fy, -fy, py < ST_LF(0.0f));
    *x = ST_SELECT(ST_W, px, fx, d.z < ST_LF(0.0f));
    *y = ST_SELECT(ST_W, py, fy, d.z < ST_LF(0.0f));
}

/* An integer whose unsigned order is the order of the floats (not NaN):
 * a float's bits with the sign bit set where it is positive, all bits
 * flipped where it is negative. */
ST_FN st_u32 st_order_monotone(st_f32 f)
{
    union {
        st_f32 f;
        st_u32 u;
    } b;
    b.f = f;
    return (b.u & 0x80000000u) ? ~b.u : b.u | 0x80000000u;
}

ST_FN st_f32 st_order_float(st_u32 m)
{
    union {
        st_f32 f;
        st_u32 u;
    } b;
    b.u = (m & 0x80000000u) ? m & 0x7fffffffu : ~m;
    return b.f;
}

/* Where the wave's bounds put the cells: per coordinate (the origin's
 * three, the octahedral two) the low end, cells per unit and the cells'
 * bits. */
typedef struct st_order_frame {
    st_f32 lo[5], scale[5];
    st_u32 bits[5];
} st_order_frame;

/* The frame of the bounds b (ST_ORDER_BOUNDS gathered integers): each
 * coordinate's range split into 2^bits cells, ST_ORDER_ORIGIN_BITS and
 * ST_ORDER_DIR_BITS, but where the origins are one point (a pinhole
 * camera's rays) every bit of the key goes to the directions; none (scale
 * 0: every ray in cell 0) where the range is one point or nothing was
 * gathered. */
ST_FN st_order_frame st_order_frame_of(const ST_GLOBAL st_u32 *b)
{
    st_order_frame f;
    int spread = 0;
    for (st_u32 c = 0u; c < 5u; ++c) {
        st_u32 at = c < 3u ? c : 3u + c; /* the largest; its negation's follows */
        st_u32 neg = c < 3u ? at + 3u : at + 2u;
        st_f32 lo = -st_order_float(b[neg]), hi = st_order_float(b[at]);
        spread |= c < 3u && hi > lo;
        f.bits[c] = c < 3u ? ST_ORDER_ORIGIN_BITS
                           : spread ? ST_ORDER_DIR_BITS : ST_ORDER_KEY_BITS / 2u;
        f.lo[c] = hi > lo ? lo : 0.0f;
        f.scale[c] = hi > lo ? (st_f32)(1u << f.bits[c]) / (hi - lo) : 0.0f;
    }
    for (st_u32 c = 0u; c < 3u && !spread; ++c)
        f.bits[c] = 0u;
    return f;
}

/* The lanes' cells of v in frame coordinate c: 2^bits[c] of them, the edge
 * ones taking what lies beyond (NaN the first). */
ST_FN st_li st_order_cell(const st_order_frame *f, st_u32 c, st_lf v)
{
    st_lf x = (v - ST_LF(f->lo[c])) * ST_LF(f->scale[c]);
    st_lf last = ST_LF((st_f32)((1u << f->bits[c]) - 1u));
    return ST_CONVERT(int, ST_W, ST_FMINF(ST_FMAXF(x, ST_LF(0.0f)), last));
}

/* The bits of a and b (bits each) interleaved, a's above b's; of a, b and
 * c, a's highest. */
ST_FN st_li st_order_interleave2(st_li a, st_li b, st_u32 bits)
{
    st_li m = (st_li)(0);
    for (st_u32 k = 0u; k < bits; ++k)
        m |= ((a >> k & 1) << (2u * k + 1u)) | ((b >> k & 1) << (2u * k));
    return m;
}

ST_FN st_li st_order_interleave3(st_li a, st_li b, st_li c, st_u32 bits)
{
    st_li m = (st_li)(0);
    for (st_u32 k = 0u; k < bits; ++k)
        m |= ((a >> k & 1) << (3u * k + 2u)) | ((b >> k & 1) << (3u * k + 1u)) |
             ((c >> k & 1) << (3u * k));
    return m;
}

/* The keys of the lanes' rays (origins o, directions d) in frame f: each
 * below 2^ST_ORDER_KEY_BITS. */
ST_FN st_li st_order_key(const st_order_frame *f, st_lv3 o, st_lv3 d)
{
    st_lf x, y;
    st_order_octahedral(d, &x, &y);
    st_li origin = st_order_interleave3(st_order_cell(f, 0u, o.x), st_order_cell(f, 1u, o.y),
                                        st_order_cell(f, 2u, o.z), f->bits[0]);
    st_li dir = st_order_interleave2(st_order_cell(f, 3u, x), st_order_cell(f, 4u, y),
                                     f->bits[3]);
    return origin << (2u * f->bits[3]) | dir;
}

#endif
