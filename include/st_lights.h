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

/* Builds the table for the scene's triangles in BVH order (uv[k]: their
 * st_tri_uv of TEXCOORD_k, for emissive textures; uv[1] is read only where
 * a texture's uv_set is 1). Arrays are never empty (one entry at least, for
 * the device). ST_ERR_NOMEM. */
st_status st_lights_build(const st_scene *s, const st_bvh *bvh, const st_tri_uv *const uv[2],
                          st_lights *out, st_error *err);
void st_lights_free(st_lights *l);

/* Radius of the scene's bounding sphere (half the bounds' diagonal). */
double st_scene_radius(const st_scene *s);

/* The power a punctual light emits (W, the mean over RGB): a point light
 * 4π I; a spot 2π I ((1 - cos_inner) + (cos_inner - cos_outer) / 3), the
 * integral over the sphere of the extension's falloff t², t linear in the
 * cosine from the outer cone (0) to the inner one (1); a directional light
 * its irradiance times the area of the disk of the scene's bounding sphere,
 * π radius² (pbrt-v4's choice: what it sends through the scene). */
double st_punctual_power(const st_punctual *l, double radius);

/* Next-event estimation's choice among the punctual lights (st_params
 * punct_count, punct_share; the punct_cdf buffer): each with probability
 * proportional to its power. cdf has count entries, cdf[count - 1] = 1
 * (all zero when none emits); the return value is their total power. */
double st_punctual_cdf(const st_punctual *l, st_u32 count, double radius, float *cdf);

/* The probability that next-event estimation picks a punctual light rather
 * than the area lights and the environment: their share of the power, the
 * environment's as st_env_power gives it (st_envmap.h). 0 when the
 * punctual lights emit nothing, 1 when only they emit. */
float st_punctual_share(double punct_power, double area_power, double env_power);

/* The probability that next-event estimation, having taken no punctual
 * light, samples the environment rather than the area lights
 * (st_shading.env_pick): its share of their power; 0 without an
 * environment, 1 without area lights (light_count emissive triangles). So
 * each of the three kinds is chosen with probability proportional to its
 * power. */
float st_env_pick(double area_power, double env_power, st_u32 light_count);

/* |e1 x e2| (twice the triangle's area), the cross product taken in float as
 * the light table and the texture level of detail have always taken it. */
double st_triangle_cross_norm(const st_triangle *t);

#endif
