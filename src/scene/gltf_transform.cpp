/* gltf_transform.cpp — node transforms and vertices to world space.
 *
 * A node's local matrix (§3.5.3), products of matrices, the normal matrix,
 * and the vertices, normals and tangents of one primitive carried into world
 * space by one matrix. */
#include "gltf_int.h"

#include <cmath>

namespace st_gltf {

mat4 identity()
{
    mat4 r = {};
    r.m[0] = r.m[5] = r.m[10] = r.m[15] = 1.0;
    return r;
}

mat4 mul(const mat4 &a, const mat4 &b)
{
    mat4 r;
    for (int c = 0; c < 4; c++)
        for (int row = 0; row < 4; row++) {
            double s = 0.0;
            for (int k = 0; k < 4; k++)
                s += a.m[4 * k + row] * b.m[4 * c + k];
            r.m[4 * c + row] = s;
        }
    return r;
}

static void check_numbers(const std::vector<double> &v, size_t n, int node, const char *what)
{
    if (!v.empty() && v.size() != n)
        fail("node %d: %s needs %zu numbers, has %zu", node, what, n, v.size());
    for (double x : v)
        if (!std::isfinite(x))
            fail("node %d: non-finite %s", node, what);
}

/* Local transform of a node (§3.5.3): its matrix, or T * R * S with the unit
 * quaternion R = (x, y, z, w) turned into a rotation matrix (Shoemake,
 * "Animating rotation with quaternion curves", SIGGRAPH 1985). */
/* A node's matrix must be affine (§5.25: a TRS transform), its last row
 * 0 0 0 1: strata transforms points and normals without a projective divide. */
static void check_affine(const mat4 &r, int idx)
{
    if (r.m[3] != 0.0 || r.m[7] != 0.0 || r.m[11] != 0.0 || r.m[15] != 1.0)
        fail("node %d: matrix is not affine (last row %g %g %g %g, not 0 0 0 1)", idx, r.m[3],
             r.m[7], r.m[11], r.m[15]);
}

mat4 node_local(const tinygltf::Node &n, int idx)
{
    check_numbers(n.matrix, 16, idx, "matrix");
    check_numbers(n.translation, 3, idx, "translation");
    check_numbers(n.rotation, 4, idx, "rotation");
    check_numbers(n.scale, 3, idx, "scale");
    mat4 r = identity();
    if (!n.matrix.empty()) {
        for (int i = 0; i < 16; i++)
            r.m[i] = n.matrix[size_t(i)];
        check_affine(r, idx);
        return r;
    }
    double q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
    if (!n.rotation.empty()) {
        double len = std::sqrt(n.rotation[0] * n.rotation[0] + n.rotation[1] * n.rotation[1] +
                               n.rotation[2] * n.rotation[2] + n.rotation[3] * n.rotation[3]);
        if (!(len > 0.0))
            fail("node %d: zero rotation quaternion", idx);
        for (int i = 0; i < 4; i++)
            q[i] = n.rotation[size_t(i)] / len;
    }
    for (int i = 0; i < 3 && !n.scale.empty(); i++)
        s[i] = n.scale[size_t(i)];
    const double x = q[0], y = q[1], z = q[2], w = q[3];
    const double rot[3][3] = {
        {1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
        {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
        {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)},
    };
    for (int c = 0; c < 3; c++)
        for (int row = 0; row < 3; row++)
            r.m[4 * c + row] = rot[row][c] * s[c];
    for (int i = 0; i < 3 && !n.translation.empty(); i++)
        r.m[12 + i] = n.translation[size_t(i)];
    return r;
}

void cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

normal_xform normal_matrix(const mat4 &m)
{
    const double a0[3] = {m.m[0], m.m[1], m.m[2]};
    const double a1[3] = {m.m[4], m.m[5], m.m[6]};
    const double a2[3] = {m.m[8], m.m[9], m.m[10]};
    normal_xform nx;
    cross(a1, a2, nx.col[0]);
    cross(a2, a0, nx.col[1]);
    cross(a0, a1, nx.col[2]);
    nx.det = a0[0] * nx.col[0][0] + a0[1] * nx.col[0][1] + a0[2] * nx.col[0][2];
    const double sign = nx.det < 0.0 ? -1.0 : 1.0;
    for (auto &c : nx.col)
        for (double &v : c)
            v *= sign;
    return nx;
}

bool normalize3(double v[3])
{
    double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(len > 0.0) || !std::isfinite(len))
        return false;
    for (int i = 0; i < 3; i++)
        v[i] /= len;
    return true;
}

/* Tangents of the used vertices (s.used) to world space: xyz by the world matrix and
 * renormalised, w times the sign of its determinant (a mirror turns the bitangent over); 0
 * where xyz cannot be normalised. */
void transform_tangents(const mat4 &w, double det, scratch &s)
{
    const size_t nv = s.t.size() / 4;
    s.wt.resize(4 * nv);
    if (nv == 0)
        return;
    for (size_t v : s.used) {
        const float *t = &s.t[4 * v];
        double o[3];
        for (int r = 0; r < 3; r++)
            o[r] = w.m[r] * t[0] + w.m[4 + r] * t[1] + w.m[8 + r] * t[2];
        for (int r = 0; r < 4; r++)
            s.wt[4 * v + size_t(r)] = 0.0f;
        if (!normalize3(o))
            continue;
        for (int r = 0; r < 3; r++)
            s.wt[4 * v + size_t(r)] = float(o[r]);
        s.wt[4 * v + 3] = (t[3] < 0.0f ? -1.0f : 1.0f) * (det < 0.0 ? -1.0f : 1.0f);
    }
}

/* Vertex v to world space: its position by the world matrix, its normal by
 * the normal matrix and renormalised; a normal that cannot be normalised is
 * marked NaN and replaced by the face normal later. */
void transform_vertex(const mat4 &w, const normal_xform &nx, scratch &s, size_t v, bool normals)
{
    const float *p = &s.p[3 * v];
    for (int r = 0; r < 3; r++)
        s.wp[3 * v + size_t(r)] =
            float(w.m[r] * p[0] + w.m[4 + r] * p[1] + w.m[8 + r] * p[2] + w.m[12 + r]);
    if (!normals)
        return;
    const float *n = &s.n[3 * v];
    double t[3];
    for (int r = 0; r < 3; r++)
        t[r] = nx.col[0][r] * n[0] + nx.col[1][r] * n[1] + nx.col[2][r] * n[2];
    if (!normalize3(t))
        t[0] = t[1] = t[2] = NAN;
    for (int r = 0; r < 3; r++)
        s.wn[3 * v + size_t(r)] = float(t[r]);
}

/* The vertices the primitive's triangles use (s.used) to world space by one matrix
 * (transform_vertex): an instance costs what it draws, not the size of the accessor it draws
 * from. The others keep whatever they held: no triangle reads them. */
void transform_vertices(const mat4 &w, const normal_xform &nx, scratch &s, bool normals)
{
    const size_t nv = s.p.size() / 3;
    s.wp.resize(3 * nv);
    s.wn.resize(normals ? 3 * nv : 0);
    for (size_t v : s.used)
        transform_vertex(w, nx, s, v, normals);
}

} /* namespace st_gltf */
