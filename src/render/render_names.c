/* render_names.c — the names of the render's kernels and of its options'
 * values, by their enums (st_render.h, render_int.h): the lowest file of the
 * renderer, read by the scene's upload when it looks the kernels up and by
 * the pass loop and the command line; and an AOV's channels under its names. */
#include "render_int.h"

const char *const st_stage_names[ST_STAGE_COUNT] = {
    "generate_rays", "trace_rays", "shade_hits",
    "trace_shadow_rays", "live_scatter", "bin_samples", "splat_samples", "splat_tiles", "splat_pixels", "resolve_film"};

const char *const st_integrator_names[2] = {"direct", "path"};
const char *const st_reconstruction_names[2] = {"splat", "fis"};
const char *const st_packet_names[4] = {"auto", "none", "coherent", "all"};

const st_aov_layout st_aov_layouts[ST_AOV_COUNT] = {
    [ST_AOV_NONE] = {"", "", 0, {NULL, NULL, NULL}},
    [ST_AOV_ALBEDO] = {"albedo", "Albedo.", 3, {"Albedo.R", "Albedo.G", "Albedo.B"}},
    [ST_AOV_NORMAL] = {"normal", "N.", 3, {"N.X", "N.Y", "N.Z"}},
    [ST_AOV_POSITION] = {"position", "P.", 3, {"P.X", "P.Y", "P.Z"}},
    [ST_AOV_DEPTH] = {"depth", "Z.", 1, {"Z", NULL, NULL}},
};

#define ST_KERNEL_NAME(id, name, stage) name,
const char *const st_kernel_names[ST_KERNEL_COUNT] = {ST_KERNEL_LIST(ST_KERNEL_NAME)};
#undef ST_KERNEL_NAME
#define ST_KERNEL_STAGE(id, name, stage) stage,
const int st_kernel_stages[ST_KERNEL_COUNT] = {ST_KERNEL_LIST(ST_KERNEL_STAGE)};
#undef ST_KERNEL_STAGE

st_status st_render_aov_image(const st_image *rendered, st_u32 aov, st_image *out,
                              st_error *err)
{
    const st_aov_layout *l = &st_aov_layouts[aov];
    if (st_image_create(out, rendered->width, rendered->height, l->channels, l->channel, err))
        return err->status;
    for (size_t i = 0; i < (size_t)rendered->width * rendered->height; i++)
        for (st_u32 c = 0; c < l->channels; c++)
            out->data[l->channels * i + c] = rendered->data[rendered->channels * i + c];
    st_image_place_like(out, rendered);
    return ST_OK;
}
