/* make_envmap.c — writes an equirectangular environment map as a Radiance
 * .hdr (stb_image_write), in strata's convention (kernels/integrator/envmap.h: +Y up,
 * the centre column looking along -Z, the right quarter along +X):
 *   sky      an outdoor sky: a gradient from a pale horizon to a blue zenith,
 *            a sun disc of 2.5 degrees radius (radiance 250) at 40 degrees
 *            elevation towards (+X, +Z) (behind a camera that looks along -Z,
 *            over its right shoulder), a dim brown ground; a white surface
 *            facing the sun gets about π (sun 1.5, sky 1.4), as under a
 *            uniform environment of 1 (`make` puts it in build/envmaps/sky.hdr
 *            for the README's pictures)
 *   compass  the convention made visible: the quarter of the sphere around
 *            -Z red, +X green, +Z blue, -X yellow, bright above the horizon
 *            and dark below, with a dark line every 30 degrees of azimuth and
 *            elevation and a white horizon
 * OUT.png writes an 8-bit preview instead (radiance clamped to 1, sRGB).
 * Usage: make_envmap sky|compass OUT.hdr|OUT.png [WIDTH HEIGHT]   (default 512 x 256) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image_write.h> /* Debian: implementations live in libstb (-lstb) */

#define PI 3.14159265358979323846

/* The direction of map coordinates (u, v): kernels/integrator/envmap.h's formula,
 * written out here so that the tool does not depend on the renderer. */
static void direction(double u, double v, double d[3])
{
    double phi = 2.0 * PI * (u - 0.5), theta = PI * v;
    d[0] = sin(theta) * sin(phi);
    d[1] = cos(theta);
    d[2] = -sin(theta) * cos(phi);
}

static void sky(const double d[3], float c[3])
{
    static const double sun_elev = 40.0 * PI / 180.0, sun_radius = 2.5 * PI / 180.0;
    double s[3] = {cos(sun_elev) * sqrt(0.5), sin(sun_elev), cos(sun_elev) * sqrt(0.5)};
    double cos_sun = d[0] * s[0] + d[1] * s[1] + d[2] * s[2];
    if (cos_sun > cos(sun_radius)) {
        c[0] = 250.0f, c[1] = 237.5f, c[2] = 212.5f;
        return;
    }
    static const double horizon[3] = {0.55, 0.57, 0.6}, zenith[3] = {0.15, 0.27, 0.6},
                        ground[3] = {0.12, 0.10, 0.08};
    double t = d[1] > 0.0 ? pow(d[1], 0.5) : 0.0;
    for (int k = 0; k < 3; k++)
        c[k] = (float)(d[1] >= 0.0 ? horizon[k] + t * (zenith[k] - horizon[k]) : ground[k]);
}

static void compass(const double d[3], float c[3])
{
    static const float quarter[4][3] = {{1, 0.1f, 0.1f}, {0.1f, 1, 0.1f}, {0.1f, 0.2f, 1},
                                        {1, 0.9f, 0.1f}}; /* -Z, +X, +Z, -X */
    double az = atan2(d[0], -d[2]) * 180.0 / PI; /* 0 at -Z, 90 at +X */
    double el = asin(d[1] < -1.0 ? -1.0 : d[1] > 1.0 ? 1.0 : d[1]) * 180.0 / PI;
    int q = (int)floor((az + 45.0 + 360.0) / 90.0) % 4;
    double scale = el >= 0.0 ? 1.0 : 0.25;
    if (fabs(el) < 1.0)
        scale = 4.0; /* the horizon, white */
    else if (fabs(fmod(az + 360.0, 30.0)) < 0.7 || fabs(fmod(el + 90.0, 30.0)) < 0.7)
        scale = 0.05;
    for (int k = 0; k < 3; k++)
        c[k] = fabs(el) < 1.0 ? 1.0f : (float)(quarter[q][k] * scale);
    if (fabs(el) < 1.0)
        c[0] = c[1] = c[2] = (float)scale;
}

/* An 8-bit sRGB preview (IEC 61966-2-1 encoding of the clamped radiance). */
static int write_png(const char *path, int w, int h, const float *px)
{
    size_t n = 3 * (size_t)w * h;
    unsigned char *b = malloc(n);
    if (!b)
        return 0;
    for (size_t k = 0; k < n; k++) {
        double l = px[k] < 0.0f ? 0.0 : px[k] > 1.0f ? 1.0 : px[k];
        double v = l <= 0.0031308 ? 12.92 * l : 1.055 * pow(l, 1.0 / 2.4) - 0.055;
        b[k] = (unsigned char)(v * 255.0 + 0.5);
    }
    int ok = stbi_write_png(path, w, h, 3, b, 3 * w);
    free(b);
    return ok;
}

int main(int argc, char **argv)
{
    if (argc != 3 && argc != 5) {
        fprintf(stderr, "usage: make_envmap sky|compass OUT.hdr|OUT.png [WIDTH HEIGHT]\n");
        return 2;
    }
    int is_sky = !strcmp(argv[1], "sky");
    if (!is_sky && strcmp(argv[1], "compass")) {
        fprintf(stderr, "make_envmap: unknown map '%s' (sky or compass)\n", argv[1]);
        return 2;
    }
    int w = argc == 5 ? atoi(argv[3]) : 512, h = argc == 5 ? atoi(argv[4]) : 256;
    if (w < 1 || h < 1 || w > 16384 || h > 8192) {
        fprintf(stderr, "make_envmap: size %d x %d out of 1..16384 x 1..8192\n", w, h);
        return 2;
    }
    float *px = malloc(sizeof *px * 3 * (size_t)w * h);
    if (!px) {
        fprintf(stderr, "make_envmap: out of memory\n");
        return 1;
    }
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            double d[3];
            direction((i + 0.5) / w, (j + 0.5) / h, d);
            (is_sky ? sky : compass)(d, px + 3 * ((size_t)j * w + i));
        }
    size_t len = strlen(argv[2]);
    int ok = len > 4 && !strcmp(argv[2] + len - 4, ".png") ? write_png(argv[2], w, h, px)
                                                            : stbi_write_hdr(argv[2], w, h, 3, px);
    free(px);
    if (!ok) {
        fprintf(stderr, "make_envmap: cannot write %s\n", argv[2]);
        return 1;
    }
    return 0;
}
