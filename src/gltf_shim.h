/* gltf_shim.h — private C interface of the tinygltf shim (src/gltf_shim.cpp),
 * the one C++ file of strata. Used only by src/scene.c.
 *
 * The shim parses one glTF 2.0 document (JSON .gltf or binary .glb, chosen by
 * the "glTF" magic of the bytes, not by the file name), validates every index,
 * accessor and bufferView range it uses, and flattens the default scene (or
 * scene 0) into world-space triangles. Only plain C types cross this header:
 * kernels/st_shared.h uses _Static_assert, which C++ does not accept. */
#ifndef ST_GLTF_SHIM_H
#define ST_GLTF_SHIM_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#include "st_error.h" /* inside extern "C": st_error.h has no guards of its own */

/* tri_material value of a triangle whose primitive names no material. */
#define ST_GLTF_NO_MATERIAL 0xffffffffu

/* The flattened default scene. Every array is malloc'd (free() releases it;
 * st_gltf_shim_release frees them all). Triangles that survive are finite
 * and have non-zero area; their shading normals are unit length. */
typedef struct st_gltf_data {
    size_t tri_count;       /* triangles kept */
    size_t dropped;         /* zero-area or non-finite triangles left out */
    float *positions;       /* 9 floats per triangle, world space */
    float *normals;         /* 9 floats per triangle, unit, world space */
    uint32_t *tri_material; /* index into materials, or ST_GLTF_NO_MATERIAL */
    size_t material_count;  /* the file's materials, all of them */
    float *materials;       /* 8 floats each: base colour RGBA, emission RGB, 0 */
    int has_camera;         /* 1: the first perspective camera node was found */
    float cam_origin[3], cam_forward[3], cam_up[3], cam_yfov;
} st_gltf_data;

/* Parses `size` bytes of a glTF document and fills *out (zeroed first).
 * `label` heads every error message ("box.gltf: accessor 3: ..."). External
 * URIs resolve against `base_dir` ("" = the working directory); base_dir NULL
 * forbids every file access, so only data: URIs and the GLB chunk load.
 * Errors: ST_ERR_FORMAT for anything malformed (tinygltf's own message
 * included), ST_ERR_NOMEM. On error *out holds nothing to free. */
st_status st_gltf_shim_load(const char *label, const unsigned char *bytes, size_t size,
                            const char *base_dir, st_gltf_data *out, st_error *err);

/* Frees the arrays of *data and zeroes it. NULL: does nothing. */
void st_gltf_shim_release(st_gltf_data *data);

#ifdef __cplusplus
}
#endif

#endif
