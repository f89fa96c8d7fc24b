/* scene_fs.c — bounded, confined file reading for the scene module (see
 * scene_fs.h). */
#define _XOPEN_SOURCE 700 /* realpath(3), openat(2), O_NOFOLLOW, O_DIRECTORY */
#include "scene_fs.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

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

/* Reads the open file fd (a regular file, checked by the caller) within limit; closes fd. */
static st_status read_fd(int fd, const char *path, size_t limit, const char *what,
                         unsigned char **data, size_t *size, st_error *err)
{
    *data = NULL;
    *size = 0;
    struct stat sb;
    st_status s;
    FILE *f = NULL;
    if (fstat(fd, &sb) != 0)
        s = st_fail(err, ST_ERR_IO, "%s: cannot read: %s", path, strerror(errno));
    else if (S_ISDIR(sb.st_mode))
        s = st_fail(err, ST_ERR_IO, "%s: is a folder", path);
    else if (!S_ISREG(sb.st_mode))
        s = st_fail(err, ST_ERR_IO, "%s: not a regular file (a device, FIFO or socket); refused",
                    path);
    else if ((size_t)sb.st_size > limit)
        s = st_fail(err, ST_ERR_FORMAT, "%s: %lld bytes, larger than %zu MiB, the limit for %s",
                    path, (long long)sb.st_size, limit >> 20, what);
    else if (!(f = fdopen(fd, "rb")))
        s = st_fail(err, ST_ERR_NOMEM, "%s: cannot read: %s", path, strerror(errno));
    else
        s = read_bounded(f, path, limit, what, data, size, err);
    if (f)
        fclose(f);
    else
        close(fd);
    if (s != ST_OK) {
        free(*data);
        *data = NULL;
        *size = 0;
    }
    return s;
}

/* O_NONBLOCK: opening a FIFO returns at once instead of waiting for a writer (it is refused by
 * fstat next); a regular file ignores the flag. */
#define OPEN_FLAGS (O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC)

st_status st_scene_fs_read(const char *path, size_t limit, const char *what, unsigned char **data,
                           size_t *size, st_error *err)
{
    *data = NULL;
    *size = 0;
    int fd = open(path, OPEN_FLAGS);
    if (fd < 0)
        return st_fail(err, ST_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    return read_fd(fd, path, limit, what, data, size, err);
}

st_status st_scene_fs_read_stdin(size_t limit, unsigned char **data, size_t *size, st_error *err)
{
    *data = NULL;
    *size = 0;
    st_status s = read_bounded(stdin, "standard input", limit, "a scene file", data, size, err);
    if (s != ST_OK) {
        free(*data);
        *data = NULL;
        *size = 0;
    }
    return s;
}

int st_scene_fs_open_dir(const char *base_dir)
{
    return open(base_dir[0] ? base_dir : ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
}

/* The most folders deep a URI may reach below the scene's folder. */
#define MAX_URI_DEPTH 64

/* Opens the folder or file `name` (one path component) in folder fd without following a
 * symbolic link; -1 with errno set. */
static int open_component(int fd, const char *name, int last)
{
    return openat(fd, name, last ? OPEN_FLAGS | O_NOFOLLOW
                                 : O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
}

/* Why opening a component failed, in the user's words (O_NOFOLLOW fails with ELOOP on a link). */
static const char *open_failure(int e)
{
    return e == ELOOP ? "a symbolic link, which could lead anywhere; refused" : strerror(e);
}

st_status st_scene_fs_read_at(int dir_fd, const char *uri, size_t limit, const char *what,
                              unsigned char **data, size_t *size, st_error *err)
{
    *data = NULL;
    *size = 0;
    if (uri[0] == '/')
        return st_fail(err, ST_ERR_IO, "%s: an absolute path; the URI leads outside the scene's "
                       "folder, refused", uri);
    /* walked one name at a time from the folder's descriptor, keeping each folder open: ".."
     * steps back to the folder it came from, never above the scene's own, and no name is looked
     * up twice, so nothing can be swapped between a check and the open */
    int stack[MAX_URI_DEPTH + 1], depth = 0;
    stack[0] = dir_fd;
    st_status s = ST_OK;
    const char *p = uri;
    char name[NAME_MAX + 1];
    while (s == ST_OK) {
        size_t n = strcspn(p, "/");
        int last = p[n] == '\0';
        if (n > NAME_MAX) {
            s = st_fail(err, ST_ERR_IO, "%s: a name longer than %d bytes", uri, NAME_MAX);
            break;
        }
        memcpy(name, p, n);
        name[n] = '\0';
        p += n + !last;
        if (last && (n == 0 || !strcmp(name, ".") || !strcmp(name, ".."))) {
            s = st_fail(err, ST_ERR_IO, "%s: names a folder, not a file", uri);
        } else if (n == 0 || !strcmp(name, ".")) {
            continue;
        } else if (!strcmp(name, "..")) {
            if (depth == 0)
                s = st_fail(err, ST_ERR_IO, "%s: the URI leads outside the scene's folder; refused",
                            uri);
            else
                close(stack[depth--]);
        } else if (last) {
            int fd = open_component(stack[depth], name, 1);
            if (fd < 0)
                s = st_fail(err, ST_ERR_IO, "%s: cannot open: %s", uri, open_failure(errno));
            else
                s = read_fd(fd, uri, limit, what, data, size, err);
            break;
        } else if (depth == MAX_URI_DEPTH) {
            s = st_fail(err, ST_ERR_IO, "%s: more than %d folders deep", uri, MAX_URI_DEPTH);
        } else {
            int fd = open_component(stack[depth], name, 0);
            struct stat sb; /* a link to a folder fails as "not a folder": say which it is */
            if (fd < 0 && errno == ENOTDIR &&
                fstatat(stack[depth], name, &sb, AT_SYMLINK_NOFOLLOW) == 0 && S_ISLNK(sb.st_mode))
                errno = ELOOP;
            if (fd < 0)
                s = st_fail(err, ST_ERR_IO, "%s: cannot open %s: %s", uri, name,
                            open_failure(errno));
            else
                stack[++depth] = fd;
        }
    }
    while (depth > 0)
        close(stack[depth--]);
    return s;
}

char *st_scene_fs_link_target(const char *path)
{
    struct stat sb;
    return lstat(path, &sb) == 0 && S_ISLNK(sb.st_mode) ? realpath(path, NULL) : NULL;
}
