/* cli_check.h — the bench's correctness gate: like LuxMark, strata reports no
 * speed for a device that renders a wrong image. The check renders the
 * built-in furnace scene (an emitting, reflecting closed cube: every camera
 * ray has radiance Σ_{k=0..D} a^k, a = 0.5, in closed form) with the bench's
 * device, sampler, filter and integrator, and compares. */
#ifndef ST_CLI_CHECK_H
#define ST_CLI_CHECK_H

#include "cli_args.h"
#include "st_device.h"

typedef struct st_cli_check {
    double expected, measured; /* mean pixel value */
    char message[160];
} st_cli_check;

/* Relative tolerance of the check on the image mean: 32x32 pixels at 64 spp
 * give a standard error near 0.3%; 2% leaves a wide margin. */
#define ST_CHECK_TOLERANCE 0.02

/* ST_ERR_CHECK (and the message) when the device's image is wrong. */
st_status st_cli_check_device(st_device *dev, const st_render_options *o, st_cli_check *out,
                              st_error *err);

#endif
