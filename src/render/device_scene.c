/* device_scene.c — the scene on the device: triangles in BVH order with
 * their normals, materials, texture coordinates and light table, uploaded
 * once per renderer; and the camera basis of a view. */
#include "render_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "st_bvh.h"
#include "st_lights.h"

_Static_assert(ST_SCENE_tile + 5 == ST_SCENE_BUFFER_COUNT && ST_SCENE_fis_cdf == ST_SCENE_tile + 1 &&
                   ST_SCENE_pmj02 == ST_SCENE_tile + 2 && ST_SCENE_env_texels == ST_SCENE_tile + 3 &&
                   ST_SCENE_env_cdf == ST_SCENE_tile + 4,
               "the per-render inputs and the environment map come last in ST_SCENE_BUFFERS");

/* One set of texture coordinates (6 floats per triangle: s->uvs, s->uvs1)
 * in BVH order and the triangle's part of the ray-cone level of detail,
 * lod = 1/2 log2(uv area / world area) (st_tri_uv). */
static void make_tri_uv(const float *uvs, const st_bvh *bvh, st_tri_uv *out)
{
    for (st_u32 t = 0; t < bvh->tri_count; t++) {
        const float *uv = uvs + 6 * (size_t)bvh->order[t];
        memcpy(out[t].uv, uv, 6 * sizeof(float));
        double world = st_triangle_cross_norm(&bvh->tris[t]);
        double tex = fabs(((double)uv[2] - uv[0]) * ((double)uv[5] - uv[1]) -
                          ((double)uv[4] - uv[0]) * ((double)uv[3] - uv[1]));
        out[t].lod = tex > 0.0 && world > 0.0 ? (float)(0.5 * log2(tex / world)) : -64.0f;
        out[t].pad = 0.0f;
    }
}

/* Per-vertex 4-vectors of each triangle (12 floats: tangents, colours) in BVH
 * order, into an array of 48-byte triangle records (st_tri_tangents,
 * st_tri_colors). */
static void reorder_vertex4(const float *src, const st_bvh *bvh, void *out)
{
    for (st_u32 t = 0; t < bvh->tri_count; t++)
        memcpy((char *)out + 12 * sizeof(float) * t, src + 12 * (size_t)bvh->order[t],
               12 * sizeof(float));
}

/* Shading normals in BVH order, each triangle's fourth floats holding its
 * unit geometric normal turned to the side the shading normals face. */
static void make_normals(const st_scene *s, const st_bvh *bvh, st_tri_normals *nrm)
{
    st_u32 n = bvh->tri_count;
    memset(nrm, 0, sizeof *nrm * (n ? n : 1));
    for (st_u32 t = 0; t < n; t++) {
        const float *sn = s->normals + 9 * (size_t)bvh->order[t];
        memcpy(nrm[t].n0, sn, 3 * sizeof(float));
        memcpy(nrm[t].n1, sn + 3, 3 * sizeof(float));
        memcpy(nrm[t].n2, sn + 6, 3 * sizeof(float));
        /* unit geometric normal, on the side of the shading normals */
        const float *e1 = bvh->tris[t].e1, *e2 = bvh->tris[t].e2;
        double g[3] = {(double)e1[1] * e2[2] - (double)e1[2] * e2[1],
                       (double)e1[2] * e2[0] - (double)e1[0] * e2[2],
                       (double)e1[0] * e2[1] - (double)e1[1] * e2[0]};
        double len = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]), side = 0.0;
        for (int a = 0; a < 3; a++)
            side += g[a] * ((double)sn[a] + sn[3 + a] + sn[6 + a]);
        double scale = (side < 0.0 ? -1.0 : 1.0) / (len > 0.0 ? len : 1.0);
        nrm[t].n0[3] = (float)(g[0] * scale);
        nrm[t].n1[3] = (float)(g[1] * scale);
        nrm[t].n2[3] = (float)(g[2] * scale);
    }
}

static st_status upload_scene(st_renderer *r, const st_bvh *bvh, st_error *err)
{
    const st_scene *s = r->scene;
    st_u32 n = bvh->tri_count;
    st_tri_normals *nrm = malloc(sizeof *nrm * (n ? n : 1));
    st_u32 *mat = malloc(sizeof *mat * (n ? n : 1));
    st_tri_uv *uv = calloc(n ? n : 1, sizeof *uv);
    /* TEXCOORD_1 only where a texture reads it: 32 bytes a triangle */
    st_u32 n1 = s->uvs1 && n ? n : 1;
    st_tri_uv *uv1 = calloc(n1, sizeof *uv1);
    st_tri_tangents *tan = calloc(n ? n : 1, sizeof *tan);
    st_tri_colors *col = calloc(n ? n : 1, sizeof *col);
    st_lights lights = {0};
    st_u32 np = s->punctual_count;
    float *punct_cdf = calloc(np ? np : 1, sizeof *punct_cdf);
    static const st_punctual no_punctual;
    st_status rc = ST_OK;
    static const st_texture no_texture; /* device buffers are never empty */
    static const st_u32 no_texel;
    if (!nrm || !mat || !uv || !uv1 || !tan || !col || !punct_cdf) {
        rc = st_fail(err, ST_ERR_NOMEM, "out of memory preparing the scene");
        goto done;
    }
    make_normals(s, bvh, nrm);
    for (st_u32 t = 0; t < n; t++)
        mat[t] = s->tri_material[bvh->order[t]];
    make_tri_uv(s->uvs, bvh, uv);
    if (s->uvs1)
        make_tri_uv(s->uvs1, bvh, uv1);
    reorder_vertex4(s->tangents, bvh, tan);
    reorder_vertex4(s->colors, bvh, col);
    if (st_lights_build(s, bvh, (const st_tri_uv *const[2]){uv, uv1}, &lights, err) != ST_OK) {
        rc = err->status;
        goto done;
    }
    r->light_count = lights.count;
    r->punct_count = np;
    st_punctual_cdf(s->punctual, np, st_scene_radius(s), punct_cdf);
    /* the scene's buffers by name (ST_SCENE_BUFFERS); tile, fis_cdf and
     * pmj02 are made per render (render.c) */
    struct { size_t bytes; const void *data; } up[ST_SCENE_tile] = {
        [ST_SCENE_nodes] = {sizeof(st_bvh_wide_node) * (bvh->wide_count + bvh->leaf_slots), bvh->wide},
        [ST_SCENE_tris] = {sizeof(st_triangle) * (n ? n : 1), bvh->tris},
        [ST_SCENE_normals] = {sizeof(st_tri_normals) * (n ? n : 1), nrm},
        [ST_SCENE_tri_material] = {sizeof(st_u32) * (n ? n : 1), mat},
        [ST_SCENE_materials] = {sizeof(st_material) * s->material_count, s->materials},
        [ST_SCENE_light_tri] = {sizeof(st_u32) * (r->light_count ? r->light_count : 1), lights.tri},
        [ST_SCENE_light_cdf] = {sizeof(float) * (r->light_count ? r->light_count : 1), lights.cdf},
        [ST_SCENE_light_pdf] = {sizeof(float) * (n ? n : 1), lights.pdf_area},
        [ST_SCENE_punctual] = {sizeof(st_punctual) * (np ? np : 1),
         np ? (const void *)s->punctual : (const void *)&no_punctual},
        [ST_SCENE_punct_cdf] = {sizeof(float) * (np ? np : 1), punct_cdf},
        [ST_SCENE_tri_uv] = {sizeof(st_tri_uv) * (n ? n : 1), uv},
        [ST_SCENE_tri_uv1] = {sizeof(st_tri_uv) * n1, uv1},
        [ST_SCENE_tangents] = {sizeof(st_tri_tangents) * (n ? n : 1), tan},
        [ST_SCENE_colors] = {sizeof(st_tri_colors) * (n ? n : 1), col},
        [ST_SCENE_textures] = {sizeof(st_texture) * (s->texture_count ? s->texture_count : 1),
         s->texture_count ? (const void *)s->textures : (const void *)&no_texture},
        [ST_SCENE_texels] = {sizeof(st_u32) * (s->texel_count ? s->texel_count : 1),
         s->texel_count ? (const void *)s->texels : (const void *)&no_texel},
    };
    for (int b = 0; b < ST_SCENE_tile && rc == ST_OK; b++)
        rc = st_device_buffer_create(r->dev, up[b].bytes, up[b].data, &r->scene_buf[b], err);
done:
    free(nrm);
    free(mat);
    free(uv);
    free(uv1);
    free(tan);
    free(col);
    free(punct_cdf);
    st_lights_free(&lights);
    return rc;
}

/* Whether every point of material m's surface that emits lies on a
 * light-list triangle (st_lights_build): its emission is its factor alone,
 * none of it negative, so a triangle of it emits where its light-selection
 * weight is positive; not unlit (which shows its base colour as light). */
static int emission_listed(const st_material *m)
{
    const float *e = m->emission;
    int emits = e[0] > 0.0f || e[1] > 0.0f || e[2] > 0.0f;
    int by_factor = m->emission_tex == ST_NO_TEXTURE && e[0] >= 0.0f && e[1] >= 0.0f &&
                    e[2] >= 0.0f;
    return !(m->flags & ST_MAT_UNLIT) && (!emits || by_factor);
}

st_status st_renderer_create(st_device *dev, const st_scene *scene, st_renderer **out,
                             st_error *err)
{
    *out = NULL;
    st_renderer *r = calloc(1, sizeof *r);
    if (!r)
        return st_fail(err, ST_ERR_NOMEM, "out of memory creating the renderer");
    r->dev = dev;
    r->scene = scene;
    float extent = 0.0f;
    for (int a = 0; a < 3; a++) {
        extent = fmaxf(extent, fabsf(scene->bounds_min[a]));
        extent = fmaxf(extent, fabsf(scene->bounds_max[a]));
    }
    r->ray_eps = 1e-4f * fmaxf(extent, 1e-3f);
    st_bvh *bvh = NULL;
    if (st_plan_force_from_env(r, err) != ST_OK ||
        (scene->default_sky && st_envmap_sky(&r->sky, err) != ST_OK))
        goto fail;
    double t0 = st_render_now();
    if (st_bvh_build_threads(scene->positions, scene->tri_count,
                             st_renderer_bvh_threads(st_device_get_info(dev), scene->tri_count),
                             &bvh, err) != ST_OK)
        goto fail;
    st_bvh_set_sides(bvh, scene->tri_material, scene->materials);
    r->bvh_seconds = st_render_now() - t0;
    if (upload_scene(r, bvh, err) != ST_OK || st_renderer_upload_env_map(r, NULL, err) != ST_OK ||
        st_device_build(dev, NULL, err) != ST_OK)
        goto fail;
    for (int k = 0; k < ST_KERNEL_COUNT; k++)
        if (st_device_kernel(dev, st_kernel_names[k], &r->kernel[k], err) != ST_OK)
            goto fail;
    r->all_opaque = 1;
    for (st_u32 m = 0; m < scene->material_count; m++)
        r->all_opaque &= scene->materials[m].alpha_mode == ST_ALPHA_OPAQUE;
    r->emitters_listed = r->all_opaque;
    for (st_u32 m = 0; m < scene->material_count; m++)
        r->emitters_listed &= emission_listed(&scene->materials[m]);
    st_bvh_destroy(bvh);
    *out = r;
    return ST_OK;
fail:
    st_bvh_destroy(bvh);
    st_renderer_destroy(r);
    return err->status;
}

void st_renderer_destroy(st_renderer *r)
{
    if (!r)
        return;
    for (int b = 0; b < ST_SCENE_BUFFER_COUNT; b++)
        st_device_buffer_destroy(r->dev, r->scene_buf[b]);
    st_envmap_free(r->sky);
    free(r);
}

unsigned st_renderer_bvh_threads(const st_device_info *info, st_u32 tri_count)
{
    unsigned threads = st_bvh_threads(0u, tri_count);
    return info->is_cpu && info->compute_units < threads ? info->compute_units : threads;
}

st_status st_renderer_upload_env_map(st_renderer *r, const st_envmap *m, st_error *err)
{
    static const float none[4]; /* device buffers are never empty */
    size_t n = m ? (size_t)m->width * m->height : 0;
    st_device_buffer_destroy(r->dev, r->scene_buf[ST_SCENE_env_texels]);
    st_device_buffer_destroy(r->dev, r->scene_buf[ST_SCENE_env_cdf]);
    r->scene_buf[ST_SCENE_env_texels] = r->scene_buf[ST_SCENE_env_cdf] = NULL;
    r->env_map = NULL;
    st_status rc = st_device_buffer_create(r->dev, m ? sizeof(float) * 4 * n : sizeof none,
                                           m ? m->texels : none,
                                           &r->scene_buf[ST_SCENE_env_texels], err);
    if (rc == ST_OK)
        rc = st_device_buffer_create(r->dev, m ? sizeof(float) * (m->height + n) : sizeof none,
                                     m ? m->cdf : none, &r->scene_buf[ST_SCENE_env_cdf], err);
    if (rc == ST_OK)
        r->env_map = m;
    return rc;
}

double st_renderer_bvh_seconds(const st_renderer *r) { return r->bvh_seconds; }
st_u32 st_renderer_light_count(const st_renderer *r) { return r->light_count; }

/* Camera basis from the scene's camera and the image aspect. */
st_camera st_render_camera(const st_scene_camera *c, st_u32 w, st_u32 h)
{
    st_camera cam;
    memset(&cam, 0, sizeof cam);
    const float *f = c->forward, *u = c->up;
    float right[3] = {f[1] * u[2] - f[2] * u[1], f[2] * u[0] - f[0] * u[2],
                      f[0] * u[1] - f[1] * u[0]};
    for (int a = 0; a < 3; a++) {
        cam.origin[a] = c->origin[a];
        cam.right[a] = right[a];
        cam.up[a] = u[a];
        cam.forward[a] = f[a];
    }
    /* st_camera: forward[3] = 1 marks an orthographic camera, whose
     * origin[3] is the half height ymag instead of tan(yfov / 2) */
    cam.origin[3] = c->orthographic ? c->ymag : tanf(0.5f * c->yfov);
    cam.forward[3] = c->orthographic ? 1.0f : 0.0f;
    cam.right[3] = (float)w / (float)h;
    return cam;
}
