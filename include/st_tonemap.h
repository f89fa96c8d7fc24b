/* st_tonemap.h — from linear radiance to the [0, 1] display range of an 8-bit PNG: an exposure
 * and a tone curve. An EXR stays linear; only the PNG path calls this.
 *
 *   exposure:  c' = c * 2^EV                                   (each of R, G, B)
 *   clamp:     c' unchanged; the sRGB encoder clips at 1       (the default: a hard clip)
 *   reinhard:  c' = c / (1 + L), L = 0.2126 R + 0.7152 G + 0.0722 B   (Reinhard et al. 2002,
 *              "Photographic tone reproduction", eq. 3, applied to luminance so hue is kept;
 *              Rec. 709 luminance weights)
 *   filmic:    c' = h(c) / h(W), h(x) = (x(Ax + CB) + DE) / (x(Ax + B) + DF) - E/F, per channel,
 *              A = 0.15, B = 0.50, C = 0.10, D = 0.20, E = 0.02, F = 0.30, W = 11.2 (Hable 2010,
 *              "Filmic tonemapping operators", without its exposure bias: use --exposure)
 */
#ifndef ST_TONEMAP_H
#define ST_TONEMAP_H

#include <stddef.h>

typedef enum { ST_TONEMAP_CLAMP = 0, ST_TONEMAP_REINHARD, ST_TONEMAP_FILMIC, ST_TONEMAP_COUNT } st_tonemap;

extern const char *const st_tonemap_names[ST_TONEMAP_COUNT]; /* "clamp", "reinhard", "filmic" */

/* Applies the exposure, then the curve, in place to n interleaved RGB triples (stride floats
 * apart, stride >= 3). Non-finite values are left to the encoder (which maps NaN to 0). */
void st_tonemap_apply(float *rgb, size_t n, size_t stride, float exposure_ev, st_tonemap curve);

#endif
