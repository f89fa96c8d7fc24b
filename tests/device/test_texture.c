/* test_texture.c — textures: the lookups of kernels/integrator/texture.h (run here on
 * the host, the device's own code), the mip chains of st_scene_build_mips,
 * and textured renders on the device (constant textures times factors, the
 * environment light, alpha cut-outs, and texture filtering on the
 * checkerboard against a supersampled reference).
 *
 * Expected values come from the definitions, computed here independently:
 * the IEC 61966-2-1 sRGB formula, OpenGL 4.6's wrap-mode formulas (§8.14.2,
 * Table 8.20: MIRRORED_REPEAT as (size - 1) - mirror((i mod 2 size) - size)),
 * bilinear weights written out, the [1 3 3 1] / 8 filter applied to a
 * delta, the ray-cone level of detail at which a texel spans the cone, and
 * closed-form radiance (a surface open to a uniform environment L reflects
 * albedo x L; emission adds). Run from the repository root. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "device_fixture.h"
#include "st_device.h"
#include "st_diff.h"
#include "st_render.h"
#include "st_scene.h"
#include "texture.h"

#define SCENES "tests/scenes/"

static void near(double got, double want, double tol, const char *what)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("%s: got %.9g, want %.9g (tolerance %g)", what, got, want, tol);
}

/* sRGB decode by the formula, in double. */
static double srgb_formula(int b)
{
    double c = b / 255.0;
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

/* A texture over `rgba` (w x h, bytes R G B A) with its whole mip chain. */
typedef struct test_tex {
    st_texture desc;
    st_u32 *texels;
} test_tex;

static test_tex make_tex(const unsigned char *rgba, st_u32 w, st_u32 h, st_u32 flags,
                         st_u32 wrap_s, st_u32 wrap_t)
{
    test_tex t;
    memset(&t, 0, sizeof t);
    st_error err = {0};
    st_u32 levels;
    if (st_scene_build_mips(rgba, w, h, flags & ST_TEX_SRGB, wrap_s, wrap_t, &t.texels, &levels,
                            &err) != ST_OK)
        fail_msg("mips: %s", err.msg);
    t.desc.transform[0] = t.desc.transform[4] = 1.0f;
    t.desc.width = w;
    t.desc.height = h;
    t.desc.levels = levels;
    t.desc.flags = flags;
    t.desc.wrap_s = wrap_s;
    t.desc.wrap_t = wrap_t;
    t.desc.lod_bias = 0.5f * log2f((float)w * (float)h);
    return t;
}

/* Bytes of a w x h image from a fixed pseudo-random stream. */
static unsigned char *random_rgba(st_u32 w, st_u32 h, uint32_t seed)
{
    unsigned char *p = malloc((size_t)w * h * 4);
    assert_non_null(p);
    for (size_t i = 0; i < (size_t)w * h * 4; i++) {
        seed = seed * 1664525u + 1013904223u;
        p[i] = (unsigned char)(seed >> 24);
    }
    return p;
}

/* Texel (x, y) of level 0 as linear RGBA, decoded here from the bytes. */
static void texel_of(const unsigned char *rgba, st_u32 w, st_u32 x, st_u32 y, int srgb,
                     double out[4])
{
    const unsigned char *p = rgba + 4 * ((size_t)y * w + x);
    for (int c = 0; c < 4; c++)
        out[c] = srgb && c < 3 ? srgb_formula(p[c]) : p[c] / 255.0;
}

/* ---- sRGB and wrap modes ---------------------------------------------------- */

static void srgb_table_equals_iec_formula(void **state)
{
    (void)state;
    for (st_u32 b = 0; b < 256; b++) {
        near(st_srgb_to_linear(b), srgb_formula((int)b), 2e-8 + 1e-7 * srgb_formula((int)b),
             "sRGB table");
        if (b > 0)
            assert_true(st_srgb_table[b] > st_srgb_table[b - 1]); /* strictly increasing */
    }
    assert_true(st_srgb_table[0] == 0.0f && st_srgb_table[255] == 1.0f);
}

/* OpenGL 4.6 §8.14.2: REPEAT i mod size; CLAMP_TO_EDGE clamp(i, 0, size - 1);
 * MIRRORED_REPEAT (size - 1) - mirror((i mod 2 size) - size), mirror(a) = a
 * for a >= 0, -(1 + a) otherwise. */
static void wrap_modes_match_opengl_definitions(void **state)
{
    (void)state;
    for (st_i32 n = 1; n <= 7; n++)
        for (st_i32 i = -4 * n; i <= 4 * n; i++) {
            st_i32 rep = ((i % n) + n) % n;
            st_i32 clamp = i < 0 ? 0 : i > n - 1 ? n - 1 : i;
            st_i32 a = (((i % (2 * n)) + 2 * n) % (2 * n)) - n;
            st_i32 mirror = (n - 1) - (a >= 0 ? a : -(1 + a));
            assert_int_equal(st_tex_wrap(i, n, ST_WRAP_REPEAT), rep);
            assert_int_equal(st_tex_wrap(i, n, ST_WRAP_CLAMP), clamp);
            assert_int_equal(st_tex_wrap(i, n, ST_WRAP_MIRROR), mirror);
        }
    /* coordinates far outside [0, 1] and non-finite ones stay in range */
    const float far[] = {1e9f, -1e9f, 12345.678f, INFINITY, -INFINITY, NAN};
    for (size_t k = 0; k < sizeof far / sizeof far[0]; k++)
        for (st_u32 mode = 0; mode < 3; mode++) {
            float r = st_tex_reduce(far[k], mode);
            assert_true(r >= -1.0f && r <= 2.0f);
        }
}

/* st_tex_floor is floor() for every float but -0 (+0 then): a sweep across
 * the integers and halves of [-40, 40], the ends of the exact-integer range
 * (2^23) and beyond, the smallest magnitudes, and the non-finite values. */
static void tex_floor_is_floor(void **state)
{
    (void)state;
    for (int k = -400; k <= 400; k++) {
        float x = (float)k / 10.0f;
        assert_true(st_tex_floor(x) == floorf(x));
        assert_true(st_tex_floor(nextafterf(x, -INFINITY)) == floorf(nextafterf(x, -INFINITY)));
        assert_true(st_tex_floor(nextafterf(x, INFINITY)) == floorf(nextafterf(x, INFINITY)));
    }
    const float odd[] = {8388607.5f, -8388607.5f, 8388608.0f, -8388608.0f, 8388609.0f,
                         -8388609.0f, 16777217.0f, 3e9f, -3e9f, 1e30f, -1e30f, FLT_MAX,
                         -FLT_MAX, FLT_MIN, -FLT_MIN, 1e-45f, -1e-45f, 0.5f, -0.5f, 0.0f};
    for (size_t k = 0; k < sizeof odd / sizeof odd[0]; k++)
        assert_true(st_tex_floor(odd[k]) == floorf(odd[k]));
    assert_true(st_tex_floor(INFINITY) == INFINITY && st_tex_floor(-INFINITY) == -INFINITY);
    assert_true(isnan(st_tex_floor(NAN)));
    assert_true(st_tex_floor(-0.0f) == 0.0f && !signbit(st_tex_floor(-0.0f)));
}

/* ---- lookups ---------------------------------------------------------------- */

/* At a texel centre bilinear interpolation returns that texel; at the cell
 * of a texel NEAREST returns it, for sRGB and linear textures. */
static void lookups_at_texel_centres_return_texels(void **state)
{
    (void)state;
    const st_u32 w = 5, h = 3;
    unsigned char *rgba = random_rgba(w, h, 1);
    for (int srgb = 0; srgb < 2; srgb++) {
        test_tex t = make_tex(rgba, w, h, srgb ? ST_TEX_SRGB : 0u, ST_WRAP_REPEAT, ST_WRAP_REPEAT);
        for (st_u32 y = 0; y < h; y++)
            for (st_u32 x = 0; x < w; x++) {
                double want[4];
                float got[4], near_got[4];
                texel_of(rgba, w, x, y, srgb, want);
                float u = (x + 0.5f) / w, v = (y + 0.5f) / h;
                st_tex_bilinear(&t.desc, t.texels, 0, u, v, got);
                st_tex_nearest(&t.desc, t.texels, 0, u + 0.3f / w, v - 0.4f / h, near_got);
                for (int c = 0; c < 4; c++) {
                    near(got[c], want[c], 1e-6, "bilinear at a texel centre");
                    near(near_got[c], want[c], 1e-7, "nearest in the texel's cell");
                }
            }
        free(t.texels);
    }
    free(rgba);
}

/* Between four texel centres: the weights (1 - fx)(1 - fy), fx(1 - fy),
 * (1 - fx) fy, fx fy, written out; across the REPEAT edge it blends the last
 * and first columns. */
static void bilinear_weights_between_centres(void **state)
{
    (void)state;
    const st_u32 w = 4, h = 4;
    unsigned char *rgba = random_rgba(w, h, 2);
    test_tex t = make_tex(rgba, w, h, 0u, ST_WRAP_REPEAT, ST_WRAP_REPEAT);
    const float fx = 0.3f, fy = 0.8f;
    for (st_u32 y = 0; y < h; y++)
        for (st_u32 x = 0; x < w; x++) {
            double a[4], b[4], c[4], d[4];
            texel_of(rgba, w, x, y, 0, a);
            texel_of(rgba, w, (x + 1) % w, y, 0, b);
            texel_of(rgba, w, x, (y + 1) % h, 0, c);
            texel_of(rgba, w, (x + 1) % w, (y + 1) % h, 0, d);
            float got[4];
            st_tex_bilinear(&t.desc, t.texels, 0, (x + 0.5f + fx) / w, (y + 0.5f + fy) / h, got);
            for (int k = 0; k < 4; k++)
                near(got[k],
                     (1 - fx) * (1 - fy) * a[k] + fx * (1 - fy) * b[k] + (1 - fx) * fy * c[k] +
                         fx * fy * d[k],
                     2e-6, "bilinear weights");
        }
    free(t.texels);
    free(rgba);
}

/* REPEAT: u and u + 3 read the same; MIRRORED_REPEAT: u and -u, u and 2 - u;
 * CLAMP_TO_EDGE: anything left of the first texel centre reads column 0. */
static void wrap_modes_in_lookups(void **state)
{
    (void)state;
    const st_u32 w = 6, h = 2;
    unsigned char *rgba = random_rgba(w, h, 3);
    test_tex rep = make_tex(rgba, w, h, 0u, ST_WRAP_REPEAT, ST_WRAP_REPEAT);
    test_tex mir = make_tex(rgba, w, h, 0u, ST_WRAP_MIRROR, ST_WRAP_REPEAT);
    test_tex cla = make_tex(rgba, w, h, 0u, ST_WRAP_CLAMP, ST_WRAP_REPEAT);
    const float v = 0.25f;
    for (float u = 0.01f; u < 1.0f; u += 0.049f) {
        float a[4], b[4];
        st_tex_bilinear(&rep.desc, rep.texels, 0, u, v, a);
        st_tex_bilinear(&rep.desc, rep.texels, 0, u + 3.0f, v, b);
        for (int c = 0; c < 4; c++)
            near(a[c], b[c], 1e-5, "REPEAT period 1");
        st_tex_bilinear(&mir.desc, mir.texels, 0, u, v, a);
        st_tex_bilinear(&mir.desc, mir.texels, 0, -u, v, b);
        for (int c = 0; c < 4; c++)
            near(a[c], b[c], 1e-5, "MIRRORED_REPEAT symmetric about 0");
        st_tex_bilinear(&mir.desc, mir.texels, 0, 2.0f - u, v, b);
        for (int c = 0; c < 4; c++)
            near(a[c], b[c], 1e-5, "MIRRORED_REPEAT symmetric about 1");
    }
    float edge[4], out[4];
    st_tex_bilinear(&cla.desc, cla.texels, 0, 0.5f / w, v, edge);
    const float left[] = {0.0f, -0.5f, -7.0f, 0.2f / w};
    for (size_t k = 0; k < sizeof left / sizeof left[0]; k++) {
        st_tex_bilinear(&cla.desc, cla.texels, 0, left[k], v, out);
        for (int c = 0; c < 4; c++)
            near(out[c], edge[c], 1e-6, "CLAMP_TO_EDGE");
    }
    free(rep.texels);
    free(mir.texels);
    free(cla.texels);
    free(rgba);
}

/* Filters: NONE reads level 0's nearest texel whatever lod; BILINEAR level
 * 0; TRILINEAR at integer lod l equals bilinear of level l, between levels
 * the linear blend by the fraction, below 0 level 0 (nearest with
 * ST_TEX_MAG_NEAREST), beyond the last level the last level. */
static void trilinear_blends_levels_by_lod(void **state)
{
    (void)state;
    const st_u32 w = 16, h = 8;
    unsigned char *rgba = random_rgba(w, h, 4);
    test_tex t = make_tex(rgba, w, h, ST_TEX_SRGB, ST_WRAP_REPEAT, ST_WRAP_REPEAT);
    assert_int_equal(t.desc.levels, 5); /* 16x8, 8x4, 4x2, 2x1, 1x1 */
    const float u = 0.37f, v = 0.61f;
    float lv[5][4], got[4], near0[4];
    for (st_u32 l = 0; l < 5; l++)
        st_tex_bilinear(&t.desc, t.texels, l, u, v, lv[l]);
    st_tex_nearest(&t.desc, t.texels, 0, u, v, near0);
    for (st_u32 l = 0; l < 5; l++) {
        st_tex_sample(&t.desc, t.texels, u, v, l == 0 ? 1e-9f : (float)l, ST_TEXFILTER_TRILINEAR,
                      got);
        for (int c = 0; c < 4; c++)
            near(got[c], lv[l][c], 1e-6, "trilinear at an integer lod");
    }
    st_tex_sample(&t.desc, t.texels, u, v, 2.25f, ST_TEXFILTER_TRILINEAR, got);
    for (int c = 0; c < 4; c++)
        near(got[c], 0.75 * lv[2][c] + 0.25 * lv[3][c], 1e-6, "trilinear between levels");
    st_tex_sample(&t.desc, t.texels, u, v, 40.0f, ST_TEXFILTER_TRILINEAR, got);
    for (int c = 0; c < 4; c++)
        near(got[c], lv[4][c], 1e-6, "lod beyond the last level");
    st_tex_sample(&t.desc, t.texels, u, v, -3.0f, ST_TEXFILTER_TRILINEAR, got);
    for (int c = 0; c < 4; c++)
        near(got[c], lv[0][c], 1e-6, "magnification: level 0 bilinear");
    t.desc.flags |= ST_TEX_MAG_NEAREST;
    st_tex_sample(&t.desc, t.texels, u, v, -3.0f, ST_TEXFILTER_TRILINEAR, got);
    for (int c = 0; c < 4; c++)
        near(got[c], near0[c], 1e-7, "magnification with magFilter NEAREST");
    st_tex_sample(&t.desc, t.texels, u, v, 2.5f, ST_TEXFILTER_NONE, got);
    for (int c = 0; c < 4; c++)
        near(got[c], near0[c], 1e-7, "NONE ignores lod");
    st_tex_sample(&t.desc, t.texels, u, v, 2.5f, ST_TEXFILTER_BILINEAR, got);
    for (int c = 0; c < 4; c++)
        near(got[c], lv[0][c], 1e-7, "BILINEAR ignores lod");
    free(t.texels);
    free(rgba);
}

/* KHR_texture_transform: a lookup at (u, v) equals the untransformed lookup
 * at (t0 u + t1 v + t2, t3 u + t4 v + t5). */
static void transform_applies_before_lookup(void **state)
{
    (void)state;
    unsigned char *rgba = random_rgba(8, 8, 5);
    test_tex t = make_tex(rgba, 8, 8, 0u, ST_WRAP_REPEAT, ST_WRAP_REPEAT);
    test_tex id = t;
    const float m[6] = {0.0f, 3.0f, 0.5f, -2.0f, 0.0f, 0.25f}; /* rotation by 90 deg, scale (2, 3) */
    memcpy(t.desc.transform, m, sizeof m);
    for (float u = 0.05f; u < 1.0f; u += 0.15f)
        for (float v = 0.05f; v < 1.0f; v += 0.15f) {
            float a[4], b[4];
            st_tex_sample(&t.desc, t.texels, u, v, 0.0f, ST_TEXFILTER_BILINEAR, a);
            st_tex_sample(&id.desc, id.texels, m[0] * u + m[1] * v + m[2],
                          m[3] * u + m[4] * v + m[5], 0.0f, ST_TEXFILTER_BILINEAR, b);
            for (int c = 0; c < 4; c++)
                near(a[c], b[c], 1e-6, "transformed lookup");
        }
    free(t.texels);
    free(rgba);
}

/* Ray cones: lod 0 where one texel spans the cone's width head-on; each
 * doubling of the width, or halving of |cos|, adds one level. Triangle: uv =
 * world x s, so tri lod = 1/2 log2(s^2) = log2 s; a w x w texture has
 * lod_bias = log2 w; a texel is 1 / (s w) world units wide. */
static void ray_cone_lod_is_zero_when_a_texel_spans_the_cone(void **state)
{
    (void)state;
    st_texture t;
    memset(&t, 0, sizeof t);
    const float s = 0.25f, w = 64.0f;
    t.lod_bias = 0.5f * log2f(w * w);
    const float tri_lod = 0.5f * log2f(s * s), texel = 1.0f / (s * w);
    near(st_tex_lod(tri_lod, &t, texel, 1.0f), 0.0, 1e-6, "texel = cone width");
    near(st_tex_lod(tri_lod, &t, 2.0f * texel, 1.0f), 1.0, 1e-6, "twice the width");
    near(st_tex_lod(tri_lod, &t, texel, -0.5f), 1.0, 1e-6, "cos 1/2, back face");
    near(st_tex_lod(tri_lod, &t, 0.25f * texel, 1.0f), -2.0, 1e-6, "magnified");
    assert_true(isfinite(st_tex_lod(tri_lod, &t, texel, 0.0f))); /* grazing: clamped */
    assert_true(isfinite(st_tex_lod(tri_lod, &t, 0.0f, 1.0f)));  /* pinhole at distance 0 */
}

/* ---- mip chains --------------------------------------------------------------- */

static void mip_chain_sizes_follow_halving_rule(void **state)
{
    (void)state;
    static const st_u32 sizes[][2] = {{1, 1}, {8, 8}, {5, 3}, {1, 7}, {640, 480}, {3, 1}};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        st_u32 w = sizes[k][0], h = sizes[k][1], levels = 0, want_levels = 1;
        st_u64 total = 0;
        for (st_u32 lw = w, lh = h;; want_levels++) { /* brute force */
            total += (st_u64)lw * lh;
            if (lw == 1 && lh == 1)
                break;
            lw = lw > 1 ? lw / 2 : 1;
            lh = lh > 1 ? lh / 2 : 1;
        }
        assert_int_equal(st_scene_mip_texels(w, h), total);
        unsigned char *rgba = random_rgba(w, h, 6);
        st_u32 *t = NULL;
        st_error err = {0};
        assert_int_equal(st_scene_build_mips(rgba, w, h, 1, ST_WRAP_REPEAT, ST_WRAP_CLAMP, &t,
                                             &levels, &err),
                         ST_OK);
        assert_int_equal(levels, want_levels);
        assert_int_equal(levels, 1 + (st_u32)floor(log2((double)(w > h ? w : h))));
        free(t);
        free(rgba);
    }
    st_error err = {0};
    st_u32 *t = NULL, levels;
    assert_int_equal(st_scene_build_mips(NULL, 0, 4, 0, 0, 0, &t, &levels, &err), ST_ERR_USAGE);
    assert_null(t);
}

/* A constant image stays constant at every level, in both colour spaces,
 * every wrap mode and odd sizes (the weights are normalised; the sRGB
 * re-encoding is the nearest byte, so decode-encode returns the byte). */
static void mip_of_constant_image_is_constant(void **state)
{
    (void)state;
    const st_u32 w = 7, h = 5;
    unsigned char rgba[7 * 5 * 4];
    for (size_t i = 0; i < sizeof rgba; i += 4) {
        rgba[i] = 188;
        rgba[i + 1] = 3;
        rgba[i + 2] = 250;
        rgba[i + 3] = 77;
    }
    const st_u32 want = 188u | 3u << 8 | 250u << 16 | 77u << 24;
    for (int srgb = 0; srgb < 2; srgb++)
        for (st_u32 wrap = 0; wrap < 3; wrap++) {
            st_u32 *t = NULL, levels;
            st_error err = {0};
            assert_int_equal(st_scene_build_mips(rgba, w, h, srgb, wrap, wrap, &t, &levels, &err),
                             ST_OK);
            for (st_u64 i = 0; i < st_scene_mip_texels(w, h); i++)
                assert_int_equal(t[i], want);
            free(t);
        }
}

/* One bright texel (255 at x = 4 of an 8 x 1 linear image) spreads into
 * level 1 as 255 x [1 3 3 1] / 8 read at 2i - 1 .. 2i + 2: 3/8 into texel 2,
 * 1/8 into texel 1, rounded: 96 and 32. */
static void mip_filter_is_1331_on_a_delta(void **state)
{
    (void)state;
    unsigned char rgba[8 * 4] = {0};
    rgba[4 * 4] = 255;
    st_u32 *t = NULL, levels;
    st_error err = {0};
    assert_int_equal(st_scene_build_mips(rgba, 8, 1, 0, ST_WRAP_REPEAT, ST_WRAP_REPEAT, &t,
                                         &levels, &err),
                     ST_OK);
    const st_u32 *l1 = t + 8;
    assert_int_equal(l1[0] & 255u, 0);
    assert_int_equal(l1[1] & 255u, 32);
    assert_int_equal(l1[2] & 255u, 96);
    assert_int_equal(l1[3] & 255u, 0);
    free(t);
    /* REPEAT wraps the taps: a delta at x = 0 reaches texel 3 (tap 2i + 2 = 8 = 0) */
    memset(rgba, 0, sizeof rgba);
    rgba[0] = 255;
    assert_int_equal(st_scene_build_mips(rgba, 8, 1, 0, ST_WRAP_REPEAT, ST_WRAP_REPEAT, &t,
                                         &levels, &err),
                     ST_OK);
    assert_int_equal(t[8 + 3] & 255u, 32);
    assert_int_equal(t[8 + 0] & 255u, 96);
    free(t);
}

/* sRGB chains average light, not bytes: sRGB 0 and 255 side by side average
 * to linear 0.5, stored as the byte whose decode is nearest to 0.5 (188); a
 * linear chain stores 128 (127.5 rounded). With REPEAT the mean of every
 * level of a power-of-two image equals level 0's within the rounding (1/2
 * byte per level). */
static void mip_averages_in_linear_light_and_keeps_the_mean(void **state)
{
    (void)state;
    unsigned char pair[8] = {0, 0, 0, 255, 255, 255, 255, 255};
    st_u32 *t = NULL, levels;
    st_error err = {0};
    assert_int_equal(st_scene_build_mips(pair, 2, 1, 1, 0, 0, &t, &levels, &err), ST_OK);
    st_u32 b = t[2] & 255u;
    for (st_u32 k = 0; k < 256; k++)
        assert_true(fabs(st_srgb_table[b] - 0.5) <= fabs(st_srgb_table[k] - 0.5));
    assert_int_equal(b, 188);
    free(t);
    assert_int_equal(st_scene_build_mips(pair, 2, 1, 0, 0, 0, &t, &levels, &err), ST_OK);
    assert_int_equal(t[2] & 255u, 128);
    free(t);

    unsigned char *rgba = random_rgba(32, 16, 7);
    assert_int_equal(st_scene_build_mips(rgba, 32, 16, 0, 0, 0, &t, &levels, &err), ST_OK);
    double mean0 = 0.0;
    for (size_t i = 0; i < 32 * 16; i++)
        mean0 += (t[i] & 255u) / (32.0 * 16.0);
    const st_u32 *lv = t;
    for (st_u32 l = 0, w = 32, h = 16; l < levels; l++) {
        double mean = 0.0;
        for (size_t i = 0; i < (size_t)w * h; i++)
            mean += (lv[i] & 255u) / ((double)w * h);
        near(mean, mean0, 0.5 * l + 1e-9, "mean of a level");
        lv += (size_t)w * h;
        w = w > 1 ? w / 2 : 1;
        h = h > 1 ? h / 2 : 1;
    }
    free(t);
    free(rgba);
}

/* ---- renders on the device ------------------------------------------------------ */



static st_scene *load(const char *spec)
{
    st_error err = {0};
    st_scene *s = NULL;
    if (st_scene_load(spec, &s, &err) != ST_OK)
        fail_msg("load %s: %s", spec, err.msg);
    return s;
}

/* A render of s with the view's environment (NULL: the scene's default)
 * and texture filter. */
static st_image render_view(const st_scene *s, st_u32 w, st_u32 h, st_u32 spp,
                            st_u32 integrator, const float *env, st_u32 texture_filter)
{
    st_render_options o = st_render_defaults();
    if (env) {
        o.env_given = 1;
        memcpy(o.env, env, sizeof o.env);
    }
    o.texture_filter = texture_filter;
    o.width = w;
    o.height = h;
    o.spp = spp;
    o.seed = 3;
    o.integrator = integrator;
    st_error err = {0};
    st_renderer *r = NULL;
    st_image img = {0};
    if (st_renderer_create(dev, s, &r, &err) || st_render(r, &o, &img, NULL, NULL, NULL, NULL, &err))
        fail_msg("render %s: %s", s->name, err.msg);
    st_renderer_destroy(r);
    return img;
}

static st_image render(const st_scene *s, st_u32 w, st_u32 h, st_u32 spp, st_u32 integrator)
{
    return render_view(s, w, h, spp, integrator, NULL, ST_TEXFILTER_TRILINEAR);
}

/* textured_quad fills the orthographic view; its material multiplies every
 * factor by a constant texture: albedo = (1, 0.5, 0.25) x srgb(188) x (1 -
 * 0.2 x 0/255) (Lambertian: specularFactor 0, and metallic 0.2 times the
 * texture's B = 0; were the texture ignored, the metal part of 0.2 would
 * add a specular lobe), emission = (0.5, 1, 0) x srgb(64). The quad emits, so it
 * is an area light too (one that cannot light itself). Under a uniform
 * environment L_env it reflects albedo x L_env on average: next-event
 * estimation samples the environment or the area light by their power
 * (the light sample adds 0 here), weighted by MIS against the BSDF sample
 * in the path integrator. Without the environment the emission is exact in
 * each sample. Tolerance 1e-5 where exact (the film's fixed point, float
 * sums); 3% for the mean at 64 spp with the environment. */
static void textured_quad_renders_emission_plus_albedo(void **state)
{
    (void)state;
    st_scene *s = load(SCENES "textured_quad.gltf");
    assert_int_equal(s->texture_count, 3);
    const double f[3] = {1.0, 0.5, 0.25}, e[3] = {0.5, 1.0, 0.0};
    const double metal = 1.0 - 0.2 * (0.0 / 255.0);
    for (int env = 0; env < 2; env++)
        for (st_u32 integ = 0; integ < 2; integ++) {
            const float view_env[3] = {(float)env, (float)env, (float)env};
            int mean_only = env;
            st_image img = render_view(s, 12, 8, mean_only ? 64 : 2, integ, view_env,
                                       ST_TEXFILTER_TRILINEAR);
            size_t n = (size_t)img.width * img.height;
            for (int c = 0; c < 3; c++) {
                double want = e[c] * srgb_formula(64) + env * f[c] * srgb_formula(188) * metal;
                double mean = 0.0;
                for (size_t p = 0; p < n; p++) {
                    double v = img.data[4 * p + (size_t)c];
                    mean += v / (double)n;
                    if (!mean_only)
                        near(v, want, 1e-5, "textured quad radiance");
                }
                near(mean, want, mean_only ? 0.03 * want : 1e-5, "textured quad mean");
            }
            st_image_free(&img);
        }
    st_scene_destroy(s);
}

/* Without emitters the environment is sampled by next-event estimation
 * too: a surface open to it reflects albedo x L_env exactly in each sample,
 * in the direct integrator (one cosine-distributed environment sample:
 * f cos / pdf = albedo) and in the path integrator (that sample and the BSDF
 * sample's miss, each weighted 1/2). Camera rays that miss see L_env: the
 * checkerboard's sky rows (above the horizon, beyond the filter's reach). */
static void environment_alone_gives_albedo_and_sky(void **state)
{
    (void)state;
    st_scene *s = load(SCENES "textured_quad.gltf");
    memset(s->materials[0].emission, 0, sizeof s->materials[0].emission);
    s->materials[0].emission_tex = ST_NO_TEXTURE;
    const float env[3] = {0.5f, 1.0f, 2.0f};
    const double f[3] = {1.0, 0.5, 0.25}, metal = 1.0 - 0.2 * (0.0 / 255.0);
    for (st_u32 integ = 0; integ < 2; integ++) {
        st_image img = render_view(s, 12, 8, 2, integ, env, ST_TEXFILTER_TRILINEAR);
        for (size_t p = 0; p < (size_t)img.width * img.height; p++)
            for (int c = 0; c < 3; c++)
                near(img.data[4 * p + (size_t)c], env[c] * f[c] * srgb_formula(188) * metal, 1e-5,
                     "albedo x environment");
        st_image_free(&img);
    }
    st_scene_destroy(s);

    s = load("checkerboard");
    st_image img = render_view(s, 32, 24, 1, ST_INTEGRATOR_PATH, env, ST_TEXFILTER_TRILINEAR);
    for (size_t p = 0; p < 4 * 32; p++) /* rows 0 to 3; the horizon is at row 7.2 */
        for (int c = 0; c < 3; c++)
            near(img.data[4 * p + (size_t)c], env[c], 1e-5, "sky");
    st_image_free(&img);
    st_scene_destroy(s);
}

/* cutout: the front quad (red, MASK) is cut away on its left half, where
 * the green back quad shows; its right half is red (green channel exactly
 * 0: nothing green reaches it, the back quad lying behind it). */
static void mask_cutout_shows_the_quad_behind(void **state)
{
    (void)state;
    st_scene *s = load(SCENES "cutout.gltf");
    assert_int_equal(s->materials[0].alpha_mode, ST_ALPHA_MASK);
    st_image img = render(s, 16, 8, 4, ST_INTEGRATOR_PATH);
    for (st_u32 y = 0; y < img.height; y++)
        for (st_u32 x = 0; x < img.width; x++) {
            const float *px = img.data + 4 * ((size_t)y * img.width + x);
            if (x < 6) /* left of the cut, away from the filter's reach */
                assert_true(px[1] > 0.1f && px[1] > 4.0f * px[0]);
            else if (x >= 10)
                assert_true(px[0] > 0.1f && px[1] == 0.0f);
        }
    st_image_free(&img);
    st_scene_destroy(s);
}

/* The checkerboard at 1 sample per pixel against a 256-spp reference
 * rendered with no texture filtering (point samples of the texture itself,
 * averaged by many samples: the antialiased image): trilinear filtering
 * must be closer (RMSE) than nearest or bilinear lookups, which alias
 * towards the horizon. Measured at 128 x 96 (direct integrator, exact for
 * a plane under the environment): none 0.130, bilinear 0.132, trilinear
 * 0.087 against 1024 spp; the reference at 256 spp is within 0.0025 of
 * that. Required: trilinear < 0.8 x the better of the other two. */
static void trilinear_beats_none_and_bilinear_on_checkerboard(void **state)
{
    (void)state;
    st_scene *s = load("checkerboard");
    const st_u32 w = 128, h = 96;
    st_image ref = render_view(s, w, h, 256, ST_INTEGRATOR_DIRECT, NULL, ST_TEXFILTER_NONE);
    double rmse[3];
    for (st_u32 f = 0; f < 3; f++) {
        st_image img = render_view(s, w, h, 1, ST_INTEGRATOR_DIRECT, NULL, f);
        st_diff_result d;
        st_error err = {0};
        if (st_diff_images(&img, &ref, &d, &err) != ST_OK)
            fail_msg("diff: %s", err.msg);
        rmse[f] = d.rmse;
        st_image_free(&img);
    }
    print_message("checkerboard 1 spp RMSE: none %.4f, bilinear %.4f, trilinear %.4f\n", rmse[0],
                  rmse[1], rmse[2]);
    double other = rmse[0] < rmse[1] ? rmse[0] : rmse[1];
    if (!(rmse[2] < 0.8 * other))
        fail_msg("trilinear RMSE %.4f is not below 0.8 x %.4f", rmse[2], other);
    st_image_free(&ref);
    st_scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest host[] = {
        cmocka_unit_test(srgb_table_equals_iec_formula),
        cmocka_unit_test(wrap_modes_match_opengl_definitions),
        cmocka_unit_test(tex_floor_is_floor),
        cmocka_unit_test(lookups_at_texel_centres_return_texels),
        cmocka_unit_test(bilinear_weights_between_centres),
        cmocka_unit_test(wrap_modes_in_lookups),
        cmocka_unit_test(trilinear_blends_levels_by_lod),
        cmocka_unit_test(transform_applies_before_lookup),
        cmocka_unit_test(ray_cone_lod_is_zero_when_a_texel_spans_the_cone),
        cmocka_unit_test(mip_chain_sizes_follow_halving_rule),
        cmocka_unit_test(mip_of_constant_image_is_constant),
        cmocka_unit_test(mip_filter_is_1331_on_a_delta),
        cmocka_unit_test(mip_averages_in_linear_light_and_keeps_the_mean),
    };
    const struct CMUnitTest device[] = {
        cmocka_unit_test(textured_quad_renders_emission_plus_albedo),
        cmocka_unit_test(environment_alone_gives_albedo_and_sky),
        cmocka_unit_test(mask_cutout_shows_the_quad_behind),
        cmocka_unit_test(trilinear_beats_none_and_bilinear_on_checkerboard),
    };
    int failed = cmocka_run_group_tests_name("texture", host, NULL, NULL);
    return failed + cmocka_run_group_tests_name("texture_render", device, device_setup, device_teardown);
}
