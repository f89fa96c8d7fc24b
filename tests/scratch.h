/* scratch.h — a fresh folder under /tmp for each test (cmocka setup and teardown) and a look at
 * what it holds, for the tests of code that writes files (test_outfile.c, test_plot.c). Include
 * after cmocka.h. Listings count hidden entries: st_outfile's temporaries start with a dot. */
#ifndef ST_TEST_SCRATCH_H
#define ST_TEST_SCRATCH_H

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char scratch_dir[64];

static int scratch_make(void **state)
{
    (void)state;
    snprintf(scratch_dir, sizeof scratch_dir, "/tmp/st_test.XXXXXX");
    return mkdtemp(scratch_dir) ? 0 : -1;
}

/* Removes the folder, the files a test left in it and empty subfolders (made writable first, in
 * case a test took the permission away). */
static int scratch_remove(void **state)
{
    (void)state;
    chmod(scratch_dir, 0755);
    DIR *d = opendir(scratch_dir);
    struct dirent *e;
    char path[512];
    while (d && (e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
            snprintf(path, sizeof path, "%s/%s", scratch_dir, e->d_name);
            if (remove(path) != 0)
                rmdir(path);
        }
    if (d)
        closedir(d);
    return rmdir(scratch_dir);
}

/* "<folder>/name" in a static buffer, valid until the next call. */
static const char *scratch_path(const char *name)
{
    static char path[512];
    snprintf(path, sizeof path, "%s/%s", scratch_dir, name);
    return path;
}

/* Number of entries in the folder besides . and ..; the first one's name goes to first when it
 * is not NULL. */
static int scratch_entries(char *first, size_t size)
{
    DIR *d = opendir(scratch_dir);
    assert_non_null(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
            if (n++ == 0 && first)
                snprintf(first, size, "%s", e->d_name);
        }
    closedir(d);
    return n;
}

#endif
