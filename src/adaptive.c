/* adaptive.c — adaptive sampling's rounds (see st_render.h and
 * kernels/adaptive.cl): after the first min_spp samples everywhere,
 * adaptive_mark picks the pixels whose error estimate is above the
 * threshold, and each round gives every one of them the next `batch`
 * samples of its own sequence. Only the active count returns to the host.
 * Rounds grow with the samples taken (batch = half of them, so a pixel's
 * sample count roughly follows 1.5^k). */
#include "render_int.h"

#include <stdlib.h>

/* One decision: books p->adaptive_batch more samples for every pixel still
 * above the threshold; *count gets how many. */
static st_status mark_round(st_renderer *r, const st_params *p, st_wave *w, size_t pixels,
                            st_u32 *count, st_error *err)
{
    st_u32 zero = 0;
    *count = 0;
    if (st_device_buffer_write(r->dev, w->b[ST_WAVE_active_count], sizeof zero, &zero, err) ||
        st_wave_set_params(r->mark, p, err) ||
        st_device_launch(r->dev, r->mark, pixels, 0, err) ||
        st_device_buffer_read(r->dev, w->b[ST_WAVE_active_count], sizeof *count, count, err))
        return err->status;
    return ST_OK;
}

st_status st_render_adaptive(st_renderer *r, st_params *p, st_wave *w,
                             const st_render_options *o, st_progress_state *pr,
                             st_render_stats *st, st_error *err)
{
    size_t pixels = (size_t)o->width * o->height;
    st_u32 *init = malloc(pixels * sizeof *init);
    if (!init)
        return st_fail(err, ST_ERR_NOMEM, "out of memory for the adaptive state");
    for (size_t i = 0; i < pixels; i++)
        init[i] = o->min_spp;
    st_status rc = st_device_buffer_write(r->dev, w->b[ST_WAVE_pixel_spp], pixels * sizeof *init,
                                          init, err);
    free(init);
    if (rc == ST_OK)
        rc = st_wave_bind_film(r->mark, p, w, err);
    p->adaptive_threshold = o->noise_threshold;
    p->adaptive_max_spp = o->spp;
    for (st_u32 done = o->min_spp; rc == ST_OK && done < o->spp;) {
        st_u32 batch = done / 2 > 1 ? done / 2 : 1, count;
        if (batch > o->spp - done)
            batch = o->spp - done;
        p->adaptive_count = 0;
        p->adaptive_batch = batch;
        if ((rc = mark_round(r, p, w, pixels, &count, err)) != ST_OK || count == 0)
            break;
        p->adaptive_count = count;
        p->adaptive_base = done;
        rc = st_render_items(r, p, w, o, 0, (st_u64)count * batch, pr, st, err);
        st->samples += (st_u64)count * batch;
        done += batch;
    }
    p->adaptive_count = 0;
    return rc;
}
