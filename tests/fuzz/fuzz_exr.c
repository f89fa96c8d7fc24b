/* fuzz_exr.c — libFuzzer harness for the EXR reader that `strata merge` and
 * `strata diff` use (st_image_load_exr, src/image/image_exr.c, on OpenEXR's core C
 * library): any bytes as a file, loaded with their attributes, then taken as
 * a split render's raw film (st_film_from_image) as merge does. ASan and
 * UBSan watch; an error must carry a message. Built by `make fuzz`, run by
 * `make test-fuzz`. The input goes to a memory file (memfd_create(2)) read by its
 * /proc/self/fd name: nothing is written to any folder, and nothing is left behind
 * when the harness crashes. */
#define _GNU_SOURCE /* memfd_create */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <unistd.h>

#include "st_film.h"
#include "st_image.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static int fd = -1;
    static char path[64];
    if (fd < 0) {
        fd = memfd_create("fuzz-exr", MFD_CLOEXEC);
        snprintf(path, sizeof path, "/proc/self/fd/%d", fd);
    }
    if (fd < 0 || ftruncate(fd, 0) != 0 ||
        (size > 0 && pwrite(fd, data, size, 0) != (ssize_t)size))
        abort(); /* the harness's own failure, not the reader's */
    st_image img = {0};
    st_attr *attrs = NULL;
    int nattrs = 0;
    st_error err = {ST_OK, ""};
    st_status s = st_image_load_exr(path, &img, &attrs, &nattrs, &err);
    if (s != ST_OK && err.msg[0] == '\0')
        abort();
    if (s == ST_OK) {
        st_i64 *sums = NULL;
        st_error e2 = {ST_OK, ""};
        if (st_film_from_image(&img, path, "", &sums, &e2) != ST_OK && e2.msg[0] == '\0')
            abort();
        free(sums);
    }
    free(attrs);
    st_image_free(&img);
    return 0;
}
