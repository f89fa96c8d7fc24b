/* st_lights.h — the emitters of a scene as next-event estimation chooses
 * them: its emissive triangles (in BVH order) with probability proportional
 * to area x emission weight, the emission weight being the emissive factor's
 * mean times, with an emissive texture, the texture averaged over the
 * triangle plus 1/256 of its brightest texel (so that the weight stays
 * positive wherever the texture may emit: the direct integrator needs that
 * to stay unbiased). A property of the loaded scene, the same for every
 * view. */
#ifndef ST_LIGHTS_H_HOST
#define ST_LIGHTS_H_HOST

#include "st_bvh.h"
#include "st_error.h"
#include "st_scene.h"
#include "st_shared.h"

typedef struct st_lights {
    st_u32 count;    /* emissive triangles */
    st_u32 *tri;     /* count: their BVH-order indices */
    float *cdf;      /* count: the CDF of choosing them, cdf[count - 1] = 1 */
    float *pdf_area; /* one per triangle: P(choose it) / its area; 0: not a light */
} st_lights;

/* Builds the table for the scene's triangles in BVH order (uv: their
 * st_tri_uv, for emissive textures). Arrays are never empty (one entry at
 * least, for the device). ST_ERR_NOMEM. */
st_status st_lights_build(const st_scene *s, const st_bvh *bvh, const st_tri_uv *uv,
                          st_lights *out, st_error *err);
void st_lights_free(st_lights *l);

/* |e1 x e2| (twice the triangle's area), the cross product taken in float as
 * the light table and the texture level of detail have always taken it. */
double st_triangle_cross_norm(const st_triangle *t);

#endif
