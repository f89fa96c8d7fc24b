/* preview.c — a look at the film while a render runs (st_renderer_set_preview,
 * for --display-server): after a wave, once the interval has passed, the
 * window's fixed-point sums are read back and divided on the host as
 * resolve_film divides them (radiance: negative values and non-finite
 * quotients 0, a pixel without weight 0), so a viewer sees the image grow.
 * It changes nothing on the device: no count, no buffer but the read. */
#include "render_int.h"

#include <math.h>
#include <stdlib.h>

void st_renderer_set_preview(st_renderer *r, double seconds, st_preview_fn fn, void *ctx)
{
    r->preview.fn = fn;
    r->preview.ctx = ctx;
    r->preview.seconds = seconds;
    r->preview.cost = 0.0;
}

/* I = Σ f L / Σ f of one channel, the kernel's float operations in its order. */
static float resolve(st_i64 sum, float w)
{
    float v = (float)sum * (1.0f / ST_FIXED_SCALE) / w;
    return w != 0.0f && isfinite(v) && v > 0.0f ? v : 0.0f;
}

st_status st_render_preview(st_renderer *r, st_wave *w, const st_render_options *o,
                            const st_u32 win[4], st_error *err)
{
    /* at most every `seconds`, and, where a look costs more than a fifth of
     * that (a large image), four times its cost apart: a viewer never takes
     * more than a fifth of the render */
    double now = st_render_now(), gap = 4.0 * r->preview.cost;
    if (now - r->preview.last < (gap > r->preview.seconds ? gap : r->preview.seconds))
        return ST_OK;
    static const char *const names[3] = {"R", "G", "B"};
    size_t pixels = (size_t)o->width * o->height;
    st_film_pixel *film = malloc(pixels * sizeof *film);
    st_image img = {0};
    if (!film)
        return st_fail(err, ST_ERR_NOMEM, "out of memory for the preview");
    st_status rc = st_device_buffer_read(r->dev, w->b[ST_WAVE_film], pixels * sizeof *film, film,
                                         err);
    if (rc == ST_OK)
        rc = st_image_create(&img, win[2], win[3], 3, names, err);
    for (st_u32 y = 0; rc == ST_OK && y < win[3]; y++)
        for (st_u32 x = 0; x < win[2]; x++) {
            const st_i64 *s = film[(size_t)(win[1] + y) * o->width + win[0] + x].sum;
            float wsum = (float)s[3] * (1.0f / ST_FIXED_SCALE);
            for (int c = 0; c < 3; c++)
                img.data[3 * ((size_t)y * win[2] + x) + (size_t)c] = resolve(s[c], wsum);
        }
    if (rc == ST_OK) {
        if (o->crop_w) {
            img.x0 = (int32_t)win[0];
            img.y0 = (int32_t)win[1];
            img.display_width = o->width;
            img.display_height = o->height;
        }
        r->preview.fn(r->preview.ctx, &img);
        r->preview.last = st_render_now(); /* the interval runs from the end of this look */
        r->preview.cost = r->preview.last - now;
    }
    st_image_free(&img);
    free(film);
    return rc;
}
