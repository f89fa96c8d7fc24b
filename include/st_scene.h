/* st_scene.h — scene import: a glTF 2.0 file, or a built-in scene embedded in
 * the binary, flattened into world-space triangle arrays with materials,
 * textures, cameras and the environment light.
 *
 * What loads: the default scene of the file (scene 0 when none is named),
 * every node reachable from it through `children`, with TRS and matrix
 * transforms composed down the tree; of each mesh, the TRIANGLES (strips, fans) primitives
 * (mode 4, the default), indexed (u8/u16/u32) or not, with any byteStride,
 * POSITION, NORMAL (flat normals where missing), TEXCOORD_0 and TEXCOORD_1
 * (float or normalised integers; each texture reads the set it names). .gltf with external .bin files or data: URIs, and
 * .glb. Other primitive modes are skipped with a warning. Materials: base
 * colour, emissive (with KHR_materials_emissive_strength) and
 * metallic-roughness factors and textures (with KHR_texture_transform),
 * alphaMode and alphaCutoff; images decoded by stb_image (PNG, JPEG, ...).
 * KHR_materials_pbrSpecularGlossiness is converted to metallic-roughness.
 * Cameras: every perspective or orthographic camera node. Lights: every
 * KHR_lights_punctual light of a node (point, spot, directional). The rest
 * pose: skins posed by their joints' default transforms, morph targets at
 * their default weights, EXT_mesh_gpu_instancing instances flattened into
 * the triangle arrays (animations are not played: a warning).
 *
 * Invariants of a loaded scene: tri_count >= 1; every triangle is finite and
 * has non-zero area (the others are dropped and counted in `dropped`); shading
 * normals are unit length, and where a node's transform mirrors (negative
 * determinant) the winding was reversed, so the geometric normal
 * (v1 - v0) x (v2 - v0) faces the side the shading normals face, as it did in
 * the file; every tri_material is < material_count; every material texture
 * index is ST_NO_TEXTURE or < texture_count; every texture's mip chain lies
 * inside texels[0, texel_count); bounds hold every vertex; every camera's
 * forward and up are unit and orthogonal.
 *
 * Errors (st_error.h): ST_ERR_IO when the file itself cannot be read,
 * ST_ERR_FORMAT for anything malformed ("FILE: what is wrong", tinygltf's own
 * message included; a missing .bin, or an image a material uses that cannot
 * be read or decoded, is a format error), ST_ERR_USAGE for an unknown
 * built-in name, ST_ERR_NOMEM. Tests: tests/unit/test_scene.c, tests/device/test_texture.c,
 * tests/cli/test_khronos.sh. */
#ifndef ST_SCENE_H
#define ST_SCENE_H

#include "st_error.h"
#include "st_shared.h" /* st_u32, st_material, st_texture */

/* st_render_options.camera of the default framing (--camera auto). */
#define ST_CAMERA_AUTO (-2)

typedef struct st_scene_camera {
    float origin[3], forward[3], up[3]; /* world space, unit forward/up, orthogonal */
    float yfov;         /* perspective: vertical field of view, radians */
    float ymag;         /* orthographic: half the view's height (world units) */
    int orthographic;   /* 1: orthographic projection; 0: perspective */
    int from_file;      /* 1: a glTF camera node; 0: default framing */
} st_scene_camera;

/* Why a scene's default environment is on or off (st_scene.default_env). */
typedef enum st_env_default {
    ST_ENV_NOTHING_EMITS, /* on: nothing in the scene emits */
    ST_ENV_DIM_EMITTERS,  /* on: its emitters are no brighter than white */
    ST_ENV_OWN_LIGHTS,    /* off: lamps and punctual lights carry most of the power */
    ST_ENV_ENCLOSED,      /* off: the default camera sits inside a closed model */
    ST_ENV_DARK_VIEW,     /* dim: own lights carry most of the power but leave most of the
                             default view dark */
    ST_ENV_HEADLIGHT      /* off: nothing emits and the default camera sits inside a closed
                             model, where no sky reaches; a point light at that camera, as a
                             viewer's headlight, is added to the punctual lights */
} st_env_default;

/* A loaded scene; owns every array (st_scene_destroy frees them).
 * materials[i]: base_color = baseColorFactor (RGB, [3] = its alpha);
 * emission = emissiveFactor x emissiveStrength (RGB, [3] = 0); metallic,
 * roughness, alpha mode and cutoff as in the file; *_tex index `textures`. */
typedef struct st_scene {
    st_u32 tri_count;
    float *positions;      /* 9 floats per triangle: v0 v1 v2, world space */
    float *normals;        /* 9 floats per triangle: unit shading normals per vertex, world space */
    float *uvs;            /* 6 floats per triangle: TEXCOORD_0 (u, v) per vertex, 0 without */
    float *uvs1;           /* 6 floats per triangle: TEXCOORD_1 per vertex, 0 without; NULL
                              when no texture reads it (st_texture.uv_set 1) */
    float *tangents;       /* 12 floats per triangle: tangent xyz, handedness w per vertex
                              (st_tri_tangents; 0 without texture coordinates) */
    float *colors;         /* 12 floats per triangle: COLOR_0 RGBA per vertex (1 without) */
    st_u32 *tri_material;  /* material index per triangle (< material_count) */
    st_u32 material_count; /* >= 1: a default white (0.8) material is appended if the file has none or a primitive has none */
    st_material *materials;
    st_u32 texture_count;  /* texture descriptors (a texture as a material slot samples it) */
    st_texture *textures;
    st_u32 texel_count;    /* RGBA8 texels of every mip level of every texture */
    st_u32 *texels;
    st_scene_camera default_camera; /* the view of a render that names no camera:
                                       cameras[0], or the default framing */
    st_scene_camera auto_camera;    /* the default framing (--camera auto): the bounds seen
                                       from the front (+Z), a little above and to the side */
    st_u32 camera_count;   /* camera nodes, depth first in scene order */
    st_scene_camera *cameras;
    st_u32 punctual_count; /* KHR_lights_punctual lights, depth first in scene order */
    st_punctual *punctual; /* world space (st_shared.h) */
    float bounds_min[3], bounds_max[3];
    st_u32 dropped;        /* degenerate (zero-area) or non-finite triangles dropped */
    /* Power radiated by the emissive surfaces (W in the renderer's units:
     * π x area x mean of emissive factor x the emissive texture's mean) and
     * by the punctual lights (st_punctual_power), which punctual_power
     * holds alone. */
    double emitted_power, punctual_power;
    /* Uniform environment radiance (linear RGB) of a render that asks for
     * none (st_render_options.env): (1, 1, 1) or 0, as env_default says
     * why: on when nothing emits, or when the emitters are dim (emissive
     * factor x strength at most 1 in every channel: a screen, a label)
     * and carry more than half of the power; off when lamps (brighter
     * emitters) and punctual lights carry at least half of it, or when
     * the default camera sits inside a closed model; dim (0.25) when
     * those lights would leave more than half of the default view dark
     * (src/scene/dark_view.h). */
    float default_env[3];
    st_env_default env_default;
    /* 1: that environment is the default sky (st_envmap_sky: white above,
     * a grey ground below) scaled by default_env, where it is on; 0: none, or a
     * uniform one for the built-in scenes, whose figures assume it */
    int default_sky;
    st_u32 warning_count;  /* what was skipped, one line each ("FILE: ...") */
    char **warnings;
    char name[256];        /* the file path, or the built-in name */
} st_scene;

/* spec: NULL -> the built-in default "cornell-box"; a bare name without '/' and without a .gltf/.glb suffix -> a built-in scene
   (embedded in the binary); anything else -> a file path.
   Cameras: every camera node, depth first in scene order; it looks down its
   world -Z with +Y up (made orthogonal to forward), from its world
   translation. scene->default_camera is the first of them. Without one, the
   default framing (auto_camera): a perspective camera from glTF's front (+Z),
   a little above and to the right, looking at the bounds' centre, yfov 40
   degrees, at the distance where the bounding sphere fits the vertical field
   of view. A scene with no triangle left is ST_ERR_FORMAT.
   On success *out is a new scene (st_scene_destroy frees it); on error *out is
   NULL. */
st_status st_scene_load(const char *spec, st_scene **out, st_error *err);
void st_scene_destroy(st_scene *scene);           /* NULL: does nothing */

/* A hash of what was loaded (triangles, normals, uvs, tangents, colours, materials, textures and
 * their texels, cameras, punctual lights, the default environment), not of the path that named
 * it: `strata merge` compares it, so one scene reached by two paths is one
 * scene, and an edited file is another. zlib's CRC-32 (ISO 3309) over the
 * arrays' bytes in that order; every array the renderer reads belongs here.
 * Pure. Tests: test_scene.c scene_content_hash_*. */
st_u32 st_scene_content_hash(const st_scene *scene);

/* The camera of a view: cameras[index], or default_camera for index -1.
   The scene is not changed: a loaded scene is immutable, and every
   per-render choice travels in the render options.
   ST_ERR_USAGE when index >= camera_count (the message says how many). */
st_status st_scene_view_camera(const st_scene *scene, st_i32 index, st_scene_camera *out,
                               st_error *err);

/* A perspective camera at eye looking at target, yfov radians (0 < yfov <
   pi), with `up` (any vector not along the view) made orthogonal to the
   view as the image's up. ST_ERR_USAGE "look at ..." where eye and target
   coincide or up lies along the view; every value must be finite. Pure.
   Tests: test_scene.c look_at_*. */
st_status st_scene_look_at(const float eye[3], const float target[3], const float up[3],
                           float yfov, st_scene_camera *out, st_error *err);

/* Names of the built-in scenes, for --scene-list: fills up to max names, returns the count.
   The count returned is the number of names written (<= max). The names
   (embedded file names without .gltf/.glb, e.g. "cornell-box") are static
   strings, valid for the life of the program. */
st_u32 st_scene_builtin_names(const char **names, st_u32 max);

/* The mip chain of a width x height RGBA8 image (bytes R, G, B, A per texel,
   rows from the top), as packed texels (R | G << 8 | B << 16 | A << 24):
   level 0 = the image, level l + 1 = max(1, w_l / 2) x max(1, h_l / 2), each
   texel a weighted mean of level l around its centre: separable tent weights
   max(0, 1 - |d| / 2), d the distance in level-l texels, normalised (for an
   even size, [1 3 3 1] / 8), taps beyond the edge wrapped by wrap_s / wrap_t
   (ST_WRAP_*). With srgb, RGB are averaged in linear light (st_srgb_table,
   then re-encoded to the nearest byte); alpha and non-sRGB data are averaged
   as they are, rounded to the nearest byte. levels = 1 + floor(log2(max(w,
   h))). *out (malloc'd, the caller frees) receives st_scene_mip_texels(w, h)
   texels. ST_ERR_NOMEM; ST_ERR_USAGE for an empty image. */
st_status st_scene_build_mips(const unsigned char *rgba, st_u32 width, st_u32 height, int srgb,
                              st_u32 wrap_s, st_u32 wrap_t, st_u32 **out, st_u32 *levels,
                              st_error *err);
/* Texels in the mip chain of a width x height image (all levels). */
st_u64 st_scene_mip_texels(st_u32 width, st_u32 height);

#endif
