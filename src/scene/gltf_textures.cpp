/* gltf_textures.cpp — texture references (§3.8), KHR_texture_transform and image decoding.
 *
 * Equal references share one table entry; images a reference uses are
 * decoded (stb_image: PNG, JPEG, ...) from the bytes tinygltf read for their
 * URI or from their checked bufferView range. */
#include "gltf_int.h"

#include <stb/stb_image.h> /* Debian's libstb holds the implementation */

#include <climits>
#include <cmath>
#include <cstring>

namespace st_gltf {

/* A number of a JSON extension object, `fallback` when absent. */
double ext_number(const tinygltf::Value &obj, const char *key, double fallback, const char *what)
{
    if (!obj.IsObject() || !obj.Has(key))
        return fallback;
    const tinygltf::Value &v = obj.Get(key);
    if (!v.IsNumber())
        fail("%s: %s is not a number", what, key);
    return v.GetNumberAsDouble();
}

/* A texCoord of a JSON object (a textureInfo of an extension, or
 * KHR_texture_transform's), `fallback` when absent: a non-negative integer. */
int tex_coord_number(const tinygltf::Value &obj, int fallback, const char *what)
{
    const double c = ext_number(obj, "texCoord", fallback, what);
    if (!(c >= 0.0 && c <= 65535.0) || c != std::floor(c))
        fail("%s: texCoord %g is not a non-negative integer", what, c);
    return int(c);
}

/* Two numbers of a JSON array (offset, scale); out unchanged when absent. */
static void ext_pair(const tinygltf::Value &obj, const char *key, double out[2], const char *what)
{
    if (!obj.IsObject() || !obj.Has(key))
        return;
    const tinygltf::Value &v = obj.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber())
        fail("%s: %s must be an array of 2 numbers", what, key);
    out[0] = v.Get(0).GetNumberAsDouble();
    out[1] = v.Get(1).GetNumberAsDouble();
}

/* KHR_texture_transform: uv' = T(offset) R(rotation) S(scale) uv with
 * R = [cos sin; -sin cos] (the extension's README, "Texture Transform"),
 * as the 2 x 3 matrix [t0 t1 t2; t3 t4 t5]. Returns the texCoord the
 * extension names, or `tex_coord` when it names none. */
static int texture_transform(const tinygltf::ExtensionMap &ext, int tex_coord, float t[6],
                             const char *what)
{
    double offset[2] = {0.0, 0.0}, scale[2] = {1.0, 1.0}, rotation = 0.0;
    auto it = ext.find("KHR_texture_transform");
    if (it != ext.end()) {
        ext_pair(it->second, "offset", offset, what);
        ext_pair(it->second, "scale", scale, what);
        rotation = ext_number(it->second, "rotation", 0.0, what);
        tex_coord = tex_coord_number(it->second, tex_coord, what);
    }
    const double c = std::cos(rotation), s = std::sin(rotation);
    const double m[6] = {c * scale[0], s * scale[1], offset[0], -s * scale[0], c * scale[1], offset[1]};
    for (int k = 0; k < 6; k++) {
        if (!std::isfinite(m[k]) || std::fabs(m[k]) > 1e30)
            fail("%s: KHR_texture_transform is not finite", what);
        t[k] = float(m[k]);
    }
    return tex_coord;
}

/* A sampler's wrap mode (§5.26: REPEAT 10497, CLAMP_TO_EDGE 33071,
 * MIRRORED_REPEAT 33648), checked. */
static int wrap_code(int sampler, int code, const char *axis)
{
    if (code != 10497 && code != 33071 && code != 33648)
        fail("sampler %d: %s %d is not a glTF wrap mode", sampler, axis, code);
    return code;
}

/* The texture table entry of one material slot (baseColorTexture, ...), or
 * -1 when the slot is empty or cannot be used (a warning says why). */
int texture_ref(const Model &m, const tinygltf::TextureInfo &info, bool srgb, size_t mat,
                const char *slot, texture_table &table, notes &warn)
{
    if (info.index == -1)
        return -1;
    char what[160];
    snprintf(what, sizeof what, "material %zu: %s", mat, slot);
    check_index(info.index, m.textures.size(), "%s: texture", what);
    st_gltf_texture ref = {};
    const int coord = texture_transform(info.extensions, info.texCoord, ref.transform, what);
    const tinygltf::Texture &tex = m.textures[size_t(info.index)];
    if (coord < 0)
        fail("%s: texCoord %d is negative", what, coord);
    if (coord > 1) { /* as an unreadable image: the factor alone, a neutral texture */
        note(warn, "%s uses TEXCOORD_%d; strata reads TEXCOORD_0 and TEXCOORD_1 only: "
                   "texture ignored, its factor kept",
             what, coord);
        return -1;
    }
    ref.tex_coord = coord;
    if (tex.source == -1) {
        note(warn, "%s: texture %d has no image strata can decode (source only in an "
                   "extension?): texture ignored",
             what, info.index);
        return -1;
    }
    check_index(tex.source, m.images.size(), "texture %d: source image", info.index);
    ref.image = tex.source;
    ref.srgb = srgb ? 1 : 0;
    ref.wrap_s = ref.wrap_t = 10497;
    if (tex.sampler != -1) {
        check_index(tex.sampler, m.samplers.size(), "texture %d: sampler", info.index);
        const tinygltf::Sampler &smp = m.samplers[size_t(tex.sampler)];
        ref.wrap_s = wrap_code(tex.sampler, smp.wrapS, "wrapS");
        ref.wrap_t = wrap_code(tex.sampler, smp.wrapT, "wrapT");
        ref.mag_nearest = smp.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
    }
    for (size_t i = 0; i < table.refs.size(); i++)
        if (memcmp(&table.refs[i], &ref, sizeof ref) == 0) /* no padding: ints and floats */
            return int(i);
    table.refs.push_back(ref);
    return int(table.refs.size() - 1);
}

/* The encoded bytes of image i: its bufferView's (checked like an accessor's) or those tinygltf
 * read for its URI. */
static void encoded_bytes(const Model &m, int i, const image_bytes &bytes,
                          const unsigned char **out, size_t *out_size)
{
    const tinygltf::Image &img = m.images[size_t(i)];
    const unsigned char *data = nullptr;
    size_t size = 0;
    if (img.bufferView != -1) {
        check_index(img.bufferView, m.bufferViews.size(), "image %d: bufferView", i);
        const tinygltf::BufferView &view = m.bufferViews[size_t(img.bufferView)];
        check_index(view.buffer, m.buffers.size(), "bufferView %d: buffer", img.bufferView);
        const std::vector<unsigned char> &buf = m.buffers[size_t(view.buffer)].data;
        if (view.byteOffset > buf.size() || view.byteLength > buf.size() - view.byteOffset)
            fail("bufferView %d: bytes %zu + %zu run past the end of buffer %d (%zu bytes)",
                 img.bufferView, view.byteOffset, view.byteLength, view.buffer, buf.size());
        data = buf.data() + view.byteOffset;
        size = view.byteLength;
    } else {
        auto it = bytes.by_index.find(i);
        if (it == bytes.by_index.end() || it->second.empty())
            fail("image %d (%s): cannot read it", i,
                 img.uri.size() > 80 ? "data: URI" : img.uri.c_str());
        data = it->second.data();
        size = it->second.size();
    }
    if (size > size_t(INT_MAX))
        fail("image %d: too large (%zu bytes)", i, size);
    *out = data;
    *out_size = size;
}

/* Decodes image i (RGBA8) from its encoded bytes. */
static st_gltf_image decode_image(const Model &m, int i, const image_bytes &bytes)
{
    const tinygltf::Image &img = m.images[size_t(i)];
    const unsigned char *data = nullptr;
    size_t size = 0;
    encoded_bytes(m, i, bytes, &data, &size);
    int w = 0, h = 0, comp = 0;
    /* the size from the header first: a small file may decode to gigabytes */
    if (stbi_info_from_memory(data, int(size), &w, &h, &comp) &&
        size_t(w) * size_t(h) > (size_t(1) << 26))
        fail("image %d: %d x %d texels: more than 2^26", i, w, h);
    unsigned char *rgba = stbi_load_from_memory(data, int(size), &w, &h, &comp, 4);
    if (!rgba)
        fail("image %d (%s): cannot decode: %s", i,
             img.uri.empty() || img.uri.size() > 80 ? img.mimeType.c_str() : img.uri.c_str(),
             stbi_failure_reason() ? stbi_failure_reason() : "unknown format");
    if (w <= 0 || h <= 0 || size_t(w) * size_t(h) > (size_t(1) << 26)) {
        stbi_image_free(rgba);
        fail("image %d: %d x %d texels: more than 2^26", i, w, h);
    }
    return {uint32_t(w), uint32_t(h), rgba};
}

/* The texels an image will decode to, from its header; 1 when it cannot be read, its header
 * not parsed, or it is past 2^26 (decode_images makes those one white texel). */
static size_t header_texels(const unsigned char *data, size_t size)
{
    int w = 0, h = 0, comp = 0;
    if (!data || !stbi_info_from_memory(data, int(size), &w, &h, &comp) || w <= 0 || h <= 0 ||
        size_t(w) * size_t(h) > (size_t(1) << 26))
        return 1;
    return size_t(w) * size_t(h);
}

/* FNV-1a, 64 bits (Fowler, Noll, Vo): a key for finding images of the same bytes. */
static uint64_t fnv1a(const unsigned char *p, size_t n)
{
    uint64_t h = 14695981039346656037ull;
    for (size_t i = 0; i < n; i++)
        h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

/* Before any image is decoded: the textures' images of identical encoded bytes made one (each
 * reference, and each image derived from one, points at the first of them, so the bytes are
 * decoded once), and the texels of those left, as their headers give them, checked against
 * ST_GLTF_MAX_TEXELS. */
void share_images(const Model &m, const image_bytes &bytes, texture_table &table)
{
    std::vector<int> first(m.images.size(), -1); /* -1: no texture uses it */
    std::map<std::pair<uint64_t, size_t>, std::vector<int>> by_bytes;
    std::vector<size_t> texels(m.images.size(), 0);
    size_t total = 0;
    for (const st_gltf_texture &t : table.refs) {
        const int i = t.image;
        if (size_t(i) >= m.images.size() || first[size_t(i)] >= 0)
            continue;
        first[size_t(i)] = i;
        const unsigned char *data = nullptr;
        size_t size = 0;
        try {
            encoded_bytes(m, i, bytes, &data, &size);
        } catch (const shim_error &e) { /* decode_images says why, and makes it white */
            if (e.status != ST_ERR_FORMAT)
                throw;
            data = nullptr;
        }
        if (data) {
            std::vector<int> &same = by_bytes[{fnv1a(data, size), size}];
            for (int j : same) {
                const unsigned char *other = nullptr;
                size_t n = 0;
                encoded_bytes(m, j, bytes, &other, &n);
                if (memcmp(other, data, size) == 0) {
                    first[size_t(i)] = j;
                    break;
                }
            }
            if (first[size_t(i)] == i)
                same.push_back(i);
        }
        if (first[size_t(i)] == i)
            total += texels[size_t(i)] = header_texels(data, size);
    }
    for (st_gltf_texture &t : table.refs)
        if (size_t(t.image) < m.images.size())
            t.image = first[size_t(t.image)];
    for (std::pair<int, float> &d : table.derived) {
        d.first = first[size_t(d.first)];
        total += texels[size_t(d.first)];
    }
    if (total > ST_GLTF_MAX_TEXELS)
        fail("the textures' images hold %zu texels in all (images of the same bytes once): more "
             "than 2^%d, the limit", total, ST_GLTF_TEXELS_LOG2);
}

/* Every image a texture reference uses, decoded into images[] (zeroed
 * beforehand); where one cannot be read or decoded, a 1 x 1 white image
 * takes its place and the result says why, by image index (empty for the
 * images that decoded). gltf_materials.cpp's note_unreadable decides what
 * each slot makes of the white image. */
std::vector<std::string> decode_images(const Model &m, const image_bytes &bytes,
                                       const texture_table &table, st_gltf_image *images)
{
    std::vector<std::string> why(m.images.size());
    for (const st_gltf_texture &t : table.refs) {
        const size_t i = size_t(t.image);
        if (i >= m.images.size() || images[i].rgba)
            continue;
        try {
            images[i] = decode_image(m, t.image, bytes);
            continue;
        } catch (const shim_error &e) {
            if (e.status != ST_ERR_FORMAT)
                throw;
            why[i] = e.msg;
        }
        unsigned char *white = static_cast<unsigned char *>(malloc(4)); /* stbi_image_free frees */
        if (!white)
            throw shim_error{ST_ERR_NOMEM, "out of memory"};
        memset(white, 255, 4);
        images[i] = {1u, 1u, white};
    }
    return why;
}

} /* namespace st_gltf */
