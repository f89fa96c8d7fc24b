/* test_leaf.c — the kernels test a leaf's triangles together (trace.h:
 * st_leaf_closest, st_leaf_any on a leaf block, one float4
 * Moller-Trumbore): on the device, through kernels/geom/leaf_probe.cl, their hits
 * are the scalar loop's (st_intersect_triangle over the leaf's triangles in
 * order) field by field, bit for bit, for every ray against every leaf of a
 * mesh made to tie: a height field whose triangles share edges and vertices,
 * exact copies of some triangles (two lanes hit at the same t: the lower
 * index must win, as the loop's strict t < best keeps it), copies lifted a
 * little (two lanes hit at different t), groups far off of four triangles
 * and one apart (leaves of one: the mesh has leaf blocks of every size, 1..4
 * triangles), one-sided triangles seen from both sides, rays through
 * vertices and edges, along an axis, and cut short by tmax. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "st_bvh.h"
#include "trace.h"
#include "device_fixture.h"

#define GRID 12                    /* cells per side of the height field */
#define BASE (2 * GRID * GRID)     /* its triangles */
#define COPIES (BASE / 5)          /* exact copies of triangles 5 c */
#define LIFTED (BASE / 7)          /* copies of triangles 7 c lifted by 2e-3 */
#define LONE 10                    /* two groups far off: four together, one apart */
#define TRIS (BASE + COPIES + LIFTED + LONE)
#define RAYS 3000

static float frand(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (float)((*s >> 40) * (1.0 / 16777216.0));
}

/* Grid point (i, j) of the height field: shared by up to six triangles. */
static void grid_point(int i, int j, float *p)
{
    float x = (float)i / GRID, y = (float)j / GRID;
    p[0] = x;
    p[1] = y;
    p[2] = 0.1f * sinf(3.0f * x) * cosf(2.0f * y);
}

/* The mesh (9 floats per triangle); base[t]: the triangle t copies (t for
 * the height field's own), so that a copy gets its original's side. */
static float *make_mesh(uint32_t *base)
{
    float *pos = malloc(sizeof(float) * 9 * TRIS);
    assert_non_null(pos);
    uint32_t t = 0;
    for (int i = 0; i < GRID; i++)
        for (int j = 0; j < GRID; j++) {
            int corner[2][3][2] = {{{i, j}, {i + 1, j}, {i + 1, j + 1}},
                                   {{i, j}, {i + 1, j + 1}, {i, j + 1}}};
            for (int h = 0; h < 2; h++, t++) {
                for (int v = 0; v < 3; v++)
                    grid_point(corner[h][v][0], corner[h][v][1], pos + 9 * t + 3 * v);
                base[t] = t;
            }
        }
    for (uint32_t c = 0; c < COPIES; c++, t++) {
        memcpy(pos + 9 * t, pos + 9 * (5 * c), sizeof(float) * 9);
        base[t] = 5 * c;
    }
    for (uint32_t c = 0; c < LIFTED; c++, t++) {
        memcpy(pos + 9 * t, pos + 9 * (7 * c), sizeof(float) * 9);
        for (int v = 0; v < 3; v++)
            pos[9 * t + 3 * v + 2] += 2e-3f;
        base[t] = t;
    }
    for (uint32_t c = 0; c < LONE; c++, t++) { /* groups of five: four together, one apart */
        memcpy(pos + 9 * t, pos + 9 * (c % 5), sizeof(float) * 9);
        for (int v = 0; v < 3; v++)
            pos[9 * t + 3 * v] += 100.0f * (float)(2 * (c / 5) + 1) + (c % 5 == 4 ? 50.0f : 0.0f);
        base[t] = t;
    }
    return pos;
}

/* Ray r aimed at a point of input triangle r % TRIS: a vertex (r % 6 == 0,
 * straight down the z axis; 1: from a random side), an edge's midpoint (2),
 * a random point of an edge (3) or inside (4, 5); tmax infinite, the
 * distance to that point (about the hit's t) or half of it. */
static st_ray aim(const float *pos, uint32_t r, uint64_t *seed)
{
    const float *v = pos + 9 * (r % TRIS);
    float b1 = frand(seed), b2 = frand(seed) * (1.0f - b1);
    float bary[6][2] = {{0, 0}, {1, 0}, {0.5f, 0.5f}, {b1, 1.0f - b1}, {b1, b2}, {b2, b1}};
    float p[3], o[3], d[3], len = 0.0f;
    st_ray w = {{0}, INFINITY, {0}, 0.0f};
    float dist = 0.2f + 1.8f * frand(seed);
    for (int a = 0; a < 3; a++) {
        float e1 = v[3 + a] - v[a], e2 = v[6 + a] - v[a];
        p[a] = v[a] + bary[r % 6][0] * e1 + bary[r % 6][1] * e2;
        o[a] = r % 6 == 0 ? p[a] + (a == 2 ? dist : 0.0f) : p[a] + dist * (frand(seed) - 0.5f);
        d[a] = p[a] - o[a];
        len += d[a] * d[a];
    }
    len = sqrtf(len);
    for (int a = 0; a < 3; a++) {
        w.o[a] = o[a];
        w.d[a] = r % 6 == 0 ? (a == 2 ? -1.0f : 0.0f) : d[a] / len;
    }
    w.tmax = r % 3 == 0 ? INFINITY : r % 3 == 1 ? len : 0.5f * len;
    return w;
}

/* The leaf slots of the wide tree (the node's unit * ST_BVH_WIDTH + k, the
 * nodes walked as st_bvh_wide_span says); leaf_of[t]: the slot holding BVH
 * triangle t; sizes[c]: the leaves of c triangles. */
static uint32_t leaf_slots(const st_bvh *bvh, uint32_t *slot, uint32_t *leaf_of, uint32_t *sizes)
{
    uint32_t n = 0, unit = 0;
    for (uint32_t w = 0; w < bvh->wide_count; w++) {
        const st_bvh_wide_node *node = st_trace_node(bvh->wide, unit);
        for (uint32_t k = 0; k < ST_BVH_WIDTH; k++) {
            uint32_t c = node->count[k];
            if (c == 0)
                continue;
            const float *l = st_trace_leaf(bvh->wide, node->child[k]);
            for (uint32_t j = 0; j < c; j++)
                leaf_of[st_leaf_first(l, c) + j] = n;
            sizes[c]++;
            slot[n++] = unit * ST_BVH_WIDTH + k;
        }
        unit += st_bvh_wide_span(node);
    }
    return n;
}

/* Runs leaf_probe.cl: 4 hits per (ray, slot) pair. */
static st_hit *probe(const st_bvh *bvh, const st_ray *rays, const uint32_t *slot,
                     uint32_t slots)
{
    st_error err = {0};
    size_t pairs = (size_t)RAYS * slots;
    st_hit *out = malloc(4 * pairs * sizeof *out);
    assert_non_null(out);
    cl_kernel k;
    cl_mem b[5];
    cl_uint n = RAYS, ns = slots;
    assert_int_equal(st_device_kernel(dev, "probe_leaf", &k, &err), ST_OK);
    assert_int_equal(st_device_buffer_create(dev, (bvh->wide_count + bvh->leaf_slots) * sizeof(st_bvh_wide_node), bvh->wide, &b[0], &err), ST_OK);
    assert_int_equal(st_device_buffer_create(dev, bvh->tri_count * sizeof(st_triangle), bvh->tris, &b[1], &err), ST_OK);
    assert_int_equal(st_device_buffer_create(dev, RAYS * sizeof *rays, rays, &b[2], &err), ST_OK);
    assert_int_equal(st_device_buffer_create(dev, slots * sizeof *slot, slot, &b[3], &err), ST_OK);
    assert_int_equal(st_device_buffer_create(dev, 4 * pairs * sizeof *out, NULL, &b[4], &err), ST_OK);
    assert_int_equal(st_device_set_args(k, &err, 7, sizeof(cl_mem), (const void *)&b[0],
                                        sizeof(cl_mem), (const void *)&b[1], sizeof(cl_mem),
                                        (const void *)&b[2], sizeof(cl_mem), (const void *)&b[3],
                                        sizeof ns, (const void *)&ns, sizeof n, (const void *)&n,
                                        sizeof(cl_mem), (const void *)&b[4]),
                     ST_OK);
    assert_int_equal(st_device_launch(dev, k, pairs, 0, &err), ST_OK);
    assert_int_equal(st_device_buffer_read(dev, b[4], 4 * pairs * sizeof *out, out, &err), ST_OK);
    for (int i = 0; i < 5; i++)
        st_device_buffer_destroy(dev, b[i]);
    return out;
}

static void fail_pair(const char *what, uint32_t r, uint32_t s, const st_hit *vec, const st_hit *sca)
{
    fail_msg("%s, ray %u leaf slot %u: vector prim %u t %a u %a v %a, scalar prim %u t %a u %a v %a",
             what, r, s, vec->prim, vec->t, vec->u, vec->v, sca->prim, sca->t, sca->u, sca->v);
}

static void leaf_test_equals_scalar_loop(void **state)
{
    (void)state;
    uint32_t *base = malloc(TRIS * sizeof *base), *slot = malloc(TRIS * sizeof *slot);
    uint32_t *leaf_of = malloc(TRIS * sizeof *leaf_of), *twin = malloc(TRIS * sizeof *twin);
    st_ray *rays = malloc(RAYS * sizeof *rays);
    assert_true(base && slot && leaf_of && twin && rays);
    float *pos = make_mesh(base);
    st_bvh *bvh = NULL;
    st_error err = {0};
    assert_int_equal(st_bvh_build(pos, TRIS, &bvh, &err), ST_OK);
    for (uint32_t i = 0; i < TRIS; i++) /* a third one-sided, a copy as its original */
        bvh->tris[i].v0[3] = base[bvh->order[i]] % 3 == 0 ? ST_TRI_ONE_SIDED : 0.0f;
    st_bvh_pack_leaves(bvh);
    uint32_t sizes[5] = {0};
    uint32_t slots = leaf_slots(bvh, slot, leaf_of, sizes);
    printf("# leaves of 1, 2, 3, 4 triangles: %u, %u, %u, %u\n", sizes[1], sizes[2], sizes[3],
           sizes[4]);
    for (int c = 1; c <= 4; c++)
        assert_true(sizes[c] > 0);
    /* twin[t]: the other BVH triangle of an exact copy, when in t's leaf */
    for (uint32_t i = 0; i < TRIS; i++)
        twin[i] = ST_NO_HIT;
    for (uint32_t i = 0; i < TRIS; i++)
        for (uint32_t j = 0; j < TRIS; j++)
            if (i != j && base[bvh->order[i]] == base[bvh->order[j]] && leaf_of[i] == leaf_of[j])
                twin[i] = j;
    uint64_t seed = 15;
    for (uint32_t r = 0; r < RAYS; r++)
        rays[r] = aim(pos, r, &seed);
    st_hit *out = probe(bvh, rays, slot, slots);
    size_t hits = 0, any = 0, ties = 0;
    for (uint32_t r = 0; r < RAYS; r++)
        for (uint32_t s = 0; s < slots; s++) {
            const st_hit *h = out + 4 * ((size_t)r * slots + s);
            if (memcmp(&h[0], &h[1], sizeof *h))
                fail_pair("closest", r, s, &h[0], &h[1]);
            if (memcmp(&h[2], &h[3], sizeof *h))
                fail_pair("any", r, s, &h[2], &h[3]);
            hits += h[1].prim != ST_NO_HIT;
            any += h[3].prim != ST_NO_HIT;
            /* an exact copy in the same leaf is hit at the same t: the lower index wins */
            if (h[1].prim != ST_NO_HIT && twin[h[1].prim] != ST_NO_HIT) {
                assert_true(h[1].prim < twin[h[1].prim]);
                ties++;
            }
        }
    printf("# %u rays x %u leaves: %zu closest hits, %zu any hits, %zu ties between copies\n",
           RAYS, slots, hits, any, ties);
    assert_true(hits > RAYS / 2 && any == hits && ties > 50);
    free(out);
    st_bvh_destroy(bvh);
    free(pos);
    free(base);
    free(slot);
    free(leaf_of);
    free(twin);
    free(rays);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(leaf_test_equals_scalar_loop),
    };
    return cmocka_run_group_tests(tests, device_setup, device_teardown);
}
