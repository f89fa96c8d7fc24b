/* gltf_shim.h — private C interface of the tinygltf shim (src/scene/gltf_*.cpp,
 * strata's C++ files; gltf_shim.cpp holds the entry points). Used only by
 * src/scene/scene.c.
 *
 * The shim parses one glTF 2.0 document (JSON .gltf or binary .glb, chosen by
 * the "glTF" magic of the bytes, not by the file name), validates every index,
 * accessor and bufferView range it uses, flattens the default scene (or
 * scene 0) into world-space triangles, and decodes (stb_image) the images its
 * materials use. Only plain C types cross this header: kernels/shared/st_shared.h
 * uses _Static_assert, which C++ does not accept. */
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
/* At most this many warnings are kept; a last one counts the rest. */
#define ST_GLTF_MAX_WARNINGS 32
/* At most this many triangles (EXT_mesh_gpu_instancing instances and nodes
 * sharing a mesh counted each time), checked before the triangle arrays are
 * allocated: each takes about 200 bytes of vertex data here and as much
 * again in the device's tree and buffers, so 2^24 is some 6 GB. A small
 * file that instances a large buffer many times would otherwise ask for
 * any amount. */
#define ST_GLTF_MAX_TRIANGLES (1u << 24)
/* At most this many materials in a file (checked in its JSON, before tinygltf makes an object of
 * each). */
#define ST_GLTF_MAX_MATERIALS (1u << 16)
/* At most this many vertices read by the import: each drawing of a mesh reads its primitives'
 * POSITION elements (and their other attributes), consecutive drawings of one mesh once. */
#define ST_GLTF_MAX_VERTEX_READS (1u << 26)
/* At most this many drawings of meshes (nodes and EXT_mesh_gpu_instancing instances): each
 * costs a matrix and more, even for a mesh without triangles. */
#define ST_GLTF_MAX_INSTANCES (1u << 20)
/* At most this many bytes of sparse accessors made dense, all of those the scene reads
 * together (an unread one is never expanded). */
#define ST_GLTF_MAX_SPARSE_BYTES (1u << 30)
/* At most this many texels in the images the textures use, all together (2^28: 1 GiB as RGBA,
 * more with mip maps), counted from the images' headers before any is decoded; an image of the
 * same bytes as another counts once (and is decoded once). */
#define ST_GLTF_TEXELS_LOG2 28
#define ST_GLTF_MAX_TEXELS ((size_t)1 << ST_GLTF_TEXELS_LOG2)

/* A material of the file (§3.9). Factors as in the file (defaults filled);
 * *_tex index st_gltf_data.textures, -1 for none. alpha_mode: 0 OPAQUE,
 * 1 MASK, 2 BLEND (the values of st_shared.h's ST_ALPHA_*). */
typedef struct st_gltf_material {
    float base_color[4];   /* baseColorFactor */
    float emission[3];     /* emissiveFactor x KHR_materials_emissive_strength */
    float metallic, roughness;
    float alpha_cutoff;    /* alphaCutoff, 0.5 by default */
    int alpha_mode;
    int base_color_tex, emission_tex, metallic_roughness_tex;
    float specular[4];     /* KHR_materials_specular: specularColorFactor RGB, specularFactor */
    float ior;             /* KHR_materials_ior, 1.5 by default */
    int unlit;             /* KHR_materials_unlit */
    int double_sided;      /* doubleSided (false by default: one-sided) */
    int specular_tex, specular_color_tex; /* specularTexture (A), specularColorTexture */
    int normal_tex;        /* normalTexture */
    float normal_scale;    /* normalTexture.scale, 1 by default */
    float transmission;    /* KHR_materials_transmission's transmissionFactor, 0 by default */
    int transmission_tex;  /* its transmissionTexture (R) */
    int thin_walled;       /* transmission without KHR_materials_volume (no interior) */
    float attenuation[4];  /* KHR_materials_volume: attenuationColor RGB (1) and
                              attenuationDistance (+infinity) */
    float clearcoat, clearcoat_roughness; /* KHR_materials_clearcoat's factors (0, 0) */
    int clearcoat_tex, clearcoat_roughness_tex; /* clearcoatTexture (R), ..RoughnessTexture (G) */
    int clearcoat_normal_tex;     /* clearcoatNormalTexture */
    float clearcoat_normal_scale; /* its scale, 1 by default */
    float sheen_color[3], sheen_roughness; /* KHR_materials_sheen's factors (0, 0) */
    int sheen_color_tex, sheen_roughness_tex; /* sheenColorTexture (sRGB RGB), ..RoughnessTexture (A) */
    float anisotropy, anisotropy_rotation; /* KHR_materials_anisotropy's strength and
                                              rotation (radians), 0 and 0 */
    int anisotropy_tex;    /* its anisotropyTexture (RG direction, B strength; linear) */
    float diffuse_trans[4]; /* KHR_materials_diffuse_transmission: colour (1, 1, 1) and
                               factor (0) */
    int diffuse_trans_tex, diffuse_trans_color_tex; /* their textures (A linear; sRGB RGB) */
    float iridescence[4];  /* KHR_materials_iridescence: factor (0), ior (1.3), thickness
                              minimum and maximum (100, 400 nm) */
    int iridescence_tex, iridescence_thickness_tex; /* their textures (R; G; linear) */
    float dispersion;      /* KHR_materials_dispersion: 20 / Abbe number (0) */
} st_gltf_material;

/* One texture reference as a material samples it (§3.8): an image, the
 * sampler's wrap modes and magFilter, the colour space of its slot and the
 * reference's KHR_texture_transform, (u', v') = (t0 u + t1 v + t2,
 * t3 u + t4 v + t5). Equal references share one entry. */
typedef struct st_gltf_texture {
    int image;          /* index into st_gltf_data.images */
    int srgb;           /* 1: base colour or emission; 0: metallic-roughness */
    int wrap_s, wrap_t; /* glTF codes: 10497 REPEAT, 33071 CLAMP_TO_EDGE, 33648 MIRRORED_REPEAT */
    int mag_nearest;    /* magFilter is NEAREST (9728) */
    float transform[6];
    int tex_coord;      /* the set it reads: 0 TEXCOORD_0, 1 TEXCOORD_1 (texCoord, or
                           KHR_texture_transform's texCoord where that names one) */
} st_gltf_texture;

/* A decoded image (only those a texture above uses): RGBA8, rows from the
 * top (glTF's uv (0, 0) is the first texel of the first row). Images no
 * texture uses keep width = height = 0 and rgba = NULL. */
typedef struct st_gltf_image {
    uint32_t width, height;
    unsigned char *rgba;
} st_gltf_image;

/* A camera node (§3.10): it looks down its local -Z with +Y up. */
typedef struct st_gltf_camera {
    float origin[3], forward[3], up[3]; /* world space; forward, up unit, orthogonal */
    int orthographic;
    float yfov;                         /* perspective: vertical field of view, radians */
    float ymag;                         /* orthographic: half the view's height */
} st_gltf_camera;

/* A KHR_lights_punctual light on a node of the scene: type 0 point, 1 spot,
 * 2 directional (st_shared.h's ST_PUNCT_*); at its node's world translation,
 * shining along the node's world -Z (unit); colour x intensity as in the
 * file; the spot's cone angles in radians. `range` is not read. */
typedef struct st_gltf_light {
    int type;
    float pos[3], dir[3];
    float color[3], intensity;
    float inner_cone, outer_cone;
} st_gltf_light;

/* The flattened default scene. Every array is malloc'd (free() releases it;
 * st_gltf_shim_release frees them all). Triangles that survive are finite
 * and have non-zero area; their shading normals are unit length. */
typedef struct st_gltf_data {
    size_t tri_count;       /* triangles kept */
    size_t dropped;         /* zero-area or non-finite triangles left out */
    float *positions;       /* 9 floats per triangle, world space */
    float *normals;         /* 9 floats per triangle, unit, world space */
    float *uvs;             /* 6 floats per triangle: TEXCOORD_0, 0 where a primitive has none */
    float *uvs1;            /* 6 floats per triangle: TEXCOORD_1, 0 where a primitive has none;
                               NULL when no texture reads TEXCOORD_1 */
    float *tangents;        /* 12 floats per triangle: world tangent xyz and handedness w per
                               vertex (TANGENT, or generated from the set the material's normal
                               map reads, TEXCOORD_0 without one; 0 without that set) */
    float *colors;          /* 12 floats per triangle: COLOR_0 RGBA per vertex, 1 without it */
    uint32_t *tri_material; /* index into materials, or ST_GLTF_NO_MATERIAL */
    size_t material_count;  /* the file's materials, all of them */
    st_gltf_material *materials;
    size_t texture_count;   /* distinct texture references of the materials */
    st_gltf_texture *textures;
    size_t image_count;     /* the file's images (decoded where used) */
    st_gltf_image *images;
    size_t camera_count;    /* camera nodes, depth first in scene order */
    st_gltf_camera *cameras;
    size_t light_count;     /* KHR_lights_punctual lights of nodes, depth first in scene order */
    st_gltf_light *lights;
    size_t warning_count;   /* things skipped, one line each (no file name) */
    char **warnings;
} st_gltf_data;

/* Parses `size` bytes of a glTF document and fills *out (zeroed first).
 * `label` heads every error message ("box.gltf: accessor 3: ..."). External
 * URIs resolve against `base_dir` ("" = the working directory); base_dir NULL
 * forbids every file access, so only data: URIs and the GLB chunk load.
 * Errors: ST_ERR_FORMAT for anything malformed (tinygltf's own message
 * included; an image that a material uses and that cannot be read or
 * decoded), ST_ERR_NOMEM. On error *out holds nothing to free. */
st_status st_gltf_shim_load(const char *label, const unsigned char *bytes, size_t size,
                            const char *base_dir, st_gltf_data *out, st_error *err);

/* Frees the arrays of *data and zeroes it. NULL: does nothing. */
void st_gltf_shim_release(st_gltf_data *data);

#ifdef __cplusplus
}
#endif

#endif
