/* gltf_geometry.cpp — mesh primitives (§3.7.2) as world-space triangles.
 *
 * A primitive's POSITION, NORMAL, TEXCOORD_0/1, COLOR_0, TANGENT (or tangents
 * generated from its uvs) and indices (strips and fans made lists), morphed
 * and skinned (gltf_skins.cpp) or moved by its node's matrix, emitted into
 * the triangle arrays; zero-area and non-finite triangles are dropped. */
#include "gltf_int.h"

#include <cmath>
#include <cstring>

namespace st_gltf {

bool is_triangles(const tinygltf::Primitive &prim)
{
    return prim.mode == TINYGLTF_MODE_TRIANGLES || prim.mode == -1 || /* -1: the default */
           prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP || prim.mode == TINYGLTF_MODE_TRIANGLE_FAN;
}

/* A TRIANGLE_STRIP's or TRIANGLE_FAN's vertex list as a triangle list, by
 * §3.7.2.1: strip triangle i = (v_i, v_{i+1+i%2}, v_{i+2-i%2}), fan triangle
 * i = (v_{i+1}, v_{i+2}, v_0). */
static void strip_or_fan_to_list(int mode, std::vector<uint32_t> &idx)
{
    if (mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN)
        return;
    std::vector<uint32_t> list;
    for (size_t i = 0; i + 2 < idx.size(); i++) {
        const size_t odd = i % 2;
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP)
            list.insert(list.end(), {idx[i], idx[i + 1 + odd], idx[i + 2 - odd]});
        else
            list.insert(list.end(), {idx[i + 1], idx[i + 2], idx[0]});
    }
    idx.swap(list);
}

/* The POSITION accessor of a TRIANGLES primitive; -1 for a primitive that is
 * not drawn (another mode, or no POSITION: §3.7.2.1). */
static int position_accessor(const Model &m, int mesh, size_t p)
{
    const tinygltf::Primitive &prim = primitive(m, mesh, p);
    if (!is_triangles(prim))
        return -1;
    auto it = prim.attributes.find("POSITION");
    if (it == prim.attributes.end())
        return -1;
    check_index(it->second, m.accessors.size(), "mesh %d primitive %zu: POSITION accessor", mesh,
                p);
    return it->second;
}

static const char *mode_name(int mode)
{
    static const char *names[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP",
                                  "TRIANGLES", "TRIANGLE_STRIP", "TRIANGLE_FAN"};
    return mode >= 0 && mode <= 6 ? names[mode] : "unknown";
}

/* One warning per primitive that a mesh of the scene has and strata skips. */
void note_skipped_primitives(const Model &m, int mesh, notes &warn)
{
    const tinygltf::Mesh &me = m.meshes[size_t(mesh)];
    for (size_t p = 0; p < me.primitives.size(); p++) {
        const tinygltf::Primitive &prim = me.primitives[p];
        if (!is_triangles(prim))
            note(warn, "mesh %d (%s) primitive %zu: mode %d (%s) skipped: strata renders "
                       "triangles only",
                 mesh, me.name.c_str(), p, prim.mode, mode_name(prim.mode));
        else if (prim.attributes.find("POSITION") == prim.attributes.end())
            note(warn, "mesh %d (%s) primitive %zu: no POSITION, skipped", mesh,
                 me.name.c_str(), p);
    }
}

/* Upper bound of a primitive's triangles (checked ranges), to size the output
 * once: the index count / 3, or the vertex count / 3 without indices (n - 2
 * of n for a strip or fan). */
size_t primitive_bound(const Model &m, int mesh, size_t p)
{
    const int pos = position_accessor(m, mesh, p);
    if (pos < 0)
        return 0;
    const int ind = primitive(m, mesh, p).indices;
    if (ind != -1)
        check_index(ind, m.accessors.size(), "mesh %d primitive %zu: indices accessor", mesh, p);
    const size_t n = accessor_span(m, ind != -1 ? ind : pos).count;
    const int mode = primitive(m, mesh, p).mode;
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP || mode == TINYGLTF_MODE_TRIANGLE_FAN)
        return n >= 3 ? n - 2 : 0;
    return n / 3;
}

/* The vertices a drawing of a primitive reads (its POSITION's elements; 0 when it is not
 * drawn), for the import's budget of work. */
size_t primitive_vertices(const Model &m, int mesh, size_t p)
{
    const int pos = position_accessor(m, mesh, p);
    return pos < 0 ? 0 : accessor_span(m, pos).count;
}

/* Reads COLOR_0 (§3.7.2.1: float, or normalised unsigned byte or short,
 * VEC3 or VEC4; linear) into RGBA, alpha 1 for VEC3. */
static void read_colors(const Model &m, int a, size_t vertices, std::vector<float> &out)
{
    const tinygltf::Accessor &acc = m.accessors[size_t(a)];
    const int ct = acc.componentType;
    const int n = acc.type == TINYGLTF_TYPE_VEC3 ? 3 : acc.type == TINYGLTF_TYPE_VEC4 ? 4 : 0;
    const bool ok = ct == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                    ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                    ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    if (n == 0 || !ok)
        fail("accessor %d: COLOR_0 must be float, unsigned byte or unsigned short VEC3 or VEC4",
             a);
    const span s = accessor_span(m, a);
    if (s.count != vertices)
        fail("accessor %d: COLOR_0 has %zu elements, POSITION %zu", a, s.count, vertices);
    out.assign(4 * s.count, 1.0f);
    for (size_t i = 0; i < s.count; i++) {
        const unsigned char *p = s.data + i * s.stride;
        for (int k = 0; k < n; k++) {
            float v;
            if (ct == TINYGLTF_COMPONENT_TYPE_FLOAT) {
                memcpy(&v, p + 4 * k, 4);
            } else if (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
                v = float(p[k]) / 255.0f;
            } else {
                uint16_t h;
                memcpy(&h, p + 2 * k, 2);
                v = float(h) / 65535.0f;
            }
            if (!std::isfinite(v) || v < 0.0f)
                fail("accessor %d: COLOR_0 element %zu is negative or not finite", a, i);
            out[4 * i + size_t(k)] = v;
        }
    }
}

/* Reads TANGENT (§3.7.2.1: float VEC4, xyz unit, w = ±1 the handedness;
 * normalised bytes or shorts with KHR_mesh_quantization). */
static void read_tangents(const Model &m, int a, size_t vertices, std::vector<float> &out)
{
    read_attribute(m, a, "TANGENT", 4, vertices, out);
}

/* Per-vertex tangents from the texture coordinates, in object space: each
 * triangle's dP/du and dP/dv (solving the edges against their uv deltas,
 * Lengyel's method), summed at its vertices weighted by the triangle's size
 * (the unnormalised solution carries it), then made orthogonal to the
 * vertex normal (or the summed face normal). The handedness is MikkTSpace's
 * as glTF applies it: glTF's v runs down the image while a normal map's
 * green axis points up it, so the bitangent the map needs is -dP/dv, and
 * w = +1 where cross(n, t) points along -dP/dv, else -1 (the bitangent is
 * w cross(n, t), as for a file's TANGENT). A vertex whose uvs are
 * degenerate gets 0. */
static void generate_tangents(scratch &s, const std::vector<float> &uv, bool normals)
{
    const size_t nv = s.p.size() / 3;
    std::vector<double> tu(3 * nv, 0.0), tv(3 * nv, 0.0), fn(3 * nv, 0.0);
    for (size_t t = 0; t + 3 <= s.idx.size(); t += 3) {
        const uint32_t *i = &s.idx[t];
        double e1[3], e2[3], g[3];
        for (int k = 0; k < 3; k++) {
            e1[k] = double(s.p[3 * i[1] + k]) - s.p[3 * i[0] + k];
            e2[k] = double(s.p[3 * i[2] + k]) - s.p[3 * i[0] + k];
        }
        const double du1 = double(uv[2 * i[1]]) - uv[2 * i[0]],
                     dv1 = double(uv[2 * i[1] + 1]) - uv[2 * i[0] + 1],
                     du2 = double(uv[2 * i[2]]) - uv[2 * i[0]],
                     dv2 = double(uv[2 * i[2] + 1]) - uv[2 * i[0] + 1];
        const double det = du1 * dv2 - du2 * dv1, sgn = det < 0.0 ? -1.0 : 1.0;
        cross(e1, e2, g);
        if (det == 0.0 || !std::isfinite(det))
            continue;
        for (int v = 0; v < 3; v++)
            for (int k = 0; k < 3; k++) { /* (e1 dv2 - e2 dv1) / det, times |det| */
                tu[3 * i[v] + k] += (e1[k] * dv2 - e2[k] * dv1) * sgn;
                tv[3 * i[v] + k] += (e2[k] * du1 - e1[k] * du2) * sgn;
                fn[3 * i[v] + k] += g[k];
            }
    }
    s.t.assign(4 * nv, 0.0f);
    for (size_t v = 0; v < nv; v++) {
        double n[3], t[3], b[3], c[3];
        for (int k = 0; k < 3; k++) {
            n[k] = normals ? double(s.n[3 * v + k]) : fn[3 * v + k];
            t[k] = tu[3 * v + k];
            b[k] = tv[3 * v + k];
        }
        if (!normalize3(n))
            continue;
        const double d = t[0] * n[0] + t[1] * n[1] + t[2] * n[2];
        for (int k = 0; k < 3; k++)
            t[k] -= d * n[k];
        if (!normalize3(t))
            continue;
        cross(n, t, c);
        for (int k = 0; k < 3; k++)
            s.t[4 * v + size_t(k)] = float(t[k]);
        s.t[4 * v + 3] = c[0] * b[0] + c[1] * b[1] + c[2] * b[2] > 0.0 ? -1.0f : 1.0f;
    }
}

/* Appends triangle (i0, i1, i2) unless it is non-finite or has zero area;
 * `sets`: bit k when the primitive has TEXCOORD_k (0s where it has not).
 * The face normal g = (p1 - p0) x (p2 - p0) / |...| is computed in double,
 * where float inputs cannot overflow, so |g| is finite exactly when the three
 * positions are; g stands in for missing or unusable vertex normals. */
static void emit_triangle(const scratch &s, const uint32_t i[3], bool normals, unsigned sets,
                          uint32_t material, sink &out)
{
    const float *p[3] = {&s.wp[3 * size_t(i[0])], &s.wp[3 * size_t(i[1])], &s.wp[3 * size_t(i[2])]};
    double e1[3], e2[3], g[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = double(p[1][k]) - p[0][k];
        e2[k] = double(p[2][k]) - p[0][k];
    }
    cross(e1, e2, g);
    if (!normalize3(g)) {
        out.dropped++;
        return;
    }
    float *dp = out.pos + 9 * out.count, *dn = out.nrm + 9 * out.count;
    float *duv = out.uv + 6 * out.count, *dt = out.tan + 12 * out.count;
    float *dc = out.col + 12 * out.count;
    for (int v = 0; v < 3; v++) {
        for (int k = 0; k < 4; k++) {
            dt[4 * v + k] = s.wt.empty() ? 0.0f : s.wt[4 * size_t(i[v]) + size_t(k)];
            dc[4 * v + k] = s.c.empty() ? 1.0f : s.c[4 * size_t(i[v]) + size_t(k)];
        }
        const float *n = normals ? &s.wn[3 * size_t(i[v])] : nullptr;
        const bool usable = n && !std::isnan(n[0]);
        for (int k = 0; k < 3; k++) {
            dp[3 * v + k] = p[v][k];
            dn[3 * v + k] = usable ? n[k] : float(g[k]);
        }
        for (int k = 0; k < 2; k++) {
            const size_t at = 2 * size_t(i[v]) + size_t(k);
            duv[2 * v + k] = sets & 1u ? s.uv[at] : 0.0f;
            if (out.uv1)
                out.uv1[6 * out.count + 2 * size_t(v) + size_t(k)] = sets & 2u ? s.uv1[at] : 0.0f;
        }
    }
    out.mat[out.count++] = material;
}

/* The vertices of idx's whole triangles (a trailing 1 or 2 indices draw nothing), each once,
 * ascending, into s.used. */
static void find_used(scratch &s, size_t nv)
{
    std::vector<char> mark(nv, 0);
    for (size_t t = 0; t < s.idx.size() / 3 * 3; t++)
        mark[s.idx[t]] = 1;
    s.used.clear();
    for (size_t v = 0; v < nv; v++)
        if (mark[v])
            s.used.push_back(uint32_t(v));
}

/* One primitive read into s in object space, morphed by `weights`: its attributes (TEXCOORD_1
 * only when want_uv1), its indices as a triangle list, its tangents (read, or generated from
 * the normal map's set) and the vertices its triangles use. s.drawn is false for a primitive
 * strata skips. */
void read_primitive(const Model &m, int mesh, size_t p, const std::vector<double> &weights,
                    const std::vector<uv_use> &use, bool want_uv1, scratch &s)
{
    const int pos = position_accessor(m, mesh, p);
    s.drawn = pos >= 0;
    if (!s.drawn)
        return;
    const tinygltf::Primitive &prim = primitive(m, mesh, p);
    if (prim.material != -1)
        check_index(prim.material, m.materials.size(), "mesh %d primitive %zu: material", mesh, p);
    s.material = prim.material == -1 ? ST_GLTF_NO_MATERIAL : uint32_t(prim.material);
    read_vec3(m, pos, "POSITION", s.p);
    const size_t nv = s.p.size() / 3;
    apply_morph(m, mesh, p, weights, "POSITION", 3, s.p);
    const int nrm = attribute(m, mesh, p, "NORMAL");
    s.normals = nrm >= 0;
    if (nrm >= 0) {
        read_vec3(m, nrm, "NORMAL", s.n);
        if (s.n.size() != s.p.size())
            fail("mesh %d primitive %zu: NORMAL has %zu elements, POSITION %zu", mesh, p,
                 s.n.size() / 3, nv);
        apply_morph(m, mesh, p, weights, "NORMAL", 3, s.n);
    }
    const int uv = attribute(m, mesh, p, "TEXCOORD_0");
    if (uv >= 0)
        read_uv(m, uv, "TEXCOORD_0", nv, s.uv);
    const int uv1 = want_uv1 ? attribute(m, mesh, p, "TEXCOORD_1") : -1;
    if (uv1 >= 0)
        read_uv(m, uv1, "TEXCOORD_1", nv, s.uv1);
    s.sets = (uv >= 0 ? 1u : 0u) | (uv1 >= 0 ? 2u : 0u);
    if (prim.indices != -1) {
        check_index(prim.indices, m.accessors.size(), "mesh %d primitive %zu: indices accessor",
                    mesh, p);
        read_indices(m, prim.indices, nv, s.idx);
    } else {
        s.idx.resize(nv);
        for (size_t v = 0; v < nv; v++)
            s.idx[v] = uint32_t(v);
    }
    strip_or_fan_to_list(prim.mode, s.idx);
    find_used(s, nv);
    const int col = attribute(m, mesh, p, "COLOR_0");
    s.c.clear();
    if (col >= 0)
        read_colors(m, col, nv, s.c);
    const int tan = attribute(m, mesh, p, "TANGENT");
    const bool set1 = s.material != ST_GLTF_NO_MATERIAL && use[s.material].normal_set == 1;
    s.t.clear();
    if (tan >= 0 && nrm >= 0) { /* §3.7.2.1: TANGENT is used with NORMAL only */
        read_tangents(m, tan, nv, s.t);
        apply_morph(m, mesh, p, weights, "TANGENT", 4, s.t);
    } else if ((set1 ? uv1 : uv) >= 0) { /* from the normal map's own set */
        generate_tangents(s, set1 ? s.uv1 : s.uv, nrm >= 0);
    }
}

/* One drawing of a primitive that read_primitive read into s: skinned by `joints` (the skin's
 * joint matrices; NULL: not skinned) or moved by `world`, then its triangles emitted. */
void place_primitive(const Model &m, int mesh, size_t p, const mat4 &world,
                     const normal_xform &nx, const std::vector<mat4> *joints, scratch &s,
                     sink &out)
{
    if (!s.drawn)
        return;
    if (joints) {
        skin_vertices(skin_matrices(m, mesh, p, *joints, world, s.p.size() / 3), s, s.normals);
    } else {
        transform_vertices(world, nx, s, s.normals);
        transform_tangents(world, nx.det, s);
    }
    for (size_t t = 0; t + 3 <= s.idx.size(); t += 3) { /* a trailing 1 or 2 are ignored */
        uint32_t tri[3] = {s.idx[t], s.idx[t + 1], s.idx[t + 2]};
        if (joints ? s.neg[tri[0]] != 0 : nx.det < 0.0) { /* mirrored: winding reversed */
            tri[1] = s.idx[t + 2];
            tri[2] = s.idx[t + 1];
        }
        emit_triangle(s, tri, s.normals, s.sets, s.material, out);
    }
}

} /* namespace st_gltf */
