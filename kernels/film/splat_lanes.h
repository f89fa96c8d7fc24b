/* splat_lanes.h — the splat of up to ST_N samples a call, written once over
 * ST_N lanes (lanes.h), one sample a lane for its taps' range and weights
 * (filter_lanes.h), then each sample's splat in turn (splat_weighted).
 * film.cl includes it once per width it needs, with ST_N defined, and gets
 * max_abs<N> and splat_items<N>:
 *   1: splat_samples' one sample a work-item (filter importance sampling,
 *      the reference of the tile paths) and a GPU's splat_tiles;
 *   ST_W: a CPU work-item's samples in splat_tiles.
 * Each lane computes what width 1 computes (filter_lanes.h), so the film's
 * integers do not depend on the width. No include guard: one copy per ST_N. */
#ifndef ST_N
#error "define ST_N (the lane count) before including splat_lanes.h"
#endif

#define ST_F ST_VEC(float, ST_N)
#define ST_I ST_VEC(int, ST_N)

/* Per lane l the largest |w[k N + l]| of its n_l weights (m >= every
 * n_l), a NaN passed over as fmax would (a comparison, which compiles to
 * one max, where fmax's NaN rule took four instructions per weight). */
ST_HOT ST_F ST_CAT(max_abs, ST_N)(const float *w, ST_I n, int m)
{
    ST_F b = (ST_F)(0.0f);
    for (int k = 0; k < m; k++) {
        ST_F a = fabs(ST_VLOAD(ST_N, w + k * ST_N));
        b = ST_SELECT(ST_N, b, a, (a > b) & ((ST_I)(k) < n));
    }
    return b;
}

/* The items item[0 .. n) (n <= ST_N, a private list) to d: their taps'
 * weights made in ST_N lanes at once, one sample a lane, then each
 * sample's splat in turn (splat_weighted). Their counts start from their
 * tally slots and go back there, or, where d gathers counts (d->counts, a
 * tile's bin), start from zero and are added there. Where d has an int32
 * window, the room of the samples that fit it is made once for all
 * (near_room). A lane past n weighs a sample of no taps. */
ST_HOT void ST_CAT(splat_items, ST_N)(const st_params *p, const st_u32 *item, st_u32 n,
                                      __global const st_sample *sample,
                                      __global const st_path *path, __global st_tally *tally,
                                      __global st_film_stats *stats,
                                      __global const st_f32 *splat_scale, splat_dest *d)
{
    float sx[ST_N], sy[ST_N], wx[ST_MAX_TAPS * ST_N], wy[ST_MAX_TAPS * ST_N];
    for (st_u32 l = 0; l < ST_N; l++) {
        st_sample s = sample[item[l < n ? l : 0]];
        sx[l] = s.film[0];
        sy[l] = s.film[1];
    }
    /* every lane's taps at once; a lane past n has none */
    ST_F fx = ST_VLOAD(ST_N, sx), fy = ST_VLOAD(ST_N, sy);
    ST_I x0, x1, y0, y1, live = ST_IOTA(ST_N) < (int)n;
    ST_CAT(st_tap_range, ST_N)(fx, p->filter.radius, (int)p->width, &x0, &x1);
    ST_CAT(st_tap_range, ST_N)(fy, p->filter.radius, (int)p->height, &y0, &y1);
    ST_I nx = ST_SELECT(ST_N, (ST_I)(0), x1 - x0 + 1, live & (x1 >= x0));
    ST_I ny = ST_SELECT(ST_N, (ST_I)(0), y1 - y0 + 1, live & (y1 >= y0));
    int lx[ST_N], hx[ST_N], ly[ST_N], hy[ST_N], cx[ST_N], cy[ST_N], mx = 0, my = 0;
    ST_VSTORE(ST_N, x0, lx);
    ST_VSTORE(ST_N, x1, hx);
    ST_VSTORE(ST_N, y0, ly);
    ST_VSTORE(ST_N, y1, hy);
    ST_VSTORE(ST_N, nx, cx);
    ST_VSTORE(ST_N, ny, cy);
    for (st_u32 l = 0; l < ST_N; l++) {
        mx = max(mx, cx[l]);
        my = max(my, cy[l]);
    }
    ST_F wbx = (ST_F)(0.0f), wby = (ST_F)(0.0f);
    if (splat_weighs(p)) {
        st_filter flt = p->filter;
        ST_CAT(st_filter_taps, ST_N)(&flt, d->turn, x0, nx, mx, fx, wx);
        ST_CAT(st_filter_taps, ST_N)(&flt, d->turn, y0, ny, my, fy, wy);
        wbx = ST_CAT(max_abs, ST_N)(wx, nx, mx);
        wby = ST_CAT(max_abs, ST_N)(wy, ny, my);
    }
    float bx[ST_N], by[ST_N];
    ST_VSTORE(ST_N, wbx, bx);
    ST_VSTORE(ST_N, wby, by);
    float3 L[ST_N];
    st_tally t[ST_N];
    float scale[ST_N];
    int near[ST_N], need = 0, r0 = INT_MAX, r1 = INT_MIN;
    for (st_u32 l = 0; l < n; l++) {
        if (d->counts)
            t[l] = (st_tally){0u, 0u, 0u, 0u};
        else
            t[l] = tally[item[l]];
        L[l] = item_radiance(item[l], path, stats, &t[l]);
        scale[l] = item_scale(p, splat_scale, sample[item[l]]);
        near[l] = 0;
        if (!d->near || !splat_weighs(p) || cx[l] <= 0 || cy[l] <= 0)
            continue;
        /* a tap's integer is at most its bound plus 1/2 (round) */
        float b = tap_bound(bx[l], by[l], scale[l], (float4)(L[l], 1.0f));
        near[l] = b <= NEAR_TAP_MAX;
        if (near[l]) {
            need += (int)b + 1;
            r0 = min(r0, ly[l]);
            r1 = max(r1, hy[l]);
        }
    }
    if (need)
        near_room(d, r0 - d->oy, r1 - d->oy, need);
    for (st_u32 l = 0; l < n; l++) {
        tap_weights w = {(int4)(lx[l], hx[l], ly[l], hy[l]), wx + l, wy + l, ST_N, bx[l], by[l],
                         near[l]};
        splat_weighted(p, item[l], sample[item[l]], w, L[l], t[l], scale[l], tally, stats, d);
    }
}

#undef ST_I
#undef ST_F
