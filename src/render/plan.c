/* plan.c — what a render runs (plan.h): every choice of kernel and lane
 * width in one place. None changes the image; each is the faster way where
 * it was measured (on PoCL's CPU device; a GPU's choices follow from its
 * work-items running in lockstep, one item each). */
#include "plan.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render_int.h"
#include "st_sampling.h"

size_t st_plan_window_bytes(st_u32 side, float radius, int alone)
{
    /* the apron of ceil(r) + 1 pixels (film.cl), four sums of 8 bytes a
     * pixel; a work-item alone adds four int32 partial sums a pixel and an
     * int's room a row (film.cl: near_room) */
    size_t s = side + 2 * ((size_t)ceilf(radius) + 1);
    size_t wide = s * s * 4 * sizeof(st_i64);
    return alone ? wide + s * s * 4 * sizeof(st_i32) + s * sizeof(st_i32) : wide;
}

/* Which rays go in packets: where the kernels have lanes to fill (a CPU
 * device's, or --lanes above 1), the coherent ones, whatever the scene's
 * size: packets of camera rays and their shadow rays measured faster for
 * direct lighting and paths alike on the large meshes and on small scenes
 * too, down to the 32-triangle Cornell box. At one lane (a GPU's) a packet
 * would be one ray: none. */
int st_renderer_packets(const st_renderer *r, const st_render_options *o)
{
    if (o->packet_path != ST_PACKET_AUTO)
        return o->packet_path;
    return st_device_get_info(r->dev)->lanes > 1u ? ST_PACKET_COHERENT : ST_PACKET_NONE;
}

/* Whether the rays of stage k (ST_STAGE_TRACE or ST_STAGE_SHADOW) at vertex
 * v go in packets: coherent are the rays of vertex 0 (camera rays, and the
 * shadow rays from where they hit), not a bounce's scattered rays; shadow
 * rays only where any hit blocks (no alpha to walk through: shadow.h). */
static int in_packets(const st_plan *pl, const st_renderer *r, int k, st_u32 v)
{
    int n = pl->packets == ST_PACKET_ALL || (pl->packets == ST_PACKET_COHERENT && v == 0u);
    return n && (k != ST_STAGE_SHADOW || r->all_opaque);
}

/* The last vertex adds only the light its ray meets (shade.cl), so where
 * every emitter is in the light list (st_renderer.emitters_listed) its ray
 * is tested against those triangles, then for an occluder before the
 * nearest: one any-hit traversal where one meets an emitter (or an
 * environment gives light), none where it meets nothing that shines,
 * instead of a closest-hit traversal for every ray; and in a scene whose
 * environment gives no light, shade makes the same test of the emitters
 * in lanes before it stores that ray (p->last_lights), ending the paths
 * whose ray meets none there. Each ray tests the triangles one by one, so
 * a scene with more than ST_LAST_EMITTERS_MAX of them keeps the traversal
 * (a bound on that loop; the gain was measured on the bench Cornell box's
 * two, whose direct lighting it made about half again as fast). */
#define ST_LAST_EMITTERS_MAX 16u
static int plan_last(const st_renderer *r)
{
    if (r->force.last != ST_LAST_AUTO)
        return r->force.last == ST_LAST_EMITTERS && r->emitters_listed;
    return r->emitters_listed && r->light_count <= ST_LAST_EMITTERS_MAX;
}

/* Next-event estimation's area light: picked in lanes (shade's
 * area_lanes: each CDF entry compared with every lane's u at once, the
 * point's barycentrics in vector arithmetic) where it samples area lights
 * alone (no punctual light, no environment sample) from a list of at most
 * ST_AREA_LANES_MAX, whose loop over the entries then costs less than a
 * binary search lane by lane (it made the bench Cornell box's shading
 * stage about a tenth faster); lane by lane otherwise. The same floats
 * either way. */
#define ST_AREA_LANES_MAX 16u
static int plan_area_lanes(const st_renderer *r, const st_shading *sh, const st_params *p)
{
    return r->force.area != ST_AREA_LANE_BY_LANE && sh->punct_count == 0u &&
           sh->env_pick == 0.0f && p->light_count > 0u && p->light_count <= ST_AREA_LANES_MAX;
}

/* The ray order (order.cl): a stream of rays sorted by origin and direction
 * before its trace, so that a ray finds in the caches the nodes and leaves
 * its forerunner fetched. The trace benchmark's streams are sorted where
 * the scene's tree is larger than the caches (ST_ORDER_MIN_TRIANGLES) on a
 * CPU device: on the 327,680-triangle icosphere its camera rays in random
 * order were traced about 15 % faster, sort included, and its random rays
 * about 6 %; the 32-triangle Cornell box's tree stays in the caches anyway,
 * and a GPU's sort is not measured. A render keeps its lists' order: the
 * bounces of paths in the icosphere inside the Cornell box, sorted, made
 * the whole pass about 5 % slower (the sort, and the trace's reads of
 * records strewn over the wave), and a camera ray's neighbours in the list
 * are its neighbours in the image already. ST_ORDER_ON sorts both. */
#define ST_ORDER_MIN_TRIANGLES 65536u
int st_plan_orders(const st_renderer *r)
{
    if (r->force.order != ST_ORDER_AUTO)
        return r->force.order;
    const st_device_info *info = st_device_get_info(r->dev);
    return info->is_cpu && r->scene->tri_count >= ST_ORDER_MIN_TRIANGLES ? ST_ORDER_ON
                                                                         : ST_ORDER_OFF;
}

/* The splat: filter importance sampling takes one tap per sample, so
 * splat_samples; otherwise bins for splat_tiles where a window fits the
 * device's local memory, except on a CPU device for a filter of radius 1/2
 * or less (a box's one tap but on pixel edges: binning and the window's
 * flush cost more than the atomics they save), which gathers by pixel where
 * a wave allows it. */
static int plan_splat(const st_renderer *r, const st_render_options *o)
{
    const st_plan_force *f = &r->force;
    const st_device_info *info = st_device_get_info(r->dev);
    if (f->splat != ST_SPLAT_AUTO)
        return o->reconstruction == ST_RECON_FIS && f->splat != ST_SPLAT_PIXELS
                   ? ST_SPLAT_PER_SAMPLE
                   : f->splat;
    if (o->reconstruction == ST_RECON_FIS)
        return ST_SPLAT_PER_SAMPLE;
    if (info->is_cpu && o->filter.radius <= 0.5f)
        return ST_SPLAT_PIXELS;
    /* a CPU device runs a group's items in turn on one thread: one item a
     * group then owns its window and adds without atomics */
    return info->is_cpu ? ST_SPLAT_TILES_ALONE : ST_SPLAT_TILES;
}

/* The work-group size of splat_tiles under splat path `splat`. */
static size_t tile_group(int splat, const st_render_options *o)
{
    return splat == ST_SPLAT_TILES_ALONE ? 1 : o->local_size ? o->local_size : 64;
}

/* Bins of the largest side of 32, 16 or 8 pixels (a power of two: film.cl
 * finds a bin's pixels by shifts) whose window fits the
 * device's local memory; none when no window fits. */
static void plan_bins(const st_renderer *r, const st_render_options *o, int splat, st_params *p)
{
    p->bins = p->bin_side = p->bins_x = 0;
    if (splat != ST_SPLAT_TILES && splat != ST_SPLAT_TILES_ALONE)
        return;
    unsigned long long local = st_device_get_info(r->dev)->local_mem;
    for (st_u32 side = 32; side >= 8; side /= 2)
        if (st_plan_window_bytes(side, o->filter.radius, tile_group(splat, o) == 1) <= local) {
            p->bin_side = side;
            p->bins_x = (o->width + side - 1) / side;
            p->bins = p->bins_x * ((o->height + side - 1) / side);
            return;
        }
}

/* Whether splat_tiles runs in four passes of bins whose windows do not
 * overlap (an apron of at most half a tile), so that windows go to the film
 * with plain adds: where a group is one work-item, on a CPU, whose locked
 * adds stall the core's pipeline (they were about half of splat_tiles' time
 * in one launch). A GPU's group of many work-items keeps one launch: its
 * atomics do not stall the work-item, and a quarter of the bins would leave
 * compute units idle. */
static int plan_tile_passes(const st_plan *pl, const st_params *p)
{
    st_u32 apron = (st_u32)ceilf(p->filter.radius) + 1u;
    return pl->splat == ST_SPLAT_TILES_ALONE && p->bins && 2u * apron <= p->bin_side;
}

size_t st_plan_tile_group(const st_plan *pl, const st_render_options *o)
{
    return tile_group(pl->splat, o);
}

int st_plan_gathers(const st_plan *pl, const st_params *p)
{
    /* a sample reaches its own pixel, and across an edge it lies on exactly
     * its neighbours (box, radius <= 1/2: splat_pixels adds those
     * atomically), and item g lies in region pixel g mod npix: a per-pixel
     * sampler outside adaptive rounds */
    return pl->splat == ST_SPLAT_PIXELS && p->reconstruction == ST_RECON_SPLAT &&
           p->filter.kind == ST_FILTER_BOX && p->filter.radius <= 0.5f &&
           st_items_by_pixel(p) && !p->adaptive_scaled;
}

/* Each vertex's kernels (st_plan_vertex): the last vertex's rays by the
 * light list where the plan says so, a vertex's rays in packets where
 * in_packets says so, else one ray a work-item, a bounce's sorted first
 * where the plan sorts them. */
static void plan_vertices(st_plan *pl, const st_renderer *r, const st_params *p)
{
    for (st_u32 v = 0; v < ST_PLAN_VERTICES; v++) {
        st_plan_vertex *x = &pl->vertex[v];
        x->trace_lanes = in_packets(pl, r, ST_STAGE_TRACE, v);
        x->shadow_lanes = in_packets(pl, r, ST_STAGE_SHADOW, v);
        x->sorted = 0;
        if (v == p->max_depth && pl->last_by_emitters) {
            x->trace = ST_K_TRACE_LAST;
            x->trace_lanes = 0;
        } else if (x->trace_lanes) {
            x->trace = ST_K_TRACE_PACKET;
        } else {
            x->trace = ST_K_TRACE;
            x->sorted = pl->order == ST_ORDER_ON && v > 0u;
        }
        x->shadow = pl->shadows_in_shade || v >= p->max_depth ? -1
                    : x->shadow_lanes                        ? ST_K_SHADOW_PACKET
                                                             : ST_K_SHADOW;
    }
}

st_plan st_plan_make(const st_renderer *r, const st_render_options *o, const st_shading *sh,
                     st_params *p)
{
    const st_plan_force *f = &r->force;
    const st_device_info *info = st_device_get_info(r->dev);
    st_plan pl;
    pl.lanes = info->lanes;
    pl.packets = st_renderer_packets(r, o);
    /* tracing shadow rays in shade measured no faster than their own stage */
    pl.shadows_in_shade = f->shadow == ST_SHADOW_IN_SHADE;
    /* the list of live paths keeps every lane of trace and shade busy where
     * paths end early (misses, roulette) for three small launches a vertex */
    pl.live_lists = f->paths != ST_PATHS_ALL;
    pl.last_by_emitters = plan_last(r);
    p->last_lights = (st_u32)pl.last_by_emitters;
    pl.area_lanes = plan_area_lanes(r, sh, p);
    p->area_lanes = (st_u32)pl.area_lanes;
    pl.splat = plan_splat(r, o);
    plan_bins(r, o, pl.splat, p);
    if (!p->bins && (pl.splat == ST_SPLAT_TILES || pl.splat == ST_SPLAT_TILES_ALONE))
        pl.splat = ST_SPLAT_PER_SAMPLE;
    pl.tile_passes = plan_tile_passes(&pl, p);
    pl.bins = p->bins;
    pl.order = f->order == ST_ORDER_ON ? ST_ORDER_ON : ST_ORDER_OFF;
    pl.shade = pl.shadows_in_shade ? ST_K_SHADE_SHADOWED : ST_K_SHADE;
    plan_vertices(&pl, r, p);
    return pl;
}

st_status st_plan_force_from_env(st_renderer *r, st_error *err)
{
    static const char *const names[] = {[ST_SPLAT_PER_SAMPLE] = "samples",
                                        [ST_SPLAT_TILES] = "tiles",
                                        [ST_SPLAT_TILES_ALONE] = "tiles-alone",
                                        [ST_SPLAT_PIXELS] = "pixels"};
    const char *v = getenv("STRATA_SPLAT");
    if (!v || !*v)
        return ST_OK;
    for (int k = ST_SPLAT_PER_SAMPLE; k <= ST_SPLAT_PIXELS; k++)
        if (!strcmp(v, names[k])) {
            r->force.splat = k;
            return ST_OK;
        }
    return st_fail(err, ST_ERR_USAGE,
                   "STRATA_SPLAT=%.40s: unknown splat (samples, tiles, tiles-alone or pixels)", v);
}

void st_renderer_force(st_renderer *r, const st_plan_force *f)
{
    static const st_plan_force none = {0, 0, 0, 0, 0, 0};
    r->force = f ? *f : none;
}

void st_render_note_ran(st_renderer *r, cl_kernel kl)
{
    for (unsigned i = 0; i < r->ran_count; i++)
        if (r->ran[i] == kl)
            return;
    if (r->ran_count < ST_RAN_MAX)
        r->ran[r->ran_count++] = kl;
}

size_t st_render_lane_items(st_device *dev, size_t n)
{
    size_t lanes = st_device_get_info(dev)->lanes;
    return (n + lanes - 1u) / lanes;
}

const char *st_renderer_ran(st_renderer *r)
{
    size_t n = (size_t)snprintf(r->ran_text, sizeof r->ran_text, "lanes %u:", r->plan.lanes);
    for (unsigned i = 0; i < r->ran_count && n < sizeof r->ran_text; i++) {
        char name[64] = "?";
        clGetKernelInfo(r->ran[i], CL_KERNEL_FUNCTION_NAME, sizeof name, name, NULL);
        n += (size_t)snprintf(r->ran_text + n, sizeof r->ran_text - n, "%s %s", i ? "," : "",
                              name);
    }
    return r->ran_text;
}
