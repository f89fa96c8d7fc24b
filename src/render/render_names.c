/* render_names.c — the names of the render's kernels and of its options'
 * values, by their enums (st_render.h, render_int.h): the lowest file of the
 * renderer, read by the scene's upload when it looks the kernels up and by
 * the pass loop and the command line. */
#include "render_int.h"

const char *const st_stage_names[ST_STAGE_COUNT] = {
    "generate_rays", "trace_rays", "shade_hits",
    "trace_shadow_rays", "live_scatter", "bin_samples", "splat_samples", "splat_tiles", "splat_pixels", "resolve_film"};

const char *const st_integrator_names[2] = {"direct", "path"};
const char *const st_reconstruction_names[2] = {"splat", "fis"};
const char *const st_packet_names[4] = {"auto", "none", "coherent", "all"};

const char *const st_adaptive_kernel_names[ST_ADAPTIVE_KERNELS] = {
    "adaptive_moments", "adaptive_estimate", "adaptive_blend"};

const char *const st_order_kernel_names[ST_ORDER_KERNELS] = {
    "order_bounds", "order_keys", "order_count_low", "order_scan", "order_scatter_low",
    "order_count_high", "order_scatter_high"};
