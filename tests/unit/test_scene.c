/* test_scene.c — tests of the scene module (st_scene.h, src/scene/scene.c,
 * src/scene/gltf_*.cpp). Run from the repository root: the test scenes are in
 * tests/scenes/ (written by tests/scenes/make_test_scenes.py), the Khronos
 * sample models, when present, in ../shared/scenes/khronos.
 *
 * Expected values come from outside the loader: the published Cornell box
 * measurements, the pyramid table below (a copy of the generator's), Python's
 * own transform of the nested scene (trs_baked.gltf), geometric identities
 * (a transformed face normal stays perpendicular to the transformed face),
 * and the triangle counts of the Khronos models' INDEX.md. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "skip.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "dark_view.h"
#include "st_render.h"
#include "st_scene.h"

#define SCENES "tests/scenes/"
#define KHRONOS "../shared/scenes/khronos"

/* ---- helpers --------------------------------------------------------------- */

static void near(double got, double want, double tol, const char *what)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("%s: got %.9g, want %.9g (tolerance %g)", what, got, want, tol);
}

static void near3(const float *got, double x, double y, double z, double tol, const char *what)
{
    near(got[0], x, tol, what);
    near(got[1], y, tol, what);
    near(got[2], z, tol, what);
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Unit geometric normal (v1 - v0) x (v2 - v0) of triangle t, in double. */
static void face_normal(const st_scene *s, st_u32 t, double n[3])
{
    const float *p = s->positions + 9 * (size_t)t;
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = (double)p[3 + k] - p[k];
        e2[k] = (double)p[6 + k] - p[k];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double len = sqrt(dot3(n, n));
    for (int k = 0; k < 3; k++)
        n[k] /= len;
}

/* Everything st_scene.h promises of a loaded scene. */
static void check_invariants(const st_scene *s)
{
    assert_true(s->tri_count >= 1);
    assert_true(s->material_count >= 1);
    for (st_u32 t = 0; t < s->tri_count; t++) {
        assert_true(s->tri_material[t] < s->material_count);
        double g[3];
        face_normal(s, t, g);
        assert_true(isfinite(g[0]) && isfinite(g[1]) && isfinite(g[2])); /* non-zero area */
        for (int v = 0; v < 3; v++) {
            const float *p = s->positions + 9 * (size_t)t + 3 * v;
            const float *n = s->normals + 9 * (size_t)t + 3 * v;
            for (int k = 0; k < 3; k++) {
                assert_true(isfinite(p[k]));
                assert_true(p[k] >= s->bounds_min[k] && p[k] <= s->bounds_max[k]);
            }
            near(sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]), 1.0, 1e-5,
                 "shading normal length");
        }
    }
    for (st_u32 t = 0; t < s->tri_count; t++)
        for (int k = 0; k < 6; k++)
            assert_true(isfinite(s->uvs[6 * (size_t)t + k]));
    for (st_u32 m = 0; m < s->material_count; m++) {
        const st_material *mat = &s->materials[m];
        const st_u32 tex[3] = {mat->base_color_tex, mat->emission_tex,
                               mat->metallic_roughness_tex};
        for (int k = 0; k < 3; k++)
            assert_true(tex[k] == ST_NO_TEXTURE || tex[k] < s->texture_count);
        assert_true(mat->alpha_mode <= ST_ALPHA_BLEND);
    }
    for (st_u32 i = 0; i < s->texture_count; i++) {
        const st_texture *t = &s->textures[i];
        assert_true(t->width >= 1 && t->height >= 1 && t->levels >= 1);
        assert_true((st_u64)t->offset + st_scene_mip_texels(t->width, t->height) <=
                    s->texel_count);
    }
    for (st_u32 i = 0; i <= s->camera_count; i++) {
        const st_scene_camera *c = i < s->camera_count ? &s->cameras[i] : &s->default_camera;
        const double f[3] = {c->forward[0], c->forward[1], c->forward[2]};
        const double u[3] = {c->up[0], c->up[1], c->up[2]};
        near(sqrt(dot3(f, f)), 1.0, 1e-5, "camera forward length");
        near(sqrt(dot3(u, u)), 1.0, 1e-5, "camera up length");
        near(dot3(f, u), 0.0, 1e-5, "camera forward . up");
        if (c->orthographic)
            assert_true(c->ymag > 0.0f && isfinite(c->ymag));
        else
            assert_true(c->yfov > 0.0f && c->yfov < 3.1415927f);
    }
    for (st_u32 i = 0; i < s->warning_count; i++)
        assert_non_null(strstr(s->warnings[i], s->name)); /* each names the file */
}

/* Does some warning of s contain `phrase`? */
static int has_warning(const st_scene *s, const char *phrase)
{
    for (st_u32 i = 0; i < s->warning_count; i++)
        if (strstr(s->warnings[i], phrase))
            return 1;
    return 0;
}

static st_scene *load_ok(const char *spec)
{
    st_error err = {0};
    st_scene *s = NULL;
    st_status st = st_scene_load(spec, &s, &err);
    if (st != ST_OK)
        fail_msg("loading %s: status %d: %s", spec ? spec : "(default)", st, err.msg);
    check_invariants(s);
    return s;
}

/* Loads spec expecting failure with `status`; the message must name `name`
 * (when given) and contain `phrase` (when given). */
static void load_fails(const char *spec, st_status status, const char *name, const char *phrase)
{
    static st_scene sentinel;
    st_error err = {0};
    st_scene *s = &sentinel; /* must come back NULL */
    st_status st = st_scene_load(spec, &s, &err);
    if (st != status || err.status != status)
        fail_msg("%s: status %d (err %d, \"%s\"), want %d", spec, st, err.status, err.msg, status);
    assert_null(s);
    if (name && !strstr(err.msg, name))
        fail_msg("%s: message \"%s\" does not name the file", spec, err.msg);
    if (phrase && !strstr(err.msg, phrase))
        fail_msg("%s: message \"%s\" lacks \"%s\"", spec, err.msg, phrase);
}

static unsigned char *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    assert_int_equal(fseek(f, 0, SEEK_END), 0);
    long n = ftell(f);
    assert_true(n > 0);
    rewind(f);
    unsigned char *data = malloc((size_t)n);
    assert_non_null(data);
    assert_int_equal(fread(data, 1, (size_t)n, f), (size_t)n);
    fclose(f);
    *size = (size_t)n;
    return data;
}

static void write_all(const char *path, const unsigned char *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, size, f), size);
    assert_int_equal(fclose(f), 0);
}

/* A scratch directory for generated files, removed by the caller. */
static void make_scratch(char dir[64])
{
    snprintf(dir, 64, "/tmp/strata-test-scene-XXXXXX");
    assert_non_null(mkdtemp(dir));
}

static int dir_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* ---- the built-in Cornell box --------------------------------------------- */

/* Published data (Cornell Program of Computer Graphics, "Cornell Box Data"),
 * in metres: room 0..0.556 x 0..0.5488 x 0..0.5592; camera at
 * (0.278, 0.273, -0.800) looking along +Z, 35 mm lens on 25 mm film. */
static void cornell_box_loads_as_default_builtin(void **state)
{
    (void)state;
    st_scene *s = load_ok(NULL);
    assert_string_equal(s->name, "cornell-box");
    assert_int_equal(s->tri_count, 32); /* 5 walls + 2 x 5 block faces + light, 2 each */
    assert_int_equal(s->dropped, 0);
    assert_int_equal(s->material_count, 4); /* every primitive names one: no default */
    assert_int_equal(s->default_camera.from_file, 1);
    near3(s->default_camera.origin, 0.278, 0.273, -0.800, 1e-6, "camera origin");
    near3(s->default_camera.forward, 0, 0, 1, 1e-6, "camera forward");
    near3(s->default_camera.up, 0, 1, 0, 1e-6, "camera up");
    near(s->default_camera.yfov, 2.0 * atan(12.5 / 35.0), 1e-6, "camera yfov");
    near3(s->bounds_min, 0, 0, 0, 1e-6, "bounds min");
    near3(s->bounds_max, 0.556, 0.5488, 0.5592, 1e-6, "bounds max");
    st_scene_destroy(s);

    s = load_ok("cornell-box");
    assert_string_equal(s->name, "cornell-box");
    assert_int_equal(s->tri_count, 32);
    st_scene_destroy(s);
}

static void cornell_box_materials_have_specified_values(void **state)
{
    (void)state;
    st_scene *s = load_ok("cornell-box");
    /* emission = light colour, base colour = albedo; per material, the number of
     * triangles: white = floor, ceiling, back wall and 10 block faces. */
    static const struct {
        float albedo[3], emission[3];
        int triangles;
    } want[4] = {
        {{0.73f, 0.73f, 0.73f}, {0, 0, 0}, 26},
        {{0.63f, 0.065f, 0.05f}, {0, 0, 0}, 2},
        {{0.14f, 0.45f, 0.09f}, {0, 0, 0}, 2},
        {{0.78f, 0.78f, 0.78f}, {17, 12, 4}, 2},
    };
    int count[4] = {0};
    for (st_u32 t = 0; t < s->tri_count; t++)
        count[s->tri_material[t]]++;
    for (int m = 0; m < 4; m++) {
        near3(s->materials[m].base_color, want[m].albedo[0], want[m].albedo[1], want[m].albedo[2],
              1e-6, "albedo");
        near3(s->materials[m].emission, want[m].emission[0], want[m].emission[1],
              want[m].emission[2], 1e-5, "emission");
        assert_int_equal(count[m], want[m].triangles);
    }
    st_scene_destroy(s);
}

/* (x, z) inside the convex footprint of a block (4 corners, either order). */
static int inside_footprint(const double fp[4][2], double x, double z)
{
    int pos = 0, neg = 0;
    for (int i = 0; i < 4; i++) {
        const double *a = fp[i], *b = fp[(i + 1) % 4];
        double c = (b[0] - a[0]) * (z - a[1]) - (b[1] - a[1]) * (x - a[0]);
        pos += c > 0;
        neg += c < 0;
    }
    return pos == 0 || neg == 0;
}

/* A point of the room's air: inside the walls, outside both blocks. */
static int in_air(const double q[3])
{
    static const double short_fp[4][2] = {
        {0.130, 0.065}, {0.082, 0.225}, {0.240, 0.272}, {0.290, 0.114}};
    static const double tall_fp[4][2] = {
        {0.423, 0.247}, {0.265, 0.296}, {0.314, 0.456}, {0.472, 0.406}};
    int in_room = q[0] > 0 && q[0] < 0.556 && q[1] > 0 && q[1] < 0.5488 && q[2] > 0 &&
                  q[2] < 0.5592;
    int in_short = q[1] < 0.165 && inside_footprint(short_fp, q[0], q[2]);
    int in_tall = q[1] < 0.330 && inside_footprint(tall_fp, q[0], q[2]);
    return in_room && !in_short && !in_tall;
}

/* Stepping 5 mm along the normal from points of a triangle must reach the air
 * of the room. A normal facing the wrong way lands behind a wall, below the
 * floor or inside a block from every point of the face; a right one reaches
 * the air from at least one of the centroid and the three points near the
 * corners (a floor triangle's centroid may lie under a block). The shading
 * normals must also equal the face normals (flat faces). */
static void cornell_box_normals_face_the_air(void **state)
{
    (void)state;
    static const double bary[4][3] = {
        {1 / 3.0, 1 / 3.0, 1 / 3.0}, {0.8, 0.1, 0.1}, {0.1, 0.8, 0.1}, {0.1, 0.1, 0.8}};
    st_scene *s = load_ok(NULL);
    for (st_u32 t = 0; t < s->tri_count; t++) {
        double g[3];
        face_normal(s, t, g);
        for (int v = 0; v < 3; v++) {
            const float *n = s->normals + 9 * (size_t)t + 3 * v;
            const double nd[3] = {n[0], n[1], n[2]};
            near(dot3(nd, g), 1.0, 1e-6, "shading normal . face normal");
        }
        int reached = 0;
        for (int b = 0; b < 4; b++) {
            const float *p = s->positions + 9 * (size_t)t;
            double q[3];
            for (int k = 0; k < 3; k++)
                q[k] = bary[b][0] * p[k] + bary[b][1] * p[3 + k] + bary[b][2] * p[6 + k] +
                       0.005 * g[k];
            reached += in_air(q);
        }
        if (!reached)
            fail_msg("triangle %u: normal (%g %g %g) faces away from the air", t, g[0], g[1], g[2]);
    }
    st_scene_destroy(s);
}

static void builtin_names_list_cornell_box(void **state)
{
    (void)state;
    const char *names[16];
    st_u32 n = st_scene_builtin_names(names, 16);
    int found = 0;
    for (st_u32 i = 0; i < n; i++)
        found |= strcmp(names[i], "cornell-box") == 0;
    assert_true(found);
    assert_int_equal(st_scene_builtin_names(names, 0), 0);
}

static void unknown_builtin_and_missing_file_are_errors(void **state)
{
    (void)state;
    load_fails("no-such-scene", ST_ERR_USAGE, "no-such-scene", "cornell-box");
    load_fails(SCENES "no_such_file.gltf", ST_ERR_IO, SCENES "no_such_file.gltf", NULL);
    /* a .gltf suffix makes it a path, even without '/' */
    load_fails("cornell-box.gltf", ST_ERR_IO, "cornell-box.gltf", NULL);
    st_scene_destroy(NULL);
}

/* ---- accessor layouts ----------------------------------------------------------- */

/* The pyramid of make_test_scenes.py: vertex normals point away from
 * (0.5, 0.5, -0.5). */
static const double PYRAMID_V[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}};
static const int PYRAMID_T[4][3] = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};

static void check_pyramid(const char *path)
{
    st_scene *s = load_ok(path);
    assert_int_equal(s->tri_count, 4);
    assert_int_equal(s->dropped, 0);
    assert_int_equal(s->material_count, 1); /* the default, appended */
    near3(s->materials[0].base_color, 0.8, 0.8, 0.8, 1e-7, "default albedo");
    for (int t = 0; t < 4; t++)
        for (int v = 0; v < 3; v++) {
            const double *p = PYRAMID_V[PYRAMID_T[t][v]];
            double n[3] = {p[0] - 0.5, p[1] - 0.5, p[2] + 0.5};
            double len = sqrt(dot3(n, n));
            near3(s->positions + 9 * t + 3 * v, p[0], p[1], p[2], 0, path);
            near3(s->normals + 9 * t + 3 * v, n[0] / len, n[1] / len, n[2] / len, 1e-6, path);
        }
    assert_int_equal(s->default_camera.from_file, 0);
    st_scene_destroy(s);
}

static void layouts_u8_u16_u32_indices_give_same_triangles(void **state)
{
    (void)state;
    check_pyramid(SCENES "layout_u8.gltf"); /* external .bin */
    check_pyramid(SCENES "layout_u16.gltf");
    check_pyramid(SCENES "layout_u32.gltf");
}

static void layouts_interleaved_stride_gives_same_triangles(void **state)
{
    (void)state;
    check_pyramid(SCENES "layout_interleaved.gltf");
}

static void layouts_nonindexed_and_glb_give_same_triangles(void **state)
{
    (void)state;
    check_pyramid(SCENES "layout_nonindexed.gltf");
    check_pyramid(SCENES "layout.glb");
}

/* ---- transforms --------------------------------------------------------------- */

static void nested_trs_equals_baked_vertices(void **state)
{
    (void)state;
    st_scene *a = load_ok(SCENES "trs_nested.gltf");
    st_scene *b = load_ok(SCENES "trs_baked.gltf");
    assert_int_equal(a->tri_count, 8); /* 4 nodes x 2; the other scene's node is not loaded */
    assert_int_equal(b->tri_count, 8);
    for (size_t i = 0; i < 9 * 8; i++) {
        near(a->positions[i], b->positions[i], 1e-5, "position");
        near(a->normals[i], b->normals[i], 1e-5, "normal");
    }
    assert_true(a->bounds_max[0] < 50.0f); /* node "other_scene_only" sits at x = 100 */
    st_scene_destroy(a);
    st_scene_destroy(b);
}

/* The file's normals are the mesh's face normals; the inverse transpose keeps
 * them perpendicular to the transformed faces, and the winding flip of the
 * mirrored node keeps the face normal on the same side: so every shading
 * normal must equal the world face normal, whatever the transform. */
static void nested_trs_normals_equal_face_normals(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "trs_nested.gltf");
    for (st_u32 t = 0; t < s->tri_count; t++) {
        double g[3];
        face_normal(s, t, g);
        for (int v = 0; v < 3; v++) {
            const float *n = s->normals + 9 * (size_t)t + 3 * v;
            const double nd[3] = {n[0], n[1], n[2]};
            near(dot3(nd, g), 1.0, 1e-5, "shading normal . face normal");
        }
    }
    st_scene_destroy(s);
}

/* ---- cameras -------------------------------------------------------------------- */

/* Scene roots: geometry, rig, later_root. rig (T (1,0,0), S 2) has children
 * ortho (orthographic, ymag 1), arm -> picked (T (0,1,0), R_y 90), late
 * (T (0,0,9)); later_root (T (0,0,5)) is a root of its own. Depth first:
 * ortho at (1,0,0); picked at (1,0,0) + 2 (0,1,0), R_y(90) mapping -Z to -X;
 * late at (1,0,0) + 2 (0,0,9); later_root at (0,0,5). The node scale does not
 * scale ymag (camera axes are normalised). The first is the default. */
static void cameras_listed_depth_first_first_is_default(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "camera_pick.gltf");
    assert_int_equal(s->camera_count, 4);
    static const struct {
        double origin[3], forward[3];
        int ortho;
        double fov_or_mag;
    } want[4] = {
        {{1, 0, 0}, {0, 0, -1}, 1, 1.0},
        {{1, 2, 0}, {-1, 0, 0}, 0, 0.5},
        {{1, 0, 18}, {0, 0, -1}, 0, 0.9},
        {{0, 0, 5}, {0, 0, -1}, 0, 0.9},
    };
    for (st_u32 i = 0; i < 4; i++) {
        const st_scene_camera *c = &s->cameras[i];
        assert_int_equal(c->from_file, 1);
        assert_int_equal(c->orthographic, want[i].ortho);
        near3(c->origin, want[i].origin[0], want[i].origin[1], want[i].origin[2], 1e-6, "origin");
        near3(c->forward, want[i].forward[0], want[i].forward[1], want[i].forward[2], 1e-6,
              "forward");
        near3(c->up, 0, 1, 0, 1e-6, "up");
        near(c->orthographic ? c->ymag : c->yfov, want[i].fov_or_mag, 1e-7, "yfov or ymag");
    }
    assert_memory_equal(&s->default_camera, &s->cameras[0], sizeof s->default_camera);
    st_error err = {0};
    st_scene_camera view;
    assert_int_equal(st_scene_view_camera(s, 1, &view, &err), ST_OK);
    assert_memory_equal(&view, &s->cameras[1], sizeof view);
    assert_int_equal(st_scene_view_camera(s, -1, &view, &err), ST_OK);
    assert_memory_equal(&view, &s->default_camera, sizeof view);
    assert_int_equal(st_scene_view_camera(s, 4, &view, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "4 camera nodes"));
    assert_memory_equal(&s->default_camera, &s->cameras[0], sizeof view); /* unchanged */
    st_scene_destroy(s);
}

/* Without a camera: looking at the bounds' centre (the direction:
 * auto_camera_sees_the_front), yfov 40 degrees, and the bounding
 * sphere (centre c, radius r) exactly fills the vertical view:
 * |origin - c| sin(yfov / 2) = r. Then every corner of the bounds is within
 * the cone of half-angle yfov / 2. */
static void default_camera_frames_bounding_sphere(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "materials_flat.gltf");
    const st_scene_camera *c = &s->default_camera;
    assert_int_equal(c->from_file, 0);
    near(c->yfov, 40.0 * 3.14159265358979 / 180.0, 1e-6, "yfov");
    double centre[3], r2 = 0, dist2 = 0;
    for (int k = 0; k < 3; k++) {
        centre[k] = 0.5 * (s->bounds_min[k] + s->bounds_max[k]);
        r2 += 0.25 * (s->bounds_max[k] - s->bounds_min[k]) * (s->bounds_max[k] - s->bounds_min[k]);
        dist2 += (c->origin[k] - centre[k]) * (c->origin[k] - centre[k]);
    }
    for (int k = 0; k < 3; k++) /* it looks at the centre */
        near(c->origin[k] + sqrt(dist2) * c->forward[k], centre[k], 1e-5, "looks at the centre");
    near(sqrt(dist2) * sin(0.5 * c->yfov), sqrt(r2), 1e-5, "sphere fit");
    for (int i = 0; i < 8; i++) {
        double d[3];
        for (int k = 0; k < 3; k++)
            d[k] = ((i >> k) & 1 ? s->bounds_max[k] : s->bounds_min[k]) - c->origin[k];
        double cosang = (d[0] * c->forward[0] + d[1] * c->forward[1] + d[2] * c->forward[2]) /
                        sqrt(dot3(d, d));
        assert_true(cosang >= cos(0.5 * c->yfov) - 1e-6);
    }
    st_scene_destroy(s);
}

/* ---- materials, flat normals, dropped triangles -------------------------------- */

static void materials_and_flat_normals_follow_the_file(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "materials_flat.gltf");
    assert_int_equal(s->tri_count, 3);
    assert_int_equal(s->dropped, 2); /* a repeated vertex, three collinear points */
    assert_true(has_warning(s, "materials_flat.gltf: 2 triangles dropped (zero area or non-finite)"));
    assert_true(has_warning(s, "mode 0 (POINTS) skipped"));
    assert_int_equal(s->material_count, 2); /* the file's one + the default */
    assert_int_equal(s->tri_material[0], 0);
    assert_int_equal(s->tri_material[1], 0);
    assert_int_equal(s->tri_material[2], 1);
    /* emission = emissiveFactor (1, 0.5, 0.25) x emissiveStrength 4 */
    near3(s->materials[0].base_color, 0.2, 0.3, 0.4, 1e-7, "base colour");
    near(s->materials[0].base_color[3], 0.5, 1e-7, "base colour alpha");
    near3(s->materials[0].emission, 4, 2, 1, 1e-6, "emission");
    near3(s->materials[1].base_color, 0.8, 0.8, 0.8, 1e-7, "default base colour");
    near3(s->materials[1].emission, 0, 0, 0, 0, "default emission");
    /* no NORMAL: flat normals from the winding, counter-clockwise = +Z */
    static const double want[3][3] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}};
    for (int t = 0; t < 3; t++)
        for (int v = 0; v < 3; v++)
            near3(s->normals + 9 * t + 3 * v, want[t][0], want[t][1], want[t][2], 1e-7,
                  "flat normal");
    st_scene_destroy(s);
}

/* ---- texture coordinates, textures, warnings -------------------------------- */

/* textures.gltf (make_test_scenes.py): three quads (primitive order: float,
 * u8, u16 TEXCOORD_0), indices 0 1 2, 0 2 3, so triangle 2k holds vertices
 * 0, 1, 2 of quad k. Normalised integers divide by 255 and 65535. */
static void texcoords_float_u8_u16_read_as_file_says(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "textures.gltf");
    assert_int_equal(s->tri_count, 6);
    static const double quad_uv[4][2] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    static const int tri_vertex[2][3] = {{0, 1, 2}, {0, 2, 3}};
    for (int q = 0; q < 3; q++)
        for (int t = 0; t < 2; t++)
            for (int v = 0; v < 3; v++) {
                const float *uv = s->uvs + 6 * (size_t)(2 * q + t) + 2 * v;
                const double *want = quad_uv[tri_vertex[t][v]];
                double u = want[0];
                if (q == 2 && u == 1.0)
                    u = 32768.0 / 65535.0; /* the u16 quad's u is 32768 where the others' is 1 */
                near(uv[0], u, 1e-7, "u");
                near(uv[1], want[1], 0, "v");
            }
    st_scene_destroy(s);
}

/* Texture references: material 0 samples image 0 (4 x 2, data: URI) as
 * sRGB base colour with sampler 0 (NEAREST, MIRRORED_REPEAT x
 * CLAMP_TO_EDGE), image 1 (2 x 2, in a bufferView) as sRGB emission through
 * KHR_texture_transform (offset (0.5, 0.25), rotation pi/2, scale (2, 3):
 * [cos 2, sin 3, 0.5; -sin 2, cos 3, 0.25]), and image 0 again, as linear
 * metallic-roughness data (its own chain). Material 2 shares material 0's
 * base colour reference; material 1's texture reads TEXCOORD_1, which its
 * primitive lacks (a warning; the coordinates are 0 there), and the LINES
 * primitive is skipped with a warning. */
static void texture_references_follow_the_file(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "textures.gltf");
    assert_int_equal(s->texture_count, 4);
    const st_material *m = s->materials;
    assert_int_equal(m[0].alpha_mode, ST_ALPHA_MASK);
    near(m[0].alpha_cutoff, 0.3, 1e-7, "alphaCutoff");
    near(m[0].metallic, 0.5, 0, "metallicFactor");
    near(m[1].metallic, 0.0, 0, "metallicFactor");
    near(m[2].roughness, 1.0, 0, "roughnessFactor default");
    assert_int_equal(m[1].alpha_mode, ST_ALPHA_BLEND);
    assert_int_equal(m[2].alpha_mode, ST_ALPHA_OPAQUE);
    assert_int_equal(s->textures[m[1].base_color_tex].uv_set, 1);
    assert_int_equal(s->textures[m[0].base_color_tex].uv_set, 0);
    for (int k = 0; k < 6; k++) /* the u16 quad, triangles 4 and 5: no TEXCOORD_1 */
        assert_true(s->uvs1[24 + k] == 0.0f && s->uvs1[30 + k] == 0.0f);
    assert_int_equal(m[2].base_color_tex, m[0].base_color_tex);
    const st_texture *base = &s->textures[m[0].base_color_tex];
    const st_texture *emit = &s->textures[m[0].emission_tex];
    const st_texture *mr = &s->textures[m[0].metallic_roughness_tex];
    assert_int_equal(base->width, 4);
    assert_int_equal(base->height, 2);
    assert_int_equal(base->levels, 3);
    assert_int_equal(base->flags, ST_TEX_SRGB | ST_TEX_MAG_NEAREST);
    assert_int_equal(base->wrap_s, ST_WRAP_MIRROR);
    assert_int_equal(base->wrap_t, ST_WRAP_CLAMP);
    near(base->lod_bias, 0.5 * log2(8.0), 1e-6, "lod_bias");
    assert_int_equal(emit->width, 2);
    assert_int_equal(emit->flags, ST_TEX_SRGB);
    assert_int_equal(emit->wrap_s, ST_WRAP_REPEAT);
    const double want_t[6] = {0, 3, 0.5, -2, 0, 0.25};
    for (int k = 0; k < 6; k++)
        near(emit->transform[k], want_t[k], 1e-6, "texture transform");
    near(emit->lod_bias, 0.5 * log2(4.0 * 6.0), 1e-6, "lod_bias with |det| 6");
    assert_int_equal(mr->flags, 0);
    assert_int_equal(mr->wrap_s, ST_WRAP_REPEAT);
    assert_true(mr->offset != base->offset); /* same image, linear chain of its own */
    /* level 0 holds the PNG's bytes: row 0 texel 1 = (40, 50, 60, 128) */
    assert_int_equal(s->texels[base->offset + 1], 40u | 50u << 8 | 60u << 16 | 128u << 24);
    assert_int_equal(s->texels[mr->offset + 4], 130u | 140u << 8 | 150u << 16 | 255u << 24);
    /* image 1 (bufferView): red, green / blue, white */
    assert_int_equal(s->texels[emit->offset + 2], 0u | 0u << 8 | 255u << 16 | 255u << 24);
    assert_true(has_warning(s, "mesh 0 (quads) primitive 3: mode 1 (LINES) skipped"));
    assert_true(has_warning(s, "primitive 2: material 1 reads TEXCOORD_1, which the primitive "
                               "lacks"));
    assert_int_equal(s->warning_count, 2);
    st_scene_destroy(s);
}

/* The default environment (st_scene.h): white where nothing emits
 * (cutout, layout_u16, checkerboard; black_emitter's emissive texture is
 * black) or where most of the power comes from emitters no brighter than
 * white (textured_quad's emission 0.5 x a dark texture; lamp_and_glow's
 * lamp carries pi of 5 pi; glow_box_open, whose missing face lets the
 * camera out, and glow_box_one_sided, whose walls it sees through from
 * inside); none where lamps or punctual lights carry at least half
 * (the Cornell box and soft-shadows, strengths 17 and 8; lamp_over_glow,
 * 8 pi of 12 pi; punctual; sun_front, its quad lit) or where the camera sits
 * inside a closed model (furnace, glow_box), and there, where nothing emits
 * (dark_box), a point light at the camera, of intensity pi d^2 with d a
 * distance of the view (its rays meet the cube's -Z wall 1 to
 * sqrt(1 + 2 tan^2 0.25) away); dim (0.25) where those lights
 * leave most of the view dark (sun_behind, lit from behind; lamp_in_glass,
 * a lamp inside a glass bulb). */
static void default_environment_follows_the_lights(void **state)
{
    (void)state;
    static const struct {
        const char *spec;
        float env;
        st_env_default why;
    } cases[] = {{"cornell-box", 0.0f, ST_ENV_OWN_LIGHTS},
                 {"soft-shadows", 0.0f, ST_ENV_OWN_LIGHTS},
                 {"furnace", 0.0f, ST_ENV_ENCLOSED},
                 {"checkerboard", 1.0f, ST_ENV_NOTHING_EMITS},
                 {SCENES "cutout.gltf", 1.0f, ST_ENV_NOTHING_EMITS},
                 {SCENES "layout_u16.gltf", 1.0f, ST_ENV_NOTHING_EMITS},
                 {SCENES "black_emitter.gltf", 1.0f, ST_ENV_NOTHING_EMITS},
                 {SCENES "textured_quad.gltf", 1.0f, ST_ENV_DIM_EMITTERS},
                 {SCENES "lamp_and_glow.gltf", 1.0f, ST_ENV_DIM_EMITTERS},
                 {SCENES "lamp_over_glow.gltf", 0.0f, ST_ENV_OWN_LIGHTS},
                 {SCENES "punctual.gltf", 0.0f, ST_ENV_OWN_LIGHTS},
                 {SCENES "glow_box.gltf", 0.0f, ST_ENV_ENCLOSED},
                 {SCENES "dark_box.gltf", 0.0f, ST_ENV_HEADLIGHT},
                 {SCENES "glow_box_open.gltf", 1.0f, ST_ENV_DIM_EMITTERS},
                 {SCENES "glow_box_one_sided.gltf", 1.0f, ST_ENV_DIM_EMITTERS},
                 {SCENES "sun_front.gltf", 0.0f, ST_ENV_OWN_LIGHTS},
                 {SCENES "sun_behind.gltf", 0.25f, ST_ENV_DARK_VIEW},
                 {SCENES "lamp_in_glass.gltf", 0.25f, ST_ENV_DARK_VIEW}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        st_scene *s = load_ok(cases[i].spec);
        near3(s->default_env, cases[i].env, cases[i].env, cases[i].env, 0, cases[i].spec);
        if (s->env_default != cases[i].why)
            fail_msg("%s: default %d, want %d", cases[i].spec, s->env_default, cases[i].why);
        assert_int_equal(st_render_defaults().texture_filter, ST_TEXFILTER_TRILINEAR);
        st_scene_destroy(s);
    }
    /* the powers behind lamp_and_glow's and lamp_over_glow's cases */
    st_scene *s = load_ok(SCENES "lamp_and_glow.gltf");
    near(s->emitted_power, 5.0 * 3.14159265358979, 1e-4, "lamp_and_glow: 4 pi glow + pi lamp");
    st_scene_destroy(s);
    s = load_ok(SCENES "lamp_over_glow.gltf");
    near(s->emitted_power, 12.0 * 3.14159265358979, 1e-4, "lamp_over_glow: 4 pi glow + 8 pi lamp");
    st_scene_destroy(s);
    /* dark_box's light at its camera */
    s = load_ok(SCENES "dark_box.gltf");
    assert_int_equal(s->punctual_count, 1);
    near3(s->punctual[0].pos, s->default_camera.origin[0], s->default_camera.origin[1],
          s->default_camera.origin[2], 0, "dark_box: the light at the camera");
    assert_int_equal((int)s->punctual[0].pos[3], ST_PUNCT_POINT);
    double pi = 3.14159265358979, corner = 1.0 + 2.0 * tan(0.25) * tan(0.25);
    for (int k = 0; k < 3; k++)
        if (!(s->punctual[0].intensity[k] > pi && s->punctual[0].intensity[k] < pi * corner))
            fail_msg("dark_box: intensity %g, want pi .. %g", s->punctual[0].intensity[k],
                     pi * corner);
    assert_true(s->emitted_power > 0.0);
    st_scene_destroy(s);
}

/* The built-in scenes load, and a bare name finds each. */
static void builtin_scenes_load_by_name(void **state)
{
    (void)state;
    const char *names[16];
    st_u32 n = st_scene_builtin_names(names, 16);
    static const char *want[] = {"cornell-box", "furnace", "checkerboard", "soft-shadows",
                                 "zone-plate"};
    for (size_t k = 0; k < sizeof want / sizeof want[0]; k++) {
        int found = 0;
        for (st_u32 i = 0; i < n; i++)
            found |= !strcmp(names[i], want[k]);
        if (!found)
            fail_msg("built-in %s missing", want[k]);
        st_scene *s = load_ok(want[k]);
        assert_int_equal(s->warning_count, 0);
        assert_int_equal(s->default_camera.from_file, 1);
        st_scene_destroy(s);
    }
}

/* ---- content hash ------------------------------------------------------------- */

/* st_scene_content_hash names the content, not the path: one file by a relative, a "./" and an
 * absolute path hashes alike; any single flipped bit of a hashed array changes it (CRC-32
 * detects every single-bit error); two different scenes differ. */
static void scene_content_hash_follows_content_not_path(void **state)
{
    (void)state;
    char cwd[4096], abs_path[4200];
    assert_non_null(getcwd(cwd, sizeof cwd));
    snprintf(abs_path, sizeof abs_path, "%s/tests/scenes/textures.gltf", cwd);
    st_scene *a = load_ok("tests/scenes/textures.gltf"), *b = load_ok("./tests/scenes/textures.gltf");
    st_scene *c = load_ok(abs_path);
    st_u32 h = st_scene_content_hash(a);
    assert_int_equal(st_scene_content_hash(b), h);
    assert_int_equal(st_scene_content_hash(c), h);
    assert_true(a->texel_count > 0);
    unsigned char *bytes[] = {(unsigned char *)a->positions, (unsigned char *)a->normals,
                              (unsigned char *)a->uvs, (unsigned char *)a->materials,
                              (unsigned char *)a->texels};
    for (size_t k = 0; k < sizeof bytes / sizeof bytes[0]; k++) {
        bytes[k][1] ^= 0x10;
        if (st_scene_content_hash(a) == h)
            fail_msg("array %zu: a flipped bit left the hash %08x", k, (unsigned)h);
        bytes[k][1] ^= 0x10;
        assert_int_equal(st_scene_content_hash(a), h);
    }
    st_scene *d = load_ok("cornell-box"), *e = load_ok("checkerboard");
    assert_int_not_equal(st_scene_content_hash(d), st_scene_content_hash(e));
    st_scene_destroy(a);
    st_scene_destroy(b);
    st_scene_destroy(c);
    st_scene_destroy(d);
    st_scene_destroy(e);
}

/* ---- malformed input ---------------------------------------------------------- */

static void malformed_files_return_format_error_naming_file(void **state)
{
    (void)state;
    static const struct {
        const char *file, *phrase;
    } cases[] = {
        {"bad_truncated.gltf", NULL},
        {"bad_not_gltf.gltf", NULL},
        {"bad_index.gltf", "accessor 2: index 812 out of range"},
        {"bad_view_past_buffer.gltf", "bufferView 1"},
        {"bad_accessor_past_view.gltf", "accessor 0"},
        {"bad_missing_bin.gltf", "bad_missing_bin.bin"},
        {"bad_nonfinite.gltf", "non-finite"},
        {"bad_node_cycle.gltf", "node"},
        {"bad_mesh_index.gltf", "mesh 5 out of range"},
        {"bad_position_type.gltf", "float VEC3"},
        {"bad_stride.gltf", "byteStride"},
        {"bad_no_triangles.gltf", "no triangles"},
        {"bad_glb_chunk.glb", "chunk"},
        {"bad_requires_draco.gltf",
         "requires extension KHR_draco_mesh_compression, which strata does not support"},
        {"bad_texture_index.gltf", "baseColorTexture: texture 7 out of range"},
        {"bad_image_index.gltf", "source image 9 out of range"},
        {"bad_sampler_wrap.gltf", "wrapS 1234"},
        {"bad_texcoord_type.gltf", "TEXCOORD_0 must be"},
        {"bad_texcoord1_type.gltf", "TEXCOORD_1 must be"},
        {"bad_quantized_undeclared.gltf", "POSITION must be float VEC3"},
        {"bad_alpha_mode.gltf", "alphaMode"},
        {"bad_camera_ymag.gltf", "ymag"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char path[256];
        snprintf(path, sizeof path, SCENES "%s", cases[i].file);
        load_fails(path, ST_ERR_FORMAT, path, cases[i].phrase);
    }
}

/* An image that cannot be decoded or read is a warning naming it, and a
 * 1 x 1 white texture in its place (the factor alone); an extension that is
 * only used and not implemented is a warning naming it; so is
 * occlusionTexture, which is not read. */
static void unreadable_images_and_unknown_extensions_warn(void **state)
{
    (void)state;
    static const struct {
        const char *file, *phrase;
    } cases[] = {
        {SCENES "image_undecodable.gltf", "image 0 (image/png): cannot decode"},
        {SCENES "image_missing.gltf", "image 0 (no_such_image.png): cannot read"},
    };
    for (int i = 0; i < 2; i++) {
        st_scene *s = load_ok(cases[i].file);
        assert_true(has_warning(s, cases[i].phrase));
        assert_true(has_warning(s, "replaced by a white texture"));
        const st_texture *t = &s->textures[s->materials[0].base_color_tex];
        assert_int_equal(t->width, 1);
        assert_int_equal(t->height, 1);
        assert_int_equal(s->texels[t->offset], 0xffffffffu);
        st_scene_destroy(s);
    }
    st_scene *s = load_ok(SCENES "occlusion.gltf"); /* one material with occlusionTexture */
    assert_true(has_warning(s, "occlusionTexture of material 0 is not read (a path tracer "
                               "finds occlusion itself)"));
    st_scene_destroy(s);
    s = load_ok(SCENES "textured_quad.gltf"); /* none: no word */
    assert_false(has_warning(s, "occlusionTexture"));
    st_scene_destroy(s);
    s = load_ok(SCENES "uses_variants.gltf");
    assert_true(has_warning(s, "uses extension KHR_materials_variants, which strata ignores"));
    st_scene_destroy(s);
}

/* The fraction of the default view no light reaches directly
 * (dark_view.h), where it is known exactly: sun_front's quad fills the
 * orthographic view and faces its directional light (0); sun_behind's
 * faces away from it (1); lamp_in_glass's lamp lies inside a closed glass
 * bulb, which blocks every shadow ray to it, and the view around the floor
 * is empty (1). The Cornell box's light reaches most of its view. */
static void dark_fraction_counts_what_no_light_reaches(void **state)
{
    (void)state;
    static const struct {
        const char *spec;
        double lo, hi;
    } cases[] = {{SCENES "sun_front.gltf", 0.0, 0.0},
                 {SCENES "sun_behind.gltf", 1.0, 1.0},
                 {SCENES "lamp_in_glass.gltf", 1.0, 1.0},
                 {"cornell-box", 0.0, 0.5}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        st_scene *s = load_ok(cases[i].spec);
        st_error err = {0};
        double dark = -1.0;
        assert_int_equal(st_scene_dark_fraction(s, &dark, &err), ST_OK);
        print_message("%s: dark fraction %.4f\n", cases[i].spec, dark);
        if (!(dark >= cases[i].lo && dark <= cases[i].hi))
            fail_msg("%s: dark fraction %g, want [%g, %g]", cases[i].spec, dark, cases[i].lo,
                     cases[i].hi);
        st_scene_destroy(s);
    }
}

/* A normal map (the base's or the clear coat's) whose image cannot be
 * read is left out, not made white (a white texel is the normal (1, 1, 1),
 * some 55 degrees off): the material has no such texture and the warning
 * says so; no white texture stands in for it. */
static void unreadable_normal_map_is_left_out(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "normal_missing.gltf");
    assert_int_equal(s->materials[0].normal_tex, ST_NO_TEXTURE);
    assert_true(has_warning(s, "material 0: normalTexture: image 3 (no_such_normal_map.png): "
                               "cannot read it: left out (the vertex normals kept)"));
    assert_false(has_warning(s, "no_such_normal_map.png): cannot read it: replaced by a white"));
    st_scene_destroy(s);
    s = load_ok(SCENES "normal_tilt.gltf"); /* the same file with its map readable */
    assert_int_not_equal(s->materials[0].normal_tex, ST_NO_TEXTURE);
    st_scene_destroy(s);
    s = load_ok(SCENES "coat_normal_missing.gltf"); /* the clear coat's normal map */
    assert_int_equal(s->materials[0].clearcoat_normal_tex, ST_NO_TEXTURE);
    assert_true(has_warning(s, "material 0: clearcoatNormalTexture: image 3 "
                               "(no_such_coat_normal_map.png): cannot read it: left out (the "
                               "vertex normals kept)"));
    assert_false(has_warning(s, "no_such_coat_normal_map.png): cannot read it: replaced by"));
    st_scene_destroy(s);
    s = load_ok(SCENES "coat_normal.gltf"); /* readable: read, with its scale */
    assert_int_not_equal(s->materials[0].clearcoat_normal_tex, ST_NO_TEXTURE);
    near(s->materials[0].clearcoat_normal_scale, 1.0 / 3.0, 1e-7, "clearcoatNormalTexture.scale");
    assert_true(s->materials[0].flags & ST_MAT_TEXTURED);
    assert_false(has_warning(s, "clearcoatNormalTexture"));
    st_scene_destroy(s);
}

/* KHR_materials_transmission without KHR_materials_volume is thin-walled
 * (ST_MAT_THIN: tests/scenes/thin_pane.gltf's pane), with a volume a
 * solid (glass_slab.gltf, whose volume absorbs, and glass.gltf, whose
 * volume only has a thickness); a material without transmission is
 * neither (the lamp). */
static void transmission_without_volume_is_thin(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "thin_pane.gltf");
    assert_false(s->materials[0].flags & ST_MAT_THIN);
    assert_true(s->materials[1].flags & ST_MAT_THIN);
    st_scene_destroy(s);
    const char *solid[] = {SCENES "glass_slab.gltf", SCENES "glass.gltf"};
    for (int k = 0; k < 2; k++) {
        s = load_ok(solid[k]);
        int glass = 0;
        for (st_u32 i = 0; i < s->material_count; i++) {
            glass += s->materials[i].transmission > 0.0f;
            assert_false(s->materials[i].flags & ST_MAT_THIN);
        }
        assert_true(glass > 0);
        st_scene_destroy(s);
    }
    /* KHR_materials_volume: thicknessFactor 0, its default, is thin-walled
     * too; any other thickness bounds a solid */
    static const double thickness[] = {-1.0 /* not given */, 0.0, 0.5};
    char dir[64], path[128];
    size_t size;
    unsigned char *data = read_all(SCENES "thin_pane.gltf", &size);
    make_scratch(dir);
    snprintf(path, sizeof path, "%s/volume.gltf", dir);
    for (int k = 0; k < 3; k++) {
        cJSON *doc = cJSON_ParseWithLength((const char *)data, size);
        assert_non_null(doc);
        cJSON *ext = cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(doc, "materials"),
                                                            1), "extensions");
        cJSON *vol = cJSON_AddObjectToObject(ext, "KHR_materials_volume");
        if (thickness[k] >= 0.0)
            cJSON_AddNumberToObject(vol, "thicknessFactor", thickness[k]);
        char *text = cJSON_PrintUnformatted(doc);
        write_all(path, (const unsigned char *)text, strlen(text));
        cJSON_free(text);
        cJSON_Delete(doc);
        s = load_ok(path);
        if (k < 2)
            assert_true(s->materials[1].flags & ST_MAT_THIN);
        else
            assert_false(s->materials[1].flags & ST_MAT_THIN);
        st_scene_destroy(s);
    }
    unlink(path);
    rmdir(dir);
    free(data);
}

/* KHR_materials_sheen's factors and textures as the specification names
 * them (tests/scenes/sheen_quad.gltf): sheenColorTexture decoded as sRGB,
 * sheenRoughnessTexture read linear, ST_MAT_SHEEN where the colour is not
 * black, and no warning. */
static void sheen_is_imported(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "sheen_quad.gltf");
    assert_false(has_warning(s, "KHR_materials_sheen"));
    const st_material *m = &s->materials[0], *w = &s->materials[1];
    near3(m->sheen_color, 1.0, 0.5, 0.25, 0.0, "sheenColorFactor");
    near(m->sheen_roughness, 1.0, 0.0, "sheenRoughnessFactor");
    assert_true(m->flags & ST_MAT_SHEEN);
    assert_int_not_equal(m->sheen_color_tex, ST_NO_TEXTURE);
    assert_int_not_equal(m->sheen_roughness_tex, ST_NO_TEXTURE);
    assert_true(s->textures[m->sheen_color_tex].flags & ST_TEX_SRGB);
    assert_false(s->textures[m->sheen_roughness_tex].flags & ST_TEX_SRGB);
    near3(w->sheen_color, 0.8, 0.8, 0.8, 1e-7, "sheenColorFactor");
    near(w->sheen_roughness, 0.5, 0.0, "sheenRoughnessFactor");
    assert_int_equal(w->sheen_color_tex, ST_NO_TEXTURE);
    assert_int_equal(w->sheen_roughness_tex, ST_NO_TEXTURE);
    st_scene_destroy(s);
    s = load_ok(SCENES "coat.gltf"); /* no sheen: black, no flag */
    for (st_u32 i = 0; i < s->material_count; i++) {
        assert_false(s->materials[i].flags & ST_MAT_SHEEN);
        near3(s->materials[i].sheen_color, 0.0, 0.0, 0.0, 0.0, "no sheen");
    }
    st_scene_destroy(s);
}

/* A copy of file with material `mat`'s extension `name` replaced by the
 * JSON object `ext`, written to dir/variant.gltf (its path in path). */
static void write_ext_variant(const char *file, int mat, const char *name, const char *ext,
                              const char *dir, char *path, size_t len)
{
    size_t size;
    unsigned char *data = read_all(file, &size);
    cJSON *doc = cJSON_ParseWithLength((const char *)data, size);
    assert_non_null(doc);
    cJSON *exts = cJSON_GetObjectItem(
        cJSON_GetArrayItem(cJSON_GetObjectItem(doc, "materials"), mat), "extensions");
    cJSON *value = cJSON_Parse(ext);
    assert_non_null(value);
    cJSON_ReplaceItemInObject(exts, name, value);
    char *text = cJSON_PrintUnformatted(doc);
    snprintf(path, len, "%s/variant.gltf", dir);
    write_all(path, (const unsigned char *)text, strlen(text));
    cJSON_free(text);
    cJSON_Delete(doc);
    free(data);
}

/* KHR_materials_anisotropy as the specification names it
 * (tests/scenes/aniso_quad.gltf): anisotropyStrength, anisotropyRotation
 * as its cosine and sine, anisotropyTexture read linear, ST_MAT_ANISO where
 * the strength is above 0, and no warning; the material without the
 * extension gets strength 0 and rotation 0. A strength outside [0, 1], or a
 * rotation or strength that is no number, is an error naming the material;
 * an anisotropyTexture that cannot be read is left out, with a warning. */
static void anisotropy_is_imported(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "aniso_quad.gltf");
    assert_false(has_warning(s, "KHR_materials_anisotropy"));
    const st_material *m = &s->materials[0], *w = &s->materials[1];
    near(m->anisotropy[0], 0.8, 1e-7, "anisotropyStrength");
    near(m->anisotropy[1], cos(0.5), 1e-6, "cos anisotropyRotation");
    near(m->anisotropy[2], sin(0.5), 1e-6, "sin anisotropyRotation");
    assert_true(m->flags & ST_MAT_ANISO);
    assert_int_not_equal(m->anisotropy_tex, ST_NO_TEXTURE);
    assert_false(s->textures[m->anisotropy_tex].flags & ST_TEX_SRGB);
    assert_false(m->flags & ST_MAT_TEXTURED); /* aniso_gather reads it, not material_at */
    assert_false(w->flags & ST_MAT_ANISO);
    near(w->anisotropy[0], 0.0, 0.0, "no strength");
    st_scene_destroy(s);
    s = load_ok(SCENES "coat.gltf"); /* no anisotropy: strength 0, rotation 0 */
    for (st_u32 i = 0; i < s->material_count; i++) {
        assert_false(s->materials[i].flags & ST_MAT_ANISO);
        near3(s->materials[i].anisotropy, 0.0, 1.0, 0.0, 0.0, "no anisotropy");
        assert_int_equal(s->materials[i].anisotropy_tex, ST_NO_TEXTURE);
    }
    st_scene_destroy(s);
    static const struct {
        const char *ext, *phrase;
    } bad[] = {
        {"{\"anisotropyStrength\": 1.5}",
         "material 0: KHR_materials_anisotropy: anisotropyStrength 1.5 is not in [0, 1]"},
        {"{\"anisotropyStrength\": -0.1}", "anisotropyStrength -0.1 is not in [0, 1]"},
        {"{\"anisotropyStrength\": \"high\"}", "anisotropyStrength is not a number"},
        {"{\"anisotropyRotation\": \"east\"}", "anisotropyRotation is not a number"},
        {"{\"anisotropyTexture\": {\"index\": 9}}", "anisotropyTexture: texture 9 out of range"},
    };
    char dir[64], path[128];
    make_scratch(dir);
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        write_ext_variant(SCENES "aniso_quad.gltf", 0, "KHR_materials_anisotropy", bad[k].ext, dir,
                          path, sizeof path);
        load_fails(path, ST_ERR_FORMAT, path, bad[k].phrase);
    }
    /* an unreadable anisotropyTexture is left out (white would turn the
     * direction by 45 degrees), the factors kept */
    size_t size;
    unsigned char *data = read_all(SCENES "aniso_quad.gltf", &size);
    cJSON *doc = cJSON_ParseWithLength((const char *)data, size);
    cJSON_ReplaceItemInObject(cJSON_GetArrayItem(cJSON_GetObjectItem(doc, "images"), 0), "uri",
                              cJSON_CreateString("no_such_aniso_map.png"));
    char *text = cJSON_PrintUnformatted(doc);
    write_all(path, (const unsigned char *)text, strlen(text));
    cJSON_free(text);
    cJSON_Delete(doc);
    free(data);
    s = load_ok(path);
    assert_int_equal(s->materials[0].anisotropy_tex, ST_NO_TEXTURE);
    near(s->materials[0].anisotropy[0], 0.8, 1e-7, "anisotropyStrength kept");
    assert_true(has_warning(s, "material 0: anisotropyTexture: image 0 (no_such_aniso_map.png): "
                               "cannot read it: left out (the factors kept)"));
    assert_false(has_warning(s, "replaced by a white"));
    st_scene_destroy(s);
    unlink(path);
    rmdir(dir);
}

/* KHR_materials_diffuse_transmission as the specification names it
 * (tests/scenes/dtrans_lamp.gltf): the factor and the colour factor, the
 * texture read linear and the colour texture as sRGB, ST_MAT_DIFFUSE_TRANS
 * where the factor is above 0 and a surface met from both sides
 * (ST_MAT_DOUBLE_SIDED, as a transmissive one), and no warning; without
 * the extension, factor 0 and colour 1. A factor outside [0, 1] or one that
 * is no number is an error naming the material. */
static void diffuse_transmission_is_imported(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "dtrans_lamp.gltf");
    assert_false(has_warning(s, "KHR_materials_diffuse_transmission"));
    const st_material *m = &s->materials[0], *lamp = &s->materials[1];
    near(m->diffuse_trans[3], 0.75, 0.0, "diffuseTransmissionFactor");
    near3(m->diffuse_trans, 1.0, 0.5, 1.0, 0.0, "diffuseTransmissionColorFactor");
    assert_true(m->flags & ST_MAT_DIFFUSE_TRANS);
    assert_true(m->flags & ST_MAT_DOUBLE_SIDED);
    assert_int_not_equal(m->diffuse_trans_tex, ST_NO_TEXTURE);
    assert_int_not_equal(m->diffuse_trans_color_tex, ST_NO_TEXTURE);
    assert_false(s->textures[m->diffuse_trans_tex].flags & ST_TEX_SRGB);
    assert_true(s->textures[m->diffuse_trans_color_tex].flags & ST_TEX_SRGB);
    assert_false(m->flags & ST_MAT_TEXTURED); /* dtrans_gather reads them, not material_at */
    assert_false(lamp->flags & (ST_MAT_DIFFUSE_TRANS | ST_MAT_DOUBLE_SIDED));
    near(lamp->diffuse_trans[3], 0.0, 0.0, "no diffuse transmission");
    near3(lamp->diffuse_trans, 1.0, 1.0, 1.0, 0.0, "its colour");
    assert_int_equal(lamp->diffuse_trans_tex, ST_NO_TEXTURE);
    st_scene_destroy(s);
    static const struct {
        const char *ext, *phrase;
    } bad[] = {
        {"{\"diffuseTransmissionFactor\": 1.5}", "material 0: KHR_materials_diffuse_transmission: "
                                                 "diffuseTransmissionFactor and "
                                                 "diffuseTransmissionColorFactor must lie in [0, 1]"},
        {"{\"diffuseTransmissionColorFactor\": [1, -0.5, 1]}", "must lie in [0, 1]"},
        {"{\"diffuseTransmissionColorFactor\": [1, 1]}",
         "diffuseTransmissionColorFactor must be an array of 3 numbers"},
        {"{\"diffuseTransmissionFactor\": \"half\"}", "diffuseTransmissionFactor is not a number"},
        {"{\"diffuseTransmissionTexture\": {\"index\": 5}}",
         "diffuseTransmissionTexture: texture 5 out of range"},
    };
    char dir[64], path[128];
    make_scratch(dir);
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        write_ext_variant(SCENES "dtrans_lamp.gltf", 0, "KHR_materials_diffuse_transmission",
                          bad[k].ext, dir, path, sizeof path);
        load_fails(path, ST_ERR_FORMAT, path, bad[k].phrase);
    }
    unlink(path);
    rmdir(dir);
}

/* KHR_materials_iridescence as the specification names it
 * (tests/scenes/irid_quad.gltf): the factor, the film's ior and thickness
 * range (100 and 400 nm by default), both textures read linear,
 * ST_MAT_IRIDESCENT where the factor is above 0, and no warning; without
 * the extension, factor 0. Out-of-range values are errors naming the
 * material. */
static void iridescence_is_imported(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "irid_quad.gltf");
    assert_false(has_warning(s, "KHR_materials_iridescence"));
    const st_material *m = &s->materials[0], *w = &s->materials[1];
    const float want_m[4] = {1.0f, 1.3f, 200.0f, 600.0f}, want_w[4] = {0.5f, 1.8f, 100.0f, 400.0f};
    for (int k = 0; k < 4; k++) {
        near(m->iridescence[k], want_m[k], 0.0, "iridescence (textured)");
        near(w->iridescence[k], want_w[k], 0.0, "iridescence (defaults)");
    }
    assert_true((m->flags & ST_MAT_IRIDESCENT) && (w->flags & ST_MAT_IRIDESCENT));
    assert_int_not_equal(m->iridescence_tex, ST_NO_TEXTURE);
    assert_int_not_equal(m->iridescence_thickness_tex, ST_NO_TEXTURE);
    assert_false(s->textures[m->iridescence_tex].flags & ST_TEX_SRGB);
    assert_false(s->textures[m->iridescence_thickness_tex].flags & ST_TEX_SRGB);
    assert_false(m->flags & ST_MAT_TEXTURED); /* irid_gather reads them, not material_at */
    assert_int_equal(w->iridescence_tex, ST_NO_TEXTURE);
    st_scene_destroy(s);
    s = load_ok(SCENES "coat.gltf");
    for (st_u32 i = 0; i < s->material_count; i++) {
        assert_false(s->materials[i].flags & ST_MAT_IRIDESCENT);
        near(s->materials[i].iridescence[0], 0.0, 0.0, "no iridescence");
    }
    st_scene_destroy(s);
    static const struct {
        const char *ext, *phrase;
    } bad[] = {
        {"{\"iridescenceFactor\": 2}",
         "material 0: KHR_materials_iridescence: iridescenceFactor 2 is not in [0, 1]"},
        {"{\"iridescenceFactor\": 1, \"iridescenceIor\": 0.5}",
         "iridescenceIor 0.5 is not a finite number >= 1"},
        {"{\"iridescenceFactor\": 1, \"iridescenceThicknessMinimum\": -10}",
         "iridescenceThicknessMinimum and ..Maximum must be finite and >= 0"},
        {"{\"iridescenceFactor\": \"all\"}", "iridescenceFactor is not a number"},
        {"{\"iridescenceThicknessTexture\": {\"index\": 4}}",
         "iridescenceThicknessTexture: texture 4 out of range"},
    };
    char dir[64], path[128];
    make_scratch(dir);
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        write_ext_variant(SCENES "irid_quad.gltf", 0, "KHR_materials_iridescence", bad[k].ext,
                          dir, path, sizeof path);
        load_fails(path, ST_ERR_FORMAT, path, bad[k].phrase);
    }
    unlink(path);
    rmdir(dir);
}

/* KHR_materials_dispersion (tests/scenes/dispersion_slab.gltf and its
 * variants): the value, ST_MAT_DISPERSIVE on a solid transmissive
 * material with dispersion above 0 only (not at 0, not without the
 * extension, not on a thin wall), no warning; a negative value or one that
 * is no number is an error naming the material. */
static void dispersion_is_imported(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "dispersion_slab.gltf");
    assert_false(has_warning(s, "KHR_materials_dispersion"));
    near(s->materials[0].dispersion, 5.0, 0.0, "dispersion");
    assert_true(s->materials[0].flags & ST_MAT_DISPERSIVE);
    assert_false(s->materials[1].flags & ST_MAT_DISPERSIVE); /* the lamp */
    st_scene_destroy(s);
    const char *none[] = {SCENES "dispersion_slab_zero.gltf", SCENES "clear_slab.gltf"};
    for (int k = 0; k < 2; k++) {
        s = load_ok(none[k]);
        assert_false(s->materials[0].flags & ST_MAT_DISPERSIVE);
        near(s->materials[0].dispersion, 0.0, 0.0, "no dispersion");
        st_scene_destroy(s);
    }
    static const struct {
        const char *ext, *phrase;
    } cases[] = {
        {"{\"dispersion\": -1}",
         "material 0: KHR_materials_dispersion: dispersion -1 is not a finite number >= 0"},
        {"{\"dispersion\": \"much\"}", "dispersion is not a number"},
    };
    char dir[64], path[128];
    make_scratch(dir);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        write_ext_variant(SCENES "dispersion_slab.gltf", 0, "KHR_materials_dispersion",
                          cases[k].ext, dir, path, sizeof path);
        load_fails(path, ST_ERR_FORMAT, path, cases[k].phrase);
    }
    /* a thin wall (no KHR_materials_volume) bends no ray: no dispersion */
    write_ext_variant(SCENES "dispersion_slab.gltf", 0, "KHR_materials_volume", "{}", dir, path,
                      sizeof path);
    s = load_ok(path);
    assert_true(s->materials[0].flags & ST_MAT_THIN);
    assert_false(s->materials[0].flags & ST_MAT_DISPERSIVE);
    st_scene_destroy(s);
    unlink(path);
    rmdir(dir);
}

/* ST_MAT_TEXTURED, the one test material_at makes before its texture
 * lookups: set by each of the ten textured factors it reads alone, not by
 * the sheen's, the anisotropy's, the diffuse transmission's or the
 * film's (sheen_gather and the other gathers read those), and on the
 * imported materials
 * exactly where one of the ten has a texture. */
static void textured_flag_follows_the_factors(void **state)
{
    (void)state;
    st_material m;
    st_u32 *slot[] = {&m.base_color_tex,   &m.emission_tex,   &m.metallic_roughness_tex,
                      &m.specular_tex,     &m.specular_color_tex, &m.normal_tex,
                      &m.transmission_tex, &m.clearcoat_tex,  &m.clearcoat_roughness_tex,
                      &m.clearcoat_normal_tex, &m.sheen_color_tex, &m.sheen_roughness_tex,
                      &m.anisotropy_tex, &m.diffuse_trans_tex, &m.diffuse_trans_color_tex,
                      &m.iridescence_tex, &m.iridescence_thickness_tex};
    const size_t slots = sizeof slot / sizeof slot[0];
    for (size_t k = 0; k <= slots; k++) { /* k = slots: none textured */
        memset(&m, 0, sizeof m);
        for (size_t j = 0; j < slots; j++)
            *slot[j] = ST_NO_TEXTURE;
        if (k < slots)
            *slot[k] = 3u;
        assert_int_equal(st_material_reads_textures(&m) != 0, k < 10);
    }
    st_scene *s = load_ok(SCENES "textures.gltf"); /* base colour (and more) textured */
    for (st_u32 i = 0; i < s->material_count; i++)
        assert_true(s->materials[i].flags & ST_MAT_TEXTURED);
    st_scene_destroy(s);
    s = load_ok(SCENES "sheen_quad.gltf"); /* material 0: sheen textures alone */
    assert_int_not_equal(s->materials[0].sheen_color_tex, ST_NO_TEXTURE);
    assert_false(s->materials[0].flags & ST_MAT_TEXTURED);
    st_scene_destroy(s);
    s = load_ok(SCENES "coat.gltf"); /* factors alone */
    for (st_u32 i = 0; i < s->material_count; i++)
        assert_false(s->materials[i].flags & ST_MAT_TEXTURED);
    st_scene_destroy(s);
}

/* The default framing sees a model from glTF's front (+Z), a little above
 * and to the side, whatever the shape of its bounds: a quad in the z = 0
 * plane (textured_quad) and the checkerboard's floor y = 0, which the old
 * framing looked down on from above, are both seen from the +Z side, with
 * the eye raised 10..30 degrees above the centre and turned 15..45 degrees
 * towards +X (measured here from the eye's offset, not from the code's
 * angles); up is +Y made orthogonal to the view; the camera sits
 * r / sin(yfov / 2) from the centre, r the half diagonal. --camera auto
 * (ST_CAMERA_AUTO) gives it even where the file has cameras. */
static void auto_camera_sees_the_front(void **state)
{
    (void)state;
    const double deg = 180.0 / 3.14159265358979323846;
    static const char *files[] = {SCENES "textured_quad.gltf", "checkerboard"};
    for (int f = 0; f < 2; f++) {
        st_scene *s = load_ok(files[f]);
        st_scene_camera c;
        st_error err = {0};
        assert_int_equal(st_scene_view_camera(s, ST_CAMERA_AUTO, &c, &err), ST_OK);
        assert_int_equal(c.from_file, 0);
        double r2 = 0.0, d2 = 0.0, o[3];
        for (int k = 0; k < 3; k++) {
            double h = 0.5 * ((double)s->bounds_max[k] - s->bounds_min[k]);
            o[k] = c.origin[k] - 0.5 * ((double)s->bounds_max[k] + s->bounds_min[k]);
            r2 += h * h;
            d2 += o[k] * o[k];
        }
        double d = sqrt(d2), elevation = asin(o[1] / d) * deg, azimuth = atan2(o[0], o[2]) * deg;
        if (!(o[2] > 0.0 && elevation >= 10.0 && elevation <= 30.0 && azimuth >= 15.0 &&
              azimuth <= 45.0))
            fail_msg("%s: eye at offset (%g, %g, %g): elevation %g, azimuth %g degrees", files[f],
                     o[0], o[1], o[2], elevation, azimuth);
        near3(c.forward, -o[0] / d, -o[1] / d, -o[2] / d, 1e-6, "auto camera looks at the centre");
        near(c.forward[0] * c.up[0] + c.forward[1] * c.up[1] + c.forward[2] * c.up[2], 0.0, 1e-6,
             "auto camera up . forward");
        near(c.up[0] * c.forward[2] - c.up[2] * c.forward[0], 0.0, 1e-6, "up in the plane of +Y");
        assert_true(c.up[1] > 0.0f);
        near(d, sqrt(r2) / sin(0.5 * c.yfov), 1e-4 * d, "auto camera distance");
        st_scene_destroy(s);
    }
}

/* st_scene_look_at: from (1, 2, 3) at (1, 2, -7) with up (0, 5, 1) looks
 * along -Z with up +Y (the up's part along the view removed, unit
 * length); the same with the default up of the CLI. Degenerate views are
 * usage errors naming "look at"; fov outside (0, 180) is "fov". */
static void look_at_builds_the_view(void **state)
{
    (void)state;
    const float pi = 3.14159265f;
    st_scene_camera c;
    st_error err = {0};
    const float eye[3] = {1, 2, 3}, target[3] = {1, 2, -7}, up[3] = {0, 5, 1};
    assert_int_equal(st_scene_look_at(eye, target, up, 0.5f, &c, &err), ST_OK);
    near3(c.origin, 1, 2, 3, 0, "eye");
    near3(c.forward, 0, 0, -1, 1e-7, "forward");
    near3(c.up, 0, 1, 0, 1e-7, "up");
    near(c.yfov, 0.5, 0, "yfov");
    assert_int_equal(c.orthographic, 0);
    const float y[3] = {0, 1, 0}, along[3] = {0, 0, -2}, zero[3] = {0, 0, 0};
    assert_int_equal(st_scene_look_at(eye, eye, y, 0.5f, &c, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "look at"));
    err = (st_error){0};
    assert_int_equal(st_scene_look_at(eye, target, along, 0.5f, &c, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "along the view"));
    err = (st_error){0};
    assert_int_equal(st_scene_look_at(eye, target, zero, 0.5f, &c, &err), ST_ERR_USAGE);
    err = (st_error){0};
    assert_int_equal(st_scene_look_at(eye, target, y, pi, &c, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "fov"));
}

/* A TRIANGLE_STRIP and a TRIANGLE_FAN of the 2 x 2 quad in z = 0 give its
 * two triangles: area 2 each (a wrong fan or strip rule gives other ones)
 * and wound counter-clockwise seen from +z, as the quad's normals face (the
 * strip's odd triangles swap two vertices, §3.7.2.1). */
static void strips_and_fans_become_triangles(void **state)
{
    (void)state;
    static const char *files[] = {SCENES "quad_strip.gltf", SCENES "quad_fan.gltf"};
    for (int f = 0; f < 2; f++) {
        st_scene *s = load_ok(files[f]);
        assert_int_equal(s->tri_count, 2);
        for (st_u32 t = 0; t < 2; t++) {
            const float *p = s->positions + 9 * t;
            double e1[2] = {p[3] - p[0], p[4] - p[1]}, e2[2] = {p[6] - p[0], p[7] - p[1]};
            near(0.5 * (e1[0] * e2[1] - e1[1] * e2[0]), 2.0, 1e-6, "signed area seen from +z");
        }
        st_scene_destroy(s);
    }
}

/* Sparse accessors: vertex 2 of the quad, moved to (2, 3, 0) sparsely over
 * its own positions or over zeros, is where the first triangle (0 1 2)
 * has its third vertex; vertex 1 stays at (1, -1, 0). */
static void sparse_accessors_substitute_values(void **state)
{
    (void)state;
    static const char *files[] = {SCENES "quad_sparse.gltf", SCENES "quad_sparse_zeros.gltf"};
    for (int f = 0; f < 2; f++) {
        st_scene *s = load_ok(files[f]);
        assert_int_equal(s->tri_count, 2);
        near3(s->positions + 3, 1.0, -1.0, 0.0, 0, "vertex 1");
        near3(s->positions + 6, 2.0, 3.0, 0.0, 0, "vertex 2, sparse");
        st_scene_destroy(s);
    }
}

/* KHR_mesh_quantization: the pyramid stored as shorts and bytes (plain and
 * normalised) loads to the same triangles, normals, tangents and texture
 * coordinates, bit for bit, as its float twin, which holds the values that
 * the extension's decoding gives, computed in Python; without the extension
 * the same integer types are refused. */
static void quantized_attributes_equal_their_float_twin(void **state)
{
    (void)state;
    st_scene *q = load_ok(SCENES "quantized.gltf"), *f = load_ok(SCENES "quantized_float.gltf");
    assert_int_equal(q->tri_count, 4);
    assert_int_equal(f->tri_count, 4);
    size_t t = q->tri_count;
    assert_memory_equal(q->positions, f->positions, 9 * t * sizeof(float));
    assert_memory_equal(q->normals, f->normals, 9 * t * sizeof(float));
    assert_memory_equal(q->tangents, f->tangents, 12 * t * sizeof(float));
    assert_memory_equal(q->uvs, f->uvs, 6 * t * sizeof(float));
    near3(f->positions + 6, 1.0, 0.0, 0.375, 1e-6, "apex (0, 0, 3) under the node's scale");
    st_scene_destroy(q);
    st_scene_destroy(f);
}

/* KHR_materials_specular, KHR_materials_ior and normalTexture reach the
 * material as the file gives them; absent, their defaults (specular 1,
 * colour 1, ior 1.5, no texture). */
static void material_extensions_are_read(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "material_extensions.gltf");
    const st_material *m = &s->materials[0];
    near3(m->specular, 1.0, 0.5, 0.25, 0, "specularColorFactor");
    near(m->specular[3], 0.5, 0, "specularFactor");
    near(m->ior, 1.4, 1e-7, "ior");
    assert_int_not_equal(m->specular_tex, ST_NO_TEXTURE);
    assert_int_equal(m->specular_color_tex, ST_NO_TEXTURE);
    assert_int_not_equal(m->normal_tex, ST_NO_TEXTURE);
    near(m->normal_scale, 0.5, 0, "normalTexture.scale");
    assert_int_equal(s->warning_count, 0);
    st_scene_destroy(s);
    s = load_ok(SCENES "layout_u16.gltf");
    m = &s->materials[0];
    near3(m->specular, 1.0, 1.0, 1.0, 0, "default specularColorFactor");
    near(m->specular[3], 1.0, 0, "default specularFactor");
    near(m->ior, 1.5, 0, "default ior");
    assert_int_equal(m->normal_tex, ST_NO_TEXTURE);
    st_scene_destroy(s);
}

/* ---- instancing, morph targets, skins -------------------------------------------- */

/* Triangle t of s is (a, b, c), each to 1e-6, and its shading normals are n. */
static void triangle_is(const st_scene *s, st_u32 t, const double want[3][3], const double n[3],
                        const char *what)
{
    for (int v = 0; v < 3; v++) {
        near3(s->positions + 9 * (size_t)t + 3 * v, want[v][0], want[v][1], want[v][2], 1e-6,
              what);
        near3(s->normals + 9 * (size_t)t + 3 * v, n[0], n[1], n[2], 1e-6, what);
    }
}

/* EXT_mesh_gpu_instancing: world = node T(10, 0, 0) x instance T R S
 * applied to (0, 0, 0), (1, 0, 0), (0, 1, 0): instance 0 only moves it;
 * instance 1 turns it 90 degrees about +z ((x, y) -> (-y, x)) and moves it
 * by (1, 0, 0); instance 2 doubles it and moves it by (0, 2, 0). A file
 * whose instances come to more than ST_GLTF_MAX_TRIANGLES fails before
 * anything is allocated for them. */
static void gpu_instances_are_drawn_each(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "instancing.gltf");
    assert_int_equal(s->tri_count, 3);
    const double z[3] = {0, 0, 1};
    const double i0[3][3] = {{10, 0, 0}, {11, 0, 0}, {10, 1, 0}};
    const double i1[3][3] = {{11, 0, 0}, {11, 1, 0}, {10, 0, 0}};
    const double i2[3][3] = {{10, 2, 0}, {12, 2, 0}, {10, 4, 0}};
    triangle_is(s, 0, i0, z, "instance 0");
    triangle_is(s, 1, i1, z, "instance 1 (turned)");
    triangle_is(s, 2, i2, z, "instance 2 (scaled)");
    assert_int_equal(s->warning_count, 0);
    st_scene_destroy(s);
    load_fails(SCENES "instancing_huge.gltf", ST_ERR_FORMAT, "instancing_huge.gltf",
               "65 instances of 1048576 triangles");
}

/* Morph targets at their default weights (§3.7.2.2): vertex 2 = (0, 1, 0)
 * + 0.5 (0, 0, 1) + 0.25 (0, 1, 0) with the mesh's weights, (0, 1, 0) +
 * (0, 0, 1) with node 1's own (1, 0) (and its translation); the normals
 * (0, 0, 1) + w0 (1, 0, 0), made unit. */
static void morph_targets_take_the_default_weights(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "morph.gltf");
    assert_int_equal(s->tri_count, 2);
    const double a[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1.25, 0.5}};
    const double b[3][3] = {{5, 0, 0}, {6, 0, 0}, {5, 1, 1}};
    const double na[3] = {0.5 / sqrt(1.25), 0, 1 / sqrt(1.25)}, nb[3] = {sqrt(0.5), 0, sqrt(0.5)};
    triangle_is(s, 0, a, na, "mesh weights (0.5, 0.25)");
    triangle_is(s, 1, b, nb, "node weights (1, 0)");
    st_scene_destroy(s);
}

/* A skin in its rest pose (§3.7.3.3): vertex = sum_i w_i world(joint_i)
 * x inverseBind_i x vertex, the skinned node's own transform ignored.
 * Joint 0 is the identity; joint 1's matrix is T(0, 1, 0) R_z(90)
 * T(0, -1, 0): v2 (0, 2, 0) -> (0, 1, 0) -> (-1, 0, 0) -> (-1, 1, 0); v3
 * (0.5, 1, 0) goes to (0, 1.5, 0) by joint 1, stays by joint 0, so
 * (0.25, 1.25, 0) half and half. The animation is named in the one
 * warning. */
static void skins_take_the_rest_pose(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "skin.gltf");
    assert_int_equal(s->tri_count, 2);
    const double z[3] = {0, 0, 1};
    const double a[3][3] = {{0, 0, 0}, {1, 0, 0}, {0.25, 1.25, 0}};
    const double b[3][3] = {{0, 0, 0}, {0.25, 1.25, 0}, {-1, 1, 0}};
    triangle_is(s, 0, a, z, "v0 v1 v3");
    triangle_is(s, 1, b, z, "v0 v3 v2");
    assert_int_equal(s->warning_count, 1);
    assert_true(has_warning(s, "1 animation not played: the rest pose is rendered"));
    st_scene_destroy(s);
}

/* KHR_materials_pbrSpecularGlossiness (required) as metallic-roughness, as
 * glTF-Transform's metalRough converts it: metallic 0, base colour =
 * diffuse, KHR_materials_specular's colour = the specular colour with
 * factor 1 and an ior whose dielectric F0 is 1 (strata's 0), roughness =
 * 1 - glossiness; with a specularGlossinessTexture, it is the specular
 * colour texture and a linear roughness map G = 255 (1 - 0.5 A / 255) is
 * made from its alpha: A 64 -> 223, A 255 -> 127.5, rounded to 128. */
static void spec_gloss_becomes_metallic_roughness(void **state)
{
    (void)state;
    st_scene *s = load_ok(SCENES "specgloss.gltf");
    assert_int_equal(s->warning_count, 0);
    const st_material *a = &s->materials[0], *b = &s->materials[1];
    near3(a->base_color, 0.5, 0.25, 1.0, 0, "diffuseFactor");
    near(a->base_color[3], 1.0, 0, "diffuse alpha");
    near3(a->specular, 0.2, 0.3, 0.4, 1e-7, "specularFactor");
    near(a->specular[3], 1.0, 0, "specular weight");
    near(a->ior, 0.0, 0, "ior: F0 = specular colour");
    near(a->metallic, 0.0, 0, "metallic");
    near(a->roughness, 0.25, 1e-7, "roughness = 1 - glossiness");
    assert_int_equal(a->metallic_roughness_tex, ST_NO_TEXTURE);
    assert_int_equal(a->specular_color_tex, ST_NO_TEXTURE);
    near3(b->base_color, 1.0, 1.0, 1.0, 0, "default diffuse");
    near(b->roughness, 1.0, 0, "roughness factor with a map");
    near(b->metallic, 0.0, 0, "metallic");
    assert_int_not_equal(b->base_color_tex, ST_NO_TEXTURE);
    assert_int_not_equal(b->specular_color_tex, ST_NO_TEXTURE);
    const st_texture *spec = &s->textures[b->specular_color_tex];
    assert_true(spec->width == 2 && spec->height == 1 && (spec->flags & ST_TEX_SRGB));
    assert_int_not_equal(b->metallic_roughness_tex, ST_NO_TEXTURE);
    const st_texture *rough = &s->textures[b->metallic_roughness_tex];
    assert_true(rough->width == 2 && rough->height == 1 && !(rough->flags & ST_TEX_SRGB));
    const st_u32 want[2] = {223, 128};
    for (int x = 0; x < 2; x++) {
        st_u32 t = s->texels[rough->offset + (st_u32)x];
        assert_int_equal(t & 255u, 255);        /* R unused */
        assert_int_equal(t >> 8 & 255u, want[x]); /* G: roughness */
        assert_int_equal(t >> 16 & 255u, 0);      /* B: metallic */
    }
    st_scene_destroy(s);
}

/* ---- tangents ------------------------------------------------------------------ */

/* The shading normal a normal map's tangent-space normal m gives at vertex
 * v of triangle t, by st_shared.h's frame: x along the tangent, y along the
 * bitangent w cross(n, t), z along the shading normal n. */
static void mapped_normal(const st_scene *s, st_u32 t, int v, const double m[3], double out[3])
{
    const float *tan = s->tangents + 12 * (size_t)t + 4 * (size_t)v;
    const float *n = s->normals + 9 * (size_t)t + 3 * (size_t)v;
    const double w = tan[3], b[3] = {w * ((double)n[1] * tan[2] - (double)n[2] * tan[1]),
                                     w * ((double)n[2] * tan[0] - (double)n[0] * tan[2]),
                                     w * ((double)n[0] * tan[1] - (double)n[1] * tan[0])};
    for (int k = 0; k < 3; k++)
        out[k] = m[0] * tan[k] + m[1] * b[k] + m[2] * n[k];
}

/* tangent_ramp's map holds the tangent-space normal (0, -0.5, 0.87) (bytes
 * 128, 64, 238): it tilts away from the map's green axis, which points up
 * the image, towards -v. On the quad v runs down the world's y (v = (1 -
 * y) / 2), so up the image is +y and the mapped normal must lean to -y:
 * (0, -0.5, 0.87) in the world, mirrored u or not (mirroring u turns the
 * tangent over, not the bitangent). Generated tangents must also equal the
 * TANGENT that glTF's definition gives the same quad, (1, 0, 0, +1).
 * With the handedness flipped the normal leans to +y and all three fail. */
static void generated_tangents_have_gltf_handedness(void **state)
{
    (void)state;
    static const struct {
        const char *file;
        double tx, w;
    } cases[] = {{SCENES "tangent_ramp.gltf", 1.0, 1.0},
                 {SCENES "tangent_ramp_mirrored.gltf", -1.0, -1.0},
                 {SCENES "tangent_ramp_given.gltf", 1.0, 1.0}};
    const double m[3] = {128.0 / 255.0 * 2.0 - 1.0, 64.0 / 255.0 * 2.0 - 1.0,
                         238.0 / 255.0 * 2.0 - 1.0};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        st_scene *s = load_ok(cases[c].file);
        assert_int_equal(s->tri_count, 2);
        for (st_u32 t = 0; t < s->tri_count; t++)
            for (int v = 0; v < 3; v++) {
                const float *tan = s->tangents + 12 * (size_t)t + 4 * (size_t)v;
                near3(tan, cases[c].tx, 0.0, 0.0, 1e-6, cases[c].file);
                near(tan[3], cases[c].w, 0.0, cases[c].file);
                double n[3];
                mapped_normal(s, t, v, m, n);
                near(n[0], m[0] * cases[c].tx, 1e-6, "mapped normal x (u mirrored: -x)");
                near(n[1], m[1], 1e-6, "mapped normal y (towards +v: the world's -y)");
                near(n[2], m[2], 1e-6, "mapped normal z");
            }
        st_scene_destroy(s);
    }
}

/* A copy of the glTF file `path` in `dir` without any TANGENT attribute,
 * with the buffers its URIs name copied beside it (images are left out: the
 * loader puts white in their place, which does not touch the tangents).
 * Returns the copy's path (malloc'd). */
static char *strip_tangents(const char *path, const char *dir)
{
    size_t size;
    unsigned char *raw = read_all(path, &size);
    cJSON *root = cJSON_ParseWithLength((const char *)raw, size);
    free(raw);
    assert_non_null(root);
    const cJSON *mesh, *prim, *buf;
    cJSON_ArrayForEach(mesh, cJSON_GetObjectItem(root, "meshes"))
        cJSON_ArrayForEach(prim, cJSON_GetObjectItem(mesh, "primitives"))
            cJSON_DeleteItemFromObject(cJSON_GetObjectItem(prim, "attributes"), "TANGENT");
    char from[512], to[512];
    const char *slash = strrchr(path, '/');
    cJSON_ArrayForEach(buf, cJSON_GetObjectItem(root, "buffers")) {
        const char *uri = cJSON_GetStringValue(cJSON_GetObjectItem(buf, "uri"));
        if (!uri || !strncmp(uri, "data:", 5))
            continue;
        snprintf(from, sizeof from, "%.*s/%s", (int)(slash - path), path, uri);
        snprintf(to, sizeof to, "%s/%s", dir, uri);
        unsigned char *bin = read_all(from, &size);
        write_all(to, bin, size);
        free(bin);
    }
    char *text = cJSON_PrintUnformatted(root);
    snprintf(to, sizeof to, "%s/%s", dir, slash + 1);
    write_all(to, (const unsigned char *)text, strlen(text));
    free(text);
    cJSON_Delete(root);
    return strdup(to);
}

/* The Khronos models that carry TANGENT (MikkTSpace's, as their exporters
 * wrote them) loaded with and without it: where both have a tangent, the
 * generated handedness must agree with the file's at 95 % of the vertices
 * and the tangents must point the same way (mean cosine 0.9). The flipped
 * handedness agrees almost nowhere. */
static void generated_tangents_agree_with_khronos_tangents(void **state)
{
    (void)state;
    static const char *files[] = {"Avocado/Avocado.gltf", "WaterBottle/WaterBottle.gltf",
                                  "AlphaBlendModeTest/AlphaBlendModeTest.gltf",
                                  "NormalTangentTest/NormalTangentTest.gltf",
                                  "NormalTangentTest/glTF/NormalTangentTest.gltf",
                                  "NormalTangentMirrorTest/NormalTangentMirrorTest.gltf",
                                  "NormalTangentMirrorTest/glTF/NormalTangentMirrorTest.gltf"};
    int checked = 0;
    for (size_t f = 0; f < sizeof files / sizeof files[0]; f++) {
        char path[256], dir[64];
        snprintf(path, sizeof path, KHRONOS "/%s", files[f]);
        if (access(path, R_OK) != 0)
            continue;
        make_scratch(dir);
        char *copy = strip_tangents(path, dir);
        st_scene *given = load_ok(path), *made = load_ok(copy);
        assert_int_equal(given->tri_count, made->tri_count);
        size_t both = 0, agree = 0;
        double cos_sum = 0.0;
        for (size_t i = 0; i < 3 * (size_t)given->tri_count; i++) {
            const float *a = given->tangents + 4 * i, *b = made->tangents + 4 * i;
            if (a[3] == 0.0f || b[3] == 0.0f)
                continue;
            both++;
            agree += a[3] == b[3];
            cos_sum += (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2];
        }
        print_message("%s: %zu vertices, handedness agrees at %.4f, mean cosine %.4f\n",
                      files[f], both, (double)agree / (double)both, cos_sum / (double)both);
        assert_true(both > 0);
        if (!((double)agree >= 0.95 * (double)both && cos_sum >= 0.9 * (double)both))
            fail_msg("%s: generated tangents disagree with the file's", files[f]);
        st_scene_destroy(given);
        st_scene_destroy(made);
        char cmd[160];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
        assert_int_equal(system(cmd), 0);
        free(copy);
        checked++;
    }
    if (!checked)
        ST_SKIP(dir_exists(KHRONOS) ? "no Khronos model with tangents under %s"
                                    : "%s not found (the Khronos sample models)", KHRONOS);
}

/* Every proper prefix of a valid file is malformed: status ST_ERR_FORMAT,
 * never a crash. The .gltf is cut before its closing brace (a prefix that
 * only drops trailing white space is still the whole document). */
static void truncated_files_return_format_error(void **state)
{
    (void)state;
    static const char *files[] = {SCENES "layout.glb", SCENES "layout_u16.gltf"};
    char dir[64], path[128];
    make_scratch(dir);
    for (int f = 0; f < 2; f++) {
        size_t size;
        unsigned char *data = read_all(files[f], &size);
        size_t full = size;
        while (full > 0 && (data[full - 1] == '\n' || data[full - 1] == ' '))
            full--;
        snprintf(path, sizeof path, "%s/cut%s", dir, f == 0 ? ".glb" : ".gltf");
        for (size_t n = 0; n < full; n++) {
            write_all(path, data, n);
            load_fails(path, ST_ERR_FORMAT, path, NULL);
        }
        unlink(path);
        free(data);
    }
    rmdir(dir);
}

/* Each byte of a .glb overwritten with 0x00, 0xff and itself ^ 0x5a: the load
 * either fails with ST_ERR_FORMAT or gives a scene that keeps every invariant
 * (run under the sanitizers, `make test SANITIZE=1`, this also checks that
 * no byte is read out of bounds). layout.glb exercises the accessors,
 * textured.glb the image in the BIN chunk (damaged PNGs reach stb_image). */
static void mutate_glb(const char *file)
{
    char dir[64], path[128];
    make_scratch(dir);
    snprintf(path, sizeof path, "%s/mutant.glb", dir);
    size_t size;
    unsigned char *data = read_all(file, &size);
    int loaded = 0, failed = 0;
    for (size_t i = 0; i < size; i++)
        for (int m = 0; m < 3; m++) {
            unsigned char keep = data[i];
            data[i] = m == 0 ? 0x00 : m == 1 ? 0xff : (unsigned char)(keep ^ 0x5a);
            write_all(path, data, size);
            data[i] = keep;
            st_error err = {0};
            st_scene *s = NULL;
            st_status st = st_scene_load(path, &s, &err);
            if (st == ST_OK) {
                check_invariants(s);
                st_scene_destroy(s);
                loaded++;
            } else {
                if (st != ST_ERR_FORMAT || !strstr(err.msg, path))
                    fail_msg("%s byte %zu, mutation %d: status %d: %s", file, i, m, st, err.msg);
                failed++;
            }
        }
    assert_true(loaded > 0 && failed > 0); /* both outcomes were exercised */
    unlink(path);
    free(data);
    rmdir(dir);
}

static void mutated_glb_fails_cleanly_or_loads_valid_scene(void **state)
{
    (void)state;
    mutate_glb(SCENES "layout.glb");
    mutate_glb(SCENES "textured.glb");
}

/* ---- Khronos sample models ---------------------------------------------------- */

/* Triangles, materials and cameras of `file` (e.g. "Box/Box.gltf") in
 * INDEX.md's table row "| Dir | `file` | triangles | materials | textures |
 * cameras | ..."; 0 when the row is absent. */
static int index_row(const char *index, const char *file, long *tris, long *mats, long *cams)
{
    char key[160];
    snprintf(key, sizeof key, "| `%s` | ", file);
    const char *row = strstr(index, key);
    if (!row)
        return 0;
    char *p = (char *)row + strlen(key);
    *tris = strtol(p, &p, 10);
    p += strspn(p, " |");
    *mats = strtol(p, &p, 10);
    p += strspn(p, " |");
    strtol(p, &p, 10); /* textures (glTF's array; strata counts references) */
    p += strspn(p, " |");
    *cams = strtol(p, &p, 10);
    return 1;
}

/* Every model INDEX.md lists loads. INDEX.md counts every TRIANGLES
 * primitive of every node reachable from the default scene; strata keeps
 * those with non-zero area, so kept + dropped must equal it. Materials: the
 * file's, plus strata's default when some primitive has none. Camera nodes
 * are at least the file's cameras that some node uses, so >= 1 when the
 * file has any (the counts differ where a camera is used twice). */
static void khronos_models_match_index_counts(void **state)
{
    (void)state;
    if (!dir_exists(KHRONOS))
        ST_SKIP("%s not found (the Khronos sample models)", KHRONOS);
    size_t size;
    unsigned char *raw = read_all(KHRONOS "/INDEX.md", &size);
    char *index = malloc(size + 1);
    assert_non_null(index);
    memcpy(index, raw, size);
    index[size] = '\0';
    free(raw);
    int models = 0;
    for (const char *row = strstr(index, "| `"); row; row = strstr(row + 3, "| `")) {
        char file[128];
        const char *end = strchr(row + 3, '`');
        if (!end || end - (row + 3) >= (long)sizeof file)
            continue;
        memcpy(file, row + 3, (size_t)(end - (row + 3)));
        file[end - (row + 3)] = '\0';
        if (!strstr(file, ".gl"))
            continue; /* a code span in the prose, not a model */
        long tris, mats, cams;
        if (!index_row(index, file, &tris, &mats, &cams))
            continue;
        char path[256];
        snprintf(path, sizeof path, KHRONOS "/%s", file);
        st_scene *s = load_ok(path);
        if ((long)s->tri_count + (long)s->dropped != tris)
            fail_msg("%s: %u kept + %u dropped, INDEX.md says %ld", file, s->tri_count,
                     s->dropped, tris);
        int appended = s->material_count == (st_u32)mats + 1;
        if (!((long)s->material_count == mats || appended))
            fail_msg("%s: %u materials, INDEX.md says %ld", file, s->material_count, mats);
        if (cams > 0 && s->camera_count == 0)
            fail_msg("%s: no camera node, INDEX.md lists %ld cameras", file, cams);
        if (cams == 0)
            assert_int_equal(s->camera_count, 0);
        st_scene_destroy(s);
        models++;
    }
    assert_true(models >= 19);
    free(index);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(cornell_box_loads_as_default_builtin),
        cmocka_unit_test(cornell_box_materials_have_specified_values),
        cmocka_unit_test(cornell_box_normals_face_the_air),
        cmocka_unit_test(builtin_names_list_cornell_box),
        cmocka_unit_test(unknown_builtin_and_missing_file_are_errors),
        cmocka_unit_test(layouts_u8_u16_u32_indices_give_same_triangles),
        cmocka_unit_test(layouts_interleaved_stride_gives_same_triangles),
        cmocka_unit_test(layouts_nonindexed_and_glb_give_same_triangles),
        cmocka_unit_test(nested_trs_equals_baked_vertices),
        cmocka_unit_test(nested_trs_normals_equal_face_normals),
        cmocka_unit_test(cameras_listed_depth_first_first_is_default),
        cmocka_unit_test(default_camera_frames_bounding_sphere),
        cmocka_unit_test(materials_and_flat_normals_follow_the_file),
        cmocka_unit_test(texcoords_float_u8_u16_read_as_file_says),
        cmocka_unit_test(texture_references_follow_the_file),
        cmocka_unit_test(default_environment_follows_the_lights),
        cmocka_unit_test(dark_fraction_counts_what_no_light_reaches),
        cmocka_unit_test(builtin_scenes_load_by_name),
        cmocka_unit_test(scene_content_hash_follows_content_not_path),
        cmocka_unit_test(malformed_files_return_format_error_naming_file),
        cmocka_unit_test(unreadable_images_and_unknown_extensions_warn),
        cmocka_unit_test(unreadable_normal_map_is_left_out),
        cmocka_unit_test(transmission_without_volume_is_thin),
        cmocka_unit_test(sheen_is_imported),
        cmocka_unit_test(anisotropy_is_imported),
        cmocka_unit_test(diffuse_transmission_is_imported),
        cmocka_unit_test(iridescence_is_imported),
        cmocka_unit_test(dispersion_is_imported),
        cmocka_unit_test(textured_flag_follows_the_factors),
        cmocka_unit_test(auto_camera_sees_the_front),
        cmocka_unit_test(look_at_builds_the_view),
        cmocka_unit_test(strips_and_fans_become_triangles),
        cmocka_unit_test(sparse_accessors_substitute_values),
        cmocka_unit_test(material_extensions_are_read),
        cmocka_unit_test(quantized_attributes_equal_their_float_twin),
        cmocka_unit_test(truncated_files_return_format_error),
        cmocka_unit_test(mutated_glb_fails_cleanly_or_loads_valid_scene),
        cmocka_unit_test(khronos_models_match_index_counts),
        cmocka_unit_test(generated_tangents_have_gltf_handedness),
        cmocka_unit_test(gpu_instances_are_drawn_each),
        cmocka_unit_test(morph_targets_take_the_default_weights),
        cmocka_unit_test(skins_take_the_rest_pose),
        cmocka_unit_test(spec_gloss_becomes_metallic_roughness),
        cmocka_unit_test(generated_tangents_agree_with_khronos_tangents),
    };
    return cmocka_run_group_tests_name("scene", tests, NULL, NULL);
}
