/* st_scene.h — scene import: a glTF 2.0 file, or a built-in scene embedded in
 * the binary, flattened into world-space triangle arrays with materials and a
 * camera.
 *
 * What loads: the default scene of the file (scene 0 when none is named),
 * every node reachable from it through `children`, with TRS and matrix
 * transforms composed down the tree; of each mesh, the TRIANGLES primitives
 * (mode 4, the default), indexed (u8/u16/u32) or not, with any byteStride.
 * .gltf with external .bin files or data: URIs, and .glb. Other primitive
 * modes are skipped; textures are not read.
 *
 * Invariants of a loaded scene: tri_count >= 1; every triangle is finite and
 * has non-zero area (the others are dropped and counted in `dropped`); shading
 * normals are unit length, and where a node's transform mirrors (negative
 * determinant) the winding was reversed, so the geometric normal
 * (v1 - v0) x (v2 - v0) faces the side the shading normals face, as it did in
 * the file; every tri_material is < material_count; bounds hold every vertex;
 * camera.forward and camera.up are unit and orthogonal.
 *
 * Errors (st_error.h): ST_ERR_IO when the file itself cannot be read,
 * ST_ERR_FORMAT for anything malformed ("FILE: what is wrong", tinygltf's own
 * message included; a missing .bin is a format error), ST_ERR_USAGE for an
 * unknown built-in name, ST_ERR_NOMEM. Tests: tests/test_scene.c. */
#ifndef ST_SCENE_H
#define ST_SCENE_H

#include "st_error.h"
#include "st_shared.h" /* st_u32, st_material {base_color[4], emission[4]} */

typedef struct st_scene_camera {
    float origin[3], forward[3], up[3]; /* world space, unit forward/up, orthogonal */
    float yfov;                         /* vertical field of view, radians */
    int from_file; /* 1: a glTF perspective camera node; 0: default framing */
} st_scene_camera;

/* A loaded scene; owns every array (st_scene_destroy frees them).
 * materials[i].base_color = baseColorFactor (RGB, [3] = its alpha);
 * materials[i].emission = emissiveFactor x emissiveStrength (RGB, [3] = 0). */
typedef struct st_scene {
    st_u32 tri_count;
    float *positions;      /* 9 floats per triangle: v0 v1 v2, world space */
    float *normals;        /* 9 floats per triangle: unit shading normals per vertex, world space */
    st_u32 *tri_material;  /* material index per triangle (< material_count) */
    st_u32 material_count; /* >= 1: a default white (0.8) material is appended if the file has none or a primitive has none */
    st_material *materials;
    st_scene_camera camera;
    float bounds_min[3], bounds_max[3];
    st_u32 dropped;        /* degenerate (zero-area) or non-finite triangles dropped */
    char name[256];        /* the file path, or the built-in name */
} st_scene;

/* spec: NULL -> the built-in default "cornell-box"; a bare name without '/' and without a .gltf/.glb suffix -> a built-in scene
   (embedded in the binary); anything else -> a file path.
   The camera is the first node, depth first in scene order, holding a
   perspective camera: origin = the node's world translation, forward = its
   world -Z axis, up = its world +Y axis made orthogonal to forward. Without
   one, a default camera looks along -Z from the +Z side of the bounds, yfov
   40 degrees, at the distance where the bounding sphere fits the vertical
   field of view. A scene with no triangle left is ST_ERR_FORMAT.
   On success *out is a new scene (st_scene_destroy frees it); on error *out is
   NULL. */
st_status st_scene_load(const char *spec, st_scene **out, st_error *err);
void st_scene_destroy(st_scene *scene);           /* NULL: does nothing */
/* Names of the built-in scenes, for --scene-list: fills up to max names, returns the count.
   The count returned is the number of names written (<= max). The names
   (embedded file names without .gltf/.glb, e.g. "cornell-box") are static
   strings, valid for the life of the program. */
st_u32 st_scene_builtin_names(const char **names, st_u32 max);

#endif
