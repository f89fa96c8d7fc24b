/* scene_fs.c — bounded, confined file reading for the scene module (see
 * scene_fs.h). */
#define _XOPEN_SOURCE 700 /* realpath(3) */
#include "scene_fs.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Reads at most limit + 1 bytes of f into a growing buffer. */
static st_status read_bounded(FILE *f, const char *path, size_t limit, const char *what,
                              unsigned char **data, size_t *size, st_error *err)
{
    size_t cap = 0;
    for (;;) {
        if (*size == cap) {
            if (cap > limit)
                return st_fail(err, ST_ERR_FORMAT, "%s: larger than %zu MiB, the limit for %s",
                               path, limit >> 20, what);
            cap = cap ? 2 * cap : 1 << 16;
            cap = cap > limit + 1 ? limit + 1 : cap;
            unsigned char *grown = realloc(*data, cap);
            if (!grown)
                return st_fail(err, ST_ERR_NOMEM, "%s: out of memory reading the file", path);
            *data = grown;
        }
        size_t got = fread(*data + *size, 1, cap - *size, f);
        *size += got;
        if (got == 0) {
            if (ferror(f))
                return st_fail(err, ST_ERR_IO, "%s: cannot read: %s", path, strerror(errno));
            if (*size > limit)
                return st_fail(err, ST_ERR_FORMAT, "%s: larger than %zu MiB, the limit for %s",
                               path, limit >> 20, what);
            return ST_OK;
        }
    }
}

st_status st_scene_fs_read(const char *path, size_t limit, const char *what, unsigned char **data,
                           size_t *size, st_error *err)
{
    *data = NULL;
    *size = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return st_fail(err, ST_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat sb;
    st_status s;
    if (fstat(fileno(f), &sb) == 0 && S_ISDIR(sb.st_mode))
        s = st_fail(err, ST_ERR_IO, "%s: is a folder", path);
    else if (fstat(fileno(f), &sb) == 0 && S_ISREG(sb.st_mode) && (size_t)sb.st_size > limit)
        s = st_fail(err, ST_ERR_FORMAT, "%s: %lld bytes, larger than %zu MiB, the limit for %s",
                    path, (long long)sb.st_size, limit >> 20, what);
    else
        s = read_bounded(f, path, limit, what, data, size, err);
    fclose(f);
    if (s != ST_OK) {
        free(*data);
        *data = NULL;
        *size = 0;
    }
    return s;
}

int st_scene_fs_is_inside(const char *base_dir, const char *path)
{
    char *dir = realpath(base_dir[0] ? base_dir : ".", NULL);
    char *file = realpath(path, NULL);
    size_t n = dir ? strlen(dir) : 0;
    /* "/a/b" holds "/a/b/x", not "/a/bc"; the root folder holds everything */
    int inside = dir && file && strncmp(file, dir, n) == 0 &&
                 (file[n] == '/' || (n == 1 && dir[0] == '/'));
    free(dir);
    free(file);
    return inside;
}
