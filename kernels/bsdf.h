/* bsdf.h — the surface's scattering: Lambertian, f = albedo / π, sampled
 * cosine-weighted (Malley's method), so f cos / pdf = albedo. OpenCL only
 * (shade.cl). */
#ifndef ST_BSDF_H
#define ST_BSDF_H

/* Orthonormal basis around n (Duff et al., "Building an Orthonormal Basis,
 * Revisited", JCGT 6(1), 2017). */
static void basis(float3 n, float3 *t, float3 *b)
{
    float s = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (s + n.z), c = n.x * n.y * a;
    *t = (float3)(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
    *b = (float3)(c, s + n.y * n.y * a, -n.y);
}

/* A cosine-distributed direction around ns from (u1, u2); *cos_theta gets
 * its cosine to ns (pdf = cos_theta / π). native_: the device's fast sine,
 * deterministic on one device; the accurate one's argument reduction cost a
 * tenth of the frame on PoCL. */
static float3 cosine_direction(float3 ns, float u1, float u2, float *cos_theta)
{
    float r = sqrt(u1), phi = 2.0f * ST_PI_F * u2;
    float3 tu, tv;
    basis(ns, &tu, &tv);
    float cz = sqrt(fmax(0.0f, 1.0f - u1));
    *cos_theta = cz;
    return normalize(r * native_cos(phi) * tu + r * native_sin(phi) * tv + cz * ns);
}

static float power_heuristic(float a, float b)
{
    return a * a / (a * a + b * b);
}

#endif
