/* envmap.h — the equirectangular environment map as both sides use it: the
 * mapping between directions and map coordinates, the rotation about +Y,
 * and the piecewise-constant distribution that importance-samples it.
 * Compiled by the host (src/render/envmap.c builds the tables; the tests sample
 * and check them) and the kernels (shade.cl), so both run the same code.
 * Include after st_shared.h.
 *
 * Convention (tools/make_envmap.c's compass map shows it): +Y is up; map
 * coordinates (u, v) in [0, 1]², u across the image from its left edge, v down from its top row.
 * v = 0 is +Y, v = 1 is -Y (θ = π v from +Y). The centre column u = 1/2
 * looks along -Z (where a glTF camera looks), u = 3/4 along +X, u = 1/4
 * along -X, and the left and right edges meet at +Z: seen from inside,
 * looking along -Z with +Y up, the image appears as it is drawn, not
 * mirrored (Mitsuba 3's convention turned by half a turn: Mitsuba's centre
 * is +Z). d(u, v) = (sin θ sin φ, cos θ, -sin θ cos φ), φ = 2π (u - 1/2).
 *
 * The rotation (--env-rotate a) turns the map by a about +Y, right-handed
 * (from +Z towards +X): a feature the map puts at direction d is seen at
 * R_y(a) d. rot = (cos a, sin a).
 *
 * The distribution: texel (i, j) of a w x h map has weight f_ij = its
 * luminance times sin θ_j (θ_j at the row's centre: the sphere's area
 * element), p(u, v) = w h f_ij / Σ f. Rows are chosen by the marginal CDF,
 * columns by the row's conditional CDF (pbrt's Distribution2D, our code),
 * and the density of a direction in solid angle is p(u, v) / (2π² sin θ),
 * θ the direction's own (the Jacobian of (u, v) -> d). The table is one
 * float array: h entries of the marginal CDF, then h rows of w entries of
 * the conditional CDFs; each CDF's last entry is 1. Probabilities are
 * taken as differences of these CDFs, the very numbers the sampling uses,
 * so the pdf matches the sampling exactly. Radiance is looked up at the
 * nearest texel, the same cells. */
#ifndef ST_ENVMAP_H
#define ST_ENVMAP_H

/* Index of the first entry of cdf[0..n) above *u (the interval holding *u)
 * and *u rescaled to [0, 1) within that interval. A zero-width interval is
 * never chosen. */
ST_FN st_u32 st_cdf_pick(ST_GLOBAL const float *cdf, st_u32 n, float *u)
{
    st_u32 lo = 0, hi = n - 1u;
    while (lo < hi) {
        st_u32 mid = (lo + hi) / 2u;
        if (cdf[mid] > *u)
            hi = mid;
        else
            lo = mid + 1u;
    }
    float c0 = lo ? cdf[lo - 1u] : 0.0f, c1 = cdf[lo];
    *u = c1 > c0 ? fmin((*u - c0) / (c1 - c0), 0.99999994f) : 0.0f;
    return lo;
}

/* The probability of interval k of cdf. */
ST_FN float st_cdf_prob(ST_GLOBAL const float *cdf, st_u32 k)
{
    return cdf[k] - (k ? cdf[k - 1u] : 0.0f);
}

/* The direction d (unit, the map's frame) of map coordinates (u, v). */
ST_FN void st_env_direction(float u, float v, float d[3])
{
    float phi = 2.0f * ST_PI_F * (u - 0.5f), theta = ST_PI_F * v;
    float st = sin(theta);
    d[0] = st * sin(phi);
    d[1] = cos(theta);
    d[2] = -st * cos(phi);
}

/* The map coordinates (u, v) in [0, 1] of the unit direction d. */
ST_FN void st_env_coords(const float d[3], float *u, float *v)
{
    float y = fmin(fmax(d[1], -1.0f), 1.0f);
    *u = 0.5f + atan2(d[0], -d[2]) * (0.5f / ST_PI_F);
    *v = acos(y) * (1.0f / ST_PI_F);
}

/* The map's frame from the world's (inverse: sign of rot[1] turned), or the
 * world's from the map's (dir = 1): R_y(±a). */
ST_FN void st_env_rotate(const float rot[2], int to_world, const float in[3], float out[3])
{
    float c = rot[0], s = to_world ? rot[1] : -rot[1];
    float x = c * in[0] + s * in[2], z = -s * in[0] + c * in[2];
    out[0] = x;
    out[1] = in[1];
    out[2] = z;
}

/* The texel (column *i, row *j) holding map coordinates (u, v). */
ST_FN void st_env_texel(st_u32 w, st_u32 h, float u, float v, st_u32 *i, st_u32 *j)
{
    *i = (st_u32)fmin(fmax(u * (float)w, 0.0f), (float)(w - 1u));
    *j = (st_u32)fmin(fmax(v * (float)h, 0.0f), (float)(h - 1u));
}

/* p(u, v) of texel (i, j): its probability times w h. */
ST_FN float st_env_texel_pdf(ST_GLOBAL const float *cdf, st_u32 w, st_u32 h, st_u32 i, st_u32 j)
{
    return st_cdf_prob(cdf, j) * st_cdf_prob(cdf + h + (size_t)j * w, i) * (float)w * (float)h;
}

/* Map coordinates from (u1, u2) in [0, 1)²: the row by u1 (marginal), the
 * column by u2 (that row's conditional), each placed uniformly within its
 * cell by the rescaled number. Returns p(u, v) (st_env_texel_pdf). */
ST_FN float st_env_sample(ST_GLOBAL const float *cdf, st_u32 w, st_u32 h, float u1, float u2,
                          float *u, float *v)
{
    st_u32 j = st_cdf_pick(cdf, h, &u1);
    st_u32 i = st_cdf_pick(cdf + h + (size_t)j * w, w, &u2);
    *u = ((float)i + u2) / (float)w;
    *v = ((float)j + u1) / (float)h;
    return st_env_texel_pdf(cdf, w, h, i, j);
}

/* The density in solid angle of p(u, v) at polar angle θ = π v: p / (2π²
 * sin θ); 0 at the poles (where the sampling never lands). */
ST_FN float st_env_solid_angle_pdf(float p_uv, float v)
{
    float st = sin(ST_PI_F * v);
    return st > 0.0f ? p_uv / (2.0f * ST_PI_F * ST_PI_F * st) : 0.0f;
}

#endif
