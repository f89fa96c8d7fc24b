/* cli_bench_trace.c — `strata bench SCENE --rays camera|random [--count N]
 * [--json]`: the trace benchmark (st_trace_bench.h) and the BVH build, as
 * text or one JSON object. */
#include <cjson/cJSON.h> /* Debian libcjson-dev */
#include <stdio.h>

#include "cli_commands.h"
#include "cli_error.h"
#include "cli_session.h"
#include "cli_text.h"
#include "st_trace_bench.h"
#include "st_version.h"

#define ST_BENCH_DEFAULT_RAYS (1u << 21)

typedef struct trace_report {
    const char *device, *scene, *kind;
    st_trace_bench_result t;
    st_u32 triangles;
    double bvh_seconds;
} trace_report;

static double per_second(double n, double s) { return s > 0.0 ? n / s : 0.0; }

static void print_text(const trace_report *r)
{
    printf("device     %s\nscene      %s (%u triangles)\n", r->device, r->scene, r->triangles);
    printf("bvh build  %.4f s (%.2f M triangles/s)\n", r->bvh_seconds,
           per_second(r->triangles, r->bvh_seconds) * 1e-6);
    printf("trace      %s rays: %llu in %.4f s, %.2f M rays/s, hit fraction %.4f%s\n", r->kind,
           (unsigned long long)r->t.rays, r->t.seconds,
           per_second((double)r->t.rays, r->t.seconds) * 1e-6,
           r->t.rays ? (double)r->t.hits / (double)r->t.rays : 0.0,
           r->t.sorted ? " (sorted by ray first, sort counted)" : "");
}

/* {"device", "scene", "rays": {kind, count, seconds, rays_per_second,
 * hit_fraction, sorted}, "bvh": {triangles, seconds, triangles_per_second}} */
static st_status print_json(const trace_report *r, st_error *err)
{
    cJSON *root = cJSON_CreateObject();
    int ok = root && cJSON_AddStringToObject(root, "version", st_version) &&
             cJSON_AddStringToObject(root, "device", r->device) &&
             cJSON_AddStringToObject(root, "scene", r->scene);
    cJSON *rays = ok ? cJSON_AddObjectToObject(root, "rays") : NULL;
    cJSON *bvh = ok ? cJSON_AddObjectToObject(root, "bvh") : NULL;
    double n = (double)r->t.rays;
    ok = rays && bvh && cJSON_AddStringToObject(rays, "kind", r->kind) &&
             cJSON_AddNumberToObject(rays, "count", n) &&
             cJSON_AddNumberToObject(rays, "seconds", r->t.seconds) &&
             cJSON_AddNumberToObject(rays, "rays_per_second", per_second(n, r->t.seconds)) &&
             cJSON_AddNumberToObject(rays, "hit_fraction", n > 0 ? (double)r->t.hits / n : 0.0) &&
             cJSON_AddBoolToObject(rays, "sorted", r->t.sorted) &&
             cJSON_AddNumberToObject(bvh, "triangles", r->triangles) &&
             cJSON_AddNumberToObject(bvh, "seconds", r->bvh_seconds) &&
             cJSON_AddNumberToObject(bvh, "triangles_per_second",
                                     per_second(r->triangles, r->bvh_seconds));
    if (!ok) {
        cJSON_Delete(root);
        root = NULL;
    }
    return st_cli_put_json(root, err);
}

int st_cli_bench_trace(st_cli_render_args *a)
{
    st_error err = {0};
    st_cli_session s;
    int set = a->rays - 1, rc = 0;
    trace_report r = {0};
    if (st_cli_session_open(a, &s, &err) ||
        st_trace_bench(s.renderer, &a->opt, set, a->ray_count ? a->ray_count : ST_BENCH_DEFAULT_RAYS,
                       &r.t, &err)) {
        rc = st_cli_session_fail(&s, &err);
        goto done;
    }
    r.device = st_device_get_info(s.dev)->name;
    r.scene = s.scene->name;
    r.kind = st_ray_set_names[set];
    r.triangles = s.scene->tri_count;
    if (st_trace_bench_build(s.renderer, &r.bvh_seconds, &err) != ST_OK) {
        rc = st_cli_fail(&err);
        goto done;
    }
    if (!a->json)
        print_text(&r);
    else if (print_json(&r, &err) != ST_OK)
        rc = st_cli_fail(&err);
done:
    st_cli_session_close(&s);
    return rc;
}
