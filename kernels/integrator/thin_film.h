/* thin_film.h — the Fresnel reflectance of a thin dielectric film over a
 * surface: KHR_materials_iridescence's, after Belcour & Barla, "A Practical
 * Extension to Microfacet Theory for the Modeling of Varying Iridescence"
 * (SIGGRAPH 2017), as the extension's specification adapts it to RGB.
 * Written over lanes (lanes.h) and compiled as C11 too, so that
 * tests/unit/test_thin_film.c runs the device's own code.
 *
 * Light arrives from a medium of ior 1 at cos θ1 on a film of ior n2 and
 * thickness d (nanometres) over a base whose reflectance at normal
 * incidence is F0 per channel (read as the ior n3 = (1 + √F0) / (1 - √F0)).
 * The film's ior goes from 1 at d = 0 to n2 at d >= 0.03 nm (smoothstep),
 * so that no film is no film. Snell gives cos θ2 inside; the first
 * interface reflects R12 = the exact dielectric Fresnel of 1 -> n2 at θ1
 * and passes T121 = 1 - R12 (there and back), the second R23 = Schlick's
 * of ((n3 - n2) / (n3 + n2))² at θ2; the phase shifts by φ12 = π where
 * the film is less dense than the outside (else 0), φ21 = π - φ12, and
 * φ23 = π where the base is less dense than the film. The Airy sum of the multiply reflected waves,
 * its DC term and first two harmonics integrated against the CIE XYZ
 * matching functions (Belcour & Barla's Gaussian fits of their Fourier
 * transforms) and turned to linear Rec. 709 RGB, is
 *   I = R12 + Rs + Σ_{m=1,2} 2 C_m S_m,  Rs = T121² R23 / (1 - R12 R23),
 *   C_m = (Rs - T121) (R12 R23)^(m/2),  S_m = S(m OPD, m φ),
 *   OPD = 2 n2 d cos θ2,  φ = φ21 + φ23,
 * and 1 past the film's critical angle. Two departures from the
 * specification's sample code, both for its zero-thickness limit: R12 is
 * the exact Fresnel (Schlick's is not 0 at grazing angles for equal iors)
 * and R12 R23 is not held above 1e-5, so that d = 0 gives the base's
 * Schlick reflectance exactly (tests/unit/test_thin_film.c). */
#ifndef ST_THIN_FILM_H
#define ST_THIN_FILM_H

#ifndef __OPENCL_VERSION__
#include "st_shared.h"
#endif
#include "lanes.h"

/* The unpolarised Fresnel reflectance of a dielectric interface at cos_i
 * (>= 0) on the incident side, η = η(transmitted side) / η(incident side);
 * 1 past the critical angle. */
ST_FN st_lf st_fresnel_dielectric(st_lf cos_i, st_lf eta)
{
    st_lf sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
    st_lf cos_t = ST_SQRTF(ST_FMAXF(0.0f, 1.0f - sin2_t));
    st_lf rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    st_lf rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return ST_SELECT(ST_W, 0.5f * (rs * rs + rp * rp), ST_LF(1.0f), sin2_t >= 1.0f);
}

/* exp of each lane, one lane at a time: a vector exp may round its lanes
 * otherwise than the scalar one, and a lane must compute at every width
 * what it computes at width 1. */
ST_FN st_lf st_exp_by_lane(st_lf x)
{
    float a[ST_W];
    ST_VSTORE(ST_W, x, a);
    for (int k = 0; k < ST_W; k++)
        a[k] = ST_EXPF(a[k]);
    return ST_VLOAD(ST_W, a);
}

/* S(OPD, shift): the spectral sensitivity of a wave of optical path
 * difference opd (nm) and phase shifts shift[3] (applied to X, Y and Z),
 * in linear Rec. 709 RGB (Belcour & Barla 2017, their fit of the XYZ
 * matching functions' Fourier transforms by Gaussians: at phase
 * p = 2π opd 10^-9, X, Y, Z = v sqrt(2π s) cos(c p + shift) exp(-s p²),
 * X with a second Gaussian, all over 1.0685e-7). */
ST_FN void st_film_sensitivity(st_lf opd, const st_lf *shift, st_lf *rgb)
{
    const float v[3] = {5.4856e-13f, 4.4201e-13f, 5.2481e-13f};
    const float c[3] = {1.6810e+06f, 1.7953e+06f, 2.2084e+06f};
    const float s[3] = {4.3278e+09f, 9.3046e+09f, 6.6121e+09f};
    st_lf p = 2.0f * ST_PI_F * opd * 1e-9f, xyz[3];
    for (int k = 0; k < 3; k++)
        xyz[k] = v[k] * ST_SQRTF(2.0f * ST_PI_F * s[k]) * ST_COSF(c[k] * p + shift[k]) *
                 st_exp_by_lane(-s[k] * p * p);
    xyz[0] += 9.7470e-14f * ST_SQRTF(2.0f * ST_PI_F * 4.5282e+09f) *
              ST_COSF(2.2399e+06f * p + shift[0]) * st_exp_by_lane(-4.5282e+09f * p * p);
    for (int k = 0; k < 3; k++)
        xyz[k] = xyz[k] / 1.0685e-7f;
    rgb[0] = 3.2404542f * xyz[0] - 1.5371385f * xyz[1] - 0.4985314f * xyz[2];
    rgb[1] = -0.9692660f * xyz[0] + 1.8760108f * xyz[1] + 0.0415560f * xyz[2];
    rgb[2] = 0.0556434f * xyz[0] - 0.2040259f * xyz[1] + 1.0572252f * xyz[2];
}

/* The film's reflectance into out[3] at cos1 = cos θ1 in [0, 1], for a
 * film of ior n2 and thickness d nm over a base of normal reflectance
 * f0[3] (the file's head gives the formula). */
ST_FN void st_thin_film(st_lf n2, st_lf d, st_lf cos1, const st_lf *f0, st_lf *out)
{
    st_lf t = ST_FMINF(ST_FMAXF(d / 0.03f, 0.0f), 1.0f);
    n2 = 1.0f + (n2 - 1.0f) * (t * t * (3.0f - 2.0f * t));
    st_lf sin2 = (1.0f - cos1 * cos1) / (n2 * n2);
    st_li tir = sin2 >= 1.0f;
    st_lf cos2 = ST_SQRTF(ST_FMAXF(0.0f, 1.0f - sin2));
    st_lf r12 = st_fresnel_dielectric(cos1, n2), t121 = 1.0f - r12;
    /* φ12 = π off a denser film, φ21 = π - φ12 back out of it */
    st_lf phi21 = ST_SELECT(ST_W, ST_LF(ST_PI_F), ST_LF(0.0f), n2 < 1.0f);
    st_lf opd = 2.0f * n2 * d * cos2, x = 1.0f - cos2, x5 = x * x * x * x * x;
    st_lf rs[3], cm[3], r123[3], shift[3];
    for (int k = 0; k < 3; k++) {
        st_lf q = ST_SQRTF(ST_FMINF(ST_FMAXF(f0[k], 0.0f), 0.9999f));
        st_lf n3 = (1.0f + q) / (1.0f - q), a = (n3 - n2) / (n3 + n2), r1 = a * a;
        st_lf r23 = r1 + (1.0f - r1) * x5;
        shift[k] = phi21 + ST_SELECT(ST_W, ST_LF(0.0f), ST_LF(ST_PI_F), n3 < n2);
        r123[k] = ST_FMINF(r12 * r23, 0.9999f);
        rs[k] = t121 * t121 * r23 / (1.0f - r123[k]);
        out[k] = r12 + rs[k];
        cm[k] = rs[k] - t121;
    }
    for (int m = 1; m <= 2; m++) {
        st_lf sm[3], sh[3];
        for (int k = 0; k < 3; k++) {
            cm[k] = cm[k] * ST_SQRTF(r123[k]);
            sh[k] = (float)m * shift[k];
        }
        st_film_sensitivity((float)m * opd, sh, sm);
        for (int k = 0; k < 3; k++)
            out[k] = out[k] + cm[k] * 2.0f * sm[k];
    }
    for (int k = 0; k < 3; k++)
        out[k] = ST_SELECT(ST_W, ST_FMAXF(out[k], 0.0f), ST_LF(1.0f), tir);
}

#endif
