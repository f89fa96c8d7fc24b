/* st_outfile.h — the one way strata writes a user's file: to a temporary, then rename(2).
 *
 * Every output (EXR, PNG, CSV, plots) goes through an st_outfile, so a failed or abandoned write
 * never leaves a partial file under the destination's name, nor a temporary beside it, and an
 * existing file of that name is replaced only when the new one is complete and on disk.
 *
 * What the destination is decides how it is written: a new name or a regular file through a
 * temporary and rename (a replaced file keeps its mode, and its owner where the writer may give
 * it); a symbolic link by replacing its target, never the link; a character device (/dev/null,
 * /dev/stdout on a terminal), a FIFO or "-" (stdout) directly, streamed, with no temporary (what
 * was written to them cannot be taken back); anything else (a folder, a block device, a socket, a
 * link to nothing) is refused by name. A non-regular file is never replaced.
 *
 *   st_outfile *out;
 *   if (st_outfile_open(path, &out, err) != ST_OK) return err->status;
 *   fprintf(st_outfile_stream(out), ...);            (or st_outfile_write / st_outfile_write_at)
 *   return st_outfile_commit(out, err);              (or st_outfile_abort(out) to give up)
 *
 * The temporary is "<folder>/.<name>.strata-tmp.<host>.<pid>.<n>" (<name> cut to NAME_MAX - 99
 * bytes, so the longest legal name has one; <host> is gethostname(2) with anything but letters,
 * digits and '-' written '_'), created with O_CREAT|O_EXCL (mode 0666 less the umask, as fopen) in
 * the destination's own folder, so the final rename(2) never crosses a file system and two writers
 * never share a temporary. Its writer holds an exclusive flock(2) on it until it is renamed or
 * removed. Commit flushes, fsyncs, closes and renames; whatever fails on the way removes the
 * temporary.
 *
 * Errors: ST_ERR_IO with one line starting with the destination path ("out.png: cannot create
 * (No such file or directory)"), ST_ERR_NOMEM when the handle cannot be allocated. Nothing here
 * prints or exits. A handle is used by one thread at a time, except st_outfile_write_at, which
 * (like pwrite(2)) may be called concurrently on disjoint ranges.
 */
#ifndef ST_OUTFILE_H
#define ST_OUTFILE_H

#include "st_error.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

typedef struct st_outfile st_outfile; /* opaque: the temporary's name, fd, stream, first error */

/* Creates the temporary for destination `path` and returns its handle in *out (NULL on failure,
 * when no file is left). The destination is not touched until st_outfile_commit. Release the
 * handle with exactly one of st_outfile_commit or st_outfile_abort. */
st_status st_outfile_open(const char *path, st_outfile **out, st_error *err);

/* The temporary as a stdio stream, valid until commit or abort. Write errors on it are noticed
 * by commit (ferror). */
FILE *st_outfile_stream(st_outfile *f);

/* The destination path given to st_outfile_open (borrowed, valid until commit or abort). */
const char *st_outfile_path(const st_outfile *f);

/* Appends n bytes through the stream. Returns 0, or -1 with errno set; the first failure's errno
 * is kept and reported by commit, so callbacks (stb, cairo) need not keep their own. */
int st_outfile_write(st_outfile *f, const void *data, size_t n);

/* Writes n bytes at byte offset `offset` with pwrite(2), for writers that seek (OpenEXR writes its
 * chunk table last, before the pixels it indexes). Flushes the stream first, so earlier stream
 * writes land before it. Returns 0, or -1 with errno set (kept as for st_outfile_write). */
int st_outfile_write_at(st_outfile *f, const void *data, size_t n, uint64_t offset);

/* The errno of the first failed st_outfile_write or st_outfile_write_at, 0 if none. */
int st_outfile_error(const st_outfile *f);

/* Finishes the file: fflush, fsync, close, then rename over the destination. On any failure, or
 * when a write failed earlier, the temporary is removed, the destination keeps what it held, and
 * err names the path and the reason. Always releases f. */
st_status st_outfile_commit(st_outfile *f, st_error *err);

/* Gives up: closes and removes the temporary; the destination is untouched. Releases f. NULL:
 * does nothing. */
void st_outfile_abort(st_outfile *f);

/* Checks, before long work, that `path` could be written: refuses a folder and creates and removes
 * a temporary beside it (so a missing or read-only folder is found now, not after a render); a
 * device or FIFO is checked with access(2), not opened (a FIFO's open waits for a reader). The
 * same errors as st_outfile_open, or ST_ERR_IO "out.exr: is a folder, not a file to write". */
st_status st_outfile_check(const char *path, st_error *err);

/* One name of a command's files and what it is to the command ("-o", "--env", "part 2"). */
typedef struct st_outfile_role {
    const char *path; /* NULL: not given, skipped */
    const char *role;
} st_outfile_role;

/* Whether a and b name one file: the same device and inode (through symbolic links and hard
 * links, as cp(1) tells "are the same file"), or, for a name not made yet, the same last
 * component in the same folder (by device and inode). "-" (a stream) is no file. */
int st_outfile_is_same(const char *a, const char *b);

/* Refuses a command whose output would replace one of its inputs or another of its outputs:
 * files[0..nout) are outputs, files[nout..n) inputs. ST_ERR_USAGE "p0.exr: -o and part 1 are the
 * same file; refused (an output never replaces an input or another output)". An output that is a
 * device or a FIFO (/dev/null, /dev/stdout) may be named twice: it replaces nothing. */
st_status st_outfile_check_apart(const st_outfile_role *files, int n, int nout, st_error *err);

/* Unlinks every temporary that an open st_outfile of this process holds. Async-signal-safe: for a
 * SIGINT/SIGTERM handler, which then ends the process (the handles stay allocated). At most 64
 * outputs are open at once (st_outfile_open fails beyond that), each name below PATH_MAX. */
void st_outfile_remove_temporaries(void);

/* Removes the temporaries in dest's folder that a writer no longer running left behind (killed by
 * SIGKILL, or by a crash): only strata's own kind (".NAME.strata-tmp.HOST.PID.N"), only of this
 * host, only regular files of this user, and only those whose lock can be taken (the kernel drops
 * a lock when its process ends, in any pid namespace; a pid is no proof: a writer in a container
 * has one this process cannot see). Another host's temporaries in a shared folder are never
 * touched, nor files merely named like them. Called by st_outfile_open before it creates a
 * temporary there. */
void st_outfile_remove_stale(const char *dest);

#endif
