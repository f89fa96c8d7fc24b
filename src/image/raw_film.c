/* raw_film.c — raw film sums to and from images (see st_film.h). */
#include "st_film.h"

#include <stdio.h>
#include <stdlib.h>

static const char *const names[ST_FILM_CHANNELS] = {
    "sum.R.hi", "sum.R.lo", "sum.G.hi", "sum.G.lo", "sum.B.hi", "sum.B.lo", "sum.W.hi", "sum.W.lo"};

/* names with the layer's prefix, in text (ST_IMAGE_NAME_LEN each) */
static void layer_names(const char *layer, char text[][ST_IMAGE_NAME_LEN], const char **out)
{
    for (int c = 0; c < ST_FILM_CHANNELS; c++) {
        snprintf(text[c], ST_IMAGE_NAME_LEN, "%s%s", layer, names[c]);
        out[c] = text[c];
    }
}

int st_film_has_layer(const st_image *img, const char *layer)
{
    char text[ST_FILM_CHANNELS][ST_IMAGE_NAME_LEN];
    const char *named[ST_FILM_CHANNELS];
    layer_names(layer, text, named);
    return st_image_find_channel(img, named[0]) >= 0;
}

st_status st_film_to_image(const st_i64 *sums, st_u32 width, st_u32 height, const char *layer,
                           st_image *out, st_error *err)
{
    char text[ST_FILM_CHANNELS][ST_IMAGE_NAME_LEN];
    const char *named[ST_FILM_CHANNELS];
    layer_names(layer, text, named);
    if (st_image_create(out, width, height, ST_FILM_CHANNELS, named, err) != ST_OK)
        return err->status;
    for (int c = 0; c < ST_FILM_CHANNELS; c++)
        out->types[c] = ST_PIXEL_UINT;
    size_t n = (size_t)width * height;
    for (size_t i = 0; i < n; i++)
        for (int s = 0; s < ST_FILM_SUMS; s++) {
            st_u64 v = (st_u64)sums[ST_FILM_SUMS * i + s];
            out->udata[ST_FILM_CHANNELS * i + 2 * s] = (st_u32)(v >> 32);
            out->udata[ST_FILM_CHANNELS * i + 2 * s + 1] = (st_u32)v;
        }
    return ST_OK;
}

st_status st_film_from_image(const st_image *img, const char *path, const char *layer,
                             st_i64 **sums, st_error *err)
{
    char text[ST_FILM_CHANNELS][ST_IMAGE_NAME_LEN];
    const char *named[ST_FILM_CHANNELS];
    int at[ST_FILM_CHANNELS];
    layer_names(layer, text, named);
    *sums = NULL;
    for (int c = 0; c < ST_FILM_CHANNELS; c++) {
        at[c] = st_image_find_channel(img, named[c]);
        if (at[c] < 0 || img->types[at[c]] != ST_PIXEL_UINT)
            return st_fail(err, ST_ERR_FORMAT,
                           "%s: no UINT channel %s: not the raw film of a split render "
                           "(a render of a sample range)",
                           path, named[c]);
    }
    size_t n = (size_t)img->width * img->height;
    st_i64 *s = malloc(sizeof *s * ST_FILM_SUMS * (n ? n : 1));
    if (!s)
        return st_fail(err, ST_ERR_NOMEM, "%s: out of memory", path);
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < ST_FILM_SUMS; k++) {
            st_u64 hi = img->udata[img->channels * i + at[2 * k]];
            st_u64 lo = img->udata[img->channels * i + at[2 * k + 1]];
            s[ST_FILM_SUMS * i + k] = (st_i64)(hi << 32 | lo);
        }
    *sums = s;
    return ST_OK;
}
