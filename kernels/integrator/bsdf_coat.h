/* bsdf_coat.h — KHR_materials_clearcoat: a smooth or rough dielectric coat
 * (ior 1.5, so F0 = 0.04) over the whole material of bsdf_dielectric.h.
 * Written over lanes like bsdf.h; tests/unit/test_bsdf.c runs it on the host.
 *
 * The glTF specification's layering, f = (1 - w Fc(wo.h)) f_base + w Fc(wo.h)
 * D_c V_c, reflects more than it receives over a white base (1.024 at 60
 * degrees over a white Lambertian base: tests/unit/test_bsdf.c's coat_furnace
 * saw it), since the base keeps 1 - Fc of the half vector's angle while
 * the coat takes Fc of wo's. strata keeps the coat's lobe and attenuates
 * the base by what light crossing the coat keeps each way, as the
 * specification's reference viewer does with n.v (and physically layered
 * models with both directions):
 *   f = (1 - w Fc(|wo.z|)) (1 - w Fc(|wi.z|)) f_base + w Fc(wo.h) D_c V_c,
 *   Fc(x) = 0.04 + 0.96 (1 - x)^5 (ior 1.5),
 * with w the clearcoat factor (x texture R), h the half vector of wo and
 * wi, and D_c, V_c bsdf.h's GGX terms at α_c = clearcoatRoughness² (x
 * texture G). Each factor is symmetric in wo and wi, so the base's
 * reciprocity (and a refraction's generalised one) holds under the coat.
 * The coat's lobe and Fresnel are taken about its own normal (from
 * clearcoatNormalTexture; the base's shading normal without one), given
 * in the base's shading frame (st_coat_tilt): wo and wi turn into the
 * coat's frame for them, while the base keeps its frame and cosines. A
 * direction must lie above both surfaces, the coat's and the base's.
 *
 * Sampling: the coat's visible normals (reflected) with probability
 * st_coat_prob (w x its Fresnel towards wo, lifted so that its sharp lobe
 * is found, kept below 0.9 so that the base is too), else the base's own
 * sampling; the pdf is the mixture's. This file follows bsdf_sheen.h. */
#ifndef ST_BSDF_COAT_H
#define ST_BSDF_COAT_H

/* The coat at one point. */
typedef struct st_coat {
    st_lf weight; /* clearcoat factor x texture, in [0, 1] */
    st_lf alpha;  /* (clearcoatRoughness x texture)², at least bsdf.h's least α */
    st_lv3 tu, tv, n; /* the coat's frame in the base's shading frame */
} st_coat;

ST_FN st_coat st_coat_make(st_lf factor, st_lf roughness)
{
    st_coat c;
    st_lf r = st_clamp01(roughness);
    c.weight = st_clamp01(factor);
    c.alpha = ST_FMAXF(r * r, ST_BRDF_MIN_ALPHA);
    c.tu = st_lv3_make(ST_LF(1.0f), ST_LF(0.0f), ST_LF(0.0f));
    c.tv = st_lv3_make(ST_LF(0.0f), ST_LF(1.0f), ST_LF(0.0f));
    c.n = st_lv3_make(ST_LF(0.0f), ST_LF(0.0f), ST_LF(1.0f));
    return c;
}

/* The coat's normal n (unit, n.z > 0) in the base's shading frame. */
ST_FN void st_coat_tilt(st_coat *c, st_dir n)
{
    c->n = n;
    st_basis(n, &c->tu, &c->tv);
}

/* w (in the base's frame) in the coat's frame, and back. */
ST_FN st_dir st_coat_in(const st_coat *c, st_dir w)
{
    return st_lv3_make(st_lv3_dot(w, c->tu), st_lv3_dot(w, c->tv), st_lv3_dot(w, c->n));
}

ST_FN st_dir st_coat_out(const st_coat *c, st_dir w)
{
    return st_lv3_make(w.x * c->tu.x + w.y * c->tv.x + w.z * c->n.x,
                       w.x * c->tu.y + w.y * c->tv.y + w.z * c->n.y,
                       w.x * c->tu.z + w.y * c->tv.z + w.z * c->n.z);
}

/* The coat's Schlick Fresnel at cosine x (ior 1.5: F0 = 0.04, F90 = 1). */
ST_FN st_lf st_coat_fresnel(st_lf x)
{
    return 0.04f + 0.96f * st_schlick(x);
}

/* What the coat passes of the base's f(wo, wi). */
ST_FN st_lf st_coat_pass(const st_coat *c, st_dir wo, st_dir wi)
{
    return (1.0f - c->weight * st_coat_fresnel(ST_FABSF(st_lv3_dot(wo, c->n)))) *
           (1.0f - c->weight * st_coat_fresnel(ST_FABSF(st_lv3_dot(wi, c->n))));
}

/* The coat's own reflection w Fc(wo.h) D_c V_c (0 unless both above). */
ST_FN st_lf st_coat_eval(const st_coat *c, st_dir wo, st_dir wi)
{
    st_dir o = st_coat_in(c, wo), i = st_coat_in(c, wi);
    st_dir h = st_half_vector(o, i);
    st_lf oh = o.x * h.x + o.y * h.y + o.z * h.z;
    st_lf f = c->weight * st_coat_fresnel(oh) * st_ggx_d(c->alpha, h) * st_ggx_v(c->alpha, o, i);
    return ST_SELECT(ST_W, ST_LF(0.0f), f, o.z > 0.0f && i.z > 0.0f && wo.z > 0.0f && wi.z > 0.0f);
}

/* The probability of sampling the coat towards wo. */
ST_FN st_lf st_coat_prob(const st_coat *c, st_dir wo)
{
    return ST_FMINF(c->weight * (0.2f + 0.8f * st_coat_fresnel(st_lv3_dot(wo, c->n))), 0.9f);
}

/* The coat lobe's own density: its visible normals reflected. */
ST_FN st_lf st_coat_lobe_pdf(const st_coat *c, st_dir wo, st_dir wi)
{
    st_dir o = st_coat_in(c, wo), i = st_coat_in(c, wi);
    st_dir h = st_half_vector(o, i);
    st_lf p = st_ggx_g1(c->alpha, o) * st_ggx_d(c->alpha, h) / (4.0f * o.z);
    return ST_SELECT(ST_W, ST_LF(0.0f), p, o.z > 0.0f && i.z > 0.0f && wo.z > 0.0f && wi.z > 0.0f);
}

/* A direction from the coat's visible normals (u1 in [0, 1)), reflected;
 * (0, 0, 0) where it falls below either surface (lost, as the base's). */
ST_FN st_dir st_coat_reflect(const st_coat *c, st_dir wo, st_lf u1, st_lf u2)
{
    st_dir o = st_coat_in(c, wo);
    st_dir h = st_ggx_visible_normal(c->alpha, c->alpha, o, u1, u2);
    st_dir r = st_reflect(o, h), w = st_coat_out(c, r);
    st_li lost = r.z <= 0.0f || w.z <= 0.0f;
    return st_lv3_select(w, st_lv3_make(ST_LF(0.0f), ST_LF(0.0f), ST_LF(0.0f)), lost);
}

/* ---- the coated material: the coat over bsdf_dielectric.h's whole, or
 * over bsdf_sheen.h's sheened whole (the _sheened forms, which the
 * kernels run only where a lane has a sheen) ------------------------------- */

/* The coat over a base's f(wo, wi) in f[3], and over its pdf. */
ST_FN void st_coat_over(const st_coat *c, st_dir wo, st_dir wi, st_lf *f)
{
    st_lf pass = st_coat_pass(c, wo, wi), coat = st_coat_eval(c, wo, wi);
    for (int k = 0; k < 3; k++)
        f[k] = f[k] * pass + coat;
}

ST_FN st_lf st_coat_over_pdf(const st_coat *c, st_dir wo, st_dir wi, st_lf base)
{
    st_lf p = st_coat_prob(c, wo);
    return (1.0f - p) * base + p * st_coat_lobe_pdf(c, wo, wi);
}

/* A direction from the coat (u1 below st_coat_prob, rescaled), else `base`,
 * made by the caller from u1 rescaled to the rest (st_coat_rest); a coat
 * reflection below the surface is lost (0, 0, 0), as the base's. */
ST_FN st_lf st_coat_rest(const st_coat *c, st_dir wo, st_lf u1)
{
    st_lf p = st_coat_prob(c, wo);
    return ST_FMINF((u1 - p) / (1.0f - p), 0.99999994f);
}

ST_FN st_dir st_coat_pick(const st_coat *c, st_dir wo, st_lf u1, st_lf u2, st_dir base)
{
    st_lf p = st_coat_prob(c, wo);
    st_li coat = u1 < p;
    st_dir wi = base;
    if (ST_ANY(ST_W, coat))
        wi = st_lv3_select(wi, st_coat_reflect(c, wo, ST_FMINF(u1 / p, 0.99999994f), u2), coat);
    return wi;
}

ST_FN void st_coated_eval(const st_brdf *b, const st_dielectric *d, const st_coat *c, st_dir wo,
                          st_dir wi, st_lf *f)
{
    st_bsdf_eval(b, d, wo, wi, f);
    st_lf pass = st_coat_pass(c, wo, wi), coat = st_coat_eval(c, wo, wi);
    for (int k = 0; k < 3; k++)
        f[k] = f[k] * pass + coat;
}

ST_FN st_lf st_coated_pdf(const st_brdf *b, const st_dielectric *d, const st_coat *c, st_dir wo,
                          st_dir wi)
{
    st_lf p = st_coat_prob(c, wo);
    return (1.0f - p) * st_bsdf_pdf(b, d, wo, wi) + p * st_coat_lobe_pdf(c, wo, wi);
}

/* u1 below st_coat_prob picks the coat (u1 rescaled), else the base with
 * u1 rescaled to the rest; a coat reflection below the surface is lost
 * (0, 0, 0), as the base's. */
ST_FN st_dir st_coated_sample(const st_brdf *b, const st_dielectric *d, const st_coat *c,
                              st_dir wo, st_lf u1, st_lf u2, st_lf u3)
{
    st_lf p = st_coat_prob(c, wo);
    st_li coat = u1 < p;
    st_dir wi = wo;
    if (ST_ANY(ST_W, !coat))
        wi = st_bsdf_sample(b, d, wo, ST_FMINF((u1 - p) / (1.0f - p), 0.99999994f), u2, u3);
    if (ST_ANY(ST_W, coat))
        wi = st_lv3_select(wi, st_coat_reflect(c, wo, ST_FMINF(u1 / p, 0.99999994f), u2), coat);
    return wi;
}

ST_FN void st_coated_sheened_eval(const st_brdf *b, const st_dielectric *d, const st_sheen *s,
                                  const st_coat *c, st_dir wo, st_dir wi, st_lf *f)
{
    st_sheened_eval(b, d, s, wo, wi, f);
    st_coat_over(c, wo, wi, f);
}

ST_FN st_lf st_coated_sheened_pdf(const st_brdf *b, const st_dielectric *d, const st_sheen *s,
                                  const st_coat *c, st_dir wo, st_dir wi)
{
    return st_coat_over_pdf(c, wo, wi, st_sheened_pdf(b, d, s, wo, wi));
}

ST_FN st_dir st_coated_sheened_sample(const st_brdf *b, const st_dielectric *d,
                                      const st_sheen *s, const st_coat *c, st_dir wo, st_lf u1,
                                      st_lf u2, st_lf u3)
{
    st_dir wi = wo;
    if (ST_ANY(ST_W, !(u1 < st_coat_prob(c, wo))))
        wi = st_sheened_sample(b, d, s, wo, st_coat_rest(c, wo, u1), u2, u3);
    return st_coat_pick(c, wo, u1, u2, wi);
}

#endif
