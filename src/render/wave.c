/* wave.c — the wavefront state (see wave.h): sizes from the one list in
 * st_shared.h, allocation and binding. */
#include "wave.h"

#include <string.h>

#define ST_WAVE_ELEM(name, type, extent) sizeof(type),
static const size_t elem_bytes[ST_WAVE_BUFFER_COUNT] = {ST_WAVE_BUFFERS(ST_WAVE_ELEM)};
#define ST_WAVE_EXTENT(name, type, extent) extent,
static const int extents[ST_WAVE_BUFFER_COUNT] = {ST_WAVE_BUFFERS(ST_WAVE_EXTENT)};

size_t st_wave_count(const st_wave *w, int b)
{
    switch (extents[b]) {
    case ST_PER_ITEM: return w->items;
    case ST_PER_PIXEL: return w->pixels;
    case ST_PER_ADAPTIVE: return w->adaptive ? w->pixels : 1;
    case ST_PER_BIN: return w->pixels + 1;
    case ST_PER_ORDER:
        return w->ordered ? ST_ORDER_COUNTS +
                                ST_ORDER_DIGITS * ((w->items + ST_ORDER_BLOCK - 1) / ST_ORDER_BLOCK)
                          : 1;
    case ST_PER_ORDER_ITEM: return w->ordered ? w->items : 1;
    default: return 1;
    }
}

size_t st_wave_bytes(const st_wave *w, int b)
{
    return elem_bytes[b] * st_wave_count(w, b);
}

st_status st_wave_create(st_device *dev, size_t items, size_t pixels, int adaptive, int ordered,
                         st_wave *w, st_error *err)
{
    memset(w, 0, sizeof *w);
    w->dev = dev;
    w->items = items;
    w->pixels = pixels;
    w->adaptive = adaptive;
    w->ordered = ordered;
    /* sums and counters that kernels only add to */
    static const int zeroed[] = {ST_WAVE_film,      ST_WAVE_pilot_film, ST_WAVE_moments,
                                 ST_WAVE_tally,     ST_WAVE_bin_tally,  ST_WAVE_stats,
                                 ST_WAVE_bin_count, ST_WAVE_order_count};
    st_status rc = ST_OK;
    for (int b = 0; b < ST_WAVE_BUFFER_COUNT && rc == ST_OK; b++)
        rc = st_device_buffer_create(dev, st_wave_bytes(w, b), NULL, &w->b[b], err);
    for (size_t z = 0; z < sizeof zeroed / sizeof zeroed[0] && rc == ST_OK; z++)
        rc = st_device_buffer_zero(dev, w->b[zeroed[z]], st_wave_bytes(w, zeroed[z]), err);
    if (rc != ST_OK)
        st_wave_destroy(w);
    return rc;
}

void st_wave_destroy(st_wave *w)
{
    for (int b = 0; b < ST_WAVE_BUFFER_COUNT; b++) {
        st_device_buffer_destroy(w->dev, w->b[b]);
        w->b[b] = NULL;
    }
}

st_status st_wave_set_params(cl_kernel k, const st_params *p, st_error *err)
{
    return st_device_set_arg(k, 0, sizeof *p, p, err);
}

/* Binds the wave's buffers from argument `first` on. */
static st_status bind_buffers(cl_kernel k, unsigned first, const cl_mem *b, int n,
                              st_error *err)
{
    st_status rc = ST_OK;
    for (int i = 0; i < n && rc == ST_OK; i++)
        rc = st_device_set_arg(k, first + (unsigned)i, sizeof(cl_mem), &b[i], err);
    return rc;
}

st_status st_wave_bind_stage(cl_kernel k, const st_params *p, const st_shading *sh,
                             const cl_mem scene[ST_SCENE_BUFFER_COUNT], const st_wave *w,
                             st_error *err)
{
    if (st_wave_set_params(k, p, err) || st_device_set_arg(k, 1, sizeof *sh, sh, err) ||
        bind_buffers(k, 2, scene, ST_SCENE_BUFFER_COUNT, err) ||
        bind_buffers(k, 2 + ST_SCENE_BUFFER_COUNT, w->b, ST_WAVE_BUFFER_COUNT, err))
        return err->status;
    return ST_OK;
}

st_status st_wave_bind_film(cl_kernel k, const st_params *p, const st_wave *w, st_error *err)
{
    if (st_wave_set_params(k, p, err) || bind_buffers(k, 1, w->b, ST_WAVE_BUFFER_COUNT, err))
        return err->status;
    return ST_OK;
}
