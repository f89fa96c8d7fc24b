/* gltf_shim.cpp — glTF 2.0 import through tinygltf, the one C++ file of strata,
 * behind the C interface of gltf_shim.h.
 *
 * Spec: Khronos Group, "glTF 2.0 Specification", version 2.0.1 (2021):
 * §3.5 nodes and the TRS/matrix transform hierarchy, §3.6 buffers, bufferViews
 * and accessors, §3.7.2 mesh primitives, §3.9 materials, §4.4 the GLB
 * container; and the KHR_materials_emissive_strength extension.
 *
 * Invariants: no byte of a buffer is read before the accessor and bufferView
 * ranges that cover it were checked against the buffer's real size, and no
 * index is used before it was checked against its array; a malformed file
 * becomes a shim_error (one line), never a crash. No C++ exception leaves this
 * file: st_gltf_shim_load catches them all. Buffers are read as little-endian
 * (the glTF byte order) with memcpy, so no alignment is assumed.
 *
 * Flattening: every node reachable from the scene's roots contributes its
 * mesh's TRIANGLES primitives, transformed by the node's world matrix
 * (parent * local, local = T * R * S or the node's matrix). Normals go through
 * the inverse transpose; where the determinant is negative the winding is
 * reversed (v1 <-> v2), as the spec asks of mirrored nodes (§3.7.2.1). */
#include "gltf_shim.h"

#include <tiny_gltf.h>

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <vector>

namespace {

using tinygltf::Model;

/* Raised anywhere below; st_gltf_shim_load turns it into the st_error. */
struct shim_error {
    st_status status;
    std::string msg;
};

[[noreturn]] void fail(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void fail(const char *fmt, ...)
{
    char buf[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    throw shim_error{ST_ERR_FORMAT, buf};
}

/* ---- file access for tinygltf ------------------------------------------- */

/* Our own file callbacks replace tinygltf's defaults, which pass every URI
 * through wordexp() (expanding "$VAR" and "~" in file names) and also look
 * for a missing file in the working directory. */
struct fs_context {
    const char *base_dir; /* NULL: no file access at all (embedded scenes) */
};

bool fs_exists(const std::string &path, void *user)
{
    const fs_context *ctx = static_cast<const fs_context *>(user);
    if (!ctx->base_dir)
        return false;
    size_t n = strlen(ctx->base_dir);
    if (path.compare(0, n, ctx->base_dir) != 0) /* tinygltf's "./" fallback */
        return false;
    FILE *f = fopen(path.c_str(), "rb");
    if (!f)
        return false;
    fclose(f);
    return true;
}

std::string fs_expand(const std::string &path, void *) { return path; }

bool fs_read(std::vector<unsigned char> *out, std::string *err, const std::string &path,
             void *user)
{
    const fs_context *ctx = static_cast<const fs_context *>(user);
    if (!ctx->base_dir) {
        *err = "built-in scenes may use data: URIs only";
        return false;
    }
    FILE *f = fopen(path.c_str(), "rb");
    if (!f) {
        *err = strerror(errno);
        return false;
    }
    unsigned char chunk[65536];
    size_t got;
    out->clear();
    while ((got = fread(chunk, 1, sizeof chunk, f)) > 0)
        out->insert(out->end(), chunk, chunk + got);
    bool ok = !ferror(f);
    if (!ok)
        *err = "read error";
    fclose(f);
    return ok;
}

bool fs_write(std::string *, const std::string &, const std::vector<unsigned char> &, void *)
{
    return false;
}

/* Textures are not used yet: skip decoding images (time, and formats that stb
 * cannot read would otherwise fail the whole load). */
bool skip_image(tinygltf::Image *, const int, std::string *, std::string *, int, int,
                const unsigned char *, int, void *)
{
    return true;
}

std::string first_line(const std::string &s)
{
    std::string line = s.substr(0, s.find('\n'));
    while (!line.empty() && (line.back() == '\r' || line.back() == ' '))
        line.pop_back();
    return line;
}

uint32_t le32(const unsigned char *p)
{
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

/* GLB (§4.4): a 12-byte header (magic, version, total length) and chunks of
 * (length, type, data). tinygltf 2.7 checks a BIN chunk's end without its
 * 8-byte header, so every chunk is checked to lie inside the data here. */
void check_glb(const unsigned char *b, size_t size)
{
    if (size < 12)
        fail("GLB header cut off (%zu bytes)", size);
    uint32_t length = le32(b + 8);
    if (length > size)
        fail("GLB header says %u bytes, the file has %zu", length, size);
    for (size_t off = 12; off < length;) {
        if (length - off < 8)
            fail("GLB chunk header at byte %zu cut off", off);
        uint32_t chunk = le32(b + off);
        if (chunk > length - off - 8)
            fail("GLB chunk at byte %zu (%u bytes) runs past the end", off, chunk);
        off += 8 + size_t(chunk);
    }
}

void parse(Model &model, const unsigned char *bytes, size_t size, const char *base_dir)
{
    if (size > UINT_MAX)
        fail("file too large (%zu bytes)", size);
    const bool glb = size >= 4 && memcmp(bytes, "glTF", 4) == 0;
    if (glb)
        check_glb(bytes, size);
    fs_context ctx = {base_dir};
    tinygltf::FsCallbacks fs = {fs_exists, fs_expand, fs_read, fs_write, &ctx};
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks(fs);
    loader.SetImageLoader(skip_image, nullptr);
    std::string err, warn, dir = base_dir ? base_dir : "";
    bool ok = glb ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes, unsigned(size), dir)
                  : loader.LoadASCIIFromString(&model, &err, &warn,
                                               reinterpret_cast<const char *>(bytes),
                                               unsigned(size), dir);
    if (!ok) {
        std::string why = first_line(err.empty() ? warn : err);
        fail("%s", why.empty() ? "tinygltf could not parse the file" : why.c_str());
    }
    for (const std::string &ext : model.extensionsRequired)
        if (ext == "KHR_draco_mesh_compression" || ext == "EXT_meshopt_compression" ||
            ext == "KHR_mesh_quantization")
            fail("requires extension %s, which strata does not support", ext.c_str());
}

/* ---- transforms ------------------------------------------------------------ */

struct mat4 {
    double m[16]; /* column-major, m[4 * column + row], as glTF stores matrices */
};

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

void check_numbers(const std::vector<double> &v, size_t n, int node, const char *what)
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

/* Normal matrix of the upper 3x3 A = [a0 a1 a2] (columns): A^-T has columns
 * (a1 x a2, a2 x a0, a0 x a1) / det A (the cofactor matrix over the
 * determinant; pbr-book 4ed §3.10.3 "Normals"). Normals are renormalised
 * afterwards, so only the sign of det matters: n' = sign(det) cof(A) n. */
struct normal_xform {
    double col[3][3];
    double det;
};

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

/* ---- the node tree ---------------------------------------------------------- */

struct instance {
    int mesh;
    mat4 world;
};

struct camera_pick {
    bool found;
    float origin[3], forward[3], up[3], yfov;
};

bool normalize3(double v[3])
{
    double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(len > 0.0) || !std::isfinite(len))
        return false;
    for (int i = 0; i < 3; i++)
        v[i] /= len;
    return true;
}

/* A perspective camera looks down its node's local -Z with +Y up (§3.10.1).
 * Up is made orthogonal to forward (Gram-Schmidt). A node whose transform
 * collapses either axis (zero scale) is passed over. */
void take_camera(const Model &m, int cam, const mat4 &world, camera_pick &pick)
{
    const tinygltf::Camera &c = m.cameras[size_t(cam)];
    if (c.type != "perspective")
        return;
    const double yfov = c.perspective.yfov;
    if (!(yfov > 0.0 && yfov < M_PI))
        fail("camera %d: yfov %g is not in (0, pi)", cam, yfov);
    double f[3] = {0.0 - world.m[8], 0.0 - world.m[9], 0.0 - world.m[10]}; /* no -0 */
    double u[3] = {world.m[4], world.m[5], world.m[6]};
    if (!normalize3(f))
        return;
    const double d = u[0] * f[0] + u[1] * f[1] + u[2] * f[2];
    for (int i = 0; i < 3; i++)
        u[i] -= d * f[i];
    if (!normalize3(u))
        return;
    for (int i = 0; i < 3; i++) {
        pick.origin[i] = float(world.m[12 + i]);
        pick.forward[i] = float(f[i]);
        pick.up[i] = float(u[i]);
    }
    pick.yfov = float(yfov);
    pick.found = true;
}

/* Fails with "<context> I out of range (have N)" unless 0 <= i < n; the
 * context is printf-formatted ("node %d: mesh"). */
void check_index(int i, size_t n, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
void check_index(int i, size_t n, const char *fmt, ...)
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

/* Depth-first, in scene order (an explicit stack: a deep chain of nodes must
 * not overflow the C stack). The node graph must be disjoint trees (§3.5.2),
 * so a node reached twice (a cycle, or two parents) is an error. */
void walk_scene(const Model &m, std::vector<instance> &out, camera_pick &cam)
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
            out.push_back({node.mesh, world});
        }
        if (node.camera != -1) {
            check_index(node.camera, m.cameras.size(), "node %d: camera", it.node);
            if (!cam.found)
                take_camera(m, node.camera, world, cam);
        }
        for (size_t i = node.children.size(); i-- > 0;) {
            check_index(node.children[i], m.nodes.size(), "node %d: child", it.node);
            stack.push_back({node.children[i], world});
        }
    }
}

/* ---- accessors -------------------------------------------------------------- */

/* The checked bytes of one accessor: element i starts at data + i * stride. */
struct span {
    const unsigned char *data;
    size_t stride, count;
    int component;
};

size_t component_size(int type)
{
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
    }
}

size_t type_components(int type)
{
    switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4:
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
    }
}

/* Checks accessor `a` and its bufferView against the buffer's actual bytes
 * (§3.6.2.4: offset + stride * (count - 1) + element size <= view length). */
span accessor_span(const Model &m, int a)
{
    const tinygltf::Accessor &acc = m.accessors[size_t(a)];
    if (acc.sparse.isSparse)
        fail("accessor %d: sparse accessors are not supported", a);
    if (acc.bufferView < 0)
        fail("accessor %d: no bufferView (not supported)", a);
    check_index(acc.bufferView, m.bufferViews.size(), "accessor %d: bufferView", a);
    const tinygltf::BufferView &view = m.bufferViews[size_t(acc.bufferView)];
    check_index(view.buffer, m.buffers.size(), "bufferView %d: buffer", acc.bufferView);
    const std::vector<unsigned char> &buf = m.buffers[size_t(view.buffer)].data;
    if (view.byteOffset > buf.size() || view.byteLength > buf.size() - view.byteOffset)
        fail("bufferView %d: bytes %zu + %zu run past the end of buffer %d (%zu bytes)",
             acc.bufferView, view.byteOffset, view.byteLength, view.buffer, buf.size());
    const size_t elem = component_size(acc.componentType) * type_components(acc.type);
    if (elem == 0)
        fail("accessor %d: bad componentType %d or type %d", a, acc.componentType, acc.type);
    const size_t stride = view.byteStride ? view.byteStride : elem;
    if (stride < elem)
        fail("accessor %d: byteStride %zu is smaller than an element (%zu bytes)", a, stride,
             elem);
    if (acc.count > 0) {
        const bool starts_inside = acc.byteOffset <= view.byteLength;
        const size_t avail = starts_inside ? view.byteLength - acc.byteOffset : 0;
        if (!starts_inside || elem > avail || acc.count - 1 > (avail - elem) / stride)
            fail("accessor %d: %zu elements from byte %zu run past the end of bufferView %d "
                 "(%zu bytes)",
                 a, acc.count, acc.byteOffset, acc.bufferView, view.byteLength);
    }
    return {buf.data() + view.byteOffset + acc.byteOffset, stride, acc.count, acc.componentType};
}

/* Reads a float VEC3 accessor (POSITION, NORMAL) into xyz triples. glTF
 * accessors must not hold NaN or infinity (glTF-Validator's
 * ACCESSOR_INVALID_FLOAT), so one is a format error, not a dropped triangle. */
void read_vec3(const Model &m, int a, std::vector<float> &out)
{
    const tinygltf::Accessor &acc = m.accessors[size_t(a)];
    if (acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || acc.type != TINYGLTF_TYPE_VEC3)
        fail("accessor %d: must be float VEC3 (componentType %d, type %d)", a,
             acc.componentType, acc.type);
    const span s = accessor_span(m, a);
    out.resize(3 * s.count);
    for (size_t i = 0; i < s.count; i++)
        memcpy(&out[3 * i], s.data + i * s.stride, 3 * sizeof(float));
    for (size_t k = 0; k < out.size(); k++)
        if (!std::isfinite(out[k]))
            fail("accessor %d: non-finite value in element %zu", a, k / 3);
}

/* Reads an index accessor (unsigned byte, short or int scalars), checking
 * every index against the vertex count. */
void read_indices(const Model &m, int a, size_t vertices, std::vector<uint32_t> &out)
{
    const tinygltf::Accessor &acc = m.accessors[size_t(a)];
    const int ct = acc.componentType;
    const bool unsigned_int = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                              ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
                              ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    if (acc.type != TINYGLTF_TYPE_SCALAR || !unsigned_int)
        fail("accessor %d: indices must be unsigned byte, short or int scalars", a);
    const span s = accessor_span(m, a);
    out.resize(s.count);
    for (size_t i = 0; i < s.count; i++) {
        const unsigned char *p = s.data + i * s.stride;
        uint32_t v;
        if (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
            v = p[0];
        } else if (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
            uint16_t h;
            memcpy(&h, p, 2);
            v = h;
        } else {
            memcpy(&v, p, 4);
        }
        if (v >= vertices)
            fail("accessor %d: index %u out of range (%zu vertices)", a, v, vertices);
        out[i] = v;
    }
}

/* ---- primitives -------------------------------------------------------------- */

const tinygltf::Primitive &primitive(const Model &m, int mesh, size_t p)
{
    return m.meshes[size_t(mesh)].primitives[p];
}

int position_accessor(const Model &m, int mesh, size_t p)
{
    const tinygltf::Primitive &prim = primitive(m, mesh, p);
    const int mode = prim.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != -1) /* -1: Primitive() default */
        return -1; /* points, lines, strips and fans: not yet */
    auto it = prim.attributes.find("POSITION");
    if (it == prim.attributes.end()) /* §3.7.2.1: such a primitive is not drawn */
        return -1;
    check_index(it->second, m.accessors.size(), "mesh %d primitive %zu: POSITION accessor", mesh,
                p);
    return it->second;
}

/* Upper bound of a primitive's triangles (checked ranges), to size the output
 * once: the index count / 3, or the vertex count / 3 without indices. */
size_t primitive_bound(const Model &m, int mesh, size_t p)
{
    const int pos = position_accessor(m, mesh, p);
    if (pos < 0)
        return 0;
    const int ind = primitive(m, mesh, p).indices;
    if (ind != -1)
        check_index(ind, m.accessors.size(), "mesh %d primitive %zu: indices accessor", mesh, p);
    return accessor_span(m, ind != -1 ? ind : pos).count / 3;
}

/* Where triangles go: arrays sized by the bound, filled in scene order. */
struct sink {
    float *pos, *nrm;
    uint32_t *mat;
    size_t count, dropped;
};

/* Per-primitive scratch, reused so that big scenes allocate once. */
struct scratch {
    std::vector<float> p, n, wp, wn;
    std::vector<uint32_t> idx;
};

/* Vertices to world space: positions by the world matrix, normals by the
 * normal matrix and renormalised; a normal that cannot be normalised is
 * marked NaN and replaced by the face normal later. */
void transform_vertices(const mat4 &w, const normal_xform &nx, scratch &s, bool normals)
{
    const size_t nv = s.p.size() / 3;
    s.wp.resize(3 * nv);
    s.wn.resize(normals ? 3 * nv : 0);
    for (size_t v = 0; v < nv; v++) {
        const float *p = &s.p[3 * v];
        for (int r = 0; r < 3; r++)
            s.wp[3 * v + size_t(r)] =
                float(w.m[r] * p[0] + w.m[4 + r] * p[1] + w.m[8 + r] * p[2] + w.m[12 + r]);
        if (!normals)
            continue;
        const float *n = &s.n[3 * v];
        double t[3];
        for (int r = 0; r < 3; r++)
            t[r] = nx.col[0][r] * n[0] + nx.col[1][r] * n[1] + nx.col[2][r] * n[2];
        if (!normalize3(t))
            t[0] = t[1] = t[2] = NAN;
        for (int r = 0; r < 3; r++)
            s.wn[3 * v + size_t(r)] = float(t[r]);
    }
}

/* Appends triangle (i0, i1, i2) unless it is non-finite or has zero area.
 * The face normal g = (p1 - p0) x (p2 - p0) / |...| is computed in double,
 * where float inputs cannot overflow, so |g| is finite exactly when the three
 * positions are; g stands in for missing or unusable vertex normals. */
void emit_triangle(const scratch &s, const uint32_t i[3], bool normals, uint32_t material,
                   sink &out)
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
    for (int v = 0; v < 3; v++) {
        const float *n = normals ? &s.wn[3 * size_t(i[v])] : nullptr;
        const bool usable = n && !std::isnan(n[0]);
        for (int k = 0; k < 3; k++) {
            dp[3 * v + k] = p[v][k];
            dn[3 * v + k] = usable ? n[k] : float(g[k]);
        }
    }
    out.mat[out.count++] = material;
}

void emit_primitive(const Model &m, int mesh, size_t p, const mat4 &world,
                    const normal_xform &nx, scratch &s, sink &out)
{
    const int pos = position_accessor(m, mesh, p);
    if (pos < 0)
        return;
    const tinygltf::Primitive &prim = primitive(m, mesh, p);
    if (prim.material != -1)
        check_index(prim.material, m.materials.size(), "mesh %d primitive %zu: material", mesh, p);
    const uint32_t material = prim.material == -1 ? ST_GLTF_NO_MATERIAL : uint32_t(prim.material);
    read_vec3(m, pos, s.p);
    const size_t nv = s.p.size() / 3;
    auto nit = prim.attributes.find("NORMAL");
    const bool normals = nit != prim.attributes.end();
    if (normals) {
        check_index(nit->second, m.accessors.size(), "mesh %d primitive %zu: NORMAL accessor",
                    mesh, p);
        read_vec3(m, nit->second, s.n);
        if (s.n.size() != s.p.size())
            fail("mesh %d primitive %zu: NORMAL has %zu elements, POSITION %zu", mesh, p,
                 s.n.size() / 3, nv);
    }
    if (prim.indices != -1) {
        check_index(prim.indices, m.accessors.size(), "mesh %d primitive %zu: indices accessor",
                    mesh, p);
        read_indices(m, prim.indices, nv, s.idx);
    } else {
        s.idx.resize(nv);
        for (size_t v = 0; v < nv; v++)
            s.idx[v] = uint32_t(v);
    }
    transform_vertices(world, nx, s, normals);
    const bool flip = nx.det < 0.0;
    for (size_t t = 0; t + 3 <= s.idx.size(); t += 3) { /* a trailing 1 or 2 are ignored */
        uint32_t tri[3] = {s.idx[t], s.idx[t + 1], s.idx[t + 2]};
        if (flip) {
            tri[1] = s.idx[t + 2];
            tri[2] = s.idx[t + 1];
        }
        emit_triangle(s, tri, normals, material, out);
    }
}

/* ---- materials ------------------------------------------------------------- */

/* base colour = pbrMetallicRoughness.baseColorFactor (RGBA); emission =
 * emissiveFactor x KHR_materials_emissive_strength.emissiveStrength (1 when
 * absent). Factors must be finite and non-negative. */
void read_materials(const Model &m, float *out)
{
    for (size_t i = 0; i < m.materials.size(); i++) {
        const tinygltf::Material &mat = m.materials[i];
        const std::vector<double> &bc = mat.pbrMetallicRoughness.baseColorFactor;
        const std::vector<double> &ef = mat.emissiveFactor;
        if (bc.size() != 4 || ef.size() != 3)
            fail("material %zu: baseColorFactor needs 4 numbers, emissiveFactor 3", i);
        double strength = 1.0;
        auto ext = mat.extensions.find("KHR_materials_emissive_strength");
        if (ext != mat.extensions.end() && ext->second.Has("emissiveStrength")) {
            const tinygltf::Value &v = ext->second.Get("emissiveStrength");
            if (!v.IsNumber())
                fail("material %zu: emissiveStrength is not a number", i);
            strength = v.GetNumberAsDouble();
        }
        float *o = out + 8 * i;
        for (int k = 0; k < 4; k++)
            o[k] = float(bc[size_t(k)]);
        for (int k = 0; k < 3; k++)
            o[4 + k] = float(ef[size_t(k)] * strength);
        o[7] = 0.0f;
        for (int k = 0; k < 7; k++)
            if (!std::isfinite(o[k]) || o[k] < 0.0f)
                fail("material %zu: colour factors and emissiveStrength must be finite and "
                     ">= 0",
                     i);
    }
}

/* ---- the whole file ---------------------------------------------------------- */

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

void flatten(const Model &m, st_gltf_data &out)
{
    std::vector<instance> inst;
    camera_pick cam = {};
    walk_scene(m, inst, cam);
    size_t bound = 0;
    for (const instance &in : inst)
        for (size_t p = 0; p < m.meshes[size_t(in.mesh)].primitives.size(); p++)
            bound += primitive_bound(m, in.mesh, p); /* each <= buffer bytes / 3 */
    out.positions = alloc_array<float>(bound, 9);
    out.normals = alloc_array<float>(bound, 9);
    out.tri_material = alloc_array<uint32_t>(bound, 1);
    sink s = {out.positions, out.normals, out.tri_material, 0, 0};
    scratch tmp;
    for (const instance &in : inst) {
        const normal_xform nx = normal_matrix(in.world);
        for (size_t p = 0; p < m.meshes[size_t(in.mesh)].primitives.size(); p++)
            emit_primitive(m, in.mesh, p, in.world, nx, tmp, s);
    }
    out.tri_count = s.count;
    out.dropped = s.dropped;
    out.positions = shrink(out.positions, s.count, 9);
    out.normals = shrink(out.normals, s.count, 9);
    out.tri_material = shrink(out.tri_material, s.count, 1);
    out.material_count = m.materials.size();
    out.materials = alloc_array<float>(out.material_count, 8);
    read_materials(m, out.materials);
    if (cam.found) {
        out.has_camera = 1;
        memcpy(out.cam_origin, cam.origin, sizeof cam.origin);
        memcpy(out.cam_forward, cam.forward, sizeof cam.forward);
        memcpy(out.cam_up, cam.up, sizeof cam.up);
        out.cam_yfov = cam.yfov;
    }
}

} /* namespace */

extern "C" st_status st_gltf_shim_load(const char *label, const unsigned char *bytes,
                                       size_t size, const char *base_dir, st_gltf_data *out,
                                       st_error *err)
{
    *out = st_gltf_data();
    if (!label)
        label = "(glTF)";
    try {
        Model model;
        parse(model, bytes, size, base_dir);
        flatten(model, *out);
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
    free(data->tri_material);
    free(data->materials);
    *data = st_gltf_data();
}
