/* cli_check.c — the furnace check of `strata bench` (see cli_check.h). */
#include "cli_check.h"

#include <math.h>
#include <stdio.h>

#include "st_render.h"
#include "st_scene.h"

#define FURNACE_ALBEDO 0.5
#define FURNACE_EMISSION 1.0

st_status st_cli_check_device(st_device *dev, const st_render_options *o, st_cli_check *out,
                              st_error *err)
{
    st_render_options c = *o;
    c.width = c.height = 32;
    c.spp = 64;
    c.sample_begin = c.sample_end = 0;
    c.profile = 0;
    c.wave = 0;
    st_u32 depth = c.integrator == ST_INTEGRATOR_DIRECT ? 1u : c.max_depth;
    out->expected = 0.0;
    for (st_u32 k = 0; k <= depth; k++)
        out->expected += FURNACE_EMISSION * pow(FURNACE_ALBEDO, k);
    st_scene *scene = NULL;
    st_renderer *r = NULL;
    st_image img = {0};
    st_status rc = ST_OK;
    if (st_scene_load("furnace", &scene, err) || st_renderer_create(dev, scene, &r, err) ||
        st_render(r, &c, &img, NULL, NULL, NULL, NULL, err)) {
        rc = err->status;
        goto done;
    }
    double sum = 0.0;
    size_t n = (size_t)img.width * img.height;
    for (size_t i = 0; i < n; i++)
        for (int ch = 0; ch < 3; ch++)
            sum += img.data[img.channels * i + ch];
    out->measured = sum / (3.0 * n);
    double rel = fabs(out->measured / out->expected - 1.0);
    snprintf(out->message, sizeof out->message,
             "furnace scene mean %.5f, analytic %.5f (off by %.2f%%, tolerance %.0f%%)",
             out->measured, out->expected, 100.0 * rel, 100.0 * ST_CHECK_TOLERANCE);
    if (!(rel <= ST_CHECK_TOLERANCE))
        rc = st_fail(err, ST_ERR_CHECK, "bench check failed on this device: %s", out->message);
done:
    st_image_free(&img);
    st_renderer_destroy(r);
    st_scene_destroy(scene);
    return rc;
}
