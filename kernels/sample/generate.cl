/* generate.cl — the first stages of a wave: sample positions on the film,
 * camera rays and fresh paths, in one kernel (generate_rays) or two
 * (generate_samples, generate_camera_rays; render.c chooses).
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

/* Render item g of a per-pixel sampler over the region (see the top): its
 * pixel (px, py) and sample index, as st_region_pixel and g mod n, g / n
 * give them, with two divides (one 64-bit, which x86 compilers run as a
 * 32-bit one while g < 2^32), no longer a third that split the pixel's
 * index back into (px, py). A multiply by a per-launch reciprocal was
 * tried (mul_hi(ulong)): PoCL emulates that with four multiplies, and
 * could not hoist the reciprocal's own divide out of its work-item loop,
 * so it ran far more instructions than the two divides (callgrind). */
static void region_item(const st_params *p, st_u64 g, st_u32 *px, st_u32 *py, st_u32 *s)
{
    st_u32 npix = p->region_w * p->region_h; /* the image, or a crop's window and apron */
    st_u32 j = (st_u32)(g % npix), row = j / p->region_w;
    *s = (st_u32)(g / npix);
    *px = p->region_x + (j - row * p->region_w);
    *py = p->region_y + row;
}

/* Render item g's sample: the film position, (pixel, sample index) and the
 * sampler's key and word for shade (st_sample_resume). With
 * filter importance sampling the sampler's two pixel dimensions are warped
 * through the CDF of |f| (their stratification carries over) into an offset
 * from the pixel centre. */
ST_HOT st_sample item_sample(const st_params *p, __global const st_tile_point *tile,
                             __global const st_u32 *active, __global const st_u32 *pmj02,
                             __global const float *fis_cdf, st_u64 g)
{
    if (ST_SAMPLER_IS_TILED(p->sampler))
        return tile_sample(p, tile, g);
    st_u32 px, py, s;
    if (p->adaptive_count) { /* a round of adaptive sampling (adaptive.cl) */
        st_u32 pixel = active[g % p->adaptive_count];
        s = p->adaptive_base + (st_u32)(g / p->adaptive_count);
        px = pixel % p->width;
        py = pixel / p->width;
    } else {
        region_item(p, g, &px, &py, &s);
    }
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

/* Writes item i's camera ray through smp's film position and resets its
 * path: beta = 1, bsdf pdf 0, radiance 0, depth 0 (ST_PATH_DEAD for a
 * dropped point outside the image), no rays traced. */
ST_HOT void start_path(const st_params *p, st_sample smp, st_u32 i, __global st_ray *ray,
                       __global st_path *path)
{
    float2 f = (float2)(smp.film[0], smp.film[1]);
    float4 o = vload4(0, p->camera.origin), r = vload4(0, p->camera.right);
    float4 u = vload4(0, p->camera.up), fw = vload4(0, p->camera.forward);
    float sx = (2.0f * f.x / (float)p->width - 1.0f) * o.w * r.w;
    float sy = (1.0f - 2.0f * f.y / (float)p->height) * o.w;
    /* orthographic (forward.w = 1): parallel rays from the image plane,
     * o.w = ymag, the half height */
    int ortho = fw.w > 0.5f;
    float3 d = ortho ? fw.xyz : normalize(fw.xyz + sx * r.xyz + sy * u.xyz);
    float3 start = ortho ? o.xyz + sx * r.xyz + sy * u.xyz : o.xyz;
    st_ray ray_out = {{start.x, start.y, start.z}, INFINITY, {d.x, d.y, d.z}, 0.0f};
    ray[i] = ray_out;
    st_path fresh = {{1.0f, 1.0f, 1.0f}, 0.0f, {0.0f, 0.0f, 0.0f},
                     st_sample_on_film(p, smp) ? 0u : ST_PATH_DEAD, 0u, 0u, 0.0f, 0u};
    path[i] = fresh;
}

/* The first stages in one work-item: item i's sample (written for shade and
 * splat), its camera ray and fresh path, the sample kept in registers
 * rather than written and read back by a second kernel. The samples, rays
 * and paths are those of generate_samples then generate_camera_rays, which
 * CPU devices run instead (render.c; test_render_paths.c). */
__kernel void generate_rays(ST_STAGE_PARAMS)
{
    st_u32 i = get_global_id(0);
    if (i >= p.item_count)
        return;
    st_sample smp = item_sample(&p, tile, active, pmj02, fis_cdf, p.first_item + i);
    sample[i] = smp;
    start_path(&p, smp, i, ray, path);
}

/* Writes sample[i] (item_sample): the first of the two kernels. */
__kernel void generate_samples(ST_STAGE_PARAMS)
{
    st_u32 i = get_global_id(0);
    if (i >= p.item_count)
        return;
    sample[i] = item_sample(&p, tile, active, pmj02, fis_cdf, p.first_item + i);
}

/* Reads sample; writes the camera ray and the fresh path (start_path): the
 * second of the two kernels. */
__kernel void generate_camera_rays(ST_STAGE_PARAMS)
{
    st_u32 i = get_global_id(0);
    if (i >= p.item_count)
        return;
    start_path(&p, sample[i], i, ray, path);
}
