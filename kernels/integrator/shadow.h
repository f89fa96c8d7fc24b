/* shadow.h — shadow rays through alpha cut-outs and blended surfaces: a
 * shadow ray sees a material's alpha as a camera ray does (integrator.h's
 * alpha_passes_keyed), so a cut-out casts a cut-out shadow. OpenCL only; needs
 * trace.h and integrator.h. Test: tests/device/test_shading.c
 * (alpha_cutout_casts_cutout_shadow). */
#ifndef ST_SHADOW_H
#define ST_SHADOW_H

/* Random key of the shadow rays' BLEND coverage, apart from the camera
 * rays' (alpha_passes), so the two decisions at one triangle are independent. */
#define ST_SHADOW_ALPHA_KEY 0x5ad0a1fau

/* Whether something blocks shadow ray r of the path at depth `depth`.
 * Any hit on a triangle of an opaque material blocks it at once, so a scene
 * without alpha pays one any-hit query as before. A hit on a MASK or BLEND
 * material instead walks the hits front to back: each is alpha-tested (its
 * texture and vertex colour included, through material_at), the first that
 * does not let the ray pass blocks it, and one that does sends it on from
 * just beyond (ray_eps, as alpha_passes' camera rays go on). Each step
 * moves the origin forward, so the walk ends. */
static int shadow_blocked(__global const st_bvh_wide_node *nodes, const st_scene_refs *s,
                          const st_params *p, const st_shading *sh, st_ray r, st_sample smp,
                          st_u32 depth)
{
    st_hit h;
    if (!st_intersect_wide_any_hit(nodes, &r, &h))
        return 0;
    if (s->materials[s->tri_material[h.prim]].alpha_mode == ST_ALPHA_OPAQUE)
        return 1;
    float travelled = 0.0f;
    while (st_intersect_wide_closest(nodes, &r, &h)) {
        float3 ng = facing_normal(s->normals, h.prim), d = (float3)(r.d[0], r.d[1], r.d[2]);
        st_material_at a = material_at(s, p, sh, h, dot(ng, -d), travelled + h.t);
        if (!alpha_passes_keyed(p, &a, smp, h.prim, depth, ST_SHADOW_ALPHA_KEY))
            return 1;
        float step = h.t + p->ray_eps;
        ST_UNROLL
        for (int a = 0; a < 3; ++a)
            r.o[a] += r.d[a] * step;
        r.tmax -= step;
        travelled += step;
        if (!(r.tmax > 0.0f))
            return 0;
    }
    return 0;
}

/* Item i's shadow ray (tmax 0: none): adds its contribution to the path's
 * radiance when nothing blocks it, and counts the ray. One body for both
 * places a shadow ray is traced: the stage trace_shadow_rays (shadow.cl) and
 * shade_hits_shadowed (shade.cl), so both add the same floats in the same
 * order. */
ST_HOT void trace_shadow_item(__global const st_bvh_wide_node *nodes, const st_scene_refs *sc,
                              const st_params *p, const st_shading *sh,
                              __global const st_shadow *shadow, __global st_path *path,
                              __global const st_sample *sample, st_u32 i)
{
    __global const st_shadow *s = &shadow[i];
    if (!(s->ray.tmax > 0.0f))
        return;
    __global st_path *pa = &path[i];
    int blocked = shadow_blocked(nodes, sc, p, sh, s->ray, sample[i], pa->depth);
    float3 l = blocked ? (float3)(0.0f) : vload3(0, s->contribution);
    vstore3(vload3(0, pa->radiance) + l, 0, pa->radiance);
    pa->shadow_rays++;
}

#endif
