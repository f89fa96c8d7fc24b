/* image.c — the st_image container.
 *
 * Invariant: an st_image owns exactly one buffer of width*height*channels 4-byte samples, reached
 * through both img->data (FLOAT channels) and img->udata (UINT channels); channel names are
 * distinct, non-empty and NUL-terminated. The format files (image_exr.c, image_png.c) depend on
 * this file only, never on each other: they build and check images here, and only the dispatch
 * by extension (image_file.c, above them) names both formats.
 */
#include "image_int.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* ---- the container ---------------------------------------------------------------------- */

static st_status check_names(const char *const *names, uint32_t channels, st_error *err)
{
    for (uint32_t c = 0; c < channels; c++) {
        if (!names[c] || !names[c][0] || strlen(names[c]) >= ST_IMAGE_NAME_LEN)
            return st_fail(err, ST_ERR_USAGE, "image: channel %u name must have 1 to %d bytes", c,
                           ST_IMAGE_NAME_LEN - 1);
        for (uint32_t d = 0; d < c; d++)
            if (strcmp(names[c], names[d]) == 0)
                return st_fail(err, ST_ERR_USAGE, "image: channel name '%s' used twice", names[c]);
    }
    return ST_OK;
}

st_status st_image_create(st_image *img, uint32_t w, uint32_t h, uint32_t channels,
                          const char *const *names, st_error *err)
{
    static const char *const rgba[4] = {"R", "G", "B", "A"};
    char numbered_text[ST_IMAGE_MAX_CHANNELS][8];
    const char *numbered[ST_IMAGE_MAX_CHANNELS];
    for (int c = 0; c < ST_IMAGE_MAX_CHANNELS; c++) {
        snprintf(numbered_text[c], sizeof numbered_text[c], "C%d", c);
        numbered[c] = numbered_text[c];
    }
    memset(img, 0, sizeof *img);
    if (w == 0 || h == 0 || channels == 0 || channels > ST_IMAGE_MAX_CHANNELS)
        return st_fail(err, ST_ERR_USAGE, "image: invalid size %ux%u with %u channels (1 to %d)", w,
                       h, channels, ST_IMAGE_MAX_CHANNELS);
    if (!names)
        names = channels <= 4 ? rgba : numbered;
    if (check_names(names, channels, err) != ST_OK)
        return err ? err->status : ST_ERR_USAGE;
    size_t count = (size_t)w * h; /* no overflow: both < 2^32 and size_t is 64-bit here */
    if (count > SIZE_MAX / 4 / channels)
        return st_fail(err, ST_ERR_NOMEM, "image: %ux%u with %u channels is too large", w, h,
                       channels);
    void *buf = calloc(count * channels, 4);
    if (!buf)
        return st_fail(err, ST_ERR_NOMEM, "image: cannot allocate %ux%u with %u channels", w, h,
                       channels);
    img->width = w;
    img->height = h;
    img->channels = channels;
    for (uint32_t c = 0; c < channels; c++) {
        snprintf(img->channel_names[c], ST_IMAGE_NAME_LEN, "%s", names[c]);
        img->types[c] = ST_PIXEL_FLOAT;
    }
    img->data = buf;
    img->udata = buf;
    return ST_OK;
}

void st_image_free(st_image *img)
{
    if (!img)
        return;
    if ((void *)img->udata != (void *)img->data) /* a hand-built image with two arrays */
        free(img->udata);
    free(img->data);
    memset(img, 0, sizeof *img);
}

void st_image_place_like(st_image *dst, const st_image *src)
{
    dst->x0 = src->x0;
    dst->y0 = src->y0;
    dst->display_width = src->display_width;
    dst->display_height = src->display_height;
}

int st_image_find_channel(const st_image *img, const char *name)
{
    for (uint32_t c = 0; c < img->channels && c < ST_IMAGE_MAX_CHANNELS; c++)
        if (strcmp(img->channel_names[c], name) == 0)
            return (int)c;
    return -1;
}

st_status st_image_append(st_image *dst, const st_image *src, st_error *err)
{
    if (dst->channels == 0) { /* an empty image takes src's size (and is a copy) */
        dst->width = src->width;
        dst->height = src->height;
    }
    if (src->width != dst->width || src->height != dst->height ||
        dst->channels + src->channels > ST_IMAGE_MAX_CHANNELS)
        return st_fail(err, ST_ERR_USAGE, "image: cannot append %ux%u with %u channels to %ux%u "
                       "with %u (same size, at most %d channels)", src->width, src->height,
                       src->channels, dst->width, dst->height, dst->channels,
                       ST_IMAGE_MAX_CHANNELS);
    const char *names[ST_IMAGE_MAX_CHANNELS];
    uint32_t n = dst->channels + src->channels;
    for (uint32_t c = 0; c < n; c++)
        names[c] = c < dst->channels ? dst->channel_names[c]
                                     : src->channel_names[c - dst->channels];
    st_image out;
    if (st_image_create(&out, dst->width, dst->height, n, names, err) != ST_OK)
        return err ? err->status : ST_ERR_USAGE;
    size_t pixels = (size_t)dst->width * dst->height;
    for (size_t i = 0; i < pixels && dst->channels; i++) /* 4-byte samples: udata holds any type */
        memcpy(out.udata + n * i, dst->udata + dst->channels * i, 4u * dst->channels);
    for (size_t i = 0; i < pixels; i++)
        memcpy(out.udata + n * i + dst->channels, src->udata + src->channels * i,
               4u * src->channels);
    for (uint32_t c = 0; c < n; c++)
        out.types[c] = c < dst->channels ? dst->types[c] : src->types[c - dst->channels];
    st_image_place_like(&out, dst);
    st_image_free(dst);
    *dst = out;
    return ST_OK;
}

st_status st_image_check(const char *path, const st_image *img, st_error *err)
{
    if (!img || img->width == 0 || img->height == 0 || img->width > INT32_MAX ||
        img->height > INT32_MAX || img->channels == 0 || img->channels > ST_IMAGE_MAX_CHANNELS)
        return st_fail(err, ST_ERR_USAGE, "%s: not a valid image (size, channels or buffer)", path);
    const char *names[ST_IMAGE_MAX_CHANNELS];
    for (uint32_t c = 0; c < img->channels; c++) {
        if (memchr(img->channel_names[c], '\0', ST_IMAGE_NAME_LEN) == NULL)
            return st_fail(err, ST_ERR_USAGE, "%s: channel %u name is not terminated", path, c);
        if (img->types[c] != ST_PIXEL_FLOAT && img->types[c] != ST_PIXEL_UINT)
            return st_fail(err, ST_ERR_USAGE, "%s: channel %u has an unknown pixel type", path, c);
        if ((img->types[c] == ST_PIXEL_FLOAT && !img->data) ||
            (img->types[c] == ST_PIXEL_UINT && !img->udata))
            return st_fail(err, ST_ERR_USAGE, "%s: channel %u has no pixel buffer", path, c);
        names[c] = img->channel_names[c];
    }
    st_error local = {ST_OK, ""};
    if (check_names(names, img->channels, &local) != ST_OK)
        return st_fail(err, ST_ERR_USAGE, "%s: %s", path, local.msg + strlen("image: "));
    return ST_OK;
}
