/* st_shared.h — every layout and constant that the host (C11) and the kernels
 * (OpenCL C 1.2) must agree on. It compiles under both compilers; the host
 * static-asserts each struct's size and offsets, and tests/device/test_layout.c asks the
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
typedef ushort st_u16;
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
typedef uint16_t st_u16;
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
/* A hot helper inlined into its caller: PoCL compiles with -Dinline=, so a
 * plain `static inline` stays a call on the device (and blocks its
 * vectoriser); the host's compiler inlines by itself. Only where it pays: a
 * build with every helper forced inline more than doubled PoCL's cold
 * build, and with the filter and fixed-point helpers forced inline
 * splat_samples ran more instructions. Oclgrind's
 * build defines ST_NO_FORCED_INLINE (device.c): it cannot run the
 * llvm.experimental.noalias.scope.decl that forced inlining leaves. */
#if defined(__OPENCL_VERSION__) && !defined(ST_NO_FORCED_INLINE)
#define ST_HOT static inline __attribute__((always_inline))
#else
#define ST_HOT static inline
#endif
/* A loop of constant trip count unrolled on the device, so that a private
 * struct or array it indexes becomes registers: PoCL gives each work-item
 * its own copy in memory of whatever is still an array when it makes the
 * work-group function. */
#ifdef __OPENCL_VERSION__
#define ST_UNROLL _Pragma("unroll")
#else
#define ST_UNROLL
#endif
/* A loop over a work-item's lanes that writes each lane's record (a struct)
 * to memory, kept a loop of plain stores: on AVX-512, LLVM's loop vectoriser
 * turns the stores of a struct's fields at its stride into scatters, one
 * per field, and PoCL's x86 tuning (skylake-avx512, also on AMD's Zen 4
 * and 5) deems them cheap; on a Zen 4 they took about two thirds of
 * generate_rays' time. */
#if defined(__OPENCL_VERSION__) && defined(__clang__)
#define ST_NO_VECTORIZE _Pragma("clang loop vectorize(disable)")
#else
#define ST_NO_VECTORIZE
#endif
/* A large helper kept a call on the device, so that its callers' many call
 * sites do not each get a copy (PoCL's build time). */
#ifdef __OPENCL_VERSION__
#define ST_COLD static __attribute__((noinline))
#else
#define ST_COLD static inline
#endif
/* A work-item's index in its launch, and its group's. st_device_launch lays a
 * launch wider than a row out as rows (dimension 1) of at most 2^15 work-items
 * (dimension 0): PoCL compiles a kernel once for grids under 2^16 work-items wide
 * and again for wider ones, and rows keep every launch on the first compile. */
#ifdef __OPENCL_VERSION__
#define ST_ITEM() ((st_u32)(get_global_id(1) * get_global_size(0) + get_global_id(0)))
#define ST_GROUP() ((st_u32)(get_group_id(1) * get_num_groups(0) + get_group_id(0)))
#endif

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
#define ST_SAMPLER_PADDED_SOBOL 7u /* per pixel, later pairs shuffled (pbrt's "paddedsobol") */
#define ST_SAMPLER_SOBOL 8u        /* one global sequence across the image (pbrt's "sobol") */
#define ST_SAMPLER_ZSOBOL 9u       /* Morton-ordered blocks (pbrt's "zsobol") */
#define ST_SAMPLER_JOINT_STRATIFIED 10u /* pixel and light pairs in one orthogonal array */
#define ST_SAMPLER_PMJ02 11u /* host-made progressive multi-jittered (0,2) tables */
#define ST_SAMPLER_PMJ02BN 12u /* the same, blue noise as well (pbrt-v4's "pmj02bn") */
#define ST_SAMPLER_COUNT 13u
/* pmj02, pmj02bn: ST_PMJ02_SETS sequences of 2^ceil(log2 spp) points, at most
 * 2^ST_PMJ02_MAX_LOG2 (the spp limit), uploaded per render (src/sampling/pmj02.c) */
#define ST_PMJ02_MAX_LOG2 12u
#define ST_PMJ02_SETS 16u
#define ST_SAMPLER_IS_TILED(s) ((s) == ST_SAMPLER_POISSON || (s) == ST_SAMPLER_BEST_CANDIDATE)
/* tiled samplers' later dimensions: ST_PMJ02_SETS tiles of one pixel (the
 * sampler's own pattern on the unit torus) of min(spp, ST_PAD_MAX_POINTS)
 * points each, uploaded in pmj02's place (src/sampling/pixel_tile.c, samplers.h) */
#define ST_PAD_MAX_POINTS 1024u

/* Reconstruction filters (render --filter, strata filter). */
#define ST_FILTER_BOX 0u
#define ST_FILTER_TRIANGLE 1u
#define ST_FILTER_GAUSSIAN 2u
#define ST_FILTER_MITCHELL 3u
#define ST_FILTER_LANCZOS 4u
#define ST_FILTER_CATMULL_ROM 5u
#define ST_FILTER_BLACKMAN_HARRIS 6u
#define ST_FILTER_COUNT 7u

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

/* Arbitrary output variables (--aov; st_params.aov): a render of one of them
 * takes the beauty render's samples (the same camera rays, pixel positions
 * and filter weights) and splats, in place of radiance, what the camera ray
 * meets first: the base colour (material x texture x vertex colour), the
 * shading normal (the vertex normals interpolated, turned to face the ray;
 * normal maps not applied), the hit point, or its distance from the camera
 * (along the ray: from the eye, or from an orthographic camera's plane).
 * A ray that meets nothing splats 0. Values keep their sign: resolve_film
 * clamps radiance alone. Tests: tests/device/test_aov.c. */
#define ST_AOV_NONE 0u
#define ST_AOV_ALBEDO 1u
#define ST_AOV_NORMAL 2u
#define ST_AOV_POSITION 3u
#define ST_AOV_DEPTH 4u
#define ST_AOV_COUNT 5u

/* Halton pixel mapping (pbrt-v4 HaltonSampler): the first two dimensions are
 * scaled by 2^j >= min(width, 128) and 3^k >= min(height, 128), so the pixel
 * pattern repeats every 128 x 243 pixels at most. */
#define ST_HALTON_MAX_RESOLUTION 128u

/* Film accumulation in 64-bit fixed point (see fixed.h for the proof of
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

/* Wide BVH node: ST_BVH_WIDTH children of the binary tree collapsed into
 * one (src/bvh/bvh_wide.c), their boxes as structure of arrays, lo[axis][child]
 * and hi[axis][child], so that one node is one vector slab test (trace.h:
 * float8 for 8, float4 for 4).
 * child[k] is where the child starts, in ST_LEAF_UNIT-byte units from the
 * start of the array: count[k] == 0, an interior node; count[k] = 1..4, a
 * leaf of that many triangles, its leaf block. An unused slot has an
 * inverted box (lo = FLT_MAX > hi = -FLT_MAX) that no ray enters.
 * The array holds the nodes depth first, the root at unit 0, each followed
 * by its leaf blocks in slot order and padded to a 64-byte line, where the
 * next node starts (st_bvh_wide_span): the lines a node's leaves need lie
 * right after its own, so that the prefetch of a pushed node covers them
 * (Embree's builder allocates leaves beside their node likewise). */
#define ST_BVH_WIDTH 8
typedef struct st_bvh_wide_node {
    st_f32 lo[3][ST_BVH_WIDTH];
    st_f32 hi[3][ST_BVH_WIDTH];
    st_u32 child[ST_BVH_WIDTH];
    st_u32 count[ST_BVH_WIDTH];
} st_bvh_wide_node;

/* A leaf block: a leaf's n = 1..4 triangles as structure of arrays, so that
 * one float4 Moller-Trumbore test meets them all (trace.h, st_leaf_closest),
 * and no larger than they need, so that a ray's leaf tests touch few cache
 * lines. ST_LEAF_ROWS rows of n floats, row r = ST_LEAF_V0 + a (v0 on axis
 * a), ST_LEAF_E1 + a or ST_LEAF_E2 + a (the edges), lane j = BVH triangle
 * first + j (st_triangle's v0, e1, e2 transposed); then two words: first,
 * and the lanes that are one-sided as bits (bit j: lane j's v0[3] != 0).
 * A block fills ST_LEAF_UNITS(n) units of ST_LEAF_UNIT bytes (a 2-triangle
 * leaf, the commonest, 80 bytes: two cache lines wherever it starts). The
 * blocks follow their node in the wide tree's own array, so that the
 * kernels take one buffer (src/bvh/bvh_wide.c). */
#define ST_LEAF_MAX 4 /* triangles per leaf at most */
#define ST_LEAF_ROWS 9
#define ST_LEAF_V0 0
#define ST_LEAF_E1 3
#define ST_LEAF_E2 6
#define ST_LEAF_UNIT 16u
#define ST_LEAF_UNITS(n) ((4u * (ST_LEAF_ROWS * (n) + 2u) + ST_LEAF_UNIT - 1u) / ST_LEAF_UNIT)

/* A triangle prepared for Moller-Trumbore: v0 and the two edges e1 = v1 - v0,
 * e2 = v2 - v0. v0[3] is ST_TRI_ONE_SIDED when rays hit it only from the
 * front (v0, v1, v2 counter-clockwise as seen: its material is not
 * doubleSided), 0 when from both sides; e1[3], e2[3] are padding (0). */
#define ST_TRI_ONE_SIDED 1.0f
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

/* Material flags (st_material.flags). */
#define ST_MAT_UNLIT 1u /* KHR_materials_unlit: shows its base colour, unlit */
#define ST_MAT_VERTEX_COLOR 2u /* some triangle of it has a COLOR_0 other than white */
#define ST_MAT_DOUBLE_SIDED 4u /* glTF doubleSided: its triangles are hit from both sides */
#define ST_MAT_SHEEN 8u        /* KHR_materials_sheen with a sheen colour other than black */
#define ST_MAT_TEXTURED 16u    /* some factor that material_at reads has a texture */
#define ST_MAT_THIN 32u        /* transmission without KHR_materials_volume: thin-walled */
#define ST_MAT_ANISO 64u       /* KHR_materials_anisotropy with a strength above 0 */
#define ST_MAT_DIFFUSE_TRANS 128u /* KHR_materials_diffuse_transmission, factor above 0 */
#define ST_MAT_IRIDESCENT 256u /* KHR_materials_iridescence with a factor above 0 */
#define ST_MAT_DISPERSIVE 512u /* KHR_materials_dispersion above 0 on a solid transmissive
                                  material (a thin wall bends no ray) */

/* A glTF metallic-roughness material (the BRDF: kernels/integrator/bsdf.h), emitting
 * on the side its shading normals face. Each factor is multiplied by its
 * texture where *_tex is a texture descriptor index (ST_NO_TEXTURE: none):
 * base_color_tex (sRGB RGB, linear alpha), emission_tex (sRGB),
 * metallic_roughness_tex (linear; metallic in B, roughness in G),
 * specular_tex (KHR_materials_specular's specularTexture, linear, A),
 * specular_color_tex (specularColorTexture, sRGB RGB), normal_tex (the
 * normal map, read in the frame of st_tri_tangents), transmission_tex
 * (KHR_materials_transmission's transmissionTexture, linear, R),
 * clearcoat_tex and clearcoat_roughness_tex (KHR_materials_clearcoat's
 * clearcoatTexture, R, and clearcoatRoughnessTexture, G; linear;
 * clearcoat_normal_tex its clearcoatNormalTexture, read as normal_tex),
 * sheen_color_tex and sheen_roughness_tex (KHR_materials_sheen's
 * sheenColorTexture, sRGB RGB, and sheenRoughnessTexture, linear A),
 * anisotropy_tex (KHR_materials_anisotropy's anisotropyTexture, linear: RG
 * the direction in the tangent frame as 2 c - 1, B the strength),
 * diffuse_trans_tex and diffuse_trans_color_tex
 * (KHR_materials_diffuse_transmission's diffuseTransmissionTexture, linear
 * A, and diffuseTransmissionColorTexture, sRGB RGB), iridescence_tex and
 * iridescence_thickness_tex (KHR_materials_iridescence's
 * iridescenceTexture, R, and iridescenceThicknessTexture, G; linear). */
typedef struct st_material {
    st_f32 base_color[4];  /* baseColorFactor: linear RGB and alpha */
    st_f32 emission[4];    /* emissiveFactor x emissiveStrength, RGB; [3] = 0 */
    st_f32 metallic, roughness;
    st_f32 alpha_cutoff;   /* ST_ALPHA_MASK: alpha below it is cut out */
    st_u32 alpha_mode;     /* ST_ALPHA_* */
    st_u32 base_color_tex, emission_tex, metallic_roughness_tex;
    st_u32 flags;          /* ST_MAT_* */
    st_f32 specular[4];    /* specularColorFactor RGB, specularFactor (1, 1, 1, 1) */
    st_f32 ior;            /* KHR_materials_ior, 1.5 */
    st_u32 specular_tex, specular_color_tex;
    st_u32 normal_tex;     /* normalTexture: tangent-space normals, linear RGB */
    st_f32 normal_scale;   /* normalTexture.scale: multiplies the normal's x and y */
    st_f32 transmission;   /* KHR_materials_transmission's transmissionFactor, 0 */
    st_u32 transmission_tex;
    st_f32 absorption[3];  /* KHR_materials_volume: the medium inside absorbs
                              exp(-absorption x distance) per channel, absorption =
                              -ln(attenuationColor) / attenuationDistance (0: clear) */
    st_f32 clearcoat, clearcoat_roughness; /* KHR_materials_clearcoat's factors, 0 and 0 */
    st_u32 clearcoat_tex, clearcoat_roughness_tex;
    st_u32 clearcoat_normal_tex;   /* the coat's own normal map (the base keeps normal_tex) */
    st_f32 clearcoat_normal_scale; /* its scale, as normal_scale */
    st_f32 sheen_color[3];  /* KHR_materials_sheen's sheenColorFactor, 0 (no sheen) */
    st_f32 sheen_roughness; /* its sheenRoughnessFactor, 0 */
    st_u32 sheen_color_tex, sheen_roughness_tex;
    st_f32 anisotropy[3];   /* KHR_materials_anisotropy: anisotropyStrength (0), and
                               cos and sin of anisotropyRotation (0), which turns the
                               direction counter-clockwise from the tangent */
    st_u32 anisotropy_tex;
    st_f32 diffuse_trans[4]; /* KHR_materials_diffuse_transmission: the colour
                                (1, 1, 1) and the factor (0), the share of the
                                Lambertian part that passes through */
    st_u32 diffuse_trans_tex, diffuse_trans_color_tex;
    st_f32 iridescence[4]; /* KHR_materials_iridescence: iridescenceFactor (0), the film's
                              ior (1.3), its thickness's minimum and maximum (100,
                              400 nm; without a thickness texture, the maximum) */
    st_u32 iridescence_tex, iridescence_thickness_tex;
    st_f32 dispersion; /* KHR_materials_dispersion: 20 / the Abbe number V_d (0: none) */
} st_material;

/* KHR_materials_dispersion's index of refraction for colour channel c (0 R,
 * 1 G, 2 B) of a material of ior n_d and dispersion 20 / V_d: Cauchy's
 * n(λ) = A + B / λ² through n_d at the d line with n_F - n_C = (n_d - 1) /
 * V_d, which the specification writes n(λ) = max(n_d + (n_d - 1) / V_d
 * (523655 / λ² - 1.5168), 1), λ in nm. An RGB renderer takes one
 * wavelength per channel: Fraunhofer's C line (656.3 nm, red), d line
 * (587.6 nm, yellow-green, as green) and F line (486.1 nm, blue), the
 * three that define V_d. Tests: test_bsdf.c dispersed_ior_*. */
ST_FN st_f32 st_dispersed_ior(st_f32 n_d, st_f32 dispersion, st_u32 c)
{
    st_f32 lambda = c == 0u ? 656.3f : c == 1u ? 587.6f : 486.1f;
    st_f32 n = n_d + (n_d - 1.0f) * (dispersion / 20.0f) * (523655.0f / (lambda * lambda) - 1.5168f);
    return n > 1.0f ? n : 1.0f;
}

/* Whether material m has a texture on a factor that the kernels'
 * material_at multiplies (the sheen's are read apart, by sheen_gather):
 * the scene sets ST_MAT_TEXTURED from it, so that material_at tests one
 * flag where it tested ten indices. */
ST_FN int st_material_reads_textures(const st_material *m)
{
    return m->base_color_tex != ST_NO_TEXTURE || m->emission_tex != ST_NO_TEXTURE ||
           m->metallic_roughness_tex != ST_NO_TEXTURE || m->specular_tex != ST_NO_TEXTURE ||
           m->specular_color_tex != ST_NO_TEXTURE || m->normal_tex != ST_NO_TEXTURE ||
           m->transmission_tex != ST_NO_TEXTURE || m->clearcoat_tex != ST_NO_TEXTURE ||
           m->clearcoat_roughness_tex != ST_NO_TEXTURE || m->clearcoat_normal_tex != ST_NO_TEXTURE;
}

/* A KHR_lights_punctual light in world space (st_lights.h). */
#define ST_PUNCT_POINT 0u
#define ST_PUNCT_SPOT 1u
#define ST_PUNCT_DIRECTIONAL 2u
typedef struct st_punctual {
    st_f32 pos[4];       /* xyz: position (point, spot); [3]: ST_PUNCT_* as a float */
    st_f32 dir[4];       /* xyz: unit direction it shines along (the node's -Z; spot,
                            directional); [3]: cos of the spot's outer cone angle */
    st_f32 intensity[4]; /* rgb: colour x intensity, radiant intensity (W/sr; point, spot)
                            or irradiance (directional); [3]: cos of the inner cone angle */
} st_punctual;

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
    st_u32 uv_set; /* the texture coordinates it reads: 0 TEXCOORD_0 (tri_uv), 1 TEXCOORD_1
                      (tri_uv1) */
    st_u32 pad;
} st_texture;

/* Per-vertex tangents of a triangle, in BVH order: xyz the unit tangent
 * (along increasing u) in world space, w the handedness: the bitangent is
 * w x cross(normal, tangent) (glTF's TANGENT; generated from the texture
 * coordinates where a mesh has none; all 0 without texture coordinates). */
typedef struct st_tri_tangents {
    st_f32 t0[4];
    st_f32 t1[4];
    st_f32 t2[4];
} st_tri_tangents;

/* Per-vertex colours (COLOR_0, linear RGBA; 1 without) of a triangle, in
 * BVH order: they multiply the base colour. */
typedef struct st_tri_colors {
    st_f32 c0[4];
    st_f32 c1[4];
    st_f32 c2[4];
} st_tri_colors;

/* Texture coordinates of a triangle's vertices (tri_uv: TEXCOORD_0, tri_uv1:
 * TEXCOORD_1), in BVH order, and lod = 1/2 log2(uv area / world area) (Akenine-Moller et al., "Texture
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
    /* KHR_lights_punctual: how many, and the probability that next-event
     * estimation picks one of them (their share of the emitted power;
     * 0 without them) rather than the area lights and environment */
    st_u32 punct_count;
    st_f32 punct_share;
    /* the environment map (--env FILE; kernels/integrator/envmap.h), env_size 0 x 0
     * without one (env is then the uniform radiance, else (1, 1, 1)); its
     * rotation about +Y as (cos, sin); and env_pick, the probability that
     * next-event estimation samples the environment rather than the area
     * lights when it takes no punctual light (by power; 1 without area
     * lights, 0 without an environment) */
    st_u32 env_size[2];
    st_f32 env_rot[2];
    st_f32 env_pick;
    st_u32 pad[3];
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
    /* adaptive sampling (adaptive.cl): nonzero during a round over the
     * active-pixel list (item g: pixel q = active[g mod adaptive_count],
     * sample pixel_spp[q] + adaptive_base + g / adaptive_count);
     * adaptive_scaled: each splat's weight is multiplied by splat_scale[its
     * pixel] (0 while the film holds the pilot's plain splats) */
    st_u32 adaptive_count, adaptive_base, adaptive_scaled;
    /* 1 where trace_rays takes its items in the order of the wave's
     * `order` (order.cl: sorted by ray) instead of the list's */
    st_u32 ordered;
    /* the vertex whose list of live paths a trace or shade launch runs over
     * (0: every item of the wave; st_live_list), and that list's length */
    st_u32 vertex, live_count;
    st_u32 sobol_log2; /* sobol, zsobol: 2^sobol_log2 >= width, height */
    /* tile-owned splat (film.cl): bins of bin_side^2 pixels, bins_x across,
     * bins in all; bins 0: the per-sample splat */
    st_u32 bin_side, bins_x, bins;
    /* halton, scrambled: 1 when the kernels' sampler tables (the pmj02
     * argument) hold the render's digit permutations (samplers.h,
     * st_sampling_halton_tables), 0: hash each digit; also keeps filter and
     * camera at a multiple of 16 bytes */
    st_u32 halton_tables;
    st_filter filter;
    st_camera camera;
    /* the pixels this launch covers, a rectangle of the width x height image
     * (all of it but for a --crop): generate_rays' item g is pixel
     * region_pixel(g mod region_w region_h), resolve_film's item i is
     * region_pixel(i) (st_region_pixel) */
    st_u32 region_x, region_y, region_w, region_h;
    /* 1 where trace_rays_last traces the last vertex's rays (the plan:
     * src/render/plan.c): shade then ends the paths whose last ray meets
     * none of the light list's triangles, in a scene without an
     * environment's light, before that ray is stored (shade.cl) */
    st_u32 last_lights;
    /* splat_tiles' bins: 0, all in one launch; c + 1, pass c of four, whose
     * bins' windows do not overlap (film.cl group_bin) */
    st_u32 bin_pass;
    /* 1 where next-event estimation picks its area light in lanes (the
     * plan: area lights alone, from a short list; shade.cl's area_lanes) */
    st_u32 area_lanes;
    st_u32 aov; /* ST_AOV_*: what the first vertex splats; NONE: radiance */
} st_params;

/* ---- the wavefront state and the film --------------------------------------
 * Every buffer the stage kernels share, declared once. The lists below
 * (X-macros, as Cycles' state_template.h) give each buffer's name, element
 * type and extent; the host derives sizes and allocation from them
 * (src/render/wave.c), the kernels their parameter lists (ST_STAGE_PARAMS), and
 * the layout probe (kernels/shared/layout.cl) checks every field on the device. */

#define ST_PATH_DEAD 0xffffffffu /* st_path.depth of a path that has ended */
#define ST_NO_HIT 0xffffffffu    /* st_hit.prim of a ray that left the scene */
/* The largest filter radius, in pixels, and the most pixel columns (or
 * rows) one sample reaches with it: |k + 0.5 - x| <= r holds for at most
 * 2r + 1 integers k. */
#define ST_FILTER_MAX_RADIUS_PX 8
#define ST_MAX_TAPS (2 * ST_FILTER_MAX_RADIUS_PX + 1)

/* A sample's place: film position in pixels (x right, y down; outside the
 * image for a dropped tile point), its pixel and its index in that pixel's
 * sequence (tiled samplers: its point in the tile); and the sampler's state
 * that generate made, so that shade resumes the sample without deriving it
 * again (samplers.h, st_sample_resume): key = st_rng_key(seed, pixel, index),
 * and word, what the sampler reads besides (st_sample_word: the index in
 * the sequence for Halton and global Sobol', the pixel's scramble key for
 * the samplers keyed per pixel, else 0). */
typedef struct st_sample {
    st_f32 film[2];
    st_u32 pixel, index;
    st_u32 key, word;
} st_sample;

/* A ray, the one of strata (the wavefront's, the traversal's, the tests'
 * and the benchmark's): from o along d (not necessarily of unit length)
 * up to t = tmax. path_length: for a path's ray, the distance the path
 * travelled before o, the ray cone's width there being the pixel's spread
 * times it (shade.cl, texture level of detail); 0 elsewhere. */
typedef struct st_ray {
    st_f32 o[3], tmax;
    st_f32 d[3], path_length;
} st_ray;

/* The closest hit of a ray: t, barycentrics u, v of v1 and v2 (the point is
 * v0 + u e1 + v e2) and the BVH-order triangle, ST_NO_HIT on a miss. */
typedef struct st_hit {
    st_f32 t, u, v;
    st_u32 prim;
} st_hit;

/* A path: throughput beta, the pdf of the BSDF sample that made its current
 * ray (for MIS at an emitter it reaches), the radiance gathered, its depth
 * (vertices shaded; ST_PATH_DEAD once ended) and the rays it traced. */
typedef struct st_path {
    st_f32 beta[3], bsdf_pdf;
    st_f32 radiance[3];
    st_u32 depth;
    st_u32 closest_rays, shadow_rays;
    st_f32 env_pdf; /* the pdf of next-event estimation's environment sample
                       (cos / π) for the current ray's direction, for MIS at a miss */
    st_u32 channel; /* 0, or 1 + the colour channel a dispersive surface chose for the
                       path (KHR_materials_dispersion: shade.cl vertex_gather) */
} st_path;

/* A shadow ray and what it adds to its path's radiance when nothing blocks
 * it; ray.tmax 0: this vertex made none. */
typedef struct st_shadow {
    st_ray ray;
    st_f32 contribution[3], pad;
} st_shadow;

/* Per work-item slot, summed over the waves (the same slot in every wave,
 * so no atomics): splats made, closest and shadow rays traced. */
typedef struct st_tally {
    st_u32 splats, closest_rays, shadow_rays, pad;
} st_tally;

/* Per bin of splat_tiles, summed over the waves: st_tally's counts of the
 * bin's samples, which splat_tiles adds once per work-item and wave instead
 * of a read and a write of each item's tally; 64-bit, as a bin holds the
 * samples of many pixels. */
typedef struct st_bin_tally {
    st_u64 splats, closest_rays, shadow_rays, pad;
} st_bin_tally;

/* The film's sums per pixel, 64-bit fixed point (fixed.h): Σ f L for R, G, B
 * and the weight Σ f. */
#define ST_FILM_SUMS 4
typedef struct st_film_pixel {
    st_i64 sum[ST_FILM_SUMS];
} st_film_pixel;

/* A resolved pixel: I = Σ f L / Σ f, and the weight Σ f. */
typedef struct st_pixel {
    st_f32 rgb[3], weight;
} st_pixel;

/* Counters of a render, atomically incremented by the kernels. */
typedef struct st_film_stats {
    st_u32 clamped;     /* splats whose value was clamped to ST_SPLAT_MAX */
    st_u32 nonfinite;   /* samples with NaN/Inf radiance (dropped), NaN pixels */
    st_u32 zero_weight; /* pixels whose filter weight sum was 0 */
    st_u32 pad;
} st_film_stats;

/* A key and its item, as the ray order's first pass leaves them (order.cl). */
typedef struct st_order_pair {
    st_u32 key, item;
} st_order_pair;

/* A point of a tiled sampler's tile, in pixels. */
typedef struct st_tile_point {
    st_f32 x, y;
} st_tile_point;

/* Extents: how many elements a buffer holds. */
#define ST_PER_ITEM 0     /* one per work-item of a wave */
#define ST_PER_PIXEL 1    /* one per image pixel */
/* Adaptive sampling's error estimate of a pixel (adaptive.cl, and the QMC
 * samplers' on the host, src/render/adaptive.c): per-sample standard
 * deviation over (μ² + ε²)^(γ / 2). γ = 0 would minimise the summed squared
 * error, γ = 1 the relative squared error (x − r)² / (r² + ε²); ¾ lies
 * between and, measured against ½ and 1 on the Cornell box and two Khronos
 * models, gained clearly by both. */
#define ST_ADAPTIVE_GAMMA 0.75f
#define ST_ADAPTIVE_EPS 0.1f
#define ST_PER_ADAPTIVE 2 /* one per pixel in an adaptive render, else one */
#define ST_PER_BIN 4      /* one per pixel, plus one: a bin's count or start (bins <= pixels) */
#define ST_ONE 3          /* one */

#define ST_LIVE_CHUNK 64u /* live_bits words per chunk of live.cl's scan */

/* The ray order (kernels/geom/order.h, order.cl): keys of ST_ORDER_KEY_BITS
 * bits, the origin's cell (ST_ORDER_ORIGIN_BITS per axis) above the
 * direction's (ST_ORDER_DIR_BITS per axis), sorted a digit of
 * ST_ORDER_DIGIT_BITS at a time over blocks of ST_ORDER_BLOCK positions.
 * order_count holds the wave's bounds (ST_ORDER_BOUNDS integers: the
 * largest origin coordinate per axis, the largest of its negation per axis,
 * then the same of the directions' octahedral coordinates x, y, each float
 * as st_order_monotone's integer, so that atomic_max gathers them; 0 lies
 * below every float's: none gathered), then from ST_ORDER_COUNTS on a count
 * per digit and block. */
#define ST_ORDER_ORIGIN_BITS 2u
#define ST_ORDER_DIR_BITS 5u
#define ST_ORDER_KEY_BITS 16u
#define ST_ORDER_DIGIT_BITS 8u
#define ST_ORDER_DIGITS (1u << ST_ORDER_DIGIT_BITS)
#define ST_ORDER_BLOCK 4096u
#define ST_ORDER_SAMPLE 256u /* the rays of a block that order_bounds looks at */
#define ST_ORDER_BOUNDS 10u
/* A dead path's marks: on its key (order_key, order_pair: above the key's
 * bits, which the digits do not read) and on its entry of `order` (above
 * any item), so that the sorted trace skips it without reading its path,
 * and order_ray keeps no ray for it. */
#define ST_ORDER_DEAD_KEY (1u << ST_ORDER_KEY_BITS)
#define ST_ORDER_DEAD 0x80000000u
#define ST_ORDER_COUNTS 16u
#define ST_PER_ORDER 5 /* order_count's: ST_ORDER_COUNTS + a digit's count per block */
#define ST_PER_ORDER_ITEM 6 /* one per work-item */
/* (both where the wave sorts its rays, st_wave.ordered; one element otherwise) */

/* The per-render state: X(name, element type, extent). */
#define ST_WAVE_BUFFERS(X)                                                                  \
    X(sample, st_sample, ST_PER_ITEM)                                                       \
    X(ray, st_ray, ST_PER_ITEM)                                                        \
    X(hit, st_hit, ST_PER_ITEM)                                                             \
    X(path, st_path, ST_PER_ITEM)                                                           \
    X(shadow, st_shadow, ST_PER_ITEM)                                                   \
    X(tally, st_tally, ST_PER_ITEM)                                                         \
    X(bin_tally, st_bin_tally, ST_PER_BIN) /* splat_tiles' counts per bin */                \
    X(live_a, st_u32, ST_PER_ITEM)   /* the items of the paths alive at odd vertices */     \
    X(live_b, st_u32, ST_PER_ITEM)   /* ... at even vertices but 0 (live.cl) */             \
    X(live_bits, st_u32, ST_PER_ITEM) /* shade's work-item g: bit k, item k goes on */      \
    X(live_sum, st_u32, ST_PER_ITEM) /* per chunk of live_bits: live items, then start */   \
    X(live_total, st_u32, ST_ONE)    /* the paths alive at the next vertex */               \
    X(bin_count, st_u32, ST_PER_BIN) /* samples per bin; 0 between waves (film.cl) */      \
    X(bin_start, st_u32, ST_PER_BIN) /* a bin's first index into bin_item */               \
    X(bin_item, st_u32, ST_PER_ITEM) /* the wave's items, ordered by bin */                \
    X(edge, st_u32, ST_PER_ITEM) /* splat_pixels' work-item j: 1, samples on other pixels */ \
    X(order, st_u32, ST_PER_ORDER_ITEM) /* the items of a trace in ray order (order.cl) */      \
    X(order_key, st_u32, ST_PER_ORDER_ITEM) /* position g's key (order.h) */                    \
    X(order_pair, st_order_pair, ST_PER_ORDER_ITEM) /* the order by the low digit */            \
    X(order_ray, st_ray, ST_PER_ORDER_ITEM) /* the rays of order, in its order */                \
    X(order_count, st_u32, ST_PER_ORDER) /* bounds, and counts then starts (order.cl) */  \
    X(film, st_film_pixel, ST_PER_PIXEL)                                                    \
    X(pilot_film, st_film_pixel, ST_PER_ADAPTIVE) /* the adaptive pilot's splats */        \
    X(moments, st_pixel, ST_PER_ADAPTIVE) /* so far: Σ Y, Σ Y², samples (adaptive.cl) */   \
    X(splat_scale, st_f32, ST_PER_ADAPTIVE) /* adaptive: weight of the pixel's samples */  \
    X(pixel_spp, st_u32, ST_PER_ADAPTIVE)   /* adaptive: a pixel's samples so far */       \
    X(active, st_u32, ST_PER_ADAPTIVE)      /* pixels by falling sample count */           \
    X(stats, st_film_stats, ST_ONE)                                                         \
    X(image, st_pixel, ST_PER_PIXEL)

/* The scene, uploaded once per renderer, and the inputs made per render
 * (a tiled sampler's points, filter importance sampling's CDF of |f|,
 * pmj02's tables):
 * X(name, element type). */
#define ST_SCENE_BUFFERS(X)                                                                 \
    X(nodes, st_bvh_wide_node)                                                                  \
    X(tris, st_triangle)                                                                    \
    X(normals, st_tri_normals)                                                              \
    X(tri_material, st_u32)                                                                 \
    X(materials, st_material)                                                               \
    X(light_tri, st_u32)                                                                    \
    X(light_cdf, st_f32)                                                                    \
    X(light_pdf, st_f32) /* P(choose the triangle) / its area; 0: not a light */           \
    X(punctual, st_punctual)                                                                \
    X(punct_cdf, st_f32) /* CDF of choosing among the punctual lights, by power */          \
    X(tri_uv, st_tri_uv)                                                                    \
    X(tri_uv1, st_tri_uv) /* TEXCOORD_1 (one entry when no texture reads it) */            \
    X(tangents, st_tri_tangents)                                                            \
    X(colors, st_tri_colors)                                                                \
    X(textures, st_texture)                                                                 \
    X(texels, st_u32)                                                                       \
    X(tile, st_tile_point)                                                                  \
    X(fis_cdf, st_f32)                                                                      \
    X(pmj02, st_u32) /* pmj02's tables: x, y words of each point (st_sampling_pmj02) */    \
    X(env_texels, st_f32) /* the environment map's RGB0 texels (st_render_options.env_map) */ \
    X(env_cdf, st_f32)    /* its sampling table (kernels/integrator/envmap.h) */

/* A hint that `p` will be read soon, so that its cache line is on its way
 * while the traversal works elsewhere: the wide nodes and triangles of a big
 * mesh do not fit in the caches, and a random ray waits on memory more than
 * it computes (perf on the 327,680-triangle icosphere: over half of
 * trace_rays' samples on the first load of a node and of a leaf's first
 * triangle), and a splat reads its samples where the stages before left
 * them. OpenCL's own prefetch() is a no-op on PoCL, so a kernel uses
 * clang's __builtin_prefetch, but only where the host asks for it with
 * -DST_PREFETCH_HINTS (device.c: PoCL's CPU devices, where it was measured):
 * other OpenCL compilers need not know it, and Oclgrind cannot run the
 * llvm.prefetch clang makes of it. The host's gcc has it too. Elsewhere
 * nothing. */
#if defined(__OPENCL_VERSION__) && defined(ST_PREFETCH_HINTS) && defined(__has_builtin)
#if __has_builtin(__builtin_prefetch)
#define ST_PREFETCH(p) __builtin_prefetch(p)
#endif
#endif
#if !defined(ST_PREFETCH) && defined(__GNUC__) && !defined(__OPENCL_VERSION__)
#define ST_PREFETCH(p) __builtin_prefetch(p)
#endif
#ifndef ST_PREFETCH
#define ST_PREFETCH(p) ((void)0)
#endif

/* Whether wave item i lies in region pixel (first_item + i) mod npix, as
 * generate.cl places a per-pixel sampler's items outside adaptive rounds:
 * the splat then finds a pixel's items without sorting them (film.cl). */
static inline int st_items_by_pixel(const st_params *p)
{
    return !ST_SAMPLER_IS_TILED(p->sampler) && !p->adaptive_count;
}

#ifdef __OPENCL_VERSION__
/* Index in the image of the region's pixel i (row-major in the region). */
static st_u32 st_region_pixel(const st_params *p, st_u32 i)
{
    return (p->region_y + i / p->region_w) * p->width + p->region_x + i % p->region_w;
}

/* Whether a sample lies on the image (a tiled sampler's point may not: its
 * tile repeats past the image's edge). */
static int st_sample_on_film(const st_params *p, st_sample s)
{
    return !ST_SAMPLER_IS_TILED(p->sampler) ||
           (s.film[0] < (float)p->width && s.film[1] < (float)p->height);
}

/* A trace or shade launch runs over the paths alive at its vertex, p->vertex:
 * at vertex 0 over every item of the wave (position i is item i), then over
 * the list that live.cl made after the vertex before, in item order: live_a
 * at odd vertices, live_b at even ones. st_live_list gives that list (none at
 * vertex 0), st_live_item the item at position i, st_live_count how many. */
static __global const st_u32 *st_live_list(const st_params *p, __global const st_u32 *live_a,
                                           __global const st_u32 *live_b)
{
    return p->vertex == 0u ? 0 : (p->vertex & 1u) ? live_a : live_b;
}

static st_u32 st_live_item(__global const st_u32 *list, st_u32 i)
{
    return list ? list[i] : i;
}

static st_u32 st_live_count(const st_params *p)
{
    return p->vertex == 0u ? p->item_count : p->live_count;
}

#define ST_WAVE_PARAM(name, type, extent) , __global type *name
#define ST_SCENE_PARAM(name, type) , __global const type *name
/* Every stage kernel's parameters, in the order the host binds them: the
 * render's values, the scene, then the wavefront state. */
#define ST_STAGE_PARAMS \
    const st_params p, const st_shading sh ST_SCENE_BUFFERS(ST_SCENE_PARAM) ST_WAVE_BUFFERS(ST_WAVE_PARAM)
/* The film kernels' (resolve, adaptive.cl): values and the state. */
#define ST_FILM_PARAMS const st_params p ST_WAVE_BUFFERS(ST_WAVE_PARAM)
#endif


/* Every shared struct and field, for the layout probe (kernels/shared/layout.cl
 * reports the device's sizes and offsets; tests/device/test_layout.c compares them
 * with the host's). */
#define ST_LAYOUT_STRUCTS(X)                                                                \
    X(st_bvh_node) X(st_bvh_wide_node) X(st_triangle) X(st_tri_normals) X(st_material)         \
    X(st_texture)                                                                           \
    X(st_tri_uv) X(st_shading) X(st_camera) X(st_filter) X(st_params) X(st_sample)          \
    X(st_tri_tangents) X(st_tri_colors) X(st_punctual)                                      \
    X(st_ray) X(st_hit) X(st_path) X(st_shadow) X(st_tally) X(st_bin_tally) X(st_film_pixel) \
    X(st_pixel) X(st_film_stats) X(st_tile_point)
#define ST_LAYOUT_FIELDS(X)                                                                 \
    X(st_bvh_node, bmin) X(st_bvh_node, offset) X(st_bvh_node, bmax) X(st_bvh_node, meta)   \
    X(st_bvh_wide_node, lo) X(st_bvh_wide_node, hi)                                         \
    X(st_bvh_wide_node, child) X(st_bvh_wide_node, count)                                   \
    X(st_triangle, v0) X(st_triangle, e1) X(st_triangle, e2)                                \
    X(st_tri_normals, n0) X(st_tri_normals, n1) X(st_tri_normals, n2)                       \
    X(st_material, base_color) X(st_material, emission) X(st_material, metallic)            \
    X(st_material, roughness) X(st_material, alpha_cutoff) X(st_material, alpha_mode)       \
    X(st_material, base_color_tex) X(st_material, emission_tex)                             \
    X(st_material, metallic_roughness_tex) X(st_material, flags) X(st_material, specular)   \
    X(st_material, ior) X(st_material, specular_tex) X(st_material, specular_color_tex)     \
    X(st_material, normal_tex) X(st_material, normal_scale) X(st_material, transmission)    \
    X(st_material, transmission_tex) X(st_material, absorption) X(st_material, clearcoat)   \
    X(st_material, clearcoat_roughness) X(st_material, clearcoat_tex)                       \
    X(st_material, clearcoat_roughness_tex) X(st_material, clearcoat_normal_tex)            \
    X(st_material, clearcoat_normal_scale) X(st_material, sheen_color)                      \
    X(st_material, sheen_roughness) X(st_material, sheen_color_tex)                         \
    X(st_material, sheen_roughness_tex) X(st_material, anisotropy)                          \
    X(st_material, anisotropy_tex) X(st_material, diffuse_trans)                            \
    X(st_material, diffuse_trans_tex) X(st_material, diffuse_trans_color_tex)               \
    X(st_material, iridescence) X(st_material, iridescence_tex)                             \
    X(st_material, iridescence_thickness_tex) X(st_material, dispersion)                    \
    X(st_tri_tangents, t0) X(st_tri_tangents, t1) X(st_tri_tangents, t2)                    \
    X(st_tri_colors, c0) X(st_tri_colors, c1) X(st_tri_colors, c2)                          \
    X(st_texture, transform) X(st_texture, lod_bias) X(st_texture, offset)                  \
    X(st_texture, width) X(st_texture, height) X(st_texture, levels) X(st_texture, flags)    \
    X(st_texture, wrap_s) X(st_texture, wrap_t) X(st_texture, uv_set)                       \
    X(st_tri_uv, uv) X(st_tri_uv, lod)                                                      \
    X(st_shading, env) X(st_shading, texture_filter) X(st_shading, texture_count)           \
    X(st_shading, punct_count) X(st_shading, punct_share)                                   \
    X(st_shading, env_size) X(st_shading, env_rot) X(st_shading, env_pick)                  \
    X(st_punctual, pos) X(st_punctual, dir) X(st_punctual, intensity)                       \
    X(st_camera, origin) X(st_camera, right) X(st_camera, up) X(st_camera, forward)         \
    X(st_filter, kind) X(st_filter, radius) X(st_filter, b) X(st_filter, c)                 \
    X(st_filter, sigma) X(st_filter, tau)                                                   \
    X(st_params, first_item) X(st_params, width) X(st_params, height) X(st_params, spp)     \
    X(st_params, seed) X(st_params, sampler) X(st_params, scramble) X(st_params, item_count) \
    X(st_params, integrator) X(st_params, max_depth) X(st_params, light_count)              \
    X(st_params, strat_nx) X(st_params, strat_ny) X(st_params, halton_exp2)                 \
    X(st_params, halton_exp3) X(st_params, halton_stride) X(st_params, halton_inv2)         \
    X(st_params, halton_inv3) X(st_params, ray_eps) X(st_params, tile_size)                 \
    X(st_params, tile_begin) X(st_params, tile_count) X(st_params, tiles_x)                 \
    X(st_params, reconstruction) X(st_params, adaptive_count) X(st_params, adaptive_base)   \
    X(st_params, adaptive_scaled) X(st_params, vertex)         \
    X(st_params, live_count) X(st_params, sobol_log2)                                       \
    X(st_params, bin_side) X(st_params, bins_x) X(st_params, bins)                          \
    X(st_params, halton_tables)                                                             \
    X(st_params, filter)                                                                    \
    X(st_params, camera) X(st_params, region_x) X(st_params, region_y)                      \
    X(st_params, region_w) X(st_params, region_h) X(st_params, last_lights)                 \
    X(st_params, bin_pass) X(st_params, area_lanes) X(st_params, aov)                       \
    X(st_sample, film) X(st_sample, pixel) X(st_sample, index) X(st_sample, key)           \
    X(st_sample, word)                                                                      \
    X(st_ray, o) X(st_ray, tmax) X(st_ray, d) X(st_ray, path_length)                        \
    X(st_hit, t) X(st_hit, u) X(st_hit, v) X(st_hit, prim)                                  \
    X(st_path, beta) X(st_path, bsdf_pdf) X(st_path, radiance) X(st_path, depth)            \
    X(st_path, closest_rays) X(st_path, shadow_rays) X(st_path, env_pdf)                    \
    X(st_path, channel)                                                                     \
    X(st_shadow, ray) X(st_shadow, contribution)                                            \
    X(st_tally, splats) X(st_tally, closest_rays) X(st_tally, shadow_rays)                  \
    X(st_bin_tally, splats) X(st_bin_tally, closest_rays) X(st_bin_tally, shadow_rays)      \
    X(st_film_pixel, sum) X(st_pixel, rgb) X(st_pixel, weight)                              \
    X(st_film_stats, clamped) X(st_film_stats, nonfinite) X(st_film_stats, zero_weight)     \
    X(st_tile_point, x) X(st_tile_point, y)

#ifndef __OPENCL_VERSION__
ST_STATIC_ASSERT(sizeof(st_bvh_node) == 32, "st_bvh_node: kernels read 32 bytes");
ST_STATIC_ASSERT(offsetof(st_bvh_node, bmax) == 16, "st_bvh_node.bmax moved");
ST_STATIC_ASSERT(sizeof(st_bvh_wide_node) == 32 * ST_BVH_WIDTH,
                 "st_bvh_wide_node: W/2 64-byte lines");
ST_STATIC_ASSERT(sizeof(st_bvh_wide_node) % ST_LEAF_UNIT == 0,
                 "st_bvh_wide_node: a whole number of leaf units");
/* trace.h's st_leaf_row reads four floats from each row's start: the last
 * row's four stay inside the block for every size */
#define ST_LEAF_LAST_READ(n) (4u * ((ST_LEAF_ROWS - 1u) * (n) + 4u))
ST_STATIC_ASSERT(ST_LEAF_LAST_READ(1u) <= ST_LEAF_UNITS(1u) * ST_LEAF_UNIT &&
                     ST_LEAF_LAST_READ(2u) <= ST_LEAF_UNITS(2u) * ST_LEAF_UNIT &&
                     ST_LEAF_LAST_READ(3u) <= ST_LEAF_UNITS(3u) * ST_LEAF_UNIT &&
                     ST_LEAF_LAST_READ(4u) <= ST_LEAF_UNITS(4u) * ST_LEAF_UNIT,
                 "leaf block: st_leaf_row's loads inside the block");
ST_STATIC_ASSERT(sizeof(st_triangle) == 48, "st_triangle: 48 bytes");
ST_STATIC_ASSERT(sizeof(st_tri_normals) == 48, "st_tri_normals: 48 bytes");
ST_STATIC_ASSERT(sizeof(st_material) == 236, "st_material: 236 bytes");
ST_STATIC_ASSERT(offsetof(st_material, base_color_tex) == 48, "st_material.base_color_tex moved");
ST_STATIC_ASSERT(sizeof(st_texture) == 64, "st_texture: 64 bytes");
ST_STATIC_ASSERT(offsetof(st_texture, offset) == 28, "st_texture.offset moved");
ST_STATIC_ASSERT(sizeof(st_tri_uv) == 32, "st_tri_uv: 32 bytes");
ST_STATIC_ASSERT(sizeof(st_tri_tangents) == 48, "st_tri_tangents: 48 bytes");
ST_STATIC_ASSERT(sizeof(st_tri_colors) == 48, "st_tri_colors: 48 bytes");
ST_STATIC_ASSERT(sizeof(st_shading) == 64, "st_shading: 64 bytes");
ST_STATIC_ASSERT(sizeof(st_camera) == 64, "st_camera: 64 bytes");
ST_STATIC_ASSERT(sizeof(st_filter) == 32, "st_filter: 32 bytes");
ST_STATIC_ASSERT(offsetof(st_params, filter) == 144, "st_params.filter moved");
ST_STATIC_ASSERT(offsetof(st_params, camera) == 176, "st_params.camera moved");
ST_STATIC_ASSERT(sizeof(st_params) == 272, "st_params: 272 bytes");
ST_STATIC_ASSERT(sizeof(st_sample) == 24, "st_sample: 24 bytes");
ST_STATIC_ASSERT(sizeof(st_ray) == 32, "st_ray: 32 bytes");
ST_STATIC_ASSERT(sizeof(st_hit) == 16, "st_hit: 16 bytes");
ST_STATIC_ASSERT(sizeof(st_path) == 48, "st_path: 48 bytes");
ST_STATIC_ASSERT(sizeof(st_shadow) == 48, "st_shadow: 48 bytes");
ST_STATIC_ASSERT(sizeof(st_film_pixel) == 32, "st_film_pixel: 32 bytes");
#endif

#endif
