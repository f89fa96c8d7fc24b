/* outfile.c — a user's file written to an exclusive temporary beside it, then renamed into place;
 * a device, a FIFO or "-" written directly (see include/st_outfile.h for the contract).
 *
 * Invariant: from st_outfile_open until commit or abort the temporary exists and is ours alone
 * (O_EXCL); after either, it is gone — renamed over the destination on a successful commit,
 * unlinked otherwise. rename(2) within one folder is atomic (POSIX), so a reader of the
 * destination sees the old file or the complete new one; the fsync before it makes sure the new
 * name never points at data still only in the page cache after a crash.
 */
#define _GNU_SOURCE /* fopencookie(3); realpath(3) */
#include "st_outfile.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
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
    FILE *stream; /* over fd through write_cookie, so a failed write's errno is kept */
    int fd;
    int lock_fd; /* a dup of fd holding the temporary's flock(2) until it is renamed or unlinked */
    int err_no;  /* errno of the first failed write, 0 if none */
    int slot;    /* index into slots; -1 when written directly */
    int direct;  /* 1: a device, FIFO or stdout written in place, no temporary */
    char *path;  /* destination as the user named it (for messages) */
    char *dest;  /* what is renamed over: path, or a symbolic link's target */
    char *temp;  /* "<folder>/.<name>.strata-tmp.<host>.<pid>.<n>"; NULL when direct */
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

/* What marks a temporary as strata's own: no other program names its files so, and the sweep
 * (st_outfile_remove_stale) looks at nothing else. */
#define TEMP_TOKEN ".strata-tmp."

/* The most bytes of the host name kept in a temporary's name (HOST_NAME_MAX on Linux). */
#define TEMP_HOST_KEEP 64

/* The most bytes of the destination's name kept in a temporary's name: with ".", the token, the
 * host, a pid and a counter (at most 1 + 12 + 64 + 1 + 10 + 1 + 10 bytes) the temporary of the
 * longest legal name still fits in NAME_MAX. */
#define TEMP_NAME_KEEP (NAME_MAX - 99)

/* This host's name as it goes into a temporary's name: letters, digits and '-' kept, anything
 * else (the dots of a domain, a slash) written '_', so the name parses back unambiguously. */
static void host_token(char host[TEMP_HOST_KEEP + 1])
{
    char raw[256] = "";
    if (gethostname(raw, sizeof raw - 1) != 0 || !raw[0])
        strcpy(raw, "localhost");
    size_t i = 0;
    for (; raw[i] && i < TEMP_HOST_KEEP; i++) {
        char c = raw[i];
        int keep = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                   c == '-';
        host[i] = keep ? c : '_';
    }
    host[i] = '\0';
}

/* Formats the n-th temporary name for f->dest into f->temp (sized by open_temporary). */
static void temp_name(struct st_outfile *f, size_t size, unsigned n)
{
    const char *slash = strrchr(f->dest, '/');
    int dir = slash ? (int)(slash - f->dest) + 1 : 0;
    char host[TEMP_HOST_KEEP + 1];
    host_token(host);
    snprintf(f->temp, size, "%.*s.%.*s" TEMP_TOKEN "%s.%ld.%u", dir, f->dest, TEMP_NAME_KEEP,
             f->dest + dir, host, (long)getpid(), n);
}

/* Whether fd is the file that name (relative to folder fd dir, AT_FDCWD for a path) names now. */
static int still_named(int dir, const char *name, int fd)
{
    struct stat a, b;
    return fstat(fd, &a) == 0 && fstatat(dir, name, &b, AT_SYMLINK_NOFOLLOW) == 0 &&
           a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

/* Creates the temporary exclusively and takes its lock; returns its fd, or -1 with errno set.
 * The lock (flock(2), held by f->lock_fd until the temporary is renamed or unlinked) is what
 * tells a sweeping writer in any pid namespace of this host that the file is alive. A sweeper
 * may lock a new name in the instant before its writer does; the writer then finds the lock
 * taken or its file unlinked, leaves it to the sweeper and takes the next name. A file system
 * without locks leaves the temporary unlocked, and then no sweeper can lock it either. A
 * process-wide counter spreads concurrent writers of one destination over distinct names. */
static int open_temporary(struct st_outfile *f, size_t size)
{
    static atomic_uint serial;
    for (int tries = 0; tries < TEMP_TRIES; tries++) {
        temp_name(f, size, atomic_fetch_add(&serial, 1u));
        list_temporary(f);
        int fd = open(f->temp, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
        if (fd < 0 && errno != EEXIST)
            return -1;
        if (fd < 0)
            continue;
        int locked = flock(fd, LOCK_EX | LOCK_NB) == 0;
        if (!locked && errno == EWOULDBLOCK) {
            close(fd); /* a sweeper holds it and removes it */
            continue;
        }
        if (locked && !still_named(AT_FDCWD, f->temp, fd)) {
            close(fd); /* a sweeper removed it before the lock was ours */
            continue;
        }
        if ((f->lock_fd = fcntl(fd, F_DUPFD_CLOEXEC, 0)) < 0) {
            int e = errno;
            unlink(f->temp);
            close(fd);
            errno = e;
            return -1;
        }
        return fd;
    }
    errno = EEXIST;
    return -1;
}

/* stdio's writes to the file: write(2) in full, the first failure's errno kept in err_no (a
 * plain stdio stream only sets its error flag, and errno is gone by commit: a full disk would be
 * reported as "Input/output error"). */
static ssize_t write_cookie(void *cookie, const char *buf, size_t size)
{
    struct st_outfile *f = cookie;
    size_t done = 0;
    while (done < size) {
        ssize_t w = write(f->fd, buf + done, size - done);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0) {
            if (f->err_no == 0)
                f->err_no = w < 0 ? errno : EIO;
            return 0; /* fopencookie(3): 0 is an error; the stream's error flag is set */
        }
        done += (size_t)w;
    }
    return (ssize_t)size;
}

static int seek_cookie(void *cookie, off64_t *offset, int whence)
{
    struct st_outfile *f = cookie;
    off_t at = lseek(f->fd, (off_t)*offset, whence);
    if (at < 0)
        return -1;
    *offset = at;
    return 0;
}

static int close_cookie(void *cookie)
{
    struct st_outfile *f = cookie;
    int rc = close(f->fd);
    f->fd = -1;
    return rc;
}

/* The stream over f->fd; NULL with errno set. */
static FILE *open_stream(struct st_outfile *f)
{
    cookie_io_functions_t io = {NULL, write_cookie, seek_cookie, close_cookie};
    return fopencookie(f, "wb", io);
}

/* After the temporary is gone (renamed or unlinked): frees the slot and f. */
static void release(struct st_outfile *f)
{
    if (f->lock_fd >= 0)
        close(f->lock_fd); /* the temporary is gone: its lock goes too */
    if (f->slot >= 0)
        atomic_store(&slots[f->slot].used, 0);
    free(f->path);
    free(f->dest);
    free(f->temp);
    free(f);
}

/* How a destination is written. */
enum kind { NEW_FILE, REPLACE, DIRECT_STDOUT, DIRECT };

/* Sorts path by what it names (following a symbolic link to its target): a new name or a regular
 * file is replaced through a temporary, "-", a character device or a FIFO is written in place, and
 * anything else is refused by name. *dest gets the name to replace (malloc'd: the path, or the
 * link's resolved target), *sb the existing file's status. */
static st_status classify(const char *path, enum kind *kind, char **dest, struct stat *sb,
                          st_error *err)
{
    *dest = NULL;
    if (!path || !path[0])
        return st_fail(err, ST_ERR_USAGE, "output: empty file name");
    if (!strcmp(path, "-")) {
        *kind = DIRECT_STDOUT;
        return ST_OK;
    }
    int link = lstat(path, sb) == 0 && S_ISLNK(sb->st_mode);
    if (stat(path, sb) != 0) {
        if (errno != ENOENT || link)
            return st_fail(err, ST_ERR_IO, "%s: cannot create (%s)", path,
                           link ? "a symbolic link to a missing file" : strerror(errno));
        *kind = NEW_FILE;
    } else if (S_ISREG(sb->st_mode)) {
        *kind = REPLACE;
    } else if (S_ISCHR(sb->st_mode) || S_ISFIFO(sb->st_mode)) {
        *kind = DIRECT;
    } else {
        return st_fail(err, ST_ERR_IO, "%s: is %s, not a file to write; refused", path,
                       S_ISDIR(sb->st_mode) ? "a folder" : S_ISBLK(sb->st_mode) ? "a block device"
                       : S_ISSOCK(sb->st_mode) ? "a socket" : "a special file");
    }
    /* a link's target is replaced, so the temporary goes beside the target; a device or FIFO is
     * opened by the name given (/dev/stdout's target may be no name at all: "pipe:[N]") */
    *dest = link && *kind == REPLACE ? realpath(path, NULL) : strdup(path);
    if (!*dest)
        return st_fail(err, ST_ERR_NOMEM, "%s: cannot resolve the output's name", path);
    return ST_OK;
}

/* Opens a device, FIFO or stdout for writing in place: no temporary, nothing to rename. */
static int open_direct(struct st_outfile *f, enum kind kind)
{
    if (kind == DIRECT_STDOUT) {
        fflush(stdout); /* whatever stdio holds for fd 1 goes first */
        return dup(STDOUT_FILENO);
    }
    return open(f->dest, O_WRONLY | O_NOCTTY | O_CLOEXEC);
}

/* Gives a replacement the mode (and, where allowed, the owner) of the file it replaces. The
 * owner first: chown(2) clears set-user-ID bits that the mode then restores. */
static void keep_mode(int fd, const struct stat *old)
{
    if ((old->st_uid != geteuid() || old->st_gid != getegid()) &&
        fchown(fd, old->st_uid, old->st_gid) != 0) {
        /* only root may give a file away: the new file is then the writer's own */
    }
    (void)fchmod(fd, old->st_mode & 07777);
}

st_status st_outfile_open(const char *path, st_outfile **out, st_error *err)
{
    *out = NULL;
    enum kind kind;
    char *dest;
    struct stat sb;
    if (classify(path, &kind, &dest, &sb, err) != ST_OK)
        return err->status;
    int direct = kind == DIRECT || kind == DIRECT_STDOUT;
    const char *slash = dest ? strrchr(dest, '/') : NULL;
    size_t dir = slash ? (size_t)(slash - dest) + 1 : 0;
    size_t size = dest ? dir + strlen(dest + dir) + 128 : 0; /* token, host, pid, counter */
    if (!direct && dir + 100 + (strlen(dest + dir) < TEMP_NAME_KEEP ? strlen(dest + dir)
                                                                   : TEMP_NAME_KEEP) >= PATH_MAX) {
        free(dest);
        return st_fail(err, ST_ERR_IO, "%.200s...: file name too long", path);
    }
    struct st_outfile *f = calloc(1, sizeof *f);
    if (f) {
        f->slot = -1;
        f->lock_fd = -1;
        f->direct = direct;
        f->dest = dest;
        dest = NULL;
        f->path = strdup(path);
        if (!direct) {
            f->slot = claim_slot();
            f->temp = malloc(size);
        }
    }
    free(dest);
    if (f && !direct && f->slot < 0) {
        release(f);
        return st_fail(err, ST_ERR_IO, "%s: more than %d outputs open at once", path, SLOTS);
    }
    if (!f || !f->path || (!direct && !f->temp)) {
        if (f)
            release(f);
        return st_fail(err, ST_ERR_NOMEM, "%s: cannot allocate an output file", path);
    }
    if (!direct)
        st_outfile_remove_stale(f->dest);
    int fd = direct ? open_direct(f, kind) : open_temporary(f, size);
    if (fd >= 0 && kind == REPLACE)
        keep_mode(fd, &sb);
    f->fd = fd;
    if (fd >= 0 && !(f->stream = open_stream(f))) {
        int e = errno;
        close(fd);
        if (!direct)
            unlink(f->temp);
        fd = -1;
        errno = e;
    }
    if (fd < 0) {
        int e = errno;
        const char *slash = direct ? NULL : strrchr(f->temp, '/');
        st_status s = direct ? st_fail(err, ST_ERR_IO, "%s: cannot open (%s)", path, strerror(e))
                             : st_fail(err, ST_ERR_IO, "%s: cannot create its temporary %s "
                                       "(%s)%s", path, slash ? slash + 1 : f->temp, strerror(e),
                                       kind == REPLACE && (e == EACCES || e == EROFS)
                                           ? " (a file is replaced through a new one beside it, "
                                             "so its folder must be writable too)" : "");
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

/* Writes of at least this many bytes go to the file at once (after what the stream holds), as
 * a stdio stream of a file with 4 KiB blocks would: their failure is seen by the caller, not
 * only at commit. */
#define DIRECT_WRITE_BYTES 4096

int st_outfile_write(st_outfile *f, const void *data, size_t n)
{
    errno = 0;
    if (n >= DIRECT_WRITE_BYTES) {
        if (fflush(f->stream) != 0 || write_cookie(f, data, n) != (ssize_t)n)
            return note_failure(f);
        return 0;
    }
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
        ssize_t w = pwrite(f->fd, p, n, (off_t)offset);
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
    if (e == 0 && !f->direct && fsync(f->fd) != 0)
        e = errno; /* a device or pipe has nothing to sync (EINVAL) */
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
    else if (!f->direct && rename(f->temp, f->dest) != 0)
        s = st_fail(err, ST_ERR_IO, "%s: cannot rename into place (%s)", f->path,
                    strerror(errno));
    if (s != ST_OK && !f->direct)
        unlink(f->temp);
    release(f);
    return s;
}

void st_outfile_abort(st_outfile *f)
{
    if (!f)
        return;
    fclose(f->stream);
    if (!f->direct) /* what went to a device or pipe cannot be taken back */
        unlink(f->temp);
    release(f);
}

st_status st_outfile_check(const char *path, st_error *err)
{
    enum kind kind;
    char *dest;
    struct stat sb;
    if (classify(path, &kind, &dest, &sb, err) != ST_OK)
        return err->status;
    free(dest);
    /* a device or FIFO is not opened now: a FIFO's open waits for its reader */
    if (kind == DIRECT && access(path, W_OK) != 0)
        return st_fail(err, ST_ERR_IO, "%s: cannot open (%s)", path, strerror(errno));
    if (kind == DIRECT || kind == DIRECT_STDOUT)
        return ST_OK;
    st_outfile *f;
    if (st_outfile_open(path, &f, err) != ST_OK)
        return err->status;
    st_outfile_abort(f);
    return ST_OK;
}

/* A name's identity for st_outfile_is_same: the file's device and inode when it exists, else its
 * folder's and its last component (*leaf; "" for an existing file). 0: neither can be found. */
static int identify(const char *path, struct stat *sb, const char **leaf)
{
    *leaf = "";
    if (stat(path, sb) == 0)
        return 1;
    const char *slash = strrchr(path, '/');
    char folder[PATH_MAX];
    snprintf(folder, sizeof folder, "%.*s", slash ? (int)(slash - path) + 1 : 1, slash ? path : ".");
    *leaf = slash ? slash + 1 : path;
    return stat(folder, sb) == 0;
}

int st_outfile_is_same(const char *a, const char *b)
{
    struct stat sa, sb;
    const char *la, *lb;
    if (!a || !b || !strcmp(a, "-") || !strcmp(b, "-") || !identify(a, &sa, &la) ||
        !identify(b, &sb, &lb))
        return 0;
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino && !strcmp(la, lb);
}

st_status st_outfile_check_apart(const st_outfile_role *files, int n, int nout, st_error *err)
{
    for (int i = 0; i < nout; i++)
        for (int j = i + 1; j < n; j++) {
            struct stat sb;
            if (!files[i].path || !files[j].path ||
                (stat(files[i].path, &sb) == 0 && !S_ISREG(sb.st_mode)) ||
                !st_outfile_is_same(files[i].path, files[j].path))
                continue;
            return st_fail(err, ST_ERR_USAGE, "%s: %s and %s are the same file; refused (an output "
                           "never replaces an input or another output)", files[i].path,
                           files[i].role, files[j].role);
        }
    return ST_OK;
}

/* Whether name is a temporary of host's (host_token), ".NAME.strata-tmp.HOST.PID.N". */
static int is_our_temporary(const char *name, const char *host)
{
    const char *tok = name[0] == '.' ? strstr(name + 1, TEMP_TOKEN) : NULL;
    while (tok && strstr(tok + 1, TEMP_TOKEN))
        tok = strstr(tok + 1, TEMP_TOKEN); /* the last token (NAME may hold one) */
    if (!tok || tok == name + 1)
        return 0;
    const char *p = tok + strlen(TEMP_TOKEN);
    size_t n = strlen(host);
    if (strncmp(p, host, n) || p[n] != '.')
        return 0;
    p += n + 1;
    for (int field = 0; field < 2; field++) { /* PID '.' N, digits only */
        if (*p < '0' || *p > '9')
            return 0;
        while (*p >= '0' && *p <= '9')
            p++;
        if (field == 0 && *p++ != '.')
            return 0;
    }
    return *p == '\0';
}

/* Removes the temporary `name` in folder dir if its writer is provably gone: a regular file of
 * this user whose lock can be taken (a lock lives as long as the writer's process, in whatever
 * pid namespace of this kernel it runs) and that still bears the name once locked. */
static void remove_if_dead(int dir, const char *name)
{
    struct stat sb;
    if (fstatat(dir, name, &sb, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISREG(sb.st_mode) ||
        sb.st_uid != geteuid())
        return;
    int fd = openat(dir, name, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0)
        return;
    if (flock(fd, LOCK_EX | LOCK_NB) == 0 && still_named(dir, name, fd))
        unlinkat(dir, name, 0);
    close(fd);
}

void st_outfile_remove_stale(const char *dest)
{
    const char *slash = strrchr(dest, '/');
    char folder[PATH_MAX];
    snprintf(folder, sizeof folder, "%.*s", slash ? (int)(slash - dest) + 1 : 1,
             slash ? dest : ".");
    DIR *d = opendir(folder);
    if (!d)
        return;
    char host[TEMP_HOST_KEEP + 1];
    host_token(host);
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        if (is_our_temporary(e->d_name, host))
            remove_if_dead(dirfd(d), e->d_name);
    closedir(d);
}
