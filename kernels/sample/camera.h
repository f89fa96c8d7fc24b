/* camera.h — the camera's rays through points of the film, written once
 * over lanes (lanes.h): the generate stage (generate.cl) makes ST_W rays a
 * work-item, the host's trace benchmark (src/render/trace_bench.c) one at
 * a time in C, the same text at width 1.
 *
 * Pinhole (forward[3] = 0): from the eye through the point of the image
 * plane at distance 1 along forward, whose half height is origin[3] and
 * whose aspect is right[3]. Orthographic (forward[3] = 1): parallel rays
 * along forward from that point of the plane through the eye, origin[3]
 * then being the half height (glTF's ymag). */
#ifndef ST_CAMERA_H
#define ST_CAMERA_H

#ifndef __OPENCL_VERSION__
#include "st_shared.h"
#endif
#include "lanes.h"

/* The rays through film points (fx, fy), in pixels of a width x height
 * image (x right, y down): their origins *o and unit directions *d. Every
 * product has a lane for a factor, so each statement contracts alike at
 * every width (lanes.h). */
ST_HOT void st_camera_rays(const st_camera *c, st_u32 width, st_u32 height, st_lf fx, st_lf fy,
                           st_lv3 *o, st_lv3 *d)
{
    /* the point on the plane, in half heights from its centre */
    st_lf sx = (2.0f * fx / (float)width - 1.0f) * c->origin[3] * c->right[3];
    st_lf sy = (1.0f - 2.0f * fy / (float)height) * c->origin[3];
    st_lv3 eye = st_lv3_make(ST_LF(c->origin[0]), ST_LF(c->origin[1]), ST_LF(c->origin[2]));
    st_lv3 fw = st_lv3_make(ST_LF(c->forward[0]), ST_LF(c->forward[1]), ST_LF(c->forward[2]));
    st_lv3 side = st_lv3_make(sx * c->right[0] + sy * c->up[0], sx * c->right[1] + sy * c->up[1],
                              sx * c->right[2] + sy * c->up[2]);
    if (c->forward[3] > 0.5f) { /* orthographic */
        *o = st_lv3_add(eye, side);
        *d = fw;
        return;
    }
    st_lv3 dir = st_lv3_add(fw, side);
    *o = eye;
    *d = st_lv3_scale(dir, 1.0f / ST_SQRTF(st_lv3_dot(dir, dir)));
}

#endif
