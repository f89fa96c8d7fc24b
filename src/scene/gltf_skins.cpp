/* gltf_skins.cpp — morph targets (§3.7.2.2) and skins (§3.7.3).
 *
 * Morph targets are applied at the default weights (the node's, else the
 * mesh's); a skinned mesh is placed by linear blend skinning over its
 * joints' world matrices, each vertex by its own blend. */
#include "gltf_int.h"

#include <algorithm>
#include <cmath>

namespace st_gltf {

/* The morph weights a node draws its mesh with (§3.7.2.2): the node's
 * weights, else the mesh's, else 0 for every target. */
std::vector<double> morph_weights(const Model &m, int node, int mesh)
{
    const tinygltf::Mesh &me = m.meshes[size_t(mesh)];
    size_t targets = 0;
    for (const tinygltf::Primitive &prim : me.primitives)
        targets = std::max(targets, prim.targets.size());
    const std::vector<double> &w = node >= 0 && !m.nodes[size_t(node)].weights.empty()
                                       ? m.nodes[size_t(node)].weights
                                       : me.weights;
    if (w.empty())
        return std::vector<double>(targets, 0.0);
    for (double x : w)
        if (!std::isfinite(x))
            fail("mesh %d: a morph weight is not finite", mesh);
    return w;
}

/* Adds the morph targets' displacements of attribute `attr` (POSITION,
 * NORMAL, or TANGENT's xyz: `stride` floats a vertex) to `values`, each
 * times its weight (§3.7.2.2); a primitive must have as many targets as
 * there are weights. */
void apply_morph(const Model &m, int mesh, size_t p, const std::vector<double> &w,
                 const char *attr, size_t stride, std::vector<float> &values)
{
    const tinygltf::Primitive &prim = primitive(m, mesh, p);
    if (prim.targets.empty())
        return;
    if (prim.targets.size() != w.size())
        fail("mesh %d primitive %zu: %zu morph targets, %zu weights", mesh, p,
             prim.targets.size(), w.size());
    const size_t nv = values.size() / stride;
    std::vector<float> d;
    for (size_t k = 0; k < w.size(); k++) {
        auto it = prim.targets[k].find(attr);
        if (it == prim.targets[k].end() || w[k] == 0.0)
            continue;
        check_index(it->second, m.accessors.size(), "mesh %d primitive %zu: target %zu %s", mesh,
                    p, k, attr);
        read_attribute(m, it->second, attr, 3, nv, d);
        for (size_t v = 0; v < nv; v++)
            for (size_t c = 0; c < 3; c++)
                values[stride * v + c] = float(double(values[stride * v + c]) + w[k] * d[3 * v + c]);
    }
}

/* One warning per mesh whose morph targets move what strata does not
 * morph (texture coordinates, colours). */
void note_morph_targets(const Model &m, int mesh, notes &warn)
{
    for (const tinygltf::Primitive &prim : m.meshes[size_t(mesh)].primitives)
        for (const auto &target : prim.targets)
            for (const auto &attr : target)
                if (attr.first != "POSITION" && attr.first != "NORMAL" &&
                    attr.first != "TANGENT") {
                    note(warn, "mesh %d: morph targets of %s are not applied", mesh,
                         attr.first.c_str());
                    return;
                }
}

/* The parent of every node (-1: none). A node listed as a child twice is
 * an error where the scene reaches it (walk_scene); here the first wins. */
std::vector<int> node_parents(const Model &m)
{
    std::vector<int> parent(m.nodes.size(), -1);
    for (size_t i = 0; i < m.nodes.size(); i++)
        for (int c : m.nodes[i].children) {
            check_index(c, m.nodes.size(), "node %zu: child", i);
            if (parent[size_t(c)] == -1)
                parent[size_t(c)] = int(i);
        }
    return parent;
}

static mat4 node_world(const Model &m, node_worlds &w, int node)
{
    std::vector<int> chain; /* from node up to the first known ancestor or a root */
    int n = node;
    for (; n != -1 && !w.known[size_t(n)]; n = w.parent[size_t(n)]) {
        if (chain.size() > m.nodes.size())
            fail("node %d: its ancestors form a cycle", node);
        chain.push_back(n);
    }
    mat4 acc = n == -1 ? identity() : w.world[size_t(n)];
    for (size_t i = chain.size(); i-- > 0;) {
        acc = mul(acc, node_local(m.nodes[size_t(chain[i])], chain[i]));
        w.world[size_t(chain[i])] = acc;
        w.known[size_t(chain[i])] = 1;
    }
    return w.world[size_t(node)];
}

/* The joint matrices of skin k (§3.7.3.3): world(joint_i) x
 * inverseBindMatrices_i (float MAT4s, one per joint; identity without the
 * accessor). */
std::vector<mat4> joint_matrices(const Model &m, int k, node_worlds &worlds)
{
    const tinygltf::Skin &skin = m.skins[size_t(k)];
    if (skin.joints.empty())
        fail("skin %d: no joints", k);
    std::vector<mat4> out;
    span ibm = {nullptr, 0, 0, 0};
    if (skin.inverseBindMatrices != -1) {
        check_index(skin.inverseBindMatrices, m.accessors.size(), "skin %d: inverseBindMatrices",
                    k);
        const tinygltf::Accessor &acc = m.accessors[size_t(skin.inverseBindMatrices)];
        if (acc.type != TINYGLTF_TYPE_MAT4 || acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
            fail("skin %d: inverseBindMatrices must be float MAT4", k);
        ibm = accessor_span(m, skin.inverseBindMatrices);
        if (ibm.count < skin.joints.size())
            fail("skin %d: %zu inverseBindMatrices for %zu joints", k, ibm.count,
                 skin.joints.size());
    }
    for (size_t j = 0; j < skin.joints.size(); j++) {
        check_index(skin.joints[j], m.nodes.size(), "skin %d: joint", k);
        mat4 inv = identity();
        for (int e = 0; e < 16 && ibm.data; e++) {
            inv.m[e] = component(ibm.data + j * ibm.stride, TINYGLTF_COMPONENT_TYPE_FLOAT, false, e);
            if (!std::isfinite(inv.m[e]))
                fail("skin %d: inverseBindMatrices %zu is not finite", k, j);
        }
        out.push_back(mul(node_world(m, worlds, skin.joints[j]), inv));
    }
    return out;
}

/* Each vertex's skin matrix M = sum_i w_i J[j_i] over its JOINTS_n /
 * WEIGHTS_n sets (§3.7.3.3: linear blend skinning), the weights divided by
 * their sum; a vertex without weight keeps `fallback` (the node's world). */
std::vector<mat4> skin_matrices(const Model &m, int mesh, size_t p, const std::vector<mat4> &J,
                                const mat4 &fallback, size_t nv)
{
    std::vector<mat4> out(nv, mat4{});
    std::vector<double> sum(nv, 0.0);
    std::vector<float> joints, weights;
    for (int set = 0;; set++) {
        char jn[24], wn[24];
        snprintf(jn, sizeof jn, "JOINTS_%d", set);
        snprintf(wn, sizeof wn, "WEIGHTS_%d", set);
        const int ja = attribute(m, mesh, p, jn), wa = attribute(m, mesh, p, wn);
        if (ja < 0 || wa < 0)
            break;
        read_attribute(m, ja, jn, 4, nv, joints);
        read_attribute(m, wa, wn, 4, nv, weights);
        for (size_t v = 0; v < nv; v++)
            for (int i = 0; i < 4; i++) {
                const double w = weights[4 * v + size_t(i)];
                if (w == 0.0)
                    continue;
                const float j = joints[4 * v + size_t(i)];
                if (!(w > 0.0) || !(j < float(J.size())))
                    fail("mesh %d primitive %zu: %s / %s of vertex %zu: joint %g of %zu, weight "
                         "%g",
                         mesh, p, jn, wn, v, double(j), J.size(), w);
                for (int e = 0; e < 16; e++)
                    out[v].m[e] += w * J[size_t(j)].m[e];
                sum[v] += w;
            }
    }
    for (size_t v = 0; v < nv; v++) {
        if (!(sum[v] > 0.0)) {
            out[v] = fallback;
            continue;
        }
        for (double &e : out[v].m)
            e /= sum[v];
    }
    return out;
}

/* Skinned vertices to world space, each by its own skin matrix (positions;
 * normals by its normal matrix; tangents by it, w times the sign of its
 * determinant), as transform_vertices and transform_tangents do with one
 * matrix; neg marks the vertices whose matrix mirrors. */
void skin_vertices(const std::vector<mat4> &M, scratch &s, bool normals)
{
    const size_t nv = s.p.size() / 3;
    s.wp.resize(3 * nv);
    s.wn.resize(normals ? 3 * nv : 0);
    s.wt.assign(s.t.empty() ? 0 : 4 * nv, 0.0f);
    s.neg.assign(nv, 0);
    for (size_t v : s.used) {
        const double *w = M[v].m;
        const normal_xform nx = normal_matrix(M[v]);
        s.neg[v] = nx.det < 0.0;
        transform_vertex(M[v], nx, s, v, normals);
        if (s.t.empty() || s.t[4 * v + 3] == 0.0f)
            continue;
        const float *t = &s.t[4 * v];
        double o[3];
        for (int r = 0; r < 3; r++)
            o[r] = w[r] * t[0] + w[4 + r] * t[1] + w[8 + r] * t[2];
        if (!normalize3(o))
            continue;
        for (int r = 0; r < 3; r++)
            s.wt[4 * v + size_t(r)] = float(o[r]);
        s.wt[4 * v + 3] = (t[3] < 0.0f ? -1.0f : 1.0f) * (nx.det < 0.0 ? -1.0f : 1.0f);
    }
}

} /* namespace st_gltf */
