/* lights.h — the emitters as next-event estimation samples them: the
 * emissive triangles, chosen by power from a CDF, a point uniform in area on
 * the chosen one, its emission (factor x texture); and the scene's
 * triangles as the shading steps read them. OpenCL only (shade.cl). */
#ifndef ST_LIGHTS_H
#define ST_LIGHTS_H

#include "envmap.h"

/* The scene buffers the shading steps read, gathered so that each step
 * takes one argument for them. */
typedef struct st_scene_refs {
    __global const st_triangle *tris;
    __global const st_tri_normals *normals;
    __global const uint *tri_material;
    __global const st_material *materials;
    __global const uint *light_tri;
    __global const float *light_cdf;
    __global const float *light_pdf;
    __global const st_punctual *punctual;
    __global const float *punct_cdf;
    __global const st_tri_uv *tri_uv;
    __global const st_tri_tangents *tangents;
    __global const st_tri_colors *colors;
    __global const st_texture *textures;
    __global const uint *texels;
    __global const float *env_texels;
    __global const float *env_cdf;
    __global const st_tri_uv *tri_uv1;
} st_scene_refs;

/* The refs of a stage kernel, from its parameters (ST_STAGE_PARAMS): the one
 * initialiser, so that a new field cannot be left out of one kernel. */
#define ST_SCENE_REFS_INIT                                                                  \
    {tris,     normals,   tri_material, materials, light_tri, light_cdf, light_pdf,         \
     punctual, punct_cdf, tri_uv,       tangents,  colors,    textures,  texels,           \
     env_texels, env_cdf, tri_uv1}

/* Index of the light whose CDF interval holds *u (first cdf[i] > *u), and *u
 * rescaled to [0, 1) within that interval, so that one stratified dimension
 * both chooses the light and places the point on it: a light's share of the
 * samples stays stratified (drawing the choice from a dimension of its own
 * would scatter each light's points and lose the stratification). */
static st_u32 pick_light(__global const float *cdf, st_u32 n, float *u)
{
    return st_cdf_pick(cdf, n, u);
}

/* Point of triangle t at barycentrics (b1, b2) of v1 and v2. */
static float3 triangle_at(__global const st_triangle *tris, st_u32 t, float b1, float b2)
{
    float3 v0 = vload4(0, tris[t].v0).xyz;
    return v0 + b1 * vload4(0, tris[t].e1).xyz + b2 * vload4(0, tris[t].e2).xyz;
}

/* Geometric normal of triangle t, turned to the side of its shading normals
 * (precomputed: st_tri_normals). */
static float3 facing_normal(__global const st_tri_normals *normals, st_u32 t)
{
    return (float3)(normals[t].n0[3], normals[t].n1[3], normals[t].n2[3]);
}

/* Texture coordinates at barycentrics (b1, b2) of triangle t. */
static float2 tri_uv_at(__global const st_tri_uv *tri_uv, st_u32 t, float b1, float b2)
{
    __global const float *u = tri_uv[t].uv;
    return (1.0f - b1 - b2) * (float2)(u[0], u[1]) + b1 * (float2)(u[2], u[3]) +
           b2 * (float2)(u[4], u[5]);
}

/* The buffers a texture lookup reads, passed by value: tex_lookup stays a
 * call on PoCL, and a pointer to the caller's st_scene_refs would keep all
 * of that in memory, stored for every work-item, textured or not. */
typedef struct st_tex_refs {
    __global const st_texture *textures;
    __global const uint *texels;
    __global const st_tri_uv *tri_uv, *tri_uv1;
} st_tex_refs;

ST_HOT st_tex_refs tex_refs(const st_scene_refs *s)
{
    st_tex_refs r = {s->textures, s->texels, s->tri_uv, s->tri_uv1};
    return r;
}

/* Texture `tex` (ST_NO_TEXTURE: white) at barycentrics (b1, b2) of triangle
 * t, in the coordinate set it reads (st_texture.uv_set; tri_uv1 holds data
 * only when some texture reads it), with the ray-cone level of detail of a
 * cone of width `width` meeting the surface at cos_nd. */
static float4 tex_lookup(st_tex_refs s, st_u32 tex, st_u32 t, float b1, float b2, float width,
                         float cos_nd, st_u32 filter)
{
    if (tex == ST_NO_TEXTURE)
        return (float4)(1.0f);
    __global const st_texture *x = &s.textures[tex];
    __global const st_tri_uv *set = x->uv_set ? s.tri_uv1 : s.tri_uv;
    float2 uv = tri_uv_at(set, t, b1, b2);
    float c[4];
    st_tex_sample(x, s.texels, uv.x, uv.y, st_tex_lod(set[t].lod, x, width, cos_nd), filter, c);
    return (float4)(c[0], c[1], c[2], c[3]);
}

/* Emitted radiance of light triangle lt at the point (u1, u2) picks,
 * uniform in area (integrator.h's area_at): the factor times the emissive
 * texture's level 0. */
static float3 light_emission(const st_scene_refs *s, st_u32 lt, float u1, float u2,
                             st_u32 filter)
{
    __global const st_material *m = &s->materials[s->tri_material[lt]];
    float3 le = vload4(0, m->emission).xyz;
    if (m->emission_tex == ST_NO_TEXTURE)
        return le;
    float su = sqrt(u1); /* width 0: level 0 */
    return le *
           tex_lookup(tex_refs(s), m->emission_tex, lt, 1.0f - su, u2 * su, 0.0f, 1.0f, filter).xyz;
}

/* The radiant intensity (or a directional light's irradiance) that
 * punctual light l sends along wi from the shading point towards it (wi:
 * from the point to the light): a spot's falls off as the extension
 * defines, t² with t = (cos - cos_outer) / max(1e-3, cos_inner - cos_outer)
 * clamped to [0, 1], cos measured from its axis. */
static float3 punctual_intensity(__global const st_punctual *l, float3 wi)
{
    float3 i = vload4(0, l->intensity).xyz;
    if ((st_u32)l->pos[3] != ST_PUNCT_SPOT)
        return i;
    float co = l->dir[3], ci = l->intensity[3];
    float t = clamp((dot(-wi, vload4(0, l->dir).xyz) - co) / fmax(1e-3f, ci - co), 0.0f, 1.0f);
    return i * (t * t);
}
#endif
