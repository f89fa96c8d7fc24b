/* gltf_int.h — what the glTF importer's files (src/scene/gltf_*.cpp) share:
 * the error and warning helpers, the types that pass between the jobs, and
 * each file's functions that another file calls. Private to them: scene.c
 * sees only gltf_shim.h.
 *
 * Errors: fail() throws a shim_error (one line); st_gltf_shim_load
 * (gltf_shim.cpp) catches every exception, so none leaves the importer.
 * The files call one way (tools/check_layers.py checks it): transform and
 * accessors at the bottom; cameras, lights, skins; geometry; instancing;
 * textures, then materials; parse; gltf_shim.cpp on top. */
#ifndef ST_GLTF_INT_H
#define ST_GLTF_INT_H

#include "gltf_shim.h"

#include <tiny_gltf.h>

#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace st_gltf {

using tinygltf::Model;

/* ---- errors and warnings ------------------------------------------------- */

/* Raised anywhere in the importer; st_gltf_shim_load turns it into the st_error. */
struct shim_error {
    st_status status;
    std::string msg;
};

[[noreturn]] inline void fail(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
inline void fail(const char *fmt, ...)
{
    char buf[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    throw shim_error{ST_ERR_FORMAT, buf};
}

/* Warnings of one load: the first ST_GLTF_MAX_WARNINGS lines and a count of
 * the rest. */
struct notes {
    std::vector<std::string> lines;
    size_t more = 0;
};

inline void note(notes &n, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
inline void note(notes &n, const char *fmt, ...)
{
    if (n.lines.size() >= ST_GLTF_MAX_WARNINGS - 1) {
        n.more++;
        return;
    }
    char buf[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    n.lines.push_back(buf);
}

/* Fails with "<context> I out of range (have N)" unless 0 <= i < n; the
 * context is printf-formatted ("node %d: mesh"). */
inline void check_index(int i, size_t n, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
inline void check_index(int i, size_t n, const char *fmt, ...)
{
    if (i >= 0 && size_t(i) < n)
        return;
    char what[160];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    fail("%s %d out of range (have %zu)", what, i, n);
}

/* ---- types that pass between the files ------------------------------------ */

struct mat4 {
    double m[16]; /* column-major, m[4 * column + row], as glTF stores matrices */
};

/* Normal matrix of the upper 3x3 A = [a0 a1 a2] (columns): A^-T has columns
 * (a1 x a2, a2 x a0, a0 x a1) / det A (the cofactor matrix over the
 * determinant; pbr-book 4ed §3.10.3 "Normals"). Normals are renormalised
 * afterwards, so only the sign of det matters: n' = sign(det) cof(A) n. */
struct normal_xform {
    double col[3][3];
    double det;
};

/* A mesh as one node (or one EXT_mesh_gpu_instancing instance of it)
 * draws it: its world matrix, the node (its morph weights) and the node's
 * skin (-1: none). */
struct instance {
    int mesh;
    mat4 world;
    int node = -1, skin = -1;
};

/* The checked bytes of one accessor: element i starts at data + i * stride. */
struct span {
    const unsigned char *data;
    size_t stride, count;
    int component;
};

/* Where triangles go: arrays sized by the bound, filled in scene order. */
struct sink {
    float *pos, *nrm, *uv, *tan, *col;
    float *uv1; /* nullptr: no texture reads TEXCOORD_1 */
    uint32_t *mat;
    size_t count, dropped;
};

/* One primitive as read_primitive made it (object space: p, n, uv, uv1, t, c, idx as a
 * triangle list, and the vertices its triangles use) and as place_primitive moves it (world
 * space: wp, wn, wt, neg); kept while consecutive drawings of its mesh reuse it. */
struct scratch {
    std::vector<float> p, n, uv, uv1, wp, wn, t, wt, c;
    std::vector<uint32_t> idx;
    std::vector<uint32_t> used; /* the distinct vertices of idx's whole triangles, ascending */
    std::vector<char> neg;      /* skinned: the vertex's skin matrix mirrors (det < 0) */
    bool drawn = false;         /* false: a primitive strata skips (another mode, no POSITION) */
    bool normals = false;       /* it has NORMAL */
    unsigned sets = 0;          /* bit k: it has TEXCOORD_k */
    uint32_t material = ST_GLTF_NO_MATERIAL;
};

/* What a material's textures read: bit k of `sets` for TEXCOORD_k, and
 * the set of its normal map, the one its generated tangents follow (0
 * without a normal map). */
struct uv_use {
    unsigned sets = 0;
    int normal_set = 0;
};

/* Encoded bytes of the images given by URI (file or data:), by image index;
 * images in a bufferView are read later from their checked range. */
struct image_bytes {
    std::map<int, std::vector<unsigned char>> by_index;
};

/* World matrices of the nodes skins name, by their chains of parents (a
 * joint need not lie under the scene's roots the way the skinned mesh
 * does), each node's computed once. */
struct node_worlds {
    std::vector<int> parent;
    std::vector<mat4> world;
    std::vector<char> known;
};

/* Texture references of the materials, made unique; and the images made
 * here rather than read (image index m.images.size() + k): roughness maps
 * derived from a KHR_materials_pbrSpecularGlossiness texture's alpha
 * (source image, glossinessFactor). */
struct texture_table {
    std::vector<st_gltf_texture> refs;
    std::vector<std::pair<int, float>> derived;
};

inline const tinygltf::Primitive &primitive(const Model &m, int mesh, size_t p)
{
    return m.meshes[size_t(mesh)].primitives[p];
}

/* ---- each file's functions that others call (comments at the definitions) -- */

/* gltf_transform.cpp */
mat4 identity();
mat4 mul(const mat4 &a, const mat4 &b);
mat4 node_local(const tinygltf::Node &n, int idx);
void cross(const double a[3], const double b[3], double out[3]);
bool normalize3(double v[3]);
normal_xform normal_matrix(const mat4 &m);
void transform_vertex(const mat4 &w, const normal_xform &nx, scratch &s, size_t v, bool normals);
void transform_vertices(const mat4 &w, const normal_xform &nx, scratch &s, bool normals);
void transform_tangents(const mat4 &w, double det, scratch &s);

/* gltf_accessors.cpp */
span accessor_span(const Model &m, int a);
void densify_sparse(Model &m, const std::vector<char> &used);
float component(const unsigned char *p, int ct, bool normalized, int k);
void read_attribute(const Model &m, int a, const char *attr, int n, size_t vertices,
                    std::vector<float> &out);
void read_vec3(const Model &m, int a, const char *attr, std::vector<float> &out);
void read_indices(const Model &m, int a, size_t vertices, std::vector<uint32_t> &out);
void read_uv(const Model &m, int a, const char *attr, size_t vertices, std::vector<float> &out);
int attribute(const Model &m, int mesh, size_t p, const char *name);

/* gltf_cameras.cpp */
void take_camera(const Model &m, int node, int cam, const mat4 &world,
                 std::vector<st_gltf_camera> &out, notes &warn);

/* gltf_lights.cpp */
int node_light(const tinygltf::Node &node, int index, size_t light_count);
void take_light(const Model &m, int node, int li, const mat4 &world,
                std::vector<st_gltf_light> &out, notes &warn);

/* gltf_skins.cpp */
std::vector<double> morph_weights(const Model &m, int node, int mesh);
void apply_morph(const Model &m, int mesh, size_t p, const std::vector<double> &w,
                 const char *attr, size_t stride, std::vector<float> &values);
void note_morph_targets(const Model &m, int mesh, notes &warn);
std::vector<int> node_parents(const Model &m);
std::vector<mat4> joint_matrices(const Model &m, int k, node_worlds &worlds);
std::vector<mat4> skin_matrices(const Model &m, int mesh, size_t p, const std::vector<mat4> &J,
                                const mat4 &fallback, size_t nv);
void skin_vertices(const std::vector<mat4> &M, scratch &s, bool normals);

/* gltf_geometry.cpp */
bool is_triangles(const tinygltf::Primitive &prim);
void note_skipped_primitives(const Model &m, int mesh, notes &warn);
size_t primitive_bound(const Model &m, int mesh, size_t p);
size_t primitive_vertices(const Model &m, int mesh, size_t p);
void read_primitive(const Model &m, int mesh, size_t p, const std::vector<double> &weights,
                    const std::vector<uv_use> &use, bool want_uv1, scratch &s);
void place_primitive(const Model &m, int mesh, size_t p, const mat4 &world,
                     const normal_xform &nx, const std::vector<mat4> *joints, scratch &s,
                     sink &out);

/* gltf_instancing.cpp */
size_t mesh_bound(const Model &m, int mesh);
void add_mesh_instances(const Model &m, int node, const mat4 &world, std::vector<instance> &out,
                        size_t &instanced, notes &warn);

/* gltf_textures.cpp */
double ext_number(const tinygltf::Value &obj, const char *key, double fallback, const char *what);
int tex_coord_number(const tinygltf::Value &obj, int fallback, const char *what);
int texture_ref(const Model &m, const tinygltf::TextureInfo &info, bool srgb, size_t mat,
                const char *slot, texture_table &table, notes &warn);
void share_images(const Model &m, const image_bytes &bytes, texture_table &table);
std::vector<std::string> decode_images(const Model &m, const image_bytes &bytes,
                                       const texture_table &table, st_gltf_image *images);

/* gltf_materials.cpp */
st_gltf_material read_material(const Model &m, size_t i, texture_table &table, notes &warn);
st_gltf_image roughness_from_gloss(const st_gltf_image &src, float gloss);
void note_unreadable(std::vector<st_gltf_material> &mats, const texture_table &table,
                     const std::vector<std::string> &why, notes &warn);
void note_occlusion(const Model &m, notes &warn);

/* gltf_parse.cpp */
void parse(Model &model, const unsigned char *bytes, size_t size, const char *base_dir,
           image_bytes &images, notes &warn_out);

} /* namespace st_gltf */

#endif
