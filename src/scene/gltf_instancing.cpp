/* gltf_instancing.cpp — a node's mesh drawn once, or once per EXT_mesh_gpu_instancing
 * instance. */
#include "gltf_int.h"

namespace st_gltf {

/* Triangles of one drawing of a mesh (primitive_bound summed). */
size_t mesh_bound(const Model &m, int mesh)
{
    size_t n = 0;
    for (size_t p = 0; p < m.meshes[size_t(mesh)].primitives.size(); p++)
        n += primitive_bound(m, mesh, p);
    return n;
}

/* The accessor of EXT_mesh_gpu_instancing attribute `name` (checked), or -1. */
static int instancing_accessor(const Model &m, const tinygltf::Value &attrs, const char *name,
                              int node)
{
    if (!attrs.IsObject() || !attrs.Has(name))
        return -1;
    const tinygltf::Value &v = attrs.Get(name);
    if (!v.IsInt())
        fail("node %d: EXT_mesh_gpu_instancing %s is not an accessor index", node, name);
    check_index(v.Get<int>(), m.accessors.size(), "node %d: EXT_mesh_gpu_instancing %s accessor",
                node, name);
    return v.Get<int>();
}

[[noreturn]] static void too_many(int node, size_t drawings)
{
    fail("node %d: %zu drawings of meshes (nodes and EXT_mesh_gpu_instancing instances): more "
         "than %u, the limit", node, drawings, ST_GLTF_MAX_INSTANCES);
}

/* The node's mesh as it is drawn: once, or, with EXT_mesh_gpu_instancing,
 * once per instance with world = the node's world x T_i R_i S_i (the
 * extension's README: instance transforms apply in the node's space;
 * TRANSLATION, ROTATION and SCALE hold one element each per instance, a
 * missing one is the identity). Instances are flattened into the triangle
 * arrays, so their triangles count against ST_GLTF_MAX_TRIANGLES here,
 * and the drawings themselves (a mesh without triangles too) against
 * ST_GLTF_MAX_INSTANCES, before anything is allocated for them. A skinned node is drawn by its
 * joints, once (instancing of it is not read: a warning). */
void add_mesh_instances(const Model &m, int node, const mat4 &world, std::vector<instance> &out,
                        size_t &instanced, notes &warn)
{
    const tinygltf::Node &n = m.nodes[size_t(node)];
    if (n.skin != -1)
        check_index(n.skin, m.skins.size(), "node %d: skin", node);
    auto ext = n.extensions.find("EXT_mesh_gpu_instancing");
    if (ext == n.extensions.end() || n.skin != -1) {
        if (ext != n.extensions.end())
            note(warn, "node %d: EXT_mesh_gpu_instancing on a skinned mesh is not read: "
                       "drawn once",
                 node);
        if (out.size() >= ST_GLTF_MAX_INSTANCES)
            too_many(node, out.size() + 1);
        out.push_back({n.mesh, world, node, n.skin});
        return;
    }
    const tinygltf::Value attrs = ext->second.Get("attributes");
    static const char *const names[3] = {"TRANSLATION", "ROTATION", "SCALE"};
    std::vector<float> trs[3];
    size_t count = 0;
    bool any = false;
    for (int k = 0; k < 3; k++) {
        const int a = instancing_accessor(m, attrs, names[k], node);
        if (a < 0)
            continue;
        const size_t elems = accessor_span(m, a).count;
        if (elems > ST_GLTF_MAX_INSTANCES - out.size()) /* before the attributes are read */
            too_many(node, out.size() + elems);
        if (any && elems != count)
            fail("node %d: EXT_mesh_gpu_instancing attributes of %zu and %zu instances", node,
                 count, elems);
        count = elems;
        any = true;
        read_attribute(m, a, names[k], k == 1 ? 4 : 3, count, trs[k]);
    }
    if (!any)
        fail("node %d: EXT_mesh_gpu_instancing has no TRANSLATION, ROTATION or SCALE", node);
    const size_t each = mesh_bound(m, n.mesh);
    if (each > 0 && count > (ST_GLTF_MAX_TRIANGLES - instanced) / each)
        fail("node %d: EXT_mesh_gpu_instancing: %zu instances of %zu triangles: more than %u "
             "triangles in all, the most strata takes",
             node, count, each, ST_GLTF_MAX_TRIANGLES);
    instanced += count * each;
    for (size_t i = 0; i < count; i++) {
        tinygltf::Node local; /* node_local's checks and formula, on this instance */
        for (int k = 0; k < 3; k++)
            if (!trs[k].empty()) {
                std::vector<double> &v = k == 0 ? local.translation : k == 1 ? local.rotation
                                                                             : local.scale;
                const size_t c = k == 1 ? 4 : 3;
                v.assign(trs[k].begin() + long(c * i), trs[k].begin() + long(c * (i + 1)));
            }
        out.push_back({n.mesh, mul(world, node_local(local, node)), node, -1});
    }
}

} /* namespace st_gltf */
