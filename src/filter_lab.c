/* filter_lab.c — filter profiles and frequency responses (st_filter_lab.h). */
#include "st_filter_lab.h"

#include <math.h>

#include "filters.h"

#define SIMPSON_INTERVALS 4096

void st_filter_profile(const st_filter *f, st_u32 n, double *x, double *y)
{
    double r = f->radius;
    for (st_u32 i = 0; i < n; i++) {
        x[i] = -r + 2.0 * r * i / (n - 1);
        y[i] = st_filter_eval_1d(f, (float)x[i]);
    }
}

/* ∫_{-r}^{r} f(x) cos(2πωx) dx by composite Simpson. */
static double cosine_transform(const st_filter *f, double omega)
{
    double r = f->radius, h = 2.0 * r / SIMPSON_INTERVALS, sum = 0.0;
    for (int i = 0; i <= SIMPSON_INTERVALS; i++) {
        double x = -r + i * h;
        double w = (i == 0 || i == SIMPSON_INTERVALS) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        /* the support is open at ±r: f(±r) = 0 except for the box, whose ends
         * take half weight as the limit of the jump */
        double v = (i == 0 || i == SIMPSON_INTERVALS) ? 0.5 * st_filter_eval_1d(f, (float)(x * (1 - 1e-7)))
                                                       : st_filter_eval_1d(f, (float)x);
        sum += w * v * cos(2.0 * 3.14159265358979323846 * omega * x);
    }
    return sum * h / 3.0;
}

void st_filter_response(const st_filter *f, st_u32 n, const double *omega, double *magnitude)
{
    double dc = cosine_transform(f, 0.0);
    for (st_u32 i = 0; i < n; i++)
        magnitude[i] = fabs(cosine_transform(f, omega[i]) / dc);
}
