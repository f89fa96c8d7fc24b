/* envmap.c — environment maps: reading, the sampling tables, the power (see
 * st_envmap.h; the convention and sampling: kernels/integrator/envmap.h). */
#include "st_envmap.h"
#include "st_mem_plan.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <stb/stb_image.h> /* Debian: implementations live in libstb (-lstb) */

#include "envmap.h"
#include "st_image.h"

#define PI 3.14159265358979323846

/* Luminance of linear Rec. 709 RGB (ITU-R BT.709 weights). */
static double luminance(const float *c)
{
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

/* The marginal and conditional CDFs of f_ij = luminance x sin θ_j (the
 * layout of kernels/integrator/envmap.h); a row that is black everywhere (probability
 * 0, never chosen) gets a uniform CDF. Returns Σ f, 0 when all are black. */
static double build_cdf(const float *texels, st_u32 w, st_u32 h, float *cdf)
{
    double total = 0.0;
    float *marg = cdf;
    double *rows = malloc(sizeof *rows * h);
    if (!rows)
        return -1.0;
    for (st_u32 j = 0; j < h; j++) {
        double s = sin(PI * (j + 0.5) / h), acc = 0.0;
        float *cond = cdf + h + (size_t)j * w;
        for (st_u32 i = 0; i < w; i++) {
            acc += luminance(&texels[4 * ((size_t)j * w + i)]) * s;
            cond[i] = (float)acc; /* normalised below */
        }
        for (st_u32 i = 0; i < w; i++)
            cond[i] = acc > 0.0 ? (i + 1 == w ? 1.0f : (float)(cond[i] / acc))
                                : (float)(i + 1) / (float)w;
        if (acc > 0.0)
            cond[w - 1] = 1.0f;
        rows[j] = acc;
        total += acc;
    }
    double acc = 0.0;
    for (st_u32 j = 0; j < h; j++) {
        acc += rows[j];
        marg[j] = total > 0.0 ? (j + 1 == h ? 1.0f : (float)(acc / total)) : 0.0f;
    }
    free(rows);
    return total;
}

st_status st_envmap_make(const float *rgb, st_u32 w, st_u32 h, const char *name,
                         st_envmap **out, st_error *err)
{
    *out = NULL;
    if (w == 0 || h == 0 || (st_u64)w * h > ST_ENV_MAX_TEXELS)
        return st_fail(err, ST_ERR_FORMAT, "%s: %u x %u texels: an environment map has 1 to 2^26",
                       name, w, h);
    size_t n = (size_t)w * h;
    for (size_t k = 0; k < 3 * n; k++)
        if (!isfinite(rgb[k]))
            return st_fail(err, ST_ERR_FORMAT, "%s: texel (%zu, %zu) is not finite", name,
                           k / 3 % w, k / 3 / w);
    st_envmap *m = calloc(1, sizeof *m);
    if (m) {
        m->texels = malloc(sizeof(float) * 4 * n);
        m->cdf = malloc(sizeof(float) * (h + n));
    }
    if (!m || !m->texels || !m->cdf) {
        st_envmap_free(m);
        return st_fail(err, ST_ERR_NOMEM, "%s: out of memory for the environment map", name);
    }
    m->width = w;
    m->height = h;
    double integral = 0.0;
    for (size_t k = 0; k < n; k++) {
        st_u32 j = (st_u32)(k / w);
        /* the cell's solid angle: 2π / w (cos θ0 - cos θ1) */
        double omega = 2.0 * PI / w * (cos(PI * j / h) - cos(PI * (j + 1) / h));
        for (int c = 0; c < 3; c++)
            m->texels[4 * k + c] = fmaxf(rgb[3 * k + c], 0.0f);
        m->texels[4 * k + 3] = 0.0f;
        integral += omega * (m->texels[4 * k] + m->texels[4 * k + 1] + m->texels[4 * k + 2]) / 3.0;
    }
    m->integral = integral;
    double total = build_cdf(m->texels, w, h, m->cdf);
    if (total < 0.0) {
        st_envmap_free(m);
        return st_fail(err, ST_ERR_NOMEM, "%s: out of memory for the environment map", name);
    }
    if (!(total > 0.0) || !(integral > 0.0)) {
        st_envmap_free(m);
        return st_fail(err, ST_ERR_FORMAT, "%s: the environment map is black (no light)", name);
    }
    *out = m;
    return ST_OK;
}

/* Bytes a map takes per texel while it loads and renders: the decoded RGB (and the EXR's own
 * copy), the RGBA texels and their sampling CDF, and the device's copy of both. */
#define ENV_BYTES_PER_TEXEL 64u

/* Refuses, before decoding, a map whose texels would not fit in the address space the
 * process may still take (ulimit -v): an 800 kB file can claim 2^26 texels, about 4 GB. */
static st_status check_env_memory(const char *path, st_u64 texels, st_error *err)
{
    unsigned long long need = texels * ENV_BYTES_PER_TEXEL, left = st_mem_plan_host_left();
    if (need > left)
        return st_fail(err, ST_ERR_NOMEM, "%s: %llu texels need about %llu MiB, more than the "
                       "%llu MiB the process may still take (ulimit -v); use a smaller map", path,
                       (unsigned long long)texels, need >> 20, left >> 20);
    return ST_OK;
}

/* R, G, B of an EXR's channels, 3 floats a texel (malloc'ed). */
static st_status exr_rgb(const char *path, float **rgb, st_u32 *w, st_u32 *h, st_error *err)
{
    st_image img;
    uint64_t hw, hh; /* the size from the header first: the cap holds before any decoding */
    if (st_image_exr_size(path, &hw, &hh, err) != ST_OK)
        return err->status;
    if (hw * hh > ST_ENV_MAX_TEXELS)
        return st_fail(err, ST_ERR_FORMAT, "%s: %llu x %llu texels: an environment map has 1 to 2^26",
                       path, (unsigned long long)hw, (unsigned long long)hh);
    if (check_env_memory(path, hw * hh, err) != ST_OK ||
        st_image_load_exr(path, &img, NULL, NULL, err) != ST_OK)
        return err->status;
    int ch[3] = {st_image_find_channel(&img, "R"), st_image_find_channel(&img, "G"),
                 st_image_find_channel(&img, "B")};
    st_status rc = ST_OK;
    for (int c = 0; c < 3 && rc == ST_OK; c++) {
        if (ch[c] < 0)
            rc = st_fail(err, ST_ERR_FORMAT, "%s: no %c channel (an environment map needs R, G, B)",
                         path, "RGB"[c]);
        else if (img.types[ch[c]] != ST_PIXEL_FLOAT)
            rc = st_fail(err, ST_ERR_FORMAT, "%s: channel %c is not float or half", path, "RGB"[c]);
    }
    size_t n = (size_t)img.width * img.height;
    *rgb = rc == ST_OK ? malloc(sizeof(float) * 3 * n) : NULL;
    if (rc == ST_OK && !*rgb)
        rc = st_fail(err, ST_ERR_NOMEM, "%s: out of memory", path);
    for (size_t k = 0; rc == ST_OK && k < n; k++)
        for (int c = 0; c < 3; c++)
            (*rgb)[3 * k + c] = img.data[k * img.channels + (size_t)ch[c]];
    *w = img.width;
    *h = img.height;
    st_image_free(&img);
    return rc;
}

/* stb_image reads a .hdr through these callbacks so that a file cut short is
 * seen: stb decodes past the end as zeros without a word (repeating the last
 * texel of a flat file, and looping for ever on a zero run length in a
 * run-length one), but it asks for bytes only when its decoder needs them, so
 * a request that finds none left (or stbi__getn's exact request of a few
 * bytes, shorter than its 128-byte buffer refill, left unfilled) means the
 * pixels run past the end. Past the end every byte is 0xFF: a run length stb
 * refuses or a run that advances, so the decoding ends either way. */
struct hdr_reader {
    FILE *f;
    int past_end;
};

static int hdr_read(void *user, char *data, int size)
{
    struct hdr_reader *r = user;
    if (size <= 0)
        return 0;
    size_t n = r->past_end ? 0 : fread(data, 1, (size_t)size, r->f);
    if (n == 0 || (n < (size_t)size && size < 128)) {
        r->past_end = 1;
        memset(data + n, 0xFF, (size_t)size - n);
        n = (size_t)size;
    }
    return (int)n;
}

static void hdr_skip(void *user, int n)
{
    struct hdr_reader *r = user;
    if (fseek(r->f, n, SEEK_CUR) != 0)
        r->past_end = 1;
}

static int hdr_eof(void *user)
{
    struct hdr_reader *r = user;
    return feof(r->f) || ferror(r->f);
}

/* R, G, B of a Radiance .hdr (stb_image; an 8-bit image is refused). */
static st_status hdr_rgb(const char *path, float **rgb, st_u32 *w, st_u32 *h, st_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return st_fail(err, ST_ERR_IO, "%s: cannot open (%s)", path, strerror(errno));
    int is_hdr = stbi_is_hdr_from_file(f), iw = 0, ih = 0, n = 0;
    /* the size from the header first: the cap holds before any decoding */
    int sized = is_hdr && stbi_info_from_file(f, &iw, &ih, &n) &&
                (st_u64)iw * (st_u64)ih <= ST_ENV_MAX_TEXELS;
    if (sized && check_env_memory(path, (st_u64)iw * (st_u64)ih, err) != ST_OK) {
        fclose(f);
        return err->status;
    }
    struct hdr_reader reader = {f, 0};
    const stbi_io_callbacks io = {hdr_read, hdr_skip, hdr_eof};
    float *px = sized ? stbi_loadf_from_callbacks(&io, &reader, &iw, &ih, &n, 3) : NULL;
    fclose(f);
    if (reader.past_end) {
        stbi_image_free(px);
        return st_fail(err, ST_ERR_FORMAT, "%s: cut short: the file ends before its %d x %d "
                       "texels do", path, iw, ih);
    }
    if (!is_hdr)
        return st_fail(err, ST_ERR_FORMAT, "%s: not a Radiance HDR (float) image", path);
    if (!sized && iw > 0 && ih > 0)
        return st_fail(err, ST_ERR_FORMAT, "%s: %d x %d texels: an environment map has 1 to 2^26",
                       path, iw, ih);
    if (!sized) /* stb's reason would be that of the last format it tried ("not BMP") */
        return st_fail(err, ST_ERR_FORMAT, "%s: a Radiance HDR header without a valid size (its "
                       "resolution line, -Y H +X W, with H and W positive)", path);
    if (!px) {
        const char *why = stbi_failure_reason();
        return st_fail(err, ST_ERR_FORMAT, "%s: cannot decode (%s)", path, why ? why : "unknown");
    }
    *rgb = px; /* stb allocates with malloc (STBI_MALLOC's default) */
    *w = (st_u32)iw;
    *h = (st_u32)ih;
    return ST_OK;
}

st_status st_envmap_load(const char *path, st_envmap **out, st_error *err)
{
    *out = NULL;
    size_t len = strlen(path);
    int exr = len > 4 && !strcasecmp(path + len - 4, ".exr");
    int hdr = len > 4 && !strcasecmp(path + len - 4, ".hdr");
    if (!exr && !hdr)
        return st_fail(err, ST_ERR_USAGE, "%s: an environment map is a .exr or .hdr file", path);
    float *rgb = NULL;
    st_u32 w = 0, h = 0;
    if ((exr ? exr_rgb(path, &rgb, &w, &h, err) : hdr_rgb(path, &rgb, &w, &h, err)) != ST_OK) {
        free(rgb);
        return err->status;
    }
    st_status rc = st_envmap_make(rgb, w, h, path, out, err);
    free(rgb);
    return rc;
}

st_status st_envmap_sky(st_envmap **out, st_error *err)
{
    float rgb[3 * ST_SKY_WIDTH * ST_SKY_HEIGHT];
    for (st_u32 j = 0; j < ST_SKY_HEIGHT; j++) {
        double elevation = PI / 2.0 - PI * (j + 0.5) / ST_SKY_HEIGHT; /* row 0 at the top */
        float l = elevation > 0.0 ? (float)(1.0 - (1.0 - ST_SKY_ZENITH) * sin(elevation))
                                  : ST_SKY_GROUND;
        for (st_u32 k = 0; k < 3 * ST_SKY_WIDTH; k++)
            rgb[3 * ST_SKY_WIDTH * j + k] = l;
    }
    return st_envmap_make(rgb, ST_SKY_WIDTH, ST_SKY_HEIGHT, "the default sky", out, err);
}

void st_envmap_free(st_envmap *m)
{
    if (!m)
        return;
    free(m->texels);
    free(m->cdf);
    free(m);
}

double st_env_power(const st_envmap *m, const float env[3], double radius)
{
    double integral = m ? m->integral : 4.0 * PI * ((double)env[0] + env[1] + env[2]) / 3.0;
    return PI * radius * radius * integral;
}
