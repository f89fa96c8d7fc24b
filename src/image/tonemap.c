/* tonemap.c — exposure and tone curves (see st_tonemap.h for the definitions). */
#include "st_tonemap.h"

#include <math.h>

const char *const st_tonemap_names[ST_TONEMAP_COUNT] = {"clamp", "reinhard", "filmic"};

/* Hable's curve before its white-point normalisation. */
static double hable(double x)
{
    const double A = 0.15, B = 0.50, C = 0.10, D = 0.20, E = 0.02, F = 0.30;
    return (x * (A * x + C * B) + D * E) / (x * (A * x + B) + D * F) - E / F;
}

void st_tonemap_apply(float *rgb, size_t n, size_t stride, float exposure_ev, st_tonemap curve)
{
    const double scale = exp2((double)exposure_ev), white = hable(11.2);
    for (size_t i = 0; i < n; i++) {
        float *c = rgb + i * stride;
        double v[3] = {c[0] * scale, c[1] * scale, c[2] * scale};
        if (curve == ST_TONEMAP_REINHARD) {
            double lum = 0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2];
            double k = lum > 0 ? 1.0 / (1.0 + lum) : 1.0;
            for (int j = 0; j < 3; j++)
                v[j] *= k;
        } else if (curve == ST_TONEMAP_FILMIC) {
            for (int j = 0; j < 3; j++)
                v[j] = v[j] > 0 ? hable(v[j]) / white : 0.0;
        }
        for (int j = 0; j < 3; j++)
            c[j] = (float)v[j];
    }
}
