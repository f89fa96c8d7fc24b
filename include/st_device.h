/* st_device.h — the OpenCL layer: platform and device choice, the program
 * built from the kernels embedded in the binary, buffers and launches.
 *
 * Only this module calls clRelease*. Every OpenCL failure becomes a one-line
 * st_error naming the call and the error code (CL_OUT_OF_RESOURCES, ...).
 * A failed program build keeps the compiler log (st_device_build_log). */
#ifndef ST_DEVICE_H
#define ST_DEVICE_H

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>
#ifndef CL_PLATFORM_NOT_FOUND_KHR
#define CL_PLATFORM_NOT_FOUND_KHR -1001 /* cl_khr_icd: the ICD loader found no platform */
#endif
#include <stddef.h>

#include "st_error.h"

typedef struct st_device_info {
    unsigned platform, device; /* indices for --device P:D */
    char platform_name[128];
    char name[128];
    char version[96];   /* CL_DEVICE_VERSION */
    char c_version[96]; /* CL_DEVICE_OPENCL_C_VERSION */
    char driver_version[96]; /* CL_DRIVER_VERSION */
    int is_gpu, is_cpu;
    int has_int64_atomics; /* cl_khr_int64_base_atomics */
    unsigned compute_units;
    unsigned long long global_mem;
    unsigned long long local_mem; /* CL_DEVICE_LOCAL_MEM_SIZE: one work-group's __local bytes */
    unsigned float_width; /* CL_DEVICE_PREFERRED_VECTOR_WIDTH_FLOAT */
    unsigned lanes;       /* the kernels' lane width ST_W (kernels/shared/lanes.h): 1, 4, 8 or 16 */
    int compiles_at_launch; /* PoCL: each kernel is compiled at its first launch (per
                               work-group size and grid size class), not in the build */
} st_device_info;

typedef struct st_device st_device;

/* Every device of every platform; platforms without devices are skipped.
 * *out is malloc'ed (caller frees). No platform: ST_ERR_DEVICE whose message
 * names `make deps`. */
st_status st_device_list(st_device_info **out, unsigned *count, st_error *err);

/* spec: NULL or "cpu" (the first CPU device, i.e. PoCL), "gpu" (the first
 * GPU), or "P:D" (platform P, device D of `strata devices`). Creates a context
 * and an in-order queue. The device must offer cl_khr_int64_base_atomics.
 * Errors about the spec itself open with "device SPEC: " (the CLI writes its
 * flag there). */
st_status st_device_create(const char *spec, st_device **out, st_error *err);
void st_device_destroy(st_device *dev); /* NULL: does nothing */
const st_device_info *st_device_get_info(const st_device *dev);
/* CL_DEVICE_MAX_MEM_ALLOC_SIZE: the most bytes of one buffer (0 when unknown). */
unsigned long long st_device_max_alloc(const st_device *dev);

/* Limits the device to n compute units (on a CPU: n threads) by running on an OpenCL sub-device
 * (clCreateSubDevices, CL_DEVICE_PARTITION_BY_COUNTS {n}); call before st_device_build. n equal
 * to the device's compute units changes nothing. Errors name the field "threads": n above the
 * compute units is ST_ERR_USAGE; a device that cannot be partitioned (most GPU drivers) is
 * ST_ERR_DEVICE. Images do not depend on it: the film's sums are order-free integers. */
st_status st_device_limit_compute_units(st_device *dev, unsigned n, st_error *err);

/* The lane width the kernels are built for unless asked otherwise (ST_W,
 * kernels/shared/lanes.h): on a CPU device its preferred float vector width
 * rounded down to 4, 8 or 16 (PoCL reports the ISA's: 8 for AVX2, 16 for
 * AVX-512), so that a work-item's lanes fill a vector register; elsewhere
 * 1, a GPU's work-items being its lanes already. */
unsigned st_device_default_lanes(const st_device_info *info);
/* Builds the kernels for n lanes instead (1, 4, 8 or 16; --lanes): call
 * before st_device_build. Errors name the field "lanes" (ST_ERR_USAGE). */
st_status st_device_set_lanes(st_device *dev, unsigned n, st_error *err);
/* Checks a work-group size before any launch: at most the device's CL_DEVICE_MAX_WORK_GROUP_SIZE
 * and, on a CPU device, at most what one thread's stack holds. A CPU runtime (PoCL) runs a
 * group's work-items in loops on one worker thread, its private variables (a traversal stack)
 * side by side on that thread's stack, whose size is RLIMIT_STACK (glibc's default for new
 * threads; 2 MiB when unlimited): trace_shadow_rays needs 2 to 2.3 KiB a work-item, so 4096
 * overflowed an 8 MiB stack. ST_ERR_USAGE naming the field "local size" and the limit. */
st_status st_device_check_local_size(const st_device *dev, size_t local, st_error *err);

/* Builds the program from the embedded kernels, or from the .cl files in
 * $STRATA_KERNEL_DIR when set (for kernel development: a folder laid out as
 * kernels/, its subfolders on the include path). Idempotent; the first
 * call's wall time is stored in *seconds (may be NULL). */
st_status st_device_build(st_device *dev, double *seconds, st_error *err);
/* The compiler log of the last build (empty string if none). */
const char *st_device_build_log(const st_device *dev);
/* A kernel of the built program, created once and cached by name. */
st_status st_device_kernel(st_device *dev, const char *name, cl_kernel *out, st_error *err);

/* Sets the kernel's arguments from n (size_t size, const void *value) pairs;
 * a cl_mem argument is passed as (sizeof(cl_mem), &mem). */
st_status st_device_set_args(cl_kernel k, st_error *err, unsigned n, ...);
/* Sets argument `index` of k. */
st_status st_device_set_arg(cl_kernel k, unsigned index, size_t size, const void *value,
                            st_error *err);
/* Enqueues k over `items` work-items (rounded up to the work-group size
 * `local`, 0: the driver's choice; kernels check their own bounds), in rows
 * of at most 2^15 where there are more (kernels index them by ST_ITEM). */
st_status st_device_launch(st_device *dev, cl_kernel k, size_t items, size_t local, st_error *err);
st_status st_device_finish(st_device *dev, st_error *err);

/* Launch timing by the device's own clock (its profiling events): the
 * launches that follow st_device_time_launches(dev, tag) are counted under
 * tag (0 .. ST_DEVICE_TIME_TAGS - 1) until it is called again; -1 stops
 * timing. Nothing waits: a timed launch runs as an untimed one (but for one
 * wait per thousand timed launches, when the device reads their times).
 * st_device_timed_seconds waits for the launches timed so far and adds each
 * tag's time on the device (its commands' start to end) to seconds[tag]
 * (tags below `tags`; others are dropped), then starts the sums afresh. An
 * in-order queue runs one command at a time, so the sums never exceed the
 * wall time that holds them. */
#define ST_DEVICE_TIME_TAGS 32
void st_device_time_launches(st_device *dev, int tag);
st_status st_device_timed_seconds(st_device *dev, double *seconds, unsigned tags, st_error *err);

st_status st_device_buffer_create(st_device *dev, size_t bytes, const void *init, cl_mem *out,
                                  st_error *err);
void st_device_buffer_destroy(st_device *dev, cl_mem mem); /* NULL: does nothing */
st_status st_device_buffer_read(st_device *dev, cl_mem mem, size_t bytes, void *dst, st_error *err);
st_status st_device_buffer_write(st_device *dev, cl_mem mem, size_t bytes, const void *src,
                                 st_error *err);
st_status st_device_buffer_zero(st_device *dev, cl_mem mem, size_t bytes, st_error *err);

/* "CL_OUT_OF_RESOURCES" for -5, ... */
const char *st_device_error_name(cl_int code);

#endif
