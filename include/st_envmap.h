/* st_envmap.h — an environment map read from an equirectangular EXR or
 * Radiance .hdr file (kernels/integrator/envmap.h: the convention and the sampling),
 * with the tables that importance-sample it by luminance and its integral
 * for the choice among lights by power. Host only; the renderer uploads it
 * (st_render_options.env_map). */
#ifndef ST_ENVMAP_H_HOST
#define ST_ENVMAP_H_HOST

#include "st_error.h"
#include "st_shared.h"

/* The most texels a map may have (w x h), the cap the glTF importer puts on
 * a texture's images. */
#define ST_ENV_MAX_TEXELS ((st_u64)1 << 26)

typedef struct st_envmap {
    st_u32 width, height;
    float *texels;   /* width x height x 4: linear RGB radiance and 0, row 0 at the top (+Y) */
    float *cdf;      /* height + width x height: the sampling table (kernels/integrator/envmap.h) */
    double integral; /* ∫ L dω over the sphere of the mean of R, G, B (texels constant over
                        their cells, each cell's exact solid angle) */
} st_envmap;

/* Reads path (.exr: its R, G and B channels, float or half; .hdr: stb_image's
 * Radiance reader) and builds the map (st_envmap_make). Errors name the file:
 * ST_ERR_USAGE (another extension), ST_ERR_IO (cannot open), ST_ERR_FORMAT
 * (not a float image, no R, G, B, a texel not finite, too many texels, no
 * light at all), ST_ERR_NOMEM. */
st_status st_envmap_load(const char *path, st_envmap **out, st_error *err);

/* The map of w x h texels of linear radiance rgb (3 floats a texel, row 0
 * at the top); negative values count as 0. name labels errors.
 * ST_ERR_FORMAT: a size of 0 or more than ST_ENV_MAX_TEXELS, a value that is
 * not finite, or a map that is black everywhere. */
st_status st_envmap_make(const float *rgb, st_u32 w, st_u32 h, const char *name,
                         st_envmap **out, st_error *err);
void st_envmap_free(st_envmap *m); /* NULL: does nothing */

/* The default sky (st_scene.default_sky): radiance 1 at the horizon falling
 * to ST_SKY_ZENITH straight up, L = 1 - (1 - ST_SKY_ZENITH) sin(elevation),
 * over a uniform grey ground of ST_SKY_GROUND below the horizon (+Y up), as
 * ST_SKY_WIDTH x ST_SKY_HEIGHT texels (each row its centre's value; the
 * horizon falls between two rows). So a white model shows its shape under
 * it: lit from above, darker below, against a brighter background.
 * ST_ERR_NOMEM. Tests: tests/device/test_envmap.c default_sky_*. */
#define ST_SKY_ZENITH 0.7f
#define ST_SKY_GROUND 0.3f
#define ST_SKY_WIDTH 4u
#define ST_SKY_HEIGHT 128u
st_status st_envmap_sky(st_envmap **out, st_error *err);

/* The power next-event estimation weighs an environment with (st_lights.h):
 * π radius² ∫ L dω (pbrt-v4's Phi of an infinite light: the power crossing the
 * disk of the scene's bounding sphere from every direction), with L the map's
 * (m not NULL) or the uniform env's mean of R, G, B (then 4π² radius² L). */
double st_env_power(const st_envmap *m, const float env[3], double radius);

#endif
