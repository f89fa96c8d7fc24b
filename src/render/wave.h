/* wave.h — the wavefront state on the device: every buffer of
 * ST_WAVE_BUFFERS (st_shared.h), sized from its element type and extent,
 * and the one way the kernels' parameters are bound (ST_STAGE_PARAMS,
 * ST_FILM_PARAMS), so no kernel is bound argument by argument. */
#ifndef ST_WAVE_H
#define ST_WAVE_H

#include "st_device.h"
#include "st_error.h"
#include "st_shared.h"

#define ST_WAVE_ENUM(name, type, extent) ST_WAVE_##name,
enum { ST_WAVE_BUFFERS(ST_WAVE_ENUM) ST_WAVE_BUFFER_COUNT };
#define ST_SCENE_ENUM(name, type) ST_SCENE_##name,
enum { ST_SCENE_BUFFERS(ST_SCENE_ENUM) ST_SCENE_BUFFER_COUNT };

typedef struct st_wave {
    cl_mem b[ST_WAVE_BUFFER_COUNT];
    size_t items, pixels; /* work-items per wave; image pixels */
    int adaptive;         /* the ST_PER_ADAPTIVE buffers hold one per pixel */
    int ordered;          /* the ray order's buffers (order.cl) hold a wave's sort */
    st_device *dev;       /* that holds the buffers */
} st_wave;

/* Elements of buffer b (ST_WAVE_*) and their bytes. */
size_t st_wave_count(const st_wave *w, int b);
size_t st_wave_bytes(const st_wave *w, int b);

/* Allocates every buffer (the ray order's at full size where `ordered`);
 * the film, the pilot's film and moments, the tallies and the counters start
 * at zero. On error what was made is released. */
st_status st_wave_create(st_device *dev, size_t items, size_t pixels, int adaptive, int ordered,
                         st_wave *w, st_error *err);
void st_wave_destroy(st_wave *w);

/* Binds a stage kernel: p, sh, the scene buffers (in ST_SCENE_BUFFERS
 * order), then the wave's. */
st_status st_wave_bind_stage(cl_kernel k, const st_params *p, const st_shading *sh,
                             const cl_mem scene[ST_SCENE_BUFFER_COUNT], const st_wave *w,
                             st_error *err);
/* Binds a film kernel (resolve_film, adaptive.cl's): p, then the wave's buffers. */
st_status st_wave_bind_film(cl_kernel k, const st_params *p, const st_wave *w, st_error *err);
/* Sets only the st_params argument (argument 0), which changes per wave. */
st_status st_wave_set_params(cl_kernel k, const st_params *p, st_error *err);

#endif
