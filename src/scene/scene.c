/* scene.c — scene loading (st_scene.h): resolves a scene spec to a built-in
 * scene (embedded in the binary) or a file, hands the bytes to the glTF shim
 * (gltf_*.cpp), and adds what does not depend on the file format: the
 * default material, the textures' mip chains in one texel array, the bounds,
 * the cameras (or the default one) and the environment light.
 *
 * Invariant: a scene returned by st_scene_load satisfies st_scene.h's list
 * (tri_count >= 1, finite non-degenerate triangles, unit normals, materials
 * and textures in range, mip chains inside the texel array, bounds holding
 * every vertex, orthonormal cameras); anything else is an error and no
 * scene. */
#include "st_scene.h"
#include "st_names.h"

#include <zlib.h>

#include <errno.h>
#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "st_embedded.h"
#include "scene_fs.h"
#include "dark_view.h"
#include "gltf_shim.h"
#include "texture.h"
#include "st_lights.h"

#define DEFAULT_SCENE "cornell-box"
#define DEFAULT_YFOV_DEGREES 40.0
#define DEFAULT_ALBEDO 0.8f
#define MAX_BUILTIN 64
#define PI 3.14159265358979323846

/* ---- built-in scenes ------------------------------------------------------ */

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    if (n < k)
        return 0;
    for (size_t i = 0; i < k; i++) {
        char c = s[n - k + i];
        if (c >= 'A' && c <= 'Z')
            c = (char)(c - 'A' + 'a');
        if (c != suffix[i])
            return 0;
    }
    return 1;
}

/* Length of a scene file name without its .gltf/.glb suffix; 0 if it has
 * neither (then it is not a scene). */
static size_t scene_stem(const char *file)
{
    if (ends_with(file, ".gltf"))
        return strlen(file) - 5;
    if (ends_with(file, ".glb"))
        return strlen(file) - 4;
    return 0;
}

/* The extension of a file name that is neither .gltf nor .glb ("m.obj": ".obj"), else NULL:
 * such a name is refused with the formats strata reads, rather than looked up as a built-in
 * scene or parsed as glTF. */
static const char *foreign_extension(const char *spec)
{
    const char *base = strrchr(spec, '/');
    base = base ? base + 1 : spec;
    const char *dot = strrchr(base, '.');
    return dot && dot != base && dot[1] && !scene_stem(base) ? dot : NULL;
}

static int is_builtin_spec(const char *spec)
{
    return !strchr(spec, '/') && !ends_with(spec, ".gltf") && !ends_with(spec, ".glb");
}

static const st_embedded_file *find_builtin(const char *name)
{
    for (unsigned i = 0; i < st_embedded_scene_count; i++) {
        size_t n = scene_stem(st_embedded_scenes[i].name);
        if (n > 0 && strlen(name) == n && strncasecmp(name, st_embedded_scenes[i].name, n) == 0)
            return &st_embedded_scenes[i];
    }
    return NULL;
}

static char builtin_names[MAX_BUILTIN][64];
static const char *builtin_list[MAX_BUILTIN];
static st_u32 builtin_count;
static pthread_once_t builtin_once = PTHREAD_ONCE_INIT;

static void list_builtins(void)
{
    for (unsigned i = 0; i < st_embedded_scene_count && builtin_count < MAX_BUILTIN; i++) {
        size_t n = scene_stem(st_embedded_scenes[i].name);
        if (n == 0 || n >= sizeof builtin_names[0])
            continue;
        memcpy(builtin_names[builtin_count], st_embedded_scenes[i].name, n);
        builtin_names[builtin_count][n] = '\0';
        builtin_list[builtin_count] = builtin_names[builtin_count];
        builtin_count++;
    }
}

st_u32 st_scene_builtin_names(const char **names, st_u32 max)
{
    pthread_once(&builtin_once, list_builtins);
    st_u32 n = builtin_count < max ? builtin_count : max;
    for (st_u32 i = 0; i < n; i++)
        names[i] = builtin_list[i];
    return n;
}

static st_status unknown_builtin(const char *name, st_error *err)
{
    const char *names[MAX_BUILTIN];
    st_u32 n = st_scene_builtin_names(names, MAX_BUILTIN);
    char list[256] = "";
    for (st_u32 i = 0; i < n; i++) {
        size_t used = strlen(list);
        snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "", names[i]);
    }
    int k = st_name_nearest(names, (int)n, name);
    if (k >= 0)
        return st_fail(err, ST_ERR_USAGE, "unknown built-in scene '%s'; did you mean %s? "
                       "(built-in: %s)", name, names[k], list);
    return st_fail(err, ST_ERR_USAGE, "unknown built-in scene '%s' (built-in: %s)", name,
                   n ? list : "none");
}

/* ---- files ------------------------------------------------------------------ */

/* The directory external URIs resolve against: the path up to its last '/'
 * ("" for a bare file name: the working directory; "/" for a root file). */
static char *dir_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    size_t n = slash ? (size_t)(slash - path) : 0;
    if (slash && n == 0)
        n = 1;
    char *dir = malloc(n + 1);
    if (dir) {
        memcpy(dir, path, n);
        dir[n] = '\0';
    }
    return dir;
}

/* ---- completing the scene ------------------------------------------------------- */

static void compute_bounds(st_scene *s)
{
    for (int k = 0; k < 3; k++) {
        s->bounds_min[k] = INFINITY;
        s->bounds_max[k] = -INFINITY;
    }
    for (size_t i = 0; i < 3 * (size_t)s->tri_count; i++)
        for (int k = 0; k < 3; k++) {
            float v = s->positions[3 * i + (size_t)k];
            s->bounds_min[k] = fminf(s->bounds_min[k], v);
            s->bounds_max[k] = fmaxf(s->bounds_max[k], v);
        }
}

/* Default framing (--camera auto, and the view of a file without
 * cameras): the camera looks at the bounds' centre c from glTF's front
 * (+Z: "the front of an asset faces +Z", glTF 2.0 §3.4), raised by
 * FRAMING_ELEVATION and turned by FRAMING_AZIMUTH towards +X, so a model
 * is seen as its author faced it, a little from above and from the side
 * (its depth shows). The bounding sphere (radius r = half the box
 * diagonal) subtends the vertical field of view from distance
 * d = r / sin(yfov / 2) (its tangent cone's half-angle is asin(r / d)).
 * Tests: test_scene.c auto_camera_sees_the_front. */
#define FRAMING_ELEVATION_DEGREES 20.0
#define FRAMING_AZIMUTH_DEGREES 30.0
static void frame_bounds(const st_scene *s, st_scene_camera *cam)
{
    double c[3], r2 = 0.0;
    for (int k = 0; k < 3; k++) {
        double e = (double)s->bounds_max[k] - s->bounds_min[k];
        c[k] = 0.5 * ((double)s->bounds_min[k] + s->bounds_max[k]);
        r2 += 0.25 * e * e;
    }
    const double el = FRAMING_ELEVATION_DEGREES * PI / 180.0;
    const double az = FRAMING_AZIMUTH_DEGREES * PI / 180.0;
    const double dir[3] = {cos(el) * sin(az), sin(el), cos(el) * cos(az)}; /* c to the eye */
    const double yfov = DEFAULT_YFOV_DEGREES * PI / 180.0;
    const double d = sqrt(r2) / sin(0.5 * yfov);
    float eye[3], target[3];
    for (int k = 0; k < 3; k++) {
        eye[k] = (float)(c[k] + d * dir[k]);
        target[k] = (float)c[k];
    }
    st_error ignored = {0}; /* d > 0 and the view is never along +Y: it cannot fail */
    st_scene_look_at(eye, target, (const float[3]){0.0f, 1.0f, 0.0f}, (float)yfov, cam, &ignored);
    cam->from_file = 0;
}

st_status st_scene_look_at(const float eye[3], const float target[3], const float up[3],
                           float yfov, st_scene_camera *out, st_error *err)
{
    double f[3], u[3], fl = 0.0, ul = 0.0, fu = 0.0;
    for (int k = 0; k < 3; k++) {
        if (!isfinite(eye[k]) || !isfinite(target[k]) || !isfinite(up[k]))
            return st_fail(err, ST_ERR_USAGE, "look at: every coordinate must be finite");
        f[k] = (double)target[k] - eye[k];
        fl += f[k] * f[k];
    }
    if (!(yfov > 0.0f && yfov < (float)PI))
        return st_fail(err, ST_ERR_USAGE, "fov %g: must lie strictly between 0 and 180 degrees",
                       yfov * 180.0 / PI);
    if (fl == 0.0)
        return st_fail(err, ST_ERR_USAGE, "look at: the eye and the target are the same point");
    fl = sqrt(fl);
    for (int k = 0; k < 3; k++) {
        f[k] /= fl;
        fu += f[k] * up[k];
    }
    for (int k = 0; k < 3; k++) { /* up made orthogonal to the view (Gram-Schmidt) */
        u[k] = up[k] - fu * f[k];
        ul += u[k] * u[k];
    }
    ul = sqrt(ul);
    double upl = sqrt((double)up[0] * up[0] + (double)up[1] * up[1] + (double)up[2] * up[2]);
    if (!(ul > 1e-6 * upl)) /* also up = 0 */
        return st_fail(err, ST_ERR_USAGE, "look at: the up vector %g,%g,%g lies along the view "
                       "(give another up)", up[0], up[1], up[2]);
    memset(out, 0, sizeof *out);
    for (int k = 0; k < 3; k++) {
        out->origin[k] = eye[k];
        out->forward[k] = (float)f[k];
        out->up[k] = (float)(u[k] / ul);
    }
    out->yfov = yfov;
    return ST_OK;
}

/* ---- mip chains ----------------------------------------------------------------- */

st_u64 st_scene_mip_texels(st_u32 width, st_u32 height)
{
    st_u64 n = 0;
    for (;;) {
        n += (st_u64)width * height;
        if (width <= 1 && height <= 1)
            return n;
        width = width > 1 ? width / 2 : 1;
        height = height > 1 ? height / 2 : 1;
    }
}

/* The byte whose sRGB decode is nearest to linear value x (binary search in
 * st_srgb_table, which increases), so decode(encode(decode(b))) = decode(b). */
static st_u32 srgb_encode(float x)
{
    st_u32 lo = 0, hi = 255;
    while (lo < hi) { /* the largest b with table[b] <= x, or 0 */
        st_u32 mid = (lo + hi + 1) / 2;
        if (st_srgb_table[mid] <= x)
            lo = mid;
        else
            hi = mid - 1;
    }
    if (lo < 255 && st_srgb_table[lo + 1] - x < x - st_srgb_table[lo])
        lo++;
    return lo;
}

/* Taps of one dimension of the downsampling filter: destination texel i of
 * m (= max(1, n / 2)) from a level of n texels. Its centre lies at source
 * coordinate x = (i + 1/2) n / m - 1/2 (texel centres at integers); the
 * weights are the tent max(0, 1 - |j - x| / 2) over source texels j
 * (radius: one destination texel), normalised, indices wrapped by the
 * texture's wrap mode. For even n that is [1 3 3 1] / 8 at 2i - 1 .. 2i + 2,
 * the quadratic B-spline's two-scale filter, which attenuates what the next
 * level cannot hold far better than the 2 x 2 box (at 0.35 cycles per texel,
 * 0.09 against 0.45). Returns the tap count (<= 5). */
static int filter_taps(st_u32 i, st_u32 n, st_u32 m, st_u32 wrap, st_u32 idx[5], double w[5])
{
    if (n == 1) {
        idx[0] = 0;
        w[0] = 1.0;
        return 1;
    }
    double x = (i + 0.5) * n / m - 0.5, sum = 0.0;
    int k = 0;
    for (long j = (long)floor(x - 2.0) + 1; j < x + 2.0; j++) {
        double wt = 1.0 - fabs((double)j - x) / 2.0;
        if (wt <= 0.0 || k == 5)
            continue;
        idx[k] = (st_u32)st_tex_wrap((st_i32)j, (st_i32)n, wrap);
        w[k] = wt;
        sum += wt;
        k++;
    }
    for (int t = 0; t < k; t++)
        w[t] /= sum;
    return k;
}

/* Level l + 1 of a chain from level l (w x h texels at src). */
static void downsample(const st_u32 *src, st_u32 w, st_u32 h, int srgb, st_u32 wrap_s,
                       st_u32 wrap_t, st_u32 *dst)
{
    st_u32 nw = w > 1 ? w / 2 : 1, nh = h > 1 ? h / 2 : 1;
    for (st_u32 y = 0; y < nh; y++) {
        st_u32 ys[5];
        double wy[5];
        int ny = filter_taps(y, h, nh, wrap_t, ys, wy);
        for (st_u32 x = 0; x < nw; x++) {
            st_u32 xs[5];
            double wx[5], sum[4] = {0, 0, 0, 0};
            int nx = filter_taps(x, w, nw, wrap_s, xs, wx);
            for (int b = 0; b < ny; b++)
                for (int a = 0; a < nx; a++) {
                    st_u32 t = src[(size_t)ys[b] * w + xs[a]];
                    for (int c = 0; c < 4; c++) {
                        st_u32 v = (t >> (8 * c)) & 255u;
                        double lin = srgb && c < 3 ? (double)st_srgb_to_linear(v) : (double)v;
                        sum[c] += wx[a] * wy[b] * lin;
                    }
                }
            st_u32 out = 0;
            for (int c = 0; c < 4; c++) {
                st_u32 v = srgb && c < 3 ? srgb_encode((float)sum[c]) : (st_u32)(sum[c] + 0.5);
                out |= (v > 255 ? 255u : v) << (8 * c);
            }
            dst[(size_t)y * nw + x] = out;
        }
    }
}

st_status st_scene_build_mips(const unsigned char *rgba, st_u32 width, st_u32 height, int srgb,
                              st_u32 wrap_s, st_u32 wrap_t, st_u32 **out, st_u32 *levels,
                              st_error *err)
{
    *out = NULL;
    if (width == 0 || height == 0)
        return st_fail(err, ST_ERR_USAGE, "mip chain of an empty image");
    st_u64 total = st_scene_mip_texels(width, height);
    st_u32 *t = total <= SIZE_MAX / sizeof *t ? malloc((size_t)total * sizeof *t) : NULL;
    if (!t)
        return st_fail(err, ST_ERR_NOMEM, "out of memory for a %ux%u mip chain", width, height);
    for (size_t i = 0; i < (size_t)width * height; i++)
        t[i] = (st_u32)rgba[4 * i] | (st_u32)rgba[4 * i + 1] << 8 |
               (st_u32)rgba[4 * i + 2] << 16 | (st_u32)rgba[4 * i + 3] << 24;
    st_u32 *level = t, w = width, h = height, n = 1;
    while (w > 1 || h > 1) {
        st_u32 *next = level + (size_t)w * h;
        downsample(level, w, h, srgb, wrap_s, wrap_t, next);
        level = next;
        w = w > 1 ? w / 2 : 1;
        h = h > 1 ? h / 2 : 1;
        n++;
    }
    *out = t;
    *levels = n;
    return ST_OK;
}

/* ---- textures and materials --------------------------------------------------- */

static st_u32 wrap_mode(int gltf_code)
{
    return gltf_code == 33071 ? ST_WRAP_CLAMP : gltf_code == 33648 ? ST_WRAP_MIRROR
                                                                   : ST_WRAP_REPEAT;
}

/* One mip chain per (image, colour space, wrap modes), shared by the
 * descriptors that sample it. */
typedef struct chain {
    int image, srgb, wrap_s, wrap_t;
    st_u32 offset, levels;
} chain;

static int same_chain(const chain *c, const st_gltf_texture *r)
{
    return c->image == r->image && c->srgb == r->srgb && c->wrap_s == r->wrap_s &&
           c->wrap_t == r->wrap_t;
}

/* Builds the texel array and a descriptor per texture reference of the shim
 * (descriptor i = reference i, so material texture indices carry over). */
static st_status take_textures(const st_gltf_data *g, st_scene *s, const char *label,
                               st_error *err)
{
    if (g->texture_count == 0)
        return ST_OK;
    chain *chains = calloc(g->texture_count, sizeof *chains);
    s->textures = calloc(g->texture_count, sizeof *s->textures);
    st_status rc = ST_OK;
    size_t nchains = 0;
    st_u64 total = 0;
    if (!chains || !s->textures) {
        rc = st_fail(err, ST_ERR_NOMEM, "%s: out of memory", label);
        goto done;
    }
    for (size_t i = 0; i < g->texture_count; i++) { /* sizes first: one allocation */
        const st_gltf_texture *r = &g->textures[i];
        size_t c = 0;
        while (c < nchains && !same_chain(&chains[c], r))
            c++;
        if (c == nchains) {
            const st_gltf_image *im = &g->images[r->image];
            chains[nchains].image = r->image;
            chains[nchains].wrap_s = r->wrap_s;
            chains[nchains].wrap_t = r->wrap_t;
            chains[nchains++].srgb = r->srgb;
            chains[c].offset = (st_u32)total; /* checked below, before use */
            total += st_scene_mip_texels(im->width, im->height);
            if (total > UINT32_MAX) {
                rc = st_fail(err, ST_ERR_FORMAT, "%s: textures too large (over 2^32 texels)",
                             label);
                goto done;
            }
        }
    }
    s->texels = malloc((size_t)total * sizeof *s->texels);
    if (!s->texels) {
        rc = st_fail(err, ST_ERR_NOMEM, "%s: out of memory for %llu texels", label,
                     (unsigned long long)total);
        goto done;
    }
    s->texel_count = (st_u32)total;
    for (size_t c = 0; c < nchains && rc == ST_OK; c++) {
        const st_gltf_image *im = &g->images[chains[c].image];
        st_u32 *mips = NULL;
        rc = st_scene_build_mips(im->rgba, im->width, im->height, chains[c].srgb,
                                 wrap_mode(chains[c].wrap_s), wrap_mode(chains[c].wrap_t), &mips,
                                 &chains[c].levels, err);
        if (rc == ST_OK)
            memcpy(s->texels + chains[c].offset, mips,
                   (size_t)st_scene_mip_texels(im->width, im->height) * sizeof *mips);
        free(mips);
    }
    for (size_t i = 0; i < g->texture_count && rc == ST_OK; i++) {
        const st_gltf_texture *r = &g->textures[i];
        const st_gltf_image *im = &g->images[r->image];
        size_t c = 0;
        while (!same_chain(&chains[c], r))
            c++;
        st_texture *t = &s->textures[i];
        memcpy(t->transform, r->transform, sizeof t->transform);
        t->offset = chains[c].offset;
        t->width = im->width;
        t->height = im->height;
        t->levels = chains[c].levels;
        t->flags = (r->srgb ? ST_TEX_SRGB : 0u) | (r->mag_nearest ? ST_TEX_MAG_NEAREST : 0u);
        t->wrap_s = wrap_mode(r->wrap_s);
        t->wrap_t = wrap_mode(r->wrap_t);
        t->uv_set = (st_u32)r->tex_coord;
        /* texel area of a unit of uv area: width x height x |det transform| */
        double det = fabs((double)r->transform[0] * r->transform[4] -
                          (double)r->transform[1] * r->transform[3]);
        double area = (double)im->width * im->height * (det > 1e-30 ? det : 1.0);
        t->lod_bias = (float)(0.5 * log2(area));
    }
    s->texture_count = (st_u32)g->texture_count;
done:
    free(chains);
    return rc;
}

static st_u32 texture_index(int i)
{
    return i < 0 ? ST_NO_TEXTURE : (st_u32)i;
}

/* Materials of the file, plus the default white one when the file has none
 * or some triangle names none; triangles without a material get it. */
static st_status take_materials(st_gltf_data *g, st_scene *s, const char *label, st_error *err)
{
    int need_default = g->material_count == 0;
    for (size_t i = 0; i < g->tri_count && !need_default; i++)
        need_default = g->tri_material[i] == ST_GLTF_NO_MATERIAL;
    size_t count = g->material_count + (need_default ? 1 : 0);
    if (count >= UINT32_MAX)
        return st_fail(err, ST_ERR_FORMAT, "%s: too many materials (%zu)", label, count);
    s->materials = calloc(count, sizeof *s->materials);
    if (!s->materials)
        return st_fail(err, ST_ERR_NOMEM, "%s: out of memory", label);
    for (size_t i = 0; i < g->material_count; i++) {
        const st_gltf_material *in = &g->materials[i];
        st_material *m = &s->materials[i];
        memcpy(m->base_color, in->base_color, 4 * sizeof(float));
        memcpy(m->emission, in->emission, 3 * sizeof(float));
        m->metallic = in->metallic;
        m->roughness = in->roughness;
        m->alpha_cutoff = in->alpha_cutoff;
        m->alpha_mode = (st_u32)in->alpha_mode;
        m->base_color_tex = texture_index(in->base_color_tex);
        m->emission_tex = texture_index(in->emission_tex);
        m->metallic_roughness_tex = texture_index(in->metallic_roughness_tex);
        memcpy(m->specular, in->specular, sizeof m->specular);
        m->ior = in->ior;
        /* a transmissive surface is met from inside too, where the ray leaves */
        int passes = in->transmission > 0.0f || in->diffuse_trans[3] > 0.0f;
        m->flags = (in->unlit ? ST_MAT_UNLIT : 0u) |
                   (in->double_sided || passes ? ST_MAT_DOUBLE_SIDED : 0u);
        m->specular_tex = texture_index(in->specular_tex);
        m->specular_color_tex = texture_index(in->specular_color_tex);
        m->normal_tex = texture_index(in->normal_tex);
        m->normal_scale = in->normal_scale;
        m->transmission = in->transmission;
        m->transmission_tex = texture_index(in->transmission_tex);
        m->clearcoat = in->clearcoat;
        m->clearcoat_roughness = in->clearcoat_roughness;
        m->clearcoat_tex = texture_index(in->clearcoat_tex);
        m->clearcoat_roughness_tex = texture_index(in->clearcoat_roughness_tex);
        m->clearcoat_normal_tex = texture_index(in->clearcoat_normal_tex);
        m->clearcoat_normal_scale = in->clearcoat_normal_scale;
        memcpy(m->sheen_color, in->sheen_color, sizeof m->sheen_color);
        m->sheen_roughness = in->sheen_roughness;
        m->sheen_color_tex = texture_index(in->sheen_color_tex);
        m->sheen_roughness_tex = texture_index(in->sheen_roughness_tex);
        if (in->sheen_color[0] > 0.0f || in->sheen_color[1] > 0.0f || in->sheen_color[2] > 0.0f)
            m->flags |= ST_MAT_SHEEN; /* a black sheen colour turns the layer off */
        m->anisotropy[0] = in->anisotropy;
        m->anisotropy[1] = cosf(in->anisotropy_rotation);
        m->anisotropy[2] = sinf(in->anisotropy_rotation);
        m->anisotropy_tex = texture_index(in->anisotropy_tex);
        if (in->anisotropy > 0.0f) /* strength 0 is the isotropic lobe */
            m->flags |= ST_MAT_ANISO;
        memcpy(m->diffuse_trans, in->diffuse_trans, sizeof m->diffuse_trans);
        m->diffuse_trans_tex = texture_index(in->diffuse_trans_tex);
        m->diffuse_trans_color_tex = texture_index(in->diffuse_trans_color_tex);
        if (in->diffuse_trans[3] > 0.0f)
            m->flags |= ST_MAT_DIFFUSE_TRANS;
        memcpy(m->iridescence, in->iridescence, sizeof m->iridescence);
        m->iridescence_tex = texture_index(in->iridescence_tex);
        m->iridescence_thickness_tex = texture_index(in->iridescence_thickness_tex);
        if (in->iridescence[0] > 0.0f)
            m->flags |= ST_MAT_IRIDESCENT;
        m->dispersion = in->dispersion;
        if (in->dispersion > 0.0f && in->transmission > 0.0f && !in->thin_walled)
            m->flags |= ST_MAT_DISPERSIVE;
        if (st_material_reads_textures(m))
            m->flags |= ST_MAT_TEXTURED;
        if (in->thin_walled && in->transmission > 0.0f)
            m->flags |= ST_MAT_THIN;
        for (int k = 0; k < 3; k++) /* Beer-Lambert: attenuationColor after attenuationDistance */
            m->absorption[k] = isinf(in->attenuation[3]) || in->attenuation[k] >= 1.0f
                                   ? 0.0f
                                   : -logf(fmaxf(in->attenuation[k], 1e-30f)) / in->attenuation[3];
    }
    if (need_default) {
        st_material *m = &s->materials[g->material_count];
        m->base_color[0] = m->base_color[1] = m->base_color[2] = DEFAULT_ALBEDO;
        m->base_color[3] = 1.0f;
        m->roughness = 1.0f;
        m->alpha_cutoff = 0.5f;
        m->base_color_tex = m->emission_tex = m->metallic_roughness_tex = ST_NO_TEXTURE;
        m->specular[0] = m->specular[1] = m->specular[2] = m->specular[3] = 1.0f;
        m->ior = 1.5f;
        m->specular_tex = m->specular_color_tex = m->normal_tex = ST_NO_TEXTURE;
        m->normal_scale = 1.0f;
        m->transmission_tex = m->clearcoat_tex = m->clearcoat_roughness_tex = ST_NO_TEXTURE;
        m->clearcoat_normal_tex = ST_NO_TEXTURE;
        m->clearcoat_normal_scale = 1.0f;
        m->sheen_color_tex = m->sheen_roughness_tex = ST_NO_TEXTURE;
        m->anisotropy[1] = 1.0f;
        m->anisotropy_tex = ST_NO_TEXTURE;
        m->diffuse_trans[0] = m->diffuse_trans[1] = m->diffuse_trans[2] = 1.0f;
        m->diffuse_trans_tex = m->diffuse_trans_color_tex = ST_NO_TEXTURE;
        m->iridescence[1] = 1.3f;
        m->iridescence[2] = 100.0f;
        m->iridescence[3] = 400.0f;
        m->iridescence_tex = m->iridescence_thickness_tex = ST_NO_TEXTURE;
        for (size_t i = 0; i < g->tri_count; i++)
            if (g->tri_material[i] == ST_GLTF_NO_MATERIAL)
                g->tri_material[i] = (uint32_t)g->material_count;
    }
    s->material_count = (st_u32)count;
    return ST_OK;
}

/* ST_MAT_VERTEX_COLOR on the materials of triangles whose COLOR_0 is not
 * white, so that the others skip the lookup. */
static void mark_vertex_colors(st_scene *s)
{
    for (st_u32 t = 0; t < s->tri_count; t++)
        for (int k = 0; k < 12; k++)
            if (s->colors[12 * (size_t)t + (size_t)k] != 1.0f) {
                s->materials[s->tri_material[t]].flags |= ST_MAT_VERTEX_COLOR;
                break;
            }
}

/* Mean linear RGB of texture t (ST_NO_TEXTURE: 1): its mip chain's last,
 * 1 x 1 level, whose filter keeps the mean. */
static void texture_mean(const st_scene *s, st_u32 t, float mean[3])
{
    mean[0] = mean[1] = mean[2] = 1.0f;
    if (t == ST_NO_TEXTURE)
        return;
    const st_texture *tex = &s->textures[t];
    float c[4];
    st_u32 last = tex->offset + (st_u32)st_scene_mip_texels(tex->width, tex->height) - 1u;
    st_tex_texel(s->texels, last, 1, 0, 0, tex->flags & ST_TEX_SRGB, c);
    memcpy(mean, c, 3 * sizeof(float));
}

/* Where ray o + t d (t > 0) first meets triangle t of s, or INFINITY
 * (Möller and Trumbore, "Fast, minimum storage ray-triangle intersection",
 * JGT 1997), in double. A triangle whose material is not doubleSided is met
 * from its front only (determinant a > 0: the ray against (v1 - v0) x
 * (v2 - v0)), as the renderer's rays meet it. */
static double ray_triangle(const st_scene *s, st_u32 t, const double o[3], const double d[3])
{
    int two_sided = (s->materials[s->tri_material[t]].flags & ST_MAT_DOUBLE_SIDED) != 0;
    const float *p = s->positions + 9 * (size_t)t;
    double e1[3], e2[3], q[3], h[3], r[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = (double)p[3 + k] - p[k];
        e2[k] = (double)p[6 + k] - p[k];
        r[k] = o[k] - p[k];
    }
    h[0] = d[1] * e2[2] - d[2] * e2[1];
    h[1] = d[2] * e2[0] - d[0] * e2[2];
    h[2] = d[0] * e2[1] - d[1] * e2[0];
    double a = e1[0] * h[0] + e1[1] * h[1] + e1[2] * h[2];
    if (a == 0.0 || (!two_sided && a < 0.0))
        return INFINITY;
    double u = (r[0] * h[0] + r[1] * h[1] + r[2] * h[2]) / a;
    if (u < 0.0 || u > 1.0)
        return INFINITY;
    q[0] = r[1] * e1[2] - r[2] * e1[1];
    q[1] = r[2] * e1[0] - r[0] * e1[2];
    q[2] = r[0] * e1[1] - r[1] * e1[0];
    double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / a;
    if (v < 0.0 || u + v > 1.0)
        return INFINITY;
    double hit = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / a;
    return hit > 0.0 ? hit : INFINITY;
}

/* Does the default camera sit inside a closed model? Only a camera inside
 * the bounds can; then ENCLOSED_RAYS rays from it, spread evenly over the
 * sphere (a Fibonacci lattice), must each meet a triangle. Brute force
 * over the triangles: it runs only for scenes whose emitters are dim or
 * that emit nothing (see choose_default_env) and stops at the first ray
 * that escapes. */
#define ENCLOSED_RAYS 64
static int camera_enclosed(const st_scene *s)
{
    const float *c = s->default_camera.origin;
    for (int k = 0; k < 3; k++)
        if (!(c[k] > s->bounds_min[k] && c[k] < s->bounds_max[k]))
            return 0;
    const double o[3] = {c[0], c[1], c[2]}, golden = PI * (3.0 - sqrt(5.0));
    for (int i = 0; i < ENCLOSED_RAYS; i++) {
        double z = 1.0 - (2.0 * i + 1.0) / ENCLOSED_RAYS, r = sqrt(1.0 - z * z);
        const double d[3] = {r * cos(golden * i), r * sin(golden * i), z};
        st_u32 t = 0;
        while (t < s->tri_count && ray_triangle(s, t, o, d) == INFINITY)
            t++;
        if (t == s->tri_count)
            return 0;
    }
    return 1;
}

/* The most radiant intensity a light may have per channel (colour x intensity, W/sr): each factor
 * is bounded alike in the file, but their product, in float, may pass FLT_MAX and leave every
 * sample it lights non-finite. Far above any physical lamp, far below the float range. */
#define MAX_LIGHT_INTENSITY 1e30

/* ST_ENV_HEADLIGHT's light: a white point light at the default camera of
 * radiant intensity pi d^2, d the distance of the nearest tenth of the view
 * (dark_view.h), so that a white Lambertian surface facing it there shows
 * radiance 1, as under a white sky: the near part of the view looks as a
 * sky would light it, and the light's fall-off darkens what lies farther
 * (a median measured from the far walls of a city blew the near models out
 * to white). Appended to the punctual lights, its power counted. */
static st_status add_headlight(st_scene *s, st_error *err)
{
    double d = 0.0;
    if (st_scene_view_distance(s, &d, err) != ST_OK)
        return err->status;
    if (!(d > 0.0))
        d = st_scene_radius(s);
    st_punctual *lights = realloc(s->punctual, (s->punctual_count + 1u) * sizeof *lights);
    if (!lights)
        return st_fail(err, ST_ERR_NOMEM, "out of memory adding a light at the camera");
    s->punctual = lights;
    st_punctual *l = &lights[s->punctual_count++];
    double intensity = fmin(PI * d * d, MAX_LIGHT_INTENSITY);
    for (int k = 0; k < 3; k++) {
        l->pos[k] = s->default_camera.origin[k];
        l->dir[k] = s->default_camera.forward[k];
        l->intensity[k] = (float)intensity;
    }
    l->pos[3] = (float)ST_PUNCT_POINT;
    l->dir[3] = l->intensity[3] = -1.0f;
    double power = st_punctual_power(l, st_scene_radius(s));
    s->punctual_power += power;
    s->emitted_power += power;
    return ST_OK;
}

/* The environment a render that names none gets (st_scene.h). White
 * radiance 1 unless the scene's own lights carry at least half of the
 * power it emits: lamps, emitters brighter than a white surface under that
 * environment (some channel of emissive factor x strength above 1, which
 * only KHR_materials_emissive_strength allows), and punctual lights. The
 * dimmer emitters (a screen, a label, a helmet's lights) glow in a lit
 * world; a scene without them would render black. Without lamps the
 * environment is still off when the camera sits inside a closed model,
 * which it could not reach anyway; where nothing emits there, the view
 * would be black whatever the environment, and a headlight lights it
 * (add_headlight). Where the own lights would leave most
 * of the default view black (more than DARK_VIEW_MAX of it unreached by
 * any light directly, dark_view.h: a lamp behind glass, a lone directional
 * light from behind, a small model in the dark), a dim environment of
 * DIM_ENV stays on: the lights still stand out, and nothing is black. */
#define DARK_VIEW_MAX 0.5
#define DIM_ENV 0.25f
static st_status choose_default_env(st_scene *s, double lamp_power, st_error *err)
{
    double lights = lamp_power + s->punctual_power, glow = s->emitted_power - lights, dark = 0.0;
    if (s->emitted_power <= 0.0)
        s->env_default = camera_enclosed(s) ? ST_ENV_HEADLIGHT : ST_ENV_NOTHING_EMITS;
    else if (lights >= glow)
        s->env_default = ST_ENV_OWN_LIGHTS;
    else if (camera_enclosed(s))
        s->env_default = ST_ENV_ENCLOSED;
    else
        s->env_default = ST_ENV_DIM_EMITTERS;
    if (s->env_default == ST_ENV_OWN_LIGHTS) {
        if (st_scene_dark_fraction(s, &dark, err) != ST_OK)
            return err->status;
        if (dark > DARK_VIEW_MAX)
            s->env_default = ST_ENV_DARK_VIEW;
    }
    if (s->env_default == ST_ENV_HEADLIGHT && add_headlight(s, err) != ST_OK)
        return err->status;
    float level = s->env_default == ST_ENV_NOTHING_EMITS || s->env_default == ST_ENV_DIM_EMITTERS
                      ? 1.0f
                  : s->env_default == ST_ENV_DARK_VIEW ? DIM_ENV
                                                       : 0.0f;
    for (int k = 0; k < 3; k++)
        s->default_env[k] = level;
    s->default_sky = level > 0.0f;
    return ST_OK;
}

/* The power the emissive surfaces radiate, π x area x the mean of the
 * emissive factor times the emissive texture's mean (a Lambertian emitter
 * of radiance L radiates π L per unit area), and the environment default
 * it decides (choose_default_env). Lamps: materials with an emissive
 * factor (x strength) above 1 in some channel. */
static st_status emitted_power(st_scene *s, st_error *err)
{
    double power = 0.0, lamp_power = 0.0;
    for (st_u32 t = 0; t < s->tri_count; t++) {
        const st_material *m = &s->materials[s->tri_material[t]];
        if (!(m->emission[0] > 0.0f || m->emission[1] > 0.0f || m->emission[2] > 0.0f))
            continue;
        float mean[3];
        texture_mean(s, m->emission_tex, mean);
        const float *p = s->positions + 9 * (size_t)t;
        double e1[3], e2[3];
        for (int k = 0; k < 3; k++) {
            e1[k] = (double)p[3 + k] - p[k];
            e2[k] = (double)p[6 + k] - p[k];
        }
        double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
               cz = e1[0] * e2[1] - e1[1] * e2[0];
        double area = 0.5 * sqrt(cx * cx + cy * cy + cz * cz), le = 0.0;
        for (int k = 0; k < 3; k++)
            le += (double)m->emission[k] * mean[k] / 3.0;
        power += ST_PI_F * area * le;
        if (m->emission[0] > 1.0f || m->emission[1] > 1.0f || m->emission[2] > 1.0f)
            lamp_power += ST_PI_F * area * le;
    }
    s->punctual_power = 0.0;
    for (st_u32 i = 0; i < s->punctual_count; i++)
        s->punctual_power += st_punctual_power(&s->punctual[i], st_scene_radius(s));
    power += s->punctual_power;
    s->emitted_power = power;
    return choose_default_env(s, lamp_power, err);
}


/* A point of the scene, already in float: a coordinate finite as a double (1e39) may not be. */
static int finite3(const float v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

static void copy_camera(const st_gltf_camera *c, st_scene_camera *out)
{
    memcpy(out->origin, c->origin, sizeof out->origin);
    memcpy(out->forward, c->forward, sizeof out->forward);
    memcpy(out->up, c->up, sizeof out->up);
    out->yfov = c->yfov;
    out->ymag = c->ymag;
    out->orthographic = c->orthographic;
    out->from_file = 1;
}

static st_status take_cameras(const st_gltf_data *g, st_scene *s, const char *label,
                              st_error *err)
{
    frame_bounds(s, &s->auto_camera);
    if (g->camera_count == 0) {
        s->default_camera = s->auto_camera;
        return ST_OK;
    }
    if (g->camera_count > UINT32_MAX)
        return st_fail(err, ST_ERR_FORMAT, "%s: too many cameras", label);
    s->cameras = calloc(g->camera_count, sizeof *s->cameras);
    if (!s->cameras)
        return st_fail(err, ST_ERR_NOMEM, "%s: out of memory", label);
    for (size_t i = 0; i < g->camera_count; i++) {
        const st_gltf_camera *c = &g->cameras[i];
        if (!finite3(c->origin) || !finite3(c->forward) || !finite3(c->up))
            return st_fail(err, ST_ERR_FORMAT, "%s: camera %zu at (%g, %g, %g): a coordinate "
                           "past the float range (%g)", label, i, c->origin[0], c->origin[1],
                           c->origin[2], FLT_MAX);
        copy_camera(c, &s->cameras[i]);
    }
    s->camera_count = (st_u32)g->camera_count;
    s->default_camera = s->cameras[0];
    return ST_OK;
}

/* The shim's KHR_lights_punctual lights as the device reads them: colour x
 * intensity, and the spot's cone angles as cosines. */
static st_status take_lights(const st_gltf_data *g, st_scene *s, const char *label,
                             st_error *err)
{
    if (g->light_count == 0)
        return ST_OK;
    if (g->light_count > UINT32_MAX)
        return st_fail(err, ST_ERR_FORMAT, "%s: too many lights", label);
    s->punctual = calloc(g->light_count, sizeof *s->punctual);
    if (!s->punctual)
        return st_fail(err, ST_ERR_NOMEM, "%s: out of memory", label);
    for (size_t i = 0; i < g->light_count; i++) {
        const st_gltf_light *l = &g->lights[i];
        st_punctual *p = &s->punctual[i];
        if (!finite3(l->pos) || !finite3(l->dir))
            return st_fail(err, ST_ERR_FORMAT, "%s: light %zu (in node order) at (%g, %g, %g): a "
                           "coordinate past the float range (%g)", label, i, l->pos[0], l->pos[1],
                           l->pos[2], FLT_MAX);
        for (int k = 0; k < 3; k++) {
            double power = (double)l->color[k] * l->intensity;
            if (!(power <= MAX_LIGHT_INTENSITY))
                return st_fail(err, ST_ERR_FORMAT, "%s: light %zu (in node order): colour %g x "
                               "intensity %g = %g, past the most a light may have (%g)", label,
                               i, l->color[k], l->intensity, power, MAX_LIGHT_INTENSITY);
            p->pos[k] = l->pos[k];
            p->dir[k] = l->dir[k];
            p->intensity[k] = l->color[k] * l->intensity;
        }
        p->pos[3] = (float)l->type;
        p->dir[3] = l->type == ST_PUNCT_SPOT ? cosf(l->outer_cone) : -1.0f;
        p->intensity[3] = l->type == ST_PUNCT_SPOT ? cosf(l->inner_cone) : -1.0f;
    }
    s->punctual_count = (st_u32)g->light_count;
    return ST_OK;
}

/* The shim's warnings, each headed by the file name, and one for the
 * triangles dropped (zero area or non-finite after the transforms). */
static st_status take_warnings(const st_gltf_data *g, st_scene *s, const char *label,
                               st_error *err)
{
    size_t count = g->warning_count + (g->dropped ? 1 : 0);
    if (count == 0)
        return ST_OK;
    s->warnings = calloc(count, sizeof *s->warnings);
    if (!s->warnings)
        return st_fail(err, ST_ERR_NOMEM, "%s: out of memory", label);
    for (size_t i = 0; i < count; i++) {
        char dropped[96];
        snprintf(dropped, sizeof dropped, "%zu triangle%s dropped (zero area or non-finite)",
                 g->dropped, g->dropped == 1 ? "" : "s");
        const char *text = i < g->warning_count ? g->warnings[i] : dropped;
        size_t n = strlen(label) + strlen(text) + 3;
        if (!(s->warnings[i] = malloc(n)))
            return st_fail(err, ST_ERR_NOMEM, "%s: out of memory", label);
        snprintf(s->warnings[i], n, "%s: %s", label, text);
        s->warning_count++;
    }
    return ST_OK;
}

/* Moves the shim's arrays into the scene and completes it. */
static st_status build_scene(st_gltf_data *g, st_scene *s, const char *label, st_error *err)
{
    if (g->tri_count == 0 && g->dropped == 0)
        return st_fail(err, ST_ERR_FORMAT, "%s: no triangles in the default scene", label);
    if (g->tri_count == 0)
        return st_fail(err, ST_ERR_FORMAT,
                       "%s: no triangles in the default scene (%zu dropped: zero area or "
                       "non-finite)",
                       label, g->dropped);
    if (g->tri_count > UINT32_MAX || g->dropped > UINT32_MAX)
        return st_fail(err, ST_ERR_FORMAT, "%s: too many triangles (%zu)", label,
                       g->tri_count + g->dropped);
    st_status status;
    if ((status = take_materials(g, s, label, err)) != ST_OK ||
        (status = take_textures(g, s, label, err)) != ST_OK)
        return status;
    s->tri_count = (st_u32)g->tri_count;
    s->dropped = (st_u32)g->dropped;
    s->positions = g->positions;
    s->normals = g->normals;
    s->uvs = g->uvs;
    s->uvs1 = g->uvs1;
    s->tangents = g->tangents;
    s->colors = g->colors;
    g->tangents = g->colors = NULL;
    s->tri_material = g->tri_material;
    g->positions = g->normals = g->uvs = g->uvs1 = NULL;
    g->tri_material = NULL;
    compute_bounds(s);
    if ((status = take_cameras(g, s, label, err)) != ST_OK ||
        (status = take_lights(g, s, label, err)) != ST_OK ||
        (status = take_warnings(g, s, label, err)) != ST_OK ||
        (status = emitted_power(s, err)) != ST_OK)
        return status;
    mark_vertex_colors(s);
    snprintf(s->name, sizeof s->name, "%s", label);
    return ST_OK;
}

/* Reads the scene file spec (a regular file, or standard input for "-") into
 * *file and names in *dir the folder its URIs resolve against: none (NULL)
 * for standard input, whose folder is unknown; for a symbolic link (as
 * /dev/stdin, or /proc/self/fd/N, redirected from a file) the folder of the
 * file it leads to, never the link's own folder (/dev). */
static st_status read_scene_file(const char *spec, unsigned char **file, size_t *size,
                                 char **dir, st_error *err)
{
    *dir = NULL;
    if (!strcmp(spec, "-"))
        return st_scene_fs_read_stdin(ST_SCENE_MAX_FILE_BYTES, file, size, err);
    st_status status = st_scene_fs_read(spec, ST_SCENE_MAX_FILE_BYTES, "a scene file", file,
                                        size, err);
    if (status != ST_OK)
        return status;
    char *real = st_scene_fs_link_target(spec);
    *dir = dir_of(real ? real : spec);
    free(real);
    if (*dir)
        return ST_OK;
    free(*file);
    *file = NULL;
    return st_fail(err, ST_ERR_NOMEM, "%s: out of memory", spec);
}

/* ---- public API ------------------------------------------------------------------ */

st_status st_scene_load(const char *spec, st_scene **out, st_error *err)
{
    *out = NULL;
    if (!spec)
        spec = DEFAULT_SCENE;
    const unsigned char *bytes;
    size_t size;
    unsigned char *file = NULL;
    char *dir = NULL;
    st_gltf_data g = {0};
    st_scene *s = NULL;
    st_status status;
    const char *ext = foreign_extension(spec);
    if (ext)
        return st_fail(err, ST_ERR_USAGE, "%s: strata reads glTF 2.0 scenes (.gltf, .glb) and "
                       "its built-in scenes (--scene-list), not %s files: convert it to glTF "
                       "first", spec, ext);
    int builtin = is_builtin_spec(spec) && strcmp(spec, "-") != 0;
    if (builtin) {
        const st_embedded_file *e = find_builtin(spec);
        if (!e)
            return unknown_builtin(spec, err);
        bytes = e->data;
        size = e->size;
    } else {
        if ((status = read_scene_file(spec, &file, &size, &dir, err)) != ST_OK)
            return status;
        bytes = file;
    }
    /* dir stays NULL for a built-in scene: the shim then opens no file. */
    if ((status = st_gltf_shim_load(spec, bytes, size, dir, &g, err)) != ST_OK)
        goto done;
    if (!(s = calloc(1, sizeof *s))) {
        status = st_fail(err, ST_ERR_NOMEM, "%s: out of memory", spec);
        goto done;
    }
    if ((status = build_scene(&g, s, spec, err)) != ST_OK)
        goto done;
    if (builtin) /* the laboratory's scenes keep the uniform environment their figures assume */
        s->default_sky = 0;
    *out = s;
    s = NULL;
done:
    st_scene_destroy(s);
    st_gltf_shim_release(&g);
    free(dir);
    free(file);
    return status;
}

/* zlib's CRC-32 over one array's bytes (NULL or empty: unchanged). */
static st_u32 crc_of(st_u32 crc, const void *p, size_t bytes)
{
    const unsigned char *b = p;
    while (p && bytes > 0) { /* crc32 takes a uInt length */
        uInt n = bytes > 1u << 30 ? 1u << 30 : (uInt)bytes;
        crc = (st_u32)crc32(crc, b, n);
        b += n;
        bytes -= n;
    }
    return crc;
}

st_u32 st_scene_content_hash(const st_scene *s)
{
    size_t t = s->tri_count;
    st_u32 crc = (st_u32)crc32(0L, Z_NULL, 0);
    crc = crc_of(crc, &s->tri_count, sizeof s->tri_count);
    crc = crc_of(crc, s->positions, 9 * t * sizeof(float));
    crc = crc_of(crc, s->normals, 9 * t * sizeof(float));
    crc = crc_of(crc, s->uvs, 6 * t * sizeof(float));
    crc = crc_of(crc, s->uvs1, 6 * t * sizeof(float)); /* NULL: no bytes */
    crc = crc_of(crc, s->tangents, 12 * t * sizeof(float));
    crc = crc_of(crc, s->colors, 12 * t * sizeof(float));
    crc = crc_of(crc, s->tri_material, t * sizeof(st_u32));
    crc = crc_of(crc, s->materials, s->material_count * sizeof *s->materials);
    crc = crc_of(crc, s->textures, s->texture_count * sizeof *s->textures);
    crc = crc_of(crc, s->texels, s->texel_count * sizeof *s->texels);
    crc = crc_of(crc, s->cameras, s->camera_count * sizeof *s->cameras);
    /* no lights: no bytes, so the hashes of scenes without them stay as they were */
    crc = crc_of(crc, s->punctual, s->punctual_count * sizeof *s->punctual);
    crc = crc_of(crc, s->default_env, sizeof s->default_env);
    return crc_of(crc, &s->default_sky, sizeof s->default_sky);
}

void st_scene_destroy(st_scene *scene)
{
    if (!scene)
        return;
    free(scene->positions);
    free(scene->normals);
    free(scene->uvs);
    free(scene->uvs1);
    free(scene->tangents);
    free(scene->colors);
    free(scene->tri_material);
    free(scene->materials);
    free(scene->textures);
    free(scene->texels);
    free(scene->cameras);
    free(scene->punctual);
    for (st_u32 i = 0; i < scene->warning_count; i++)
        free(scene->warnings[i]);
    free(scene->warnings);
    free(scene);
}

st_status st_scene_view_camera(const st_scene *scene, st_i32 index, st_scene_camera *out,
                               st_error *err)
{
    if (index == ST_CAMERA_AUTO) {
        *out = scene->auto_camera;
        return ST_OK;
    }
    if (index >= 0 && (st_u32)index >= scene->camera_count)
        return st_fail(err, ST_ERR_USAGE, "camera %d: %s has %u camera node%s%s", (int)index,
                       scene->name, scene->camera_count, scene->camera_count == 1 ? "" : "s",
                       scene->camera_count ? " (numbered from 0)" : "");
    *out = index < 0 ? scene->default_camera : scene->cameras[index];
    return ST_OK;
}
