/* bsdf_sheen.h — KHR_materials_sheen: a layer of fibres over the whole
 * material of bsdf_dielectric.h (and under bsdf_coat.h's clear coat, as
 * the extension orders them). Written over lanes like bsdf.h;
 * tests/unit/test_bsdf.c runs it on the host.
 *
 * The sheen lobe is the specification's: colour x D V with the "Charlie"
 * distribution and visibility of Estevez & Kulla ("Production Friendly
 * Microfacet Sheen BRDF", 2017), α = sheenRoughness²,
 *   D(h) = (2 + 1/α) sin(θh)^(1/α) / (2π),
 *   V = 1 / ((1 + Λ(wo) + Λ(wi)) 4 |wo.z| |wi.z|),
 *   Λ(μ) = exp(L(μ)) below μ = 0.5, else exp(2 L(0.5) - L(1 - μ)),
 *   L(x) = a / (1 + b x^c) + d x + e,
 * the five coefficients interpolated between their α = 1 and α = 0 fits
 * by (1 - α)². The base beneath is scaled by the specification's albedo
 * scaling, symmetric in wo and wi (so reciprocity holds under the sheen):
 *   f = colour D V + f_base max(0, 1 - max3(colour) max(E(|wo.z|), E(|wi.z|))),
 * with E the lobe's directional albedo (white colour) from sheen_table.h
 * (bilinear in (sqrt cos θ, sheenRoughness)). The max(0, ..) is needed:
 * this visibility lets the lobe reflect more than it receives at grazing
 * angles when the sheen is smooth (E up to about 6 below cos θ 0.01 at
 * sheenRoughness 0; E > 1 only up to about sheenRoughness 0.26 and cos θ 0.06).
 *
 * The powers and exponentials are computed lane by lane in scalar (the
 * accurate pow and exp of one float): PoCL's vector pow and exp round
 * differently from its scalar ones in the last bits, and a lane must
 * compute at every width what it computes at width 1; the table is read
 * lane by lane too.
 *
 * Sampling: the sheen lobe by a cosine-weighted direction with probability
 * st_sheen_prob (max3(colour) E(wo.z), kept inside [0.1, 0.9]), else the
 * base's own sampling; the pdf is the mixture's. A lane whose sheen colour
 * is black takes probability 0 and keeps the base's numbers bit for bit.
 * This file follows bsdf_dielectric.h and precedes bsdf_coat.h. */
#ifndef ST_BSDF_SHEEN_H
#define ST_BSDF_SHEEN_H

#include "sheen_table.h"

/* The least α: D's exponent 1 / (2α) stays at 500 (sheen_table.h's rows
 * use the same). */
#define ST_SHEEN_MIN_ALPHA 1e-3f

/* The sheen at one point. */
typedef struct st_sheen {
    st_lf colour[3]; /* sheenColorFactor x texture, in [0, 1] */
    st_lf peak;      /* max3 colour: the albedo scaling's weight; 0: no sheen */
    st_lf rough;     /* sheenRoughness x texture, in [0, 1]: the table's row */
    st_lf alpha;     /* rough², at least ST_SHEEN_MIN_ALPHA */
} st_sheen;

ST_FN st_sheen st_sheen_make(const st_lf *colour, st_lf roughness)
{
    st_sheen s;
    for (int k = 0; k < 3; k++)
        s.colour[k] = st_clamp01(colour[k]);
    s.peak = st_max3(s.colour);
    s.rough = st_clamp01(roughness);
    s.alpha = ST_FMAXF(s.rough * s.rough, ST_SHEEN_MIN_ALPHA);
    return s;
}

/* ---- one lane's terms, in scalar -------------------------------------------- */

/* The fit L(x) at α. */
ST_FN float st_sheen_fit(float x, float alpha)
{
    float t = (1.0f - alpha) * (1.0f - alpha);
    float a = 21.5473f + (25.3245f - 21.5473f) * t, b = 3.82987f + (3.32435f - 3.82987f) * t;
    float c = 0.19823f + (0.16801f - 0.19823f) * t, d = -1.97760f + (-1.27393f + 1.97760f) * t;
    float e = -4.32054f + (-4.85967f + 4.32054f) * t;
    return a / (1.0f + b * ST_POWF(x, c)) + d * x + e;
}

/* Λ(μ) for a cosine μ in [0, 1]. */
ST_FN float st_sheen_lambda(float mu, float alpha)
{
    float l = mu < 0.5f ? st_sheen_fit(mu, alpha)
                        : 2.0f * st_sheen_fit(0.5f, alpha) - st_sheen_fit(1.0f - mu, alpha);
    return ST_EXPF(l);
}

/* D V for cosines oz, iz (0 unless both > 0) and sin² θh = s2. */
ST_FN float st_sheen_dv1(float alpha, float oz, float iz, float s2)
{
    if (!(oz > 0.0f && iz > 0.0f))
        return 0.0f;
    float d = (2.0f + 1.0f / alpha) * ST_POWF(s2, 0.5f / alpha) / (2.0f * ST_PI_F);
    float g = 1.0f + st_sheen_lambda(oz, alpha) + st_sheen_lambda(iz, alpha);
    return d / (g * 4.0f * oz * iz);
}

/* E(μ) at sheenRoughness r from sheen_table.h, bilinear in (sqrt μ, r). */
ST_FN float st_sheen_albedo1(float r, float mu)
{
    const float last = (float)(ST_SHEEN_TABLE_N - 1u);
    float x = ST_SQRTF(ST_FMINF(ST_FMAXF(mu, 0.0f), 1.0f)) * last;
    float y = ST_FMINF(ST_FMAXF(r, 0.0f), 1.0f) * last;
    int i = (int)x, j = (int)y;
    i = i < (int)ST_SHEEN_TABLE_N - 2 ? i : (int)ST_SHEEN_TABLE_N - 2;
    j = j < (int)ST_SHEEN_TABLE_N - 2 ? j : (int)ST_SHEEN_TABLE_N - 2;
    float fx = x - (float)i, fy = y - (float)j;
    int at = j * (int)ST_SHEEN_TABLE_N + i;
    float e0 = st_sheen_albedo_table[at] +
               (st_sheen_albedo_table[at + 1] - st_sheen_albedo_table[at]) * fx;
    float e1 = st_sheen_albedo_table[at + ST_SHEEN_TABLE_N] +
               (st_sheen_albedo_table[at + ST_SHEEN_TABLE_N + 1] -
                st_sheen_albedo_table[at + ST_SHEEN_TABLE_N]) *
                   fx;
    return e0 + (e1 - e0) * fy;
}

/* ---- in lanes: each lane its own scalar terms ------------------------------- */

ST_FN st_lf st_sheen_albedo(st_lf r, st_lf mu)
{
#if ST_W == 1
    return st_sheen_albedo1(r, mu);
#else
    float ra[ST_W], ma[ST_W];
    ST_VSTORE(ST_W, r, ra);
    ST_VSTORE(ST_W, mu, ma);
    for (int k = 0; k < ST_W; k++)
        ma[k] = st_sheen_albedo1(ra[k], ma[k]);
    return ST_VLOAD(ST_W, ma);
#endif
}

/* The lobe D V (white; 0 unless wo and wi both lie above). */
ST_FN st_lf st_sheen_lobe(const st_sheen *s, st_dir wo, st_dir wi)
{
    st_lf hx = wo.x + wi.x, hy = wo.y + wi.y, hz = wo.z + wi.z;
    st_lf t2 = hx * hx + hy * hy, s2 = t2 / (t2 + hz * hz);
#if ST_W == 1
    return st_sheen_dv1(s->alpha, wo.z, wi.z, s2);
#else
    float aa[ST_W], oa[ST_W], ia[ST_W], sa[ST_W];
    ST_VSTORE(ST_W, s->alpha, aa);
    ST_VSTORE(ST_W, wo.z, oa);
    ST_VSTORE(ST_W, wi.z, ia);
    ST_VSTORE(ST_W, s2, sa);
    for (int k = 0; k < ST_W; k++)
        sa[k] = st_sheen_dv1(aa[k], oa[k], ia[k], sa[k]);
    return ST_VLOAD(ST_W, sa);
#endif
}

/* What the sheen leaves of the base's f(wo, wi): the albedo scaling. */
ST_FN st_lf st_sheen_pass(const st_sheen *s, st_dir wo, st_dir wi)
{
    st_lf eo = st_sheen_albedo(s->rough, ST_FABSF(wo.z));
    st_lf ei = st_sheen_albedo(s->rough, ST_FABSF(wi.z));
    return ST_FMAXF(0.0f, 1.0f - s->peak * ST_FMAXF(eo, ei));
}

/* The probability of sampling the sheen lobe towards wo (0 without sheen). */
ST_FN st_lf st_sheen_prob(const st_sheen *s, st_dir wo)
{
    st_lf p = s->peak * st_sheen_albedo(s->rough, wo.z);
    p = ST_FMINF(ST_FMAXF(p, 0.1f), 0.9f);
    return ST_SELECT(ST_W, ST_LF(0.0f), p, s->peak > 0.0f);
}

/* ---- the material under its sheen: the sheen over bsdf_dielectric.h's whole - */

ST_FN void st_sheened_eval(const st_brdf *b, const st_dielectric *d, const st_sheen *s,
                           st_dir wo, st_dir wi, st_lf *f)
{
    st_bsdf_eval(b, d, wo, wi, f);
    st_li on = s->peak > 0.0f;
    if (!ST_ANY(ST_W, on))
        return;
    st_lf pass = st_sheen_pass(s, wo, wi), lobe = st_sheen_lobe(s, wo, wi);
    for (int k = 0; k < 3; k++)
        f[k] = ST_SELECT(ST_W, f[k], f[k] * pass + s->colour[k] * lobe, on);
}

ST_FN st_lf st_sheened_pdf(const st_brdf *b, const st_dielectric *d, const st_sheen *s,
                           st_dir wo, st_dir wi)
{
    st_lf p = st_bsdf_pdf(b, d, wo, wi);
    st_li on = s->peak > 0.0f;
    if (!ST_ANY(ST_W, on))
        return p;
    st_lf ps = st_sheen_prob(s, wo);
    st_lf cosine = ST_SELECT(ST_W, ST_LF(0.0f), wi.z / ST_PI_F, wo.z > 0.0f && wi.z > 0.0f);
    return ST_SELECT(ST_W, p, (1.0f - ps) * p + ps * cosine, on);
}

/* u1 below st_sheen_prob picks the sheen's cosine lobe (u1 rescaled), else
 * the base with u1 rescaled to the rest (unchanged where the probability
 * is 0). */
ST_FN st_dir st_sheened_sample(const st_brdf *b, const st_dielectric *d, const st_sheen *s,
                               st_dir wo, st_lf u1, st_lf u2, st_lf u3)
{
    if (!ST_ANY(ST_W, s->peak > 0.0f))
        return st_bsdf_sample(b, d, wo, u1, u2, u3);
    st_lf p = st_sheen_prob(s, wo);
    st_li sheen = u1 < p;
    st_dir wi = wo;
    if (ST_ANY(ST_W, !sheen))
        wi = st_bsdf_sample(b, d, wo, ST_FMINF((u1 - p) / (1.0f - p), 0.99999994f), u2, u3);
    if (ST_ANY(ST_W, sheen))
        wi = st_lv3_select(wi, st_cosine_sample(ST_FMINF(u1 / p, 0.99999994f), u2), sheen);
    return wi;
}

#endif
