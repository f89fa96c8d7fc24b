/* diff.c — root-mean-square error, PSNR and maximum absolute difference of two images.
 *
 * Invariant: a result is produced only from finite R, G, B samples of the pixels two images share
 * (their overlap, placed by their data windows x0, y0 in display windows of one size; none
 * shared is an error); anything else is
 * an error, so a NaN can never hide as a "small" RMSE. Definitions (e.g. Gonzalez
 * & Woods, "Digital Image Processing", 4th ed., 2018, section 8.1, fidelity criteria):
 *   RMSE = sqrt( (1/N) sum_i (a_i - b_i)^2 ),  N = overlap pixels * 3
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

/* The pixels both images hold, placed by their data windows (x0, y0) in their display windows,
 * which must be of one size (st_image display_width/height; 0: the image's own size): two
 * whole images of one size are compared whole; a crop against its full render over the crop's
 * window. */
static st_status overlap(const st_image *a, const st_image *b, int64_t win[4], st_error *err)
{
    uint32_t aw = a->display_width ? a->display_width : a->width;
    uint32_t ah = a->display_width ? a->display_height : a->height;
    uint32_t bw = b->display_width ? b->display_width : b->width;
    uint32_t bh = b->display_width ? b->display_height : b->height;
    if (aw != bw || ah != bh) /* not windows of one image */
        return st_fail(err, ST_ERR_FORMAT, "image sizes differ: first %ux%u, second %ux%u", aw, ah,
                       bw, bh);
    int64_t x0 = a->x0 > b->x0 ? a->x0 : b->x0, y0 = a->y0 > b->y0 ? a->y0 : b->y0;
    int64_t ax1 = (int64_t)a->x0 + a->width, bx1 = (int64_t)b->x0 + b->width;
    int64_t ay1 = (int64_t)a->y0 + a->height, by1 = (int64_t)b->y0 + b->height;
    int64_t x1 = ax1 < bx1 ? ax1 : bx1, y1 = ay1 < by1 ? ay1 : by1;
    if (x1 <= x0 || y1 <= y0)
        return st_fail(err, ST_ERR_FORMAT, "images do not overlap: first %ux%u at (%d, %d), second "
                       "%ux%u at (%d, %d)", a->width, a->height, a->x0, a->y0, b->width, b->height,
                       b->x0, b->y0);
    win[0] = x0;
    win[1] = y0;
    win[2] = x1 - x0;
    win[3] = y1 - y0;
    return ST_OK;
}

st_status st_diff_images(const st_image *a, const st_image *b, st_diff_result *out, st_error *err)
{
    memset(out, 0, sizeof *out);
    int ia[3], ib[3];
    if (find_rgb(a, "first", ia, err) != ST_OK || find_rgb(b, "second", ib, err) != ST_OK)
        return err ? err->status : ST_ERR_FORMAT;
    int64_t win[4] = {0}; /* the overlap: x, y, w, h in the images' common frame */
    if (overlap(a, b, win, err) != ST_OK)
        return err ? err->status : ST_ERR_FORMAT;
    double total = 0.0, max_abs = 0.0;
    for (int64_t y = win[1]; y < win[1] + win[3]; y++) {
        double row = 0.0;
        for (int64_t x = win[0]; x < win[0] + win[2]; x++) {
            size_t pa = ((size_t)(y - a->y0) * a->width + (size_t)(x - a->x0)) * a->channels;
            size_t pb = ((size_t)(y - b->y0) * b->width + (size_t)(x - b->x0)) * b->channels;
            for (int k = 0; k < 3; k++) {
                float va = a->data[pa + (size_t)ia[k]], vb = b->data[pb + (size_t)ib[k]];
                if (check_finite(va, vb, (uint32_t)x, (uint32_t)y, k, err) != ST_OK)
                    return err ? err->status : ST_ERR_FORMAT;
                double d = (double)va - (double)vb;
                row += d * d;
                if (fabs(d) > max_abs)
                    max_abs = fabs(d);
            }
        }
        total += row;
    }
    uint64_t n = (uint64_t)win[2] * (uint64_t)win[3] * 3;
    out->compared = n;
    out->rmse = sqrt(total / (double)n);
    out->max_abs = max_abs;
    out->psnr = out->rmse > 0.0 ? 20.0 * log10(1.0 / out->rmse) : INFINITY;
    return ST_OK;
}

void st_diff_quantize_srgb8(st_image *img)
{
    size_t pixels = (size_t)img->width * img->height;
    for (uint32_t c = 0; c < img->channels; c++) {
        if (img->types[c] != ST_PIXEL_FLOAT)
            continue;
        for (size_t p = 0; p < pixels; p++) {
            float *v = &img->data[p * img->channels + c];
            *v = st_image_srgb8_decode(st_image_srgb_quantize(*v));
        }
    }
}
