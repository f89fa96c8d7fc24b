/* shade8.h — one vertex of eight paths at once, in float8 lanes: the common
 * case of direct lighting (shade.cl's shade_hits8). PoCL runs a kernel one
 * work-item at a time and widens none of shade_item's float3 arithmetic
 * (its loops over work-items are not vectorised across items); explicit float8
 * stays SIMD. Each lane gathers its own item's values, the arithmetic is
 * done once for all eight, and each lane stores its own results.
 *
 * A lane is fast when its item is a first-vertex hit (depth 0) on an opaque,
 * untextured, Lambertian, lit material without vertex colours, in a direct
 * render whose next-event estimation takes only area lights (no punctual
 * lights, no environment). Every other lane runs shade_item. A fast lane
 * computes what shade_item computes with the same operations in the same
 * order, so the film is the same bit for bit (shade_hits8_equals_shade_hits
 * in tests/test_render_paths.c): the expressions below have the shapes of
 * integrator.h's (the compiler fuses a * b + c into one fma in both, the
 * same way), and dot and normalize are
 * written out as PoCL's builtins compute them (products rounded, summed
 * x + y then + z; normalize scales by 1 / sqrt of that sum). A lane whose
 * normal's squared length is below FLT_MIN or not finite, where PoCL's
 * normalize rescales first, is handed to shade_item too. OpenCL only. */
#ifndef ST_SHADE8_H
#define ST_SHADE8_H

#define ST_LANES 8u

/* Three float8 lanes of float3s. */
typedef struct st_v8 {
    float8 x, y, z;
} st_v8;

/* dot(a, b) of each lane as PoCL's builtin computes it: no fused products. */
ST_HOT float8 dot8(st_v8 a, st_v8 b)
{
#pragma OPENCL FP_CONTRACT OFF
    float8 xx = a.x * b.x, yy = a.y * b.y, zz = a.z * b.z;
    float8 xy = xx + yy;
    return xy + zz;
}

/* normalize(a) of each lane as PoCL's builtin computes it where the squared
 * length lies in [FLT_MIN, inf); *ok: those lanes (-1), others 0. */
ST_HOT st_v8 normalize8(st_v8 a, int8 *ok)
{
    float8 l2 = dot8(a, a);
    *ok = l2 >= FLT_MIN && l2 < INFINITY;
    float8 r = 1.0f / sqrt(l2);
    st_v8 n = {a.x * r, a.y * r, a.z * r};
    return n;
}

/* a, or -a in the lanes of mask m. */
ST_HOT st_v8 negate_where8(st_v8 a, int8 m)
{
    st_v8 n = {select(a.x, -a.x, m), select(a.y, -a.y, m), select(a.z, -a.z, m)};
    return n;
}

/* What each lane gathers before the arithmetic: one float8-able array per
 * value, lane k at index k (vload8 reads them). */
typedef struct st_lanes8 {
    float ox[8], oy[8], oz[8], dx[8], dy[8], dz[8]; /* the ray */
    float t[8], bu[8], bv[8];                       /* the hit */
    float n0x[8], n0y[8], n0z[8], n1x[8], n1y[8], n1z[8], n2x[8], n2y[8], n2z[8];
    float ngx[8], ngy[8], ngz[8];                   /* facing normal of the hit */
    float cr[8], cg[8], cb[8], er[8], eg[8], eb[8]; /* base colour, emission */
    float betar[8], betag[8], betab[8], radr[8], radg[8], radb[8];
    float u[8], u2[8];                              /* the light sample */
    st_u32 key[8];                                  /* the sample's key */
    float v0x[8], v0y[8], v0z[8], e1x[8], e1y[8], e1z[8], e2x[8], e2y[8], e2z[8];
    float nlx[8], nly[8], nlz[8];                   /* the light's facing normal */
    float lpdf[8], lr[8], lg[8], lb[8];             /* its pdf per area, emission */
} st_lanes8;

/* Whether item i may take a fast lane (see the top): a live first vertex
 * that hit a material of st_shade8_material. */
ST_HOT int shade8_item_fast(const st_scene_refs *s, st_u32 i, __global const st_path *path,
                            __global const st_hit *hit)
{
    if (path[i].depth != 0u || hit[i].prim == ST_NO_HIT)
        return 0;
    return st_shade8_material(&s->materials[s->tri_material[hit[i].prim]]);
}

/* st_rng_unit(key, dim) of eight keys at once: the random sampler's
 * dimension dim (st_sample_dim) in uint8 lanes. */
ST_HOT float8 rng_unit8(uint8 key, st_u32 dim)
{
    uint8 x = key ^ st_hash32(dim + 0x9e3779b9u);
    ST_HASH32_MIX(x);
    return convert_float8(x >> 8) * 5.9604644775390625e-8f; /* st_u32_to_unit */
}

/* Lane k's values from item i (any valid item for a lane that is not
 * fast: its results are never stored): the ray, hit, normals, material,
 * path, and the light sample's two dimensions (the random sampler's key
 * alone: rng_unit8 makes them for all lanes at once). */
ST_HOT void shade8_gather(const st_scene_refs *s, const st_params *p, st_u32 i, int fast, st_u32 k, __global const st_sample *sample,
                          __global const st_wave_ray *ray, __global const st_hit *hit,
                          __global const st_path *path, __global const st_u32 *pmj02,
                          st_lanes8 *l)
{
    __global const st_wave_ray *r = &ray[i];
    l->ox[k] = r->o[0], l->oy[k] = r->o[1], l->oz[k] = r->o[2];
    l->dx[k] = r->d[0], l->dy[k] = r->d[1], l->dz[k] = r->d[2];
    st_hit h = hit[i];
    st_u32 t = fast ? h.prim : 0u;
    l->t[k] = h.t, l->bu[k] = h.u, l->bv[k] = h.v;
    __global const st_tri_normals *n = &s->normals[t];
    l->n0x[k] = n->n0[0], l->n0y[k] = n->n0[1], l->n0z[k] = n->n0[2];
    l->n1x[k] = n->n1[0], l->n1y[k] = n->n1[1], l->n1z[k] = n->n1[2];
    l->n2x[k] = n->n2[0], l->n2y[k] = n->n2[1], l->n2z[k] = n->n2[2];
    l->ngx[k] = n->n0[3], l->ngy[k] = n->n1[3], l->ngz[k] = n->n2[3];
    __global const st_material *m = &s->materials[s->tri_material[t]];
    l->cr[k] = m->base_color[0], l->cg[k] = m->base_color[1], l->cb[k] = m->base_color[2];
    l->er[k] = m->emission[0], l->eg[k] = m->emission[1], l->eb[k] = m->emission[2];
    __global const st_path *gp = &path[i];
    l->betar[k] = gp->beta[0], l->betag[k] = gp->beta[1], l->betab[k] = gp->beta[2];
    l->radr[k] = gp->radiance[0], l->radg[k] = gp->radiance[1], l->radb[k] = gp->radiance[2];
    __global const st_sample *smp = &sample[i];
    l->key[k] = smp->key;
    if (p->sampler != ST_SAMPLER_RANDOM) {
        st_sample_id id = st_sample_resume(p, smp->pixel, smp->index, smp->key, smp->word);
        id.pmj02 = pmj02;
        l->u[k] = st_sample_dim(p, &id, 2u);
        l->u2[k] = st_sample_dim(p, &id, 3u);
    }
}

/* Lane k's light sample (next_event's pick, triangle_point's and
 * light_emission's inputs) from its two dimensions. */
ST_HOT void shade8_gather_light(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                                st_u32 k, st_lanes8 *l)
{
    float u = l->u[k], u2 = l->u2[k];
    st_u32 lt = s->light_tri[pick_light(s->light_cdf, p->light_count, &u)];
    l->u[k] = u;
    __global const st_triangle *tri = &s->tris[lt];
    l->v0x[k] = tri->v0[0], l->v0y[k] = tri->v0[1], l->v0z[k] = tri->v0[2];
    l->e1x[k] = tri->e1[0], l->e1y[k] = tri->e1[1], l->e1z[k] = tri->e1[2];
    l->e2x[k] = tri->e2[0], l->e2y[k] = tri->e2[1], l->e2z[k] = tri->e2[2];
    __global const st_tri_normals *nl = &s->normals[lt];
    l->nlx[k] = nl->n0[3], l->nly[k] = nl->n1[3], l->nlz[k] = nl->n2[3];
    l->lpdf[k] = s->light_pdf[lt];
    float3 le = light_emission(s, lt, u, u2, sh->texture_filter);
    l->lr[k] = le.x, l->lg[k] = le.y, l->lb[k] = le.z;
}

#define ST_V8(l, a, b, c) {vload8(0, (l)->a), vload8(0, (l)->b), vload8(0, (l)->c)}

/* What the arithmetic leaves for each lane to store: the path's radiance,
 * the shadow ray (tmax 0: none) and the lanes that stay fast. */
typedef struct st_shade8_out {
    st_v8 radiance, origin, wi, contribution;
    float8 tmax;
    int8 fast;
} st_shade8_out;

/* The surface of surface_at_ray, emission_weight's emission at a first
 * vertex, the sides turned as shade_item turns them, and the origin of the
 * shadow ray (shade_scatter): *ns, *ng the normals; o->radiance, o->origin
 * and o->fast set. */
ST_HOT void shade8_surface(const st_lanes8 *l, float eps, st_v8 *ns, st_v8 *ng,
                           st_shade8_out *o)
{
    st_v8 d = ST_V8(l, dx, dy, dz), ro = ST_V8(l, ox, oy, oz);
    float8 t = vload8(0, l->t), bu = vload8(0, l->bu), bv = vload8(0, l->bv);
    st_v8 wo = {-d.x, -d.y, -d.z};
    st_v8 pos = {ro.x - wo.x * t, ro.y - wo.y * t, ro.z - wo.z * t};
    *ng = (st_v8)ST_V8(l, ngx, ngy, ngz);
    float8 w0 = 1.0f - bu - bv;
    st_v8 n0 = ST_V8(l, n0x, n0y, n0z), n1 = ST_V8(l, n1x, n1y, n1z);
    st_v8 n2 = ST_V8(l, n2x, n2y, n2z);
    st_v8 sum = {w0 * n0.x + bu * n1.x + bv * n2.x, w0 * n0.y + bu * n1.y + bv * n2.y,
                 w0 * n0.z + bu * n1.z + bv * n2.z};
    *ns = normalize8(sum, &o->fast);
    st_v8 le = ST_V8(l, er, eg, eb), beta = ST_V8(l, betar, betag, betab);
    float8 cos_o = dot8(*ng, wo);
    int8 lit = cos_o > 0.0f && (le.x > 0.0f || le.y > 0.0f || le.z > 0.0f);
    float8 we = select((float8)(0.0f), (float8)(1.0f), lit);
    st_v8 rad = ST_V8(l, radr, radg, radb);
    o->radiance.x = select(rad.x, rad.x + beta.x * le.x * we, lit);
    o->radiance.y = select(rad.y, rad.y + beta.y * le.y * we, lit);
    o->radiance.z = select(rad.z, rad.z + beta.z * le.z * we, lit);
    *ng = negate_where8(*ng, cos_o < 0.0f);
    *ns = negate_where8(*ns, dot8(*ns, *ng) < 0.0f);
    st_v8 origin = {pos.x + ng->x * eps, pos.y + ng->y * eps, pos.z + ng->z * eps};
    o->origin = origin;
}

/* next_event's area-light sample for every lane: the point on the light
 * (triangle_point), the direction and distance, the cosines it tests, and
 * what the shadow ray adds, as surface_f_cos's Lambertian branch and
 * next_event compute them with MIS weight 1 (direct lighting). */
ST_HOT void shade8_light(const st_lanes8 *l, const st_params *p, const st_shading *sh,
                         st_v8 ns, st_v8 ng, st_shade8_out *o)
{
    float8 u = vload8(0, l->u), u2 = vload8(0, l->u2);
    float8 su = sqrt(u);
    float8 b1 = 1.0f - su, b2 = u2 * su;
    st_v8 v0 = ST_V8(l, v0x, v0y, v0z), e1 = ST_V8(l, e1x, e1y, e1z);
    st_v8 e2 = ST_V8(l, e2x, e2y, e2z);
    st_v8 q = {v0.x + b1 * e1.x + b2 * e2.x, v0.y + b1 * e1.y + b2 * e2.y,
               v0.z + b1 * e1.z + b2 * e2.z};
    st_v8 wi = {q.x - o->origin.x, q.y - o->origin.y, q.z - o->origin.z};
    float8 dist2 = dot8(wi, wi), dist = sqrt(dist2);
    wi.x /= dist;
    wi.y /= dist;
    wi.z /= dist;
    float8 cos_l = -dot8((st_v8)ST_V8(l, nlx, nly, nlz), wi), cos_s = dot8(ns, wi);
    int8 ok = cos_l > 0.0f && cos_s > 0.0f && dot8(ng, wi) > 0.0f;
    float8 pdf_light = vload8(0, l->lpdf) * dist2 / cos_l;
    float8 pdf_bsdf = dot8(ns, wi) / ST_PI_F;
    st_v8 fc = {vload8(0, l->cr) * pdf_bsdf, vload8(0, l->cg) * pdf_bsdf,
                vload8(0, l->cb) * pdf_bsdf};
    st_v8 beta = ST_V8(l, betar, betag, betab), le = ST_V8(l, lr, lg, lb);
    float choice = area_choice(sh);
    float8 w = 1.0f / pdf_light;
    o->contribution.x = beta.x * fc.x * le.x * w / choice;
    o->contribution.y = beta.y * fc.y * le.y * w / choice;
    o->contribution.z = beta.z * fc.z * le.z * w / choice;
    o->tmax = select((float8)(0.0f), dist * (1.0f - 1e-3f) - p->ray_eps, ok);
    o->wi = wi;
}

#endif
