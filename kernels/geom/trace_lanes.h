/* trace_lanes.h — the slab test and the Moller-Trumbore test, written once
 * over ST_N lanes (lanes.h); trace.h includes it once per width it needs,
 * with ST_N defined, and gets st_slab_test<N> and st_triangle_test<N>:
 *   1: the single triangle (st_intersect_triangle: the brute-force
 *      reference's test, and the last vertex's look at the lights);
 *   ST_BVH_WIDTH: one ray against a wide node's boxes;
 *   ST_LEAF_MAX: one ray against a leaf's triangles;
 *   ST_W: ST_W rays (a packet) against one triangle (kernels only).
 * The host compiles the same widths but ST_W's (lanes.h's host vectors).
 * A lane of any width computes what width 1 computes, with the same
 * operations in the same statements (OpenCL contracts a * b + c into fma
 * within a statement, so the statements must match too): a value that is
 * the same in every lane (the one ray, or the one triangle) is broadcast,
 * which changes no lane's arithmetic. No include guard: one copy per ST_N. */
#ifndef ST_N
#error "define ST_N (the lane count) before including trace_lanes.h"
#endif

#define ST_F ST_VEC(float, ST_N)
#define ST_I ST_VEC(int, ST_N)
#define ST_V3 ST_CAT(st_v3x, ST_N)

/* Slab test (Kay & Kajiya, "Ray Tracing Complex Scenes", SIGGRAPH 1986) in
 * Williams et al.'s form ("An Efficient and Robust Ray-Box Intersection
 * Algorithm", JGT 2005) of ST_N boxes by their near and far planes on each
 * axis (the ray's direction signs chose which plane is near, so no per-axis
 * swap is needed, and a box with inverted bounds is never entered). The
 * running max and min take t only when t > acc (t < acc): a NaN t, which
 * comes only from a zero direction component on a ray starting exactly in
 * that slab's plane (0 * inf), leaves the interval as it is, counting the
 * plane as inside, which it is (boxes are closed). Returns the lanes whose
 * box the ray meets at some t in [0, tmax] (the far end widened:
 * ST_TRACE_SLAB_WIDEN), and in *tn each box's entry distance. */
ST_HOT ST_I ST_CAT(st_slab_test, ST_N)(ST_F nx, ST_F fx, ST_F ny, ST_F fy, ST_F nz, ST_F fz,
                                       const st_slab_consts *r, ST_F tmax, ST_F *tn)
{
    ST_F t, t0 = ST_SPLAT(float, ST_N, 0.0f), t1 = tmax;
    t = (nx - r->o[0]) * r->inv[0];
    t0 = ST_SELECT(ST_N, t0, t, t > t0);
    t = (fx - r->o[0]) * r->inv[0];
    t1 = ST_SELECT(ST_N, t1, t, t < t1);
    t = (ny - r->o[1]) * r->inv[1];
    t0 = ST_SELECT(ST_N, t0, t, t > t0);
    t = (fy - r->o[1]) * r->inv[1];
    t1 = ST_SELECT(ST_N, t1, t, t < t1);
    t = (nz - r->o[2]) * r->inv[2];
    t0 = ST_SELECT(ST_N, t0, t, t > t0);
    t = (fz - r->o[2]) * r->inv[2];
    t1 = ST_SELECT(ST_N, t1, t, t < t1);
    *tn = t0;
    return t0 <= t1 * ST_TRACE_SLAB_WIDEN;
}

/* Moller-Trumbore ray/triangle test (Moller & Trumbore, "Fast, Minimum
 * Storage Ray/Triangle Intersection", JGT 2(1) 1997) in ST_N lanes, a ray
 * (origin o, direction d) against a triangle (v0 and its edges e1, e2):
 *   p = d x e2, det = e1 . p, s = o - v0, q = s x e1,
 *   u = (s . p) / det, v = (d . q) / det, t = (e2 . q) / det,
 *   hit iff u >= 0, v >= 0, u + v <= 1, 0 < t < tmax and, for a one-sided
 *   triangle, det > 0.
 * det = e1 . (d x e2) = -d . (e1 x e2) is positive when the ray meets the
 * front, the side from which v0, v1, v2 run counter-clockwise (glTF's front
 * face), so culling costs one compare. det = 0 (a ray parallel to the plane,
 * or a degenerate triangle) needs no test of its own: 1/det is infinite, so
 * u and v are infinite or NaN and fail the barycentric tests.
 * keep: the lanes that take part; two_sided: the lanes whose triangle is hit
 * from both sides. Returns the lanes that hit, with their t, u, v in *tt,
 * *uu, *vv (unspecified in the others). When no kept lane has u in [0, 1]
 * (a miss whatever v is: v >= 0 makes u + v >= u > 1 in floats too), it
 * returns at once without q, v and t. */
ST_HOT ST_I ST_CAT(st_triangle_test, ST_N)(ST_V3 o, ST_V3 d, ST_V3 v0, ST_V3 e1, ST_V3 e2,
                                           ST_F tmax, ST_I keep, ST_I two_sided, ST_F *tt,
                                           ST_F *uu, ST_F *vv)
{
    ST_F px = d.y * e2.z - d.z * e2.y;
    ST_F py = d.z * e2.x - d.x * e2.z;
    ST_F pz = d.x * e2.y - d.y * e2.x;
    ST_F det = e1.x * px + e1.y * py + e1.z * pz;
    ST_F inv_det = 1.0f / det;
    ST_F sx = o.x - v0.x;
    ST_F sy = o.y - v0.y;
    ST_F sz = o.z - v0.z;
    ST_F u = (sx * px + sy * py + sz * pz) * inv_det;
    ST_I in_u = (u >= 0.0f) & (u <= 1.0f) & keep;
    if (!ST_ANY(ST_N, in_u))
        return in_u;
    ST_F qx = sy * e1.z - sz * e1.y;
    ST_F qy = sz * e1.x - sx * e1.z;
    ST_F qz = sx * e1.y - sy * e1.x;
    ST_F v = (d.x * qx + d.y * qy + d.z * qz) * inv_det;
    ST_F t = (e2.x * qx + e2.y * qy + e2.z * qz) * inv_det;
    *tt = t;
    *uu = u;
    *vv = v;
    return in_u & (v >= 0.0f) & (u + v <= 1.0f) & (t > 0.0f) & (t < tmax) &
           ((det > 0.0f) | two_sided);
}

/* The closest of the triangles tris[list[0 .. count)] (a short list: the
 * emitters', for the last vertex's rays) that each kept lane's ray (o, d)
 * meets at t in (0, *tt), in list order, as st_intersect_triangle finds it
 * triangle by triangle (at width 1 the same operations): where one is
 * nearer, its t, u, v and index list[k] replace *tt, *uu, *vv and *prim.
 * Returns the lanes that met one. */
ST_HOT ST_I ST_CAT(st_list_closest, ST_N)(const ST_GLOBAL st_triangle *tris,
                                          const ST_GLOBAL st_u32 *list, st_u32 count, ST_V3 o,
                                          ST_V3 d, ST_I keep, ST_F *tt, ST_F *uu, ST_F *vv,
                                          ST_I *prim)
{
    ST_I seen = ST_SPLAT(int, ST_N, 0);
    for (st_u32 k = 0u; k < count; k++) {
        const ST_GLOBAL st_triangle *tri = &tris[list[k]];
        ST_V3 v0 = {ST_SPLAT(float, ST_N, tri->v0[0]), ST_SPLAT(float, ST_N, tri->v0[1]),
                    ST_SPLAT(float, ST_N, tri->v0[2])};
        ST_V3 e1 = {ST_SPLAT(float, ST_N, tri->e1[0]), ST_SPLAT(float, ST_N, tri->e1[1]),
                    ST_SPLAT(float, ST_N, tri->e1[2])};
        ST_V3 e2 = {ST_SPLAT(float, ST_N, tri->e2[0]), ST_SPLAT(float, ST_N, tri->e2[1]),
                    ST_SPLAT(float, ST_N, tri->e2[2])};
        ST_I two_sided = ST_BITS_MASK(ST_N, tri->v0[3] == 0.0f ? 0xffffu : 0u);
        ST_F t = *tt, u = *uu, v = *vv;
        ST_I hit = ST_CAT(st_triangle_test, ST_N)(o, d, v0, e1, e2, *tt, keep, two_sided, &t, &u,
                                                   &v);
        *tt = ST_SELECT(ST_N, *tt, t, hit);
        *uu = ST_SELECT(ST_N, *uu, u, hit);
        *vv = ST_SELECT(ST_N, *vv, v, hit);
        *prim = ST_SELECT(ST_N, *prim, ST_SPLAT(int, ST_N, (int)list[k]), hit);
        seen |= hit;
    }
    return seen;
}

#undef ST_F
#undef ST_I
#undef ST_V3
