/* gltf_parse.cpp — the glTF document read through tinygltf.
 *
 * The bytes are checked before tinygltf sees them (the GLB container, §4.4;
 * the JSON's nesting depth; asset.version; extensionsRequired against the
 * extensions strata implements; the schema's sizes and offsets; data: URIs),
 * then parsed with our own file callbacks: buffers and images are read only
 * from the scene's folder (scene_fs.h), and images are kept encoded for
 * gltf_textures.cpp to decode where a material uses them. */
#include "gltf_int.h"
#include "scene_fs.h"

#include <cjson/cJSON.h> /* Debian libcjson-dev: extensionsRequired, before tinygltf parses */

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iterator> /* std::size */

#include <unistd.h> /* close(2) */

namespace st_gltf {

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
static bool fs_exists(const std::string &path, void *user)
{
    const fs_context *ctx = static_cast<const fs_context *>(user);
    return !ctx->base_dir || path.compare(0, strlen(ctx->base_dir), ctx->base_dir) == 0;
}

static std::string fs_expand(const std::string &path, void *) { return path; }

/* The URI in tinygltf's joined path (base_dir, a '/' unless base_dir ends in
 * one, the URI). */
static std::string uri_of(const fs_context *ctx, const std::string &path)
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
static bool fs_read(std::vector<unsigned char> *out, std::string *err, const std::string &path,
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
static void check_data_uris(const unsigned char *json, size_t len)
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

static bool fs_write(std::string *, const std::string &, const std::vector<unsigned char> &, void *)
{
    return false;
}

/* tinygltf's image callback: keeps the bytes, decodes nothing (decoding waits
 * until we know which images a material uses). tinygltf passes a bufferView
 * image's bytes without checking the view against its buffer, so those are
 * not touched here. */
static bool keep_image_bytes(tinygltf::Image *img, const int idx, std::string *, std::string *, int,
                             int, const unsigned char *bytes, int size, void *user)
{
    if (img->bufferView != -1 || size <= 0)
        return true;
    static_cast<image_bytes *>(user)->by_index[idx].assign(bytes, bytes + size);
    return true;
}

static std::string first_line(const std::string &s)
{
    std::string line = s.substr(0, s.find('\n'));
    while (!line.empty() && (line.back() == '\r' || line.back() == ' '))
        line.pop_back();
    return line;
}

static uint32_t le32(const unsigned char *p)
{
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

/* GLB (§4.4): a 12-byte header (magic, version, total length) and chunks of
 * (length, type, data). tinygltf 2.7 checks a BIN chunk's end without its
 * 8-byte header, so every chunk is checked to lie inside the data here. */
static void check_glb(const unsigned char *b, size_t size)
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
static void check_nesting(const unsigned char *json, size_t len)
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
static void json_text(const unsigned char *bytes, size_t size, bool glb, const unsigned char **json,
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
    "KHR_materials_sheen", "KHR_materials_anisotropy", "KHR_materials_diffuse_transmission",
    "KHR_materials_iridescence", "KHR_materials_dispersion"};

static bool supported(const char *ext)
{
    for (const char *s : supported_extensions)
        if (strcmp(s, ext) == 0)
            return true;
    return false;
}

/* asset.version "MAJOR.MINOR": strata reads glTF 2 (a later major version
 * may change anything, §3.2); a missing version is left to tinygltf. */
static void check_asset_version(const cJSON *root)
{
    const cJSON *asset = cJSON_GetObjectItemCaseSensitive(root, "asset");
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(asset, "version");
    if (cJSON_IsString(v) && (strncmp(v->valuestring, "2.", 2) != 0 || !v->valuestring[2]))
        fail("asset version \"%.40s\": strata reads glTF 2.x only", v->valuestring);
}

/* One size or offset of the schema: absent, or an integer >= 0 (tinygltf
 * reads a negative or fractional one as 0 without a word). */
static void check_size(const cJSON *obj, const char *key, const char *what, int index)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (v && (!cJSON_IsNumber(v) || !(v->valuedouble >= 0.0) ||
              v->valuedouble != std::floor(v->valuedouble) || v->valuedouble > 9007199254740992.0))
        fail("%s %d: %s is not an integer >= 0", what, index, key);
}

/* The sizes and offsets of buffers, buffer views and accessors (with their
 * sparse parts), checked in the JSON before tinygltf reads them. */
static void check_sizes(const cJSON *root)
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

/* The keys whose number is an index or an enum of the schema (and of the extensions strata
 * reads): tinygltf converts each to int, so 4294967296 would read as 0 and 1e20 has no int. */
static const char *const index_keys[] = {
    "scene", "camera", "skin", "mesh", "light", "indices", "material", "mode", "bufferView",
    "buffer", "componentType", "target", "inverseBindMatrices", "skeleton", "source", "sampler",
    "index", "texCoord", "magFilter", "minFilter", "wrapS", "wrapT", "node", "input", "output"};
/* Keys of arrays of indices, and of objects whose every member is one. */
static const char *const index_lists[] = {"nodes", "children", "joints", "attributes"};

static bool named_in(const char *key, const char *const *names, size_t n)
{
    for (size_t i = 0; key && i < n; i++)
        if (strcmp(key, names[i]) == 0)
            return true;
    return false;
}

/* Refuses an index or enum (by its key, or as a member of an index list; a morph target's
 * members are accessor indices) that is not an integer from 0 to INT_MAX, naming its place
 * ("nodes[2].mesh"). extras, and extensions strata does not read, are free-form: skipped. The
 * recursion is bounded by check_nesting's depth. */
static void check_indices(const cJSON *item, const std::string &at, bool list)
{
    const bool targets = cJSON_IsArray(item) && item->string && !strcmp(item->string, "targets");
    const bool extensions = item->string && !strcmp(item->string, "extensions");
    size_t i = 0;
    for (const cJSON *c = item->child; c; c = c->next, i++) {
        const char *key = cJSON_IsArray(item) ? nullptr : c->string;
        if (key && (!strcmp(key, "extras") || (extensions && !supported(key))))
            continue;
        const std::string here = key ? (at.empty() ? std::string(key) : at + "." + key)
                                     : at + "[" + std::to_string(i) + "]";
        if (cJSON_IsNumber(c) && (list || named_in(key, index_keys, std::size(index_keys)))) {
            const double v = c->valuedouble;
            if (!(v >= 0.0 && v <= double(INT_MAX) && v == std::floor(v)))
                fail("%s: %.17g is not an index (an integer from 0 to %d)", here.c_str(), v,
                     INT_MAX);
        } else if (cJSON_IsArray(c) || cJSON_IsObject(c)) {
            check_indices(c, here, named_in(key, index_lists, std::size(index_lists)) || targets);
        }
    }
}

/* A scene's materials, at most: tinygltf makes a large object of each (some 2.5 kB), so a
 * million empty ones ({} in 3 bytes of JSON each) would take gigabytes before anything is read;
 * far more than any model has. */
static void check_counts(const cJSON *root)
{
    const int n = cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "materials"));
    if (n > int(ST_GLTF_MAX_MATERIALS))
        fail("%d materials: more than %u, the limit", n, ST_GLTF_MAX_MATERIALS);
}

/* extensionsRequired, read from the JSON (a GLB's first chunk) before
 * tinygltf parses the rest, so that a Draco or meshopt file fails naming
 * the extension instead of on the buffers it cannot decode. */
static void check_required(const unsigned char *bytes, size_t size, bool glb)
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
        check_counts(root);
        if (root)
            check_indices(root, "", false);
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

} /* namespace st_gltf */
