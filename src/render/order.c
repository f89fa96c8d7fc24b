/* order.c — the ray order before a trace (render_int.h: st_render_order):
 * order.cl's launches, which the plan asks for (plan.c). */
#include "render_int.h"

ST_STATIC_ASSERT(ST_ORDER_KEY_BITS == 2u * ST_ORDER_DIGIT_BITS &&
                     3u * ST_ORDER_ORIGIN_BITS + 2u * ST_ORDER_DIR_BITS <= ST_ORDER_KEY_BITS,
                 "order.cl sorts keys of two digits");

st_status st_render_order(st_renderer *r, const st_params *p, size_t n, size_t local,
                          st_error *err)
{
    /* the kernels in turn: order_keys a work-item per ST_W positions, the scans
     * one work-item, the others a work-item per block of positions, one a
     * group (each keeps its block's counts in its own array, which a CPU
     * device would copy for every work-item of a group) */
    static const int run[] = {ST_K_ORDER_BOUNDS,     ST_K_ORDER_KEYS,        ST_K_ORDER_COUNT_LOW,
                              ST_K_ORDER_SCAN,       ST_K_ORDER_SCATTER_LOW, ST_K_ORDER_COUNT_HIGH,
                              ST_K_ORDER_SCAN,       ST_K_ORDER_SCATTER_HIGH};
    size_t blocks = (n + ST_ORDER_BLOCK - 1u) / ST_ORDER_BLOCK;
    for (size_t j = 0; j < sizeof run / sizeof run[0]; j++) {
        cl_kernel k = r->kernel[run[j]];
        size_t items = run[j] == ST_K_ORDER_KEYS   ? st_render_lane_items(r->dev, n)
                       : run[j] == ST_K_ORDER_SCAN ? 1
                                                   : blocks;
        size_t group = run[j] == ST_K_ORDER_KEYS ? local : 1;
        if (st_wave_set_params(k, p, err) != ST_OK)
            return err->status;
        st_render_note_ran(r, k);
        if (st_device_launch(r->dev, k, items, group, err) != ST_OK)
            return err->status;
    }
    return ST_OK;
}
