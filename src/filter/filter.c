/* filter.c — the filter module (st_filter.h): names, defaults, the parameter
 * check, and the quantities the host derives from the profile f(x). The
 * profile itself is kernels/film/filters.h's st_filter_eval_1d, shared with the
 * splat kernel, so every number here describes the filter that renders. */
#include "st_filter.h"

#include <math.h>
#include <string.h>

#include "filters.h"
#include "st_names.h"

#define PI 3.14159265358979323846
#define INTEGRAL_INTERVALS 65536
#define SIMPSON_INTERVALS 4096

const char *const st_filter_names[ST_FILTER_COUNT] = {
    "box", "triangle", "gaussian", "mitchell", "lanczos", "catmull-rom", "blackman-harris"};

int st_filter_lookup(const char *name)
{
    return st_name_lookup(st_filter_names, (int)ST_FILTER_COUNT, name);
}

st_filter st_filter_default(st_u32 kind)
{
    st_filter f;
    memset(&f, 0, sizeof f);
    f.kind = kind;
    f.b = f.c = 1.0f / 3.0f;
    f.sigma = 0.5f;
    static const float radius[ST_FILTER_COUNT] = {0.5f, 1.0f, 1.5f, 2.0f, 3.0f, 2.0f, 2.0f};
    f.radius = kind < ST_FILTER_COUNT ? radius[kind] : 0.5f;
    f.tau = f.radius;
    return f;
}

st_u32 st_filter_parameters(st_u32 kind)
{
    switch (kind) {
    case ST_FILTER_MITCHELL: return ST_FILTER_USES_BC;
    case ST_FILTER_GAUSSIAN: return ST_FILTER_USES_SIGMA;
    case ST_FILTER_LANCZOS: return ST_FILTER_USES_TAU;
    default: return 0u;
    }
}

/* A parameter inside its documented range (st_filter.h); NaN fails too. */
static st_status check_range(const char *field, float v, float lo, float hi, st_error *err)
{
    if (!(v >= lo && v <= hi))
        return st_fail(err, ST_ERR_USAGE, "filter %s %g: must be in [%g, %g]", field, (double)v,
                       (double)lo, (double)hi);
    return ST_OK;
}

st_status st_filter_check(const st_filter *f, float max_radius, st_error *err)
{
    if (f->kind >= ST_FILTER_COUNT)
        return st_fail(err, ST_ERR_USAGE, "filter kind %u: unknown", f->kind);
    if (check_range("radius", f->radius, ST_FILTER_MIN_RADIUS, max_radius, err) != ST_OK)
        return err->status;
    st_u32 uses = st_filter_parameters(f->kind);
    if ((uses & ST_FILTER_USES_BC) &&
        (check_range("b", f->b, ST_FILTER_BC_MIN, ST_FILTER_BC_MAX, err) != ST_OK ||
         check_range("c", f->c, ST_FILTER_BC_MIN, ST_FILTER_BC_MAX, err) != ST_OK))
        return err->status;
    if ((uses & ST_FILTER_USES_SIGMA) &&
        check_range("sigma", f->sigma, ST_FILTER_SIGMA_MIN, ST_FILTER_SIGMA_MAX, err) != ST_OK)
        return err->status;
    if ((uses & ST_FILTER_USES_TAU) &&
        check_range("tau", f->tau, ST_FILTER_TAU_MIN, ST_FILTER_TAU_MAX, err) != ST_OK)
        return err->status;
    return ST_OK;
}

double st_filter_integral(const st_filter *f)
{
    double r = f->radius, h = 2.0 * r / INTEGRAL_INTERVALS, sum = 0.0;
    for (int i = 0; i < INTEGRAL_INTERVALS; i++)
        sum += st_filter_eval_1d(f, (float)(-r + (i + 0.5) * h));
    return sum * h;
}

/* The running sums are rounded to float before the division, as the table
 * the renderer has always uploaded was: images depend on these exact bits. */
void st_filter_fis_cdf(const st_filter *f, float *cdf)
{
    double acc = 0.0, rad = f->radius;
    cdf[0] = 0.0f;
    for (st_u32 i = 0; i < ST_FIS_BINS; i++) {
        double x = -rad + (i + 0.5) * 2.0 * rad / ST_FIS_BINS;
        acc += fabs(st_filter_eval_1d(f, (float)x));
        cdf[i + 1] = (float)acc;
    }
    for (st_u32 i = 1; i <= ST_FIS_BINS; i++)
        cdf[i] = i == ST_FIS_BINS ? 1.0f : (float)(cdf[i] / acc);
}

void st_filter_profile(const st_filter *f, st_u32 n, double *x, double *y)
{
    double r = f->radius;
    for (st_u32 i = 0; i < n; i++) {
        x[i] = -r + 2.0 * r * i / (n - 1);
        y[i] = st_filter_eval_1d(f, (float)x[i]);
    }
}

/* Composite Simpson; 4096 intervals put the kinks of triangle (0) and
 * mitchell (±r/2) on interval ends. */
double st_filter_transform(const st_filter *f, double omega)
{
    double r = f->radius, h = 2.0 * r / SIMPSON_INTERVALS, sum = 0.0;
    for (int i = 0; i <= SIMPSON_INTERVALS; i++) {
        double x = -r + i * h;
        int end = i == 0 || i == SIMPSON_INTERVALS;
        double w = end ? 1.0 : (i % 2 ? 4.0 : 2.0);
        /* the integrand's end values are the limits from inside [-r, r],
         * which for the closed support (filters.h) are f(±r) too: 0 for
         * most kinds, 1 for the box (halving them, as the lab once did, lost
         * h/3 of the box's F(0): test_filter.c filter_transform_*) */
        float edge = i == 0 ? -f->radius : f->radius;
        double v = st_filter_eval_1d(f, end ? nextafterf(edge, 0.0f) : (float)x);
        sum += w * v * cos(2.0 * PI * omega * x);
    }
    return sum * h / 3.0;
}

void st_filter_response(const st_filter *f, st_u32 n, const double *omega, double *magnitude)
{
    double dc = st_filter_transform(f, 0.0);
    for (st_u32 i = 0; i < n; i++)
        magnitude[i] = fabs(st_filter_transform(f, omega[i]) / dc);
}
