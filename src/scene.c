/* scene.c — scene loading (st_scene.h): resolves a scene spec to a built-in
 * scene (embedded in the binary) or a file, hands the bytes to the glTF shim
 * (gltf_shim.cpp), and adds what does not depend on the file format: the
 * default material, the bounds and the default camera.
 *
 * Invariant: a scene returned by st_scene_load satisfies st_scene.h's list
 * (tri_count >= 1, finite non-degenerate triangles, unit normals, materials in
 * range, bounds holding every vertex, orthonormal camera); anything else is an
 * error and no scene. */
#include "st_scene.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "embedded.h"
#include "gltf_shim.h"

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

static int is_builtin_spec(const char *spec)
{
    return !strchr(spec, '/') && !ends_with(spec, ".gltf") && !ends_with(spec, ".glb");
}

static const st_embedded_file *find_builtin(const char *name)
{
    for (unsigned i = 0; i < st_embedded_scene_count; i++) {
        size_t n = scene_stem(st_embedded_scenes[i].name);
        if (n > 0 && strlen(name) == n && strncmp(name, st_embedded_scenes[i].name, n) == 0)
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
    return st_fail(err, ST_ERR_USAGE, "unknown built-in scene '%s' (built-in: %s)", name,
                   n ? list : "none");
}

/* ---- files ------------------------------------------------------------------ */

static st_status read_file(const char *path, unsigned char **data, size_t *size, st_error *err)
{
    *data = NULL;
    *size = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return st_fail(err, ST_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    size_t cap = 0;
    st_status s = ST_OK;
    for (;;) {
        if (*size == cap) {
            cap = cap ? 2 * cap : 1 << 16;
            unsigned char *grown = realloc(*data, cap);
            if (!grown) {
                s = st_fail(err, ST_ERR_NOMEM, "%s: out of memory reading the file", path);
                break;
            }
            *data = grown;
        }
        size_t got = fread(*data + *size, 1, cap - *size, f);
        *size += got;
        if (got == 0) {
            if (ferror(f))
                s = st_fail(err, ST_ERR_IO, "%s: cannot read: %s", path, strerror(errno));
            break;
        }
    }
    fclose(f);
    if (s != ST_OK) {
        free(*data);
        *data = NULL;
        *size = 0;
    }
    return s;
}

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

/* Default framing: the bounding sphere (centre c, radius r = half the box
 * diagonal) subtends the vertical field of view from distance
 * d = r / sin(yfov / 2) (the sphere's tangent cone has half-angle asin(r/d)),
 * so the camera sits at c + (0, 0, d) looking along -Z with +Y up. */
static void default_camera(st_scene *s)
{
    double c[3], r2 = 0.0;
    for (int k = 0; k < 3; k++) {
        c[k] = 0.5 * ((double)s->bounds_min[k] + s->bounds_max[k]);
        double h = 0.5 * ((double)s->bounds_max[k] - s->bounds_min[k]);
        r2 += h * h;
    }
    const double yfov = DEFAULT_YFOV_DEGREES * PI / 180.0;
    const double d = sqrt(r2) / sin(0.5 * yfov);
    st_scene_camera *cam = &s->camera;
    for (int k = 0; k < 3; k++) {
        cam->origin[k] = (float)c[k];
        cam->forward[k] = 0.0f;
        cam->up[k] = 0.0f;
    }
    cam->origin[2] = (float)(c[2] + d);
    cam->forward[2] = -1.0f;
    cam->up[1] = 1.0f;
    cam->yfov = (float)yfov;
    cam->from_file = 0;
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
        memcpy(s->materials[i].base_color, g->materials + 8 * i, 4 * sizeof(float));
        memcpy(s->materials[i].emission, g->materials + 8 * i + 4, 4 * sizeof(float));
    }
    if (need_default) {
        st_material *m = &s->materials[g->material_count];
        m->base_color[0] = m->base_color[1] = m->base_color[2] = DEFAULT_ALBEDO;
        m->base_color[3] = 1.0f;
        for (size_t i = 0; i < g->tri_count; i++)
            if (g->tri_material[i] == ST_GLTF_NO_MATERIAL)
                g->tri_material[i] = (uint32_t)g->material_count;
    }
    s->material_count = (st_u32)count;
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
    st_status status = take_materials(g, s, label, err);
    if (status != ST_OK)
        return status;
    s->tri_count = (st_u32)g->tri_count;
    s->dropped = (st_u32)g->dropped;
    s->positions = g->positions;
    s->normals = g->normals;
    s->tri_material = g->tri_material;
    g->positions = g->normals = NULL;
    g->tri_material = NULL;
    compute_bounds(s);
    if (g->has_camera) {
        memcpy(s->camera.origin, g->cam_origin, sizeof s->camera.origin);
        memcpy(s->camera.forward, g->cam_forward, sizeof s->camera.forward);
        memcpy(s->camera.up, g->cam_up, sizeof s->camera.up);
        s->camera.yfov = g->cam_yfov;
        s->camera.from_file = 1;
    } else {
        default_camera(s);
    }
    snprintf(s->name, sizeof s->name, "%s", label);
    return ST_OK;
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
    if (is_builtin_spec(spec)) {
        const st_embedded_file *e = find_builtin(spec);
        if (!e)
            return unknown_builtin(spec, err);
        bytes = e->data;
        size = e->size;
    } else {
        if ((status = read_file(spec, &file, &size, err)) != ST_OK)
            return status;
        bytes = file;
        if (!(dir = dir_of(spec))) {
            status = st_fail(err, ST_ERR_NOMEM, "%s: out of memory", spec);
            goto done;
        }
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
    *out = s;
    s = NULL;
done:
    st_scene_destroy(s);
    st_gltf_shim_release(&g);
    free(dir);
    free(file);
    return status;
}

void st_scene_destroy(st_scene *scene)
{
    if (!scene)
        return;
    free(scene->positions);
    free(scene->normals);
    free(scene->tri_material);
    free(scene->materials);
    free(scene);
}
