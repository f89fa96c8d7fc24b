/* make_icosphere.c — writes the trace benchmark's large mesh: a unit
 * icosphere, the icosahedron's 20 faces split LEVEL times into four (each
 * new vertex the normalised midpoint of an edge), so 20 * 4^LEVEL triangles:
 * 327,680 at level 7. Output: OUT.gltf beside OUT.bin (a triangle soup, one
 * POSITION accessor, no indices), a camera 3 units away on +z.
 * Usage: make_icosphere OUT_BASENAME [LEVEL]   (`make bench` runs it) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static FILE *bin;
static float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};

static void put(const double *v)
{
    for (int a = 0; a < 3; a++) {
        float f = (float)v[a];
        lo[a] = f < lo[a] ? f : lo[a];
        hi[a] = f > hi[a] ? f : hi[a];
        fwrite(&f, sizeof f, 1, bin);
    }
}

static void midpoint(const double *a, const double *b, double *m)
{
    double len = 0.0;
    for (int k = 0; k < 3; k++) {
        m[k] = 0.5 * (a[k] + b[k]);
        len += m[k] * m[k];
    }
    for (int k = 0; k < 3; k++)
        m[k] /= sqrt(len);
}

static void split(const double *a, const double *b, const double *c, int level)
{
    if (level == 0) {
        put(a), put(b), put(c);
        return;
    }
    double ab[3], bc[3], ca[3];
    midpoint(a, b, ab), midpoint(b, c, bc), midpoint(c, a, ca);
    split(a, ab, ca, level - 1);
    split(ab, b, bc, level - 1);
    split(ca, bc, c, level - 1);
    split(ab, bc, ca, level - 1);
}

int main(int argc, char **argv)
{
    if (argc < 2 || argc > 3) {
        fprintf(stderr, "usage: make_icosphere OUT_BASENAME [LEVEL]\n");
        return 2;
    }
    int level = argc == 3 ? atoi(argv[2]) : 7;
    if (level < 0 || level > 9) {
        fprintf(stderr, "make_icosphere: level %s: expected 0..9\n", argv[2]);
        return 2;
    }
    /* the icosahedron: (0, +-1, +-g) and its cyclic permutations, g the golden ratio */
    double g = (1.0 + sqrt(5.0)) / 2.0, n = sqrt(1.0 + g * g), v[12][3];
    static const int f[20][3] = {
        {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
        {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    const double base[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                                {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                                {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    for (int i = 0; i < 12; i++)
        for (int k = 0; k < 3; k++)
            v[i][k] = base[i][k] / n;
    char path[4096];
    snprintf(path, sizeof path, "%s.bin", argv[1]);
    if (!(bin = fopen(path, "wb"))) {
        perror(path);
        return 1;
    }
    for (int i = 0; i < 20; i++)
        split(v[f[i][0]], v[f[i][1]], v[f[i][2]], level);
    if (fclose(bin) != 0) {
        perror(path);
        return 1;
    }
    long verts = 60L << (2 * level);
    const char *name = strrchr(argv[1], '/') ? strrchr(argv[1], '/') + 1 : argv[1];
    snprintf(path, sizeof path, "%s.gltf", argv[1]);
    FILE *out = fopen(path, "w");
    if (!out) {
        perror(path);
        return 1;
    }
    fprintf(out,
            "{\"asset\":{\"version\":\"2.0\",\"generator\":\"strata tools/make_icosphere.c\"},"
            "\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
            "\"nodes\":[{\"mesh\":0},{\"camera\":0,\"translation\":[0,0,3]}],"
            "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.7,\"znear\":0.01}}],"
            /* two-sided: every ray of the trace benchmark may hit it from inside too */
            "\"materials\":[{\"doubleSided\":true}],"
            "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"material\":0}]}],"
            "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%ld,\"type\":\"VEC3\","
            "\"min\":[%.9g,%.9g,%.9g],\"max\":[%.9g,%.9g,%.9g]}],"
            "\"bufferViews\":[{\"buffer\":0,\"byteLength\":%ld}],"
            "\"buffers\":[{\"uri\":\"%s.bin\",\"byteLength\":%ld}]}\n",
            verts, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], verts * 12, name, verts * 12);
    return fclose(out) == 0 ? 0 : 1;
}
