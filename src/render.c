/* render.c — the pass loop (see st_render.h): scene upload, wave buffers sized
 * once per render, kernel dispatch, resolve and read-back. */
#include "st_render.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "st_bvh.h"
#include "st_sampling.h"
#include "rng.h"
#include "samplers.h"
#include "filters.h"
#include "texture.h"

const char *const st_stage_names[ST_STAGE_COUNT] = {
    "generate_samples", "generate_camera_rays", "trace_rays", "shade_hits",
    "trace_shadow_rays", "splat_samples", "resolve_film"};

const char *const st_sampler_names[ST_SAMPLER_COUNT] = {
    "random", "uniform", "stratified", "halton", "hammersley", "poisson", "best-candidate",
    "sobol"};
const char *const st_filter_names[ST_FILTER_COUNT] = {
    "box", "triangle", "gaussian", "mitchell", "lanczos", "catmull-rom", "blackman-harris"};
const char *const st_integrator_names[2] = {"direct", "path"};
const char *const st_reconstruction_names[2] = {"splat", "fis"};

int st_name_lookup(const char *const *names, int count, const char *name)
{
    for (int i = 0; i < count; i++)
        if (!strcmp(names[i], name))
            return i;
    return -1;
}

int st_sampler_takes_scramble(st_u32 sampler)
{
    return sampler == ST_SAMPLER_STRATIFIED || sampler == ST_SAMPLER_HALTON ||
           sampler == ST_SAMPLER_HAMMERSLEY || sampler == ST_SAMPLER_SOBOL;
}

/* Scene buffers, uploaded once. */
enum { B_NODES, B_TRIS, B_NORMALS, B_TRI_MATERIAL, B_MATERIALS, B_LIGHT_TRI, B_LIGHT_CDF,
       B_LIGHT_PDF, B_TRI_UV, B_TEXTURES, B_TEXELS, B_SCENE_COUNT };
/* Per-wave state (one entry per item) and the film. */
enum { W_FILM, W_SAMPLE_ID, W_RAY_O, W_RAY_D, W_HIT, W_BETA, W_RADIANCE, W_DEPTH, W_SHADOW_O, W_SHADOW_D,
       W_SHADOW_L, W_TALLY, W_ACCUM, W_HALF, W_ACTIVE, W_PIXEL_SPP, W_ACTIVE_COUNT, W_STATS,
       W_IMAGE, W_COUNT };

struct st_renderer {
    st_device *dev;
    const st_scene *scene;
    cl_mem scene_buf[B_SCENE_COUNT];
    cl_kernel k[ST_STAGE_COUNT];
    st_u32 light_count;
    float ray_eps;
    double bvh_seconds;
    /* the tile of the tiled samplers, kept for renders with the same key */
    cl_mem tile;
    cl_mem fis_cdf; /* CDF of |f| for filter importance sampling, per render */
    st_u32 tile_sampler, tile_spp, tile_seed, tile_size, tile_points;
};

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

st_filter st_filter_default(st_u32 kind)
{
    st_filter f;
    memset(&f, 0, sizeof f);
    f.kind = kind;
    f.b = f.c = 1.0f / 3.0f;
    f.sigma = 0.5f;
    static const float radius[ST_FILTER_COUNT] = {0.5f, 1.0f, 1.5f, 2.0f, 3.0f, 2.0f, 2.0f};
    f.radius = kind < ST_FILTER_COUNT ? radius[kind] : 0.5f;
    f.tau = f.radius;
    return f;
}

st_render_options st_render_defaults(void)
{
    st_render_options o;
    memset(&o, 0, sizeof o);
    o.width = 512;
    o.height = 512;
    o.spp = 16;
    o.sampler = ST_SAMPLER_HALTON;
    o.scramble = 1;
    o.integrator = ST_INTEGRATOR_PATH;
    o.max_depth = 5;
    o.filter = st_filter_default(ST_FILTER_MITCHELL);
    o.min_spp = 16;
    o.noise_threshold = 0.01f;
    o.camera = -1;
    o.texture_filter = ST_TEXFILTER_TRILINEAR;
    /* a fixed work-group size: PoCL compiles a kernel again for every new
     * size, and a driver's choice follows the global size, which changes
     * from wave to wave in adaptive rounds (measured: 15 s against 1.9 s) */
    o.local_size = 64;
    return o;
}

st_status st_render_check(const st_render_options *o, st_error *err)
{
    if (o->width < 1 || o->height < 1 || o->width > 32768 || o->height > 32768)
        return st_fail(err, ST_ERR_USAGE, "image size %ux%u: width and height must be 1..32768",
                       o->width, o->height);
    if ((st_u64)o->width * o->height > (1ull << 28))
        return st_fail(err, ST_ERR_USAGE, "image size %ux%u: more than 2^28 pixels", o->width,
                       o->height);
    if (o->spp < 1)
        return st_fail(err, ST_ERR_USAGE, "--spp must be at least 1");
    if (o->sample_begin >= (o->sample_end ? o->sample_end : o->spp) ||
        (o->sample_end ? o->sample_end : o->spp) > o->spp)
        return st_fail(err, ST_ERR_USAGE, "--sample-range %u:%u: must satisfy 0 <= K < M <= spp (%u)",
                       o->sample_begin, o->sample_end, o->spp);
    if (o->sampler >= ST_SAMPLER_COUNT)
        return st_fail(err, ST_ERR_USAGE, "unknown sampler %u", o->sampler);
    if (o->sampler == ST_SAMPLER_HALTON) {
        st_params p;
        memset(&p, 0, sizeof p);
        p.width = o->width;
        p.height = o->height;
        p.spp = o->spp;
        st_sampler_prepare(&p);
        if ((st_u64)p.halton_stride * o->spp > 0xffffffffull)
            return st_fail(err, ST_ERR_USAGE,
                           "--spp %u: Halton indices would pass 2^32 at this image size",
                           o->spp);
    }
    if (o->reconstruction > ST_RECON_FIS)
        return st_fail(err, ST_ERR_USAGE, "unknown reconstruction %u", o->reconstruction);
    if (o->reconstruction == ST_RECON_FIS && ST_SAMPLER_IS_TILED(o->sampler))
        return st_fail(err, ST_ERR_USAGE,
                       "--reconstruction fis needs a per-pixel sampler; %s places its points "
                       "across pixels", st_sampler_names[o->sampler]);
    if (o->adaptive) {
        if (ST_SAMPLER_IS_TILED(o->sampler))
            return st_fail(err, ST_ERR_USAGE, "--adaptive needs a per-pixel sampler, not %s",
                           st_sampler_names[o->sampler]);
        if (o->min_spp < 2 || o->min_spp > o->spp)
            return st_fail(err, ST_ERR_USAGE,
                           "--min-spp %u: must be at least 2 (the half film needs two samples) "
                           "and at most --max-spp %u", o->min_spp, o->spp);
        if (!(o->noise_threshold > 0.0f))
            return st_fail(err, ST_ERR_USAGE, "--noise-threshold must be positive");
        if (o->sample_begin || o->sample_end)
            return st_fail(err, ST_ERR_USAGE, "--adaptive renders cannot be split by --sample-range");
    }
    if (o->max_depth > 64)
        return st_fail(err, ST_ERR_USAGE, "--max-depth %u: at most 64", o->max_depth);
    const st_filter *f = &o->filter;
    if (f->kind >= ST_FILTER_COUNT)
        return st_fail(err, ST_ERR_USAGE, "unknown filter %u", f->kind);
    if (!(f->radius > 0.0f) || f->radius > ST_FILTER_MAX_RADIUS)
        return st_fail(err, ST_ERR_USAGE, "--filter-radius %g: must be in (0, %g]",
                       (double)f->radius, (double)ST_FILTER_MAX_RADIUS);
    if (f->kind == ST_FILTER_GAUSSIAN && !(f->sigma > 0.0f))
        return st_fail(err, ST_ERR_USAGE, "--filter-sigma must be positive");
    if (f->kind == ST_FILTER_LANCZOS && !(f->tau > 0.0f))
        return st_fail(err, ST_ERR_USAGE, "--filter-tau must be positive");
    /* fixed-point headroom (fixed.h): splats one pixel can receive */
    double reach = ceil(2.0 * f->radius) + 1.0;
    if ((double)o->spp * reach * reach > ST_FIXED_MAX_SPLATS)
        return st_fail(err, ST_ERR_USAGE,
                       "--spp %u with filter radius %g could overflow the 64-bit film "
                       "(limit: spp x (ceil(2r)+1)^2 <= 2^23 - 1)",
                       o->spp, (double)f->radius);
    return ST_OK;
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
static double emission_weight(const st_scene *s, const st_material *m, const st_tri_uv *uv,
                              double area, const double *tex_max)
{
    double le = (m->emission[0] + m->emission[1] + m->emission[2]) / 3.0;
    if (!(le > 0.0) || m->emission_tex == ST_NO_TEXTURE)
        return le;
    const st_texture *tex = &s->textures[m->emission_tex];
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
static st_status build_lights(const st_scene *s, const st_bvh *bvh, const st_tri_uv *uv,
                              st_u32 **tri_out, float **cdf_out, float **pdf_out, st_u32 *count,
                              st_error *err)
{
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
        const st_triangle *tr = &bvh->tris[t];
        double cx = tr->e1[1] * tr->e2[2] - tr->e1[2] * tr->e2[1];
        double cy = tr->e1[2] * tr->e2[0] - tr->e1[0] * tr->e2[2];
        double cz = tr->e1[0] * tr->e2[1] - tr->e1[1] * tr->e2[0];
        double area = 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
        const st_material *m = &s->materials[s->tri_material[bvh->order[t]]];
        double le = area > 0.0 ? emission_weight(s, m, &uv[t], area, tex_max) : 0.0;
        if (le > 0.0 && area > 0.0) {
            total += area * le;
            tri[k] = t;
            acc[k++] = total;
        }
    }
    for (st_u32 i = 0; i < k; i++) {
        cdf[i] = i + 1 == k ? 1.0f : (float)(acc[i] / total);
        const st_triangle *tr = &bvh->tris[tri[i]];
        double cx = tr->e1[1] * tr->e2[2] - tr->e1[2] * tr->e2[1];
        double cy = tr->e1[2] * tr->e2[0] - tr->e1[0] * tr->e2[2];
        double cz = tr->e1[0] * tr->e2[1] - tr->e1[1] * tr->e2[0];
        double area = 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
        double p_select = (acc[i] - (i ? acc[i - 1] : 0.0)) / total;
        pdf[tri[i]] = (float)(p_select / area);
    }
    free(acc);
    free(tex_max);
    *tri_out = tri;
    *cdf_out = cdf;
    *pdf_out = pdf;
    *count = k;
    return ST_OK;
}

/* Texture coordinates in BVH order and the triangle's part of the ray-cone
 * level of detail, lod = 1/2 log2(uv area / world area) (st_tri_uv). */
static void make_tri_uv(const st_scene *s, const st_bvh *bvh, st_tri_uv *out)
{
    for (st_u32 t = 0; t < bvh->tri_count; t++) {
        const float *uv = s->uvs + 6 * (size_t)bvh->order[t];
        memcpy(out[t].uv, uv, 6 * sizeof(float));
        const st_triangle *tr = &bvh->tris[t];
        double cx = tr->e1[1] * tr->e2[2] - tr->e1[2] * tr->e2[1];
        double cy = tr->e1[2] * tr->e2[0] - tr->e1[0] * tr->e2[2];
        double cz = tr->e1[0] * tr->e2[1] - tr->e1[1] * tr->e2[0];
        double world = sqrt(cx * cx + cy * cy + cz * cz);
        double tex = fabs(((double)uv[2] - uv[0]) * ((double)uv[5] - uv[1]) -
                          ((double)uv[4] - uv[0]) * ((double)uv[3] - uv[1]));
        out[t].lod = tex > 0.0 && world > 0.0 ? (float)(0.5 * log2(tex / world)) : -64.0f;
        out[t].pad = 0.0f;
    }
}

static st_status upload_scene(st_renderer *r, const st_bvh *bvh, st_error *err)
{
    const st_scene *s = r->scene;
    st_u32 n = bvh->tri_count;
    st_tri_normals *nrm = malloc(sizeof *nrm * (n ? n : 1));
    st_u32 *mat = malloc(sizeof *mat * (n ? n : 1));
    st_tri_uv *uv = calloc(n ? n : 1, sizeof *uv);
    st_u32 *light_tri = NULL;
    float *light_cdf = NULL, *light_pdf = NULL;
    st_status rc = ST_OK;
    static const st_texture no_texture; /* device buffers are never empty */
    static const st_u32 no_texel;
    if (!nrm || !mat || !uv) {
        rc = st_fail(err, ST_ERR_NOMEM, "out of memory preparing the scene");
        goto done;
    }
    memset(nrm, 0, sizeof *nrm * (n ? n : 1));
    for (st_u32 t = 0; t < n; t++) {
        const float *sn = s->normals + 9 * (size_t)bvh->order[t];
        memcpy(nrm[t].n0, sn, 3 * sizeof(float));
        memcpy(nrm[t].n1, sn + 3, 3 * sizeof(float));
        memcpy(nrm[t].n2, sn + 6, 3 * sizeof(float));
        mat[t] = s->tri_material[bvh->order[t]];
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
    make_tri_uv(s, bvh, uv);
    if (build_lights(s, bvh, uv, &light_tri, &light_cdf, &light_pdf, &r->light_count,
                     err) != ST_OK) {
        rc = err->status;
        goto done;
    }
    struct { size_t bytes; const void *data; } up[B_SCENE_COUNT] = {
        {sizeof(st_bvh_node) * bvh->node_count, bvh->nodes},
        {sizeof(st_triangle) * (n ? n : 1), bvh->tris},
        {sizeof(st_tri_normals) * (n ? n : 1), nrm},
        {sizeof(st_u32) * (n ? n : 1), mat},
        {sizeof(st_material) * s->material_count, s->materials},
        {sizeof(st_u32) * (r->light_count ? r->light_count : 1), light_tri},
        {sizeof(float) * (r->light_count ? r->light_count : 1), light_cdf},
        {sizeof(float) * (n ? n : 1), light_pdf},
        {sizeof(st_tri_uv) * (n ? n : 1), uv},
        {sizeof(st_texture) * (s->texture_count ? s->texture_count : 1),
         s->texture_count ? (const void *)s->textures : (const void *)&no_texture},
        {sizeof(st_u32) * (s->texel_count ? s->texel_count : 1),
         s->texel_count ? (const void *)s->texels : (const void *)&no_texel},
    };
    for (int b = 0; b < B_SCENE_COUNT && rc == ST_OK; b++)
        rc = st_device_buffer_create(r->dev, up[b].bytes, up[b].data, &r->scene_buf[b], err);
done:
    free(nrm);
    free(mat);
    free(uv);
    free(light_tri);
    free(light_cdf);
    free(light_pdf);
    return rc;
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
    double t0 = now_seconds();
    if (st_bvh_build(scene->positions, scene->tri_count, &bvh, err) != ST_OK)
        goto fail;
    r->bvh_seconds = now_seconds() - t0;
    if (upload_scene(r, bvh, err) != ST_OK || st_device_build(dev, NULL, err) != ST_OK)
        goto fail;
    for (int k = 0; k < ST_STAGE_COUNT; k++)
        if (st_device_kernel(dev, st_stage_names[k], &r->k[k], err) != ST_OK)
            goto fail;
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
    for (int b = 0; b < B_SCENE_COUNT; b++)
        st_device_buffer_destroy(r->scene_buf[b]);
    st_device_buffer_destroy(r->tile);
    st_device_buffer_destroy(r->fis_cdf);
    free(r);
}

double st_renderer_bvh_seconds(const st_renderer *r) { return r->bvh_seconds; }
st_u32 st_renderer_light_count(const st_renderer *r) { return r->light_count; }

/* Camera basis from the scene's camera and the image aspect. */
static st_camera make_camera(const st_scene_camera *c, st_u32 w, st_u32 h)
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

typedef struct wave_state {
    cl_mem b[W_COUNT];
    size_t items;
    st_shading shading; /* the view's environment and texture filter */
} wave_state;

static size_t wave_item_bytes[W_COUNT] = {
    sizeof(float) * 2, sizeof(st_u32) * 2, sizeof(float) * 4, sizeof(float) * 4, sizeof(float) * 4,
    sizeof(float) * 4, sizeof(float) * 4, sizeof(st_u32), sizeof(float) * 4,
    sizeof(float) * 4, sizeof(float) * 4, sizeof(st_u32) * 4};

static st_status wave_alloc(st_renderer *r, wave_state *w, size_t items, size_t pixels,
                            int adaptive, st_error *err)
{
    memset(w, 0, sizeof *w);
    w->items = items;
    for (int b = 0; b < W_ACCUM; b++)
        if (st_device_buffer_create(r->dev, wave_item_bytes[b] * items, NULL, &w->b[b], err))
            return err->status;
    /* the adaptive buffers are one entry when not adaptive (kernels take them anyway) */
    size_t ap = adaptive ? pixels : 1;
    if (st_device_buffer_create(r->dev, pixels * 4 * sizeof(st_i64), NULL, &w->b[W_ACCUM], err) ||
        st_device_buffer_create(r->dev, ap * 4 * sizeof(st_i64), NULL, &w->b[W_HALF], err) ||
        st_device_buffer_create(r->dev, ap * sizeof(st_u32), NULL, &w->b[W_ACTIVE], err) ||
        st_device_buffer_create(r->dev, ap * sizeof(st_u32), NULL, &w->b[W_PIXEL_SPP], err) ||
        st_device_buffer_create(r->dev, sizeof(st_u32), NULL, &w->b[W_ACTIVE_COUNT], err) ||
        st_device_buffer_create(r->dev, ST_STAT_COUNT * sizeof(st_u32), NULL, &w->b[W_STATS], err) ||
        st_device_buffer_create(r->dev, pixels * 4 * sizeof(float), NULL, &w->b[W_IMAGE], err))
        return err->status;
    if (st_device_buffer_zero(r->dev, w->b[W_ACCUM], pixels * 4 * sizeof(st_i64), err) ||
        st_device_buffer_zero(r->dev, w->b[W_HALF], ap * 4 * sizeof(st_i64), err) ||
        st_device_buffer_zero(r->dev, w->b[W_TALLY], items * 4 * sizeof(st_u32), err) ||
        st_device_buffer_zero(r->dev, w->b[W_STATS], ST_STAT_COUNT * sizeof(st_u32), err))
        return err->status;
    return ST_OK;
}

static void wave_free(wave_state *w)
{
    for (int b = 0; b < W_COUNT; b++)
        st_device_buffer_destroy(w->b[b]);
}

#define MEM(x) sizeof(cl_mem), (const void *)&(x)
#define PARAMS(p) sizeof(st_params), (const void *)&(p)

/* Sets the arguments of stage k for this wave. */
static st_status set_stage_args(st_renderer *r, int k, const st_params *p, wave_state *w,
                                st_error *err)
{
    cl_mem *s = r->scene_buf, *b = w->b;
    cl_kernel kk = r->k[k];
    switch (k) {
    case ST_STAGE_GENERATE:
        return st_device_set_args(kk, err, 6, PARAMS(*p), MEM(r->tile), MEM(r->fis_cdf),
                                  MEM(b[W_ACTIVE]), MEM(b[W_FILM]), MEM(b[W_SAMPLE_ID]));
    case ST_STAGE_CAMERA:
        return st_device_set_args(kk, err, 7, PARAMS(*p), MEM(b[W_FILM]), MEM(b[W_RAY_O]),
                                  MEM(b[W_RAY_D]), MEM(b[W_BETA]), MEM(b[W_RADIANCE]),
                                  MEM(b[W_DEPTH]));
    case ST_STAGE_TRACE:
        return st_device_set_args(kk, err, 7, PARAMS(*p), MEM(s[B_NODES]), MEM(s[B_TRIS]),
                                  MEM(b[W_RAY_O]), MEM(b[W_RAY_D]), MEM(b[W_DEPTH]),
                                  MEM(b[W_HIT]));
    case ST_STAGE_SHADE: {
        return st_device_set_args(
            kk, err, 22, PARAMS(*p), sizeof w->shading, (const void *)&w->shading, MEM(s[B_TRIS]),
            MEM(s[B_NORMALS]), MEM(s[B_TRI_MATERIAL]), MEM(s[B_MATERIALS]), MEM(s[B_LIGHT_TRI]),
            MEM(s[B_LIGHT_CDF]), MEM(s[B_LIGHT_PDF]), MEM(s[B_TRI_UV]), MEM(s[B_TEXTURES]),
            MEM(s[B_TEXELS]), MEM(b[W_SAMPLE_ID]), MEM(b[W_HIT]), MEM(b[W_RAY_O]),
            MEM(b[W_RAY_D]), MEM(b[W_BETA]), MEM(b[W_RADIANCE]), MEM(b[W_DEPTH]),
            MEM(b[W_SHADOW_O]), MEM(b[W_SHADOW_D]), MEM(b[W_SHADOW_L]));
    }
    case ST_STAGE_SHADOW:
        return st_device_set_args(kk, err, 7, PARAMS(*p), MEM(s[B_NODES]), MEM(s[B_TRIS]),
                                  MEM(b[W_SHADOW_O]), MEM(b[W_SHADOW_D]), MEM(b[W_SHADOW_L]),
                                  MEM(b[W_RADIANCE]));
    case ST_STAGE_SPLAT:
        return st_device_set_args(kk, err, 8, PARAMS(*p), MEM(b[W_FILM]), MEM(b[W_SAMPLE_ID]),
                                  MEM(b[W_RADIANCE]), MEM(b[W_ACCUM]), MEM(b[W_HALF]),
                                  MEM(b[W_TALLY]), MEM(b[W_STATS]));
    case ST_STAGE_RESOLVE:
        return st_device_set_args(kk, err, 4, PARAMS(*p), MEM(b[W_ACCUM]), MEM(b[W_IMAGE]),
                                  MEM(b[W_STATS]));
    }
    return st_fail(err, ST_ERR_DEVICE, "unknown stage %d", k);
}

/* Launches stage k; with profiling, waits and adds its time to the stats. */
static st_status run_stage(st_renderer *r, int k, const st_params *p, wave_state *w,
                           size_t items, const st_render_options *o, st_render_stats *st,
                           st_error *err)
{
    if (set_stage_args(r, k, p, w, err) != ST_OK)
        return err->status;
    double t0 = o->profile ? now_seconds() : 0.0;
    if (st_device_launch(r->dev, r->k[k], items, o->local_size, err) != ST_OK)
        return err->status;
    if (o->profile) {
        if (st_device_finish(r->dev, err) != ST_OK)
            return err->status;
        st->stage_seconds[k] += now_seconds() - t0;
    }
    return ST_OK;
}

/* Side of the tile in pixels for the tiled samplers: about 2^14 points, at
 * most 64 x 64 pixels (Bridson makes 2^14 points in milliseconds; the
 * best-candidate cost grows with the count, see st_sampling.h). */
static st_u32 tile_side(st_u32 spp)
{
    st_u32 t = (st_u32)sqrt(16384.0 / spp);
    return t < 1u ? 1u : t > 64u ? 64u : t;
}

/* Makes (or reuses) the tile of a tiled sampler: points in pixels within
 * [0, T)^2, uploaded once. */
static st_status prepare_tile(st_renderer *r, const st_render_options *o, st_error *err)
{
    int tiled = ST_SAMPLER_IS_TILED(o->sampler);
    if (r->tile && (!tiled || (r->tile_sampler == o->sampler && r->tile_spp == o->spp &&
                               r->tile_seed == o->seed)))
        return ST_OK;
    st_device_buffer_destroy(r->tile);
    r->tile = NULL;
    if (!tiled) /* kernels take the argument anyway */
        return st_device_buffer_create(r->dev, 16, NULL, &r->tile, err);
    st_u32 side = tile_side(o->spp), target = side * side * o->spp, count = target;
    float *pts = NULL;
    st_status rc = o->sampler == ST_SAMPLER_POISSON
                       ? st_sampling_poisson_tile(target, o->seed, &pts, &count, NULL, err)
                       : st_sampling_best_candidate_tile(target, o->seed, &pts, err);
    if (rc != ST_OK)
        return rc;
    for (st_u32 i = 0; i < 2 * count; i++)
        pts[i] *= (float)side;
    rc = st_device_buffer_create(r->dev, sizeof(float) * 2 * count, pts, &r->tile, err);
    free(pts);
    r->tile_sampler = o->sampler;
    r->tile_spp = o->spp;
    r->tile_seed = o->seed;
    r->tile_size = side;
    r->tile_points = count;
    return rc;
}

/* The CDF of |f| over ST_FIS_BINS equal bins of [-r, r] (midpoint rule),
 * uploaded for filter importance sampling (pbrt-v4's FilterSampler
 * tabulates |f| the same way). */
static st_status prepare_fis(st_renderer *r, const st_render_options *o, st_error *err)
{
    float cdf[ST_FIS_BINS + 1];
    double acc = 0.0, rad = o->filter.radius;
    cdf[0] = 0.0f;
    for (st_u32 i = 0; i < ST_FIS_BINS; i++) {
        double x = -rad + (i + 0.5) * 2.0 * rad / ST_FIS_BINS;
        acc += fabs(st_filter_eval_1d(&o->filter, (float)x));
        cdf[i + 1] = (float)acc;
    }
    for (st_u32 i = 1; i <= ST_FIS_BINS; i++)
        cdf[i] = i == ST_FIS_BINS ? 1.0f : (float)(cdf[i] / acc);
    st_device_buffer_destroy(r->fis_cdf);
    r->fis_cdf = NULL;
    return st_device_buffer_create(r->dev, sizeof cdf, cdf, &r->fis_cdf, err);
}

void st_render_env(const st_scene *scene, const st_render_options *o, float env[3])
{
    memcpy(env, o->env_given ? o->env : scene->default_env, 3 * sizeof(float));
}

static st_shading make_shading(const st_renderer *r, const st_render_options *o)
{
    st_shading sh;
    memset(&sh, 0, sizeof sh);
    st_render_env(r->scene, o, sh.env);
    sh.texture_filter = o->texture_filter;
    sh.texture_count = r->scene->texture_count;
    return sh;
}

static st_params make_params(const st_renderer *r, const st_render_options *o,
                             const st_scene_camera *cam)
{
    st_params p;
    memset(&p, 0, sizeof p);
    p.width = o->width;
    p.height = o->height;
    p.spp = o->spp;
    p.seed = o->seed;
    p.sampler = o->sampler;
    p.scramble = o->scramble;
    p.integrator = o->integrator;
    p.max_depth = o->integrator == ST_INTEGRATOR_DIRECT ? 1u : o->max_depth;
    p.light_count = r->light_count;
    p.ray_eps = r->ray_eps;
    p.filter = o->filter;
    p.reconstruction = o->reconstruction;
    p.camera = make_camera(cam, o->width, o->height);
    st_sampler_prepare(&p);
    return p;
}

/* One wave: items [first, first + n) of the render's item space. */
static st_status run_wave(st_renderer *r, st_params *p, wave_state *w, const st_render_options *o,
                          st_render_stats *st, st_error *err)
{
    size_t n = p->item_count;
    if (run_stage(r, ST_STAGE_GENERATE, p, w, n, o, st, err) ||
        run_stage(r, ST_STAGE_CAMERA, p, w, n, o, st, err))
        return err->status;
    /* vertex k = 0 .. max_depth: light is gathered (NEE) at the first
     * max_depth vertices; the last one only adds emission (MIS). */
    st_u32 vertices = p->integrator == ST_INTEGRATOR_DIRECT ? 1u : p->max_depth + 1u;
    for (st_u32 v = 0; v < vertices; v++) {
        if (run_stage(r, ST_STAGE_TRACE, p, w, n, o, st, err) ||
            run_stage(r, ST_STAGE_SHADE, p, w, n, o, st, err))
            return err->status;
        if (v < p->max_depth && run_stage(r, ST_STAGE_SHADOW, p, w, n, o, st, err))
            return err->status;
    }
    return run_stage(r, ST_STAGE_SPLAT, p, w, n, o, st, err);
}

static st_status read_back(st_renderer *r, wave_state *w, const st_render_options *o,
                           st_image *out, st_i64 **sums, st_render_stats *st, st_error *err)
{
    size_t pixels = (size_t)o->width * o->height;
    const char *names[4] = {"R", "G", "B", "W"};
    float *img = malloc(pixels * 4 * sizeof(float));
    st_u32 *tally = malloc(w->items * 4 * sizeof(st_u32));
    st_u32 stats[ST_STAT_COUNT];
    st_status rc = ST_OK;
    if (!img || !tally) {
        rc = st_fail(err, ST_ERR_NOMEM, "out of memory reading the image back");
        goto done;
    }
    if (st_device_buffer_read(r->dev, w->b[W_IMAGE], pixels * 4 * sizeof(float), img, err) ||
        st_device_buffer_read(r->dev, w->b[W_TALLY], w->items * 4 * sizeof(st_u32), tally, err) ||
        st_device_buffer_read(r->dev, w->b[W_STATS], sizeof stats, stats, err)) {
        rc = err->status;
        goto done;
    }
    if (sums) {
        *sums = malloc(pixels * 4 * sizeof(st_i64));
        if (!*sums) {
            rc = st_fail(err, ST_ERR_NOMEM, "out of memory reading the film back");
            goto done;
        }
        if (st_device_buffer_read(r->dev, w->b[W_ACCUM], pixels * 4 * sizeof(st_i64), *sums,
                                  err)) {
            free(*sums);
            *sums = NULL;
            rc = err->status;
            goto done;
        }
    }
    if (st_image_create(out, o->width, o->height, 4, names, err) != ST_OK) {
        rc = err->status;
        goto done;
    }
    memcpy(out->data, img, pixels * 4 * sizeof(float));
    for (size_t i = 0; i < w->items; i++) {
        st->splats += tally[4 * i];
        st->closest_rays += tally[4 * i + 1];
        st->shadow_rays += tally[4 * i + 2];
    }
    st->rays = st->closest_rays + st->shadow_rays;
    if (o->adaptive) {
        st->spp_map = malloc(pixels * sizeof *st->spp_map);
        if (!st->spp_map) {
            rc = st_fail(err, ST_ERR_NOMEM, "out of memory for the spp map");
            goto done;
        }
        if (st_device_buffer_read(r->dev, w->b[W_PIXEL_SPP], pixels * sizeof *st->spp_map,
                                  st->spp_map, err)) {
            rc = err->status;
            goto done;
        }
        for (size_t i = 0; i < pixels; i++)
            st->spp_map[i] &= 0x7fffffffu; /* drop adaptive.cl's stopped flag */
    }
    st->clamped = stats[ST_STAT_CLAMPED];
    st->nonfinite = stats[ST_STAT_NONFINITE];
    st->zero_weight = stats[ST_STAT_ZERO_WEIGHT];
done:
    free(img);
    free(tally);
    return rc;
}

typedef struct progress_state {
    st_progress_fn fn;
    void *ctx;
    double done, total;
} progress_state;

/* Items [first, first + total) of the current item space, in waves. */
static st_status run_items(st_renderer *r, st_params *p, wave_state *w,
                           const st_render_options *o, st_u64 first, st_u64 total,
                           progress_state *pr, st_render_stats *st, st_error *err)
{
    st_status rc = ST_OK;
    for (st_u64 done = 0; rc == ST_OK && done < total; done += w->items) {
        p->first_item = first + done;
        p->item_count = (st_u32)(total - done < w->items ? total - done : w->items);
        rc = run_wave(r, p, w, o, st, err);
        if (rc == ST_OK && pr->fn) {
            rc = st_device_finish(r->dev, err);
            pr->done += p->item_count;
            pr->fn(pr->ctx, pr->done < pr->total ? pr->done / pr->total : 1.0);
        }
    }
    return rc;
}

/* Adaptive rounds after the first min_spp samples: adaptive_mark picks the
 * pixels whose error estimate is above the threshold (adaptive.cl); each round
 * gives every one of them the next `batch` samples of its own sequence. Only
 * the active count returns to the host. Rounds grow with the samples taken
 * (batch = half of them, so a pixel's sample count roughly follows 1.5^k). */
static st_status run_adaptive(st_renderer *r, st_params *p, wave_state *w,
                              const st_render_options *o, progress_state *pr,
                              st_render_stats *st, st_error *err)
{
    size_t pixels = (size_t)o->width * o->height;
    cl_kernel mark;
    st_u32 *init = malloc(pixels * sizeof *init);
    if (!init)
        return st_fail(err, ST_ERR_NOMEM, "out of memory for the adaptive state");
    for (size_t i = 0; i < pixels; i++)
        init[i] = o->min_spp;
    st_status rc = st_device_kernel(r->dev, "adaptive_mark", &mark, err);
    if (rc == ST_OK)
        rc = st_device_buffer_write(r->dev, w->b[W_PIXEL_SPP], pixels * sizeof *init, init, err);
    free(init);
    for (st_u32 done = o->min_spp; rc == ST_OK && done < o->spp;) {
        st_u32 batch = done / 2 > 1 ? done / 2 : 1, count = 0, zero = 0;
        if (batch > o->spp - done)
            batch = o->spp - done;
        float threshold = o->noise_threshold;
        st_u32 max_spp = o->spp;
        p->adaptive_count = 0;
        if (st_device_buffer_write(r->dev, w->b[W_ACTIVE_COUNT], sizeof zero, &zero, err) ||
            st_device_set_args(mark, err, 9, PARAMS(*p), MEM(w->b[W_ACCUM]), MEM(w->b[W_HALF]),
                               MEM(w->b[W_PIXEL_SPP]), MEM(w->b[W_ACTIVE]),
                               MEM(w->b[W_ACTIVE_COUNT]), sizeof threshold, (const void *)&threshold,
                               sizeof max_spp, (const void *)&max_spp, sizeof batch,
                               (const void *)&batch) ||
            st_device_launch(r->dev, mark, pixels, 0, err) ||
            st_device_buffer_read(r->dev, w->b[W_ACTIVE_COUNT], sizeof count, &count, err)) {
            rc = err->status;
            break;
        }
        if (count == 0)
            break;
        p->adaptive_count = count;
        p->adaptive_base = done;
        rc = run_items(r, p, w, o, 0, (st_u64)count * batch, pr, st, err);
        st->samples += (st_u64)count * batch;
        done += batch;
    }
    p->adaptive_count = 0;
    return rc;
}

st_status st_render_resolve(st_device *dev, const st_i64 *sums, st_u32 width, st_u32 height,
                            st_image *out, st_render_stats *stats, st_error *err)
{
    size_t pixels = (size_t)width * height;
    const char *names[4] = {"R", "G", "B", "W"};
    st_params p;
    memset(&p, 0, sizeof p);
    p.width = width;
    p.height = height;
    cl_mem accum = NULL, image = NULL, st = NULL;
    cl_kernel k;
    st_u32 counts[ST_STAT_COUNT];
    st_status rc = ST_OK;
    if (st_device_build(dev, NULL, err) ||
        st_device_kernel(dev, st_stage_names[ST_STAGE_RESOLVE], &k, err) ||
        st_device_buffer_create(dev, pixels * 4 * sizeof(st_i64), sums, &accum, err) ||
        st_device_buffer_create(dev, pixels * 4 * sizeof(float), NULL, &image, err) ||
        st_device_buffer_create(dev, sizeof counts, NULL, &st, err) ||
        st_device_buffer_zero(dev, st, sizeof counts, err) ||
        st_device_set_args(k, err, 4, PARAMS(p), MEM(accum), MEM(image), MEM(st)) ||
        st_device_launch(dev, k, pixels, 0, err) ||
        st_image_create(out, width, height, 4, names, err) ||
        st_device_buffer_read(dev, image, pixels * 4 * sizeof(float), out->data, err) ||
        st_device_buffer_read(dev, st, sizeof counts, counts, err))
        rc = err->status;
    if (rc == ST_OK && stats) {
        stats->zero_weight = counts[ST_STAT_ZERO_WEIGHT];
        stats->nonfinite = counts[ST_STAT_NONFINITE];
    }
    st_device_buffer_destroy(accum);
    st_device_buffer_destroy(image);
    st_device_buffer_destroy(st);
    return rc;
}

st_status st_render(st_renderer *r, const st_render_options *o, st_image *out, st_i64 **sums,
                    st_render_stats *stats, st_progress_fn progress, void *progress_ctx,
                    st_error *err)
{
    st_render_stats local;
    st_render_stats *st = stats ? stats : &local;
    memset(st, 0, sizeof *st);
    if (sums)
        *sums = NULL;
    if (st_render_check(o, err) != ST_OK)
        return err->status;
    size_t pixels = (size_t)o->width * o->height;
    st_scene_camera cam;
    if (o->texture_filter > ST_TEXFILTER_TRILINEAR)
        return st_fail(err, ST_ERR_USAGE, "unknown texture filter %u", o->texture_filter);
    if (st_scene_view_camera(r->scene, o->camera, &cam, err) != ST_OK ||
        prepare_tile(r, o, err) != ST_OK || prepare_fis(r, o, err) != ST_OK)
        return err->status;
    st_params p = make_params(r, o, &cam);
    st_u32 end = o->sample_end ? o->sample_end : o->spp;
    st_u64 first = (st_u64)o->sample_begin * pixels;
    st_u64 total = (st_u64)(end - o->sample_begin) * pixels;
    if (ST_SAMPLER_IS_TILED(o->sampler)) {
        /* sample range K:M of spp reads tile points [K N / spp, M N / spp) */
        st_u32 side = r->tile_size, n = r->tile_points;
        p.tile_size = side;
        p.tiles_x = (o->width + side - 1) / side;
        p.tile_begin = (st_u32)((st_u64)o->sample_begin * n / o->spp);
        p.tile_count = (st_u32)((st_u64)end * n / o->spp) - p.tile_begin;
        first = 0;
        total = (st_u64)p.tiles_x * ((o->height + side - 1) / side) * p.tile_count;
    }
    if (o->adaptive) { /* the first round: min_spp samples everywhere */
        total = (st_u64)o->min_spp * pixels;
        p.half_buffer = 1;
    }
    size_t wave = o->wave ? o->wave : (size_t)1 << 18;
    if (wave > total)
        wave = (size_t)total;
    wave_state w;
    double t0 = now_seconds();
    progress_state pr = {progress, progress_ctx, 0.0, (double)total};
    if (o->adaptive)
        pr.total = (double)o->spp * pixels;
    st_status rc = wave_alloc(r, &w, wave, pixels, o->adaptive, err);
    w.shading = make_shading(r, o);
    if (rc == ST_OK)
        rc = run_items(r, &p, &w, o, first, total, &pr, st, err);
    st->samples = total;
    if (rc == ST_OK && o->adaptive)
        rc = run_adaptive(r, &p, &w, o, &pr, st, err);
    if (rc == ST_OK)
        rc = run_stage(r, ST_STAGE_RESOLVE, &p, &w, pixels, o, st, err);
    if (rc == ST_OK)
        rc = st_device_finish(r->dev, err);
    st->seconds = now_seconds() - t0;
    if (rc == ST_OK)
        rc = read_back(r, &w, o, out, sums, st, err);
    wave_free(&w);
    return rc;
}
