/* bsdf_dielectric.h — KHR_materials_transmission: a dielectric interface
 * that reflects and refracts (Walter, Marschner, Li & Torrance, "Microfacet
 * Models for Refraction through Rough Surfaces", EGSR 2007), with the GGX
 * distribution and the roughness of bsdf.h's specular lobe, the exact
 * unpolarised Fresnel reflectance of the ior (total internal reflection
 * included), and the transmitted part tinted by the base colour (the glTF
 * specification's specular_btdf x baseColor). Written over lanes like
 * bsdf.h; tests/unit/test_bsdf.c runs it on the host.
 *
 * The material (glTF 2.0 appendix B with KHR_materials_transmission):
 *   f = m metal + (1 - m) [(1 - tr) dielectric_opaque + tr dielectric_transmissive],
 * so st_brdf_make's dielectric parts take the weight 1 - tr (its
 * `transmission`), and this lobe adds w = (1 - m) tr x
 *   F D G2 / (4 |wo.z| |wi.z|)                               (wi above)
 *   (1 - F) c D G2 |wo.h| |wi.h| / (|wo.z| |wi.z| (wo.h + η wi.h)²)   (wi below)
 * with h the half vector of each case and G2 = 1 / (1 + Λ(wo) + Λ(wi)),
 * height-correlated as in bsdf.h. Directions are local with wo above
 * (z > 0, the side the ray arrived on: integrator.h turns the frame to it);
 * η = η(wi's side) / η(wo's side): ior entering the material, 1 / ior
 * leaving it. The transmitted part is the radiance BTDF (it carries the
 * 1 / η² by which radiance spreads out entering a denser medium), so
 * f(wo, wi) / η(wo)² = f(wi, wo) / η(wi)² (Veach's thesis, §5.2).
 *
 * Sampling: a visible normal h of GGX towards wo (bsdf.h), then
 * reflection with probability F(wo.h) and refraction otherwise (one more
 * dimension, u3); pdf G1(wo) D(h) (wo.h) / wo.z x F / (4 wo.h) or
 * x (1 - F) η² |wi.h| / (wo.h + η wi.h)². A smooth surface is GGX at
 * bsdf.h's least α, as for the opaque lobes: no delta lobe to special-case.
 *
 * Thin-walled (KHR_materials_transmission without KHR_materials_volume:
 * the surface bounds no interior): light crosses the surface and goes on
 * in its direction. A transmitted direction is the reflection about the
 * microfacet normal mirrored through the surface, (x, y, -z), so the
 * smooth surface passes -wo and a rough one spreads about it with the
 * reflection's GGX lobe; there is no 1 / η² (the same medium on both
 * sides). The Fresnel reflectance is the slab's, the interreflections
 * between its two faces summed without absorption (Mitsuba 3's
 * thindielectric): R' = 2 R / (1 + R), T' = 1 - R', with R that of one
 * face at wo.h with the ior. So
 *   f = R' D G2 / (4 |wo.z| |wi.z|)                 (wi above)
 *   f = T' c D G2 / (4 |wo.z| |wi.z|)               (wi below, h of wo and wi mirrored)
 * and a smooth white thin surface keeps all of the energy.
 * This file follows bsdf.h (it uses its helpers). */
#ifndef ST_BSDF_DIELECTRIC_H
#define ST_BSDF_DIELECTRIC_H

/* The least ior a transmissive surface refracts with: at 1 the half vector
 * of a refraction (wo + η wi) vanishes. */
#define ST_DIELECTRIC_MIN_IOR 1.001f

/* The transmission lobe at one point. */
typedef struct st_dielectric {
    st_lf weight; /* (1 - metallic) x transmission: its share of the material */
    st_lf eta;    /* η(wi's side) / η(wo's side) for a refraction; the ior where thin */
    st_lf tint[3];
    st_li thin;   /* thin-walled: passes light straight through */
} st_dielectric;

/* The lobe of a material with transmission tr, metallic m, base colour c
 * and the ior, for a ray that arrived from outside (`entering`) or from
 * inside; thin-walled where `thin`. */
ST_FN st_dielectric st_dielectric_make(st_lf tr, st_lf m, const st_lf *c, st_lf ior,
                                       st_li entering, st_li thin)
{
    st_dielectric d;
    st_lf n = ST_FMAXF(ior, ST_DIELECTRIC_MIN_IOR);
    d.weight = (1.0f - st_clamp01(m)) * st_clamp01(tr);
    d.eta = ST_SELECT(ST_W, 1.0f / n, n, entering || thin);
    for (int k = 0; k < 3; k++)
        d.tint[k] = st_clamp01(c[k]);
    d.thin = thin;
    return d;
}

/* w mirrored through the surface's plane. */
ST_FN st_dir st_mirror_z(st_dir w)
{
    return st_lv3_make(w.x, w.y, -w.z);
}

/* st_fresnel_dielectric: thin_film.h. */

/* The half vector of a refraction from wo into wi: -(wo + η wi), turned
 * to wo's side (z > 0). */
ST_FN st_dir st_refraction_half(st_dir wo, st_dir wi, st_lf eta)
{
    st_dir h = st_dir_normalize(st_lv3_make(wo.x + eta * wi.x, wo.y + eta * wi.y,
                                            wo.z + eta * wi.z));
    return st_lv3_select(h, st_lv3_neg(h), h.z < 0.0f);
}

/* wo reflected about h, and refracted through it (η as above; wo.h > 0,
 * no total internal reflection). */
ST_FN st_dir st_reflect(st_dir wo, st_dir h)
{
    st_lf d = 2.0f * (wo.x * h.x + wo.y * h.y + wo.z * h.z);
    return st_lv3_make(d * h.x - wo.x, d * h.y - wo.y, d * h.z - wo.z);
}

ST_FN st_dir st_refract(st_dir wo, st_dir h, st_lf eta)
{
    st_lf c = wo.x * h.x + wo.y * h.y + wo.z * h.z;
    st_lf ct = ST_SQRTF(ST_FMAXF(0.0f, 1.0f - (1.0f - c * c) / (eta * eta)));
    st_lf a = c / eta - ct;
    return st_lv3_make(a * h.x - wo.x / eta, a * h.y - wo.y / eta, a * h.z - wo.z / eta);
}

/* The height-correlated visibility G2 / (4 |wo.z| |wi.z|) of a pair on
 * either side (bsdf.h's st_ggx_v with the cosines' magnitudes). */
ST_FN st_lf st_ggx_v_abs(st_lf alpha, st_dir wo, st_dir wi)
{
    st_lf lo = st_ggx_lambda_term(alpha, wo), li = st_ggx_lambda_term(alpha, wi);
    return 0.5f / (ST_FABSF(wi.z) * lo + ST_FABSF(wo.z) * li);
}

/* The lobe's f(wo, wi) (without its weight) per channel into f[3]; wo.z > 0. */
ST_FN void st_dielectric_eval(const st_dielectric *d, st_lf alpha, st_dir wo, st_dir wi, st_lf *f)
{
    st_li refl = wi.z > 0.0f;
    /* a thin wall's transmission is its reflection mirrored: wr */
    st_dir wr = st_lv3_select(wi, st_mirror_z(wi), d->thin && !refl);
    st_li as_refl = refl || d->thin;
    st_dir hr = st_half_vector(wo, wr), ht = st_refraction_half(wo, wi, d->eta);
    st_dir h = st_lv3_select(ht, hr, as_refl);
    st_lf oh = wo.x * h.x + wo.y * h.y + wo.z * h.z, ih = wr.x * h.x + wr.y * h.y + wr.z * h.z;
    st_lf fr = st_fresnel_dielectric(ST_FMAXF(oh, 0.0f), d->eta);
    fr = ST_SELECT(ST_W, fr, 2.0f * fr / (1.0f + fr), d->thin);
    st_lf dv = st_ggx_d(alpha, h) * st_ggx_v_abs(alpha, wo, wi);
    st_lf den = oh + d->eta * ih;
    st_lf t = ST_SELECT(ST_W, (1.0f - fr) * dv * 4.0f * oh * ST_FABSF(ih) / (den * den),
                        (1.0f - fr) * dv, d->thin);
    /* a refraction needs wo and wi on opposite sides of h, a reflection the
     * same side (and so does a thin wall's transmission, mirrored) */
    st_li valid = wo.z > 0.0f && oh > 0.0f && ST_SELECT(ST_W, ih < 0.0f, ih > 0.0f, as_refl) &&
                  wi.z != 0.0f;
    for (int k = 0; k < 3; k++)
        f[k] = ST_SELECT(ST_W, ST_LF(0.0f), ST_SELECT(ST_W, d->tint[k] * t, fr * dv, refl),
                         valid);
}

/* The density with which st_dielectric_sample chooses wi. */
ST_FN st_lf st_dielectric_pdf(const st_dielectric *d, st_lf alpha, st_dir wo, st_dir wi)
{
    st_li refl = wi.z > 0.0f;
    /* a thin wall's transmission is its reflection mirrored: wr */
    st_dir wr = st_lv3_select(wi, st_mirror_z(wi), d->thin && !refl);
    st_li as_refl = refl || d->thin;
    st_dir hr = st_half_vector(wo, wr), ht = st_refraction_half(wo, wi, d->eta);
    st_dir h = st_lv3_select(ht, hr, as_refl);
    st_lf oh = wo.x * h.x + wo.y * h.y + wo.z * h.z, ih = wr.x * h.x + wr.y * h.y + wr.z * h.z;
    st_lf fr = st_fresnel_dielectric(ST_FMAXF(oh, 0.0f), d->eta);
    fr = ST_SELECT(ST_W, fr, 2.0f * fr / (1.0f + fr), d->thin);
    st_lf vis = st_ggx_g1(alpha, wo) * oh * st_ggx_d(alpha, h) / wo.z;
    st_lf den = oh + d->eta * ih;
    st_lf pr = ST_SELECT(ST_W, fr, 1.0f - fr, d->thin && !refl) * vis / (4.0f * oh);
    st_lf pt = (1.0f - fr) * vis * d->eta * d->eta * ST_FABSF(ih) / (den * den);
    st_li valid = wo.z > 0.0f && oh > 0.0f && ST_SELECT(ST_W, ih < 0.0f, ih > 0.0f, as_refl) &&
                  wi.z != 0.0f;
    return ST_SELECT(ST_W, ST_LF(0.0f), ST_SELECT(ST_W, pt, pr, as_refl), valid);
}

/* A direction from the lobe: a visible normal from (u1, u2), then
 * reflection where u3 < F, else refraction. A reflection that ends below
 * the surface or a refraction above it is lost (0, 0, 0: every pdf and f
 * is 0 there), so that each direction has the one half vector the pdf
 * gives it. */
ST_FN st_dir st_dielectric_sample(const st_dielectric *d, st_lf alpha, st_dir wo, st_lf u1,
                                  st_lf u2, st_lf u3)
{
    st_dir h = st_ggx_visible_normal(alpha, alpha, wo, u1, u2);
    st_lf oh = wo.x * h.x + wo.y * h.y + wo.z * h.z;
    st_lf fr = st_fresnel_dielectric(ST_FMAXF(oh, 0.0f), d->eta);
    fr = ST_SELECT(ST_W, fr, 2.0f * fr / (1.0f + fr), d->thin);
    st_li refl = u3 < fr;
    st_dir r = st_reflect(wo, h);
    st_dir t = st_lv3_select(st_refract(wo, h, d->eta), st_mirror_z(r), d->thin);
    st_dir wi = st_lv3_select(t, r, refl);
    st_li kept = ST_SELECT(ST_W, wi.z < 0.0f, wi.z > 0.0f, refl);
    return st_lv3_select(st_lv3_make(ST_LF(0.0f), ST_LF(0.0f), ST_LF(0.0f)), wi, kept);
}

/* ---- the whole material: bsdf.h's BRDF plus the lobe ---------------------- */

/* f(wo, wi) of the material into f[3]: the BRDF (made with the transmission,
 * 0 below the surface) plus the lobe's weight x the lobe. */
ST_FN void st_bsdf_eval(const st_brdf *b, const st_dielectric *d, st_dir wo, st_dir wi, st_lf *f)
{
    st_lf fb[3], fd[3];
    st_brdf_eval(b, wo, wi, fb);
    st_dielectric_eval(d, b->alpha, wo, wi, fd);
    for (int k = 0; k < 3; k++)
        f[k] = fb[k] + d->weight * fd[k];
}

/* The mixture's density: the lobe with probability its weight, the BRDF's
 * sampling otherwise. */
ST_FN st_lf st_bsdf_pdf(const st_brdf *b, const st_dielectric *d, st_dir wo, st_dir wi)
{
    return (1.0f - d->weight) * st_brdf_pdf(b, wo, wi) +
           d->weight * st_dielectric_pdf(d, b->alpha, wo, wi);
}

/* A direction from the mixture: u1 below the lobe's weight picks the lobe
 * (u1 rescaled, as st_brdf_sample does between its lobes), else the BRDF. */
ST_FN st_dir st_bsdf_sample(const st_brdf *b, const st_dielectric *d, st_dir wo, st_lf u1,
                            st_lf u2, st_lf u3)
{
    st_lf w = d->weight;
    st_li lobe = u1 < w;
    st_dir wi = wo;
    if (ST_ANY(ST_W, !lobe)) { /* the BRDF's below the surface are lost, as the lobe's,
                                  but where its Lambertian part transmits */
        wi = st_brdf_sample(b, wo, ST_FMINF((u1 - w) / (1.0f - w), 0.99999994f), u2);
        wi = st_lv3_select(wi, st_lv3_make(ST_LF(0.0f), ST_LF(0.0f), ST_LF(0.0f)),
                           wi.z <= 0.0f && !st_brdf_transmits(b));
    }
    if (ST_ANY(ST_W, lobe))
        wi = st_lv3_select(
            wi, st_dielectric_sample(d, b->alpha, wo, ST_FMINF(u1 / w, 0.99999994f), u2, u3),
            lobe);
    return wi;
}

#endif
