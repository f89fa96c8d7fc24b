/* gltf_shim.cpp — glTF 2.0 import through tinygltf, behind the C interface of
 * gltf_shim.h: the whole file, from bytes to the flattened scene. Its jobs are
 * files of their own (gltf_int.h lists them): parse, accessors, geometry,
 * skins and morphs, instancing, materials, textures, lights, cameras.
 *
 * Spec: Khronos Group, "glTF 2.0 Specification", version 2.0.1 (2021):
 * §3.5 nodes and the TRS/matrix transform hierarchy, §3.6 buffers, bufferViews
 * and accessors, §3.7.2 mesh primitives, §3.8 textures, images and samplers,
 * §3.9 materials, §3.10 cameras, §4.4 the GLB container; and the extensions
 * §3.7.2.2 morph targets, §3.7.3 skins, and the extensions
 * KHR_materials_emissive_strength, KHR_materials_specular, KHR_materials_ior,
 * KHR_materials_transmission, KHR_materials_volume (attenuation),
 * KHR_materials_clearcoat, KHR_materials_sheen,
 * KHR_materials_unlit, KHR_materials_pbrSpecularGlossiness (converted),
 * KHR_texture_transform, KHR_mesh_quantization, KHR_lights_punctual and
 * EXT_mesh_gpu_instancing.
 *
 * Invariants: no byte of a buffer is read before the accessor and bufferView
 * ranges that cover it were checked against the buffer's real size, and no
 * index is used before it was checked against its array; a malformed file
 * becomes a shim_error (one line), never a crash. No C++ exception leaves the
 * importer: st_gltf_shim_load catches them all. Buffers are read as little-endian
 * (the glTF byte order) with memcpy, so no alignment is assumed.
 *
 * Flattening: every node reachable from the scene's roots contributes its
 * mesh's TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN primitives, transformed by the node's world matrix
 * (parent * local, local = T * R * S or the node's matrix; once per
 * EXT_mesh_gpu_instancing instance, times its T R S), morphed first by the
 * default weights; a skinned mesh by each vertex's blend of joint matrices
 * instead. Normals go through
 * the inverse transpose; where the determinant is negative the winding is
 * reversed (v1 <-> v2), as the spec asks of mirrored nodes (§3.7.2.1).
 *
 * Images: tinygltf hands each image's encoded bytes to keep_image_bytes,
 * which only keeps them; those a material's texture uses are decoded
 * afterwards by stb_image (PNG, JPEG, ...), images stored in a bufferView
 * read from its checked range. What is skipped (non-triangle primitives,
 * textures on other texture coordinate sets) becomes a warning line. */
#include "gltf_int.h"

#include <stb/stb_image.h> /* stbi_image_free: Debian's libstb holds the implementation */

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>

namespace st_gltf {

/* Depth-first, in scene order (an explicit stack: a deep chain of nodes must
 * not overflow the C stack). The node graph must be disjoint trees (§3.5.2),
 * so a node reached twice (a cycle, or two parents) is an error. */
static void walk_scene(const Model &m, std::vector<instance> &out,
                       std::vector<st_gltf_camera> &cams, std::vector<st_gltf_light> &lights,
                       notes &warn)
{
    if (m.scenes.empty())
        fail("no scenes: nothing to render");
    const int s = m.defaultScene >= 0 ? m.defaultScene : 0;
    check_index(s, m.scenes.size(), "default scene");
    struct item {
        int node;
        mat4 parent;
    };
    std::vector<item> stack;
    std::vector<char> seen(m.nodes.size(), 0);
    size_t instanced = 0; /* triangles of EXT_mesh_gpu_instancing instances so far */
    const std::vector<int> &roots = m.scenes[size_t(s)].nodes;
    for (size_t i = roots.size(); i-- > 0;) {
        check_index(roots[i], m.nodes.size(), "scene %d: node", s);
        stack.push_back({roots[i], identity()});
    }
    while (!stack.empty()) {
        const item it = stack.back();
        stack.pop_back();
        if (seen[size_t(it.node)])
            fail("node %d: reached twice (nodes must form disjoint trees)", it.node);
        seen[size_t(it.node)] = 1;
        const tinygltf::Node &node = m.nodes[size_t(it.node)];
        const mat4 world = mul(it.parent, node_local(node, it.node));
        if (node.mesh != -1) {
            check_index(node.mesh, m.meshes.size(), "node %d: mesh", it.node);
            add_mesh_instances(m, it.node, world, out, instanced, warn);
        }
        if (node.camera != -1) {
            check_index(node.camera, m.cameras.size(), "node %d: camera", it.node);
            take_camera(m, it.node, node.camera, world, cams, warn);
        }
        const int li = node_light(node, it.node, m.lights.size());
        if (li >= 0)
            take_light(m, it.node, li, world, lights, warn);
        for (size_t i = node.children.size(); i-- > 0;) {
            check_index(node.children[i], m.nodes.size(), "node %d: child", it.node);
            stack.push_back({node.children[i], world});
        }
    }
}

/* The accessors the import may read: the attributes, indices and morph targets of the meshes,
 * the skins' inverseBindMatrices and the EXT_mesh_gpu_instancing attributes of the nodes the
 * default scene reaches. Bad indices are skipped here: walk_scene reports them. */
static std::vector<char> used_accessors(const Model &m)
{
    std::vector<char> used(m.accessors.size(), 0), seen(m.nodes.size(), 0);
    auto use = [&used](int a) {
        if (a >= 0 && size_t(a) < used.size())
            used[size_t(a)] = 1;
    };
    const size_t s = size_t(m.defaultScene >= 0 ? m.defaultScene : 0);
    std::vector<int> stack;
    if (s < m.scenes.size())
        stack = m.scenes[s].nodes;
    while (!stack.empty()) {
        const int n = stack.back();
        stack.pop_back();
        if (n < 0 || size_t(n) >= m.nodes.size() || seen[size_t(n)])
            continue;
        seen[size_t(n)] = 1;
        const tinygltf::Node &node = m.nodes[size_t(n)];
        if (node.mesh >= 0 && size_t(node.mesh) < m.meshes.size())
            for (const tinygltf::Primitive &prim : m.meshes[size_t(node.mesh)].primitives) {
                use(prim.indices);
                for (const auto &kv : prim.attributes)
                    use(kv.second);
                for (const auto &target : prim.targets)
                    for (const auto &kv : target)
                        use(kv.second);
            }
        if (node.skin >= 0 && size_t(node.skin) < m.skins.size())
            use(m.skins[size_t(node.skin)].inverseBindMatrices);
        auto ext = node.extensions.find("EXT_mesh_gpu_instancing");
        if (ext != node.extensions.end() && ext->second.Get("attributes").IsObject()) {
            const tinygltf::Value &attrs = ext->second.Get("attributes");
            for (const std::string &key : attrs.Keys())
                if (attrs.Get(key).IsInt())
                    use(attrs.Get(key).Get<int>());
        }
        stack.insert(stack.end(), node.children.begin(), node.children.end());
    }
    return used;
}

template <typename T> T *alloc_array(size_t n, size_t per)
{
    if (n == 0)
        return nullptr;
    if (n > SIZE_MAX / (per * sizeof(T)))
        throw std::bad_alloc();
    T *p = static_cast<T *>(malloc(n * per * sizeof(T)));
    if (!p)
        throw std::bad_alloc();
    return p;
}

/* Shrinks an array to n * per elements (realloc to a smaller size may still
 * move it; failure keeps the larger block, which is harmless). */
template <typename T> T *shrink(T *p, size_t n, size_t per)
{
    if (n == 0) {
        free(p);
        return nullptr;
    }
    T *q = static_cast<T *>(realloc(p, n * per * sizeof(T)));
    return q ? q : p;
}

/* A malloc'd copy of a vector (NULL when empty). */
template <typename T> T *copy_out(const std::vector<T> &v)
{
    T *p = alloc_array<T>(v.size(), 1);
    if (p)
        memcpy(p, v.data(), v.size() * sizeof(T));
    return p;
}

/* The sets each material's textures read, from its texture references. */
static std::vector<uv_use> uv_uses(const std::vector<st_gltf_material> &mats,
                                   const texture_table &table)
{
    std::vector<uv_use> use(mats.size());
    for (size_t i = 0; i < mats.size(); i++) {
        const st_gltf_material &o = mats[i];
        const int slots[] = {o.base_color_tex, o.emission_tex,       o.metallic_roughness_tex,
                             o.specular_tex,   o.specular_color_tex, o.normal_tex,
                             o.clearcoat_normal_tex, o.anisotropy_tex, o.diffuse_trans_tex,
                             o.diffuse_trans_color_tex, o.iridescence_tex,
                             o.iridescence_thickness_tex};
        for (int t : slots)
            if (t >= 0)
                use[i].sets |= 1u << table.refs[size_t(t)].tex_coord;
        /* one tangent frame per triangle: the base's normal map's set, else
         * the clear coat's, else the anisotropy texture's */
        if (o.normal_tex >= 0)
            use[i].normal_set = table.refs[size_t(o.normal_tex)].tex_coord;
        else if (o.clearcoat_normal_tex >= 0)
            use[i].normal_set = table.refs[size_t(o.clearcoat_normal_tex)].tex_coord;
        else if (o.anisotropy_tex >= 0)
            use[i].normal_set = table.refs[size_t(o.anisotropy_tex)].tex_coord;
    }
    return use;
}

/* One warning per primitive whose material reads a texture coordinate set
 * that the primitive lacks (glTF-Validator's MESH_PRIMITIVE_TOO_FEW_TEXCOORDS):
 * its coordinates are 0 there, so those textures read at uv (0, 0). */
static void note_missing_uvs(const Model &m, int mesh, const std::vector<uv_use> &use, notes &warn)
{
    const tinygltf::Mesh &me = m.meshes[size_t(mesh)];
    for (size_t p = 0; p < me.primitives.size(); p++) {
        const tinygltf::Primitive &prim = me.primitives[p];
        if (!is_triangles(prim) || !prim.attributes.count("POSITION") || prim.material < 0 ||
            size_t(prim.material) >= use.size()) /* a bad index fails in emit_primitive */
            continue;
        for (unsigned k = 0; k < 2; k++)
            if (use[size_t(prim.material)].sets >> k & 1u &&
                !prim.attributes.count(k ? "TEXCOORD_1" : "TEXCOORD_0"))
                note(warn, "mesh %d (%s) primitive %zu: material %d reads TEXCOORD_%u, which the "
                           "primitive lacks: its textures read at uv (0, 0)",
                     mesh, me.name.c_str(), p, prim.material, k);
    }
}

/* The cap on the triangles a scene makes (ST_GLTF_MAX_TRIANGLES), checked
 * before the triangle arrays are allocated. */
static void check_triangle_bound(size_t bound)
{
    if (bound > ST_GLTF_MAX_TRIANGLES)
        fail("the scene makes up to %zu triangles, every instance counted: more than 2^24, the "
             "limit (about 400 bytes of memory each)", bound);
}

/* Whether drawing `in` (morphed by `weights`) must read its mesh's primitives anew, or may
 * reuse those the drawing before it read (*read_mesh, *read_weights; updated): consecutive
 * drawings of one mesh with the same weights (EXT_mesh_gpu_instancing's instances, sibling
 * nodes) share one read; a skinned one reads its own. */
static bool reads_mesh(const instance &in, const std::vector<double> &weights, int &read_mesh,
                       std::vector<double> &read_weights)
{
    if (in.skin < 0 && in.mesh == read_mesh && weights == read_weights)
        return false;
    read_mesh = in.skin < 0 ? in.mesh : -1;
    read_weights = weights;
    return true;
}

/* The vertices the import reads, every (re)read of a mesh counted (reads_mesh), checked
 * against ST_GLTF_MAX_VERTEX_READS before anything is read: a few bytes of JSON may draw a
 * million-vertex accessor from a thousand nodes. What each drawing then transforms is only
 * the vertices its triangles use, at most three per triangle, so ST_GLTF_MAX_TRIANGLES bounds
 * that work. */
static void check_vertex_reads(const Model &m, const std::vector<instance> &inst)
{
    size_t reads = 0;
    int read_mesh = -1;
    std::vector<double> read_weights;
    for (const instance &in : inst) {
        if (!reads_mesh(in, morph_weights(m, in.node, in.mesh), read_mesh, read_weights))
            continue;
        for (size_t p = 0; p < m.meshes[size_t(in.mesh)].primitives.size(); p++)
            reads += primitive_vertices(m, in.mesh, p);
        if (reads > ST_GLTF_MAX_VERTEX_READS)
            fail("the scene reads more than %u vertices, every node and instance that draws a "
                 "mesh counted (a mesh drawn by consecutive nodes or instances once): the limit",
                 ST_GLTF_MAX_VERTEX_READS);
    }
}

static void flatten(const Model &m, const image_bytes &bytes, notes &warn, st_gltf_data &out)
{
    std::vector<instance> inst;
    std::vector<st_gltf_camera> cams;
    std::vector<st_gltf_light> lights;
    walk_scene(m, inst, cams, lights, warn);
    /* materials first: the geometry keeps TEXCOORD_1 only where a texture reads it */
    texture_table table;
    std::vector<st_gltf_material> mats;
    for (size_t i = 0; i < m.materials.size(); i++)
        mats.push_back(read_material(m, i, table, warn));
    note_occlusion(m, warn);
    const std::vector<uv_use> use = uv_uses(mats, table);
    share_images(m, bytes, table); /* the texel budget, before anything is expanded */
    bool any_uv1 = false;
    for (const st_gltf_texture &t : table.refs)
        any_uv1 = any_uv1 || t.tex_coord == 1;
    std::vector<bool> mesh_noted(m.meshes.size(), false); /* once per mesh, however many draws */
    size_t bound = 0;
    for (const instance &in : inst) {
        if (!mesh_noted[size_t(in.mesh)]) {
            mesh_noted[size_t(in.mesh)] = true;
            note_skipped_primitives(m, in.mesh, warn);
            note_missing_uvs(m, in.mesh, use, warn);
            note_morph_targets(m, in.mesh, warn);
        }
        bound += mesh_bound(m, in.mesh); /* each primitive's <= its accessor's elements */
    }
    check_triangle_bound(bound);
    check_vertex_reads(m, inst);
    if (!m.animations.empty())
        note(warn, "%zu animation%s not played: the rest pose is rendered (default node "
                   "transforms and morph weights)",
             m.animations.size(), m.animations.size() == 1 ? "" : "s");
    out.positions = alloc_array<float>(bound, 9);
    out.normals = alloc_array<float>(bound, 9);
    out.uvs = alloc_array<float>(bound, 6);
    out.uvs1 = any_uv1 ? alloc_array<float>(bound, 6) : nullptr;
    out.tangents = alloc_array<float>(bound, 12);
    out.colors = alloc_array<float>(bound, 12);
    out.tri_material = alloc_array<uint32_t>(bound, 1);
    sink s = {out.positions, out.normals, out.uvs, out.tangents, out.colors, out.uvs1,
              out.tri_material, 0, 0};
    std::vector<scratch> prims; /* the mesh read last, a primitive each (reads_mesh) */
    int read_mesh = -1;
    std::vector<double> read_weights;
    node_worlds worlds;
    if (!m.skins.empty())
        worlds = {node_parents(m), std::vector<mat4>(m.nodes.size()),
                  std::vector<char>(m.nodes.size(), 0)};
    std::vector<std::vector<mat4>> joints(m.skins.size()); /* per skin, made once */
    for (const instance &in : inst) {
        const normal_xform nx = normal_matrix(in.world);
        const std::vector<double> weights = morph_weights(m, in.node, in.mesh);
        if (in.skin >= 0 && joints[size_t(in.skin)].empty())
            joints[size_t(in.skin)] = joint_matrices(m, in.skin, worlds);
        const size_t np = m.meshes[size_t(in.mesh)].primitives.size();
        if (reads_mesh(in, weights, read_mesh, read_weights)) {
            prims.resize(std::max(prims.size(), np));
            for (size_t p = 0; p < np; p++)
                read_primitive(m, in.mesh, p, weights, use, any_uv1, prims[p]);
        }
        for (size_t p = 0; p < np; p++)
            place_primitive(m, in.mesh, p, in.world, nx,
                            in.skin >= 0 ? &joints[size_t(in.skin)] : nullptr, prims[p], s);
    }
    out.tri_count = s.count;
    out.dropped = s.dropped;
    out.positions = shrink(out.positions, s.count, 9);
    out.normals = shrink(out.normals, s.count, 9);
    out.uvs = shrink(out.uvs, s.count, 6);
    out.uvs1 = any_uv1 ? shrink(out.uvs1, s.count, 6) : nullptr;
    out.tangents = shrink(out.tangents, s.count, 12);
    out.colors = shrink(out.colors, s.count, 12);
    out.tri_material = shrink(out.tri_material, s.count, 1);
    out.image_count = m.images.size() + table.derived.size();
    out.images = alloc_array<st_gltf_image>(out.image_count, 1);
    if (out.images)
        memset(out.images, 0, out.image_count * sizeof *out.images);
    note_unreadable(mats, table, decode_images(m, bytes, table, out.images), warn);
    out.material_count = mats.size();
    out.materials = copy_out(mats);
    out.texture_count = table.refs.size();
    out.textures = copy_out(table.refs);
    for (size_t k = 0; k < table.derived.size(); k++) { /* their sources are decoded above */
        const st_gltf_image &src = out.images[size_t(table.derived[k].first)];
        out.images[m.images.size() + k] = roughness_from_gloss(src, table.derived[k].second);
    }
    out.camera_count = cams.size();
    out.cameras = copy_out(cams);
    out.light_count = lights.size();
    out.lights = copy_out(lights);
}

/* The warnings as malloc'd C strings (a last line counts those left out). */
/* The scene's extent (the largest side of its bounds) outside the range in
 * which single-precision rays and their offsets still resolve it: at 1e13 and
 * above, or 1e-16 and below, the render comes out empty, so say why. */
static void note_degenerate_scale(const st_gltf_data &out, notes &warn)
{
    if (out.tri_count == 0)
        return;
    double extent = 0.0;
    for (int k = 0; k < 3; k++) {
        double lo = INFINITY, hi = -INFINITY;
        for (size_t i = k; i < 9 * out.tri_count; i += 3) {
            lo = std::min(lo, double(out.positions[i]));
            hi = std::max(hi, double(out.positions[i]));
        }
        extent = std::max(extent, hi - lo);
    }
    if (extent >= 1e13 || extent <= 1e-16)
        note(warn, "the scene spans %g units: beyond 1e13 or below 1e-16 single-precision rays "
                   "cannot resolve it and the image may be empty; scale the model",
             extent);
}

static void take_warnings(const notes &warn, st_gltf_data &out)
{
    std::vector<std::string> lines = warn.lines;
    if (warn.more)
        lines.push_back("... and " + std::to_string(warn.more) + " more warnings");
    out.warnings = alloc_array<char *>(lines.size(), 1);
    for (const std::string &l : lines) {
        char *c = static_cast<char *>(malloc(l.size() + 1));
        if (!c)
            throw std::bad_alloc();
        memcpy(c, l.c_str(), l.size() + 1);
        out.warnings[out.warning_count++] = c;
    }
}

} /* namespace st_gltf */

using namespace st_gltf;

extern "C" st_status st_gltf_shim_load(const char *label, const unsigned char *bytes,
                                       size_t size, const char *base_dir, st_gltf_data *out,
                                       st_error *err)
{
    *out = st_gltf_data();
    if (!label)
        label = "(glTF)";
    try {
        Model model;
        image_bytes images;
        notes warn;
        parse(model, bytes, size, base_dir, images, warn);
        densify_sparse(model, used_accessors(model));
        flatten(model, images, warn, *out);
        note_degenerate_scale(*out, warn);
        take_warnings(warn, *out);
        return ST_OK;
    } catch (const shim_error &e) {
        st_gltf_shim_release(out);
        return st_fail(err, e.status, "%s: %s", label, e.msg.c_str());
    } catch (const std::bad_alloc &) {
        st_gltf_shim_release(out);
        return st_fail(err, ST_ERR_NOMEM, "%s: out of memory", label);
    } catch (const std::exception &e) {
        st_gltf_shim_release(out);
        return st_fail(err, ST_ERR_FORMAT, "%s: %s", label, e.what());
    } catch (...) {
        st_gltf_shim_release(out);
        return st_fail(err, ST_ERR_FORMAT, "%s: unreadable glTF", label);
    }
}

extern "C" void st_gltf_shim_release(st_gltf_data *data)
{
    if (!data)
        return;
    free(data->positions);
    free(data->normals);
    free(data->uvs);
    free(data->uvs1);
    free(data->tangents);
    free(data->colors);
    free(data->tri_material);
    free(data->materials);
    free(data->textures);
    for (size_t i = 0; i < data->image_count && data->images; i++)
        stbi_image_free(data->images[i].rgba);
    free(data->images);
    free(data->cameras);
    free(data->lights);
    for (size_t i = 0; i < data->warning_count; i++)
        free(data->warnings[i]);
    free(data->warnings);
    *data = st_gltf_data();
}
