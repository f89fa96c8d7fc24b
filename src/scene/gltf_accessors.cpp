/* gltf_accessors.cpp — accessors (§3.6): checked ranges and typed reads.
 *
 * No byte of a buffer is read before the accessor and bufferView ranges that
 * cover it were checked against the buffer's real size; the sparse accessors
 * the scene reads are made dense once, before anything reads them (the
 * others stay sparse: never expanded); each attribute is read with
 * the component types the core and KHR_mesh_quantization allow it. */
#include "gltf_int.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace st_gltf {

static size_t component_size(int type)
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

static size_t type_components(int type)
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

/* The `bytes` bytes at `offset` of bufferView v, checked against its
 * buffer; what names the reader in errors. */
static const unsigned char *view_bytes(const Model &m, int v, size_t offset, size_t bytes, int a,
                                       const char *what)
{
    check_index(v, m.bufferViews.size(), "accessor %d: sparse %s bufferView", a, what);
    const tinygltf::BufferView &view = m.bufferViews[size_t(v)];
    check_index(view.buffer, m.buffers.size(), "bufferView %d: buffer", v);
    const std::vector<unsigned char> &buf = m.buffers[size_t(view.buffer)].data;
    if (view.byteOffset > buf.size() || view.byteLength > buf.size() - view.byteOffset ||
        offset > view.byteLength || bytes > view.byteLength - offset)
        fail("accessor %d: sparse %s (%zu bytes from %zu) run past bufferView %d", a, what, bytes,
             offset, v);
    return buf.data() + view.byteOffset + offset;
}

/* The sparse accessors (§3.6.2.3) that `used` marks made dense, once,
 * before anything reads them: the base (its bufferView, or zeros without
 * one) copied into a new buffer, the sparse values written over it at their
 * indices, and the accessor pointed at the copy. Their dense bytes, all
 * together, are checked against ST_GLTF_MAX_SPARSE_BYTES first: a sparse
 * accessor of a billion zeros takes a few bytes of JSON. */
void densify_sparse(Model &m, const std::vector<char> &used)
{
    size_t total = 0;
    for (size_t a = 0; a < m.accessors.size(); a++) {
        const tinygltf::Accessor &acc = m.accessors[a];
        if (!acc.sparse.isSparse || !used[a])
            continue;
        const size_t elem = component_size(acc.componentType) * type_components(acc.type);
        if (elem == 0)
            fail("accessor %zu: bad componentType %d or type %d", a, acc.componentType, acc.type);
        if (acc.count > (ST_GLTF_MAX_SPARSE_BYTES - total) / elem)
            fail("accessor %zu: sparse accessors made dense for the scene (%zu elements of %zu "
                 "bytes here): more than %u MiB in all, the limit",
                 a, acc.count, elem, ST_GLTF_MAX_SPARSE_BYTES >> 20);
        total += acc.count * elem;
    }
    for (size_t a = 0; a < m.accessors.size(); a++) {
        tinygltf::Accessor &acc = m.accessors[a];
        if (!acc.sparse.isSparse || !used[a])
            continue;
        const size_t elem = component_size(acc.componentType) * type_components(acc.type);
        std::vector<unsigned char> dense(elem * acc.count, 0);
        acc.sparse.isSparse = false;
        if (acc.bufferView >= 0) {
            const span base = accessor_span(m, int(a));
            for (size_t i = 0; i < acc.count; i++)
                memcpy(&dense[i * elem], base.data + i * base.stride, elem);
        }
        const size_t n = size_t(acc.sparse.count > 0 ? acc.sparse.count : 0);
        const int ict = acc.sparse.indices.componentType;
        const size_t isz = ict == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                           : ict == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                           : ict == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                           : 0;
        if (isz == 0 || n > acc.count)
            fail("accessor %zu: sparse indices must be unsigned integers, at most count", a);
        const unsigned char *idx = view_bytes(m, acc.sparse.indices.bufferView,
                                              size_t(acc.sparse.indices.byteOffset), n * isz,
                                              int(a), "indices");
        const unsigned char *val = view_bytes(m, acc.sparse.values.bufferView,
                                              size_t(acc.sparse.values.byteOffset), n * elem,
                                              int(a), "values");
        for (size_t k = 0; k < n; k++) {
            uint32_t i = 0;
            memcpy(&i, idx + k * isz, isz); /* little-endian, as glTF */
            if (i >= acc.count)
                fail("accessor %zu: sparse index %u out of range (%zu elements)", a, i,
                     acc.count);
            memcpy(&dense[i * elem], val + k * elem, elem);
        }
        tinygltf::Buffer buf;
        buf.data.swap(dense);
        tinygltf::BufferView view;
        view.buffer = int(m.buffers.size());
        view.byteLength = buf.data.size();
        m.buffers.push_back(std::move(buf));
        acc.bufferView = int(m.bufferViews.size());
        acc.byteOffset = 0;
        m.bufferViews.push_back(view);
    }
}

/* The (componentType, normalized) pairs an attribute may use, one bit each:
 * float, then the signed and unsigned bytes and shorts, plain or normalised. */
enum : unsigned {
    Q_F = 1u, Q_B = 2u, Q_UB = 4u, Q_S = 8u, Q_US = 16u,
    Q_BN = 32u, Q_UBN = 64u, Q_SN = 128u, Q_USN = 256u,
    Q_INT = Q_B | Q_UB | Q_S | Q_US | Q_BN | Q_UBN | Q_SN | Q_USN
};

static unsigned type_bit(int ct, bool normalized)
{
    switch (ct) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return normalized ? 0u : Q_F;
    case TINYGLTF_COMPONENT_TYPE_BYTE: return normalized ? Q_BN : Q_B;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? Q_UBN : Q_UB;
    case TINYGLTF_COMPONENT_TYPE_SHORT: return normalized ? Q_SN : Q_S;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return normalized ? Q_USN : Q_US;
    default: return 0u;
    }
}

/* Component k of the element at p as a float: a float as stored; an
 * integer as its value or, normalised, as §3.11 maps it: c / 255,
 * c / 65535, max(c / 127, -1), max(c / 32767, -1). */
float component(const unsigned char *p, int ct, bool normalized, int k)
{
    float v;
    switch (ct) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
        memcpy(&v, p + 4 * k, 4);
        return v;
    case TINYGLTF_COMPONENT_TYPE_BYTE:
        v = float(int8_t(p[k]));
        return normalized ? std::max(v / 127.0f, -1.0f) : v;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        v = float(p[k]);
        return normalized ? v / 255.0f : v;
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
        int16_t h;
        memcpy(&h, p + 2 * k, 2);
        return normalized ? std::max(float(h) / 32767.0f, -1.0f) : float(h);
    }
    default: {
        uint16_t h;
        memcpy(&h, p + 2 * k, 2);
        return normalized ? float(h) / 65535.0f : float(h);
    }
    }
}

/* The types an attribute may use: the core's (§3.7.2.1), widened by
 * KHR_mesh_quantization's table where the file uses that extension. */
static unsigned allowed_types(const Model &m, const char *attr)
{
    if (strncmp(attr, "JOINTS_", 7) == 0) /* §3.7.3.3 */
        return Q_UB | Q_US;
    if (strncmp(attr, "WEIGHTS_", 8) == 0)
        return Q_F | Q_UBN | Q_USN;
    if (strcmp(attr, "ROTATION") == 0) /* EXT_mesh_gpu_instancing */
        return Q_F | Q_BN | Q_SN;
    bool quantized = false;
    for (const std::string &ext : m.extensionsUsed)
        quantized = quantized || ext == "KHR_mesh_quantization";
    const bool uv = strncmp(attr, "TEXCOORD", 8) == 0;
    if (!quantized)
        return uv ? Q_F | Q_UBN | Q_USN : Q_F;
    if (strcmp(attr, "NORMAL") == 0 || strcmp(attr, "TANGENT") == 0)
        return Q_F | Q_BN | Q_SN;
    return Q_F | Q_INT; /* POSITION, TEXCOORD_n */
}

/* The types of a mask of allowed_types in words ("unsigned byte or unsigned short"). */
static std::string type_words(unsigned mask)
{
    static const char *const names[] = {
        "float", "byte", "unsigned byte", "short", "unsigned short", "normalized byte",
        "normalized unsigned byte", "normalized short", "normalized unsigned short"};
    std::vector<const char *> on;
    for (unsigned k = 0; k < sizeof names / sizeof names[0]; k++)
        if (mask >> k & 1u)
            on.push_back(names[k]);
    std::string s;
    for (size_t i = 0; i < on.size(); i++)
        s += std::string(i == 0 ? "" : i + 1 == on.size() ? " or " : ", ") + on[i];
    return s;
}

/* Reads attribute accessor a (`attr`: POSITION, NORMAL, TANGENT,
 * TEXCOORD_n) of n components per element into floats, of a type that
 * allowed_types permits; vertices > 0: the element count it must have.
 * glTF accessors must not hold NaN or infinity (glTF-Validator's
 * ACCESSOR_INVALID_FLOAT), so one is a format error, not a dropped triangle. */
void read_attribute(const Model &m, int a, const char *attr, int n, size_t vertices,
                    std::vector<float> &out)
{
    const tinygltf::Accessor &acc = m.accessors[size_t(a)];
    const int ct = acc.componentType;
    const int type = n == 2 ? TINYGLTF_TYPE_VEC2 : n == 3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4;
    if (acc.type != type || !(type_bit(ct, acc.normalized) & allowed_types(m, attr)))
        fail("accessor %d: %s must be %s VEC%d (componentType %d%s, type %d)", a, attr,
             type_words(allowed_types(m, attr)).c_str(), n, ct,
             acc.normalized ? " normalized" : "", acc.type);
    const span s = accessor_span(m, a);
    if (vertices > 0 && s.count != vertices)
        fail("accessor %d: %s has %zu elements, POSITION %zu", a, attr, s.count, vertices);
    out.resize(size_t(n) * s.count);
    for (size_t i = 0; i < s.count; i++)
        for (int k = 0; k < n; k++) {
            const float v = component(s.data + i * s.stride, ct, acc.normalized, k);
            if (!std::isfinite(v))
                fail("accessor %d: non-finite value in element %zu", a, i);
            out[size_t(n) * i + size_t(k)] = v;
        }
}

/* Reads POSITION or NORMAL into xyz triples. */
void read_vec3(const Model &m, int a, const char *attr, std::vector<float> &out)
{
    read_attribute(m, a, attr, 3, 0, out);
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

/* Reads TEXCOORD_n (`attr`; §3.7.2.1: float, or normalised unsigned byte or
 * short, VEC2; more with KHR_mesh_quantization) into (u, v) pairs, one per
 * vertex. */
void read_uv(const Model &m, int a, const char *attr, size_t vertices, std::vector<float> &out)
{
    read_attribute(m, a, attr, 2, vertices, out);
}

/* The accessor of attribute `name`, checked; -1 when the primitive has none. */
int attribute(const Model &m, int mesh, size_t p, const char *name)
{
    const tinygltf::Primitive &prim = primitive(m, mesh, p);
    auto it = prim.attributes.find(name);
    if (it == prim.attributes.end())
        return -1;
    check_index(it->second, m.accessors.size(), "mesh %d primitive %zu: %s accessor", mesh, p,
                name);
    return it->second;
}

} /* namespace st_gltf */
