/* generate.cl — the first stages of a wave: sample positions on the film, then
 * camera rays. Item i of a wave is render item g = first_item + i, with
 * pixel = g mod (width * height) and sample = g / (width * height). */
#include "st_shared.h"
#include "rng.h"
#include "samplers.h"

/* Writes: film[i] = the sample's film position in pixels (x right, y down). */
__kernel void generate_samples(const st_params p, __global float2 *film)
{
    st_u32 i = get_global_id(0);
    if (i >= p.item_count)
        return;
    st_u64 g = p.first_item + i;
    st_u32 npix = p.width * p.height;
    st_u32 pixel = (st_u32)(g % npix), s = (st_u32)(g / npix);
    st_u32 px = pixel % p.width, py = pixel / p.width;
    st_sample_id id = st_sample_begin(&p, px, py, s);
    film[i] = (float2)((float)px + st_sample_dim(&p, &id, 0u),
                       (float)py + st_sample_dim(&p, &id, 1u));
}

/* Reads film; writes the camera ray (ray_o.w = tmax) and resets the path:
 * beta = (1, 1, 1, bsdf pdf 0), radiance 0, depth 0. */
__kernel void generate_camera_rays(const st_params p, __global const float2 *film,
                                   __global float4 *ray_o, __global float4 *ray_d,
                                   __global float4 *beta, __global float4 *radiance,
                                   __global uint *depth)
{
    st_u32 i = get_global_id(0);
    if (i >= p.item_count)
        return;
    float2 f = film[i];
    float4 o = vload4(0, p.camera.origin), r = vload4(0, p.camera.right);
    float4 u = vload4(0, p.camera.up), fw = vload4(0, p.camera.forward);
    float sx = (2.0f * f.x / (float)p.width - 1.0f) * o.w * r.w;
    float sy = (1.0f - 2.0f * f.y / (float)p.height) * o.w;
    float3 d = normalize(fw.xyz + sx * r.xyz + sy * u.xyz);
    ray_o[i] = (float4)(o.xyz, INFINITY);
    ray_d[i] = (float4)(d, 0.0f);
    beta[i] = (float4)(1.0f, 1.0f, 1.0f, 0.0f);
    radiance[i] = (float4)(0.0f);
    depth[i] = 0u;
}
