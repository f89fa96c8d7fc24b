/* outfile.c — a user's file written to an exclusive temporary beside it, then renamed into place
 * (see include/st_outfile.h for the contract).
 *
 * Invariant: from st_outfile_open until commit or abort the temporary exists and is ours alone
 * (O_EXCL); after either, it is gone — renamed over the destination on a successful commit,
 * unlinked otherwise. rename(2) within one folder is atomic (POSIX), so a reader of the
 * destination sees the old file or the complete new one; the fsync before it makes sure the new
 * name never points at data still only in the page cache after a crash.
 */
#include "st_outfile.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Every live temporary's name, in static storage that a signal handler may read
 * (st_outfile_remove_temporaries): a slot is claimed before its temporary is
 * created and released only after the temporary is renamed or unlinked, so a
 * temporary that exists is always listed. Names live in the slot itself, never
 * in freed heap memory. */
#define SLOTS 64
static struct {
    atomic_int used;  /* 0 free, 1 claimed (name may be incomplete), 2 name valid */
    char name[PATH_MAX];
} slots[SLOTS];

struct st_outfile {
    FILE *stream;
    int err_no;  /* errno of the first failed write, 0 if none */
    int slot;    /* index into slots */
    char *path;  /* destination */
    char *temp;  /* "<folder>/.<name>.tmp.<pid>.<n>" */
};

static int claim_slot(void)
{
    for (int i = 0; i < SLOTS; i++) {
        int expect = 0;
        if (atomic_compare_exchange_strong(&slots[i].used, &expect, 1))
            return i;
    }
    return -1;
}

/* Lists f->temp before it is created. */
static void list_temporary(const struct st_outfile *f)
{
    atomic_store(&slots[f->slot].used, 1);
    strcpy(slots[f->slot].name, f->temp); /* fits: open checked the length */
    atomic_store(&slots[f->slot].used, 2);
}

void st_outfile_remove_temporaries(void)
{
    for (int i = 0; i < SLOTS; i++)
        if (atomic_load(&slots[i].used) == 2)
            unlink(slots[i].name); /* async-signal-safe (POSIX.1-2008 §2.4.3) */
}

/* Tries this many names before giving up: only a crashed earlier run of the same pid (or a
 * hostile folder) leaves names of ours behind. */
#define TEMP_TRIES 100

/* Formats the n-th temporary name for path into f->temp (sized by open_temporary). */
static void temp_name(struct st_outfile *f, size_t size, unsigned n)
{
    const char *slash = strrchr(f->path, '/');
    int dir = slash ? (int)(slash - f->path) + 1 : 0;
    snprintf(f->temp, size, "%.*s.%s.tmp.%ld.%u", dir, f->path, f->path + dir, (long)getpid(), n);
}

/* Creates the temporary exclusively; returns its fd, or -1 with errno set. A process-wide
 * counter spreads concurrent writers of one destination over distinct names at once. */
static int open_temporary(struct st_outfile *f, size_t size)
{
    static atomic_uint serial;
    for (int tries = 0; tries < TEMP_TRIES; tries++) {
        temp_name(f, size, atomic_fetch_add(&serial, 1u));
        list_temporary(f);
        int fd = open(f->temp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0 || errno != EEXIST)
            return fd;
    }
    errno = EEXIST;
    return -1;
}

/* After the temporary is gone (renamed or unlinked): frees the slot and f. */
static void release(struct st_outfile *f)
{
    if (f->slot >= 0)
        atomic_store(&slots[f->slot].used, 0);
    free(f->path);
    free(f->temp);
    free(f);
}

st_status st_outfile_open(const char *path, st_outfile **out, st_error *err)
{
    *out = NULL;
    if (!path || !path[0])
        return st_fail(err, ST_ERR_USAGE, "output: empty file name");
    size_t size = strlen(path) + 48; /* ".", ".tmp.", a pid and a counter */
    if (size > PATH_MAX)
        return st_fail(err, ST_ERR_IO, "%.200s...: file name too long", path);
    struct st_outfile *f = calloc(1, sizeof *f);
    if (f) {
        f->slot = claim_slot();
        f->path = strdup(path);
        f->temp = malloc(size);
    }
    if (f && f->slot < 0) {
        release(f);
        return st_fail(err, ST_ERR_IO, "%s: more than %d outputs open at once", path, SLOTS);
    }
    if (!f || !f->path || !f->temp) {
        if (f)
            release(f);
        return st_fail(err, ST_ERR_NOMEM, "%s: cannot allocate an output file", path);
    }
    int fd = open_temporary(f, size);
    if (fd >= 0 && !(f->stream = fdopen(fd, "wb"))) {
        int e = errno;
        close(fd);
        unlink(f->temp);
        fd = -1;
        errno = e;
    }
    if (fd < 0) {
        st_status s = st_fail(err, ST_ERR_IO, "%s: cannot create (%s)", path, strerror(errno));
        release(f);
        return s;
    }
    *out = f;
    return ST_OK;
}

FILE *st_outfile_stream(st_outfile *f) { return f->stream; }

const char *st_outfile_path(const st_outfile *f) { return f->path; }

/* Keeps the first failure's errno (EIO when the call left none) and returns -1. */
static int note_failure(struct st_outfile *f)
{
    if (errno == 0)
        errno = EIO;
    if (f->err_no == 0)
        f->err_no = errno;
    return -1;
}

int st_outfile_write(st_outfile *f, const void *data, size_t n)
{
    errno = 0;
    if (n > 0 && fwrite(data, 1, n, f->stream) != n)
        return note_failure(f);
    return 0;
}

int st_outfile_write_at(st_outfile *f, const void *data, size_t n, uint64_t offset)
{
    errno = 0;
    if (fflush(f->stream) != 0 || offset > (uint64_t)INT64_MAX - n)
        return note_failure(f);
    const char *p = data;
    while (n > 0) {
        ssize_t w = pwrite(fileno(f->stream), p, n, (off_t)offset);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0) /* 0 for n > 0 means no progress: report it rather than spin */
            return note_failure(f);
        p += w;
        n -= (size_t)w;
        offset += (uint64_t)w;
    }
    return 0;
}

int st_outfile_error(const st_outfile *f) { return f->err_no; }

/* Flushes, syncs and closes the stream; returns 0 or an errno (the first one met). */
static int finish_stream(struct st_outfile *f)
{
    int e = f->err_no;
    if (e == 0 && ferror(f->stream))
        e = EIO; /* a stream write failed and errno is long gone */
    if (e == 0 && fflush(f->stream) != 0)
        e = errno;
    if (e == 0 && fsync(fileno(f->stream)) != 0)
        e = errno;
    if (fclose(f->stream) != 0 && e == 0)
        e = errno;
    f->stream = NULL;
    return e;
}

st_status st_outfile_commit(st_outfile *f, st_error *err)
{
    st_status s = ST_OK;
    int e = finish_stream(f);
    if (e != 0)
        s = st_fail(err, ST_ERR_IO, "%s: cannot write (%s)", f->path, strerror(e));
    else if (rename(f->temp, f->path) != 0)
        s = st_fail(err, ST_ERR_IO, "%s: cannot rename into place (%s)", f->path,
                    strerror(errno));
    if (s != ST_OK)
        unlink(f->temp);
    release(f);
    return s;
}

void st_outfile_abort(st_outfile *f)
{
    if (!f)
        return;
    fclose(f->stream);
    unlink(f->temp);
    release(f);
}

st_status st_outfile_check(const char *path, st_error *err)
{
    struct stat sb;
    if (path && stat(path, &sb) == 0 && S_ISDIR(sb.st_mode))
        return st_fail(err, ST_ERR_IO, "%s: is a folder", path);
    st_outfile *f;
    if (st_outfile_open(path, &f, err) != ST_OK)
        return err->status;
    st_outfile_abort(f);
    return ST_OK;
}
