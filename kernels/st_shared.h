/* st_shared.h — every layout and constant that the host (C11) and the kernels
 * (OpenCL C 1.2) must agree on. It compiles under both compilers; the host
 * static-asserts each struct's size and offsets, and tests/test_layout.c asks the
 * device for its own. Only fixed-size types cross: no int/long/size_t/bool, no
 * float3 (OpenCL sizes it as four floats), no pointers. Arrays of 4 floats are
 * read with vload4 on the device.
 *
 * Pure functions that both sides must compute bit-identically live in the
 * companion headers beside it (rng.h, samplers.h, filters.h, fixed.h,
 * trace.h), each included after this one, so host tests run the device's own
 * code. */
#ifndef ST_SHARED_H
#define ST_SHARED_H

#ifdef __OPENCL_VERSION__
typedef uint st_u32;
typedef int st_i32;
typedef ulong st_u64;
typedef long st_i64;
#define ST_GLOBAL __global
#define ST_CONSTANT __constant
#define ST_STATIC_ASSERT(cond, msg)
#define ST_CLZ32(x) clz(x)
#define ST_CLZ64(x) ((st_u32)clz(x))
#define ST_LDEXPF(x, e) ldexp(x, e)
#else
#include <math.h>
#include <stddef.h>
#include <stdint.h>
typedef uint32_t st_u32;
typedef int32_t st_i32;
typedef uint64_t st_u64;
typedef int64_t st_i64;
#define ST_GLOBAL
#define ST_CONSTANT static const
#define ST_STATIC_ASSERT(cond, msg) _Static_assert(cond, msg)
#define ST_CLZ32(x) ((x) ? (st_u32)__builtin_clz(x) : 32u)
#define ST_CLZ64(x) ((x) ? (st_u32)__builtin_clzll(x) : 64u)
#define ST_LDEXPF(x, e) ldexpf(x, e)
#endif
typedef float st_f32;
#define ST_FN static inline

/* ---- constants ------------------------------------------------------------ */

#define ST_PI_F 3.14159265358979323846f

/* Samplers (render --sampler, pattern --sampler). POISSON and BEST_CANDIDATE
 * read a tile of points made on the host (ST_SAMPLER_IS_TILED). */
#define ST_SAMPLER_RANDOM 0u
#define ST_SAMPLER_UNIFORM 1u
#define ST_SAMPLER_STRATIFIED 2u
#define ST_SAMPLER_HALTON 3u
#define ST_SAMPLER_HAMMERSLEY 4u
#define ST_SAMPLER_POISSON 5u
#define ST_SAMPLER_BEST_CANDIDATE 6u
#define ST_SAMPLER_SOBOL 7u
#define ST_SAMPLER_COUNT 8u
#define ST_SAMPLER_IS_TILED(s) ((s) == ST_SAMPLER_POISSON || (s) == ST_SAMPLER_BEST_CANDIDATE)

/* Reconstruction filters (render --filter, strata filter). */
#define ST_FILTER_BOX 0u
#define ST_FILTER_TRIANGLE 1u
#define ST_FILTER_GAUSSIAN 2u
#define ST_FILTER_MITCHELL 3u
#define ST_FILTER_LANCZOS 4u
#define ST_FILTER_CATMULL_ROM 5u
#define ST_FILTER_BLACKMAN_HARRIS 6u
#define ST_FILTER_COUNT 7u

/* depth of a path that has ended (film sample still splatted) */
#define ST_PATH_DEAD 0xffffffffu

/* Reconstruction (render --reconstruction): splat every sample into every
 * pixel within the filter radius, or filter importance sampling (pbrt-v4):
 * draw the sample's offset from the pixel centre from |f| and add it, weighted
 * by the sign of f, to its own pixel only. */
#define ST_RECON_SPLAT 0u
#define ST_RECON_FIS 1u
/* Bins of the tabulated |f| whose CDF the FIS offsets are drawn from. */
#define ST_FIS_BINS 512u

#define ST_INTEGRATOR_DIRECT 0u
#define ST_INTEGRATOR_PATH 1u

/* Halton pixel mapping (pbrt-v4 HaltonSampler): the first two dimensions are
 * scaled by 2^j >= min(width, 128) and 3^k >= min(height, 128), so the pixel
 * pattern repeats every 128 x 243 pixels at most. */
#define ST_HALTON_MAX_RESOLUTION 128u

/* Film accumulation in 64-bit fixed point (see st_fixed.h for the proof of
 * headroom): a value v is stored as round(v * 2^24). */
#define ST_FIXED_SHIFT 24
#define ST_FIXED_SCALE 16777216.0f
/* Largest |f * L| one splat may add, per channel; larger values are clamped and
 * counted. 2^16 * 2^24 = 2^40 per splat: 2^23 - 1 splats per pixel stay below
 * the signed 64-bit limit 2^63 - 1 (2^23 would reach 2^63); the host refuses
 * renders whose spp * (pixels per filter footprint) could exceed
 * ST_FIXED_MAX_SPLATS. */
#define ST_SPLAT_MAX 65536.0f
#define ST_FIXED_MAX_SPLATS 8388607.0

/* Offsets of the film counters (render stats) in the stats buffer. */
#define ST_STAT_CLAMPED 0u   /* splat values clamped to ST_SPLAT_MAX */
#define ST_STAT_NONFINITE 1u /* samples with NaN/Inf radiance (dropped) */
#define ST_STAT_ZERO_WEIGHT 2u /* pixels whose filter weight sum was <= 0 */
#define ST_STAT_COUNT 4u

/* A sample counts the rays it traces in radiance.w: 1 per closest-hit ray,
 * ST_SHADOW_RAY_UNIT per shadow ray (exact in a float: at most 65 closest and
 * 64 shadow rays); splat_samples adds them up per work-item slot. */
#define ST_SHADOW_RAY_UNIT 65536.0f

/* ---- layouts ------------------------------------------------------------- */

/* BVH node, flattened depth first (pbrt's LinearBVHNode): an interior node's
 * first child follows it in the array and `offset` is the second child's index;
 * a leaf holds `count` triangles starting at `offset` in BVH order. `meta` =
 * count << 2 | split axis; count == 0 marks an interior node. */
typedef struct st_bvh_node {
    st_f32 bmin[3];
    st_u32 offset;
    st_f32 bmax[3];
    st_u32 meta;
} st_bvh_node;

/* A triangle prepared for Moller-Trumbore: v0 and the two edges e1 = v1 - v0,
 * e2 = v2 - v0. The fourth float of each is padding (0). */
typedef struct st_triangle {
    st_f32 v0[4];
    st_f32 e1[4];
    st_f32 e2[4];
} st_triangle;

/* Per-vertex shading normals of a triangle, in the same (BVH) order; the
 * fourth floats n0[3], n1[3], n2[3] hold the unit geometric normal, turned to
 * the side the shading normals face (computed once on the host). */
typedef struct st_tri_normals {
    st_f32 n0[4];
    st_f32 n1[4];
    st_f32 n2[4];
} st_tri_normals;

/* ---- textures and materials (scene import, shade.cl, texture.h) ------------ */

#define ST_NO_TEXTURE 0xffffffffu
/* Wrap modes of a texture coordinate (glTF sampler wrapS / wrapT). */
#define ST_WRAP_REPEAT 0u
#define ST_WRAP_CLAMP 1u
#define ST_WRAP_MIRROR 2u
/* st_texture.flags */
#define ST_TEX_SRGB 1u        /* RGB bytes sRGB-encoded (base colour, emission); alpha linear */
#define ST_TEX_MAG_NEAREST 2u /* the glTF sampler's magFilter is NEAREST */
/* Texture filtering (render --texture-filter): nearest texel of level 0,
 * bilinear in level 0, or trilinear between mip levels from the ray cone. */
#define ST_TEXFILTER_NONE 0u
#define ST_TEXFILTER_BILINEAR 1u
#define ST_TEXFILTER_TRILINEAR 2u
/* glTF alphaMode: MASK cuts out where alpha < alpha_cutoff; BLEND is
 * rendered as stochastic coverage (a ray passes with probability 1 - alpha). */
#define ST_ALPHA_OPAQUE 0u
#define ST_ALPHA_MASK 1u
#define ST_ALPHA_BLEND 2u

/* A glTF metallic-roughness material, shaded as Lambertian with albedo =
 * base colour x (1 - metallic) (roughness is kept, unused), emitting on the
 * side its shading normals face. Each factor is multiplied by its texture
 * where *_tex is a texture descriptor index (ST_NO_TEXTURE: none):
 * base_color_tex (sRGB RGB, linear alpha), emission_tex (sRGB),
 * metallic_roughness_tex (linear; metallic in B, roughness in G). */
typedef struct st_material {
    st_f32 base_color[4];  /* baseColorFactor: linear RGB and alpha */
    st_f32 emission[4];    /* emissiveFactor x emissiveStrength, RGB; [3] = 0 */
    st_f32 metallic, roughness;
    st_f32 alpha_cutoff;   /* ST_ALPHA_MASK: alpha below it is cut out */
    st_u32 alpha_mode;     /* ST_ALPHA_* */
    st_u32 base_color_tex, emission_tex, metallic_roughness_tex;
    st_u32 pad;
} st_material;

/* A texture as a material samples it: one image's mip chain (RGBA8 texels
 * packed R | G << 8 | B << 16 | A << 24 in one array; level 0 at `offset`,
 * each next level, max(1, w/2) x max(1, h/2), right after the previous one),
 * its sampler's wrap modes and the KHR_texture_transform of the reference:
 * (u', v') = (t[0] u + t[1] v + t[2], t[3] u + t[4] v + t[5]). lod_bias =
 * 1/2 log2(width x height x |det t|): the texel-area term of the ray-cone
 * level of detail that depends on the texture (texture.h, st_tex_lod). */
typedef struct st_texture {
    st_f32 transform[6];
    st_f32 lod_bias;
    st_u32 offset;
    st_u32 width, height, levels;
    st_u32 flags; /* ST_TEX_* */
    st_u32 wrap_s, wrap_t; /* ST_WRAP_* */
    st_u32 pad[2];
} st_texture;

/* Texture coordinates (TEXCOORD_0) of a triangle's vertices, in BVH order,
 * and lod = 1/2 log2(uv area / world area) (Akenine-Moller et al., "Texture
 * Level of Detail Strategies for Real-Time Ray Tracing", Ray Tracing Gems
 * 2019, eq. 34's Delta without the texture size; -64 for a triangle whose
 * UVs have no area). */
typedef struct st_tri_uv {
    st_f32 uv[6];
    st_f32 lod;
    st_f32 pad;
} st_tri_uv;

/* Scene-wide shading settings: a value argument of shade_hits. */
typedef struct st_shading {
    st_f32 env[4];          /* uniform environment radiance RGB (0: none); [3] = 0 */
    st_u32 texture_filter;  /* ST_TEXFILTER_* */
    st_u32 texture_count;
    st_u32 pad[2];
} st_shading;

/* Pinhole perspective camera: image-plane x maps to right * tan(fov/2) * aspect,
 * y to up * tan(fov/2). origin[3] = tan(yfov/2), right[3] = aspect (w/h).
 * forward[3] = 1 marks an orthographic camera: rays along forward from
 * origin + x * right * ymag * aspect + y * up * ymag, origin[3] = ymag. */
typedef struct st_camera {
    st_f32 origin[4];
    st_f32 right[4];
    st_f32 up[4];
    st_f32 forward[4];
} st_camera;

/* Reconstruction filter as a value: kind, radius r, and its parameters
 * (b, c for mitchell; sigma for gaussian; tau for lanczos). */
typedef struct st_filter {
    st_u32 kind;
    st_f32 radius;
    st_f32 b, c;
    st_f32 sigma, tau;
    st_f32 pad[2];
} st_filter;

/* Everything a render's kernels read besides the scene buffers; passed by
 * value to each kernel. A wave is `item_count` consecutive items of the
 * render's item space, item g = sample * npixels + pixel, starting at
 * `first_item`; the same (pixel, sample) always gives the same numbers,
 * whatever the wave size. */
typedef struct st_params {
    st_u64 first_item;
    st_u32 width, height;
    st_u32 spp;        /* samples per pixel of the whole render */
    st_u32 seed;
    st_u32 sampler;    /* ST_SAMPLER_* */
    st_u32 scramble;   /* 1: randomise (digit permutations, jitter), 0: none */
    st_u32 item_count;
    st_u32 integrator; /* ST_INTEGRATOR_* */
    st_u32 max_depth;  /* pbrt: vertices at which light is gathered */
    st_u32 light_count;
    st_u32 strat_nx, strat_ny;   /* stratified grid, nx * ny = spp */
    st_u32 halton_exp2, halton_exp3; /* 2^exp2, 3^exp3: Halton pixel scales */
    st_u32 halton_stride;        /* 2^exp2 * 3^exp3 */
    st_u32 halton_inv2, halton_inv3; /* multiplicative inverses (see st_sampling.h) */
    st_f32 ray_eps;              /* ray offset, scaled to the scene size */
    /* poisson and best-candidate: a toroidal tile of tile_size^2 pixels,
     * repeated tiles_x times across; this wave reads points tile_begin ..
     * tile_begin + tile_count - 1 of every repetition (see generate.cl) */
    st_u32 tile_size, tile_begin, tile_count, tiles_x;
    st_u32 reconstruction; /* ST_RECON_* */
    /* adaptive sampling: nonzero during a round over the active-pixel list
     * (item g: pixel active[g mod adaptive_count], sample adaptive_base +
     * g / adaptive_count); half_buffer: even samples also go to the half film */
    st_u32 adaptive_count, adaptive_base, half_buffer;
    st_u32 pad[4];
    st_filter filter;
    st_camera camera;
} st_params;

#ifndef __OPENCL_VERSION__
ST_STATIC_ASSERT(sizeof(st_bvh_node) == 32, "st_bvh_node: kernels read 32 bytes");
ST_STATIC_ASSERT(offsetof(st_bvh_node, bmax) == 16, "st_bvh_node.bmax moved");
ST_STATIC_ASSERT(sizeof(st_triangle) == 48, "st_triangle: 48 bytes");
ST_STATIC_ASSERT(sizeof(st_tri_normals) == 48, "st_tri_normals: 48 bytes");
ST_STATIC_ASSERT(sizeof(st_material) == 64, "st_material: 64 bytes");
ST_STATIC_ASSERT(offsetof(st_material, base_color_tex) == 48, "st_material.base_color_tex moved");
ST_STATIC_ASSERT(sizeof(st_texture) == 64, "st_texture: 64 bytes");
ST_STATIC_ASSERT(offsetof(st_texture, offset) == 28, "st_texture.offset moved");
ST_STATIC_ASSERT(sizeof(st_tri_uv) == 32, "st_tri_uv: 32 bytes");
ST_STATIC_ASSERT(sizeof(st_shading) == 32, "st_shading: 32 bytes");
ST_STATIC_ASSERT(sizeof(st_camera) == 64, "st_camera: 64 bytes");
ST_STATIC_ASSERT(sizeof(st_filter) == 32, "st_filter: 32 bytes");
ST_STATIC_ASSERT(offsetof(st_params, filter) == 128, "st_params.filter moved");
ST_STATIC_ASSERT(offsetof(st_params, camera) == 160, "st_params.camera moved");
ST_STATIC_ASSERT(sizeof(st_params) == 224, "st_params: 224 bytes");
#endif

#endif
