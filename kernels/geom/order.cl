/* order.cl — the order in which trace_rays takes a stream of rays, where
 * the plan sorts them (src/render/plan.c): by order.h's key, a radix sort
 * of two digits (least significant first, each a counting sort) over the
 * trace's n positions (the vertex's live paths, or every item of the
 * wave), in blocks of ST_ORDER_BLOCK positions, a work-item each, so that
 * counts and cursors stay in the work-item's own array and no atomic is
 * taken per ray. order_bounds gathers the bounds of the rays' origins and
 * directions from a sample of each block, order_keys keys each position in
 * lanes, order_count_low counts the low digits, order_scan turns counts
 * into starts, order_scatter_low places (key, item) pairs by the low
 * digit, order_count_high counts their high digits, order_scan again, and
 * order_scatter_high places the items in `order` and their rays in
 * `order_ray`, which the trace then reads in a run. A stable sort, but only
 * the trace's speed depends on the order: each ray's hit is the same
 * whichever order it is traced in. */
#include "st_shared.h"
#include "order.h"

/* Block b's positions [*first, *end) of the n; 0 where it has none. */
static int order_block(st_u32 b, st_u32 n, st_u32 *first, st_u32 *end)
{
    *first = b * ST_ORDER_BLOCK;
    *end = min(*first + ST_ORDER_BLOCK, n);
    return *first < n;
}

static st_u32 order_blocks(st_u32 n)
{
    return (n + ST_ORDER_BLOCK - 1u) / ST_ORDER_BLOCK;
}

/* The counts (then starts) of order_count: digit-major, block b's count of
 * digit d at d * blocks + b, so that their exclusive sums in that order are
 * the starts of a stable sort. */
static __global st_u32 *order_counts(__global st_u32 *order_count)
{
    return order_count + ST_ORDER_COUNTS;
}

/* Block b's counts, one per digit, to order_count. */
static void order_put_counts(__global st_u32 *order_count, st_u32 b, st_u32 n,
                             const st_u32 count[ST_ORDER_DIGITS])
{
    __global st_u32 *c = order_counts(order_count) + b;
    st_u32 blocks = order_blocks(n);
    for (st_u32 d = 0u; d < ST_ORDER_DIGITS; d++)
        c[d * blocks] = count[d];
}

/* Block b's cursors: the starts order_scan left for it. */
static void order_get_starts(__global st_u32 *order_count, st_u32 b, st_u32 n,
                             st_u32 start[ST_ORDER_DIGITS])
{
    __global const st_u32 *c = order_counts(order_count) + b;
    st_u32 blocks = order_blocks(n);
    for (st_u32 d = 0u; d < ST_ORDER_DIGITS; d++)
        start[d] = c[d * blocks];
}

/* The lanes' rays: lane k that of position first + k step, or of first
 * where that lies at or beyond end; *alive: lane k's path goes on, as bit k. */
static void order_lanes(const st_params *p, __global const st_u32 *live_a,
                        __global const st_u32 *live_b, __global const st_ray *ray,
                        __global const st_path *path, st_u32 first, st_u32 step, st_u32 end,
                        st_lv3 *o, st_lv3 *d, st_u32 *alive)
{
    __global const st_u32 *list = st_live_list(p, live_a, live_b);
    st_f32 v[6][ST_W];
    *alive = 0u;
    for (st_u32 k = 0u; k < ST_W; k++) {
        st_u32 at = first + k * step;
        st_u32 i = st_live_item(list, at < end ? at : first);
        st_ray r = ray[i];
        for (st_u32 a = 0u; a < 3u; a++) {
            v[a][k] = r.o[a];
            v[3u + a][k] = r.d[a];
        }
        *alive |= (path[i].depth != ST_PATH_DEAD ? 1u : 0u) << k;
    }
    o->x = ST_VLOAD(ST_W, v[0]);
    o->y = ST_VLOAD(ST_W, v[1]);
    o->z = ST_VLOAD(ST_W, v[2]);
    d->x = ST_VLOAD(ST_W, v[3]);
    d->y = ST_VLOAD(ST_W, v[4]);
    d->z = ST_VLOAD(ST_W, v[5]);
}

/* Work-item b: the bounds of the sample of block b's rays (its first
 * ST_ORDER_SAMPLE positions, read in a run; paths alive, rays finite; a ray
 * outside them goes to an edge cell, which changes its place in the order,
 * nothing else), ST_W at a time, gathered into order_count's by atomic_max
 * (order_scan leaves them 0 for the next sort). The blocks' samples lie
 * all over the stream. */
__kernel void order_bounds(ST_STAGE_PARAMS)
{
    st_u32 n = st_live_count(&p), first, end;
    if (!order_block(ST_ITEM(), n, &first, &end))
        return;
    end = min(end, first + ST_ORDER_SAMPLE);
    st_u32 m[ST_ORDER_BOUNDS] = {0u};
    for (st_u32 g = first; g < end; g += ST_W) {
        st_lv3 o, d;
        st_u32 alive;
        order_lanes(&p, live_a, live_b, ray, path, g, 1u, end, &o, &d, &alive);
        st_f32 v[5][ST_W];
        st_lf x, y;
        st_order_octahedral(d, &x, &y);
        ST_VSTORE(ST_W, o.x, v[0]);
        ST_VSTORE(ST_W, o.y, v[1]);
        ST_VSTORE(ST_W, o.z, v[2]);
        ST_VSTORE(ST_W, x, v[3]);
        ST_VSTORE(ST_W, y, v[4]);
        for (st_u32 k = 0u; k < ST_W; k++) {
            if (!(alive >> k & 1u) || !isfinite(v[0][k] + v[1][k] + v[2][k] + v[3][k] + v[4][k]))
                continue;
            for (st_u32 c = 0u; c < 5u; c++) {
                st_u32 at = c < 3u ? c : 3u + c; /* order.h: st_order_frame_of */
                st_u32 neg = c < 3u ? at + 3u : at + 2u;
                m[at] = max(m[at], st_order_monotone(v[c][k]));
                m[neg] = max(m[neg], st_order_monotone(-v[c][k]));
            }
        }
    }
    for (st_u32 k = 0u; k < ST_ORDER_BOUNDS; k++)
        if (m[k])
            atomic_max(&order_count[k], m[k]);
}

/* The low and the high digit of a key (its dead mark left out). */
static st_u32 order_low(st_u32 key) { return key % ST_ORDER_DIGITS; }
static st_u32 order_high(st_u32 key) { return key / ST_ORDER_DIGITS % ST_ORDER_DIGITS; }

/* Work-item g: the keys of positions ST_W g .. ST_W g + ST_W - 1 (those
 * below the count) into order_key, in lanes, a dead path's marked. */
__kernel void order_keys(ST_STAGE_PARAMS)
{
    st_u32 n = st_live_count(&p), first = ST_W * ST_ITEM();
    if (first >= n)
        return;
    st_lv3 o, d;
    st_u32 alive;
    order_lanes(&p, live_a, live_b, ray, path, first, 1u, n, &o, &d, &alive);
    st_order_frame f = st_order_frame_of(order_count);
    st_i32 key[ST_W];
    ST_VSTORE(ST_W, st_order_key(&f, o, d), key);
    for (st_u32 k = 0u; k < min((st_u32)ST_W, n - first); k++)
        order_key[first + k] = (st_u32)key[k] | ((alive >> k & 1u) ? 0u : ST_ORDER_DEAD_KEY);
}

/* Work-item b: the counts of the low digits of block b's keys. */
__kernel void order_count_low(ST_STAGE_PARAMS)
{
    st_u32 n = st_live_count(&p), first, end;
    if (!order_block(ST_ITEM(), n, &first, &end))
        return;
    st_u32 count[ST_ORDER_DIGITS] = {0u};
    for (st_u32 g = first; g < end; g++)
        count[order_low(order_key[g])]++;
    order_put_counts(order_count, ST_ITEM(), n, count);
}

/* One work-item: the counts, digit by digit and block by block, become
 * their exclusive sums, the starts; and the bounds go back to 0. */
__kernel void order_scan(ST_STAGE_PARAMS)
{
    if (ST_ITEM() != 0u)
        return;
    st_u32 n = st_live_count(&p), sum = 0u;
    __global st_u32 *c = order_counts(order_count);
    for (st_u32 j = 0u; j < ST_ORDER_DIGITS * order_blocks(n); j++) {
        st_u32 here = c[j];
        c[j] = sum;
        sum += here;
    }
    for (st_u32 k = 0u; k < ST_ORDER_BOUNDS; k++)
        order_count[k] = 0u;
}

/* Work-item b: block b's positions, in order, to their low digit's range
 * of order_pair. */
__kernel void order_scatter_low(ST_STAGE_PARAMS)
{
    st_u32 n = st_live_count(&p), first, end;
    if (!order_block(ST_ITEM(), n, &first, &end))
        return;
    __global const st_u32 *list = st_live_list(&p, live_a, live_b);
    st_u32 start[ST_ORDER_DIGITS];
    order_get_starts(order_count, ST_ITEM(), n, start);
    for (st_u32 g = first; g < end; g++) {
        st_order_pair e = {order_key[g], st_live_item(list, g)};
        order_pair[start[order_low(e.key)]++] = e;
    }
}

/* Work-item b: the counts of the high digits of block b of order_pair. */
__kernel void order_count_high(ST_STAGE_PARAMS)
{
    st_u32 n = st_live_count(&p), first, end;
    if (!order_block(ST_ITEM(), n, &first, &end))
        return;
    st_u32 count[ST_ORDER_DIGITS] = {0u};
    for (st_u32 j = first; j < end; j++)
        count[order_high(order_pair[j].key)]++;
    order_put_counts(order_count, ST_ITEM(), n, count);
}

/* Work-item b: block b of order_pair, in order, to its high digit's range
 * of order (the items sorted by key, a dead path's marked ST_ORDER_DEAD)
 * and of order_ray (their rays, but a dead path's: this loop's reads of
 * them overlap, the trace's would wait on each). */
__kernel void order_scatter_high(ST_STAGE_PARAMS)
{
    st_u32 n = st_live_count(&p), first, end;
    if (!order_block(ST_ITEM(), n, &first, &end))
        return;
    st_u32 start[ST_ORDER_DIGITS];
    order_get_starts(order_count, ST_ITEM(), n, start);
    for (st_u32 j = first; j < end; j++) {
        st_order_pair e = order_pair[j];
        st_u32 at = start[order_high(e.key)]++;
        if (e.key & ST_ORDER_DEAD_KEY) {
            order[at] = e.item | ST_ORDER_DEAD;
            continue;
        }
        order[at] = e.item;
        order_ray[at] = ray[e.item];
    }
}
