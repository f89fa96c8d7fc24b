/* diff.c — root-mean-square error, PSNR and maximum absolute difference of two images.
 *
 * Invariant: a result is produced only from finite R, G, B samples of two images of equal size;
 * anything else is an error, so a NaN can never hide as a "small" RMSE. Definitions (e.g. Gonzalez
 * & Woods, "Digital Image Processing", 4th ed., 2018, section 8.1, fidelity criteria):
 *   RMSE = sqrt( (1/N) sum_i (a_i - b_i)^2 ),  N = width * height * 3
 *   PSNR = 20 log10(peak / RMSE) with peak = 1.0 (linear radiance scale), infinite when RMSE = 0.
 * Differences and squares are taken in double, summed per row and the row sums added, which keeps
 * the rounding error (relative ~1e-16 per addition) far below any tolerance a test states.
 * Tests: test_diff.c.
 */
#include "st_diff.h"

#include <math.h>
#include <string.h>

static const char *const rgb_names[3] = {"R", "G", "B"};

/* Finds the FLOAT channels R, G, B of img, naming img by `which` in errors. */
static st_status find_rgb(const st_image *img, const char *which, int idx[3], st_error *err)
{
    if (!img || !img->data || img->width == 0 || img->height == 0)
        return st_fail(err, ST_ERR_FORMAT, "%s image: empty or without pixels", which);
    for (int k = 0; k < 3; k++) {
        idx[k] = st_image_find_channel(img, rgb_names[k]);
        if (idx[k] < 0)
            return st_fail(err, ST_ERR_FORMAT, "%s image: no channel %s", which, rgb_names[k]);
        if (img->types[idx[k]] != ST_PIXEL_FLOAT)
            return st_fail(err, ST_ERR_FORMAT, "%s image: channel %s is not float", which,
                           rgb_names[k]);
    }
    return ST_OK;
}

/* Reports the first non-finite sample of (x, y) among a's and b's R, G, B channels, if any. */
static st_status check_finite(float va, float vb, uint32_t x, uint32_t y, int k, st_error *err)
{
    if (!isfinite(va))
        return st_fail(err, ST_ERR_FORMAT, "first image: non-finite %s at pixel (%u, %u)",
                       rgb_names[k], x, y);
    if (!isfinite(vb))
        return st_fail(err, ST_ERR_FORMAT, "second image: non-finite %s at pixel (%u, %u)",
                       rgb_names[k], x, y);
    return ST_OK;
}

st_status st_diff_images(const st_image *a, const st_image *b, st_diff_result *out, st_error *err)
{
    memset(out, 0, sizeof *out);
    int ia[3], ib[3];
    if (find_rgb(a, "first", ia, err) != ST_OK || find_rgb(b, "second", ib, err) != ST_OK)
        return err ? err->status : ST_ERR_FORMAT;
    if (a->width != b->width || a->height != b->height)
        return st_fail(err, ST_ERR_FORMAT, "image sizes differ: first %ux%u, second %ux%u",
                       a->width, a->height, b->width, b->height);
    double total = 0.0, max_abs = 0.0;
    for (uint32_t y = 0; y < a->height; y++) {
        double row = 0.0;
        for (uint32_t x = 0; x < a->width; x++) {
            size_t pa = ((size_t)y * a->width + x) * a->channels;
            size_t pb = ((size_t)y * b->width + x) * b->channels;
            for (int k = 0; k < 3; k++) {
                float va = a->data[pa + (size_t)ia[k]], vb = b->data[pb + (size_t)ib[k]];
                if (check_finite(va, vb, x, y, k, err) != ST_OK)
                    return err ? err->status : ST_ERR_FORMAT;
                double d = (double)va - (double)vb;
                row += d * d;
                if (fabs(d) > max_abs)
                    max_abs = fabs(d);
            }
        }
        total += row;
    }
    uint64_t n = (uint64_t)a->width * a->height * 3;
    out->compared = n;
    out->rmse = sqrt(total / (double)n);
    out->max_abs = max_abs;
    out->psnr = out->rmse > 0.0 ? 20.0 * log10(1.0 / out->rmse) : INFINITY;
    return ST_OK;
}
