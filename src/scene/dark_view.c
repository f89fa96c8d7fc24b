/* dark_view.c — how much of the default view a scene's own lights leave
 * dark (dark_view.h).
 *
 * A grid of DARK_GRID x DARK_GRID camera rays through the default camera's
 * view (square, as the default image) is traced on the host through the
 * wide BVH the kernels trace (kernels/geom/trace.h). A ray's point is lit
 * when it lies on an emitter, or when some light reaches it directly: a
 * punctual light on its side, inside a spot's cone, with nothing in between;
 * or one of up to DARK_EMITTERS emissive triangles (spread over the list of
 * them), whose centre faces it and is in view. Anything between the point
 * and the light blocks it, glass included, as it blocks next-event
 * estimation; alpha is not read, so a cut-out shadow counts as solid. A ray
 * that leaves the scene is dark (no environment). So the fraction is of the
 * pixels that direct lighting leaves black: an upper bound of those the
 * path tracer leaves black, which finds light through glass and bounces
 * only by chance. Tests: tests/unit/test_scene.c
 * dark_fraction_counts_what_no_light_reaches,
 * default_environment_follows_the_lights. */
#include "dark_view.h"

#include "st_bvh.h"
#include "trace.h"

#include <math.h>
#include <stdlib.h>

#define DARK_GRID 32
#define DARK_EMITTERS 16

/* Camera ray (i, j) of the DARK_GRID x DARK_GRID grid, through pixel centres
 * (the grid is symmetric, so the sign of the right axis does not matter). */
static void grid_ray(const st_scene_camera *c, int i, int j, st_ray *ray)
{
    double sx = (2.0 * (i + 0.5) / DARK_GRID - 1.0), sy = (1.0 - 2.0 * (j + 0.5) / DARK_GRID);
    double right[3] = {c->forward[1] * c->up[2] - c->forward[2] * c->up[1],
                       c->forward[2] * c->up[0] - c->forward[0] * c->up[2],
                       c->forward[0] * c->up[1] - c->forward[1] * c->up[0]};
    double half = c->orthographic ? c->ymag : tan(0.5 * c->yfov), d[3], o[3];
    for (int k = 0; k < 3; k++) {
        double side = half * (sx * right[k] + sy * c->up[k]);
        o[k] = c->origin[k] + (c->orthographic ? side : 0.0);
        d[k] = c->forward[k] + (c->orthographic ? 0.0 : side);
    }
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; k++) {
        ray->o[k] = (float)o[k];
        ray->d[k] = (float)(d[k] / len);
    }
    ray->tmax = INFINITY;
    ray->path_length = 0.0f;
}

/* Whether the segment from p (offset by eps along n) to q, or along the unit
 * direction q where far is set, is free of triangles. */
static int in_view(const st_bvh *bvh, const float p[3], const float n[3], float eps,
                   const double q[3], int far)
{
    st_ray r;
    double d[3], len = 0.0;
    for (int k = 0; k < 3; k++) {
        r.o[k] = p[k] + eps * n[k];
        d[k] = far ? q[k] : q[k] - r.o[k];
        len += d[k] * d[k];
    }
    len = sqrt(len);
    if (!(len > 0.0))
        return 0;
    for (int k = 0; k < 3; k++)
        r.d[k] = (float)(d[k] / len);
    r.tmax = far ? INFINITY : (float)(len * (1.0 - 1e-4));
    r.path_length = 0.0f;
    return !st_intersect_wide_any(bvh->wide, &r);
}

/* A punctual light reaches point p of normal n (facing the viewer). */
static int punctual_reaches(const st_bvh *bvh, const st_punctual *l, const float p[3],
                            const float n[3], float eps)
{
    st_u32 type = (st_u32)l->pos[3];
    if (!(l->intensity[0] > 0.0f || l->intensity[1] > 0.0f || l->intensity[2] > 0.0f))
        return 0;
    double to[3], len = 0.0;
    for (int k = 0; k < 3; k++) {
        to[k] = type == ST_PUNCT_DIRECTIONAL ? -(double)l->dir[k] : (double)l->pos[k] - p[k];
        len += to[k] * to[k];
    }
    len = sqrt(len);
    if (!(len > 0.0) || n[0] * to[0] + n[1] * to[1] + n[2] * to[2] <= 0.0)
        return 0;
    if (type == ST_PUNCT_SPOT &&
        -(to[0] * l->dir[0] + to[1] * l->dir[1] + to[2] * l->dir[2]) / len <= l->dir[3])
        return 0;
    if (type == ST_PUNCT_DIRECTIONAL)
        return in_view(bvh, p, n, eps, to, 1);
    const double q[3] = {l->pos[0], l->pos[1], l->pos[2]};
    return in_view(bvh, p, n, eps, q, 0);
}

/* Emissive triangle t's centre faces point p of normal n and is in view. */
static int emitter_reaches(const st_scene *s, const st_bvh *bvh, st_u32 t, const float p[3],
                           const float n[3], float eps)
{
    const float *v = s->positions + 9 * (size_t)t;
    double c[3], e1[3], e2[3], to[3];
    for (int k = 0; k < 3; k++) {
        c[k] = (v[k] + v[3 + k] + v[6 + k]) / 3.0;
        e1[k] = (double)v[3 + k] - v[k];
        e2[k] = (double)v[6 + k] - v[k];
        to[k] = c[k] - p[k];
    }
    double g[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                   e1[0] * e2[1] - e1[1] * e2[0]};
    int two_sided = (s->materials[s->tri_material[t]].flags & ST_MAT_DOUBLE_SIDED) != 0;
    double facing = -(g[0] * to[0] + g[1] * to[1] + g[2] * to[2]);
    if (n[0] * to[0] + n[1] * to[1] + n[2] * to[2] <= 0.0 || (!two_sided && facing <= 0.0))
        return 0;
    /* stop short of the emitter itself: the segment ends 1e-4 of its length before c */
    return in_view(bvh, p, n, eps, c, 0);
}

static int emits(const st_material *m)
{
    return m->emission[0] > 0.0f || m->emission[1] > 0.0f || m->emission[2] > 0.0f;
}

/* Whether the point a camera ray meets on triangle t is lit directly. */
static int lit(const st_scene *s, const st_bvh *bvh, const st_u32 *emitters, st_u32 emitter_count,
               const st_ray *ray, const st_hit *hit, float eps)
{
    st_u32 t = bvh->order[hit->prim];
    if (emits(&s->materials[s->tri_material[t]]))
        return 1;
    const float *v = s->positions + 9 * (size_t)t;
    float p[3], n[3];
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) {
        p[k] = ray->o[k] + hit->t * ray->d[k];
        e1[k] = (double)v[3 + k] - v[k];
        e2[k] = (double)v[6 + k] - v[k];
    }
    double g[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                   e1[0] * e2[1] - e1[1] * e2[0]};
    double len = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    double side = g[0] * ray->d[0] + g[1] * ray->d[1] + g[2] * ray->d[2] > 0.0 ? -1.0 : 1.0;
    for (int k = 0; k < 3; k++)
        n[k] = (float)(side * g[k] / len); /* towards the viewer */
    for (st_u32 k = 0; k < s->punctual_count; k++)
        if (punctual_reaches(bvh, &s->punctual[k], p, n, eps))
            return 1;
    st_u32 step = emitter_count > DARK_EMITTERS ? emitter_count / DARK_EMITTERS : 1;
    for (st_u32 k = 0; k < emitter_count; k += step)
        if (emitter_reaches(s, bvh, emitters[k], p, n, eps))
            return 1;
    return 0;
}

/* The scene's BVH as the kernels trace it (one-sided surfaces culled). */
static st_status view_bvh(const st_scene *s, st_bvh **bvh, st_error *err)
{
    if (st_bvh_build(s->positions, s->tri_count, bvh, err) != ST_OK)
        return err->status;
    st_bvh_set_sides(*bvh, s->tri_material, s->materials);
    return ST_OK;
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

st_status st_scene_view_distance(const st_scene *s, double *distance, st_error *err)
{
    *distance = 0.0;
    if (s->tri_count == 0)
        return ST_OK;
    st_bvh *bvh = NULL;
    if (view_bvh(s, &bvh, err) != ST_OK)
        return err->status;
    double t[DARK_GRID * DARK_GRID];
    int n = 0;
    for (int j = 0; j < DARK_GRID; j++)
        for (int i = 0; i < DARK_GRID; i++) {
            st_ray ray;
            st_hit hit;
            grid_ray(&s->default_camera, i, j, &ray);
            if (st_intersect_wide_closest(bvh->wide, &ray, &hit))
                t[n++] = hit.t;
        }
    st_bvh_destroy(bvh);
    if (n > 0) {
        qsort(t, (size_t)n, sizeof t[0], by_value);
        *distance = t[n / 10];
    }
    return ST_OK;
}

st_status st_scene_dark_fraction(const st_scene *s, double *fraction, st_error *err)
{
    *fraction = 1.0;
    if (s->tri_count == 0)
        return ST_OK;
    st_bvh *bvh = NULL;
    st_u32 *emitters = malloc(s->tri_count * sizeof *emitters), emitter_count = 0;
    if (!emitters)
        return st_fail(err, ST_ERR_NOMEM, "out of memory probing the view's lighting");
    for (st_u32 t = 0; t < s->tri_count; t++)
        if (emits(&s->materials[s->tri_material[t]]))
            emitters[emitter_count++] = t;
    if (view_bvh(s, &bvh, err) != ST_OK) {
        free(emitters);
        return err->status;
    }
    float extent = 0.0f; /* the renderer's ray offset (device_scene.c) */
    for (int a = 0; a < 3; a++)
        extent = fmaxf(extent, fmaxf(fabsf(s->bounds_min[a]), fabsf(s->bounds_max[a])));
    float eps = 1e-4f * fmaxf(extent, 1e-3f);
    int dark = 0;
    for (int j = 0; j < DARK_GRID; j++)
        for (int i = 0; i < DARK_GRID; i++) {
            st_ray ray;
            st_hit hit;
            grid_ray(&s->default_camera, i, j, &ray);
            if (!st_intersect_wide_closest(bvh->wide, &ray, &hit) ||
                !lit(s, bvh, emitters, emitter_count, &ray, &hit, eps))
                dark++;
        }
    st_bvh_destroy(bvh);
    free(emitters);
    *fraction = dark / (double)(DARK_GRID * DARK_GRID);
    return ST_OK;
}
