/* device.c — OpenCL platforms, devices, the program and its kernels (see
 * st_device.h). Sizes are queried before buffers are filled; extensions are
 * matched as whole tokens. */
#include "st_device.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "st_embedded.h"

#define MAX_KERNELS 32

/* Every queue keeps the device's own start and end times of its commands, so
 * that a launch can be timed without a wait after it (st_device_time_launches):
 * a host clock around a launch and its wait counts the wait too, and the
 * launches' sum then exceeded the whole render's time on small renders. An
 * event is asked for only where a launch is timed. */
#define QUEUE_PROPERTIES CL_QUEUE_PROFILING_ENABLE
/* Timed launches whose events are kept before their times are read: a full
 * list is read at the launch that would overflow it (a wait there, once per
 * this many launches; a render of a few hundred launches reads them at its
 * end alone). */
#define TIMED_EVENTS 1024u

struct st_device {
    st_device_info info;
    cl_platform_id platform;
    cl_device_id id;
    cl_device_id sub; /* the sub-device of st_device_limit_compute_units, or NULL */
    cl_context context;
    cl_command_queue queue;
    cl_program program;
    char *log;
    struct { char name[64]; cl_kernel k; } kernels[MAX_KERNELS];
    unsigned kernel_count;
    /* launch timing (st_device_time_launches): the tag of the launches to
     * come (-1: untimed), the events of those not yet read, and the seconds
     * of those read, by tag */
    int time_tag;
    struct { cl_event ev; int tag; } timed[TIMED_EVENTS];
    unsigned timed_count;
    double tag_seconds[ST_DEVICE_TIME_TAGS];
    /* Oclgrind's released buffers, kept until the device goes
     * (st_device_buffer_destroy) */
    cl_mem *kept;
    size_t kept_count, kept_cap;
};

const char *st_device_error_name(cl_int code)
{
#define E(c) case c: return #c;
    switch (code) {
    E(CL_SUCCESS) E(CL_DEVICE_NOT_FOUND) E(CL_DEVICE_NOT_AVAILABLE)
    E(CL_COMPILER_NOT_AVAILABLE) E(CL_MEM_OBJECT_ALLOCATION_FAILURE)
    E(CL_OUT_OF_RESOURCES) E(CL_OUT_OF_HOST_MEMORY) E(CL_BUILD_PROGRAM_FAILURE)
    E(CL_INVALID_VALUE) E(CL_INVALID_PLATFORM) E(CL_INVALID_DEVICE) E(CL_INVALID_CONTEXT)
    E(CL_INVALID_COMMAND_QUEUE) E(CL_INVALID_MEM_OBJECT) E(CL_INVALID_BINARY)
    E(CL_INVALID_BUILD_OPTIONS) E(CL_INVALID_PROGRAM) E(CL_INVALID_PROGRAM_EXECUTABLE)
    E(CL_INVALID_KERNEL_NAME) E(CL_INVALID_KERNEL) E(CL_INVALID_ARG_INDEX)
    E(CL_INVALID_ARG_VALUE) E(CL_INVALID_ARG_SIZE) E(CL_INVALID_KERNEL_ARGS)
    E(CL_INVALID_WORK_DIMENSION) E(CL_INVALID_WORK_GROUP_SIZE) E(CL_INVALID_WORK_ITEM_SIZE)
    E(CL_INVALID_GLOBAL_OFFSET) E(CL_INVALID_EVENT_WAIT_LIST) E(CL_INVALID_OPERATION)
    E(CL_INVALID_BUFFER_SIZE) E(CL_INVALID_GLOBAL_WORK_SIZE) E(CL_PLATFORM_NOT_FOUND_KHR)
    default: return "CL_UNKNOWN_ERROR";
    }
#undef E
}

static st_status cl_fail(st_error *err, const char *call, cl_int code)
{
    return st_fail(err, ST_ERR_DEVICE, "%s failed: %s (%d)", call, st_device_error_name(code),
                   (int)code);
}

static int has_token(const char *list, const char *token)
{
    size_t n = strlen(token);
    for (const char *s = list; (s = strstr(s, token)) != NULL; s += n) {
        int starts = s == list || s[-1] == ' ';
        int ends = s[n] == '\0' || s[n] == ' ';
        if (starts && ends)
            return 1;
    }
    return 0;
}

static void device_string(cl_device_id d, cl_device_info what, char *buf, size_t cap)
{
    size_t n = 0;
    buf[0] = '\0';
    if (clGetDeviceInfo(d, what, cap, buf, &n) != CL_SUCCESS)
        buf[0] = '\0';
    buf[cap - 1] = '\0';
}

static void fill_info(cl_platform_id p, cl_device_id d, unsigned pi, unsigned di,
                      st_device_info *info)
{
    memset(info, 0, sizeof *info);
    info->platform = pi;
    info->device = di;
    clGetPlatformInfo(p, CL_PLATFORM_NAME, sizeof info->platform_name, info->platform_name, NULL);
    device_string(d, CL_DEVICE_NAME, info->name, sizeof info->name);
    device_string(d, CL_DEVICE_VERSION, info->version, sizeof info->version);
    device_string(d, CL_DEVICE_OPENCL_C_VERSION, info->c_version, sizeof info->c_version);
    device_string(d, CL_DRIVER_VERSION, info->driver_version, sizeof info->driver_version);
    cl_device_type type = 0;
    clGetDeviceInfo(d, CL_DEVICE_TYPE, sizeof type, &type, NULL);
    info->is_gpu = (type & CL_DEVICE_TYPE_GPU) != 0;
    info->is_cpu = (type & CL_DEVICE_TYPE_CPU) != 0;
    cl_uint cu = 0;
    clGetDeviceInfo(d, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof cu, &cu, NULL);
    info->compute_units = cu;
    cl_ulong mem = 0;
    clGetDeviceInfo(d, CL_DEVICE_GLOBAL_MEM_SIZE, sizeof mem, &mem, NULL);
    info->global_mem = mem;
    mem = 0;
    clGetDeviceInfo(d, CL_DEVICE_LOCAL_MEM_SIZE, sizeof mem, &mem, NULL);
    info->local_mem = mem;
    cl_uint width = 0;
    clGetDeviceInfo(d, CL_DEVICE_PREFERRED_VECTOR_WIDTH_FLOAT, sizeof width, &width, NULL);
    info->float_width = width;
    info->lanes = st_device_default_lanes(info);
    info->compiles_at_launch = strstr(info->platform_name, "Portable Computing Language") != NULL;
    size_t n = 0;
    if (clGetDeviceInfo(d, CL_DEVICE_EXTENSIONS, 0, NULL, &n) == CL_SUCCESS && n > 0) {
        char *ext = malloc(n + 1);
        if (ext && clGetDeviceInfo(d, CL_DEVICE_EXTENSIONS, n, ext, NULL) == CL_SUCCESS) {
            ext[n] = '\0';
            info->has_int64_atomics = has_token(ext, "cl_khr_int64_base_atomics");
        }
        free(ext);
    }
}

/* PoCL's name for its platform (CL_PLATFORM_NAME). */
#define POCL_NAME "Portable Computing Language"

/* The smallest file-size limit (ulimit -f) under which PoCL can write its kernel cache: one
 * compiled program of strata's is some megabytes. */
#define POCL_CACHE_MIN_FILE ((rlim_t)64 << 20)

/* Why PoCL could not use its kernel cache, in *why, or 0 when nothing is seen wrong. PoCL keeps
 * every build there ($POCL_CACHE_DIR, else $XDG_CACHE_HOME/pocl/kcache, else
 * ~/.cache/pocl/kcache) and, where it cannot write there, fails to build or even to offer its
 * device, with no word of why. */
static int pocl_cache_problem(char *why, size_t size)
{
    struct rlimit rl;
    if (getrlimit(RLIMIT_FSIZE, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
        rl.rlim_cur < POCL_CACHE_MIN_FILE) {
        snprintf(why, size, "the file-size limit (ulimit -f) of %llu bytes is too small for "
                 "PoCL's kernel cache", (unsigned long long)rl.rlim_cur);
        return 1;
    }
    const char *own = getenv("POCL_CACHE_DIR"), *xdg = getenv("XDG_CACHE_HOME");
    const char *home = getenv("HOME");
    char path[1024];
    if (own && *own)
        snprintf(path, sizeof path, "%s", own);
    else if (xdg && *xdg)
        snprintf(path, sizeof path, "%s/pocl/kcache", xdg);
    else if (home && *home)
        snprintf(path, sizeof path, "%s/.cache/pocl/kcache", home);
    else
        return 0;
    const char *var = own && *own ? " (POCL_CACHE_DIR)" : "";
    /* the folder, or the nearest of its parents that exists, must be a folder this user may
     * write in */
    char at[sizeof path];
    snprintf(at, sizeof at, "%s", path);
    struct stat sb;
    while (stat(at, &sb) != 0) {
        char *slash = strrchr(at, '/');
        if ((errno != ENOENT && errno != ENOTDIR) || !slash || slash == at)
            return 0; /* nothing more to say than PoCL's own failure */
        *slash = '\0';
    }
    if (!S_ISDIR(sb.st_mode))
        snprintf(why, size, "PoCL's kernel cache %.400s%s cannot be made: %.400s is not a folder", path,
                 var, at);
    else if (access(at, W_OK | X_OK) != 0)
        snprintf(why, size, "PoCL's kernel cache %.400s%s cannot be written: %.400s: %s", path, var, at,
                 strerror(errno));
    else
        return 0;
    return 1;
}

/* Calls visit(platform, device, info) for every device; stops when it
 * returns nonzero. Fails when there is none at all. */
static st_status each_device(int (*visit)(cl_platform_id, cl_device_id, const st_device_info *,
                                          void *),
                             void *ctx, st_error *err)
{
    cl_uint np = 0;
    cl_int rc = clGetPlatformIDs(0, NULL, &np);
    if (rc == CL_PLATFORM_NOT_FOUND_KHR || np == 0)
        return st_fail(err, ST_ERR_DEVICE,
                       "no OpenCL platform found: run `make deps` to install PoCL "
                       "(pocl-opencl-icd) or install a GPU driver's OpenCL ICD");
    if (rc != CL_SUCCESS)
        return cl_fail(err, "clGetPlatformIDs", rc);
    cl_platform_id *ps = calloc(np, sizeof *ps);
    if (!ps)
        return st_fail(err, ST_ERR_NOMEM, "out of memory listing platforms");
    clGetPlatformIDs(np, ps, NULL);
    int stop = 0, pocl_empty = 0;
    unsigned devices = 0;
    for (cl_uint p = 0; p < np && !stop; p++) {
        cl_uint nd = 0;
        if (clGetDeviceIDs(ps[p], CL_DEVICE_TYPE_ALL, 0, NULL, &nd) != CL_SUCCESS || nd == 0) {
            char name[256] = "";
            clGetPlatformInfo(ps[p], CL_PLATFORM_NAME, sizeof name - 1, name, NULL);
            pocl_empty |= strstr(name, POCL_NAME) != NULL;
            continue; /* a platform without devices is skipped */
        }
        devices += nd;
        cl_device_id *ds = calloc(nd, sizeof *ds);
        if (!ds)
            break;
        clGetDeviceIDs(ps[p], CL_DEVICE_TYPE_ALL, nd, ds, NULL);
        for (cl_uint d = 0; d < nd && !stop; d++) {
            st_device_info info;
            fill_info(ps[p], ds[d], p, d, &info);
            stop = visit(ps[p], ds[d], &info, ctx);
        }
        free(ds);
    }
    free(ps);
    char why[1200];
    if (devices == 0 && pocl_empty && pocl_cache_problem(why, sizeof why))
        return st_fail(err, ST_ERR_DEVICE, "no OpenCL devices: %s", why);
    if (devices == 0)
        return st_fail(err, ST_ERR_DEVICE, "no OpenCL devices on %u platform%s (run `make deps` "
                       "for PoCL's CPU device)", np, np == 1 ? "" : "s");
    return ST_OK;
}

typedef struct list_ctx { st_device_info *v; unsigned n, cap; int nomem; } list_ctx;

static int collect(cl_platform_id p, cl_device_id d, const st_device_info *info, void *ctx)
{
    (void)p;
    (void)d;
    list_ctx *l = ctx;
    if (l->n == l->cap) {
        unsigned cap = l->cap ? 2 * l->cap : 8;
        st_device_info *v = realloc(l->v, cap * sizeof *v);
        if (!v) {
            l->nomem = 1;
            return 1;
        }
        l->v = v;
        l->cap = cap;
    }
    l->v[l->n++] = *info;
    return 0;
}

st_status st_device_list(st_device_info **out, unsigned *count, st_error *err)
{
    list_ctx l = {0};
    *out = NULL;
    *count = 0;
    if (each_device(collect, &l, err) != ST_OK) {
        free(l.v);
        return err->status;
    }
    if (l.nomem) {
        free(l.v);
        return st_fail(err, ST_ERR_NOMEM, "out of memory listing devices");
    }
    *out = l.v;
    *count = l.n;
    return ST_OK;
}

typedef struct pick_ctx {
    int want_cpu, want_gpu;
    unsigned p, d;
    int found;
    cl_platform_id platform;
    cl_device_id id;
    st_device_info info;
} pick_ctx;

static int pick(cl_platform_id p, cl_device_id d, const st_device_info *info, void *ctx)
{
    pick_ctx *c = ctx;
    int match = c->want_cpu   ? info->is_cpu
                : c->want_gpu ? info->is_gpu
                              : (info->platform == c->p && info->device == c->d);
    if (match) {
        c->found = 1;
        c->platform = p;
        c->id = d;
        c->info = *info;
    }
    return match;
}

static st_status parse_spec(const char *spec, pick_ctx *c, st_error *err)
{
    memset(c, 0, sizeof *c);
    if (!spec || !strcmp(spec, "cpu")) {
        c->want_cpu = 1;
        return ST_OK;
    }
    if (!strcmp(spec, "gpu")) {
        c->want_gpu = 1;
        return ST_OK;
    }
    char tail;
    if (sscanf(spec, "%u:%u%c", &c->p, &c->d, &tail) == 2)
        return ST_OK;
    return st_fail(err, ST_ERR_USAGE, "device %s: expected cpu, gpu or P:D", spec);
}

st_status st_device_create(const char *spec, st_device **out, st_error *err)
{
    *out = NULL;
    pick_ctx c;
    if (parse_spec(spec, &c, err) != ST_OK || each_device(pick, &c, err) != ST_OK)
        return err->status;
    if (!c.found)
        return st_fail(err, ST_ERR_DEVICE, "device %s: no OpenCL device matches",
                       spec ? spec : "cpu");
    if (!c.info.has_int64_atomics)
        return st_fail(err, ST_ERR_DEVICE, "%s: device lacks cl_khr_int64_base_atomics, needed for the film",
                       c.info.name);
    st_device *dev = calloc(1, sizeof *dev);
    if (!dev)
        return st_fail(err, ST_ERR_NOMEM, "out of memory creating the device");
    dev->info = c.info;
    dev->platform = c.platform;
    dev->id = c.id;
    cl_int rc;
    cl_context_properties props[] = {CL_CONTEXT_PLATFORM, (cl_context_properties)c.platform, 0};
    dev->context = clCreateContext(props, 1, &dev->id, NULL, NULL, &rc);
    if (rc != CL_SUCCESS) {
        st_device_destroy(dev);
        return cl_fail(err, "clCreateContext", rc);
    }
    dev->time_tag = -1;
    dev->queue = clCreateCommandQueue(dev->context, dev->id, QUEUE_PROPERTIES, &rc);
    if (rc != CL_SUCCESS) {
        st_device_destroy(dev);
        return cl_fail(err, "clCreateCommandQueue", rc);
    }
    *out = dev;
    return ST_OK;
}

void st_device_destroy(st_device *dev)
{
    if (!dev)
        return;
    for (unsigned i = 0; i < dev->timed_count; i++)
        clReleaseEvent(dev->timed[i].ev);
    for (unsigned i = 0; i < dev->kernel_count; i++)
        clReleaseKernel(dev->kernels[i].k);
    if (dev->program)
        clReleaseProgram(dev->program);
    if (dev->queue)
        clReleaseCommandQueue(dev->queue);
    if (dev->context)
        clReleaseContext(dev->context);
    if (dev->sub)
        clReleaseDevice(dev->sub);
    for (size_t i = 0; i < dev->kept_count; i++)
        clReleaseMemObject(dev->kept[i]);
    free(dev->kept);
    free(dev->log);
    free(dev);
}

const st_device_info *st_device_get_info(const st_device *dev) { return &dev->info; }

unsigned st_device_default_lanes(const st_device_info *info)
{
    if (!info->is_cpu)
        return 1u;
    unsigned w = info->float_width;
    return w >= 16u ? 16u : w >= 8u ? 8u : w >= 4u ? 4u : 1u;
}

st_status st_device_set_lanes(st_device *dev, unsigned n, st_error *err)
{
    if (dev->program)
        return st_fail(err, ST_ERR_USAGE, "lanes %u: set before the build", n);
    if (n != 1u && n != 4u && n != 8u && n != 16u)
        return st_fail(err, ST_ERR_USAGE, "lanes %u: must be 1, 4, 8 or 16", n);
    dev->info.lanes = n;
    return ST_OK;
}

unsigned long long st_device_max_alloc(const st_device *dev)
{
    cl_ulong max = 0;
    if (clGetDeviceInfo(dev->id, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof max, &max, NULL) != CL_SUCCESS)
        return 0;
    return max;
}

st_status st_device_limit_compute_units(st_device *dev, unsigned n, st_error *err)
{
    if (dev->program || dev->sub)
        return st_fail(err, ST_ERR_USAGE, "threads %u: set before the build, once", n);
    if (n == 0 || n > dev->info.compute_units)
        return st_fail(err, ST_ERR_USAGE, "threads %u: %s has %u compute units", n,
                       dev->info.name, dev->info.compute_units);
    if (n == dev->info.compute_units)
        return ST_OK;
    const cl_device_partition_property by_counts[] = {
        CL_DEVICE_PARTITION_BY_COUNTS, (cl_device_partition_property)n,
        CL_DEVICE_PARTITION_BY_COUNTS_LIST_END, 0};
    cl_uint made = 0;
    cl_int rc = clCreateSubDevices(dev->id, by_counts, 1, &dev->sub, &made);
    if (rc != CL_SUCCESS || made != 1) {
        dev->sub = NULL;
        return st_fail(err, ST_ERR_DEVICE, "threads %u: %s cannot be limited (clCreateSubDevices: %s)",
                       n, dev->info.name, st_device_error_name(rc));
    }
    cl_context_properties props[] = {CL_CONTEXT_PLATFORM, (cl_context_properties)dev->platform, 0};
    cl_context ctx = clCreateContext(props, 1, &dev->sub, NULL, NULL, &rc);
    if (rc != CL_SUCCESS)
        return cl_fail(err, "clCreateContext", rc);
    cl_command_queue q = clCreateCommandQueue(ctx, dev->sub, QUEUE_PROPERTIES, &rc);
    if (rc != CL_SUCCESS) {
        clReleaseContext(ctx);
        return cl_fail(err, "clCreateCommandQueue", rc);
    }
    clReleaseCommandQueue(dev->queue);
    clReleaseContext(dev->context);
    dev->context = ctx;
    dev->queue = q;
    dev->id = dev->sub;
    dev->info.compute_units = n;
    return ST_OK;
}

const char *st_device_build_log(const st_device *dev)
{
    return dev && dev->log ? dev->log : "";
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* The most bytes of one kernel file read from $STRATA_KERNEL_DIR (the largest is some 100 kB). */
#define MAX_KERNEL_FILE (16u << 20)

/* A kernel file from $STRATA_KERNEL_DIR, headed by a #line marker so that build logs name it
 * (the embedded sources carry theirs from tools/embed.c); the path's quotes and backslashes
 * escaped in it. Only a regular file is read: a FIFO's read would wait for a writer, a device's
 * might never end. NULL with err filled. */
static char *read_text(const char *path, st_error *err)
{
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    struct stat sb;
    if (fd < 0 || fstat(fd, &sb) != 0) {
        st_fail(err, ST_ERR_IO, "%s: cannot read kernel (%s; STRATA_KERNEL_DIR)", path,
                strerror(errno));
        if (fd >= 0)
            close(fd);
        return NULL;
    }
    if (!S_ISREG(sb.st_mode) || sb.st_size > MAX_KERNEL_FILE) {
        st_fail(err, ST_ERR_IO, "%s: cannot read kernel (%s; STRATA_KERNEL_DIR)", path,
                S_ISREG(sb.st_mode) ? "larger than 16 MiB" : "not a regular file");
        close(fd);
        return NULL;
    }
    size_t n = (size_t)sb.st_size, h = 0, len = strlen(path);
    char *s = malloc(n + 2 * len + 16);
    if (!s) {
        st_fail(err, ST_ERR_NOMEM, "%s: out of memory for the kernel", path);
        close(fd);
        return NULL;
    }
    h += (size_t)sprintf(s, "#line 1 \"");
    for (size_t i = 0; i < len; i++) {
        if (path[i] == '"' || path[i] == '\\')
            s[h++] = '\\';
        s[h++] = path[i];
    }
    h += (size_t)sprintf(s + h, "\"\n");
    size_t got = 0;
    while (got < n) {
        ssize_t r = read(fd, s + h + got, n - got);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            break;
        got += (size_t)r;
    }
    close(fd);
    if (got != n) {
        st_fail(err, ST_ERR_IO, "%s: cannot read kernel (cut short; STRATA_KERNEL_DIR)", path);
        free(s);
        return NULL;
    }
    s[h + n] = '\0';
    return s;
}

/* The folder `dir` as the compiler's -I options may name it: itself, or, where its path holds a
 * blank or a quote (build options are split at blanks, with no quoting in OpenCL 1.2 §5.8.4),
 * /proc/self/fd/N of a descriptor held open on it (*fd, to close after the build; -1 if none).
 * The compilers strata runs on (PoCL, Oclgrind) compile in this process, where that name holds. */
static const char *include_root(const char *dir, char *buf, size_t size, int *fd)
{
    *fd = -1;
    if (!strpbrk(dir, " \t\n\v\f\r\"'\\"))
        return dir;
    if ((*fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC)) < 0)
        return dir; /* the read of the kernels has found it, or will say why not */
    snprintf(buf, size, "/proc/self/fd/%d", *fd);
    return buf;
}

/* Writes `to` for every `from` in the kept build log (the folder's own name for the
 * /proc/self/fd name include_root gave the compiler), so that the log names real files. */
static void rename_in_log(st_device *dev, const char *from, const char *to)
{
    size_t nf = strlen(from), nt = strlen(to), count = 0;
    for (const char *p = dev->log ? strstr(dev->log, from) : NULL; p; p = strstr(p + nf, from))
        count++;
    char *out = count ? malloc(strlen(dev->log) + count * nt + 1) : NULL;
    if (!out)
        return;
    char *o = out;
    for (const char *p = dev->log, *q; (q = strstr(p, from)) || *p; p = q + nf) {
        size_t keep = q ? (size_t)(q - p) : strlen(p);
        memcpy(o, p, keep);
        o += keep;
        if (!q)
            break;
        memcpy(o, to, nt);
        o += nt;
    }
    *o = '\0';
    free(dev->log);
    dev->log = out;
}

static void keep_log(st_device *dev)
{
    size_t n = 0;
    free(dev->log);
    dev->log = NULL;
    if (clGetProgramBuildInfo(dev->program, dev->id, CL_PROGRAM_BUILD_LOG, 0, NULL, &n) != CL_SUCCESS)
        return;
    dev->log = malloc(n + 1);
    if (dev->log && clGetProgramBuildInfo(dev->program, dev->id, CL_PROGRAM_BUILD_LOG, n, dev->log,
                                          NULL) == CL_SUCCESS)
        dev->log[n] = '\0';
}

/* Oclgrind 21.10 (`make test-oclgrind`), a device checker rather than a device, has three
 * known limits: it cannot run the llvm.bitreverse that clang makes of a bit-reversal loop
 * unless the program is built without optimisation (nor the noalias scopes of forced
 * inlining, so ST_HOT inlines nothing there: st_shared.h); it does not count
 * clEnqueueFillBuffer as initialising memory; and a buffer created after another was released
 * may take the released one's number and keep its size in the uninitialised-memory check, so
 * that writes past that size go unseen and later reads of them are reported (a render after
 * a render). On its platform strata works around all three, the last by releasing no buffer
 * before the device goes; nothing else changes. */
static int is_oclgrind(const st_device *dev)
{
    return strstr(dev->info.platform_name, "Oclgrind") != NULL;
}

/* PoCL on a CPU: the kernels' prefetch hints (trace.h, ST_PREFETCH_HINTS) were measured to pay
 * there; no other compiler is asked to take clang's __builtin_prefetch. */
static int is_pocl_cpu(const st_device *dev)
{
    return dev->info.is_cpu && strstr(dev->info.platform_name, POCL_NAME);
}

st_status st_device_build(st_device *dev, double *seconds, st_error *err)
{
    if (dev->program)
        return ST_OK;
    const char *dir = getenv("STRATA_KERNEL_DIR");
    unsigned n = st_embedded_kernel_count;
    const char *src[MAX_KERNELS];
    char *owned[MAX_KERNELS] = {0};
    char options[4096];
    int dir_fd = -1;
    st_status rc = ST_OK;
    for (unsigned i = 0; i < n && i < MAX_KERNELS; i++) {
        src[i] = (const char *)st_embedded_kernels[i].data;
        if (dir && *dir) {
            char path[1024];
            snprintf(path, sizeof path, "%s/%s", dir, st_embedded_kernels[i].name);
            if (!(owned[i] = read_text(path, err))) {
                rc = err->status;
                goto done;
            }
            src[i] = owned[i];
        }
    }
    int used = snprintf(options, sizeof options, "-cl-std=CL1.2 -DST_W=%u%s%s", dev->info.lanes,
                        is_oclgrind(dev) ? " -cl-opt-disable -DST_NO_FORCED_INLINE" : "",
                        is_pocl_cpu(dev) ? " -DST_PREFETCH_HINTS" : "");
    /* the kernel directory's include folders, the search path the embedded sources were
     * inlined with (tools/embed.c) */
    char root_buf[64];
    const char *root = dir && *dir ? include_root(dir, root_buf, sizeof root_buf, &dir_fd) : dir;
    for (unsigned i = 0; dir && *dir && st_embedded_kernel_dirs[i] && used > 0; i++) {
        size_t left = sizeof options - (size_t)used;
        int n = snprintf(options + used, left, " -I%s/%s", root, st_embedded_kernel_dirs[i]);
        if (n < 0 || (size_t)n >= left) {
            rc = st_fail(err, ST_ERR_USAGE, "%s: kernel directory path too long (STRATA_KERNEL_DIR)", dir);
            goto done;
        }
        used += n;
    }
    double t0 = now_seconds();
    cl_int code;
    dev->program = clCreateProgramWithSource(dev->context, n, src, NULL, &code);
    if (code != CL_SUCCESS) {
        rc = cl_fail(err, "clCreateProgramWithSource", code);
        goto done;
    }
    code = clBuildProgram(dev->program, 1, &dev->id, options, NULL, NULL);
    keep_log(dev);
    if (dir_fd >= 0)
        rename_in_log(dev, root, dir);
    char why[1200];
    if (code != CL_SUCCESS && strstr(dev->info.platform_name, POCL_NAME) &&
        pocl_cache_problem(why, sizeof why)) {
        rc = st_fail(err, ST_ERR_DEVICE, "kernel build failed on %s: %s: %s", dev->info.name,
                     st_device_error_name(code), why);
    } else if (code != CL_SUCCESS) {
        rc = st_fail(err, ST_ERR_DEVICE, "kernel build failed on %s: %s (compiler log follows)",
                     dev->info.name, st_device_error_name(code));
    }
    if (code != CL_SUCCESS) {
        clReleaseProgram(dev->program);
        dev->program = NULL;
        goto done;
    }
    if (seconds)
        *seconds = now_seconds() - t0;
done:
    if (dir_fd >= 0)
        close(dir_fd);
    for (unsigned i = 0; i < n && i < MAX_KERNELS; i++)
        free(owned[i]);
    return rc;
}

st_status st_device_kernel(st_device *dev, const char *name, cl_kernel *out, st_error *err)
{
    for (unsigned i = 0; i < dev->kernel_count; i++)
        if (!strcmp(dev->kernels[i].name, name)) {
            *out = dev->kernels[i].k;
            return ST_OK;
        }
    if (dev->kernel_count == MAX_KERNELS)
        return st_fail(err, ST_ERR_DEVICE, "too many kernels (limit %d)", MAX_KERNELS);
    cl_int code;
    cl_kernel k = clCreateKernel(dev->program, name, &code);
    if (code != CL_SUCCESS)
        return st_fail(err, ST_ERR_DEVICE, "clCreateKernel(%s) failed: %s", name,
                       st_device_error_name(code));
    snprintf(dev->kernels[dev->kernel_count].name, sizeof dev->kernels[0].name, "%s", name);
    dev->kernels[dev->kernel_count++].k = k;
    *out = k;
    return ST_OK;
}

st_status st_device_set_arg(cl_kernel k, unsigned index, size_t size, const void *value,
                            st_error *err)
{
    cl_int code = clSetKernelArg(k, index, size, value);
    if (code == CL_SUCCESS)
        return ST_OK;
    char name[64] = "?";
    clGetKernelInfo(k, CL_KERNEL_FUNCTION_NAME, sizeof name, name, NULL);
    return st_fail(err, ST_ERR_DEVICE, "clSetKernelArg(%s, %u) failed: %s", name, index,
                   st_device_error_name(code));
}

st_status st_device_set_args(cl_kernel k, st_error *err, unsigned n, ...)
{
    va_list ap;
    va_start(ap, n);
    st_status rc = ST_OK;
    for (unsigned i = 0; i < n && rc == ST_OK; i++) {
        size_t size = va_arg(ap, size_t);
        const void *value = va_arg(ap, const void *);
        rc = st_device_set_arg(k, i, size, value, err);
    }
    va_end(ap);
    return rc;
}

/* Stack bytes allowed per work-item on a CPU device, where PoCL keeps a group's
 * work-items' private values on one thread's stack: at one lane about twice what the
 * deepest kernel (trace_shadow_rays) was seen to need, and per further lane what shade's
 * gathered lanes add (its private arrays hold ST_W values each), with room to spare: a
 * group of 4096 work-items was seen to need at most 12 MiB at 1 lane, 28 at 8 and 56 at 16
 * (path tracing, transmission and clear coat included). */
static size_t cpu_item_stack_bytes(const st_device *dev)
{
    return 4096u + 1024u * (dev->info.lanes - 1u);
}

st_status st_device_check_local_size(const st_device *dev, size_t local, st_error *err)
{
    size_t max = 0;
    if (clGetDeviceInfo(dev->id, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof max, &max, NULL) ==
            CL_SUCCESS && max > 0 && local > max)
        return st_fail(err, ST_ERR_USAGE, "local size %zu: more than the device's %zu "
                       "work-items a group (CL_DEVICE_MAX_WORK_GROUP_SIZE)", local, max);
    if (!dev->info.is_cpu)
        return ST_OK;
    struct rlimit rl;
    size_t stack = (size_t)2 << 20; /* glibc's thread stack when RLIMIT_STACK is unlimited */
    if (getrlimit(RLIMIT_STACK, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY)
        stack = (size_t)rl.rlim_cur;
    size_t bytes = cpu_item_stack_bytes(dev), fit = stack / bytes;
    if (local > fit)
        return st_fail(err, ST_ERR_USAGE, "local size %zu: a CPU device runs a group on one "
                       "thread's stack of %zu KiB (ulimit -s), which holds at most %zu "
                       "work-items of %zu bytes at %u lanes; use a smaller --local-size or "
                       "raise ulimit -s", local, stack >> 10, fit, bytes, dev->info.lanes);
    return ST_OK;
}

/* Waits for the timed launches so far and adds each one's time on the
 * device (its command's start to end) to its tag's seconds, then releases
 * their events. */
static st_status read_timed(st_device *dev, st_error *err)
{
    st_status rc = ST_OK;
    if (dev->timed_count > 0) {
        cl_int code = clWaitForEvents(1, &dev->timed[dev->timed_count - 1].ev);
        if (code != CL_SUCCESS)
            rc = cl_fail(err, "clWaitForEvents", code);
    }
    for (unsigned i = 0; i < dev->timed_count; i++) {
        cl_ulong t0 = 0, t1 = 0;
        cl_int code = CL_SUCCESS;
        if (rc == ST_OK)
            code = clGetEventProfilingInfo(dev->timed[i].ev, CL_PROFILING_COMMAND_START,
                                           sizeof t0, &t0, NULL);
        if (rc == ST_OK && code == CL_SUCCESS)
            code = clGetEventProfilingInfo(dev->timed[i].ev, CL_PROFILING_COMMAND_END,
                                           sizeof t1, &t1, NULL);
        if (rc == ST_OK && code != CL_SUCCESS)
            rc = cl_fail(err, "clGetEventProfilingInfo", code);
        if (rc == ST_OK && t1 > t0)
            dev->tag_seconds[dev->timed[i].tag] += (double)(t1 - t0) * 1e-9;
        clReleaseEvent(dev->timed[i].ev);
    }
    dev->timed_count = 0;
    return rc;
}

/* The widest row of a launch: PoCL compiles a kernel's work-group function for grids
 * under 2^16 work-items wide, and again for wider grids at their first launch, a second
 * compile as long as the first; so a longer launch goes in rows (st_shared.h: ST_ITEM). */
#define LAUNCH_ROW ((size_t)1 << 15)

st_status st_device_launch(st_device *dev, cl_kernel k, size_t items, size_t local, st_error *err)
{
    if (items == 0)
        return ST_OK;
    size_t row = local ? (local < LAUNCH_ROW ? LAUNCH_ROW / local * local : local) : LAUNCH_ROW;
    size_t global[2] = {local ? (items + local - 1) / local * local : items, 1};
    size_t group[2] = {local, 1};
    if (global[0] > row) {
        global[1] = (items + row - 1) / row;
        global[0] = row;
    }
    cl_uint dims = global[1] > 1 ? 2 : 1;
    if (dev->time_tag >= 0 && dev->timed_count == TIMED_EVENTS &&
        read_timed(dev, err) != ST_OK)
        return err->status;
    cl_event ev = NULL;
    cl_int code = clEnqueueNDRangeKernel(dev->queue, k, dims, NULL, global, local ? group : NULL,
                                         0, NULL, dev->time_tag >= 0 ? &ev : NULL);
    if (code == CL_SUCCESS && ev) {
        dev->timed[dev->timed_count].ev = ev;
        dev->timed[dev->timed_count++].tag = dev->time_tag;
    }
    if (code != CL_SUCCESS) {
        char name[64] = "?";
        clGetKernelInfo(k, CL_KERNEL_FUNCTION_NAME, sizeof name, name, NULL);
        return st_fail(err, ST_ERR_DEVICE, "launching %s failed: %s", name,
                       st_device_error_name(code));
    }
    return ST_OK;
}

void st_device_time_launches(st_device *dev, int tag)
{
    dev->time_tag = tag >= 0 && tag < ST_DEVICE_TIME_TAGS ? tag : -1;
}

st_status st_device_timed_seconds(st_device *dev, double *seconds, unsigned tags, st_error *err)
{
    st_status rc = read_timed(dev, err);
    for (unsigned k = 0; k < ST_DEVICE_TIME_TAGS; k++) {
        if (rc == ST_OK && k < tags)
            seconds[k] += dev->tag_seconds[k];
        dev->tag_seconds[k] = 0.0;
    }
    return rc;
}

st_status st_device_finish(st_device *dev, st_error *err)
{
    cl_int code = clFinish(dev->queue);
    return code == CL_SUCCESS ? ST_OK : cl_fail(err, "clFinish", code);
}

st_status st_device_buffer_create(st_device *dev, size_t bytes, const void *init, cl_mem *out,
                                  st_error *err)
{
    cl_int code;
    if (bytes == 0)
        bytes = 16; /* OpenCL forbids empty buffers; kernels never read it */
    cl_mem_flags flags = CL_MEM_READ_WRITE | (init ? CL_MEM_COPY_HOST_PTR : 0);
    *out = clCreateBuffer(dev->context, flags, bytes, (void *)init, &code);
    if (code != CL_SUCCESS)
        return st_fail(err, ST_ERR_DEVICE, "clCreateBuffer(%zu bytes) failed: %s", bytes,
                       st_device_error_name(code));
    return ST_OK;
}

void st_device_buffer_destroy(st_device *dev, cl_mem mem)
{
    if (!mem)
        return;
    if (is_oclgrind(dev)) { /* its third limit: see is_oclgrind */
        if (dev->kept_count == dev->kept_cap) {
            size_t cap = dev->kept_cap ? 2 * dev->kept_cap : 64;
            cl_mem *kept = realloc(dev->kept, cap * sizeof *kept);
            if (kept) {
                dev->kept = kept;
                dev->kept_cap = cap;
            }
        }
        if (dev->kept_count < dev->kept_cap) {
            dev->kept[dev->kept_count++] = mem;
            return;
        }
    }
    clReleaseMemObject(mem);
}

st_status st_device_buffer_read(st_device *dev, cl_mem mem, size_t bytes, void *dst, st_error *err)
{
    cl_int code = clEnqueueReadBuffer(dev->queue, mem, CL_TRUE, 0, bytes, dst, 0, NULL, NULL);
    return code == CL_SUCCESS ? ST_OK : cl_fail(err, "clEnqueueReadBuffer", code);
}

st_status st_device_buffer_write(st_device *dev, cl_mem mem, size_t bytes, const void *src,
                                 st_error *err)
{
    cl_int code = clEnqueueWriteBuffer(dev->queue, mem, CL_TRUE, 0, bytes, src, 0, NULL, NULL);
    return code == CL_SUCCESS ? ST_OK : cl_fail(err, "clEnqueueWriteBuffer", code);
}

st_status st_device_buffer_zero(st_device *dev, cl_mem mem, size_t bytes, st_error *err)
{
    if (is_oclgrind(dev)) { /* a write initialises, for its uninitialised-memory check */
        void *zeros = calloc(1, bytes ? bytes : 1);
        if (!zeros)
            return st_fail(err, ST_ERR_NOMEM, "out of memory zeroing %zu bytes", bytes);
        st_status s = st_device_buffer_write(dev, mem, bytes, zeros, err);
        free(zeros);
        return s;
    }
    cl_uint zero = 0;
    cl_int code = clEnqueueFillBuffer(dev->queue, mem, &zero, sizeof zero, 0, bytes, 0, NULL, NULL);
    return code == CL_SUCCESS ? ST_OK : cl_fail(err, "clEnqueueFillBuffer", code);
}
