/* layout.cl — reports the device's own sizes and offsets of the shared
 * structs, so tests/test_render.c can compare them with the host's
 * (st_shared.h static-asserts the host side). */
#include "st_shared.h"

#define ST_OFFSET(var, field) ((uint)((__private char *)&(var).field - (__private char *)&(var)))

/* Writes out[0..ST_LAYOUT_COUNT): see the order in test_render.c. */
__kernel void probe_layout(__global uint *out)
{
    st_params p;
    st_bvh_node n;
    out[0] = sizeof(st_bvh_node);
    out[1] = ST_OFFSET(n, bmax);
    out[2] = sizeof(st_triangle);
    out[3] = sizeof(st_tri_normals);
    out[4] = sizeof(st_material);
    out[5] = sizeof(st_camera);
    out[6] = sizeof(st_filter);
    out[7] = sizeof(st_params);
    out[8] = ST_OFFSET(p, filter);
    out[9] = ST_OFFSET(p, camera);
    out[10] = ST_OFFSET(p, width);
    out[11] = ST_OFFSET(p, tile_size);
    st_material m;
    st_texture t;
    out[12] = ST_OFFSET(m, base_color_tex);
    out[13] = sizeof(st_texture);
    out[14] = ST_OFFSET(t, offset);
    out[15] = sizeof(st_tri_uv);
    out[16] = sizeof(st_shading);
}
