/* gltf_shim.cpp — glTF 2.0 import through tinygltf, the one C++ file of strata,
 * behind the C interface of gltf_shim.h.
 *
 * Spec: Khronos Group, "glTF 2.0 Specification", version 2.0.1 (2021):
 * §3.5 nodes and the TRS/matrix transform hierarchy, §3.6 buffers, bufferViews
 * and accessors, §3.7.2 mesh primitives, §3.8 textures, images and samplers,
 * §3.9 materials, §3.10 cameras, §4.4 the GLB container; and the extensions
 * §3.7.2.2 morph targets, §3.7.3 skins, and the extensions
 * KHR_materials_emissive_strength, KHR_materials_specular, KHR_materials_ior,
 * KHR_materials_transmission, KHR_materials_volume (attenuation),
 * KHR_materials_clearcoat (no clearcoatNormalTexture), KHR_materials_sheen,
 * KHR_materials_unlit, KHR_materials_pbrSpecularGlossiness (converted),
 * KHR_texture_transform, KHR_mesh_quantization, KHR_lights_punctual and
 * EXT_mesh_gpu_instancing.
 *
 * Invariants: no byte of a buffer is read before the accessor and bufferView
 * ranges that cover it were checked against the buffer's real size, and no
 * index is used before it was checked against its array; a malformed file
 * becomes a shim_error (one line), never a crash. No C++ exception leaves this
 * file: st_gltf_shim_load catches them all. Buffers are read as little-endian
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
#include "gltf_shim.h"
#include "scene_fs.h"

#include <tiny_gltf.h>
#include <stb/stb_image.h> /* Debian's libstb holds the implementation */
#include <cjson/cJSON.h>    /* Debian libcjson-dev: extensionsRequired, before tinygltf */

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <new>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h> /* close(2) */

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

/* Warnings of one load: the first ST_GLTF_MAX_WARNINGS lines and a count of
 * the rest. */
struct notes {
    std::vector<std::string> lines;
    size_t more = 0;
};

void note(notes &n, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void note(notes &n, const char *fmt, ...)
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

/* ---- file access for tinygltf ------------------------------------------- */

/* Our own file callbacks replace tinygltf's defaults, which pass every URI
 * through wordexp() (expanding "$VAR" and "~" in file names) and also look
 * for a missing file in the working directory. */
struct fs_context {
    const char *base_dir; /* NULL: no file access at all (embedded scenes, standard input) */
    int dir_fd;           /* base_dir opened, URIs are opened relative to it */
};

/* Whether tinygltf's joined path lies under the scene's folder by name (its
 * "./" fallback does not); with no folder, yes, so that fs_read says why not.
 * Nothing is opened here: a FIFO or device named by a URI must not be touched
 * before fs_read refuses it. */
bool fs_exists(const std::string &path, void *user)
{
    const fs_context *ctx = static_cast<const fs_context *>(user);
    return !ctx->base_dir || path.compare(0, strlen(ctx->base_dir), ctx->base_dir) == 0;
}

std::string fs_expand(const std::string &path, void *) { return path; }

/* The URI in tinygltf's joined path (base_dir, a '/' unless base_dir ends in
 * one, the URI). */
std::string uri_of(const fs_context *ctx, const std::string &path)
{
    size_t n = strlen(ctx->base_dir);
    if (n > 0 && ctx->base_dir[n - 1] != '/' && path.size() > n && path[n] == '/')
        n++;
    return path.substr(n);
}

/* Reads a buffer or image named by URI: opened from the scene folder's
 * descriptor one name at a time (no "..", absolute path or symbolic link out
 * of it), a regular file within the size cap (scene_fs.h). tinygltf puts *err
 * after the joined path, which ends with the URI. */
bool fs_read(std::vector<unsigned char> *out, std::string *err, const std::string &path,
             void *user)
{
    const fs_context *ctx = static_cast<const fs_context *>(user);
    if (!ctx->base_dir) {
        *err = "a built-in scene or one on standard input has no folder: data: URIs only";
        return false;
    }
    unsigned char *data = nullptr;
    size_t size = 0;
    st_error e = {ST_OK, ""};
    if (st_scene_fs_read_at(ctx->dir_fd, uri_of(ctx, path).c_str(), ST_SCENE_MAX_FILE_BYTES,
                            "a buffer or image", &data, &size, &e) != ST_OK) {
        const char *why = strstr(e.msg, ": "); /* the path is tinygltf's to print */
        *err = why ? why + 2 : e.msg;
        return false;
    }
    out->assign(data, data + size);
    free(data);
    return true;
}

/* The scene's folder as a descriptor for the length of one load. */
struct folder {
    int fd = -1;
    explicit folder(const char *base_dir)
    {
        if (base_dir && (fd = st_scene_fs_open_dir(base_dir)) < 0)
            fail("cannot open the scene's folder '%s': %s", base_dir[0] ? base_dir : ".",
                 strerror(errno));
    }
    ~folder()
    {
        if (fd >= 0)
            close(fd);
    }
    folder(const folder &) = delete;
    folder &operator=(const folder &) = delete;
};

/* Every string of the JSON text (a .gltf, or a GLB's JSON chunk) within
 * ST_SCENE_MAX_DATA_URI_BYTES, checked before tinygltf parses (and copies)
 * it. Every string, not only those spelled "data:...": an escape such as
 * "\u0064ata:" decodes to the same URI, and a string's decoded length is
 * never more than its length in the text, so the cap on the text holds for
 * the value. No other glTF string comes near the cap. */
void check_data_uris(const unsigned char *json, size_t len)
{
    for (size_t at = 0; at < len; at++) {
        if (json[at] != '"')
            continue;
        size_t end = at + 1;
        while (end < len && json[end] != '"')
            end += json[end] == '\\' ? 2 : 1;
        end = end < len ? end : len;
        if (end - at - 1 > ST_SCENE_MAX_DATA_URI_BYTES) {
            bool plain = len - at > 6 && memcmp(json + at, "\"data:", 6) == 0;
            fail("a %s of %zu bytes at byte %zu: more than %zu MiB, the limit",
                 plain ? "data: URI" : "string (a data: URI written with escapes?)", end - at - 1,
                 at, ST_SCENE_MAX_DATA_URI_BYTES >> 20);
        }
        at = end;
    }
}

bool fs_write(std::string *, const std::string &, const std::vector<unsigned char> &, void *)
{
    return false;
}

/* Encoded bytes of the images given by URI (file or data:), by image index;
 * images in a bufferView are read later from their checked range. */
struct image_bytes {
    std::map<int, std::vector<unsigned char>> by_index;
};

/* tinygltf's image callback: keeps the bytes, decodes nothing (decoding waits
 * until we know which images a material uses). tinygltf passes a bufferView
 * image's bytes without checking the view against its buffer, so those are
 * not touched here. */
bool keep_image_bytes(tinygltf::Image *img, const int idx, std::string *, std::string *, int,
                      int, const unsigned char *bytes, int size, void *user)
{
    if (img->bufferView != -1 || size <= 0)
        return true;
    static_cast<image_bytes *>(user)->by_index[idx].assign(bytes, bytes + size);
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
    if (le32(b + 4) != 2)
        fail("GLB version %u: strata reads version 2", le32(b + 4));
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

/* The deepest nesting of arrays and objects accepted in a scene's JSON.
 * tinygltf converts its JSON tree to Values recursively (extras and extensions
 * keep arbitrary depth), a few hundred bytes of stack per level, so a small
 * file nested thousands deep overflows the stack; the glTF schema itself needs
 * fewer than ten levels, and generous extras a few dozen. */
const size_t max_json_depth = 256;

/* Counts '[' and '{' outside strings (skipping escaped characters inside
 * them) and refuses the text before it reaches tinygltf when they nest deeper
 * than max_json_depth. Only the structure is looked at: malformed JSON is left
 * for the parser to report. */
void check_nesting(const unsigned char *json, size_t len)
{
    size_t depth = 0;
    bool in_string = false;
    for (size_t i = 0; i < len; i++) {
        unsigned char c = json[i];
        if (in_string) {
            if (c == '\\')
                i++;
            else if (c == '"')
                in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > max_json_depth)
                fail("JSON nested more than %zu deep at byte %zu, the limit", max_json_depth, i);
        } else if ((c == ']' || c == '}') && depth > 0) {
            depth--;
        }
    }
}

/* The JSON text of a .gltf, or of a GLB's first chunk (already checked by
 * check_glb to lie inside the data). */
void json_text(const unsigned char *bytes, size_t size, bool glb, const unsigned char **json,
               size_t *len)
{
    *json = bytes;
    *len = size;
    if (glb) {
        *len = size >= 20 ? le32(bytes + 12) : 0;
        *json = bytes + (size >= 20 ? 20 : size);
        if (*len > size - (size >= 20 ? 20 : size))
            *len = 0;
    }
}

/* The extensions strata implements; any other in extensionsRequired is an
 * error, any other in extensionsUsed a warning. */
const char *const supported_extensions[] = {
    "KHR_materials_emissive_strength", "KHR_materials_specular", "KHR_materials_ior",
    "KHR_materials_unlit", "KHR_texture_transform", "KHR_mesh_quantization",
    "KHR_lights_punctual", "EXT_mesh_gpu_instancing", "KHR_materials_pbrSpecularGlossiness",
    "KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_clearcoat",
    "KHR_materials_sheen"};

bool supported(const char *ext)
{
    for (const char *s : supported_extensions)
        if (strcmp(s, ext) == 0)
            return true;
    return false;
}

/* asset.version "MAJOR.MINOR": strata reads glTF 2 (a later major version
 * may change anything, §3.2); a missing version is left to tinygltf. */
void check_asset_version(const cJSON *root)
{
    const cJSON *asset = cJSON_GetObjectItemCaseSensitive(root, "asset");
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(asset, "version");
    if (cJSON_IsString(v) && (strncmp(v->valuestring, "2.", 2) != 0 || !v->valuestring[2]))
        fail("asset version \"%.40s\": strata reads glTF 2.x only", v->valuestring);
}

/* One size or offset of the schema: absent, or an integer >= 0 (tinygltf
 * reads a negative or fractional one as 0 without a word). */
void check_size(const cJSON *obj, const char *key, const char *what, int index)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (v && (!cJSON_IsNumber(v) || !(v->valuedouble >= 0.0) ||
              v->valuedouble != std::floor(v->valuedouble) || v->valuedouble > 9007199254740992.0))
        fail("%s %d: %s is not an integer >= 0", what, index, key);
}

/* The sizes and offsets of buffers, buffer views and accessors (with their
 * sparse parts), checked in the JSON before tinygltf reads them. */
void check_sizes(const cJSON *root)
{
    int i = 0;
    const cJSON *e = nullptr;
    cJSON_ArrayForEach(e, cJSON_GetObjectItemCaseSensitive(root, "buffers"))
        check_size(e, "byteLength", "buffer", i++);
    i = 0;
    cJSON_ArrayForEach(e, cJSON_GetObjectItemCaseSensitive(root, "bufferViews")) {
        for (const char *key : {"byteOffset", "byteLength", "byteStride"})
            check_size(e, key, "bufferView", i);
        i++;
    }
    i = 0;
    cJSON_ArrayForEach(e, cJSON_GetObjectItemCaseSensitive(root, "accessors")) {
        check_size(e, "byteOffset", "accessor", i);
        check_size(e, "count", "accessor", i);
        const cJSON *sparse = cJSON_GetObjectItemCaseSensitive(e, "sparse");
        check_size(sparse, "count", "accessor (sparse)", i);
        check_size(cJSON_GetObjectItemCaseSensitive(sparse, "indices"), "byteOffset",
                   "accessor (sparse indices)", i);
        check_size(cJSON_GetObjectItemCaseSensitive(sparse, "values"), "byteOffset",
                   "accessor (sparse values)", i);
        i++;
    }
}

/* extensionsRequired, read from the JSON (a GLB's first chunk) before
 * tinygltf parses the rest, so that a Draco or meshopt file fails naming
 * the extension instead of on the buffers it cannot decode. */
void check_required(const unsigned char *bytes, size_t size, bool glb)
{
    const char *json = reinterpret_cast<const char *>(bytes);
    size_t len = size;
    if (glb) {
        if (size < 20 || le32(bytes + 16) != 0x4E4F534Au) /* "JSON" */
            return; /* tinygltf reports it */
        json += 20;
        len = le32(bytes + 12);
    }
    cJSON *root = cJSON_ParseWithLength(json, len);
    try {
        check_asset_version(root);
        check_sizes(root);
    } catch (...) {
        cJSON_Delete(root);
        throw;
    }
    const cJSON *req = root ? cJSON_GetObjectItemCaseSensitive(root, "extensionsRequired") : nullptr;
    std::string missing;
    const cJSON *e = nullptr;
    cJSON_ArrayForEach(e, req)
        if (cJSON_IsString(e) && !supported(e->valuestring) && missing.empty())
            missing = e->valuestring;
    cJSON_Delete(root);
    if (!missing.empty())
        fail("requires extension %.80s, which strata does not support", missing.c_str());
}

void parse(Model &model, const unsigned char *bytes, size_t size, const char *base_dir,
           image_bytes &images, notes &warn_out)
{
    if (size > UINT_MAX)
        fail("file too large (%zu bytes)", size);
    const bool glb = size >= 4 && memcmp(bytes, "glTF", 4) == 0;
    if (glb)
        check_glb(bytes, size);
    const unsigned char *json;
    size_t json_len;
    json_text(bytes, size, glb, &json, &json_len);
    check_nesting(json, json_len);
    check_required(bytes, size, glb);
    check_data_uris(json, json_len);
    folder scene_folder(base_dir);
    fs_context ctx = {base_dir, scene_folder.fd};
    tinygltf::FsCallbacks fs = {fs_exists, fs_expand, fs_read, fs_write, &ctx};
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks(fs);
    loader.SetImageLoader(keep_image_bytes, &images);
    std::string err, warn, dir = base_dir ? base_dir : "";
    bool ok = glb ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes, unsigned(size), dir)
                  : loader.LoadASCIIFromString(&model, &err, &warn,
                                               reinterpret_cast<const char *>(bytes),
                                               unsigned(size), dir);
    if (!ok) {
        std::string why = first_line(err.empty() ? warn : err);
        fail("%s", why.empty() ? "tinygltf could not parse the file" : why.c_str());
    }
    for (const std::string &ext : model.extensionsUsed)
        if (!supported(ext.c_str()))
            note(warn_out, "uses extension %.80s, which strata ignores", ext.c_str());
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
/* A node's matrix must be affine (§5.25: a TRS transform), its last row
 * 0 0 0 1: strata transforms points and normals without a projective divide. */
void check_affine(const mat4 &r, int idx)
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

/* A mesh as one node (or one EXT_mesh_gpu_instancing instance of it)
 * draws it: its world matrix, the node (its morph weights) and the node's
 * skin (-1: none). */
struct instance {
    int mesh;
    mat4 world;
    int node = -1, skin = -1;
};

void add_mesh_instances(const Model &m, int node, const mat4 &world, std::vector<instance> &out,
                        size_t &instanced, notes &warn);

bool normalize3(double v[3])
{
    double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(len > 0.0) || !std::isfinite(len))
        return false;
    for (int i = 0; i < 3; i++)
        v[i] /= len;
    return true;
}

/* A camera looks down its node's local -Z with +Y up (§3.10.1); the node's
 * scale is ignored (the axes are normalised) and up is made orthogonal to
 * forward (Gram-Schmidt). A node whose transform collapses either axis (zero
 * scale) is passed over with a warning. */
void take_camera(const Model &m, int node, int cam, const mat4 &world,
                 std::vector<st_gltf_camera> &out, notes &warn)
{
    const tinygltf::Camera &c = m.cameras[size_t(cam)];
    st_gltf_camera pick = {};
    if (c.type == "perspective") {
        const double yfov = c.perspective.yfov;
        if (!(yfov > 0.0 && yfov < M_PI))
            fail("camera %d: yfov %g is not in (0, pi)", cam, yfov);
        pick.yfov = float(yfov);
    } else if (c.type == "orthographic") {
        const double ymag = std::fabs(c.orthographic.ymag);
        if (!(ymag > 0.0 && ymag < 1e30))
            fail("camera %d: ymag %g must be non-zero and finite", cam, c.orthographic.ymag);
        pick.orthographic = 1;
        pick.ymag = float(ymag);
    } else {
        fail("camera %d: type \"%s\" is neither perspective nor orthographic", cam,
             c.type.c_str());
    }
    double f[3] = {0.0 - world.m[8], 0.0 - world.m[9], 0.0 - world.m[10]}; /* no -0 */
    double u[3] = {world.m[4], world.m[5], world.m[6]};
    bool ok = normalize3(f);
    const double d = u[0] * f[0] + u[1] * f[1] + u[2] * f[2];
    for (int i = 0; i < 3; i++)
        u[i] -= d * f[i];
    if (!ok || !normalize3(u)) {
        note(warn, "node %d: camera %d passed over (its transform collapses an axis)", node, cam);
        return;
    }
    for (int i = 0; i < 3; i++) {
        pick.origin[i] = float(world.m[12 + i]);
        pick.forward[i] = float(f[i]);
        pick.up[i] = float(u[i]);
    }
    out.push_back(pick);
}

/* The KHR_lights_punctual light a node names (its extension's "light"),
 * or -1. */
int node_light(const tinygltf::Node &node, int index, size_t light_count)
{
    auto ext = node.extensions.find("KHR_lights_punctual");
    if (ext == node.extensions.end())
        return -1;
    const tinygltf::Value &v = ext->second.Get("light");
    if (!v.IsInt() && !v.IsNumber())
        fail("node %d: KHR_lights_punctual has no light index", index);
    const int i = v.IsInt() ? v.Get<int>() : int(v.GetNumberAsDouble());
    if (i < 0 || size_t(i) >= light_count)
        fail("node %d: light %d out of range (have %zu)", index, i, light_count);
    return i;
}

/* A punctual light (KHR_lights_punctual) at its node's world translation,
 * shining down the node's world -Z; the colour and intensity as the file
 * gives them (range, a culling hint, is not read). A spot's cone angles must
 * satisfy 0 <= inner < outer <= pi/2; a negative intensity or colour is an
 * error; a node whose transform collapses -Z drops a spot or directional
 * light with a warning. */
void take_light(const Model &m, int node, int li, const mat4 &world,
                std::vector<st_gltf_light> &out, notes &warn)
{
    const tinygltf::Light &l = m.lights[size_t(li)];
    st_gltf_light pick = {};
    if (l.type == "point")
        pick.type = 0;
    else if (l.type == "spot")
        pick.type = 1;
    else if (l.type == "directional")
        pick.type = 2;
    else
        fail("light %d: type \"%s\" is not point, spot or directional", li, l.type.c_str());
    if (!(l.intensity >= 0.0 && l.intensity < 1e30))
        fail("light %d: intensity %g must be finite and not negative", li, l.intensity);
    for (int i = 0; i < 3; i++) {
        const double c = l.color.size() == 3 ? l.color[size_t(i)] : 1.0;
        if (!(c >= 0.0 && c < 1e30))
            fail("light %d: color must be three finite values, not negative", li);
        pick.color[i] = float(c);
    }
    pick.intensity = float(l.intensity);
    pick.inner_cone = float(l.spot.innerConeAngle);
    pick.outer_cone = float(l.spot.outerConeAngle);
    if (pick.type == 1 && !(l.spot.innerConeAngle >= 0.0 &&
                            l.spot.innerConeAngle < l.spot.outerConeAngle &&
                            l.spot.outerConeAngle <= M_PI / 2.0))
        fail("light %d: spot cone angles %g, %g not 0 <= inner < outer <= pi/2", li,
             l.spot.innerConeAngle, l.spot.outerConeAngle);
    double f[3] = {0.0 - world.m[8], 0.0 - world.m[9], 0.0 - world.m[10]};
    if (!normalize3(f)) {
        if (pick.type != 0) {
            note(warn, "node %d: light %d passed over (its transform collapses -Z)", node, li);
            return;
        }
        f[2] = -1.0;
    }
    for (int i = 0; i < 3; i++) {
        pick.pos[i] = float(world.m[12 + i]);
        pick.dir[i] = float(f[i]);
    }
    out.push_back(pick);
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
void walk_scene(const Model &m, std::vector<instance> &out, std::vector<st_gltf_camera> &cams,
                std::vector<st_gltf_light> &lights, notes &warn)
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

/* The `bytes` bytes at `offset` of bufferView v, checked against its
 * buffer; what names the reader in errors. */
const unsigned char *view_bytes(const Model &m, int v, size_t offset, size_t bytes, int a,
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

/* Sparse accessors (§3.6.2.3) made dense, once, before anything reads
 * them: the base (its bufferView, or zeros without one) copied into a new
 * buffer, the sparse values written over it at their indices, and the
 * accessor pointed at the copy. */
void densify_sparse(Model &m)
{
    for (size_t a = 0; a < m.accessors.size(); a++) {
        tinygltf::Accessor &acc = m.accessors[a];
        if (!acc.sparse.isSparse)
            continue;
        const size_t elem = component_size(acc.componentType) * type_components(acc.type);
        if (elem == 0 || acc.count > (size_t(1) << 30) / elem)
            fail("accessor %zu: bad type or too many elements for a sparse accessor", a);
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

unsigned type_bit(int ct, bool normalized)
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
unsigned allowed_types(const Model &m, const char *attr)
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
             allowed_types(m, attr) == Q_F ? "float" : "float or a permitted integer", n, ct,
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

/* ---- primitives -------------------------------------------------------------- */

const tinygltf::Primitive &primitive(const Model &m, int mesh, size_t p)
{
    return m.meshes[size_t(mesh)].primitives[p];
}

bool is_triangles(const tinygltf::Primitive &prim)
{
    return prim.mode == TINYGLTF_MODE_TRIANGLES || prim.mode == -1 || /* -1: the default */
           prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP || prim.mode == TINYGLTF_MODE_TRIANGLE_FAN;
}

/* A TRIANGLE_STRIP's or TRIANGLE_FAN's vertex list as a triangle list, by
 * §3.7.2.1: strip triangle i = (v_i, v_{i+1+i%2}, v_{i+2-i%2}), fan triangle
 * i = (v_{i+1}, v_{i+2}, v_0). */
void strip_or_fan_to_list(int mode, std::vector<uint32_t> &idx)
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
int position_accessor(const Model &m, int mesh, size_t p)
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

const char *mode_name(int mode)
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

/* Where triangles go: arrays sized by the bound, filled in scene order. */
struct sink {
    float *pos, *nrm, *uv, *tan, *col;
    float *uv1; /* nullptr: no texture reads TEXCOORD_1 */
    uint32_t *mat;
    size_t count, dropped;
};

/* Per-primitive scratch, reused so that big scenes allocate once. */
struct scratch {
    std::vector<float> p, n, uv, uv1, wp, wn, t, wt, c;
    std::vector<uint32_t> idx;
    std::vector<char> neg; /* skinned: the vertex's skin matrix mirrors (det < 0) */
};

/* What a material's textures read: bit k of `sets` for TEXCOORD_k, and
 * the set of its normal map, the one its generated tangents follow (0
 * without a normal map). */
struct uv_use {
    unsigned sets = 0;
    int normal_set = 0;
};

/* Reads COLOR_0 (§3.7.2.1: float, or normalised unsigned byte or short,
 * VEC3 or VEC4; linear) into RGBA, alpha 1 for VEC3. */
void read_colors(const Model &m, int a, size_t vertices, std::vector<float> &out)
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
void read_tangents(const Model &m, int a, size_t vertices, std::vector<float> &out)
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
void generate_tangents(scratch &s, const std::vector<float> &uv, bool normals)
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

/* Tangents to world space: xyz by the world matrix and renormalised, w
 * times the sign of its determinant (a mirror turns the bitangent over). */
void transform_tangents(const mat4 &w, double det, scratch &s)
{
    const size_t nv = s.t.size() / 4;
    s.wt.assign(4 * nv, 0.0f);
    for (size_t v = 0; v < nv; v++) {
        const float *t = &s.t[4 * v];
        double o[3];
        for (int r = 0; r < 3; r++)
            o[r] = w.m[r] * t[0] + w.m[4 + r] * t[1] + w.m[8 + r] * t[2];
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

/* Every vertex to world space by one matrix (transform_vertex). */
void transform_vertices(const mat4 &w, const normal_xform &nx, scratch &s, bool normals)
{
    const size_t nv = s.p.size() / 3;
    s.wp.resize(3 * nv);
    s.wn.resize(normals ? 3 * nv : 0);
    for (size_t v = 0; v < nv; v++)
        transform_vertex(w, nx, s, v, normals);
}

/* Appends triangle (i0, i1, i2) unless it is non-finite or has zero area;
 * `sets`: bit k when the primitive has TEXCOORD_k (0s where it has not).
 * The face normal g = (p1 - p0) x (p2 - p0) / |...| is computed in double,
 * where float inputs cannot overflow, so |g| is finite exactly when the three
 * positions are; g stands in for missing or unusable vertex normals. */
void emit_triangle(const scratch &s, const uint32_t i[3], bool normals, unsigned sets,
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

/* ---- instancing, morph targets and skins ------------------------------------- */

/* Triangles of one drawing of a mesh (primitive_bound summed). */
size_t mesh_bound(const Model &m, int mesh)
{
    size_t n = 0;
    for (size_t p = 0; p < m.meshes[size_t(mesh)].primitives.size(); p++)
        n += primitive_bound(m, mesh, p);
    return n;
}

/* The accessor of EXT_mesh_gpu_instancing attribute `name` (checked), or -1. */
int instancing_accessor(const Model &m, const tinygltf::Value &attrs, const char *name, int node)
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

/* The node's mesh as it is drawn: once, or, with EXT_mesh_gpu_instancing,
 * once per instance with world = the node's world x T_i R_i S_i (the
 * extension's README: instance transforms apply in the node's space;
 * TRANSLATION, ROTATION and SCALE hold one element each per instance, a
 * missing one is the identity). Instances are flattened into the triangle
 * arrays, so their triangles count against ST_GLTF_MAX_TRIANGLES here,
 * before anything is allocated for them. A skinned node is drawn by its
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

/* World matrices of the nodes skins name, by their chains of parents (a
 * joint need not lie under the scene's roots the way the skinned mesh
 * does), each node's computed once. */
struct node_worlds {
    std::vector<int> parent;
    std::vector<mat4> world;
    std::vector<char> known;
};

mat4 node_world(const Model &m, node_worlds &w, int node)
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
    for (size_t v = 0; v < nv; v++) {
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

/* One primitive of one drawing of a mesh: morphed by `weights`, then
 * skinned by `joints` (the skin's joint matrices; NULL: not skinned) or
 * moved by `world`. */
void emit_primitive(const Model &m, int mesh, size_t p, const mat4 &world,
                    const normal_xform &nx, const std::vector<double> &weights,
                    const std::vector<mat4> *joints, const std::vector<uv_use> &use, scratch &s,
                    sink &out)
{
    const int pos = position_accessor(m, mesh, p);
    if (pos < 0)
        return;
    const tinygltf::Primitive &prim = primitive(m, mesh, p);
    if (prim.material != -1)
        check_index(prim.material, m.materials.size(), "mesh %d primitive %zu: material", mesh, p);
    const uint32_t material = prim.material == -1 ? ST_GLTF_NO_MATERIAL : uint32_t(prim.material);
    read_vec3(m, pos, "POSITION", s.p);
    const size_t nv = s.p.size() / 3;
    apply_morph(m, mesh, p, weights, "POSITION", 3, s.p);
    const int nrm = attribute(m, mesh, p, "NORMAL");
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
    const int uv1 = out.uv1 ? attribute(m, mesh, p, "TEXCOORD_1") : -1;
    if (uv1 >= 0)
        read_uv(m, uv1, "TEXCOORD_1", nv, s.uv1);
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
    const int col = attribute(m, mesh, p, "COLOR_0");
    s.c.clear();
    if (col >= 0)
        read_colors(m, col, nv, s.c);
    const int tan = attribute(m, mesh, p, "TANGENT");
    const bool set1 = material != ST_GLTF_NO_MATERIAL && use[material].normal_set == 1;
    s.t.clear();
    if (tan >= 0 && nrm >= 0) { /* §3.7.2.1: TANGENT is used with NORMAL only */
        read_tangents(m, tan, nv, s.t);
        apply_morph(m, mesh, p, weights, "TANGENT", 4, s.t);
    } else if ((set1 ? uv1 : uv) >= 0) { /* from the normal map's own set */
        generate_tangents(s, set1 ? s.uv1 : s.uv, nrm >= 0);
    }
    if (joints) {
        skin_vertices(skin_matrices(m, mesh, p, *joints, world, nv), s, nrm >= 0);
    } else {
        transform_vertices(world, nx, s, nrm >= 0);
        transform_tangents(world, nx.det, s);
    }
    for (size_t t = 0; t + 3 <= s.idx.size(); t += 3) { /* a trailing 1 or 2 are ignored */
        uint32_t tri[3] = {s.idx[t], s.idx[t + 1], s.idx[t + 2]};
        if (joints ? s.neg[tri[0]] != 0 : nx.det < 0.0) { /* mirrored: winding reversed */
            tri[1] = s.idx[t + 2];
            tri[2] = s.idx[t + 1];
        }
        emit_triangle(s, tri, nrm >= 0, (uv >= 0 ? 1u : 0u) | (uv1 >= 0 ? 2u : 0u), material,
                      out);
    }
}

/* ---- textures ----------------------------------------------------------------- */

/* Texture references of the materials, made unique; and the images made
 * here rather than read (image index m.images.size() + k): roughness maps
 * derived from a KHR_materials_pbrSpecularGlossiness texture's alpha
 * (source image, glossinessFactor). */
struct texture_table {
    std::vector<st_gltf_texture> refs;
    std::vector<std::pair<int, float>> derived;
};

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
void ext_pair(const tinygltf::Value &obj, const char *key, double out[2], const char *what)
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
int texture_transform(const tinygltf::ExtensionMap &ext, int tex_coord, float t[6],
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
int wrap_code(int sampler, int code, const char *axis)
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

/* Decodes image i (RGBA8) from its bufferView (checked like an accessor's) or
 * from the bytes tinygltf read for its URI. */
st_gltf_image decode_image(const Model &m, int i, const image_bytes &bytes)
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

/* Image i decoded, or, where it cannot be read or decoded, a warning naming
 * it and a 1 x 1 white image in its place: every slot multiplies its
 * factor by the texture, so white leaves the factor alone and the model
 * still renders. */
st_gltf_image decode_or_white(const Model &m, int i, const image_bytes &bytes, notes &warn)
{
    try {
        return decode_image(m, i, bytes);
    } catch (const shim_error &e) {
        if (e.status != ST_ERR_FORMAT)
            throw;
        note(warn, "%s: replaced by a white texture", e.msg.c_str());
    }
    unsigned char *white = static_cast<unsigned char *>(malloc(4)); /* stbi_image_free frees */
    if (!white)
        throw shim_error{ST_ERR_NOMEM, "out of memory"};
    memset(white, 255, 4);
    return {1u, 1u, white};
}

/* ---- materials ------------------------------------------------------------- */

/* The textureInfo object `key` of an extension object (index -1: none). */
tinygltf::TextureInfo ext_texture_info(const tinygltf::Value &obj, const char *key,
                                       const char *what)
{
    tinygltf::TextureInfo info;
    if (!obj.IsObject() || !obj.Has(key))
        return info;
    const tinygltf::Value &v = obj.Get(key);
    if (!v.IsObject() || !v.Has("index") || !v.Get("index").IsInt())
        fail("%s: %s needs an integer index", what, key);
    info.index = v.Get("index").GetNumberAsInt();
    info.texCoord = tex_coord_number(v, 0, what);
    if (v.Has("extensions") && v.Get("extensions").IsObject()) {
        const tinygltf::Value &e = v.Get("extensions");
        for (const std::string &name : e.Keys())
            info.extensions[name] = e.Get(name);
    }
    return info;
}

/* KHR_materials_specular (specularFactor 1, specularColorFactor 1 and their
 * textures: A of specularTexture, sRGB RGB of specularColorTexture),
 * KHR_materials_ior (ior 1.5) and KHR_materials_unlit of material i. */
void read_specular_ior_unlit(const Model &m, size_t i, texture_table &table, notes &warn,
                             st_gltf_material &o)
{
    const tinygltf::ExtensionMap &exts = m.materials[i].extensions;
    char what[64];
    snprintf(what, sizeof what, "material %zu: KHR_materials_specular", i);
    o.specular[0] = o.specular[1] = o.specular[2] = o.specular[3] = 1.0f;
    o.ior = 1.5f;
    o.specular_tex = o.specular_color_tex = -1;
    auto spec = exts.find("KHR_materials_specular");
    if (spec != exts.end()) {
        const tinygltf::Value &v = spec->second;
        o.specular[3] = float(ext_number(v, "specularFactor", 1.0, what));
        if (v.IsObject() && v.Has("specularColorFactor")) {
            const tinygltf::Value &c = v.Get("specularColorFactor");
            if (!c.IsArray() || c.ArrayLen() != 3 || !c.Get(0).IsNumber() ||
                !c.Get(1).IsNumber() || !c.Get(2).IsNumber())
                fail("%s: specularColorFactor must be an array of 3 numbers", what);
            for (int k = 0; k < 3; k++)
                o.specular[k] = float(c.Get(k).GetNumberAsDouble());
        }
        o.specular_tex = texture_ref(m, ext_texture_info(v, "specularTexture", what), false, i,
                                     "specularTexture", table, warn);
        o.specular_color_tex = texture_ref(m, ext_texture_info(v, "specularColorTexture", what),
                                           true, i, "specularColorTexture", table, warn);
    }
    auto ior = exts.find("KHR_materials_ior");
    if (ior != exts.end())
        o.ior = float(ext_number(ior->second, "ior", 1.5, "KHR_materials_ior"));
    o.unlit = exts.find("KHR_materials_unlit") != exts.end();
    for (int k = 0; k < 4; k++)
        if (!std::isfinite(o.specular[k]) || o.specular[k] < 0.0f)
            fail("%s: factors must be finite and >= 0", what);
    /* 0 is allowed: F0 = ((ior - 1) / (ior + 1))^2 = 1, the limit of a large ior */
    if (!std::isfinite(o.ior) || (o.ior < 1.0f && o.ior != 0.0f))
        fail("material %zu: KHR_materials_ior: ior %g is neither 0 nor >= 1", i, double(o.ior));
}

/* Three or four numbers of a JSON array `key` of obj into out; out unchanged
 * when absent. */
void ext_numbers(const tinygltf::Value &obj, const char *key, int n, float *out, const char *what)
{
    if (!obj.IsObject() || !obj.Has(key))
        return;
    const tinygltf::Value &v = obj.Get(key);
    if (!v.IsArray() || v.ArrayLen() != size_t(n))
        fail("%s: %s must be an array of %d numbers", what, key, n);
    for (int k = 0; k < n; k++) {
        if (!v.Get(k).IsNumber())
            fail("%s: %s must be an array of %d numbers", what, key, n);
        out[k] = float(v.Get(k).GetNumberAsDouble());
    }
}

/* KHR_materials_transmission (transmissionFactor 0, transmissionTexture's R)
 * and KHR_materials_volume's attenuation (attenuationColor 1,
 * attenuationDistance +infinity) of material i. The volume's thickness is
 * a rasteriser's stand-in for the geometry a path tracer follows: unused. */
void read_transmission_volume(const Model &m, size_t i, texture_table &table, notes &warn,
                              st_gltf_material &o)
{
    const tinygltf::ExtensionMap &exts = m.materials[i].extensions;
    char what[64];
    o.transmission = 0.0f;
    o.transmission_tex = -1;
    o.attenuation[0] = o.attenuation[1] = o.attenuation[2] = 1.0f;
    o.attenuation[3] = INFINITY;
    auto tr = exts.find("KHR_materials_transmission");
    if (tr != exts.end()) {
        snprintf(what, sizeof what, "material %zu: KHR_materials_transmission", i);
        o.transmission = float(ext_number(tr->second, "transmissionFactor", 0.0, what));
        if (!(o.transmission >= 0.0f && o.transmission <= 1.0f))
            fail("%s: transmissionFactor %g is not in [0, 1]", what, double(o.transmission));
        o.transmission_tex = texture_ref(m, ext_texture_info(tr->second, "transmissionTexture",
                                                             what),
                                         false, i, "transmissionTexture", table, warn);
    }
    auto vol = exts.find("KHR_materials_volume");
    if (vol != exts.end()) {
        snprintf(what, sizeof what, "material %zu: KHR_materials_volume", i);
        ext_numbers(vol->second, "attenuationColor", 3, o.attenuation, what);
        o.attenuation[3] = float(ext_number(vol->second, "attenuationDistance", INFINITY, what));
        for (int k = 0; k < 3; k++)
            if (!(o.attenuation[k] >= 0.0f && o.attenuation[k] <= 1.0f))
                fail("%s: attenuationColor must lie in [0, 1]", what);
        if (!(o.attenuation[3] > 0.0f))
            fail("%s: attenuationDistance %g is not > 0", what, double(o.attenuation[3]));
    }
}

/* KHR_materials_clearcoat of material i: clearcoatFactor and
 * clearcoatRoughnessFactor (0, 0) with their textures (R and G, linear).
 * clearcoatNormalTexture is not read: the coat takes the base's shading
 * normal (a warning). */
void read_clearcoat(const Model &m, size_t i, texture_table &table, notes &warn,
                    st_gltf_material &o)
{
    o.clearcoat = o.clearcoat_roughness = 0.0f;
    o.clearcoat_tex = o.clearcoat_roughness_tex = -1;
    auto cc = m.materials[i].extensions.find("KHR_materials_clearcoat");
    if (cc == m.materials[i].extensions.end())
        return;
    const tinygltf::Value &v = cc->second;
    char what[64];
    snprintf(what, sizeof what, "material %zu: KHR_materials_clearcoat", i);
    o.clearcoat = float(ext_number(v, "clearcoatFactor", 0.0, what));
    o.clearcoat_roughness = float(ext_number(v, "clearcoatRoughnessFactor", 0.0, what));
    if (!(o.clearcoat >= 0.0f && o.clearcoat <= 1.0f) ||
        !(o.clearcoat_roughness >= 0.0f && o.clearcoat_roughness <= 1.0f))
        fail("%s: clearcoatFactor and clearcoatRoughnessFactor must lie in [0, 1]", what);
    o.clearcoat_tex = texture_ref(m, ext_texture_info(v, "clearcoatTexture", what), false, i,
                                  "clearcoatTexture", table, warn);
    o.clearcoat_roughness_tex =
        texture_ref(m, ext_texture_info(v, "clearcoatRoughnessTexture", what), false, i,
                    "clearcoatRoughnessTexture", table, warn);
    if (v.IsObject() && v.Has("clearcoatNormalTexture"))
        note(warn, "%s: clearcoatNormalTexture is not read (the coat takes the base's normal)",
                 what);
}

/* KHR_materials_sheen of material i: sheenColorFactor (0, 0, 0: no sheen)
 * times sheenColorTexture's RGB (sRGB), sheenRoughnessFactor (0) times
 * sheenRoughnessTexture's alpha (linear). */
void read_sheen(const Model &m, size_t i, texture_table &table, notes &warn, st_gltf_material &o)
{
    o.sheen_color[0] = o.sheen_color[1] = o.sheen_color[2] = o.sheen_roughness = 0.0f;
    o.sheen_color_tex = o.sheen_roughness_tex = -1;
    auto sh = m.materials[i].extensions.find("KHR_materials_sheen");
    if (sh == m.materials[i].extensions.end())
        return;
    const tinygltf::Value &v = sh->second;
    char what[64];
    snprintf(what, sizeof what, "material %zu: KHR_materials_sheen", i);
    ext_numbers(v, "sheenColorFactor", 3, o.sheen_color, what);
    o.sheen_roughness = float(ext_number(v, "sheenRoughnessFactor", 0.0, what));
    for (int k = 0; k < 3; k++)
        if (!(o.sheen_color[k] >= 0.0f && o.sheen_color[k] <= 1.0f))
            fail("%s: sheenColorFactor must lie in [0, 1]", what);
    if (!(o.sheen_roughness >= 0.0f && o.sheen_roughness <= 1.0f))
        fail("%s: sheenRoughnessFactor must lie in [0, 1]", what);
    o.sheen_color_tex = texture_ref(m, ext_texture_info(v, "sheenColorTexture", what), true, i,
                                    "sheenColorTexture", table, warn);
    o.sheen_roughness_tex = texture_ref(m, ext_texture_info(v, "sheenRoughnessTexture", what),
                                        false, i, "sheenRoughnessTexture", table, warn);
}

/* KHR_materials_pbrSpecularGlossiness as metallic-roughness, the way
 * Khronos' glTF-Transform converts it (its metalRough function): a
 * dielectric (metallic 0) whose base colour is the diffuse colour, whose
 * F0 is the specular colour itself (KHR_materials_specular's
 * specularColorFactor and texture, the RGB of specularGlossinessTexture,
 * with an ior that makes the dielectric F0 1: strata takes ior 0 as that
 * limit) and whose roughness is 1 - glossiness. With a
 * specularGlossinessTexture the roughness map is made from its alpha: G =
 * 255 (1 - glossinessFactor x A / 255), roughness factor 1. Defaults (the
 * extension's README): diffuse 1, specular 1, glossiness 1. */
void read_spec_gloss(const Model &m, size_t i, texture_table &table, notes &warn,
                     st_gltf_material &o)
{
    auto ext = m.materials[i].extensions.find("KHR_materials_pbrSpecularGlossiness");
    if (ext == m.materials[i].extensions.end())
        return;
    const tinygltf::Value &v = ext->second;
    char what[80];
    snprintf(what, sizeof what, "material %zu: KHR_materials_pbrSpecularGlossiness", i);
    float diffuse[4] = {1, 1, 1, 1}, spec[3] = {1, 1, 1};
    ext_numbers(v, "diffuseFactor", 4, diffuse, what);
    ext_numbers(v, "specularFactor", 3, spec, what);
    const float gloss = float(ext_number(v, "glossinessFactor", 1.0, what));
    for (float f : {diffuse[0], diffuse[1], diffuse[2], diffuse[3], spec[0], spec[1], spec[2]})
        if (!std::isfinite(f) || f < 0.0f)
            fail("%s: factors must be finite and >= 0", what);
    if (!(gloss >= 0.0f && gloss <= 1.0f))
        fail("%s: glossinessFactor %g is not in [0, 1]", what, double(gloss));
    memcpy(o.base_color, diffuse, sizeof diffuse);
    memcpy(o.specular, spec, sizeof spec);
    o.specular[3] = 1.0f;
    o.ior = 0.0f;
    o.metallic = 0.0f;
    o.roughness = 1.0f - gloss;
    o.specular_tex = -1;
    o.base_color_tex = texture_ref(m, ext_texture_info(v, "diffuseTexture", what), true, i,
                                   "diffuseTexture", table, warn);
    const tinygltf::TextureInfo sg = ext_texture_info(v, "specularGlossinessTexture", what);
    o.specular_color_tex = texture_ref(m, sg, true, i, "specularGlossinessTexture", table, warn);
    o.metallic_roughness_tex = -1;
    if (o.specular_color_tex < 0)
        return;
    st_gltf_texture rough = table.refs[size_t(o.specular_color_tex)];
    const int source = rough.image;
    size_t k = 0;
    while (k < table.derived.size() &&
           (table.derived[k].first != source || table.derived[k].second != gloss))
        k++;
    if (k == table.derived.size())
        table.derived.push_back({source, gloss});
    rough.image = int(m.images.size() + k);
    rough.srgb = 0;
    o.roughness = 1.0f;
    size_t r = 0;
    while (r < table.refs.size() && memcmp(&table.refs[r], &rough, sizeof rough) != 0)
        r++;
    if (r == table.refs.size())
        table.refs.push_back(rough);
    o.metallic_roughness_tex = int(r);
}

/* A roughness map made from a specular-glossiness image (read_spec_gloss):
 * R 255, G = 255 (1 - gloss x A / 255) rounded, B 0 (metallic), A 255. */
st_gltf_image roughness_from_gloss(const st_gltf_image &src, float gloss)
{
    const size_t n = size_t(src.width) * src.height;
    unsigned char *rgba = static_cast<unsigned char *>(malloc(4 * n)); /* stbi_image_free frees */
    if (!rgba)
        throw std::bad_alloc();
    for (size_t t = 0; t < n; t++) {
        const double g = 255.0 * (1.0 - double(gloss) * src.rgba[4 * t + 3] / 255.0);
        rgba[4 * t] = 255;
        rgba[4 * t + 1] = static_cast<unsigned char>(std::lround(std::min(255.0, std::max(0.0, g))));
        rgba[4 * t + 2] = 0;
        rgba[4 * t + 3] = 255;
    }
    return {src.width, src.height, rgba};
}

/* A material's factors (§3.9.2, §3.9.3 defaults: base colour 1, metallic 1,
 * roughness 1, emission 0, alphaCutoff 0.5; emission x
 * KHR_materials_emissive_strength's emissiveStrength, 1 when absent) and its
 * base colour, emissive and metallic-roughness textures. Factors must be
 * finite and non-negative. */
st_gltf_material read_material(const Model &m, size_t i, texture_table &table, notes &warn)
{
    const tinygltf::Material &mat = m.materials[i];
    const tinygltf::PbrMetallicRoughness &pbr = mat.pbrMetallicRoughness;
    const std::vector<double> &bc = pbr.baseColorFactor;
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
    st_gltf_material o = {};
    for (int k = 0; k < 4; k++)
        o.base_color[k] = float(bc[size_t(k)]);
    for (int k = 0; k < 3; k++)
        o.emission[k] = float(ef[size_t(k)] * strength);
    o.metallic = float(pbr.metallicFactor);
    o.roughness = float(pbr.roughnessFactor);
    o.alpha_cutoff = float(mat.alphaCutoff);
    o.double_sided = mat.doubleSided ? 1 : 0;
    const float check[10] = {o.base_color[0], o.base_color[1], o.base_color[2], o.base_color[3],
                             o.emission[0],   o.emission[1],   o.emission[2],   o.metallic,
                             o.roughness,     o.alpha_cutoff};
    for (float v : check)
        if (!std::isfinite(v) || v < 0.0f)
            fail("material %zu: colour factors, emissiveStrength, metallic, roughness and "
                 "alphaCutoff must be finite and >= 0",
                 i);
    if (mat.alphaMode == "MASK")
        o.alpha_mode = 1;
    else if (mat.alphaMode == "BLEND")
        o.alpha_mode = 2;
    else if (mat.alphaMode != "OPAQUE" && !mat.alphaMode.empty())
        fail("material %zu: alphaMode \"%.40s\" is not OPAQUE, MASK or BLEND", i,
             mat.alphaMode.c_str());
    o.base_color_tex = texture_ref(m, pbr.baseColorTexture, true, i, "baseColorTexture", table, warn);
    o.emission_tex = texture_ref(m, mat.emissiveTexture, true, i, "emissiveTexture", table, warn);
    o.metallic_roughness_tex = texture_ref(m, pbr.metallicRoughnessTexture, false, i,
                                           "metallicRoughnessTexture", table, warn);
    read_specular_ior_unlit(m, i, table, warn, o);
    read_transmission_volume(m, i, table, warn, o);
    read_clearcoat(m, i, table, warn, o);
    read_sheen(m, i, table, warn, o);
    tinygltf::TextureInfo normal; /* NormalTextureInfo less its scale */
    normal.index = mat.normalTexture.index;
    normal.texCoord = mat.normalTexture.texCoord;
    normal.extensions = mat.normalTexture.extensions;
    o.normal_tex = texture_ref(m, normal, false, i, "normalTexture", table, warn);
    o.normal_scale = float(mat.normalTexture.scale);
    if (!std::isfinite(o.normal_scale))
        fail("material %zu: normalTexture.scale is not finite", i);
    read_spec_gloss(m, i, table, warn, o);
    return o;
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

/* A malloc'd copy of a vector (NULL when empty). */
template <typename T> T *copy_out(const std::vector<T> &v)
{
    T *p = alloc_array<T>(v.size(), 1);
    if (p)
        memcpy(p, v.data(), v.size() * sizeof(T));
    return p;
}

/* The sets each material's textures read, from its texture references. */
std::vector<uv_use> uv_uses(const std::vector<st_gltf_material> &mats, const texture_table &table)
{
    std::vector<uv_use> use(mats.size());
    for (size_t i = 0; i < mats.size(); i++) {
        const st_gltf_material &o = mats[i];
        const int slots[] = {o.base_color_tex, o.emission_tex,       o.metallic_roughness_tex,
                             o.specular_tex,   o.specular_color_tex, o.normal_tex};
        for (int t : slots)
            if (t >= 0)
                use[i].sets |= 1u << table.refs[size_t(t)].tex_coord;
        if (o.normal_tex >= 0)
            use[i].normal_set = table.refs[size_t(o.normal_tex)].tex_coord;
    }
    return use;
}

/* One warning per primitive whose material reads a texture coordinate set
 * that the primitive lacks (glTF-Validator's MESH_PRIMITIVE_TOO_FEW_TEXCOORDS):
 * its coordinates are 0 there, so those textures read at uv (0, 0). */
void note_missing_uvs(const Model &m, int mesh, const std::vector<uv_use> &use, notes &warn)
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
void check_triangle_bound(size_t bound)
{
    if (bound > ST_GLTF_MAX_TRIANGLES)
        fail("the scene makes up to %zu triangles, every instance counted: more than 2^24, the "
             "limit (about 400 bytes of memory each)", bound);
}

void flatten(const Model &m, const image_bytes &bytes, notes &warn, st_gltf_data &out)
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
    const std::vector<uv_use> use = uv_uses(mats, table);
    bool any_uv1 = false;
    for (const st_gltf_texture &t : table.refs)
        any_uv1 = any_uv1 || t.tex_coord == 1;
    std::vector<char> mesh_noted(m.meshes.size(), 0);
    size_t bound = 0;
    for (const instance &in : inst) {
        if (!mesh_noted[size_t(in.mesh)]++) {
            note_skipped_primitives(m, in.mesh, warn);
            note_missing_uvs(m, in.mesh, use, warn);
            note_morph_targets(m, in.mesh, warn);
        }
        bound += mesh_bound(m, in.mesh); /* each primitive's <= its accessor's elements */
    }
    check_triangle_bound(bound);
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
    scratch tmp;
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
        for (size_t p = 0; p < m.meshes[size_t(in.mesh)].primitives.size(); p++)
            emit_primitive(m, in.mesh, p, in.world, nx, weights,
                           in.skin >= 0 ? &joints[size_t(in.skin)] : nullptr, use, tmp, s);
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
    out.material_count = mats.size();
    out.materials = copy_out(mats);
    out.texture_count = table.refs.size();
    out.textures = copy_out(table.refs);
    out.image_count = m.images.size() + table.derived.size();
    out.images = alloc_array<st_gltf_image>(out.image_count, 1);
    if (out.images)
        memset(out.images, 0, out.image_count * sizeof *out.images);
    for (const st_gltf_texture &t : table.refs)
        if (size_t(t.image) < m.images.size() && !out.images[size_t(t.image)].rgba)
            out.images[size_t(t.image)] = decode_or_white(m, t.image, bytes, warn);
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
void note_degenerate_scale(const st_gltf_data &out, notes &warn)
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

void take_warnings(const notes &warn, st_gltf_data &out)
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
        image_bytes images;
        notes warn;
        parse(model, bytes, size, base_dir, images, warn);
        densify_sparse(model);
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
