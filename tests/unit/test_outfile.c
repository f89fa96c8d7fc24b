/* test_outfile.c — guards src/base/outfile.c (include/st_outfile.h): the temporary-then-rename writer
 * every strata output goes through.
 *
 * Each test works in a fresh folder under /tmp and checks the folder's listing afterwards: a
 * commit leaves exactly the destination, an abort or any failure leaves exactly what was there
 * before. Write failures are real ones, injected with RLIMIT_FSIZE (EFBIG once a file would grow
 * past the limit; SIGXFSZ ignored so the process survives), in the spirit of SQLite's fault
 * simulation.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "scratch.h"
#include "st_outfile.h"

#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static void put_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(text, f);
    assert_int_equal(fclose(f), 0);
}

/* The file's whole content (at most 255 bytes) as a string. */
static const char *content(const char *path)
{
    static char buf[256];
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    return buf;
}

static void assert_message_names(const st_error *err, const char *path)
{
    if (strncmp(err->msg, path, strlen(path)) != 0)
        fail_msg("message does not start with '%s': %s", path, err->msg);
}

/* ---- success ------------------------------------------------------------------------------- */

/* Before commit only the hidden, exclusive temporary exists; after it only the destination. */
static void outfile_commit_renames_temporary(void **state)
{
    (void)state;
    char path[512], name[256];
    snprintf(path, sizeof path, "%s", scratch_path("out.csv"));
    st_outfile *f = NULL;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_outfile_open(path, &f, &err), ST_OK);
    assert_string_equal(st_outfile_path(f), path);
    fprintf(st_outfile_stream(f), "a,b\n");
    assert_int_equal(st_outfile_write(f, "1,2\n", 4), 0);
    assert_int_equal(scratch_entries(name, sizeof name), 1);
    assert_true(strncmp(name, ".out.csv.strata-tmp.", 20) == 0);
    assert_int_equal(access(path, F_OK), -1);
    assert_int_equal(st_outfile_commit(f, &err), ST_OK);
    assert_string_equal(content(path), "a,b\n1,2\n");
    assert_int_equal(scratch_entries(name, sizeof name), 1);
    assert_string_equal(name, "out.csv");
}

/* Positioned writes land where asked, after what the stream wrote (OpenEXR's chunk table). */
static void outfile_write_at_overwrites_after_stream(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s", scratch_path("seek.bin"));
    st_outfile *f = NULL;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_outfile_open(path, &f, &err), ST_OK);
    fputs("xxxxxx", st_outfile_stream(f)); /* still buffered: write_at must flush it first */
    assert_int_equal(st_outfile_write_at(f, "ab", 2, 1), 0);
    assert_int_equal(st_outfile_write_at(f, "yz", 2, 6), 0);
    assert_int_equal(st_outfile_commit(f, &err), ST_OK);
    assert_string_equal(content(path), "xabxxxyz");
}

/* Two writers of one destination at once get distinct temporaries; the later commit wins. */
static void outfile_concurrent_writers_use_distinct_temporaries(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s", scratch_path("same.txt"));
    st_outfile *a = NULL, *b = NULL;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_outfile_open(path, &a, &err), ST_OK);
    assert_int_equal(st_outfile_open(path, &b, &err), ST_OK);
    assert_int_equal(scratch_entries(NULL, 0), 2);
    fputs("first", st_outfile_stream(a));
    fputs("second", st_outfile_stream(b));
    assert_int_equal(st_outfile_commit(a, &err), ST_OK);
    assert_int_equal(st_outfile_commit(b, &err), ST_OK);
    assert_string_equal(content(path), "second");
    assert_int_equal(scratch_entries(NULL, 0), 1);
}

/* ---- abort and an existing destination ------------------------------------------------------ */

static void outfile_abort_leaves_nothing(void **state)
{
    (void)state;
    st_outfile *f = NULL;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_outfile_open(scratch_path("gone.png"), &f, &err), ST_OK);
    fputs("partial", st_outfile_stream(f));
    st_outfile_abort(f);
    assert_int_equal(scratch_entries(NULL, 0), 0);
    st_outfile_abort(NULL); /* documented no-op */
}

/* An existing file keeps its content while a new one is written, after an abort, and is
 * replaced only by a commit. */
static void outfile_existing_destination_replaced_only_on_commit(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s", scratch_path("keep.txt"));
    put_file(path, "old");
    st_outfile *f = NULL;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_outfile_open(path, &f, &err), ST_OK);
    assert_int_equal(st_outfile_write(f, "new", 3), 0);
    assert_int_equal(fflush(st_outfile_stream(f)), 0);
    assert_string_equal(content(path), "old");
    st_outfile_abort(f);
    assert_string_equal(content(path), "old");
    assert_int_equal(scratch_entries(NULL, 0), 1);

    assert_int_equal(st_outfile_open(path, &f, &err), ST_OK);
    assert_int_equal(st_outfile_write(f, "new", 3), 0);
    assert_string_equal(content(path), "old");
    assert_int_equal(st_outfile_commit(f, &err), ST_OK);
    assert_string_equal(content(path), "new");
    assert_int_equal(scratch_entries(NULL, 0), 1);
}

/* ---- failures ------------------------------------------------------------------------------ */

/* A folder that does not exist, and a "folder" that is a file: ST_ERR_IO naming the path. */
static void outfile_missing_folder_fails_naming_path(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s", scratch_path("missing/out.exr"));
    st_outfile *f = (st_outfile *)1;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_outfile_open(path, &f, &err), ST_ERR_IO);
    assert_null(f);
    assert_message_names(&err, path);
    assert_non_null(strstr(err.msg, strerror(ENOENT)));
    assert_int_equal(scratch_entries(NULL, 0), 0);

    put_file(scratch_path("plain"), "x");
    snprintf(path, sizeof path, "%s", scratch_path("plain/out.exr"));
    st_error err2 = {ST_OK, ""};
    assert_int_equal(st_outfile_open(path, &f, &err2), ST_ERR_IO);
    assert_message_names(&err2, path);
    assert_non_null(strstr(err2.msg, strerror(ENOTDIR)));
    assert_int_equal(scratch_entries(NULL, 0), 1);
}

/* A folder without write permission. Root passes permission checks, so for root the folder is
 * /proc, which refuses to create files for anyone; then errno is not EACCES but some error. */
static void outfile_unwritable_folder_fails_naming_path(void **state)
{
    (void)state;
    char sub[512], path[600];
    snprintf(sub, sizeof sub, "%s", scratch_path("ro"));
    assert_int_equal(mkdir(sub, 0555), 0);
    int root = access(sub, W_OK) == 0;
    snprintf(path, sizeof path, "%s/out.png", root ? "/proc" : sub);
    st_outfile *f = NULL;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_outfile_open(path, &f, &err), ST_ERR_IO);
    assert_null(f);
    assert_message_names(&err, path);
    assert_non_null(strstr(err.msg, "cannot create its temporary .out.png.strata-tmp."));
    if (!root)
        assert_non_null(strstr(err.msg, strerror(EACCES)));
    assert_int_equal(rmdir(sub), 0); /* still empty */
}

/* The rename fails at commit (a folder took the new name meanwhile): the temporary goes, the
 * folder stays. */
static void outfile_failed_rename_removes_temporary(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s", scratch_path("taken"));
    st_outfile *f = NULL;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_outfile_open(path, &f, &err), ST_OK);
    assert_int_equal(mkdir(path, 0755), 0);
    fputs("data", st_outfile_stream(f));
    assert_int_equal(st_outfile_commit(f, &err), ST_ERR_IO);
    assert_message_names(&err, path);
    assert_non_null(strstr(err.msg, "rename"));
    assert_int_equal(scratch_entries(NULL, 0), 1);
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_true(S_ISDIR(st.st_mode));
}

/* Runs one write through fn with files limited to 16 bytes, then commits: the commit fails with
 * EFBIG's text, the existing destination is untouched and no temporary is left. */
static void fails_past_file_limit(int (*fn)(st_outfile *))
{
    char path[512];
    snprintf(path, sizeof path, "%s", scratch_path("big.bin"));
    put_file(path, "old");
    struct rlimit saved, small = {16, 16};
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &saved), 0);
    small.rlim_max = saved.rlim_max; /* keep the hard limit, so it can be restored */
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
    st_outfile *f = NULL;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_outfile_open(path, &f, &err), ST_OK);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &small), 0);
    int as_expected = fn(f); /* no asserts until the limit is lifted again */
    st_status s = st_outfile_commit(f, &err);
    setrlimit(RLIMIT_FSIZE, &saved);
    signal(SIGXFSZ, old_handler);
    assert_true(as_expected);
    assert_int_equal(s, ST_ERR_IO);
    assert_message_names(&err, path);
    assert_non_null(strstr(err.msg, "cannot write"));
    assert_string_equal(content(path), "old");
    assert_int_equal(scratch_entries(NULL, 0), 1);
}

static char block[4096];

/* Each returns whether the write behaved as documented: a refused write returns -1 and keeps
 * EFBIG for commit. */
static int write_block(st_outfile *f)
{
    return st_outfile_write(f, block, sizeof block) == -1 && st_outfile_error(f) == EFBIG;
}

static int write_block_at(st_outfile *f)
{
    return st_outfile_write_at(f, block, 8, 1000) == -1 && st_outfile_error(f) == EFBIG;
}

/* Small stream writes stay buffered and only fail when commit flushes them. */
static int print_block(st_outfile *f)
{
    for (int i = 0; i < 4; i++)
        fprintf(st_outfile_stream(f), "%s", "0123456789");
    return st_outfile_error(f) == 0;
}

static void outfile_write_failure_removes_temporary(void **state)
{
    (void)state;
    fails_past_file_limit(write_block);
}

static void outfile_write_at_failure_removes_temporary(void **state)
{
    (void)state;
    fails_past_file_limit(write_block_at);
}

static void outfile_flush_failure_removes_temporary(void **state)
{
    (void)state;
    fails_past_file_limit(print_block);
}

/* The signal handler's clean-up: every open temporary goes, the destinations stay untouched,
 * and a handle released afterwards (commit fails, abort) leaves nothing either. A committed
 * handle is no longer listed: removing again leaves its file. */
static void outfile_remove_temporaries_removes_every_open_one(void **state)
{
    (void)state;
    char a[512], b[512], c[512], name[256];
    snprintf(a, sizeof a, "%s", scratch_path("a.exr"));
    snprintf(b, sizeof b, "%s", scratch_path("b.png"));
    snprintf(c, sizeof c, "%s", scratch_path("c.txt"));
    put_file(b, "old");
    st_outfile *fa = NULL, *fb = NULL, *fc = NULL;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_outfile_open(c, &fc, &err), ST_OK);
    fputs("kept", st_outfile_stream(fc));
    assert_int_equal(st_outfile_commit(fc, &err), ST_OK);
    assert_int_equal(st_outfile_open(a, &fa, &err), ST_OK);
    assert_int_equal(st_outfile_open(b, &fb, &err), ST_OK);
    assert_int_equal(st_outfile_write(fa, "data", 4), 0);
    assert_int_equal(scratch_entries(name, sizeof name), 4); /* b, c and two temporaries */
    st_outfile_remove_temporaries();
    assert_int_equal(scratch_entries(name, sizeof name), 2);
    assert_string_equal(content(b), "old");
    assert_string_equal(content(c), "kept");
    assert_int_not_equal(st_outfile_commit(fa, &err), ST_OK); /* its temporary is gone */
    st_outfile_abort(fb);
    assert_int_equal(scratch_entries(name, sizeof name), 2);
    assert_int_equal(access(a, F_OK), -1);
}

/* st_outfile_check: a writable folder passes and is left as it was; a missing folder and a
 * destination that is a folder fail naming the path. */
static void outfile_check_finds_unwritable_destinations(void **state)
{
    (void)state;
    char ok[512], missing[512], dir[512], name[256];
    snprintf(ok, sizeof ok, "%s", scratch_path("fine.exr"));
    snprintf(missing, sizeof missing, "%s", scratch_path("no/such.exr"));
    snprintf(dir, sizeof dir, "%s", scratch_path("d.exr"));
    st_error err = {ST_OK, ""};
    assert_int_equal(st_outfile_check(ok, &err), ST_OK);
    assert_int_equal(scratch_entries(name, sizeof name), 0);
    assert_int_equal(st_outfile_check(missing, &err), ST_ERR_IO);
    assert_message_names(&err, missing);
    assert_int_equal(mkdir(dir, 0755), 0);
    err = (st_error){ST_OK, ""};
    assert_int_equal(st_outfile_check(dir, &err), ST_ERR_IO);
    assert_message_names(&err, dir);
    assert_non_null(strstr(err.msg, "is a folder"));
}

/* ---- what the destination is ---------------------------------------------------------------- */

/* Writes text to path through an st_outfile and commits; returns the status. */
static st_status write_text(const char *path, const char *text, st_error *err)
{
    st_outfile *f = NULL;
    if (st_outfile_open(path, &f, err) != ST_OK)
        return err->status;
    fputs(text, st_outfile_stream(f));
    return st_outfile_commit(f, err);
}

/* A folder is refused when the output is opened, by name, before anything is written. */
static void outfile_folder_refused_at_open(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s", scratch_path("d.exr"));
    assert_int_equal(mkdir(path, 0755), 0);
    st_outfile *f = NULL;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_outfile_open(path, &f, &err), ST_ERR_IO);
    assert_null(f);
    assert_message_names(&err, path);
    assert_non_null(strstr(err.msg, "is a folder"));
    assert_int_equal(scratch_entries(NULL, 0), 1);
}

/* A replaced file keeps its mode (the new one would otherwise get 0666 less the umask). */
static void outfile_replacement_keeps_mode(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s", scratch_path("m.csv"));
    put_file(path, "old");
    assert_int_equal(chmod(path, 0640), 0);
    st_error err = {ST_OK, ""};
    assert_int_equal(write_text(path, "new", &err), ST_OK);
    struct stat sb;
    assert_int_equal(stat(path, &sb), 0);
    assert_int_equal(sb.st_mode & 07777, 0640);
    assert_string_equal(content(path), "new");
}

/* A symbolic link stays a link: its target gets the new content. A link to nothing is refused. */
static void outfile_symlink_target_replaced(void **state)
{
    (void)state;
    char target[512], link[512], dangling[512];
    snprintf(target, sizeof target, "%s", scratch_path("target.csv"));
    snprintf(link, sizeof link, "%s", scratch_path("link.csv"));
    snprintf(dangling, sizeof dangling, "%s", scratch_path("dangling.csv"));
    put_file(target, "old");
    assert_int_equal(symlink("target.csv", link), 0);
    st_error err = {ST_OK, ""};
    assert_int_equal(write_text(link, "new", &err), ST_OK);
    struct stat sb;
    assert_int_equal(lstat(link, &sb), 0);
    assert_true(S_ISLNK(sb.st_mode));
    assert_string_equal(content(target), "new");
    assert_int_equal(symlink("nowhere.csv", dangling), 0);
    assert_int_equal(write_text(dangling, "new", &err), ST_ERR_IO);
    assert_message_names(&err, dangling);
    assert_int_equal(scratch_entries(NULL, 0), 3); /* target, link, dangling: no temporary */
}

/* A FIFO is written directly (a reader gets the bytes) and stays a FIFO; no temporary. */
static void outfile_fifo_written_directly(void **state)
{
    (void)state;
    char path[512], got[16] = {0};
    snprintf(path, sizeof path, "%s", scratch_path("pipe"));
    assert_int_equal(mkfifo(path, 0600), 0);
    int rd = open(path, O_RDONLY | O_NONBLOCK); /* a reader, so the writer's open returns */
    assert_true(rd >= 0);
    st_error err = {ST_OK, ""};
    assert_int_equal(st_outfile_check(path, &err), ST_OK);
    assert_int_equal(write_text(path, "through", &err), ST_OK);
    assert_int_equal(read(rd, got, sizeof got - 1), 7);
    close(rd);
    assert_string_equal(got, "through");
    struct stat sb;
    assert_int_equal(lstat(path, &sb), 0);
    assert_true(S_ISFIFO(sb.st_mode));
    assert_int_equal(scratch_entries(NULL, 0), 1);
}

/* /dev/null is written directly and stays a character device (replacing it needs root, which
 * the writer may well be). */
static void outfile_device_written_directly(void **state)
{
    (void)state;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_outfile_check("/dev/null", &err), ST_OK);
    assert_int_equal(write_text("/dev/null", "gone", &err), ST_OK);
    struct stat sb;
    assert_int_equal(lstat("/dev/null", &sb), 0);
    assert_true(S_ISCHR(sb.st_mode));
}

/* The longest legal name (NAME_MAX bytes less a little) still has a temporary short enough. */
static void outfile_long_name_works(void **state)
{
    (void)state;
    char name[256], path[512];
    memset(name, 'n', 244);
    name[244] = '\0';
    snprintf(path, sizeof path, "%s", scratch_path(name));
    st_error err = {ST_OK, ""};
    assert_int_equal(write_text(path, "long", &err), ST_OK);
    assert_string_equal(content(path), "long");
    assert_int_equal(scratch_entries(NULL, 0), 1);
}

/* This host's name as the temporaries carry it (see st_outfile.h). */
static const char *host_token(void)
{
    static char host[65];
    char raw[256] = "";
    assert_int_equal(gethostname(raw, sizeof raw - 1), 0);
    size_t i = 0;
    for (; raw[i] && i < 64; i++)
        host[i] = isalnum((unsigned char)raw[i]) || raw[i] == '-' ? raw[i] : '_';
    host[i] = '\0';
    return host;
}

/* Holds an exclusive flock on path in a child process (a writer that kill(2) cannot see, as one
 * in another pid namespace) until the returned pid is killed. */
static pid_t hold_lock(const char *path)
{
    int ready[2];
    assert_int_equal(pipe(ready), 0);
    pid_t child = fork();
    assert_true(child >= 0);
    if (child == 0) {
        int fd = open(path, O_RDONLY);
        if (fd < 0 || flock(fd, LOCK_EX) != 0)
            _exit(1);
        (void)!write(ready[1], "x", 1);
        pause();
        _exit(0);
    }
    char c;
    assert_int_equal(read(ready[0], &c, 1), 1);
    close(ready[0]);
    close(ready[1]);
    return child;
}

/* A dead writer's temporary (unlocked, this host's, strata's kind) goes on the next write into
 * the folder; a live one stays even when its pid is not one this process can see (a writer in
 * another pid namespace); so do another host's temporaries and files merely like ours. */
static void outfile_stale_temporaries_removed(void **state)
{
    (void)state;
    char dead[512], live[512], host[512], foreign[512], name[256];
    snprintf(name, sizeof name, ".x.exr.strata-tmp.%s.4000000.3", host_token());
    snprintf(dead, sizeof dead, "%s", scratch_path(name));
    snprintf(name, sizeof name, ".x.exr.strata-tmp.%s.4000001.3", host_token());
    snprintf(live, sizeof live, "%s", scratch_path(name));
    snprintf(host, sizeof host, "%s", scratch_path(".x.exr.strata-tmp.elsewhere-host.4000000.3"));
    snprintf(foreign, sizeof foreign, "%s", scratch_path(".thesis.tex.tmp.4000000.1"));
    put_file(dead, "partial");
    put_file(live, "partial");
    put_file(host, "partial");
    put_file(foreign, "a user's own");
    pid_t holder = hold_lock(live);
    st_error err = {ST_OK, ""};
    assert_int_equal(write_text(scratch_path("y.csv"), "new", &err), ST_OK);
    kill(holder, SIGKILL);
    waitpid(holder, NULL, 0);
    assert_int_equal(access(dead, F_OK), -1);
    assert_int_equal(access(live, F_OK), 0);
    assert_int_equal(access(host, F_OK), 0);
    assert_string_equal(content(foreign), "a user's own");
}

/* A second writer of the same destination never removes a first one's live temporary: both
 * commit. */
static void outfile_second_writer_keeps_first_ones_temporary(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s", scratch_path("b.csv"));
    st_outfile *first = NULL;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_outfile_open(path, &first, &err), ST_OK);
    fputs("first", st_outfile_stream(first));
    pid_t child = fork(); /* the second writer: another process, which sweeps the folder */
    assert_true(child >= 0);
    if (child == 0) {
        st_outfile *f = NULL;
        st_error e = {ST_OK, ""};
        int ok = st_outfile_open(path, &f, &e) == ST_OK;
        if (ok) {
            fputs("second", st_outfile_stream(f));
            st_outfile_abort(f);
        }
        _exit(ok ? 0 : 1);
    }
    int st;
    assert_int_equal(waitpid(child, &st, 0), child);
    assert_true(WIFEXITED(st) && WEXITSTATUS(st) == 0);
    assert_int_equal(st_outfile_commit(first, &err), ST_OK);
    assert_string_equal(content(path), "first");
}

/* One file by device and inode, through a hard link, a symbolic link and a spelling with "./";
 * a new name twice is one file too; "-" and distinct files are not. */
static void outfile_is_same_by_device_and_inode(void **state)
{
    (void)state;
    char a[512], hard[512], soft[512], dot[512], b[512], fresh[512];
    snprintf(a, sizeof a, "%s", scratch_path("a.exr"));
    snprintf(hard, sizeof hard, "%s", scratch_path("hard.exr"));
    snprintf(soft, sizeof soft, "%s", scratch_path("soft.exr"));
    snprintf(dot, sizeof dot, "%s", scratch_path("./a.exr"));
    snprintf(b, sizeof b, "%s", scratch_path("b.exr"));
    snprintf(fresh, sizeof fresh, "%s", scratch_path("new.png"));
    put_file(a, "a");
    put_file(b, "b");
    assert_int_equal(link(a, hard), 0);
    assert_int_equal(symlink("a.exr", soft), 0);
    assert_true(st_outfile_is_same(a, hard));
    assert_true(st_outfile_is_same(soft, a));
    assert_true(st_outfile_is_same(dot, a));
    assert_true(st_outfile_is_same(fresh, fresh));
    assert_false(st_outfile_is_same(a, b));
    assert_false(st_outfile_is_same(fresh, a));
    assert_false(st_outfile_is_same("-", "-"));
    st_outfile_role files[] = {{b, "-o"}, {NULL, "--spp-map"}, {hard, "part 1"}, {a, "part 2"}};
    st_error err = {ST_OK, ""};
    assert_int_equal(st_outfile_check_apart(files, 4, 2, &err), ST_OK);
    files[0].path = hard;
    assert_int_equal(st_outfile_check_apart(files, 4, 2, &err), ST_ERR_USAGE);
    assert_message_names(&err, hard);
    assert_non_null(strstr(err.msg, "-o and part 1 are the same file"));
    assert_string_equal(content(a), "a"); /* nothing written */
}

int main(void)
{
#define T(name) cmocka_unit_test_setup_teardown(name, scratch_make, scratch_remove)
    const struct CMUnitTest tests[] = {
        T(outfile_commit_renames_temporary),
        T(outfile_remove_temporaries_removes_every_open_one),
        T(outfile_check_finds_unwritable_destinations),
        T(outfile_write_at_overwrites_after_stream),
        T(outfile_concurrent_writers_use_distinct_temporaries),
        T(outfile_abort_leaves_nothing),
        T(outfile_existing_destination_replaced_only_on_commit),
        T(outfile_missing_folder_fails_naming_path),
        T(outfile_unwritable_folder_fails_naming_path),
        T(outfile_failed_rename_removes_temporary),
        T(outfile_write_failure_removes_temporary),
        T(outfile_write_at_failure_removes_temporary),
        T(outfile_flush_failure_removes_temporary),
        T(outfile_folder_refused_at_open),
        T(outfile_replacement_keeps_mode),
        T(outfile_symlink_target_replaced),
        T(outfile_fifo_written_directly),
        T(outfile_device_written_directly),
        T(outfile_long_name_works),
        T(outfile_stale_temporaries_removed),
        T(outfile_second_writer_keeps_first_ones_temporary),
        T(outfile_is_same_by_device_and_inode),
    };
#undef T
    return cmocka_run_group_tests_name("outfile", tests, NULL, NULL);
}
