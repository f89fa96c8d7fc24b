/* shade_lanes.h — one vertex of ST_W paths at once, one per lane
 * (lanes.h): the common case of direct lighting (shade.cl's
 * shade_hits_lanes). PoCL runs a kernel one work-item at a time and widens
 * none of shade_item's float3 arithmetic; explicit lanes stay SIMD, and
 * the device's lane width (st_device_default_lanes: 8 on AVX2, 16 on
 * AVX-512) fills its vector registers. Each lane gathers its own item's
 * values, the arithmetic is done once for all lanes, and each lane stores
 * its own results.
 *
 * A lane is fast when its item is a first-vertex hit (depth 0) on an opaque,
 * untextured, Lambertian, lit material without vertex colours, in a direct
 * render whose next-event estimation takes only area lights (no punctual
 * lights, no environment). Every other lane runs shade_item. A fast lane
 * computes what shade_item computes with the same operations in the same
 * order, so the film is the same bit for bit at every width
 * (shade_lanes_equal_shade_hits in tests/test_render_paths.c): the
 * expressions below have the shapes of integrator.h's (the compiler fuses
 * a * b + c into one fma in both, the same way), and dot and normalize are
 * written out as PoCL's builtins compute them (products rounded, summed
 * x + y then + z; normalize scales by 1 / sqrt of that sum). A lane whose
 * normal's squared length is below FLT_MIN or not finite, where PoCL's
 * normalize rescales first, is handed to shade_item too. OpenCL only. */
#ifndef ST_SHADE_LANES_H
#define ST_SHADE_LANES_H

/* A float, a mask and a key per lane, and a 3-vector per lane (x, y and z
 * each in lanes: trace_lanes.h's st_v3x at ST_W). */
typedef ST_VEC(float, ST_W) st_lf;
typedef ST_VEC(int, ST_W) st_li;
typedef ST_VEC(uint, ST_W) st_lu;
typedef ST_CAT(st_v3x, ST_W) st_lv3;

/* Lanes of floats from uints, rounded to nearest (convert_float). */
#define ST_LANES_TO_FLOAT(x) ST_CAT(ST_LANES_TO_FLOAT_, ST_W)(x)
#define ST_LANES_TO_FLOAT_1(x) convert_float(x)
#define ST_LANES_TO_FLOAT_4(x) convert_float4(x)
#define ST_LANES_TO_FLOAT_8(x) convert_float8(x)
#define ST_LANES_TO_FLOAT_16(x) convert_float16(x)

/* dot(a, b) of each lane as PoCL's builtin computes it: no fused products. */
ST_HOT st_lf lv3_dot(st_lv3 a, st_lv3 b)
{
#pragma OPENCL FP_CONTRACT OFF
    st_lf xx = a.x * b.x, yy = a.y * b.y, zz = a.z * b.z;
    st_lf xy = xx + yy;
    return xy + zz;
}

/* normalize(a) of each lane as PoCL's builtin computes it where the squared
 * length lies in [FLT_MIN, inf); *ok: those lanes (-1), others 0. */
ST_HOT st_lv3 lv3_normalize(st_lv3 a, st_li *ok)
{
    st_lf l2 = lv3_dot(a, a);
    *ok = l2 >= FLT_MIN && l2 < INFINITY;
    st_lf r = 1.0f / sqrt(l2);
    st_lv3 n = {a.x * r, a.y * r, a.z * r};
    return n;
}

/* a, or -a in the lanes of mask m. */
ST_HOT st_lv3 lv3_negate_where(st_lv3 a, st_li m)
{
    st_lv3 n = {ST_SELECT(ST_W, a.x, -a.x, m), ST_SELECT(ST_W, a.y, -a.y, m), ST_SELECT(ST_W, a.z, -a.z, m)};
    return n;
}

/* What each lane gathers before the arithmetic: an array of ST_W per
 * value, lane k at index k (ST_VLOAD reads them as lanes). */
typedef struct st_shade_lanes {
    float ox[ST_W], oy[ST_W], oz[ST_W], dx[ST_W], dy[ST_W], dz[ST_W]; /* the ray */
    float t[ST_W], bu[ST_W], bv[ST_W];                       /* the hit */
    float n0x[ST_W], n0y[ST_W], n0z[ST_W], n1x[ST_W], n1y[ST_W], n1z[ST_W], n2x[ST_W], n2y[ST_W], n2z[ST_W];
    float ngx[ST_W], ngy[ST_W], ngz[ST_W];                   /* facing normal of the hit */
    float cr[ST_W], cg[ST_W], cb[ST_W], er[ST_W], eg[ST_W], eb[ST_W]; /* base colour, emission */
    float betar[ST_W], betag[ST_W], betab[ST_W], radr[ST_W], radg[ST_W], radb[ST_W];
    float u[ST_W], u2[ST_W];                              /* the light sample */
    st_u32 key[ST_W];                                  /* the sample's key */
    float v0x[ST_W], v0y[ST_W], v0z[ST_W], e1x[ST_W], e1y[ST_W], e1z[ST_W], e2x[ST_W], e2y[ST_W], e2z[ST_W];
    float nlx[ST_W], nly[ST_W], nlz[ST_W];                   /* the light's facing normal */
    float lpdf[ST_W], lr[ST_W], lg[ST_W], lb[ST_W];             /* its pdf per area, emission */
} st_shade_lanes;

/* Whether item i may take a fast lane (see the top): a live first vertex
 * that hit a material of st_shade_lanes_material. */
ST_HOT int shade_lanes_item_fast(const st_scene_refs *s, st_u32 i, __global const st_path *path,
                            __global const st_hit *hit)
{
    if (path[i].depth != 0u || hit[i].prim == ST_NO_HIT)
        return 0;
    return st_shade_lanes_material(&s->materials[s->tri_material[hit[i].prim]]);
}

/* st_rng_unit(key, dim) of a key per lane at once: the random sampler's
 * dimension dim (st_sample_dim) in uint lanes. */
ST_HOT st_lf rng_unit_lanes(st_lu key, st_u32 dim)
{
    st_lu x = key ^ st_hash32(dim + 0x9e3779b9u);
    ST_HASH32_MIX(x);
    return ST_LANES_TO_FLOAT(x >> 8) * 5.9604644775390625e-8f; /* st_u32_to_unit */
}

/* Lane k's values from item i (any valid item for a lane that is not
 * fast: its results are never stored): the ray, hit, normals, material,
 * path, and the light sample's two dimensions (the random sampler's key
 * alone: rng_unit_lanes makes them for all lanes at once). */
ST_HOT void shade_lanes_gather(const st_scene_refs *s, const st_params *p, st_u32 i, int fast, st_u32 k, __global const st_sample *sample,
                          __global const st_wave_ray *ray, __global const st_hit *hit,
                          __global const st_path *path, __global const st_u32 *pmj02,
                          st_shade_lanes *l)
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
ST_HOT void shade_lanes_gather_light(const st_scene_refs *s, const st_params *p, const st_shading *sh,
                                st_u32 k, st_shade_lanes *l)
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

#define ST_LV3(l, a, b, c) {ST_VLOAD(ST_W, (l)->a), ST_VLOAD(ST_W, (l)->b), ST_VLOAD(ST_W, (l)->c)}

/* What the arithmetic leaves for each lane to store: the path's radiance,
 * the shadow ray (tmax 0: none) and the lanes that stay fast. */
typedef struct st_shade_lanes_out {
    st_lv3 radiance, origin, wi, contribution;
    st_lf tmax;
    st_li fast;
} st_shade_lanes_out;

/* The surface of surface_at_ray, emission_weight's emission at a first
 * vertex, the sides turned as shade_item turns them, and the origin of the
 * shadow ray (shade_scatter): *ns, *ng the normals; o->radiance, o->origin
 * and o->fast set. */
ST_HOT void shade_lanes_surface(const st_shade_lanes *l, float eps, st_lv3 *ns, st_lv3 *ng,
                           st_shade_lanes_out *o)
{
    st_lv3 d = ST_LV3(l, dx, dy, dz), ro = ST_LV3(l, ox, oy, oz);
    st_lf t = ST_VLOAD(ST_W, l->t), bu = ST_VLOAD(ST_W, l->bu), bv = ST_VLOAD(ST_W, l->bv);
    st_lv3 wo = {-d.x, -d.y, -d.z};
    st_lv3 pos = {ro.x - wo.x * t, ro.y - wo.y * t, ro.z - wo.z * t};
    *ng = (st_lv3)ST_LV3(l, ngx, ngy, ngz);
    st_lf w0 = 1.0f - bu - bv;
    st_lv3 n0 = ST_LV3(l, n0x, n0y, n0z), n1 = ST_LV3(l, n1x, n1y, n1z);
    st_lv3 n2 = ST_LV3(l, n2x, n2y, n2z);
    st_lv3 sum = {w0 * n0.x + bu * n1.x + bv * n2.x, w0 * n0.y + bu * n1.y + bv * n2.y,
                 w0 * n0.z + bu * n1.z + bv * n2.z};
    *ns = lv3_normalize(sum, &o->fast);
    st_lv3 le = ST_LV3(l, er, eg, eb), beta = ST_LV3(l, betar, betag, betab);
    st_lf cos_o = lv3_dot(*ng, wo);
    st_li lit = cos_o > 0.0f && (le.x > 0.0f || le.y > 0.0f || le.z > 0.0f);
    st_lf we = ST_SELECT(ST_W, (st_lf)(0.0f), (st_lf)(1.0f), lit);
    st_lv3 rad = ST_LV3(l, radr, radg, radb);
    o->radiance.x = ST_SELECT(ST_W, rad.x, rad.x + beta.x * le.x * we, lit);
    o->radiance.y = ST_SELECT(ST_W, rad.y, rad.y + beta.y * le.y * we, lit);
    o->radiance.z = ST_SELECT(ST_W, rad.z, rad.z + beta.z * le.z * we, lit);
    *ng = lv3_negate_where(*ng, cos_o < 0.0f);
    *ns = lv3_negate_where(*ns, lv3_dot(*ns, *ng) < 0.0f);
    st_lv3 origin = {pos.x + ng->x * eps, pos.y + ng->y * eps, pos.z + ng->z * eps};
    o->origin = origin;
}

/* next_event's area-light sample for every lane: the point on the light
 * (triangle_point), the direction and distance, the cosines it tests, and
 * what the shadow ray adds, as surface_f_cos's Lambertian branch and
 * next_event compute them with MIS weight 1 (direct lighting). */
ST_HOT void shade_lanes_light(const st_shade_lanes *l, const st_params *p, const st_shading *sh,
                         st_lv3 ns, st_lv3 ng, st_shade_lanes_out *o)
{
    st_lf u = ST_VLOAD(ST_W, l->u), u2 = ST_VLOAD(ST_W, l->u2);
    st_lf su = sqrt(u);
    st_lf b1 = 1.0f - su, b2 = u2 * su;
    st_lv3 v0 = ST_LV3(l, v0x, v0y, v0z), e1 = ST_LV3(l, e1x, e1y, e1z);
    st_lv3 e2 = ST_LV3(l, e2x, e2y, e2z);
    st_lv3 q = {v0.x + b1 * e1.x + b2 * e2.x, v0.y + b1 * e1.y + b2 * e2.y,
               v0.z + b1 * e1.z + b2 * e2.z};
    st_lv3 wi = {q.x - o->origin.x, q.y - o->origin.y, q.z - o->origin.z};
    st_lf dist2 = lv3_dot(wi, wi), dist = sqrt(dist2);
    wi.x /= dist;
    wi.y /= dist;
    wi.z /= dist;
    st_lf cos_l = -lv3_dot((st_lv3)ST_LV3(l, nlx, nly, nlz), wi), cos_s = lv3_dot(ns, wi);
    st_li ok = cos_l > 0.0f && cos_s > 0.0f && lv3_dot(ng, wi) > 0.0f;
    st_lf pdf_light = ST_VLOAD(ST_W, l->lpdf) * dist2 / cos_l;
    st_lf pdf_bsdf = lv3_dot(ns, wi) / ST_PI_F;
    st_lv3 fc = {ST_VLOAD(ST_W, l->cr) * pdf_bsdf, ST_VLOAD(ST_W, l->cg) * pdf_bsdf,
                ST_VLOAD(ST_W, l->cb) * pdf_bsdf};
    st_lv3 beta = ST_LV3(l, betar, betag, betab), le = ST_LV3(l, lr, lg, lb);
    float choice = area_choice(sh);
    st_lf w = 1.0f / pdf_light;
    o->contribution.x = beta.x * fc.x * le.x * w / choice;
    o->contribution.y = beta.y * fc.y * le.y * w / choice;
    o->contribution.z = beta.z * fc.z * le.z * w / choice;
    o->tmax = ST_SELECT(ST_W, (st_lf)(0.0f), dist * (1.0f - 1e-3f) - p->ray_eps, ok);
    o->wi = wi;
}

#endif
