/* cli_merge.c — `strata merge PART.exr... -o OUT`: adds the raw films of
 * split renders (render --sample-range K:M) and resolves them on the device
 * with the render's own kernel, so parts covering 0..spp give exactly the
 * image of one render. Parts must agree on every setting recorded in their
 * headers (scene, size, sampler, filter, seed, ...) and their sample ranges
 * must not overlap. */
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

/* Settings that may differ between parts: what each part rendered, and
 * facts about the run rather than the image. */
static int varies(const char *name)
{
    return !strcmp(name, "strata.sample_range") || !strcmp(name, "strata.render_seconds") ||
           !strcmp(name, "strata.device") || is_count(name);
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

static int by_begin(const void *x, const void *y)
{
    const part *a = *(const part *const *)x, *b = *(const part *const *)y;
    return (a->begin > b->begin) - (a->begin < b->begin);
}

/* Sample ranges must not overlap (sorted by start). */
static st_status check_ranges(part *parts, int n, st_error *err)
{
    part **order = malloc(sizeof *order * n);
    if (!order)
        return st_fail(err, ST_ERR_NOMEM, "out of memory");
    for (int i = 0; i < n; i++)
        order[i] = &parts[i];
    qsort(order, n, sizeof *order, by_begin);
    st_status rc = ST_OK;
    for (int i = 1; i < n && rc == ST_OK; i++)
        if (order[i]->begin < order[i - 1]->end)
            rc = st_fail(err, ST_ERR_FORMAT, "%s: samples %u:%u overlap %s's %u:%u",
                         order[i]->path, order[i]->begin, order[i]->end, order[i - 1]->path,
                         order[i - 1]->begin, order[i - 1]->end);
    free(order);
    return rc;
}

static st_status load_part(part *p, st_image *img, st_i64 **sums, st_error *err)
{
    if (st_image_load_exr(p->path, img, &p->attrs, &p->nattrs, err) ||
        st_film_from_image(img, p->path, sums, err))
        return err->status;
    const char *range = attr_value(p, "strata.sample_range");
    char tail;
    if (!range || sscanf(range, "%u:%u%c", &p->begin, &p->end, &tail) != 2 || p->begin >= p->end)
        return st_fail(err, ST_ERR_FORMAT, "%s: no valid strata.sample_range in the header", p->path);
    return ST_OK;
}

static st_status merge(part *parts, int n, const char *out, const char *device, st_error *err)
{
    st_image img = {0}, resolved = {0}, rgb = {0};
    st_i64 *total = NULL, *sums = NULL;
    st_device *dev = NULL;
    st_u32 w = 0, h = 0;
    st_status rc = ST_OK;
    for (int i = 0; i < n && rc == ST_OK; i++) {
        if ((rc = load_part(&parts[i], &img, &sums, err)) != ST_OK)
            break;
        if (i == 0) {
            w = img.width;
            h = img.height;
            total = sums;
            sums = NULL;
        } else if (img.width != w || img.height != h) {
            rc = st_fail(err, ST_ERR_FORMAT, "%s: %ux%u pixels, but %s has %ux%u", parts[i].path,
                         img.width, img.height, parts[0].path, w, h);
        } else if ((rc = check_part(&parts[0], &parts[i], err)) == ST_OK) {
            for (size_t k = 0; k < ST_FILM_SUMS * (size_t)w * h; k++) /* wraps as the device's atom_add */
                total[k] = (st_i64)((st_u64)total[k] + (st_u64)sums[k]);
        }
        free(sums);
        sums = NULL;
        st_image_free(&img);
    }
    if (rc == ST_OK)
        rc = check_ranges(parts, n, err);
    if (rc == ST_OK && st_device_create(device, &dev, err) != ST_OK)
        rc = st_cli_device_words(err);
    if (rc == ST_OK && (st_render_resolve(dev, total, w, h, &resolved, NULL, err) ||
                        st_cli_rgb_of(&resolved, &rgb, err)))
        rc = err->status;
    if (rc == ST_OK) {
        /* the first part's settings, with the ranges merged */
        st_attr attrs[ST_CLI_MAX_ATTRS + 1];
        int na = 0;
        for (int i = 0; i < parts[0].nattrs && na < ST_CLI_MAX_ATTRS; i++)
            if (strcmp(parts[0].attrs[i].name, "strata.sample_range") &&
                strcmp(parts[0].attrs[i].name, "strata.render_seconds") &&
                !is_count(parts[0].attrs[i].name))
                attrs[na++] = parts[0].attrs[i];
        snprintf(attrs[na].name, sizeof attrs[na].name, "strata.merged_parts");
        snprintf(attrs[na].value, sizeof attrs[na].value, "%d", n);
        attrs[na++].type = ST_ATTR_INT;
        rc = st_image_save(out, &rgb, attrs, na, err);
    }
    if (rc != ST_OK && dev && err->status == ST_ERR_DEVICE && st_device_build_log(dev)[0])
        fprintf(stderr, "%s\n", st_device_build_log(dev));
    st_device_destroy(dev);
    st_image_free(&resolved);
    st_image_free(&rgb);
    free(total);
    return rc;
}

int st_cli_merge(int argc, char **argv)
{
    const char *out = NULL, *device = NULL;
    part *parts = calloc(MAX_PARTS, sizeof *parts);
    int n = 0, rc = 0;
    if (!parts)
        return st_cli_fail(&(st_error){ST_ERR_NOMEM, "out of memory"});
    for (int i = 1; i < argc && rc == 0; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            puts("usage: strata merge PART.exr... -o OUT.exr|OUT.png [--device SPEC]\n"
                 "  adds the raw films of split renders (strata render --sample-range K:M)\n"
                 "  into the image one render of all their samples gives, bit for bit");
            free(parts);
            return 0;
        }
        if (!strcmp(argv[i], "-o") || !strcmp(argv[i], "--device")) {
            if (i + 1 >= argc)
                rc = st_cli_usage_error("merge: %s needs a value", argv[i]);
            else if (argv[i][1] == 'o')
                out = argv[++i];
            else
                device = argv[++i];
        } else if (argv[i][0] == '-' && argv[i][1]) {
            rc = st_cli_usage_error("merge: unknown option %s", argv[i]);
        } else if (n == MAX_PARTS) {
            rc = st_cli_usage_error("merge: more than %d parts", MAX_PARTS);
        } else {
            parts[n++].path = argv[i];
        }
    }
    if (rc == 0 && (!out || n == 0))
        rc = st_cli_usage_error("merge: needs parts and -o OUT (strata merge A.exr B.exr -o OUT.exr)");
    if (rc == 0 && !st_cli_has_extension(out, ".exr") && !st_cli_has_extension(out, ".png"))
        rc = st_cli_usage_error("-o %s: the output must end in .exr or .png", out);
    st_error err = {0};
    if (rc == 0 && st_outfile_check(out, &err) != ST_OK)
        rc = st_cli_fail(&err);
    if (rc == 0 && merge(parts, n, out, device, &err) != ST_OK)
        rc = st_cli_fail(&err);
    for (int i = 0; i < n; i++)
        free(parts[i].attrs);
    free(parts);
    return rc;
}
