/* st_film.h — the raw film of a render: per pixel the fixed-point sums
 * Σ f·L (R, G, B) and Σ f (fixed.h: value × 2^24 in a signed 64-bit integer),
 * the state from which split renders are added up exactly.
 *
 * In an EXR (a "part" of a split render) each 64-bit sum is two UINT
 * channels, its upper and lower 32 bits: sum.R.hi, sum.R.lo, sum.G.hi, ...,
 * sum.W.lo. Adding the integers of parts that cover disjoint sample ranges
 * gives exactly the sums of one render of all of them. */
#ifndef ST_FILM_H
#define ST_FILM_H

#include "st_error.h"
#include "st_image.h"
#include "st_shared.h"

#define ST_FILM_CHANNELS (2 * ST_FILM_SUMS) /* each sum as (hi, lo) */

/* The sums (4 per pixel) as an image of ST_FILM_CHANNELS UINT channels,
 * their names prefixed by layer ("" for the image's radiance; an AOV's
 * "Albedo." gives Albedo.sum.R.hi, ...: st_aov_layouts). */
st_status st_film_to_image(const st_i64 *sums, st_u32 width, st_u32 height, const char *layer,
                           st_image *out, st_error *err);
/* Reads the sums back from such an image (channels found by name); *sums is
 * malloc'ed (caller frees). ST_ERR_FORMAT naming `path` when a channel is
 * missing or not UINT. */
st_status st_film_from_image(const st_image *img, const char *path, const char *layer,
                             st_i64 **sums, st_error *err);
/* Whether img holds the raw sums of `layer` (its first channel, by name). */
int st_film_has_layer(const st_image *img, const char *layer);

#endif
