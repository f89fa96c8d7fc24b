/* image_png.c — 8-bit sRGB PNG files of an st_image, and the sRGB transfer functions.
 *
 * Invariant: a PNG is never written in place. libpng encodes it into an st_outfile
 * (st_outfile.h), the temporary beside the destination that is renamed over it only when
 * complete, so the folder afterwards holds either the complete new file or what it held before.
 * The container comes from image.c; this file knows no other format. Quantisation follows
 * IEC 61966-2-1:1999 (sRGB), section 5.2, the same formulas the header states. stb (reading) reports failure as a NULL
 * result plus a global reason (stbi_failure_reason), libpng (writing) through its error callback
 * and longjmp; this file turns both into st_error messages.
 */
#include "st_image.h"
#include "st_outfile.h"
#include "st_version.h"

#include <stb/stb_image.h> /* Debian: implementations live in libstb (-lstb) */
#include <png.h>

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

float st_image_srgb8_decode(uint8_t code) { return (float)srgb_decode(code / 255.0); }

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

/* libpng's callbacks: bytes go to the outfile, which keeps the first failure's errno for
 * commit to report; an error keeps libpng's message and unwinds to png_encode's setjmp. */
static void png_sink(png_structp png, png_bytep data, size_t n)
{
    st_outfile_write(png_get_io_ptr(png), data, n);
}

static void png_no_flush(png_structp png) { (void)png; }

static void png_fail(png_structp png, png_const_charp msg)
{
    snprintf(png_get_error_ptr(png), 128, "%s", msg);
    png_longjmp(png, 1);
}

static void png_no_warning(png_structp png, png_const_charp msg) { (void)png, (void)msg; }

/* A text chunk: tEXt (Latin-1) for ASCII values, iTXt (UTF-8) for any other. */
static void png_text_of(png_text *t, const char *key, const char *value)
{
    int ascii = 1;
    for (const char *c = value; *c; c++)
        ascii &= (unsigned char)*c < 0x80;
    t->compression = ascii ? PNG_TEXT_COMPRESSION_NONE : PNG_ITXT_COMPRESSION_NONE;
    t->key = (png_charp)key;
    t->text = (png_charp)value;
}

/* Encodes px (rows of RGB bytes) into out: an sRGB chunk (with the gAMA and cHRM that stand for
 * it, as the PNG specification recommends), "Software" and the attributes as text. */
static st_status png_encode(st_outfile *out, const char *path, const st_image *img,
                            const uint8_t *px, const st_attr *attrs, int nattrs, st_error *err)
{
    char why[128] = "out of memory", software[128];
    snprintf(software, sizeof software, "strata %s", st_version);
    png_text *text = calloc((size_t)nattrs + 1, sizeof *text);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, why, png_fail, png_no_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    int failed = !text || !info;
    if (!failed && setjmp(png_jmpbuf(png))) /* png_fail lands here */
        failed = 1;
    if (failed) {
        png_destroy_write_struct(&png, &info);
        free(text);
        return st_fail(err, ST_ERR_FORMAT, "%s: PNG encoding failed (%s)", path, why);
    }
    png_set_write_fn(png, out, png_sink, png_no_flush);
    png_set_IHDR(png, info, img->width, img->height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_text_of(&text[0], "Software", software);
    for (int i = 0; i < nattrs; i++)
        png_text_of(&text[i + 1], attrs[i].name, attrs[i].value);
    png_set_text(png, info, text, nattrs + 1);
    png_write_info(png, info);
    for (uint32_t y = 0; y < img->height; y++)
        png_write_row(png, px + (size_t)y * img->width * 3);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    free(text);
    return ST_OK;
}

st_status st_image_save_png_text(const char *path, const st_image *img, const st_attr *attrs,
                                 int nattrs, st_error *err)
{
    int rgb[3];
    if (pick_rgb(path, img, rgb, err) != ST_OK)
        return err ? err->status : ST_ERR_USAGE;
    for (int i = 0; i < nattrs; i++) {
        size_t n = strnlen(attrs[i].name, sizeof attrs[i].name);
        if (n == 0 || n > 79 || attrs[i].name[0] == ' ' || attrs[i].name[n - 1] == ' ')
            return st_fail(err, ST_ERR_USAGE, "%s: text key '%.64s' is not 1..79 characters",
                           path, attrs[i].name);
    }
    uint8_t *px = quantize_rgb(img, rgb);
    if (!px)
        return st_fail(err, ST_ERR_NOMEM, "%s: cannot allocate %ux%u RGB pixels", path,
                       img->width, img->height);
    st_outfile *out = NULL;
    st_status s = st_outfile_open(path, &out, err);
    if (s == ST_OK) {
        s = png_encode(out, path, img, px, attrs, nattrs, err);
        if (s == ST_OK)
            s = st_outfile_commit(out, err);
        else
            st_outfile_abort(out);
    }
    free(px);
    return s;
}

st_status st_image_save_png(const char *path, const st_image *img, st_error *err)
{
    return st_image_save_png_text(path, img, NULL, 0, err);
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
                       why && *why ? why : "cut short or corrupt");
    }
    st_error local = {ST_OK, ""};
    if (st_image_create(img, (uint32_t)w, (uint32_t)h, 3, NULL, &local) != ST_OK) {
        stbi_image_free(px);
        return st_fail(err, local.status, "%s: %s", path, local.msg + strlen("image: "));
    }
    float lut[256];
    for (int v = 0; v < 256; v++)
        lut[v] = st_image_srgb8_decode((uint8_t)v);
    size_t count = (size_t)w * (size_t)h * 3;
    for (size_t i = 0; i < count; i++)
        img->data[i] = lut[px[i]];
    stbi_image_free(px);
    return ST_OK;
}
