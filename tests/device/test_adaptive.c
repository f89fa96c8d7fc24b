/* test_adaptive.c — adaptive sampling (src/render/adaptive.c, kernels/film/adaptive.cl)
 * on the device: the budget is kept, the counts follow the error estimate
 * (exactly, on scenes whose estimate is known), the density-weighted splat
 * reconstructs the same image as a uniform render where the density
 * varies, adaptive beats uniform splatting at equal cost (the random
 * sampler; Sobol' and Halton, whose pixels take 2^k prefixes; the others
 * render uniformly, test_adaptive_cli.sh), a QMC sampler goes on uniformly
 * where its pilot predicts no gain, the same command gives the same image,
 * and bad options are refused. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "st_image.h"
#include "st_render.h"
#include "st_scene.h"
#include "device_fixture.h"

/* Renders scene `name` with o on device d; st (optional) gets the stats. */
static st_image render_on(st_device *d, const char *name, const st_render_options *o,
                          st_render_stats *st)
{
    st_error err = {0};
    st_scene *scene = NULL;
    st_renderer *r = NULL;
    st_image img = {0};
    st_render_stats local;
    if (st_scene_load(name, &scene, &err) || st_renderer_create(d, scene, &r, &err) ||
        st_render(r, o, &img, NULL, st ? st : &local, NULL, NULL, &err))
        fail_msg("render %s: %s", name, err.msg);
    if (!st)
        free(local.spp_map);
    st_renderer_destroy(r);
    st_scene_destroy(scene);
    return img;
}

/* render_on the fixture's device. */
static st_image render(const char *name, const st_render_options *o, st_render_stats *st)
{
    return render_on(dev, name, o, st);
}

static st_render_options adaptive(st_u32 w, st_u32 h, st_u32 spp, st_u32 pilot)
{
    st_render_options o = st_render_defaults();
    o.width = w;
    o.height = h;
    o.spp = spp;
    o.seed = 7;
    o.adaptive = 1;
    o.min_spp = pilot;
    o.sampler = ST_SAMPLER_RANDOM; /* the one sampler that stays adaptive */
    return o;
}

/* A constant image (the furnace's emission alone) has error estimate 0:
 * without a threshold the budget is spread evenly, every pixel gets spp;
 * with one, every pixel stops one sample after the pilot. Both images are 1
 * (the two films each reconstruct 1 exactly). */
static void adaptive_constant_scene(void **state)
{
    (void)state;
    for (int thr = 0; thr < 2; thr++) {
        st_render_options o = adaptive(16, 12, 16, 4);
        o.max_depth = 0;
        o.noise_threshold = thr ? 0.01f : 0.0f;
        st_render_stats st;
        st_image img = render("furnace", &o, &st);
        st_u32 want = thr ? 5 : 16;
        for (size_t i = 0; i < 16u * 12; i++) {
            assert_int_equal(st.spp_map[i], want);
            for (int c = 0; c < 3; c++)
                assert_float_equal(img.data[4 * i + c], 1.0f, 1e-6f);
        }
        assert_int_equal(st.samples, (st_u64)want * 16 * 12);
        free(st.spp_map);
        st_image_free(&img);
    }
}

/* tests/scenes/edge.gltf at max depth 0 with no environment: radiance 1
 * left of a vertical edge, 0 right of it. With a threshold, the pixels whose 3 x 3 pool sees
 * one value have estimate 0 and stop at pilot + 1: every column 2 or more
 * from the columns the edge crosses. Those (1 or 2) get more in every row;
 * the columns beside them get more where their pool's random pilot samples
 * happened to fall on both sides, and so some rows may stop. */
static void adaptive_edge_gets_more_samples(void **state)
{
    (void)state;
    st_render_options o = adaptive(32, 24, 16, 4);
    o.max_depth = 0;
    o.env_given = 1; /* black behind the quad: its emission 1 is dim, so the default is white */
    o.env[0] = o.env[1] = o.env[2] = 0.0f;
    o.noise_threshold = 0.01f;
    st_render_stats st;
    st_image img = render("tests/scenes/edge.gltf", &o, &st);
    st_u32 lo[32], hi[32], edge_cols = 0, first = 32, last = 0;
    for (st_u32 x = 0; x < 32; x++) {
        lo[x] = 0xffffffffu, hi[x] = 0;
        for (st_u32 y = 0; y < 24; y++) {
            st_u32 n = st.spp_map[y * 32 + x];
            lo[x] = n < lo[x] ? n : lo[x];
            hi[x] = n > hi[x] ? n : hi[x];
        }
        if (lo[x] > 5) { /* a column where every pixel got more: the edge */
            edge_cols++;
            first = x < first ? x : first;
            last = x;
        }
    }
    assert_true(edge_cols >= 1 && edge_cols <= 2 && last - first + 1 == edge_cols);
    for (st_u32 x = 0; x < 32; x++)
        if (x + 1 < first || x > last + 1)
            assert_int_equal(hi[x], 5); /* flat columns stop after the pilot */
    assert_true(st.samples <= 16u * 32 * 24); /* within the budget */
    free(st.spp_map);
    st_image_free(&img);
}

/* Column means over the rows of an image's R channel. */
static void column_means(const st_image *img, double *out)
{
    for (st_u32 x = 0; x < img->width; x++) {
        out[x] = 0;
        for (st_u32 y = 0; y < img->height; y++)
            out[x] += img->data[4 * ((size_t)y * img->width + x)];
        out[x] /= img->height;
    }
}

/* Where the sample density varies, the density-weighted splat still gives
 * the filtered image: on the edge scene (no noise but the pixel positions),
 * Mitchell splatting, the adaptive render gives the edge up to 128 samples (8x the
 * mean), flat pixels 5, and every column's mean over its rows stays within
 * 0.005 of a uniform 256-spp render's (measured: largest difference
 * 0.0012, the flat pixels' few later samples' positions, the image being
 * theirs alone; with the pilot blended in, 0.00017; with the 1 / m weights
 * removed from the splat, 0.020: the flat columns next to the edge pulled
 * toward the dense edge's value). */
static void adaptive_density_weighted_splat(void **state)
{
    (void)state;
    st_render_options o = adaptive(32, 24, 16, 4);
    o.max_depth = 0;
    o.env_given = 1; /* black behind the quad: its emission 1 is dim, so the default is white */
    o.env[0] = o.env[1] = o.env[2] = 0.0f;
    st_render_stats st;
    st_image a = render("tests/scenes/edge.gltf", &o, &st);
    st_u32 lo = 0xffffffffu, hi = 0;
    for (size_t i = 0; i < 32u * 24; i++) {
        lo = st.spp_map[i] < lo ? st.spp_map[i] : lo;
        hi = st.spp_map[i] > hi ? st.spp_map[i] : hi;
    }
    print_message("samples per pixel %u..%u\n", lo, hi);
    assert_true(hi >= 8 * lo); /* the density does vary */
    o.adaptive = 0;
    o.spp = 256;
    st_image u = render("tests/scenes/edge.gltf", &o, NULL);
    double ca[32], cu[32], worst = 0;
    column_means(&a, ca);
    column_means(&u, cu);
    for (int x = 0; x < 32; x++)
        worst = fmax(worst, fabs(ca[x] - cu[x]));
    print_message("largest column-mean difference %.5f\n", worst);
    if (worst > 0.005)
        fail_msg("column means differ by %.5f from the uniform render's", worst);
    free(st.spp_map);
    st_image_free(&a);
    st_image_free(&u);
}

/* RMSE and relative MSE (mean of (x - r)² / (r² + 0.01), as strata converge)
 * of img against ref over every pixel and R, G, B. */
static void errors(const st_image *img, const st_image *ref, double *rmse, double *rel)
{
    double s = 0, q = 0;
    size_t n = (size_t)img->width * img->height;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            double x = img->data[4 * i + c], r = ref->data[4 * i + c];
            s += (x - r) * (x - r);
            q += (x - r) * (x - r) / (r * r + 0.01);
        }
    *rmse = sqrt(s / (3.0 * n));
    *rel = q / (3.0 * n);
}

/* At equal cost (16 spp on average against 16 spp everywhere, both splatted
 * with Mitchell, both the random sampler), adaptive wins on the 48 x 48
 * Cornell box by RMSE and keeps the relative MSE, each the mean over seeds
 * 7..10 against a uniform 1024-spp reference (seed 99). Measured: RMSE
 * 0.0333 against 0.0659, relative MSE 0.00835 against 0.00791 (the pilot,
 * 2 of the 16, is not part of the estimate, and the calm, dark pixels that
 * weigh most in the relative MSE get few later samples). Tolerances: RMSE
 * below 0.7x uniform's, relative MSE below 1.1x uniform's. */
static void adaptive_beats_uniform_at_equal_cost(void **state)
{
    (void)state;
    st_render_options o = adaptive(48, 48, 1024, 0);
    o.adaptive = 0;
    o.seed = 99;
    st_image ref = render("cornell-box", &o, NULL);
    double rmse[2] = {0, 0}, rel[2] = {0, 0};
    for (int adapt = 0; adapt < 2; adapt++)
        for (st_u32 seed = 7; seed < 11; seed++) {
            st_render_options t = adaptive(48, 48, 16, 0);
            t.adaptive = adapt;
            t.seed = seed;
            st_render_stats st;
            st_image img = render("cornell-box", &t, &st);
            assert_true(st.samples <= 16u * 48 * 48); /* no more than uniform's cost */
            double e, q;
            errors(&img, &ref, &e, &q);
            rmse[adapt] += e / 4;
            rel[adapt] += q / 4;
            free(st.spp_map);
            st_image_free(&img);
        }
    print_message("RMSE adaptive %.4f uniform %.4f; relative MSE adaptive %.5f uniform %.5f\n",
                  rmse[1], rmse[0], rel[1], rel[0]);
    assert_true(rmse[1] < 0.7 * rmse[0]);
    assert_true(rel[1] < 1.1 * rel[0]);
    st_image_free(&ref);
}

static void assert_same_image(const st_image *a, const st_image *b);

/* A QMC sampler at equal cost: Sobol' and Halton on the 48 x 48 Cornell box,
 * 16 spp, seeds 7..10, against the same 1024-spp reference as above. The
 * counts are powers of two, not all equal, at most the budget; the RMSE is
 * below 0.7x uniform's (measured: Sobol' 0.0149 against 0.0250, Halton
 * 0.0173 against 0.0346). */
static void adaptive_qmc_beats_uniform_at_equal_cost(void **state)
{
    (void)state;
    static const st_u32 samplers[2] = {ST_SAMPLER_SOBOL, ST_SAMPLER_HALTON};
    st_render_options o = adaptive(48, 48, 1024, 0);
    o.adaptive = 0;
    o.seed = 99;
    st_image ref = render("cornell-box", &o, NULL);
    for (int k = 0; k < 2; k++) {
        double rmse[2] = {0, 0};
        for (int adapt = 0; adapt < 2; adapt++)
            for (st_u32 seed = 7; seed < 11; seed++) {
                st_render_options t = adaptive(48, 48, 16, 0);
                t.adaptive = adapt;
                t.seed = seed;
                t.sampler = samplers[k];
                st_render_stats st;
                st_image img = render("cornell-box", &t, &st);
                assert_true(st.samples <= 16u * 48 * 48);
                int unequal = 0;
                for (size_t i = 0; adapt && i < 48u * 48; i++) {
                    assert_int_equal(st.spp_map[i] & (st.spp_map[i] - 1), 0);
                    unequal |= st.spp_map[i] != st.spp_map[0];
                }
                assert_int_equal(unequal, adapt);
                assert_int_equal(st.adaptive_uniform, 0);
                double e, q;
                errors(&img, &ref, &e, &q);
                rmse[adapt] += e / 4;
                free(st.spp_map);
                st_image_free(&img);
            }
        print_message("%s: RMSE adaptive %.4f uniform %.4f\n", st_sampler_names[samplers[k]],
                      rmse[1], rmse[0]);
        assert_true(rmse[1] < 0.7 * rmse[0]);
    }
    st_image_free(&ref);
}

/* Where the pilot predicts no gain, a QMC sampler's adaptive render is the
 * uniform one: the furnace (every pixel equally noisy: its bounces), Sobol'
 * and Halton, 40 x 30, 16 spp: the same image bit for bit, spp everywhere
 * in the map, the uniform render's samples, and the stats say so. */
static void adaptive_qmc_uniform_where_no_gain(void **state)
{
    (void)state;
    static const st_u32 samplers[2] = {ST_SAMPLER_SOBOL, ST_SAMPLER_HALTON};
    for (int k = 0; k < 2; k++) {
        st_render_options o = adaptive(40, 30, 16, 0);
        o.sampler = samplers[k];
        st_render_stats st;
        st_image a = render("furnace", &o, &st);
        o.adaptive = 0;
        st_image u = render("furnace", &o, NULL);
        assert_int_equal(st.adaptive_uniform, 1);
        assert_int_equal(st.samples, 16u * 40 * 30);
        for (size_t i = 0; i < 40u * 30; i++)
            assert_int_equal(st.spp_map[i], 16);
        assert_same_image(&a, &u);
        free(st.spp_map);
        st_image_free(&a);
        st_image_free(&u);
    }
}

/* A QMC sampler with a noise threshold always adapts (the threshold asks
 * for fewer samples where it is reached): on the furnace, whose pilot
 * alone predicts no gain, Sobol' at 16 spp with threshold 0.2 takes fewer
 * samples than uniform, in powers of two; with a threshold so large that
 * every pixel reaches it at once, one sample a pixel (and the pilot's 2,
 * counted too). */
static void adaptive_qmc_noise_threshold(void **state)
{
    (void)state;
    st_render_options o = adaptive(40, 30, 16, 0);
    o.sampler = ST_SAMPLER_SOBOL;
    o.noise_threshold = 1e6f;
    st_render_stats st;
    st_image img = render("furnace", &o, &st);
    assert_int_equal(st.adaptive_uniform, 0);
    assert_int_equal(st.samples, (2u + 1u) * 40 * 30);
    for (size_t i = 0; i < 40u * 30; i++)
        assert_int_equal(st.spp_map[i], 1);
    free(st.spp_map);
    st_image_free(&img);
    o.noise_threshold = 0.2f;
    img = render("furnace", &o, &st);
    assert_int_equal(st.adaptive_uniform, 0);
    assert_true(st.samples < 16u * 40 * 30);
    for (size_t i = 0; i < 40u * 30; i++)
        assert_int_equal(st.spp_map[i] & (st.spp_map[i] - 1), 0);
    free(st.spp_map);
    st_image_free(&img);
}

/* Column x's mean signed error over its rows and R, G, B. */
static double column_error(const st_image *img, const st_image *ref, st_u32 x)
{
    double d = 0;
    for (st_u32 y = 0; y < img->height; y++)
        for (int c = 0; c < 3; c++) {
            size_t i = 4 * ((size_t)y * img->width + x) + (size_t)c;
            d += img->data[i] - ref->data[i];
        }
    return d / (3.0 * img->height);
}

/* Unbiased at the cap and beside it: the zone plate, 80 x 60 (landscape),
 * 16 spp on average, Mitchell, random sampler, cap 8 x 16 = 128. Its
 * columns 9, 10, 69 and 70 are at the cap in every row for every seed,
 * their neighbours 8, 11, 68 and 71 at most a few samples each. Over seeds
 * 1..16, each of those columns' mean signed error (per seed over its rows,
 * then the mean and its standard error over the seeds) against a uniform
 * 4096-spp Sobol' render (its own error far below these). Tolerance:
 * within 3 standard errors of 0, for the adaptive render and for the
 * uniform one at the same seeds. Measured: with the later samples' film
 * resolved as the ratio Σ f L / m over Σ f / m, columns 9 and 70 -9.6e-4
 * and -1.2e-3 (3.3 and 3.0 standard errors), 68 -1.4e-4 (3.3); with the
 * difference estimator (adaptive.cl, later_value) all within 2.7; with the
 * image the later samples' alone, all within 1.7. */
static void adaptive_unbiased_at_the_cap(void **state)
{
    (void)state;
    static const st_u32 cols[8] = {8, 9, 10, 11, 68, 69, 70, 71};
    st_render_options o = adaptive(80, 60, 4096, 0);
    o.env_given = 1; /* a uniform white environment, not the default sky: the columns */
    o.env[0] = o.env[1] = o.env[2] = 1.0f; /* below are placed for the contrast it gives */
    o.adaptive = 0;
    o.sampler = ST_SAMPLER_SOBOL;
    o.filter = st_filter_default(ST_FILTER_MITCHELL);
    st_image ref = render("zone-plate", &o, NULL);
    double sum[2][8] = {{0}}, sum2[2][8] = {{0}};
    for (st_u32 seed = 1; seed <= 16; seed++)
        for (int adapt = 0; adapt < 2; adapt++) {
            st_render_options t = adaptive(80, 60, 16, 0);
            t.env_given = 1;
            memcpy(t.env, o.env, sizeof t.env);
            t.filter = o.filter;
            t.seed = seed;
            t.adaptive = adapt;
            st_render_stats st;
            st_image img = render("zone-plate", &t, &st);
            for (int k = 0; k < 8; k++) {
                st_u32 capped = 0;
                for (st_u32 y = 0; adapt && y < 60; y++)
                    capped += st.spp_map[y * 80 + cols[k]] == 128;
                if (adapt) /* the columns are where the comment says */
                    assert_int_equal(capped, k % 4 == 1 || k % 4 == 2 ? 60 : 0);
                double e = column_error(&img, &ref, cols[k]);
                sum[adapt][k] += e;
                sum2[adapt][k] += e * e;
            }
            free(st.spp_map);
            st_image_free(&img);
        }
    for (int adapt = 0; adapt < 2; adapt++)
        for (int k = 0; k < 8; k++) {
            double mean = sum[adapt][k] / 16,
                   se = sqrt((sum2[adapt][k] / 16 - mean * mean) / 15);
            print_message("%s column %u: mean signed error %.2g, standard error %.2g (%.1f)\n",
                          adapt ? "adaptive" : "uniform", cols[k], mean, se, mean / se);
            assert_true(fabs(mean) < 3 * se);
        }
    st_image_free(&ref);
}

/* The image mean of img over the pixels of mask. */
static double masked_mean(const st_image *img, const unsigned char *mask)
{
    double s = 0;
    size_t n = 0, px = (size_t)img->width * img->height;
    for (size_t i = 0; i < px; i++)
        for (int c = 0; mask[i] && c < 3; c++, n++)
            s += img->data[4 * i + c];
    return s / (double)n;
}

/* Unbiased: the Cornell box, 32 x 32, 16 spp, random sampler, Mitchell,
 * over seeds 1..SEEDS, against a uniform 4096-spp Halton reference (seed
 * 0), the image mean over the pixels away from the light (whose 5 x 5
 * neighbourhood in the reference has no value above 1: the light's own
 * values and its edge dominate the noise). Per seed d_s = mean(render_s) -
 * mean(ref); the tolerance is 3 standard errors of their mean, with the
 * reference's own error added in quadrature, bounded by a random
 * sampler's: a uniform 16-spp render's image-mean variance (measured over
 * the same seeds) times 16 / 4096. Measured: adaptive -3.3e-5 ± 5.4e-5
 * (0.6 standard errors), uniform -7.1e-5 ± 5.0e-5 (1.4); with the pilot
 * kept in the estimate at a weight chosen from the pilot itself (Kirk and
 * Arvo 1991) adaptive was -3.7e-4 ± 5.1e-5 (7.3). */
static void unbiased_over_seeds(st_u32 sampler)
{
    enum { W = 32, H = 32, SEEDS = 96 };
    st_scene *scene = fixture_scene("cornell-box");
    st_renderer *r = NULL;
    st_error err = {0};
    if (st_renderer_create(dev, scene, &r, &err))
        fail_msg("renderer: %s", err.msg);
    st_render_options o = adaptive(W, H, 4096, 0);
    o.adaptive = 0;
    o.seed = 0;
    o.sampler = ST_SAMPLER_HALTON;
    st_image ref = {0};
    if (st_render(r, &o, &ref, NULL, NULL, NULL, NULL, &err))
        fail_msg("render: %s", err.msg);
    unsigned char mask[W * H];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            float most = 0;
            for (int v = y - 2; v <= y + 2; v++)
                for (int u = x - 2; u <= x + 2; u++)
                    for (int c = 0; c < 3 && u >= 0 && u < W && v >= 0 && v < H; c++)
                        most = fmaxf(most, ref.data[4 * (v * W + u) + c]);
            mask[y * W + x] = most <= 1.0f;
        }
    double m_ref = masked_mean(&ref, mask), sum[2] = {0}, sum2[2] = {0};
    for (st_u32 seed = 1; seed <= SEEDS; seed++)
        for (int adapt = 0; adapt < 2; adapt++) {
            st_render_options t = adaptive(W, H, 16, 0);
            t.seed = seed;
            t.adaptive = adapt;
            t.sampler = sampler;
            st_render_stats st;
            st_image img = {0};
            if (st_render(r, &t, &img, NULL, &st, NULL, NULL, &err))
                fail_msg("render: %s", err.msg);
            double d = masked_mean(&img, mask) - m_ref;
            sum[adapt] += d;
            sum2[adapt] += d * d;
            free(st.spp_map);
            st_image_free(&img);
        }
    double var_u = (sum2[0] - sum[0] * sum[0] / SEEDS) / (SEEDS - 1);
    double se_ref2 = var_u * 16.0 / 4096.0;
    for (int adapt = 0; adapt < 2; adapt++) {
        double mean = sum[adapt] / SEEDS,
               var = (sum2[adapt] - sum[adapt] * sum[adapt] / SEEDS) / (SEEDS - 1),
               se = sqrt(var / SEEDS + se_ref2);
        print_message("%s, %s: mean error %.3g, standard error %.3g (%.1f)\n",
                      st_sampler_names[sampler], adapt ? "adaptive" : "uniform", mean, se,
                      mean / se);
        assert_true(fabs(mean) < 3 * se);
    }
    st_image_free(&ref);
    st_renderer_destroy(r);
    st_scene_destroy(scene);
}

static void adaptive_unbiased_over_seeds(void **state)
{
    (void)state;
    unbiased_over_seeds(ST_SAMPLER_RANDOM);
}

/* The same with Sobol' (a QMC sampler's adaptive path: each pixel's mean of
 * a 2^k prefix, k chosen from the pilot, samples 0 .. pilot - 1 of the
 * same prefix). Measured: adaptive -2.9e-5 ± 4.4e-5 (0.7 standard errors),
 * uniform Sobol' 4.0e-6 ± 3.6e-5 (0.1). */
static void adaptive_qmc_unbiased_over_seeds(void **state)
{
    (void)state;
    unbiased_over_seeds(ST_SAMPLER_SOBOL);
}

static void assert_same_image(const st_image *a, const st_image *b)
{
    assert_int_equal(a->width, b->width);
    assert_int_equal(a->height, b->height);
    assert_memory_equal(a->data, b->data,
                        sizeof(float) * a->width * a->height * a->channels);
}

/* Same command, same image and spp map, bit for bit, with splatting and
 * with filter importance sampling; the budget is spent to within the
 * rounding of the counts (at least 95 %). */
static void adaptive_deterministic(void **state)
{
    (void)state;
    for (st_u32 recon = ST_RECON_SPLAT; recon <= ST_RECON_FIS; recon++)
        for (int qmc = 0; qmc < 2; qmc++) {
            st_render_options o = adaptive(32, 32, 32, 0);
            o.reconstruction = recon;
            o.sampler = qmc ? ST_SAMPLER_SOBOL : ST_SAMPLER_RANDOM;
            st_render_stats s1, s2;
            st_image a = render("cornell-box", &o, &s1), b = render("cornell-box", &o, &s2);
            assert_same_image(&a, &b);
            assert_memory_equal(s1.spp_map, s2.spp_map, sizeof(st_u32) * 32 * 32);
            assert_true(s1.samples <= 32u * 32 * 32 && s1.samples >= 0.95 * 32 * 32 * 32);
            free(s1.spp_map);
            free(s2.spp_map);
            st_image_free(&a);
            st_image_free(&b);
        }
}

/* The adaptive kernels take ST_W pixels a work-item: at lane widths 1, 4,
 * 8 and 16 the same command gives the same counts (the estimates, and so
 * the allocation) and the same image (the blend) bit for bit, with
 * splatting and with filter importance sampling, random and Sobol', over
 * an image of 851 pixels, which fills no last lane. */
static void adaptive_at_every_width(void **state)
{
    (void)state;
    static const unsigned widths[] = {1, 4, 8, 16};
    enum { W = 37, H = 23 };
    for (st_u32 run = 0; run < 4; run++) {
        st_render_options o = adaptive(W, H, 12, 0);
        o.reconstruction = run & 1 ? ST_RECON_FIS : ST_RECON_SPLAT;
        o.sampler = run & 2 ? ST_SAMPLER_SOBOL : ST_SAMPLER_RANDOM;
        o.filter = st_filter_default(ST_FILTER_MITCHELL);
        st_image first = {0};
        st_u32 *first_map = NULL;
        for (size_t k = 0; k < sizeof widths / sizeof widths[0]; k++) {
            st_device *d = fixture_device_at(widths[k]);
            st_render_stats st;
            st_image img = render_on(d, "cornell-box", &o, &st);
            st_device_destroy(d);
            if (k == 0) {
                first = img;
                first_map = st.spp_map;
                continue;
            }
            assert_same_image(&first, &img);
            assert_memory_equal(first_map, st.spp_map, sizeof(st_u32) * W * H);
            st_image_free(&img);
            free(st.spp_map);
        }
        st_image_free(&first);
        free(first_map);
    }
}

/* The pilot must leave room for one more sample, the cap must reach the
 * mean, a threshold must not be negative; the defaults pass. */
static void adaptive_options_checked(void **state)
{
    (void)state;
    st_error err = {0};
    st_render_options o = adaptive(8, 8, 16, 16);
    assert_int_equal(st_render_check(&o, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "min spp 16"));
    o.min_spp = 0;
    o.max_spp = 15;
    err = (st_error){0}; /* st_fail keeps the first message */
    assert_int_equal(st_render_check(&o, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "max spp 15"));
    o.max_spp = 0;
    o.noise_threshold = -1.0f;
    err = (st_error){0};
    assert_int_equal(st_render_check(&o, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "noise threshold -1"));
    o.noise_threshold = 0.0f;
    err = (st_error){0};
    assert_int_equal(st_render_check(&o, &err), ST_OK);
    st_u32 pilot, max_spp;
    st_render_adaptive_counts(&o, &pilot, &max_spp);
    assert_int_equal(pilot, 2);
    assert_int_equal(max_spp, 128);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(adaptive_options_checked),
        cmocka_unit_test(adaptive_constant_scene),
        cmocka_unit_test(adaptive_edge_gets_more_samples),
        cmocka_unit_test(adaptive_density_weighted_splat),
        cmocka_unit_test(adaptive_deterministic),
        cmocka_unit_test(adaptive_at_every_width),
        cmocka_unit_test(adaptive_beats_uniform_at_equal_cost),
        cmocka_unit_test(adaptive_unbiased_at_the_cap),
        cmocka_unit_test(adaptive_unbiased_over_seeds),
        cmocka_unit_test(adaptive_qmc_beats_uniform_at_equal_cost),
        cmocka_unit_test(adaptive_qmc_uniform_where_no_gain),
        cmocka_unit_test(adaptive_qmc_noise_threshold),
        cmocka_unit_test(adaptive_qmc_unbiased_over_seeds),
    };
    return cmocka_run_group_tests(tests, device_setup, device_teardown);
}
