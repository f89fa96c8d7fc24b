/* lights.c — the light table of a scene (see st_lights.h). */
#include "st_lights.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "texture.h"

#define PI 3.14159265358979323846

double st_triangle_cross_norm(const st_triangle *tr)
{
    double cx = tr->e1[1] * tr->e2[2] - tr->e1[2] * tr->e2[1];
    double cy = tr->e1[2] * tr->e2[0] - tr->e1[0] * tr->e2[2];
    double cz = tr->e1[0] * tr->e2[1] - tr->e1[1] * tr->e2[0];
    return sqrt(cx * cx + cy * cy + cz * cz);
}

/* Largest mean RGB of a texel of level 0 of texture t (linear). */
static double texture_max(const st_scene *s, st_u32 t)
{
    const st_texture *tex = &s->textures[t];
    double best = 0.0;
    for (size_t i = 0; i < (size_t)tex->width * tex->height; i++) {
        float c[4];
        st_tex_texel(s->texels, tex->offset, 1, (st_i32)i, 0, tex->flags & ST_TEX_SRGB, c);
        best = fmax(best, (c[0] + c[1] + c[2]) / 3.0);
    }
    return best;
}

/* The light-selection weight of triangle t's emission per unit area: the
 * emissive factor's mean times, with an emissive texture, the texture
 * averaged over the triangle (a trilinear lookup at the UV centroid at the
 * level whose texel covers the triangle's texel area: lod = 1/2 log2 t_a)
 * plus 1/256 of the texture's brightest texel, which keeps the weight
 * positive wherever the texture may emit (the direct integrator needs that
 * to stay unbiased; MIS in the path integrator would not). */
static double emission_weight(const st_scene *s, const st_material *m,
                              const st_tri_uv *const sets[2], st_u32 t, double area,
                              const double *tex_max)
{
    double le = (m->emission[0] + m->emission[1] + m->emission[2]) / 3.0;
    if (!(le > 0.0) || m->emission_tex == ST_NO_TEXTURE)
        return le;
    const st_texture *tex = &s->textures[m->emission_tex];
    const st_tri_uv *uv = &sets[tex->uv_set ? 1 : 0][t]; /* the set it reads */
    float u = (uv->uv[0] + uv->uv[2] + uv->uv[4]) / 3.0f;
    float v = (uv->uv[1] + uv->uv[3] + uv->uv[5]) / 3.0f;
    float lod = uv->lod + tex->lod_bias + 0.5f * log2f((float)(2.0 * area));
    float c[4];
    st_tex_sample(tex, s->texels, u, v, lod, ST_TEXFILTER_TRILINEAR, c);
    double mean = 0.0;
    for (int k = 0; k < 3; k++)
        mean += m->emission[k] * c[k] / 3.0;
    return mean + le * tex_max[m->emission_tex] / 256.0;
}

/* Emissive triangles (in BVH order), chosen with probability proportional to
 * area x emission weight (emission_weight); pdf_area[t] = P(choose t) / area(t). */
st_status st_lights_build(const st_scene *s, const st_bvh *bvh, const st_tri_uv *const uv[2],
                          st_lights *out, st_error *err)
{
    memset(out, 0, sizeof *out);
    st_u32 n = bvh->tri_count;
    st_u32 *tri = malloc(sizeof *tri * (n ? n : 1));
    float *cdf = malloc(sizeof *cdf * (n ? n : 1));
    float *pdf = calloc(n ? n : 1, sizeof *pdf);
    double *acc = malloc(sizeof *acc * (n ? n : 1));
    double *tex_max = calloc(s->texture_count ? s->texture_count : 1, sizeof *tex_max);
    if (!tri || !cdf || !pdf || !acc || !tex_max) {
        free(tri); free(cdf); free(pdf); free(acc); free(tex_max);
        return st_fail(err, ST_ERR_NOMEM, "out of memory building the light table");
    }
    for (st_u32 m = 0; m < s->material_count; m++) {
        st_u32 t = s->materials[m].emission_tex;
        if (t != ST_NO_TEXTURE && tex_max[t] == 0.0)
            tex_max[t] = texture_max(s, t);
    }
    st_u32 k = 0;
    double total = 0.0;
    for (st_u32 t = 0; t < n; t++) {
        double area = 0.5 * st_triangle_cross_norm(&bvh->tris[t]);
        const st_material *m = &s->materials[s->tri_material[bvh->order[t]]];
        double le = area > 0.0 ? emission_weight(s, m, uv, t, area, tex_max) : 0.0;
        if (le > 0.0 && area > 0.0) {
            total += area * le;
            tri[k] = t;
            acc[k++] = total;
        }
    }
    for (st_u32 i = 0; i < k; i++) {
        cdf[i] = i + 1 == k ? 1.0f : (float)(acc[i] / total);
        double area = 0.5 * st_triangle_cross_norm(&bvh->tris[tri[i]]);
        double p_select = (acc[i] - (i ? acc[i - 1] : 0.0)) / total;
        pdf[tri[i]] = (float)(p_select / area);
    }
    free(acc);
    free(tex_max);
    out->tri = tri;
    out->cdf = cdf;
    out->pdf_area = pdf;
    out->count = k;
    return ST_OK;
}

double st_scene_radius(const st_scene *s)
{
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) {
        double d = (double)s->bounds_max[k] - s->bounds_min[k];
        d2 += d * d;
    }
    return 0.5 * sqrt(d2);
}

double st_punctual_power(const st_punctual *l, double radius)
{
    double i = ((double)l->intensity[0] + l->intensity[1] + l->intensity[2]) / 3.0;
    switch ((st_u32)l->pos[3]) {
    case ST_PUNCT_SPOT: {
        double ci = l->intensity[3], co = l->dir[3];
        return 2.0 * PI * i * ((1.0 - ci) + (ci - co) / 3.0);
    }
    case ST_PUNCT_DIRECTIONAL:
        return PI * radius * radius * i;
    default:
        return 4.0 * PI * i;
    }
}

double st_punctual_cdf(const st_punctual *l, st_u32 count, double radius, float *cdf)
{
    double total = 0.0;
    for (st_u32 k = 0; k < count; k++)
        total += st_punctual_power(&l[k], radius);
    double acc = 0.0;
    for (st_u32 k = 0; k < count; k++) {
        acc += st_punctual_power(&l[k], radius);
        cdf[k] = total > 0.0 ? (k + 1 == count ? 1.0f : (float)(acc / total)) : 0.0f;
    }
    return total;
}

float st_punctual_share(double punct_power, double area_power, double env_power)
{
    double rest = area_power + env_power;
    if (!(punct_power > 0.0))
        return 0.0f;
    return rest > 0.0 ? (float)(punct_power / (punct_power + rest)) : 1.0f;
}

float st_env_pick(double area_power, double env_power, st_u32 light_count)
{
    if (!(env_power > 0.0))
        return 0.0f;
    if (light_count == 0u || !(area_power > 0.0))
        return 1.0f;
    return (float)(env_power / (env_power + area_power));
}

void st_lights_free(st_lights *l)
{
    free(l->tri);
    free(l->cdf);
    free(l->pdf_area);
    memset(l, 0, sizeof *l);
}

