/* image_exr.c — st_image as an OpenEXR file (scanline, ZIP-compressed chunk by chunk here; any
 * scanline or tiled file on reading).
 *
 * Files are read and written with the OpenEXR 3.1 core C API (openexr.h; file layout: "OpenEXR
 * File Layout", openexr.com), whose messages are captured by an error_handler_fn so the library
 * never prints; the first message of an operation is kept because later ones are consequences of
 * it. Writing goes through a custom write_fn into an st_outfile (st_outfile.h), the temporary and
 * rename every strata output shares, rather than OpenEXR's own EXR_INTERMEDIATE_TEMP_FILE. The
 * container and the choice of format live in image.c.
 */
#include "image_int.h"
#include "st_outfile.h"
#include "st_version.h"

#include <openexr.h>
#include <zlib.h>

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* ---- capturing OpenEXR's messages --------------------------------------------------------- */

/* OpenEXR reports through a callback without a user pointer of ours (with the default file I/O
 * the context's user_data is its own file handle), so the message of the current operation is
 * kept per thread. errno is sampled inside the callback, where it still names the failed call. */
static _Thread_local struct {
    int set;
    int code;
    int err_no;
    char msg[256];
} exr_last;

static void exr_reset(void)
{
    exr_last.set = 0;
    exr_last.code = 0;
    exr_last.err_no = 0;
    exr_last.msg[0] = '\0';
}

static void exr_record(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)ctxt;
    int saved = errno;
    if (exr_last.set)
        return; /* first message wins */
    exr_last.set = 1;
    exr_last.code = code;
    exr_last.err_no =
        (code == EXR_ERR_FILE_ACCESS || code == EXR_ERR_READ_IO || code == EXR_ERR_WRITE_IO)
            ? saved
            : 0;
    snprintf(exr_last.msg, sizeof exr_last.msg, "%s", msg ? msg : "");
    for (char *p = exr_last.msg; *p; p++)
        if (*p == '\n' || *p == '\r')
            *p = ' '; /* one line */
}

/* The reason for a failed call rc: the captured message, else OpenEXR's text for the code. */
static const char *exr_reason(exr_result_t rc)
{
    if (exr_last.set && exr_last.msg[0])
        return exr_last.msg;
    return exr_get_default_error_message(rc);
}

static exr_context_initializer_t exr_init(void)
{
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_record;
    return init;
}

/* ---- writing ------------------------------------------------------------------------------- */

static st_status check_attrs(const char *path, const st_attr *attrs, int nattrs, int *longnames,
                             st_error *err)
{
    *longnames = 0;
    if (nattrs < 0 || (nattrs > 0 && !attrs))
        return st_fail(err, ST_ERR_USAGE, "%s: invalid attribute list", path);
    for (int i = 0; i < nattrs; i++) {
        size_t n = strnlen(attrs[i].name, sizeof attrs[i].name);
        if (n == 0 || n == sizeof attrs[i].name ||
            !memchr(attrs[i].value, '\0', sizeof attrs[i].value))
            return st_fail(err, ST_ERR_USAGE, "%s: attribute %d: empty or unterminated text", path,
                           i);
        if (n > 31) /* EXR names longer than 31 bytes need the long-names flag (version 2) */
            *longnames = 1;
    }
    return ST_OK;
}

/* One attribute as its type says; the text must be exactly a number of that type. */
static st_status exr_set_attr(exr_context_t ctx, int part, const char *path, const st_attr *a,
                              st_error *err)
{
    char *end = NULL;
    exr_result_t rc = EXR_ERR_SUCCESS;
    errno = 0;
    if (a->type == ST_ATTR_INT) {
        long v = strtol(a->value, &end, 10);
        if (v < INT_MIN || v > INT_MAX)
            errno = ERANGE;
        else
            rc = exr_attr_set_int(ctx, part, a->name, (int32_t)v);
    } else if (a->type == ST_ATTR_FLOAT || a->type == ST_ATTR_DOUBLE) {
        double v = strtod(a->value, &end);
        if (!isfinite(v) || (a->type == ST_ATTR_FLOAT && !isfinite((float)v)))
            errno = ERANGE;
        else if (a->type == ST_ATTR_FLOAT)
            rc = exr_attr_set_float(ctx, part, a->name, (float)v);
        else
            rc = exr_attr_set_double(ctx, part, a->name, v);
    } else {
        rc = exr_attr_set_string(ctx, part, a->name, a->value);
    }
    if (end && (end == a->value || *end != '\0' || errno))
        return st_fail(err, ST_ERR_FORMAT, "%s: attribute '%s': '%s' is not a%s", path, a->name,
                       a->value, a->type == ST_ATTR_INT ? "n int" : " finite number");
    if (rc != EXR_ERR_SUCCESS)
        return st_fail(err, ST_ERR_FORMAT, "%s: attribute '%s': %s", path, a->name,
                       exr_reason(rc));
    return ST_OK;
}

/* What every strata EXR says of itself: its colour space, linear Rec. 709 (the sRGB primaries,
 * ITU-R BT.709-6 table 1.3-1.4, D65 white), and the program that wrote it. */
static exr_result_t exr_set_standard_attrs(exr_context_t ctx, int part)
{
    const exr_attr_chromaticities_t rec709 = {0.64f, 0.33f, 0.30f, 0.60f,
                                              0.15f, 0.06f, 0.3127f, 0.3290f};
    char software[128];
    snprintf(software, sizeof software, "strata %s", st_version);
    exr_result_t rc = exr_attr_set_chromaticities(ctx, part, "chromaticities", &rec709);
    return rc == EXR_ERR_SUCCESS ? exr_attr_set_string(ctx, part, "software", software) : rc;
}

/* A window of a larger image: the data window at (x0, y0) of the display window (0, 0) -
 * (display_width - 1, display_height - 1). */
static exr_result_t exr_set_windows(exr_context_t ctx, int part, const st_image *img)
{
    exr_attr_box2i_t dw, disp;
    dw.min.x = img->x0;
    dw.min.y = img->y0;
    dw.max.x = (int32_t)(img->x0 + (int64_t)img->width - 1);
    dw.max.y = (int32_t)(img->y0 + (int64_t)img->height - 1);
    disp.min.x = disp.min.y = 0;
    disp.max.x = (int32_t)img->display_width - 1;
    disp.max.y = (int32_t)img->display_height - 1;
    exr_result_t rc = exr_set_display_window(ctx, part, &disp);
    return rc == EXR_ERR_SUCCESS ? exr_set_data_window(ctx, part, &dw) : rc;
}

/* Declares the part: size, ZIP compression (chunks compressed by exr_write_pixels),
 * channels (sorted by OpenEXR), attributes. */
static st_status exr_define(exr_context_t ctx, const char *path, const st_image *img,
                            const st_attr *attrs, int nattrs, int longnames, st_error *err)
{
    int part = 0;
    exr_result_t rc = exr_add_part(ctx, NULL, EXR_STORAGE_SCANLINE, &part);
    if (rc == EXR_ERR_SUCCESS)
        rc = exr_initialize_required_attr_simple(ctx, part, (int32_t)img->width,
                                                 (int32_t)img->height, EXR_COMPRESSION_ZIP);
    if (rc == EXR_ERR_SUCCESS && img->display_width)
        rc = exr_set_windows(ctx, part, img);
    if (rc == EXR_ERR_SUCCESS && longnames)
        rc = exr_set_longname_support(ctx, 1);
    if (rc != EXR_ERR_SUCCESS)
        return st_fail(err, ST_ERR_FORMAT, "%s: cannot set up the header (%s)", path,
                       exr_reason(rc));
    for (uint32_t c = 0; c < img->channels; c++) {
        exr_pixel_type_t t = img->types[c] == ST_PIXEL_UINT ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT;
        rc = exr_add_channel(ctx, part, img->channel_names[c], t, EXR_PERCEPTUALLY_LOGARITHMIC, 1,
                             1);
        if (rc != EXR_ERR_SUCCESS)
            return st_fail(err, ST_ERR_FORMAT, "%s: channel '%s': %s", path, img->channel_names[c],
                           exr_reason(rc));
    }
    for (int i = 0; i < nattrs; i++)
        if (exr_set_attr(ctx, part, path, &attrs[i], err) != ST_OK)
            return err->status;
    rc = exr_set_standard_attrs(ctx, part);
    if (rc != EXR_ERR_SUCCESS)
        return st_fail(err, ST_ERR_FORMAT, "%s: chromaticities or software: %s", path,
                       exr_reason(rc));
    rc = exr_write_header(ctx);
    if (rc != EXR_ERR_SUCCESS)
        return st_fail(err, ST_ERR_IO, "%s: cannot write the header (%s)", path, exr_reason(rc));
    return ST_OK;
}

/* ---- ZIP chunks, compressed here ------------------------------------------------------------
 *
 * OpenEXR 3.1.5's own encoder stores a ZIP chunk whose zlib data is exactly as large as the raw
 * chunk with packed size == raw size, and every reader (OpenEXR's C, C++ and Python libraries
 * alike) then takes the zlib bytes for raw pixels: the image comes back as garbage
 * (test_image.c exr_roundtrip_render_three_channels holds the render that showed it). So strata
 * compresses each chunk itself, as the OpenEXR file layout defines ZIP_COMPRESSION ("OpenEXR
 * File Layout", openexr.com; OpenEXR's ImfZip.cpp), and keeps the zlib data only when it is
 * strictly smaller; otherwise the chunk is stored raw, which every reader recognises by its
 * packed size equal to the raw size. Chunks are written with exr_write_scanline_chunk. */

/* The raw chunk of lines y .. y+n-1: per line, per channel in the file's (sorted) order, the
 * width samples as 4-byte little-endian words. */
static void pack_lines(const st_image *img, const exr_attr_chlist_t *chl, int64_t y, int32_t n,
                       uint8_t *raw)
{
    for (int32_t l = 0; l < n; l++)
        for (int k = 0; k < chl->num_channels; k++) {
            int c = st_image_find_channel(img, chl->entries[k].name.str); /* declared by us */
            for (uint32_t x = 0; x < img->width; x++) {
                size_t at = ((size_t)(y + l) * img->width + x) * img->channels + (size_t)c;
                uint32_t v;
                if (img->types[c] == ST_PIXEL_UINT)
                    v = img->udata[at];
                else
                    memcpy(&v, &img->data[at], 4);
                *raw++ = (uint8_t)v;
                *raw++ = (uint8_t)(v >> 8);
                *raw++ = (uint8_t)(v >> 16);
                *raw++ = (uint8_t)(v >> 24);
            }
        }
}

/* ZIP_COMPRESSION of n raw bytes: even-indexed bytes, then odd-indexed ones; each byte replaced
 * by its difference to the previous one plus 128 (mod 256); zlib (RFC 1950). Returns the zlib
 * size in *out, or 0 when it is not strictly smaller than n (store raw). tmp holds n bytes. */
static size_t zip_chunk(const uint8_t *raw, size_t n, uint8_t *tmp, uint8_t *out, size_t out_cap)
{
    size_t half = (n + 1) / 2;
    for (size_t i = 0; i < n; i++)
        tmp[(i & 1) ? half + i / 2 : i / 2] = raw[i];
    for (size_t i = n - 1; i > 0; i--) /* backwards: tmp[i - 1] is still the original */
        tmp[i] = (uint8_t)(tmp[i] - tmp[i - 1] + 128);
    uLongf size = (uLongf)out_cap;
    if (compress2(out, &size, tmp, (uLong)n, Z_DEFAULT_COMPRESSION) != Z_OK || size >= n)
        return 0;
    return (size_t)size;
}

static st_status exr_write_pixels(exr_context_t ctx, const char *path, const st_image *img,
                                  st_error *err)
{
    int32_t lines = 0;
    const exr_attr_chlist_t *chl = NULL;
    exr_result_t rc = exr_get_scanlines_per_chunk(ctx, 0, &lines);
    if (rc == EXR_ERR_SUCCESS)
        rc = exr_get_channels(ctx, 0, &chl);
    if (rc != EXR_ERR_SUCCESS || lines <= 0 || !chl)
        return st_fail(err, ST_ERR_FORMAT, "%s: cannot size chunks (%s)", path, exr_reason(rc));
    size_t cap = (size_t)img->width * 4 * img->channels * (size_t)lines;
    size_t zcap = compressBound((uLong)cap);
    uint8_t *raw = malloc(cap), *tmp = malloc(cap), *zip = malloc(zcap);
    if (!raw || !tmp || !zip)
        rc = EXR_ERR_OUT_OF_MEMORY;
    for (int64_t y = 0; y < (int64_t)img->height && rc == EXR_ERR_SUCCESS; y += lines) {
        int32_t n = (int32_t)((int64_t)img->height - y < lines ? (int64_t)img->height - y : lines);
        size_t size = (size_t)img->width * 4 * img->channels * (size_t)n;
        pack_lines(img, chl, y, n, raw);
        size_t zsize = zip_chunk(raw, size, tmp, zip, zcap);
        rc = exr_write_scanline_chunk(ctx, 0, (int)(img->y0 + y), zsize ? zip : raw,
                                      zsize ? zsize : size);
    }
    free(raw);
    free(tmp);
    free(zip);
    if (rc != EXR_ERR_SUCCESS)
        return st_fail(err, ST_ERR_IO, "%s: cannot write pixels (%s)", path, exr_reason(rc));
    return ST_OK;
}

/* OpenEXR's write_fn: positioned writes into the temporary (the chunk table is written last, at
 * its reserved offset). Returns the bytes written or -1 after reporting through error_cb, which
 * reaches exr_record with errno still naming the failed call. */
static int64_t exr_write_outfile(exr_const_context_t ctxt, void *userdata, const void *buffer,
                                 uint64_t sz, uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    if (sz > (uint64_t)INT64_MAX ||
        st_outfile_write_at(userdata, buffer, (size_t)sz, offset) != 0) {
        int e = errno;
        error_cb(ctxt, EXR_ERR_WRITE_IO, "cannot write %llu bytes at offset %llu: %s",
                 (unsigned long long)sz, (unsigned long long)offset, strerror(e));
        errno = e;
        return -1;
    }
    return (int64_t)sz;
}

/* Header, pixels and chunk table into the open outfile; the caller commits or aborts it. */
static st_status exr_write_to(st_outfile *out, const char *path, const st_image *img,
                              const st_attr *attrs, int nattrs, int longnames, st_error *err)
{
    exr_reset();
    exr_context_initializer_t init = exr_init();
    init.user_data = out;
    init.write_fn = exr_write_outfile;
    exr_context_t ctx = NULL;
    exr_result_t rc = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rc != EXR_ERR_SUCCESS)
        return st_fail(err, ST_ERR_IO, "%s: cannot start writing (%s)", path, exr_reason(rc));
    st_error local = {ST_OK, ""};
    if (exr_define(ctx, path, img, attrs, nattrs, longnames, &local) == ST_OK)
        exr_write_pixels(ctx, path, img, &local);
    rc = exr_finish(&ctx); /* writes the chunk table through exr_write_outfile */
    if (local.status != ST_OK)
        return st_fail(err, local.status, "%s", local.msg);
    if (rc != EXR_ERR_SUCCESS)
        return st_fail(err, ST_ERR_IO, "%s: cannot finish (%s)", path, exr_reason(rc));
    return ST_OK;
}

st_status st_image_save_exr(const char *path, const st_image *img, const st_attr *attrs, int nattrs,
                            st_error *err)
{
    int longnames = 0;
    if (st_image_check(path, img, err) != ST_OK ||
        check_attrs(path, attrs, nattrs, &longnames, err) != ST_OK)
        return err ? err->status : ST_ERR_USAGE;
    st_outfile *out = NULL;
    if (st_outfile_open(path, &out, err) != ST_OK)
        return err ? err->status : ST_ERR_IO;
    st_error local = {ST_OK, ""};
    if (exr_write_to(out, path, img, attrs, nattrs, longnames, &local) != ST_OK) {
        st_outfile_abort(out);
        return st_fail(err, local.status, "%s", local.msg);
    }
    return st_outfile_commit(out, err);
}

/* ---- reading ------------------------------------------------------------------------------- */

/* The attributes that describe the file's structure rather than the image: OpenEXR 3.1 writes
 * "type" even for single-part files, multi-part files carry "name", and the required float
 * attributes (the others are of types not read here). */
static int is_structural(const char *name)
{
    return strcmp(name, "type") == 0 || strcmp(name, "name") == 0 ||
           strcmp(name, "pixelAspectRatio") == 0 || strcmp(name, "screenWindowWidth") == 0;
}

/* The shortest "%.Ng" text that reads back as exactly v (as a float when is_float). */
static void print_shortest(char *out, size_t cap, double v, int is_float)
{
    for (int digits = is_float ? 6 : 15; digits <= 17; digits++) {
        snprintf(out, cap, "%.*g", digits, v);
        double back = strtod(out, NULL);
        if (is_float ? (float)back == (float)v : back == v)
            return;
    }
}

/* The attribute as st_attr text when it is a string, int, float or double; returns whether. */
static int attr_of_exr(const exr_attribute_t *a, st_attr *out)
{
    char *v = out->value;
    size_t cap = sizeof out->value;
    if (a->type == EXR_ATTR_STRING && a->string) {
        int len = a->string->length > 0 ? a->string->length : 0;
        if ((size_t)len >= cap)
            len = (int)cap - 1;
        if (len > 0 && a->string->str)
            memcpy(v, a->string->str, (size_t)len);
        v[len] = '\0';
        out->type = ST_ATTR_STRING;
    } else if (a->type == EXR_ATTR_INT) {
        snprintf(v, cap, "%d", (int)a->i);
        out->type = ST_ATTR_INT;
    } else if (a->type == EXR_ATTR_FLOAT) {
        print_shortest(v, cap, (double)a->f, 1);
        out->type = ST_ATTR_FLOAT;
    } else if (a->type == EXR_ATTR_DOUBLE) {
        print_shortest(v, cap, a->d, 0);
        out->type = ST_ATTR_DOUBLE;
    } else {
        return 0;
    }
    snprintf(out->name, sizeof out->name, "%s", a->name);
    return 1;
}

/* Copies the string and number attributes of part 0 (structural ones left out), in file order, into a
 * malloc'ed array. */
static st_status exr_read_attrs(exr_context_t ctx, const char *path, st_attr **out, int *count,
                                st_error *err)
{
    *out = NULL;
    *count = 0;
    int32_t n = 0;
    exr_result_t rc = exr_get_attribute_count(ctx, 0, &n);
    if (rc != EXR_ERR_SUCCESS)
        return st_fail(err, ST_ERR_FORMAT, "%s: cannot list attributes (%s)", path,
                       exr_reason(rc));
    st_attr *list = n > 0 ? calloc((size_t)n, sizeof *list) : NULL;
    if (n > 0 && !list)
        return st_fail(err, ST_ERR_NOMEM, "%s: cannot allocate %d attributes", path, (int)n);
    int used = 0;
    for (int32_t i = 0; i < n; i++) {
        const exr_attribute_t *a = NULL;
        if (exr_get_attribute_by_index(ctx, 0, EXR_ATTR_LIST_FILE_ORDER, i, &a) == EXR_ERR_SUCCESS &&
            a && !is_structural(a->name) && attr_of_exr(a, &list[used]))
            used++;
    }
    if (used == 0) {
        free(list);
        list = NULL;
    }
    *out = list;
    *count = used;
    return ST_OK;
}

/* The data window's origin relative to the display window's, and the display window's size. */
static st_status exr_keep_windows(const char *path, st_image *img, const exr_attr_box2i_t *dw,
                                  const exr_attr_box2i_t *disp, st_error *err)
{
    int64_t x0 = (int64_t)dw->min.x - disp->min.x, y0 = (int64_t)dw->min.y - disp->min.y;
    int64_t w = (int64_t)disp->max.x - disp->min.x + 1, h = (int64_t)disp->max.y - disp->min.y + 1;
    if (x0 < INT32_MIN || x0 > INT32_MAX || y0 < INT32_MIN || y0 > INT32_MAX || w <= 0 ||
        h <= 0 || w > UINT32_MAX || h > UINT32_MAX) {
        st_image_free(img);
        return st_fail(err, ST_ERR_FORMAT, "%s: invalid display window", path);
    }
    img->x0 = (int32_t)x0;
    img->y0 = (int32_t)y0;
    img->display_width = (uint32_t)w;
    img->display_height = (uint32_t)h;
    return ST_OK;
}

/* Checks the part's layout and creates the matching image (channels in file order). */
static st_status exr_prepare(exr_context_t ctx, const char *path, st_image *img,
                             exr_attr_box2i_t *dw, st_error *err)
{
    exr_storage_t storage;
    const exr_attr_chlist_t *chl = NULL;
    exr_result_t rc = exr_get_storage(ctx, 0, &storage);
    exr_attr_box2i_t disp;
    if (rc == EXR_ERR_SUCCESS)
        rc = exr_get_data_window(ctx, 0, dw);
    if (rc == EXR_ERR_SUCCESS)
        rc = exr_get_display_window(ctx, 0, &disp);
    if (rc == EXR_ERR_SUCCESS)
        rc = exr_get_channels(ctx, 0, &chl);
    if (rc != EXR_ERR_SUCCESS || !chl)
        return st_fail(err, ST_ERR_FORMAT, "%s: incomplete header (%s)", path, exr_reason(rc));
    if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED)
        return st_fail(err, ST_ERR_FORMAT, "%s: deep images are not supported", path);
    int64_t w = (int64_t)dw->max.x - dw->min.x + 1, h = (int64_t)dw->max.y - dw->min.y + 1;
    if (w <= 0 || h <= 0 || w > INT32_MAX || h > INT32_MAX)
        return st_fail(err, ST_ERR_FORMAT, "%s: empty or invalid data window", path);
    int n = chl->num_channels;
    if (n < 1 || n > ST_IMAGE_MAX_CHANNELS)
        return st_fail(err, ST_ERR_FORMAT, "%s: %d channels (1 to %d supported)", path, n,
                       ST_IMAGE_MAX_CHANNELS);
    if ((uint64_t)w * (uint64_t)h * (uint64_t)n > ST_IMAGE_MAX_SAMPLES) /* a header's claim */
        return st_fail(err, ST_ERR_FORMAT, "%s: %lld x %lld pixels x %d channels: more than 2^30 "
                       "samples, the limit", path, (long long)w, (long long)h, n);
    if ((uint64_t)w * (uint64_t)n * 4u > INT32_MAX) /* the decoder's line stride is an int32 */
        return st_fail(err, ST_ERR_FORMAT, "%s: rows of %lld pixels x %d channels: more than "
                       "2^31 bytes, the limit", path, (long long)w, n);
    const char *names[ST_IMAGE_MAX_CHANNELS];
    for (int c = 0; c < n; c++) {
        const exr_attr_chlist_entry_t *e = &chl->entries[c];
        if (e->x_sampling != 1 || e->y_sampling != 1)
            return st_fail(err, ST_ERR_FORMAT, "%s: channel '%s' is subsampled (not supported)",
                           path, e->name.str);
        if (e->pixel_type != EXR_PIXEL_UINT && e->pixel_type != EXR_PIXEL_HALF &&
            e->pixel_type != EXR_PIXEL_FLOAT)
            return st_fail(err, ST_ERR_FORMAT, "%s: channel '%s' has an unknown pixel type", path,
                           e->name.str);
        names[c] = e->name.str;
    }
    st_error local = {ST_OK, ""};
    if (st_image_create(img, (uint32_t)w, (uint32_t)h, (uint32_t)n, names, &local) != ST_OK)
        return st_fail(err, local.status == ST_ERR_NOMEM ? ST_ERR_NOMEM : ST_ERR_FORMAT, "%s: %s",
                       path, local.msg + strlen("image: "));
    for (int c = 0; c < n; c++)
        img->types[c] = chl->entries[c].pixel_type == EXR_PIXEL_UINT ? ST_PIXEL_UINT
                                                                     : ST_PIXEL_FLOAT;
    return exr_keep_windows(path, img, dw, &disp, err);
}

/* Points the decoder's channels (file order = image order) at pixel (x0, y0) of img; HALF is
 * widened to FLOAT by OpenEXR's unpacker. */
static void exr_bind_decode(exr_decode_pipeline_t *dec, st_image *img, int64_t x0, int64_t y0)
{
    int32_t stride = (int32_t)(img->channels * 4);
    for (int16_t c = 0; c < dec->channel_count; c++) {
        exr_coding_channel_info_t *ch = &dec->channels[c];
        size_t at = ((size_t)y0 * img->width + (size_t)x0) * img->channels + (size_t)c;
        ch->decode_to_ptr = (uint8_t *)(img->data + at);
        ch->user_pixel_stride = stride;
        ch->user_line_stride = stride * (int32_t)img->width;
        ch->user_bytes_per_element = 4;
        ch->user_data_type = img->types[c] == ST_PIXEL_UINT ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT;
    }
}

/* Decodes one chunk whose pixels start at (x0, y0) of img (relative to the data window). */
static exr_result_t exr_decode_chunk(exr_context_t ctx, exr_decode_pipeline_t *dec, int *started,
                                     const exr_chunk_info_t *cinfo, st_image *img, int64_t x0,
                                     int64_t y0)
{
    if (x0 < 0 || y0 < 0 || cinfo->width <= 0 || cinfo->height <= 0 ||
        x0 + cinfo->width > (int64_t)img->width || y0 + cinfo->height > (int64_t)img->height)
        return EXR_ERR_CORRUPT_CHUNK;
    exr_result_t rc = *started ? exr_decoding_update(ctx, 0, cinfo, dec)
                               : exr_decoding_initialize(ctx, 0, cinfo, dec);
    if (rc != EXR_ERR_SUCCESS)
        return rc;
    *started = 1;
    if (dec->channel_count != (int16_t)img->channels)
        return EXR_ERR_CORRUPT_CHUNK;
    exr_bind_decode(dec, img, x0, y0);
    rc = exr_decoding_choose_default_routines(ctx, 0, dec);
    if (rc == EXR_ERR_SUCCESS)
        rc = exr_decoding_run(ctx, 0, dec);
    return rc;
}

static exr_result_t exr_read_scanlines(exr_context_t ctx, st_image *img,
                                       const exr_attr_box2i_t *dw)
{
    int32_t lines = 0;
    exr_result_t rc = exr_get_scanlines_per_chunk(ctx, 0, &lines);
    if (rc == EXR_ERR_SUCCESS && lines <= 0)
        rc = EXR_ERR_INVALID_ATTR;
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    int started = 0;
    for (int64_t y = dw->min.y; y <= dw->max.y && rc == EXR_ERR_SUCCESS; y += lines) {
        exr_chunk_info_t cinfo;
        rc = exr_read_scanline_chunk_info(ctx, 0, (int)y, &cinfo);
        if (rc == EXR_ERR_SUCCESS)
            rc = exr_decode_chunk(ctx, &dec, &started, &cinfo, img, 0,
                                  (int64_t)cinfo.start_y - dw->min.y);
    }
    if (started)
        exr_decoding_destroy(ctx, &dec);
    return rc;
}

static exr_result_t exr_read_tiles(exr_context_t ctx, st_image *img)
{
    int32_t tw = 0, th = 0;
    exr_result_t rc = exr_get_tile_sizes(ctx, 0, 0, 0, &tw, &th);
    if (rc == EXR_ERR_SUCCESS && (tw <= 0 || th <= 0))
        rc = EXR_ERR_INVALID_ATTR;
    if (rc != EXR_ERR_SUCCESS)
        return rc;
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    int started = 0;
    int64_t nx = ((int64_t)img->width + tw - 1) / tw, ny = ((int64_t)img->height + th - 1) / th;
    for (int64_t ty = 0; ty < ny && rc == EXR_ERR_SUCCESS; ty++)
        for (int64_t tx = 0; tx < nx && rc == EXR_ERR_SUCCESS; tx++) {
            exr_chunk_info_t cinfo;
            rc = exr_read_tile_chunk_info(ctx, 0, (int)tx, (int)ty, 0, 0, &cinfo);
            if (rc == EXR_ERR_SUCCESS)
                rc = exr_decode_chunk(ctx, &dec, &started, &cinfo, img, tx * tw, ty * th);
        }
    if (started)
        exr_decoding_destroy(ctx, &dec);
    return rc;
}

/* Opens path for reading (its header parsed), or fails naming it. */
static st_status exr_open(const char *path, exr_context_t *ctx, st_error *err)
{
    exr_reset();
    exr_context_initializer_t init = exr_init();
    exr_result_t rc = exr_start_read(ctx, path, &init);
    if (rc == EXR_ERR_SUCCESS)
        return ST_OK;
    exr_finish(ctx);
    if (rc == EXR_ERR_FILE_ACCESS)
        return st_fail(err, ST_ERR_IO, "%s: cannot open (%s)", path,
                       exr_last.err_no ? strerror(exr_last.err_no) : exr_reason(rc));
    return st_fail(err, ST_ERR_FORMAT, "%s: not a readable OpenEXR file (%s)", path,
                   exr_reason(rc));
}

st_status st_image_exr_size(const char *path, uint64_t *width, uint64_t *height, st_error *err)
{
    exr_context_t ctx = NULL;
    if (exr_open(path, &ctx, err) != ST_OK)
        return err->status;
    exr_attr_box2i_t dw;
    exr_result_t rc = exr_get_data_window(ctx, 0, &dw);
    exr_finish(&ctx);
    if (rc != EXR_ERR_SUCCESS)
        return st_fail(err, ST_ERR_FORMAT, "%s: incomplete header (%s)", path, exr_reason(rc));
    int64_t w = (int64_t)dw.max.x - dw.min.x + 1, h = (int64_t)dw.max.y - dw.min.y + 1;
    if (w <= 0 || h <= 0)
        return st_fail(err, ST_ERR_FORMAT, "%s: empty or invalid data window", path);
    *width = (uint64_t)w;
    *height = (uint64_t)h;
    return ST_OK;
}

st_status st_image_load_exr(const char *path, st_image *img, st_attr **attrs, int *nattrs,
                            st_error *err)
{
    memset(img, 0, sizeof *img);
    if (attrs)
        *attrs = NULL;
    if (nattrs)
        *nattrs = 0;
    exr_context_t ctx = NULL;
    if (exr_open(path, &ctx, err) != ST_OK)
        return err->status;
    exr_result_t rc;
    st_error local = {ST_OK, ""};
    exr_attr_box2i_t dw;
    exr_storage_t storage = EXR_STORAGE_SCANLINE;
    if (exr_prepare(ctx, path, img, &dw, &local) == ST_OK) {
        exr_get_storage(ctx, 0, &storage);
        rc = storage == EXR_STORAGE_TILED ? exr_read_tiles(ctx, img)
                                          : exr_read_scanlines(ctx, img, &dw);
        if (rc != EXR_ERR_SUCCESS)
            st_fail(&local, ST_ERR_FORMAT, "%s: cannot read pixels (%s)", path, exr_reason(rc));
    }
    if (local.status == ST_OK && attrs) {
        int n = 0;
        if (exr_read_attrs(ctx, path, attrs, &n, &local) == ST_OK && nattrs)
            *nattrs = n;
    }
    exr_finish(&ctx);
    if (local.status != ST_OK) {
        st_image_free(img);
        if (attrs) {
            free(*attrs);
            *attrs = NULL;
        }
        if (nattrs)
            *nattrs = 0;
        return st_fail(err, local.status, "%s", local.msg);
    }
    return ST_OK;
}
