/* st_image.h — images in memory and their files: OpenEXR (float/uint channels) and PNG (8-bit sRGB).
 *
 * An st_image is a rectangle of width x height pixels with 1..48 named channels, stored row-major and
 * channel-interleaved: sample (x, y, c) lives at index (y*width + x)*channels + c. Every sample takes
 * 4 bytes; FLOAT channels are read and written through `data`, UINT channels through `udata`. In an
 * image made by st_image_create or a load function the two pointers address the SAME buffer (one
 * allocation, 4 bytes per sample), so a sample must always be accessed through the pointer its
 * channel's type names. A hand-built image may instead point them at two arrays of
 * width*height*channels entries each; the save functions and st_image_free accept both.
 *
 * Files are written through st_outfile (st_outfile.h): a temporary in the destination folder,
 * renamed into place when complete, so a failed save leaves neither a partial file nor a temporary
 * behind (an existing file of the same name survives a failed save). The container and the choice
 * of format by extension are src/image/image.c; each format (image_exr.c, image_png.c) needs only them. Errors: every failing call returns a status and fills err with one
 * line that starts with the path: ST_ERR_IO when the file system refuses (cannot create, open,
 * write, rename), ST_ERR_FORMAT when a file or image content is invalid, ST_ERR_USAGE for a bad
 * argument (unknown extension, bad channel list), ST_ERR_NOMEM when memory runs out. Nothing here
 * prints: OpenEXR's messages are captured through its error_handler_fn, stb's through
 * stbi_failure_reason.
 */
#ifndef ST_IMAGE_H
#define ST_IMAGE_H

#include "st_error.h"

#include <stdint.h>

#define ST_IMAGE_MAX_CHANNELS 48
/* The most samples (pixels x channels, 4 GiB of floats) an EXR may declare to be read: a header
 * is only a claim, and found by fuzzing (tests/fuzz/fuzz_exr.c), a 100-byte file asked for 12 GB. */
#define ST_IMAGE_MAX_SAMPLES ((uint64_t)1 << 30)
#define ST_IMAGE_NAME_LEN 32 /* channel name bytes including the terminating NUL */

typedef enum { ST_PIXEL_FLOAT = 0, ST_PIXEL_UINT = 1 } st_pixel_type; /* host-only */

typedef struct st_image {
    uint32_t width, height, channels;
    char channel_names[ST_IMAGE_MAX_CHANNELS][ST_IMAGE_NAME_LEN]; /* "R", "G", "B", "sum.R.hi", ... */
    st_pixel_type types[ST_IMAGE_MAX_CHANNELS];                   /* per channel */
    float *data;     /* FLOAT samples: data[(y*width + x)*channels + c]                         */
    uint32_t *udata; /* UINT samples at the same index; the same buffer as data (see above)     */
    /* Where the pixels lie in a larger image (an EXR's data window in its display window, e.g. a
     * render's --crop): pixel (x, y) of data is (x0 + x, y0 + y) of a display_width x
     * display_height image. All 0 (as st_image_create leaves them): the image is all there is. */
    int32_t x0, y0;
    uint32_t display_width, display_height;
} st_image;

/* How an attribute is stored in an EXR header: its value is always kept as text here, and
 * written as the type says (ST_ATTR_INT: a decimal integer as "int"; ST_ATTR_FLOAT / _DOUBLE: a
 * number as "float" / "double"; ST_ATTR_STRING, the zero default: as "string"). */
typedef enum { ST_ATTR_STRING = 0, ST_ATTR_INT, ST_ATTR_FLOAT, ST_ATTR_DOUBLE } st_attr_type;

/* An attribute of an EXR header ("strata.sampler" = "halton", "strata.spp" = 64 as int). Longer
 * names or values read from a file are truncated to fit (63 and 511 bytes). Numbers read back are
 * printed as "%d", or the shortest "%g" text that reads back as the same float or double. */
typedef struct st_attr {
    char name[64];
    char value[512];
    st_attr_type type;
} st_attr;

/* The names of the film's counts of a render (clamped splats, non-finite samples and pixels,
 * pixels without weight), written as EXR ints (as doubles from 2^31 on). */
#define ST_EXR_INT_ATTRS "strata.clamped_splats", "strata.nonfinite", "strata.zero_weight_pixels"

/* Allocates a w x h image of `channels` (1..48) zeroed FLOAT channels. names: `channels` distinct,
 * non-empty names of at most 31 bytes, or NULL for "R","G","B","A" (channels <= 4) or "C0".."C47".
 * Set img->types[c] = ST_PIXEL_UINT afterwards for integer channels. On failure *img is zeroed.
 * Errors: ST_ERR_USAGE (bad size or names), ST_ERR_NOMEM. Free with st_image_free. */
st_status st_image_create(st_image *img, uint32_t w, uint32_t h, uint32_t channels,
                          const char *const *names, st_error *err);

/* Releases the pixels (data, and udata when it is a separate array) and zeroes *img. NULL or an
 * already freed image: does nothing. */
void st_image_free(st_image *img);

/* Gives dst src's place in a larger image (x0, y0, display_width, display_height). */
void st_image_place_like(st_image *dst, const st_image *src);

/* Index of the channel called `name`, or -1. */
int st_image_find_channel(const st_image *img, const char *name);
/* Appends src's channels (names and types) after dst's, src the same size;
 * dst's placement stays; a zeroed dst (no channels) becomes a copy of src's
 * pixels. ST_ERR_USAGE (sizes, too many channels, a name in
 * both), ST_ERR_NOMEM; on failure dst is unchanged. */
st_status st_image_append(st_image *dst, const st_image *src, st_error *err);

/* Writes a single-part scanline EXR, ZIP-compressed, every channel as stored (FLOAT as 32-bit
 * float, UINT as 32-bit uint, so values round-trip bit for bit), data window (0,0)-(w-1,h-1) (with a
 * display_width: (x0,y0)-(x0+w-1,y0+h-1) inside the display window (0,0)-(dw-1,dh-1)), and
 * the nattrs attributes, each as its type says (a value that does not parse as its type, or a name
 * that clashes with a required attribute such as "channels", is ST_ERR_FORMAT). Every file also
 * gets "chromaticities" (Rec. 709 primaries, D65 white: the linear sRGB strata renders in) and
 * "software" ("strata VERSION"). OpenEXR writes through a custom write_fn into the st_outfile. */
st_status st_image_save_exr(const char *path, const st_image *img, const st_attr *attrs, int nattrs,
                            st_error *err);

/* Reads the first part of a scanline or tiled EXR (level 0 of a mip/rip map) whose channels are
 * FLOAT, HALF or UINT (HALF widened to float, exactly) and not subsampled, at most 48 of them.
 * Channels come back in file order, which OpenEXR sorts by name (R,G,B is stored as B,G,R): use
 * st_image_find_channel. The data window becomes the image; x0, y0 keep its
 * origin relative to the display window's, display_width/height the display window's size. attrs/nattrs:
 * if attrs is not NULL, *attrs receives a malloc'ed array of the *nattrs string attributes in file
 * order (NULL when there are none), which the caller frees with free(): the string, int, float and
 * double attributes, typed as stored; the structural "type" and "name" attributes are left out. *img is zeroed on failure. */
st_status st_image_load_exr(const char *path, st_image *img, st_attr **attrs, int *nattrs,
                            st_error *err);

/* The data window's width and height of the first part of an OpenEXR file, from its header
 * alone (no pixel is decoded), so a caller can refuse a size before reading it. */
st_status st_image_exr_size(const char *path, uint64_t *width, uint64_t *height, st_error *err);

/* sRGB transfer functions (IEC 61966-2-1:1999, "Default RGB colour space - sRGB", section 5.2):
 *   encode (OETF): V = 12.92 L                  for L <= 0.0031308
 *                  V = 1.055 L^(1/2.4) - 0.055  otherwise
 *   decode (EOTF): L = V / 12.92                for V <= 0.04045
 *                  L = ((V + 0.055)/1.055)^2.4  otherwise
 * Both clamp their input to [0, 1] first; NaN maps to 0. Tests: test_image.c srgb_*. */
float st_image_srgb_encode(float linear);
float st_image_srgb_decode(float encoded);

/* 8-bit code of a linear value: round(255 * st_image_srgb_encode(linear)), halves rounded up. */
uint8_t st_image_srgb_quantize(float linear);
/* The linear value of an 8-bit sRGB code, as st_image_load_png reads it. */
float st_image_srgb8_decode(uint8_t code);

/* Writes an 8-bit RGB PNG: the FLOAT channels named R, G and B (any order), or else the first three
 * channels, each quantised with st_image_srgb_quantize, through an st_outfile (no file is left on
 * failure). Round trip
 * through st_image_load: |decode(code) - x| <= half a code step of the EOTF, i.e. at most
 * (2.4/1.055) * 0.5/255 < 0.00447 in linear units for x in [0, 1]. */
st_status st_image_save_png(const char *path, const st_image *img, st_error *err);

/* st_image_save_png, and the file carries an sRGB chunk (with its gAMA and cHRM fallbacks), a
 * "Software" text chunk ("strata VERSION") and the nattrs attributes as text chunks (tEXt for
 * ASCII values, iTXt for others; names must be 1..79 bytes, else ST_ERR_USAGE). libpng writes it.
 * st_image_save_png is this with no attributes. */
st_status st_image_save_png_text(const char *path, const st_image *img, const st_attr *attrs,
                                 int nattrs, st_error *err);

/* Reads a PNG (or anything stb_image decodes) as 8-bit RGB and decodes each value with
 * st_image_srgb_decode(code/255) into FLOAT channels "R","G","B" in that order (grey is
 * replicated, alpha dropped). Errors: ST_ERR_IO when it cannot be opened, ST_ERR_FORMAT when it
 * cannot be decoded. */
st_status st_image_load_png(const char *path, st_image *img, st_error *err);

/* Picks the format by extension (.exr or .png, case-insensitive); any other extension is
 * ST_ERR_USAGE naming it. "-" (standard output) gets a PNG: an EXR's chunk table is written
 * after its pixels, which a pipe cannot take. attrs go into the EXR header, or a PNG's text
 * chunks. */
st_status st_image_save(const char *path, const st_image *img, const st_attr *attrs, int nattrs,
                        st_error *err);

/* Loads .exr (as st_image_load_exr, attributes dropped) or .png (as st_image_load_png), by
 * extension, case-insensitive; other extensions are ST_ERR_USAGE. */
st_status st_image_load(const char *path, st_image *img, st_error *err);

#endif
