/* mem_plan.c — the memory a render will take, checked before allocation (st_mem_plan.h). */
#include "st_mem_plan.h"

#include <stdio.h>
#include <sys/resource.h>
#include <unistd.h>

#include "wave.h"

/* Floats per pixel that the host holds after the render: the resolved image read back and
 * its converted copy (RGB for the PNG, or the EXR's channels). */
#define HOST_FLOATS_PER_PIXEL 8

void st_mem_plan_make(size_t items, size_t pixels, int adaptive, int ordered, st_mem_plan *plan)
{
    st_wave w = {.items = items, .pixels = pixels, .adaptive = adaptive, .ordered = ordered};
    *plan = (st_mem_plan){0};
    for (int b = 0; b < ST_WAVE_BUFFER_COUNT; b++) {
        unsigned long long bytes = st_wave_bytes(&w, b);
        plan->device_bytes += bytes;
        if (bytes > plan->largest_bytes) {
            plan->largest_bytes = bytes;
            plan->largest_per_pixel = st_wave_count(&w, b) != items;
        }
    }
    /* the film's sums come back too (st_render's sums, for the EXR's exact merge) */
    w.items = 0;
    plan->host_bytes = st_wave_bytes(&w, ST_WAVE_film) +
                       (unsigned long long)pixels * HOST_FLOATS_PER_PIXEL * sizeof(float);
}

/* The address space the process may still take: RLIMIT_AS less what it maps now
 * (/proc/self/statm's first field, in pages); ~0 when unlimited or unknown. */
unsigned long long st_mem_plan_host_left(void)
{
    struct rlimit rl;
    if (getrlimit(RLIMIT_AS, &rl) != 0 || rl.rlim_cur == RLIM_INFINITY)
        return ~0ull;
    unsigned long long pages = 0;
    FILE *f = fopen("/proc/self/statm", "r");
    if (f) {
        if (fscanf(f, "%llu", &pages) != 1)
            pages = 0;
        fclose(f);
    }
    unsigned long long used = pages * (unsigned long long)sysconf(_SC_PAGESIZE);
    return used < rl.rlim_cur ? rl.rlim_cur - used : 0;
}

#define MIB(x) ((double)(x) / (1 << 20))

st_status st_mem_plan_check(const st_device *dev, size_t items, size_t pixels, int adaptive,
                            int ordered, st_error *err)
{
    st_mem_plan plan;
    st_mem_plan_make(items, pixels, adaptive, ordered, &plan);
    const char *reduce = plan.largest_per_pixel ? "--width and --height"
                                                : "--wave";
    unsigned long long max_alloc = st_device_max_alloc(dev);
    if (max_alloc && plan.largest_bytes > max_alloc)
        return st_fail(err, ST_ERR_USAGE, "the render needs a buffer of %.0f MiB (%s), more than "
                       "the device allows in one (CL_DEVICE_MAX_MEM_ALLOC_SIZE, %.0f MiB): reduce %s",
                       MIB(plan.largest_bytes), plan.largest_per_pixel ? "the film" : "the wave",
                       MIB(max_alloc), reduce);
    const st_device_info *info = st_device_get_info(dev);
    if (info->global_mem && plan.device_bytes > info->global_mem)
        return st_fail(err, ST_ERR_USAGE, "the render needs %.0f MiB of device memory, more than "
                       "the device's %.0f MiB (CL_DEVICE_GLOBAL_MEM_SIZE): reduce %s",
                       MIB(plan.device_bytes), MIB(info->global_mem), reduce);
    /* on a CPU device the buffers are the process's own memory, and the
     * device's memory is the machine's: the host's copies take from it too */
    unsigned long long need = plan.host_bytes + (info->is_cpu ? plan.device_bytes : 0);
    if (info->is_cpu && info->global_mem && need > info->global_mem)
        return st_fail(err, ST_ERR_USAGE, "the render needs about %.0f MiB of memory, more than "
                       "the machine's %.0f MiB (the CPU device's CL_DEVICE_GLOBAL_MEM_SIZE): "
                       "reduce %s", MIB(need), MIB(info->global_mem), reduce);
    unsigned long long left = st_mem_plan_host_left();
    if (need > left)
        return st_fail(err, ST_ERR_USAGE, "the render needs about %.0f MiB of memory, more than "
                       "the %.0f MiB the process may still take (ulimit -v): reduce %s",
                       MIB(need), MIB(left), reduce);
    return ST_OK;
}
