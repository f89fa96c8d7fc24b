/* cli_merge.c — `strata merge PART.exr... -o OUT`: adds the raw films of
 * split renders (render --sample-range K:M or --part K/N) and resolves them on the device
 * with the render's own kernel, so parts covering 0..spp give exactly the
 * image of one render. Parts must agree on every setting recorded in their
 * headers (the scene's content hash, size, sampler, filter, seed, device, ...;
 * not the scene's path) and their sample ranges must tile 0..spp exactly, or,
 * with --partial, at least not overlap nor pass spp. Parts of a crop must
 * hold the same data window, which the result keeps. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_commands.h"
#include "cli_error.h"
#include "cli_session.h"
#include "st_film.h"
#include "st_outfile.h"

#define MAX_PARTS 4096

typedef struct part {
    const char *path;
    st_attr *attrs;
    int nattrs;
    st_u32 begin, end;
} part;

/* Sample ranges held by a merge with --partial, as the result's label. */
#define RANGES_TEXT 256

static const char *attr_value(const part *p, const char *name)
{
    for (int i = 0; i < p->nattrs; i++)
        if (!strcmp(p->attrs[i].name, name))
            return p->attrs[i].value;
    return NULL;
}

/* The film's counts of one part (ST_EXR_INT_ATTRS): a fact of that part alone. */
static int is_count(const char *name)
{
    static const char *const counts[] = {ST_EXR_INT_ATTRS};
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++)
        if (!strcmp(name, counts[k]))
            return 1;
    return 0;
}

/* Settings that may differ between parts: what each part rendered, facts
 * about the run rather than the image (its seconds; the kernels it ran,
 * which follow its samples: a part whose paths all end early never
 * launches the last vertex's, and no kernel choice changes the image), and
 * the scene's path (its content hash, strata.scene_hash, must agree). The
 * device must agree: two devices' floats differ (up to 2e-5 relative seen
 * between PoCL and a GPU). */
static int varies(const char *name)
{
    return !strcmp(name, "strata.sample_range") || !strcmp(name, "strata.part") ||
           !strcmp(name, "strata.render_seconds") ||
           !strcmp(name, "strata.kernels") || !strcmp(name, "strata.scene") || is_count(name);
}

static st_status check_part(const part *first, const part *p, st_error *err)
{
    for (int k = 0; k < 2; k++) { /* every setting of either part, in the other */
        const part *a = k ? p : first, *b = k ? first : p;
        for (int i = 0; i < a->nattrs; i++) {
            const char *name = a->attrs[i].name;
            if (strncmp(name, "strata.", 7) || varies(name))
                continue;
            const char *v = attr_value(b, name);
            if (!v || strcmp(v, a->attrs[i].value))
                return st_fail(err, ST_ERR_FORMAT, "%s: %s is %s, but %s has %s", p->path, name,
                               k ? a->attrs[i].value : (v ? v : "missing"), first->path,
                               k ? (v ? v : "missing") : a->attrs[i].value);
        }
    }
    return ST_OK;
}

/* Parts of a crop (render --crop) must hold the same window of the same image. */
static st_status check_window(const part *first, const st_image *a, const part *p,
                              const st_image *b, st_error *err)
{
    if (a->x0 == b->x0 && a->y0 == b->y0 && a->display_width == b->display_width &&
        a->display_height == b->display_height)
        return ST_OK;
    return st_fail(err, ST_ERR_FORMAT, "%s: data window at (%d, %d) of a %ux%u image, but %s's "
                   "is at (%d, %d) of %ux%u", p->path, b->x0, b->y0, b->display_width,
                   b->display_height, first->path, a->x0, a->y0, a->display_width,
                   a->display_height);
}

static int by_begin(const void *x, const void *y)
{
    const part *a = *(const part *const *)x, *b = *(const part *const *)y;
    return (a->begin > b->begin) - (a->begin < b->begin);
}

/* Appends "K:M" to the comma-separated list held (RANGES_TEXT bytes; "..."
 * ends a list too long for it). */
static void append_range(char *held, st_u32 k, st_u32 m)
{
    size_t len = strlen(held);
    if (len + 28 >= RANGES_TEXT) {
        if (len + 4 < RANGES_TEXT && strcmp(held + len - 3, "..."))
            strcat(held, "...");
        return;
    }
    snprintf(held + len, RANGES_TEXT - len, "%s%u:%u", len ? "," : "", k, m);
}

/* Reads the decimal number at *s (digits only, at most 2^32 - 1: sscanf's %u would wrap
 * 4294967297 to 1) and moves *s past it; 0 when there is none or it is too large. */
static int read_u32(const char **s, st_u32 *out)
{
    st_u64 v = 0;
    const char *p = *s;
    for (; *p >= '0' && *p <= '9'; p++)
        if ((v = v * 10 + (st_u64)(*p - '0')) > UINT32_MAX)
            return 0;
    if (p == *s)
        return 0;
    *s = p;
    *out = (st_u32)v;
    return 1;
}

/* Sample ranges, sorted by start, must tile 0..spp: no overlap, none past
 * spp, and (unless partial) no gap. The ranges held go to `held`, the gaps
 * to `missing` (RANGES_TEXT bytes each). */
static st_status check_ranges(part *parts, int n, int partial, char *held, char *missing,
                              st_error *err)
{
    const char *spp_text = attr_value(&parts[0], "strata.spp");
    st_u32 spp = 0;
    if (!spp_text || !read_u32(&spp_text, &spp) || *spp_text)
        return st_fail(err, ST_ERR_FORMAT, "%s: no strata.spp in the header", parts[0].path);
    part **order = malloc(sizeof *order * n);
    if (!order)
        return st_fail(err, ST_ERR_NOMEM, "out of memory");
    for (int i = 0; i < n; i++)
        order[i] = &parts[i];
    qsort(order, n, sizeof *order, by_begin);
    st_status rc = ST_OK;
    st_u32 at = 0, run = 0; /* samples run..at-1 are one unbroken run of parts */
    held[0] = missing[0] = '\0';
    for (int i = 0; i < n && rc == ST_OK; i++) {
        const part *p = order[i], *prev = i ? order[i - 1] : NULL;
        if (p->end > spp)
            rc = st_fail(err, ST_ERR_FORMAT, "%s: samples %u:%u pass the spp %u", p->path,
                         p->begin, p->end, spp);
        else if (prev && p->begin < prev->end)
            rc = st_fail(err, ST_ERR_FORMAT, "%s: samples %u:%u overlap %s's %u:%u", p->path,
                         p->begin, p->end, prev->path, prev->begin, prev->end);
        else if (p->begin > at && !partial)
            rc = st_fail(err, ST_ERR_FORMAT, "samples %u:%u are in no part (%s starts at %u; "
                         "--partial merges an incomplete set)", at, p->begin, p->path, p->begin);
        if (p->begin > at)
            append_range(missing, at, p->begin);
        if (i > 0 && p->begin != at) /* a gap closes the run run..at */
            append_range(held, run, at);
        if (i == 0 || p->begin != at)
            run = p->begin;
        at = p->end;
    }
    append_range(held, run, at);
    if (at < spp)
        append_range(missing, at, spp);
    if (rc == ST_OK && at < spp && !partial)
        rc = st_fail(err, ST_ERR_FORMAT, "samples %u:%u are in no part (the last, %s, ends at "
                     "%u; --partial merges an incomplete set)", at, spp, order[n - 1]->path, at);
    free(order);
    return rc;
}

/* A part's header and raw sums: sums[0] the image's, sums[k] AOV k's where
 * the part holds its layer (render --aov), else NULL. */
static st_status load_part(part *p, st_image *img, st_i64 **sums, st_error *err)
{
    if (st_image_load_exr(p->path, img, &p->attrs, &p->nattrs, err) ||
        st_film_from_image(img, p->path, "", &sums[0], err))
        return err->status;
    for (st_u32 k = 1; k < ST_AOV_COUNT; k++)
        if (st_film_has_layer(img, st_aov_layouts[k].layer) &&
            st_film_from_image(img, p->path, st_aov_layouts[k].layer, &sums[k], err) != ST_OK)
            return err->status;
    const char *range = attr_value(p, "strata.sample_range");
    if (!range || !read_u32(&range, &p->begin) || *range++ != ':' || !read_u32(&range, &p->end) ||
        *range || p->begin >= p->end)
        return st_fail(err, ST_ERR_FORMAT, "%s: no valid strata.sample_range in the header", p->path);
    return ST_OK;
}

/* The first part's settings, labelled with the sample ranges the result
 * holds (and strata.partial when they are not all of 0..spp). */
/* The AOVs' channels (st_aov_layouts) of the summed sums total[k] that
 * the parts hold, each resolved as render resolves it, appended to exr. */
static st_status add_aovs(st_device *dev, st_i64 *const *total, st_u32 w, st_u32 h,
                          st_image *exr, st_error *err)
{
    st_status rc = ST_OK;
    for (st_u32 k = 1; k < ST_AOV_COUNT && rc == ST_OK; k++) {
        if (!total[k])
            continue;
        st_image resolved = {0}, add = {0};
        if ((rc = st_render_resolve(dev, total[k], w, h, k, &resolved, NULL, err)) == ST_OK &&
            (rc = st_render_aov_image(&resolved, k, &add, err)) == ST_OK)
            rc = st_image_append(exr, &add, err);
        st_image_free(&resolved);
        st_image_free(&add);
    }
    return rc;
}

static st_status save_result(const part *parts, int n, const char *held, int complete,
                             const char *out, const st_image *rgb, st_error *err)
{
    st_attr attrs[ST_CLI_MAX_ATTRS + 3] = {0}; /* the added ones are strings, but for merged_parts */
    int na = 0;
    for (int i = 0; i < parts[0].nattrs && na < ST_CLI_MAX_ATTRS; i++)
        if (strcmp(parts[0].attrs[i].name, "strata.sample_range") &&
            strcmp(parts[0].attrs[i].name, "strata.part") &&
            strcmp(parts[0].attrs[i].name, "strata.render_seconds") &&
            !is_count(parts[0].attrs[i].name))
            attrs[na++] = parts[0].attrs[i];
    snprintf(attrs[na].name, sizeof attrs[na].name, "strata.merged_parts");
    snprintf(attrs[na].value, sizeof attrs[na].value, "%d", n);
    attrs[na].type = ST_ATTR_INT;
    snprintf(attrs[++na].name, sizeof attrs[na].name, "strata.sample_range");
    snprintf(attrs[na].value, sizeof attrs[na].value, "%s", held);
    if (!complete) {
        snprintf(attrs[++na].name, sizeof attrs[na].name, "strata.partial");
        snprintf(attrs[na].value, sizeof attrs[na].value, "holds samples %s of every pixel", held);
    }
    return st_image_save(out, rgb, attrs, na + 1, err);
}

static st_status merge(part *parts, int n, const char *const *outs, int nouts,
                       const char *device, int partial, st_error *err)
{
    char held[RANGES_TEXT], missing[RANGES_TEXT];
    st_image img = {0}, resolved = {0}, rgb = {0}, exr = {0}; /* exr: rgb and the AOVs */
    st_i64 *total[ST_AOV_COUNT] = {NULL}, *sums[ST_AOV_COUNT] = {NULL};
    st_device *dev = NULL;
    st_image place = {0}; /* the first part's window in the image (render --crop) */
    st_u32 w = 0, h = 0;
    st_status rc = ST_OK;
    for (int i = 0; i < n && rc == ST_OK; i++) {
        if ((rc = load_part(&parts[i], &img, sums, err)) != ST_OK) {
            for (st_u32 k = 0; k < ST_AOV_COUNT; k++)
                free(sums[k]);
            st_image_free(&img);
            break;
        }
        if (i == 0) {
            w = img.width;
            h = img.height;
            st_image_place_like(&place, &img);
            memcpy(total, sums, sizeof sums);
            memset(sums, 0, sizeof sums);
        } else if (img.width != w || img.height != h) {
            rc = st_fail(err, ST_ERR_FORMAT, "%s: %ux%u pixels, but %s has %ux%u", parts[i].path,
                         img.width, img.height, parts[0].path, w, h);
        } else if (check_window(&parts[0], &place, &parts[i], &img, err) != ST_OK) {
            rc = err->status;
        } else if ((rc = check_part(&parts[0], &parts[i], err)) == ST_OK) {
            for (st_u32 a = 0; a < ST_AOV_COUNT && rc == ST_OK; a++) {
                if (!total[a] != !sums[a])
                    rc = st_fail(err, ST_ERR_FORMAT, "%s: %s the AOV %s, but %s %s",
                                 parts[i].path, sums[a] ? "holds" : "lacks",
                                 st_aov_layouts[a].name, parts[0].path,
                                 sums[a] ? "does not" : "does");
                for (size_t k = 0; sums[a] && k < ST_FILM_SUMS * (size_t)w * h; k++)
                    /* wraps as the device's atom_add */
                    total[a][k] = (st_i64)((st_u64)total[a][k] + (st_u64)sums[a][k]);
            }
        }
        for (st_u32 a = 0; a < ST_AOV_COUNT; a++) {
            free(sums[a]);
            sums[a] = NULL;
        }
        st_image_free(&img);
    }
    if (rc == ST_OK)
        rc = check_ranges(parts, n, partial, held, missing, err);
    if (rc == ST_OK && missing[0]) /* only --partial gets here with a gap */
        fprintf(stderr, "strata: note: samples %s are in no part; the image holds %s of %s "
                "spp (strata.partial)\n", missing, held, attr_value(&parts[0], "strata.spp"));
    if (rc == ST_OK && st_device_create(device, &dev, err) != ST_OK)
        rc = st_cli_device_words(err);
    st_cli_catch_interrupts(); /* PoCL's LLVM put its own handlers over ours as the device began */
    if (rc == ST_OK && (st_render_resolve(dev, total[0], w, h, ST_AOV_NONE, &resolved, NULL, err) ||
                        st_cli_rgb_of(&resolved, &rgb, err) || st_image_append(&exr, &rgb, err) ||
                        add_aovs(dev, total, w, h, &exr, err)))
        rc = err->status;
    if (rc == ST_OK) {
        st_image_place_like(&rgb, &place);
        st_image_place_like(&exr, &place);
    }
    if (rc == ST_OK) {
        char whole[sizeof parts[0].attrs->value + 2];
        snprintf(whole, sizeof whole, "0:%s", attr_value(&parts[0], "strata.spp"));
        for (int k = 0; k < nouts && rc == ST_OK; k++) /* every -o, as render writes them */
            rc = save_result(parts, n, held, !strcmp(held, whole), outs[k],
                             st_cli_has_extension(outs[k], ".png") ? &rgb : &exr, err);
    }
    if (rc != ST_OK && dev && err->status == ST_ERR_DEVICE && st_device_build_log(dev)[0])
        fprintf(stderr, "%s\n", st_device_build_log(dev));
    st_device_destroy(dev);
    st_image_free(&resolved);
    st_image_free(&rgb);
    st_image_free(&exr);
    for (st_u32 k = 0; k < ST_AOV_COUNT; k++)
        free(total[k]);
    return rc;
}

int st_cli_merge(int argc, char **argv)
{
    const char *outs[ST_CLI_MAX_OUTPUTS], *device = NULL;
    int nouts = 0;
    int partial = 0;
    part *parts = calloc(MAX_PARTS, sizeof *parts);
    int n = 0, rc = 0;
    if (!parts)
        return st_cli_fail(&(st_error){ST_ERR_NOMEM, "out of memory"});
    for (int i = 1; i < argc && rc == 0; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            puts("usage: strata merge PART.exr... -o OUT.exr|OUT.png|- [-o OUT2...] [--device SPEC] [--partial]\n"
                 "  adds the raw films of split renders (strata render --sample-range K:M\n"
                 "  or --part K/N)\n"
                 "  into the image one render of all their samples gives, bit for bit.\n"
                 "  The parts' ranges must tile 0..spp, and parts must share every setting,\n"
                 "  the scene's content, the device and the data window (render --crop),\n"
                 "  which the result keeps.\n"
                 "  --partial   merge a set with gaps; the result is labelled with the\n"
                 "              ranges it holds (strata.sample_range, strata.partial)");
            free(parts);
            return 0;
        }
        if (!strcmp(argv[i], "-o") || !strcmp(argv[i], "--device")) {
            if (i + 1 >= argc)
                rc = st_cli_usage_error("merge: %s needs a value", argv[i]);
            else if (argv[i][1] == 'o' && nouts == ST_CLI_MAX_OUTPUTS)
                rc = st_cli_usage_error("merge: -o %s: at most %d outputs", argv[i + 1],
                                        ST_CLI_MAX_OUTPUTS);
            else if (argv[i][1] == 'o')
                outs[nouts++] = argv[++i];
            else
                device = argv[++i];
        } else if (!strcmp(argv[i], "--partial")) {
            partial = 1;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            rc = st_cli_usage_error("merge: unknown option %s", argv[i]);
        } else if (n == MAX_PARTS) {
            rc = st_cli_usage_error("merge: more than %d parts", MAX_PARTS);
        } else {
            parts[n++].path = argv[i];
        }
    }
    if (rc == 0 && (!nouts || n == 0))
        rc = st_cli_usage_error("merge: needs parts and -o OUT (strata merge A.exr B.exr -o OUT.exr)");
    st_error err = {0};
    if (rc == 0) {
        st_outfile_role files[ST_CLI_MAX_OUTPUTS + MAX_PARTS];
        char roles[MAX_PARTS][24];
        for (int k = 0; k < nouts; k++)
            files[k] = (st_outfile_role){outs[k], "-o"};
        for (int k = 0; k < n; k++) {
            snprintf(roles[k], sizeof roles[k], "part %d", k + 1);
            files[nouts + k] = (st_outfile_role){parts[k].path, roles[k]};
        }
        rc = st_cli_check_apart(files, nouts + n, nouts);
    }
    for (int k = 0; k < nouts && rc == 0; k++) {
        if (!st_cli_has_extension(outs[k], ".exr") && !st_cli_has_extension(outs[k], ".png") &&
            strcmp(outs[k], "-"))
            rc = st_cli_usage_error("-o %s: the output must end in .exr or .png, or be - (a "
                                    "PNG on standard output)", outs[k]);
        else if (st_outfile_check(outs[k], &err) != ST_OK)
            rc = st_cli_fail(&err);
    }
    if (rc == 0 && merge(parts, n, outs, nouts, device, partial, &err) != ST_OK)
        rc = st_cli_fail(&err);
    for (int i = 0; i < n; i++)
        free(parts[i].attrs);
    free(parts);
    return rc;
}
