/* st_diff.h — how far apart two images are: RMSE, PSNR and the largest absolute difference.
 *
 * The one comparison behind `strata diff`, the golden-image tests and the convergence studies.
 * It reads the FLOAT channels named R, G and B of each image (any order, other channels ignored)
 * over the pixels both hold, placed by their data windows (st_image x0, y0) in display windows
 * that must be of one size: a crop (render --crop) compared with its full render is compared over
 * the crop's window. It never modifies either image. Errors (ST_ERR_FORMAT, one line naming which
 * image and what): the (display) sizes differ, the windows do not overlap, a channel is missing or
 * not FLOAT, a value is NaN or infinite.
 */
#ifndef ST_DIFF_H
#define ST_DIFF_H

#include "st_error.h"
#include "st_image.h"

#include <stdint.h>

typedef struct st_diff_result {
    double rmse;       /* sqrt( sum over pixels p, channels c in {R,G,B} of (a - b)^2 / compared ) */
    double psnr;       /* 20 log10(1 / rmse) in dB (peak 1.0); +INFINITY when rmse == 0 */
    double max_abs;    /* max |a - b| over the same samples */
    uint64_t compared; /* number of samples compared: overlap pixels * 3 */
} st_diff_result;

/* Compares a with b (a is "first image", b "second image" in messages). On failure *out is zeroed. */
st_status st_diff_images(const st_image *a, const st_image *b, st_diff_result *out, st_error *err);

/* What an 8-bit sRGB PNG of img holds, as linear values: every FLOAT sample
 * clamped to [0, 1], quantised as st_image_save_png writes it and decoded as
 * st_image_load_png reads it back (the PNG of a render with the default
 * exposure and tone curve). Lets `strata diff --convert` compare an EXR with a
 * PNG in the PNG's terms; UINT channels are left alone. */
void st_diff_quantize_srgb8(st_image *img);

#endif
