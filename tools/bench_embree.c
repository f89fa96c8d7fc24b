/* bench_embree.c — the trace benchmark of `strata bench SCENE --rays
 * camera|random`, run by Embree 3 (Debian's libembree-dev) called from C:
 * the peer tools/bench_peers.sh measures strata's traversal against. Not a
 * test and not part of the renderer (`make build/release/bench_embree`).
 *
 * Like for like, by construction:
 *   - the triangles are strata's own: the scene is read by strata's importer
 *     (st_scene_load), world space, in the same order;
 *   - the rays are strata's own: st_trace_bench_rays, the generator `strata
 *     bench --rays` traces, with its default view (st_render_defaults: 512 x
 *     512, seed 0, the scene's default camera), tmin 0, tmax infinite;
 *   - a triangle of a one-sided material is culled when met from behind, as
 *     strata's traversal culls it (kernels/geom/trace.h: det = e1 . (d x e2) must
 *     be positive), by an Embree intersection filter on the one-sided
 *     triangles' geometry (Debian's Embree is built without its compile-time
 *     culling). The filter costs Embree time (a call per candidate hit on
 *     those triangles), so a scene with one-sided triangles is also measured
 *     without it ("two-sided"): Embree's own speed, with hits that differ
 *     from strata's where rays meet a one-sided back face.
 *
 * Embree builds its BVH on THREADS threads (its device's "threads" setting),
 * timed from the geometry's creation to rtcCommitScene's return, the median
 * of ST_TRACE_BENCH_BUILDS builds after an untimed build of one triangle
 * that starts its worker threads (as st_trace_bench_build times strata's).
 * Then THREADS pthreads trace every ray, taking chunks of CHUNK rays in the generator's
 * order from a shared counter (as PoCL hands out work-groups), once with
 * rtcIntersect1, once with rtcIntersect8 and once with rtcIntersect16
 * (packets of 8 and of 16 consecutive rays; Embree emulates the 16-wide call
 * with narrower ones where the machine or its build has no AVX-512);
 * each timed pass follows an untimed one over the first wave of rays, as
 * strata's benchmark launches one untimed wave (PoCL compiles at the first
 * launch; here it warms the caches alike).
 *
 * The check: --check N rays, evenly spaced over the count, are traced by
 * strata's own trace_rays kernel (st_trace_closest on the default device,
 * PoCL, started after the timing so its threads take no core from Embree's)
 * and compared with the hits the timed Embree passes recorded: a ray agrees
 * when both miss, or both hit at t within a relative CHECK_TOL. It prints
 * how many agree, and exits 1 when fewer than all but CHECK_SLACK of them
 * do (grazing rays along an edge may fall either way in two different
 * triangle tests; a wrong generator or a wrong side rule disagrees on far
 * more). The two-sided runs are checked too, and printed, not enforced.
 *
 * Usage: bench_embree SCENE camera|random [--count N] [--threads T]
 *                     [--check N] [--json]
 * Prints strata bench's text (one trace line per Embree call), or with
 * --json one line: {"version", "device", "scene", "rays" (rtcIntersect1),
 * "rays8" (rtcIntersect8), "rays16" (rtcIntersect16), each {kind, count,
 * seconds, rays_per_second, hit_fraction}, "bvh" {triangles, seconds,
 * triangles_per_second}, "native16" (whether Embree's build traces 16 rays
 * natively), "check" {rays, agree1, agree8, agree16, tolerance}, and with
 * one-sided triangles "two_sided" {"rays", "rays8", "rays16", "check"}}. Errors: one line "bench_embree:
 * error: ...", exit 2 for usage, 1 otherwise. */
#include <cjson/cJSON.h> /* Debian libcjson-dev */
#include <embree3/rtcore.h> /* Debian libembree-dev */
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "st_device.h"
#include "st_scene.h"
#include "st_trace_bench.h"
#include "st_version.h"

#define DEFAULT_COUNT (1u << 21) /* strata bench's default --count */
#define WARM_RAYS (1u << 18)     /* strata bench's default wave, traced untimed first */
#define CHUNK 4096u              /* rays a thread takes at a time (a multiple of 16) */
#define CHECK_TOL 1e-4           /* relative difference of t allowed in the check */
#define CHECK_SLACK 0.001        /* share of checked rays allowed to disagree */

static const char usage[] =
    "usage: bench_embree SCENE camera|random [--count N] [--threads T] [--check N] [--json]";

typedef struct args {
    const char *scene;
    int set;               /* ST_RAYS_* */
    unsigned long count;   /* rays traced by each call */
    unsigned threads;      /* Embree's build threads and the tracing pthreads */
    unsigned long check;   /* rays compared with strata's kernel */
    int json;
} args;

static void die(int status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("bench_embree: error: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    exit(status);
}

static unsigned long parse_count(const char *flag, const char *v, unsigned long lo,
                                 unsigned long hi)
{
    char *end;
    errno = 0;
    unsigned long n = v ? strtoul(v, &end, 10) : 0;
    if (!v || errno || end == v || *end || v[0] == '-' || n < lo || n > hi)
        die(2, "%s %s: expected an integer in %lu .. %lu", flag, v ? v : "(missing)", lo, hi);
    return n;
}

static args parse_args(int argc, char **argv)
{
    args a = {NULL, 0, DEFAULT_COUNT, 2, 4096, 0};
    if (argc < 3)
        die(2, "%s", usage);
    a.scene = argv[1];
    if (!strcmp(argv[2], st_ray_set_names[ST_RAYS_CAMERA]))
        a.set = ST_RAYS_CAMERA;
    else if (!strcmp(argv[2], st_ray_set_names[ST_RAYS_RANDOM]))
        a.set = ST_RAYS_RANDOM;
    else
        die(2, "ray set %s: expected camera or random", argv[2]);
    for (int i = 3; i < argc; i++) {
        const char *f = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(f, "--count"))
            a.count = parse_count(f, v, 1, 1ul << 30), i++;
        else if (!strcmp(f, "--threads"))
            a.threads = (unsigned)parse_count(f, v, 1, 256), i++;
        else if (!strcmp(f, "--check"))
            a.check = parse_count(f, v, 0, 1ul << 20), i++;
        else if (!strcmp(f, "--json"))
            a.json = 1;
        else
            die(2, "unknown option %s (%s)", f, usage);
    }
    if (a.check > a.count)
        a.check = a.count;
    return a;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* ---- the scene ---- */

static void embree_error(void *user, enum RTCError code, const char *what)
{
    (void)user;
    die(1, "embree: %s (error %d)", what ? what : "unknown", (int)code);
}

/* Embree hands a filter its rays and hits as arrays of N lanes per field
 * (rtcore_ray.h's RTCRayN/RTCHitN layout; its accessors are C++ only):
 * ray dir_x, dir_y, dir_z are fields 4, 5, 6; hit primID is field 5. */
static float ray_lane(const struct RTCRayN *ray, unsigned n, unsigned field, unsigned i)
{
    return ((const float *)ray)[field * n + i];
}

/* strata's side rule (kernels/geom/trace.h, st_intersect_triangle): a one-sided
 * triangle counts only where det = e1 . (d x e2) > 0, the ray meeting the
 * side from which v0, v1, v2 run counter-clockwise. geometryUserPtr is the
 * geometry's vertices, 9 floats per triangle. */
static void cull_back_faces(const struct RTCFilterFunctionNArguments *a)
{
    const float *verts = a->geometryUserPtr;
    unsigned n = a->N;
    for (unsigned i = 0; i < n; i++) {
        if (a->valid[i] != -1)
            continue;
        const float *v = verts + 9 * (size_t)((const unsigned *)a->hit)[5 * n + i];
        float e1[3], e2[3];
        for (int k = 0; k < 3; k++) {
            e1[k] = v[3 + k] - v[k];
            e2[k] = v[6 + k] - v[k];
        }
        float dx = ray_lane(a->ray, n, 4, i), dy = ray_lane(a->ray, n, 5, i),
              dz = ray_lane(a->ray, n, 6, i);
        float det = e1[0] * (dy * e2[2] - dz * e2[1]) + e1[1] * (dz * e2[0] - dx * e2[2]) +
                    e1[2] * (dx * e2[1] - dy * e2[0]);
        if (!(det > 0.0f))
            a->valid[i] = 0;
    }
}

static int one_sided(const st_scene *s, st_u32 tri)
{
    return !(s->materials[s->tri_material[tri]].flags & ST_MAT_DOUBLE_SIDED);
}

/* The scene's triangles of one side rule as one Embree geometry (unshared
 * vertices, 3 per triangle, as strata stores them), attached to scene;
 * none when no triangle has that rule. */
static void add_mesh(RTCDevice dev, RTCScene scene, const st_scene *s, int sided, int cull)
{
    st_u32 n = 0;
    for (st_u32 i = 0; i < s->tri_count; i++)
        n += one_sided(s, i) == sided;
    if (!n)
        return;
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                       3 * sizeof(float), 3 * (size_t)n);
    unsigned *idx = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                            3 * sizeof(unsigned), n);
    if (!v || !idx)
        die(1, "embree: no memory for %u triangles", n);
    for (st_u32 i = 0, k = 0; i < s->tri_count; i++) {
        if (one_sided(s, i) != sided)
            continue;
        memcpy(v + 9 * (size_t)k, s->positions + 9 * (size_t)i, 9 * sizeof(float));
        for (int c = 0; c < 3; c++)
            idx[3 * (size_t)k + c] = 3 * k + (unsigned)c;
        k++;
    }
    if (sided && cull) {
        rtcSetGeometryUserData(g, v);
        rtcSetGeometryIntersectFilterFunction(g, cull_back_faces);
    }
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
}

/* The scene's BVH; *seconds from the first geometry to the committed scene. */
static RTCScene build(RTCDevice dev, const st_scene *s, int cull, double *seconds)
{
    double t0 = now();
    RTCScene scene = rtcNewScene(dev);
    add_mesh(dev, scene, s, 1, cull);
    add_mesh(dev, scene, s, 0, cull);
    rtcCommitScene(scene);
    *seconds = now() - t0;
    return scene;
}

/* The median seconds of ST_TRACE_BENCH_BUILDS builds of the scene, each
 * dropped, as st_trace_bench_build times strata's. */
static double build_seconds(RTCDevice dev, const st_scene *s, int cull)
{
    double t[ST_TRACE_BENCH_BUILDS];
    for (int k = 0; k < ST_TRACE_BENCH_BUILDS; k++)
        rtcReleaseScene(build(dev, s, cull, &t[k]));
    return st_trace_bench_median(t, ST_TRACE_BENCH_BUILDS);
}

/* One triangle built and dropped: Embree starts its task threads at the
 * first build, which is not the BVH's cost. */
static void warm_build(RTCDevice dev)
{
    RTCScene scene = rtcNewScene(dev);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                       3 * sizeof(float), 3);
    unsigned *idx = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                            3 * sizeof(unsigned), 1);
    const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    memcpy(v, tri, sizeof tri);
    idx[0] = 0, idx[1] = 1, idx[2] = 2;
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
    rtcReleaseScene(scene);
}

/* ---- tracing ---- */

typedef struct pass {
    RTCScene scene;
    const st_ray *rays;
    float *t;              /* per ray: the hit's t, INFINITY on a miss */
    size_t count;          /* rays [0, count) */
    int width;             /* rays a call: rtcIntersect1, 8 or 16 */
    atomic_size_t next;    /* the first ray of the next chunk to take */
    atomic_ullong hits;
} pass;

static void trace_one(pass *p, size_t begin, size_t end, unsigned long long *hits)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (size_t i = begin; i < end; i++) {
        const st_ray *r = &p->rays[i];
        struct RTCRayHit rh;
        rh.ray.org_x = r->o[0], rh.ray.org_y = r->o[1], rh.ray.org_z = r->o[2];
        rh.ray.dir_x = r->d[0], rh.ray.dir_y = r->d[1], rh.ray.dir_z = r->d[2];
        rh.ray.tnear = 0.0f, rh.ray.tfar = r->tmax, rh.ray.time = 0.0f;
        rh.ray.mask = ~0u, rh.ray.id = 0, rh.ray.flags = 0;
        rh.hit.geomID = rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(p->scene, &ctx, &rh);
        int hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        *hits += hit;
        p->t[i] = hit ? rh.ray.tfar : INFINITY;
    }
}

/* Packets of N consecutive rays through rtcIntersectN (RTCRayHitN), one
 * text for both widths Embree 3 has beside 4. */
#define TRACE_PACKETS(N)                                                                  \
    static void trace_##N(pass *p, size_t begin, size_t end, unsigned long long *hits)    \
    {                                                                                     \
        struct RTCIntersectContext ctx;                                                   \
        rtcInitIntersectContext(&ctx);                                                    \
        for (size_t b = begin; b < end; b += N) {                                         \
            struct RTCRayHit##N rh; /* RTC_ALIGN(4 N) in rtcore_ray.h */                  \
            _Alignas(4 * N) int valid[N];                                                 \
            for (unsigned k = 0; k < N; k++) {                                            \
                /* a short tail repeats a live ray, masked off */                         \
                const st_ray *r = &p->rays[b + k < end ? b + k : b];                      \
                valid[k] = b + k < end ? -1 : 0;                                          \
                rh.ray.org_x[k] = r->o[0], rh.ray.org_y[k] = r->o[1];                     \
                rh.ray.org_z[k] = r->o[2];                                                \
                rh.ray.dir_x[k] = r->d[0], rh.ray.dir_y[k] = r->d[1];                     \
                rh.ray.dir_z[k] = r->d[2];                                                \
                rh.ray.tnear[k] = 0.0f, rh.ray.tfar[k] = r->tmax, rh.ray.time[k] = 0.0f;  \
                rh.ray.mask[k] = ~0u, rh.ray.id[k] = 0, rh.ray.flags[k] = 0;              \
                rh.hit.geomID[k] = rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;         \
            }                                                                             \
            rtcIntersect##N(valid, p->scene, &ctx, &rh);                                  \
            for (unsigned k = 0; k < N && b + k < end; k++) {                             \
                int hit = rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;                    \
                *hits += hit;                                                             \
                p->t[b + k] = hit ? rh.ray.tfar[k] : INFINITY;                            \
            }                                                                             \
        }                                                                                 \
    }
TRACE_PACKETS(8)
TRACE_PACKETS(16)

static void *trace_worker(void *arg)
{
    pass *p = arg;
    unsigned long long hits = 0;
    for (;;) {
        size_t begin = atomic_fetch_add(&p->next, CHUNK);
        if (begin >= p->count)
            break;
        size_t end = begin + CHUNK < p->count ? begin + CHUNK : p->count;
        (p->width == 16 ? trace_16 : p->width == 8 ? trace_8 : trace_one)(p, begin, end, &hits);
    }
    atomic_fetch_add(&p->hits, hits);
    return NULL;
}

/* Rays [0, count) on `threads` pthreads; returns the seconds from the first
 * thread's start to the last one's end, *hits the rays that hit. */
static double trace_pass(RTCScene scene, const st_ray *rays, float *t, size_t count,
                         int width, unsigned threads, unsigned long long *hits)
{
    pass p = {scene, rays, t, count, width, 0, 0};
    pthread_t *tid = malloc(threads * sizeof *tid);
    if (!tid)
        die(1, "out of memory for %u threads", threads);
    double t0 = now();
    for (unsigned k = 0; k < threads; k++)
        if (pthread_create(&tid[k], NULL, trace_worker, &p))
            die(1, "cannot start tracing thread %u", k);
    for (unsigned k = 0; k < threads; k++)
        pthread_join(tid[k], NULL);
    double seconds = now() - t0;
    free(tid);
    *hits = atomic_load(&p.hits);
    return seconds;
}

typedef struct result {
    double seconds;
    unsigned long long hits;
} result;

/* An untimed pass over the first wave, then the timed pass over all. */
static result measure(RTCScene scene, const st_ray *rays, float *t, size_t count, int width,
                      unsigned threads)
{
    result r;
    trace_pass(scene, rays, t, count < WARM_RAYS ? count : WARM_RAYS, width, threads, &r.hits);
    r.seconds = trace_pass(scene, rays, t, count, width, threads, &r.hits);
    return r;
}

/* ---- the check against strata's kernel ---- */

static int same_hit(float strata_t, int strata_hit, float embree_t)
{
    if (!strata_hit || isinf(embree_t))
        return !strata_hit && isinf(embree_t);
    return fabs((double)strata_t - embree_t) <= CHECK_TOL * fmax(strata_t, embree_t);
}

/* One side rule's measurements: both calls' results and per-ray hits, and
 * how many of the checked rays agree with strata's. */
typedef struct run {
    int present;
    result one, eight, sixteen;
    float *t1, *t8, *t16;  /* per ray: the hit's t, INFINITY on a miss */
    size_t agree1, agree8, agree16;
} run;

/* Builds the scene under one side rule (cull: strata's) and times both
 * calls over all rays; *bvh_seconds the build's time (build_seconds). */
static void measure_rule(RTCDevice dev, const st_scene *s, int cull, const st_ray *rays,
                         size_t count, unsigned threads, run *m, double *bvh_seconds)
{
    m->present = 1;
    m->t1 = malloc(count * sizeof *m->t1);
    m->t8 = malloc(count * sizeof *m->t8);
    m->t16 = malloc(count * sizeof *m->t16);
    if (!m->t1 || !m->t8 || !m->t16)
        die(1, "out of memory for the hits of %zu rays", count);
    double traced;
    *bvh_seconds = build_seconds(dev, s, cull);
    RTCScene scene = build(dev, s, cull, &traced);
    m->one = measure(scene, rays, m->t1, count, 1, threads);
    m->eight = measure(scene, rays, m->t8, count, 8, threads);
    m->sixteen = measure(scene, rays, m->t16, count, 16, threads);
    rtcReleaseScene(scene);
}

/* Traces the sample of `n` rays (ray k * count / n) with strata's trace_rays
 * kernel and counts, for each run present, the rays on which its two calls'
 * hits agree with strata's. */
static void check(const st_scene *s, const st_render_options *o, const st_ray *rays,
                  size_t count, size_t n, run *const *runs, int run_count)
{
    if (!n)
        return;
    st_error err = {0};
    st_device *dev = NULL;
    st_renderer *r = NULL;
    st_ray *sample = malloc(n * sizeof *sample);
    st_hit *hits = malloc(n * sizeof *hits);
    size_t *at = malloc(n * sizeof *at);
    if (!sample || !hits || !at)
        die(1, "out of memory for %zu checked rays", n);
    for (size_t k = 0; k < n; k++) {
        at[k] = (size_t)((unsigned long long)k * count / n);
        sample[k] = rays[at[k]];
    }
    if (st_device_create(NULL, &dev, &err) || st_device_build(dev, NULL, &err) ||
        st_renderer_create(dev, s, &r, &err) ||
        st_trace_closest(r, o, o->packet_path == ST_PACKET_ALL, sample, n, hits, &err))
        die(1, "strata's check: %s", err.msg);
    for (int j = 0; j < run_count; j++)
        for (size_t k = 0; runs[j]->present && k < n; k++) {
            int hit = hits[k].prim != ST_NO_HIT;
            runs[j]->agree1 += same_hit(hits[k].t, hit, runs[j]->t1[at[k]]);
            runs[j]->agree8 += same_hit(hits[k].t, hit, runs[j]->t8[at[k]]);
            runs[j]->agree16 += same_hit(hits[k].t, hit, runs[j]->t16[at[k]]);
        }
    st_renderer_destroy(r);
    st_device_destroy(dev);
    free(sample);
    free(hits);
    free(at);
}

/* ---- the report ---- */

typedef struct report {
    char device[128];
    const char *scene, *kind;
    unsigned long count;
    st_u32 triangles;
    double bvh_seconds;
    int native16;          /* RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED */
    size_t checked;
    run culled, two_sided; /* strata's side rule; Embree's own (only with one-sided triangles) */
} report;

static double per_second(double n, double s) { return s > 0.0 ? n / s : 0.0; }

static void print_trace(const char *name, const report *r, const result *x)
{
    printf("%-10s %s rays: %lu in %.4f s, %.2f M rays/s, hit fraction %.4f\n", name, r->kind,
           r->count, x->seconds, per_second((double)r->count, x->seconds) * 1e-6,
           (double)x->hits / (double)r->count);
}

static void print_check(const char *rule, const report *r, const run *m)
{
    printf("check      %s: %zu rays against strata's trace_rays: rtcIntersect1 %zu agree, "
           "rtcIntersect8 %zu, rtcIntersect16 %zu (both miss, or t within %g relative)\n",
           rule, r->checked, m->agree1, m->agree8, m->agree16, CHECK_TOL);
}

static void print_text(const report *r)
{
    printf("device     %s\nscene      %s (%u triangles)\n", r->device, r->scene, r->triangles);
    printf("bvh build  %.4f s (%.2f M triangles/s)\n", r->bvh_seconds,
           per_second(r->triangles, r->bvh_seconds) * 1e-6);
    print_trace("trace 1", r, &r->culled.one);
    print_trace("trace 8", r, &r->culled.eight);
    print_trace(r->native16 ? "trace 16" : "trace 16e", r, &r->culled.sixteen);
    print_check("strata's side rule", r, &r->culled);
    if (r->two_sided.present) {
        print_trace("2-sided 1", r, &r->two_sided.one);
        print_trace("2-sided 8", r, &r->two_sided.eight);
        print_trace("2-sided 16", r, &r->two_sided.sixteen);
        print_check("two-sided, not strata's rule", r, &r->two_sided);
    }
}

static int json_rays(cJSON *root, const char *key, const report *r, const result *x)
{
    cJSON *o = cJSON_AddObjectToObject(root, key);
    double n = (double)r->count;
    return o && cJSON_AddStringToObject(o, "kind", r->kind) &&
           cJSON_AddNumberToObject(o, "count", n) &&
           cJSON_AddNumberToObject(o, "seconds", x->seconds) &&
           cJSON_AddNumberToObject(o, "rays_per_second", per_second(n, x->seconds)) &&
           cJSON_AddNumberToObject(o, "hit_fraction", (double)x->hits / n);
}

/* "rays", "rays8" and "check" of one run into obj. */
static int json_run(cJSON *obj, const report *r, const run *m)
{
    cJSON *chk;
    return json_rays(obj, "rays", r, &m->one) && json_rays(obj, "rays8", r, &m->eight) &&
           json_rays(obj, "rays16", r, &m->sixteen) &&
           (chk = cJSON_AddObjectToObject(obj, "check")) &&
           cJSON_AddNumberToObject(chk, "rays", (double)r->checked) &&
           cJSON_AddNumberToObject(chk, "agree1", (double)m->agree1) &&
           cJSON_AddNumberToObject(chk, "agree8", (double)m->agree8) &&
           cJSON_AddNumberToObject(chk, "agree16", (double)m->agree16) &&
           cJSON_AddNumberToObject(chk, "tolerance", CHECK_TOL);
}

static void print_json(const report *r)
{
    cJSON *root = cJSON_CreateObject(), *bvh, *two;
    int ok = root && cJSON_AddStringToObject(root, "version", st_version) &&
             cJSON_AddStringToObject(root, "device", r->device) &&
             cJSON_AddStringToObject(root, "scene", r->scene) && json_run(root, r, &r->culled) &&
             cJSON_AddBoolToObject(root, "native16", r->native16) &&
             (bvh = cJSON_AddObjectToObject(root, "bvh")) &&
             cJSON_AddNumberToObject(bvh, "triangles", r->triangles) &&
             cJSON_AddNumberToObject(bvh, "seconds", r->bvh_seconds) &&
             cJSON_AddNumberToObject(bvh, "triangles_per_second",
                                     per_second(r->triangles, r->bvh_seconds)) &&
             (!r->two_sided.present || ((two = cJSON_AddObjectToObject(root, "two_sided")) &&
                                        json_run(two, r, &r->two_sided)));
    char *text = ok ? cJSON_PrintUnformatted(root) : NULL;
    if (!text)
        die(1, "out of memory for the JSON report");
    puts(text);
    cJSON_free(text);
    cJSON_Delete(root);
}

static int has_one_sided(const st_scene *s)
{
    for (st_u32 i = 0; i < s->tri_count; i++)
        if (one_sided(s, i))
            return 1;
    return 0;
}

int main(int argc, char **argv)
{
    args a = parse_args(argc, argv);
    st_error err = {0};
    st_scene *s = NULL;
    if (st_scene_load(a.scene, &s, &err))
        die(err.status == ST_ERR_USAGE ? 2 : 1, "%s", err.msg);
    st_render_options o = st_render_defaults();
    st_ray *rays = malloc(a.count * sizeof *rays);
    if (!rays)
        die(1, "out of memory for %lu rays", a.count);
    if (st_trace_bench_rays(s, &o, a.set, 0, a.count, rays, &err))
        die(1, "%s", err.msg);

    char config[32];
    snprintf(config, sizeof config, "threads=%u", a.threads);
    RTCDevice dev = rtcNewDevice(config);
    if (!dev)
        die(1, "embree: cannot create a device (%s)", config);
    rtcSetDeviceErrorFunction(dev, embree_error, NULL);
    warm_build(dev);
    int native16 = rtcGetDeviceProperty(dev, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) != 0;
    report r;
    memset(&r, 0, sizeof r);
    r.scene = s->name, r.kind = st_ray_set_names[a.set], r.count = a.count;
    r.triangles = s->tri_count, r.checked = a.check, r.native16 = native16;
    snprintf(r.device, sizeof r.device, "embree %s (%u threads)", RTC_VERSION_STRING, a.threads);
    measure_rule(dev, s, 1, rays, a.count, a.threads, &r.culled, &r.bvh_seconds);
    if (has_one_sided(s)) {
        double unused;
        measure_rule(dev, s, 0, rays, a.count, a.threads, &r.two_sided, &unused);
    }
    rtcReleaseDevice(dev);

    run *const runs[2] = {&r.culled, &r.two_sided};
    check(s, &o, rays, a.count, a.check, runs, 2);
    if (a.json)
        print_json(&r);
    else
        print_text(&r);
    /* two-sided hits the one-sided back faces strata culls: not checked */
    size_t worst = r.culled.agree1 < r.culled.agree8 ? r.culled.agree1 : r.culled.agree8;
    worst = r.culled.agree16 < worst ? r.culled.agree16 : worst;
    int bad = (double)(r.checked - worst) > CHECK_SLACK * (double)r.checked;
    if (bad)
        fprintf(stderr, "bench_embree: error: %s: only %zu of %zu checked rays agree with strata's "
                        "hits: not the same rays or scene\n", a.scene, worst, r.checked);
    free(rays);
    for (int j = 0; j < 2; j++)
        free(runs[j]->t1), free(runs[j]->t8), free(runs[j]->t16);
    st_scene_destroy(s);
    return bad;
}
