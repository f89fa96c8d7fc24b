/* leaf_probe.cl — the vector leaf tests of trace.h (st_leaf_closest,
 * st_leaf_any) beside the scalar loop they replace (st_intersect_triangle
 * over the leaf's triangles in order), compiled by the device's own compiler
 * with the same contraction, so that tests/device/test_leaf.c can check them equal
 * bit for bit. Not a stage of the renderer. */
#include "st_shared.h"
#include "trace.h"

/* Work-item i = r * slots + s: ray r against leaf slot s (slot[s] = the wide
 * node's unit (trace.h: st_trace_node) * ST_BVH_WIDTH + k, a slot whose count[k] != 0). Writes out[4 i ..
 * 4 i + 3]: the closest hit by the vector test, the same by the scalar loop,
 * then the any hit by each; every search starts from the ray's tmax, and
 * a miss leaves {tmax, 0, 0, ST_NO_HIT}. */
__kernel void probe_leaf(__global const st_bvh_wide_node *nodes, __global const st_triangle *tris,
                         __global const st_ray *rays, __global const uint *slot, uint slots,
                         uint n, __global st_hit *out)
{
    uint i = ST_ITEM();
    if (i >= n * slots)
        return;
    st_ray r = rays[i / slots];
    uint node = slot[i % slots] / ST_BVH_WIDTH, k = slot[i % slots] % ST_BVH_WIDTH;
    const __global st_bvh_wide_node *wide = st_trace_node(nodes, node);
    uint count = wide->count[k];
    const __global float *l = st_trace_leaf(nodes, wide->child[k]);
    uint first = st_leaf_first(l, count);
    st_hit none = {r.tmax, 0.0f, 0.0f, ST_NO_HIT}, h[4] = {none, none, none, none};
    st_leaf_closest(l, count, &r, &h[0]);
    for (uint t = first; t < first + count; ++t)
        st_intersect_triangle(tris + t, &r, t, &h[1]);
    st_leaf_any(l, count, &r, &h[2]);
    for (uint t = first; t < first + count; ++t)
        if (st_intersect_triangle(tris + t, &r, t, &h[3]))
            break;
    for (int q = 0; q < 4; ++q)
        out[4 * i + q] = h[q];
}
