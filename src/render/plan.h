/* plan.h — what a render runs, decided in one place: the lane width the
 * kernels were built for and, per stage, which kernel, from the device, the
 * scene and the render. Every choice leaves the image as it is (the tests
 * render each way and compare the films); they are measured choices of
 * speed, and the reasons are in plan.c. Not a public header. */
#ifndef ST_PLAN_H
#define ST_PLAN_H

#include "st_render.h"
#include "st_shared.h"

/* The splat: splat_samples (one work-item per sample, atomics; filter
 * importance sampling, and the reference), bin_samples then splat_tiles (a
 * work-group per image tile, sharing its window through local atomics, or
 * ALONE: one work-item a group, plain adds), or splat_pixels (the box
 * filter's splat gathered by pixel where a wave allows it, else per sample). */
enum { ST_SPLAT_AUTO, ST_SPLAT_PER_SAMPLE, ST_SPLAT_TILES, ST_SPLAT_TILES_ALONE, ST_SPLAT_PIXELS };
/* Shadow rays: their own stage, trace_shadow_rays, or traced in shade
 * (shade_hits_shadowed). */
enum { ST_SHADOW_AUTO, ST_SHADOW_STAGE, ST_SHADOW_IN_SHADE };
/* The paths a vertex after the first runs over: those still alive, listed
 * by live.cl, or every item of the wave (the reference: ended paths skipped
 * lane by lane). */
enum { ST_PATHS_AUTO, ST_PATHS_LIVE, ST_PATHS_ALL };
/* The rays of the last vertex: traced through the tree (trace_rays, or in
 * packets), or tested against the light list's triangles first
 * (trace_rays_last, where the scene allows it). */
enum { ST_LAST_AUTO, ST_LAST_TRAVERSE, ST_LAST_EMITTERS };

/* Next-event estimation's pick of an area light: in lanes where the scene
 * allows it (st_params.area_lanes), or lane by lane. */
enum { ST_AREA_AUTO, ST_AREA_LANE_BY_LANE };
/* The order of a trace's rays: as listed, or sorted by ray (order.cl) first,
 * where the plan finds it pays (st_plan_orders); ON sorts every trace it
 * may (trace_rays' rays of a bounce, the trace benchmark's), whatever the
 * scene. */
enum { ST_ORDER_AUTO, ST_ORDER_OFF, ST_ORDER_ON };

/* Choices forced for tests and measurements (st_renderer_force): each
 * *_AUTO (0) unless set, the plan's own choice then. */
typedef struct st_plan_force {
    int splat;    /* ST_SPLAT_* */
    int shadow;   /* ST_SHADOW_* */
    int paths;    /* ST_PATHS_* */
    int last;     /* ST_LAST_* */
    int area;     /* ST_AREA_* */
    int order;    /* ST_ORDER_* */
} st_plan_force;

/* What path vertex v launches (st_plan.vertex[v], v = 0 .. max_depth, at
 * most 64): the kernel of its closest-hit trace and of its shadow rays
 * (ST_K_*, render_int.h; shadow -1 where shade traces them or at the last
 * vertex, which makes none), whether the trace's rays are sorted first
 * (order.cl), and whether each goes ST_W rays to a work-item (packets). */
#define ST_PLAN_VERTICES 65
typedef struct st_plan_vertex {
    int trace, shadow;
    int sorted;
    int trace_lanes, shadow_lanes;
} st_plan_vertex;

typedef struct st_plan {
    unsigned lanes;       /* the kernels' ST_W (st_device_info.lanes) */
    int packets;          /* ST_PACKET_NONE, COHERENT or ALL */
    int shadows_in_shade; /* shade_hits_shadowed: no trace_shadow_rays stage */
    int live_lists;       /* vertices after the first run over the live paths (live.cl) */
    int last_by_emitters; /* the last vertex's rays by trace_rays_last */
    int area_lanes;       /* area lights picked in lanes (st_params.area_lanes) */
    int splat;            /* ST_SPLAT_PER_SAMPLE, TILES, TILES_ALONE or PIXELS (where a
                             wave allows it: st_plan_gathers) */
    int tile_passes;      /* splat_tiles in four passes of bins whose windows do not
                             overlap (st_params.bin_pass), else one launch */
    unsigned bins;        /* splat_tiles' bins (st_params.bins; 0: none) */
    int order;            /* ST_ORDER_ON: a bounce's rays sorted before their trace;
                             ST_ORDER_OFF: never */
    int shade;            /* ST_K_SHADE, or ST_K_SHADE_SHADOWED with its shadow rays */
    st_plan_vertex vertex[ST_PLAN_VERTICES];
} st_plan;

typedef struct st_renderer st_renderer;

/* The plan of a render of o on r with parameters p and shading sh; fills
 * p's bins for the tile splat (bins 0: none) and its choices for the
 * kernels (last_lights, area_lanes). */
st_plan st_plan_make(const st_renderer *r, const st_render_options *o, const st_shading *sh,
                     st_params *p);
/* Whether a wave of p gathers its splat by pixel (splat_pixels). */
int st_plan_gathers(const st_plan *pl, const st_params *p);
/* Work-items per splat_tiles work-group. */
size_t st_plan_tile_group(const st_plan *pl, const st_render_options *o);
/* Whether the trace benchmark sorts its rays on r (ST_ORDER_ON or
 * ST_ORDER_OFF). */
int st_plan_orders(const st_renderer *r);
/* Bytes of splat_tiles' local window for bins of `side` pixels, with the
 * int32 window of a work-group of one work-item where `alone`. */
size_t st_plan_window_bytes(st_u32 side, float radius, int alone);

/* Forces choices on r's later renders (NULL: none). */
void st_renderer_force(st_renderer *r, const st_plan_force *f);
/* Forces the splat named by the environment's STRATA_SPLAT (samples, tiles,
 * tiles-alone, pixels; unset or empty: none) on r's renders, so that a
 * device whose plan never takes a path (Oclgrind's, GPU-like, never takes
 * the CPU's) can be made to run it: tests/oclgrind/run.sh. Every choice
 * gives the same image. ST_ERR_USAGE for another name. */
st_status st_plan_force_from_env(st_renderer *r, st_error *err);

#endif
