/* image_png.c — 8-bit sRGB PNG files of an st_image, and the sRGB transfer functions.
 *
 * Invariant: a PNG is never written in place. stb_image_write encodes it into an st_outfile
 * (st_outfile.h), the temporary beside the destination that is renamed over it only when
 * complete, so the folder afterwards holds either the complete new file or what it held before.
 * The container comes from image.c; this file knows no other format. Quantisation follows
 * IEC 61966-2-1:1999 (sRGB), section 5.2, the same formulas the header states. stb reports failure as a NULL/0 result plus
 * a global reason (stbi_failure_reason), which this file turns into st_error messages.
 */
#include "st_image.h"
#include "st_outfile.h"

#include <stb/stb_image.h> /* Debian: implementations live in libstb (-lstb) */
#include <stb/stb_image_write.h>

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- sRGB transfer functions (IEC 61966-2-1:1999 section 5.2) ---------------------------- */

/* OETF in double: 12.92 L below 0.0031308, else 1.055 L^(1/2.4) - 0.055; input clamped. */
static double srgb_encode(double x)
{
    if (!(x > 0.0)) /* also NaN */
        return 0.0;
    if (x >= 1.0)
        return 1.0;
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

/* EOTF in double: V/12.92 below 0.04045, else ((V + 0.055)/1.055)^2.4; input clamped. */
static double srgb_decode(double v)
{
    if (!(v > 0.0))
        return 0.0;
    if (v >= 1.0)
        return 1.0;
    return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}

float st_image_srgb_encode(float linear) { return (float)srgb_encode(linear); }

float st_image_srgb_decode(float encoded) { return (float)srgb_decode(encoded); }

uint8_t st_image_srgb_quantize(float linear)
{
    return (uint8_t)floor(255.0 * srgb_encode(linear) + 0.5); /* in [0, 255] after clamping */
}

/* ---- saving -------------------------------------------------------------------------------- */

/* The source channels: R, G, B by name when all three exist, else the first three. */
static st_status pick_rgb(const char *path, const st_image *img, int rgb[3], st_error *err)
{
    if (!img || !img->data || img->width == 0 || img->height == 0 || img->channels == 0 ||
        img->channels > ST_IMAGE_MAX_CHANNELS)
        return st_fail(err, ST_ERR_USAGE, "%s: not a valid image (size, channels or buffer)", path);
    rgb[0] = st_image_find_channel(img, "R");
    rgb[1] = st_image_find_channel(img, "G");
    rgb[2] = st_image_find_channel(img, "B");
    if (rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0) {
        if (img->channels < 3)
            return st_fail(err, ST_ERR_FORMAT, "%s: PNG needs R, G, B or 3 channels, image has %u",
                           path, img->channels);
        rgb[0] = 0, rgb[1] = 1, rgb[2] = 2;
    }
    for (int k = 0; k < 3; k++)
        if (img->types[rgb[k]] != ST_PIXEL_FLOAT)
            return st_fail(err, ST_ERR_FORMAT, "%s: channel '%s' is uint; PNG needs float colour",
                           path, img->channel_names[rgb[k]]);
    /* stb_image_write sizes its filter buffer as int (w*3 + 1) * h */
    if (img->width > (uint32_t)(INT_MAX / 3 - 1) ||
        (uint64_t)(img->width * 3ull + 1) * img->height > (uint64_t)INT_MAX)
        return st_fail(err, ST_ERR_FORMAT, "%s: %ux%u is too large for PNG", path, img->width,
                       img->height);
    return ST_OK;
}

static uint8_t *quantize_rgb(const st_image *img, const int rgb[3])
{
    size_t n = (size_t)img->width * img->height;
    uint8_t *px = malloc(n * 3);
    if (!px)
        return NULL;
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            px[i * 3 + k] = st_image_srgb_quantize(img->data[i * img->channels + (size_t)rgb[k]]);
    return px;
}

/* stb's write callback: the outfile keeps the first failure's errno for commit to report. */
static void sink_write(void *context, void *data, int size)
{
    if (size > 0)
        st_outfile_write(context, data, (size_t)size);
}

st_status st_image_save_png(const char *path, const st_image *img, st_error *err)
{
    int rgb[3];
    if (pick_rgb(path, img, rgb, err) != ST_OK)
        return err ? err->status : ST_ERR_USAGE;
    uint8_t *px = quantize_rgb(img, rgb);
    if (!px)
        return st_fail(err, ST_ERR_NOMEM, "%s: cannot allocate %ux%u RGB pixels", path,
                       img->width, img->height);
    st_outfile *out = NULL;
    st_status s = st_outfile_open(path, &out, err);
    if (s == ST_OK) {
        int ok = stbi_write_png_to_func(sink_write, out, (int)img->width, (int)img->height, 3, px,
                                        (int)img->width * 3);
        if (ok) {
            s = st_outfile_commit(out, err);
        } else {
            st_outfile_abort(out);
            s = st_fail(err, ST_ERR_NOMEM, "%s: PNG encoding failed (out of memory)", path);
        }
    }
    free(px);
    return s;
}

/* ---- loading ------------------------------------------------------------------------------- */

st_status st_image_load_png(const char *path, st_image *img, st_error *err)
{
    memset(img, 0, sizeof *img);
    FILE *f = fopen(path, "rb");
    if (!f)
        return st_fail(err, ST_ERR_IO, "%s: cannot open (%s)", path, strerror(errno));
    int w = 0, h = 0, n = 0;
    uint8_t *px = stbi_load_from_file(f, &w, &h, &n, 3);
    fclose(f);
    if (!px) {
        const char *why = stbi_failure_reason();
        return st_fail(err, ST_ERR_FORMAT, "%s: cannot decode image (%s)", path,
                       why ? why : "unknown reason");
    }
    st_error local = {ST_OK, ""};
    if (st_image_create(img, (uint32_t)w, (uint32_t)h, 3, NULL, &local) != ST_OK) {
        stbi_image_free(px);
        return st_fail(err, local.status, "%s: %s", path, local.msg + strlen("image: "));
    }
    float lut[256];
    for (int v = 0; v < 256; v++)
        lut[v] = (float)srgb_decode(v / 255.0);
    size_t count = (size_t)w * (size_t)h * 3;
    for (size_t i = 0; i < count; i++)
        img->data[i] = lut[px[i]];
    stbi_image_free(px);
    return ST_OK;
}
