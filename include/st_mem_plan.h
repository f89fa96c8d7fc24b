/* st_mem_plan.h — the memory a render will take, reckoned before anything is allocated.
 *
 * A render's wave and film buffers are sized by --wave and by the image (wave.h); a run that
 * cannot have them used to end in an OpenCL error after the scene was loaded, or in an abort
 * inside the OpenCL runtime when the process ran out of address space (ulimit -v). The plan adds
 * up the device buffers and what the host reads back, and compares them with the device's limits
 * (CL_DEVICE_MAX_MEM_ALLOC_SIZE for one buffer, CL_DEVICE_GLOBAL_MEM_SIZE for all) and with the
 * address space the process may still take (RLIMIT_AS; on a CPU device the buffers are host
 * memory too). Tests: test_hostile.sh (memory plan). */
#ifndef ST_MEM_PLAN_H
#define ST_MEM_PLAN_H

#include <stddef.h>

#include "st_device.h"
#include "st_error.h"

/* What a render of `pixels` pixels with waves of `items` work-items needs. */
typedef struct st_mem_plan {
    unsigned long long device_bytes;  /* every wave and film buffer */
    unsigned long long largest_bytes; /* the largest one of them */
    int largest_per_pixel;            /* 1: it grows with the image, 0: with the wave */
    unsigned long long host_bytes;    /* read back and converted on the host */
} st_mem_plan;

/* The address space the process may still take: RLIMIT_AS less what it maps now; ~0 when
 * unlimited. For loaders that size a decoded file before decoding it (environment maps). */
unsigned long long st_mem_plan_host_left(void);

/* Fills *plan for a render (adaptive: its per-pixel state too; ordered: the
 * ray order's buffers, where the render sorts its rays). */
void st_mem_plan_make(size_t items, size_t pixels, int adaptive, int ordered, st_mem_plan *plan);

/* ST_OK when the plan fits dev and the process; otherwise ST_ERR_USAGE with one line naming
 * the size, the limit and the option that reduces it (--width/--height, --wave). */
st_status st_mem_plan_check(const st_device *dev, size_t items, size_t pixels, int adaptive,
                            int ordered, st_error *err);

#endif
