/* generate.cl — the first stage of a wave, generate_rays: sample positions
 * on the film, camera rays and fresh paths.
 *
 * Item i of a wave is render item g = first_item + i. Per-pixel samplers:
 * pixel = g mod n, sample = g / n over the n pixels of the region (the whole
 * image, or a crop's window with its filter apron; st_region_pixel), so a
 * pixel's samples are the same in a crop as in the full render. Tiled samplers
 * (poisson, best-candidate): the tile of tile_size^2 pixels repeats over the
 * image; g picks repetition g / tile_count and point tile_begin + g mod
 * tile_count of it; the tile holds exactly spp points in each of its pixels,
 * so every pixel of the image gets exactly spp samples; points of pixels
 * outside the image are dropped. */
#include "st_shared.h"
#include "rng.h"
#include "samplers.h"
#include "camera.h"

/* Filter importance sampling: the offset x in (-r, r) whose CDF of |f|
 * (ST_FIS_BINS piecewise-constant bins, cdf[0] = 0, cdf[bins] = 1) is u. */
static float fis_offset(__global const float *cdf, float r, float u)
{
    st_u32 lo = 0, hi = ST_FIS_BINS - 1u; /* the bin i with cdf[i] <= u < cdf[i+1] */
    while (lo < hi) {
        st_u32 mid = (lo + hi + 1u) / 2u;
        if (cdf[mid] <= u)
            lo = mid;
        else
            hi = mid - 1u;
    }
    float t = (u - cdf[lo]) / (cdf[lo + 1u] - cdf[lo]);
    return -r + ((float)lo + t) * (2.0f * r / (float)ST_FIS_BINS);
}

/* Coordinate px + t of a pixel's point, t in [0, 1): rounded down to a float
 * below px + 1 when the sum rounds up onto the next pixel's edge. */
static float in_pixel(st_u32 px, float t)
{
    float f = (float)px + t, edge = (float)(px + 1u);
    return f < edge ? f : nextafter(edge, 0.0f);
}

/* Render item g of a tiled sampler: point j = tile_begin + g mod tile_count
 * of repetition g / tile_count; the tile's point j lies in its pixel
 * j mod side^2 as that pixel's sample j / side^2 (st_sampling_pixel_tile).
 * Its later dimensions come from the pad tables through the pixel's key,
 * carried as the sample's word (samplers.h, ST_SAMPLER_POISSON). */
static st_sample tile_sample(const st_params *p, __global const st_tile_point *tile, st_u64 g)
{
    st_u32 rep = (st_u32)(g / p->tile_count), j = p->tile_begin + (st_u32)(g % p->tile_count);
    st_u32 side = p->tile_size, tp = j % (side * side), tx = tp % side, ty = tp / side;
    st_u32 px = rep % p->tiles_x * side + tx, py = rep / p->tiles_x * side + ty;
    float fx = in_pixel(px, tile[j].x - (float)tx), fy = in_pixel(py, tile[j].y - (float)ty);
    st_u32 pixel = min(py, p->height - 1u) * p->width + min(px, p->width - 1u);
    st_u32 s = j / (side * side);
    st_sample out = {{fx, fy}, pixel, s, st_rng_key(p->seed, pixel, s), st_pixel_key(p, pixel)};
    return out;
}

/* Items g .. g + ST_W - 1 of a per-pixel sampler over the region (see the
 * top), one a lane: their pixels (px, py) and sample indices, as
 * st_region_pixel and g mod n, g / n give them. The first lane's come from
 * two divides, the others' from it by steps along the region's rows: a
 * lane past a row's end goes on in the next row (on a region narrower than
 * the lanes, again), and one past the last row in the first row of the
 * next sample. So a work-item runs two divides, not two per item (one of
 * them 64-bit; PoCL could not hoist a reciprocal's divide out of its
 * work-item loop, and emulates mul_hi(ulong) with four multiplies). */
ST_HOT void region_lanes(const st_params *p, st_u64 g, st_lu *px, st_lu *py, st_lu *s)
{
    st_u32 npix = p->region_w * p->region_h; /* the image, or a crop's window and apron */
    st_u32 j = (st_u32)(g % npix), row0 = j / p->region_w;
    st_lu col = (st_lu)(j - row0 * p->region_w) + ST_CONVERT(uint, ST_W, ST_IOTA(ST_W));
    st_lu row = (st_lu)row0, smp = (st_lu)(st_u32)(g / npix);
    for (;;) {
        st_li wraps = col >= p->region_w;
        if (!ST_ANY(ST_W, wraps))
            break;
        col = ST_SELECT(ST_W, col, col - p->region_w, wraps);
        row = ST_SELECT(ST_W, row, row + 1u, wraps);
        st_li next = row >= p->region_h;
        row = ST_SELECT(ST_W, row, (st_lu)0u, next);
        smp = ST_SELECT(ST_W, smp, smp + 1u, next);
    }
    *px = p->region_x + col;
    *py = p->region_y + row;
    *s = smp;
}

/* Sample s of pixel (px, py): the film position, (pixel, sample index) and
 * the sampler's key and word for shade (st_sample_resume). With filter
 * importance sampling the sampler's two pixel dimensions are warped
 * through the CDF of |f| (their stratification carries over) into an
 * offset from the pixel centre. */
static st_sample pixel_sample(const st_params *p, __global const st_u32 *pmj02,
                              __global const float *fis_cdf, st_u32 px, st_u32 py, st_u32 s)
{
    st_u32 pixel = py * p->width + px;
    st_sample_id sid = st_sample_begin_at(p, pixel, px, py, s);
    sid.pmj02 = pmj02;
    float u = st_sample_dim(p, &sid, 0u), v = st_sample_dim(p, &sid, 1u);
    if (p->reconstruction == ST_RECON_FIS) {
        u = 0.5f + fis_offset(fis_cdf, p->filter.radius, u);
        v = 0.5f + fis_offset(fis_cdf, p->filter.radius, v);
    }
    st_sample out = {{(float)px + u, (float)py + v}, pixel, s, sid.key, st_sample_word(p, &sid)};
    return out;
}

/* Render item g of a tiled sampler or of an adaptive round (adaptive.cl),
 * whose items do not follow the region's pixels in order: in a round, the
 * pixel's samples continue from pixel_spp[pixel], those it has so far. */
static st_sample scattered_sample(const st_params *p, __global const st_tile_point *tile,
                                  __global const st_u32 *active, __global const st_u32 *pixel_spp,
                                  __global const st_u32 *pmj02, __global const float *fis_cdf,
                                  st_u64 g)
{
    if (ST_SAMPLER_IS_TILED(p->sampler))
        return tile_sample(p, tile, g);
    st_u32 pixel = active[g % p->adaptive_count];
    st_u32 s = pixel_spp[pixel] + p->adaptive_base + (st_u32)(g / p->adaptive_count);
    return pixel_sample(p, pmj02, fis_cdf, pixel % p->width, pixel / p->width, s);
}

/* ST_W samples, lane k at index k of each array (read as lanes by
 * ST_VLOAD); lanes past a work-item's items hold zeros. */
typedef struct st_sample_lanes {
    float fx[ST_W], fy[ST_W];
    st_u32 pixel[ST_W], index[ST_W], key[ST_W], word[ST_W];
} st_sample_lanes;

static void set_lane(st_sample_lanes *l, st_u32 k, st_sample s)
{
    l->fx[k] = s.film[0];
    l->fy[k] = s.film[1];
    l->pixel[k] = s.pixel;
    l->index[k] = s.index;
    l->key[k] = s.key;
    l->word[k] = s.word;
}

static st_sample lane_sample(const st_sample_lanes *l, st_u32 k)
{
    st_sample s = {{l->fx[k], l->fy[k]}, l->pixel[k], l->index[k], l->key[k], l->word[k]};
    return s;
}

/* Samples of lanes k < n (items g + k), zeros in the others: the random
 * sampler's in lanes (its hashes), the other per-pixel samplers' pixels in
 * lanes and their dimensions lane by lane (each sampler's own sequence, as
 * shade gathers them), the tiled samplers' and adaptive rounds' lane by
 * lane. */
ST_HOT void item_samples(const st_params *p, __global const st_tile_point *tile,
                         __global const st_u32 *active, __global const st_u32 *pixel_spp,
                         __global const st_u32 *pmj02, __global const float *fis_cdf, st_u64 g,
                         st_u32 n, st_sample_lanes *l)
{
    const st_sample none = {{0.0f, 0.0f}, 0u, 0u, 0u, 0u};
    if (ST_SAMPLER_IS_TILED(p->sampler) || p->adaptive_count) {
        for (st_u32 k = 0; k < ST_W; k++)
            set_lane(l, k, k < n ? scattered_sample(p, tile, active, pixel_spp, pmj02, fis_cdf, g + k) : none);
        return;
    }
    st_lu px, py, s;
    region_lanes(p, g, &px, &py, &s);
    st_lu pixel = py * p->width + px;
    if (p->sampler == ST_SAMPLER_RANDOM && p->reconstruction != ST_RECON_FIS) {
        /* pixel_sample's arithmetic for the random sampler: no pixel key,
         * no sequence index but s */
        st_lu key = st_rng_key_lanes(p->seed, pixel, s);
        ST_VSTORE(ST_W, ST_TO_FLOAT(ST_W, px) + st_rng_unit_lanes(key, (st_lu)0u), l->fx);
        ST_VSTORE(ST_W, ST_TO_FLOAT(ST_W, py) + st_rng_unit_lanes(key, (st_lu)1u), l->fy);
        ST_VSTORE(ST_W, pixel, l->pixel);
        ST_VSTORE(ST_W, s, l->index);
        ST_VSTORE(ST_W, key, l->key);
        ST_VSTORE(ST_W, (st_lu)0u, l->word);
        return;
    }
    st_u32 x[ST_W], y[ST_W], si[ST_W];
    ST_VSTORE(ST_W, px, x);
    ST_VSTORE(ST_W, py, y);
    ST_VSTORE(ST_W, s, si);
    for (st_u32 k = 0; k < ST_W; k++)
        set_lane(l, k, k < n ? pixel_sample(p, pmj02, fis_cdf, x[k], y[k], si[k]) : none);
}

/* The camera rays through the lanes' film positions (camera.h) and fresh
 * paths for items first + k, k < n: beta = 1, bsdf pdf 0, radiance 0,
 * depth 0 (ST_PATH_DEAD for a dropped point outside the image), no rays
 * traced. */
ST_HOT void start_paths(const st_params *p, const st_sample_lanes *l, st_u32 first, st_u32 n,
                        __global st_ray *ray, __global st_path *path)
{
    st_lv3 o, d;
    st_camera_rays(&p->camera, p->width, p->height, ST_VLOAD(ST_W, l->fx), ST_VLOAD(ST_W, l->fy),
                   &o, &d);
    float ox[ST_W], oy[ST_W], oz[ST_W], dx[ST_W], dy[ST_W], dz[ST_W];
    ST_VSTORE(ST_W, o.x, ox);
    ST_VSTORE(ST_W, o.y, oy);
    ST_VSTORE(ST_W, o.z, oz);
    ST_VSTORE(ST_W, d.x, dx);
    ST_VSTORE(ST_W, d.y, dy);
    ST_VSTORE(ST_W, d.z, dz);
    ST_NO_VECTORIZE
    for (st_u32 k = 0; k < n; k++) {
        st_ray r = {{ox[k], oy[k], oz[k]}, INFINITY, {dx[k], dy[k], dz[k]}, 0.0f};
        ray[first + k] = r;
        st_path fresh = {{1.0f, 1.0f, 1.0f}, 0.0f, {0.0f, 0.0f, 0.0f},
                         st_sample_on_film(p, lane_sample(l, k)) ? 0u : ST_PATH_DEAD, 0u, 0u, 0.0f,
                         0u};
        path[first + k] = fresh;
    }
}

/* The first stage of a wave, ST_W items a work-item: work-item w takes
 * items first = ST_W w .. first + n - 1 (global size item_count / ST_W
 * rounded up), writes their samples (for shade and splat), their camera
 * rays and fresh paths. The samples stay in registers for the rays: a
 * second kernel that read them back (generate_camera_rays) ran more
 * instructions than this one on PoCL, and took longer. */
__kernel void generate_rays(ST_STAGE_PARAMS)
{
    st_u32 first = ST_W * ST_ITEM();
    if (first >= p.item_count)
        return;
    st_u32 n = min((st_u32)ST_W, p.item_count - first);
    st_sample_lanes l;
    item_samples(&p, tile, active, pixel_spp, pmj02, fis_cdf, p.first_item + first, n, &l);
    for (st_u32 k = 0; k < n; k++)
        sample[first + k] = lane_sample(&l, k);
    start_paths(&p, &l, first, n, ray, path);
}
