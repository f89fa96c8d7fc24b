/* gltf_materials.cpp — materials (§3.9) and the KHR_materials_* extensions.
 *
 * The core metallic-roughness material with its factors' defaults, and
 * KHR_materials_emissive_strength, _specular, _ior, _unlit, _transmission,
 * _volume (attenuation), _clearcoat, _sheen, _anisotropy,
 * _diffuse_transmission, _iridescence, _dispersion and
 * _pbrSpecularGlossiness (converted to metallic-roughness). */
#include "gltf_int.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <new>

namespace st_gltf {

/* The textureInfo object `key` of an extension object (index -1: none). */
static tinygltf::TextureInfo ext_texture_info(const tinygltf::Value &obj, const char *key,
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
static void read_specular_ior_unlit(const Model &m, size_t i, texture_table &table, notes &warn,
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
static void ext_numbers(const tinygltf::Value &obj, const char *key, int n, float *out,
                        const char *what)
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
 * a rasteriser's stand-in for the geometry a path tracer follows, except
 * that 0, its default, makes the material thin-walled, as does transmission
 * without a volume (the specification's rule): the surface bounds no
 * interior. */
static void read_transmission_volume(const Model &m, size_t i, texture_table &table, notes &warn,
                                     st_gltf_material &o)
{
    const tinygltf::ExtensionMap &exts = m.materials[i].extensions;
    char what[64];
    o.transmission = 0.0f;
    o.transmission_tex = -1;
    o.thin_walled = 0;
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
    double thickness = 0.0; /* the specification's default: thin-walled */
    if (vol != exts.end()) {
        snprintf(what, sizeof what, "material %zu: KHR_materials_volume", i);
        thickness = ext_number(vol->second, "thicknessFactor", 0.0, what);
        if (!(thickness >= 0.0))
            fail("%s: thicknessFactor %g is not >= 0", what, thickness);
    }
    o.thin_walled = tr != exts.end() && thickness == 0.0;
    if (vol != exts.end()) {
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
 * clearcoatRoughnessFactor (0, 0) with their textures (R and G, linear),
 * and clearcoatNormalTexture with its scale (1): the coat's own normal map,
 * which bends the interpolated normal as normalTexture does the base's. */
static void read_clearcoat(const Model &m, size_t i, texture_table &table, notes &warn,
                           st_gltf_material &o)
{
    o.clearcoat = o.clearcoat_roughness = 0.0f;
    o.clearcoat_tex = o.clearcoat_roughness_tex = o.clearcoat_normal_tex = -1;
    o.clearcoat_normal_scale = 1.0f;
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
    o.clearcoat_normal_tex =
        texture_ref(m, ext_texture_info(v, "clearcoatNormalTexture", what), false, i,
                    "clearcoatNormalTexture", table, warn);
    if (o.clearcoat_normal_tex >= 0) {
        const tinygltf::Value &n = v.Get("clearcoatNormalTexture");
        o.clearcoat_normal_scale = float(ext_number(n, "scale", 1.0, what));
        if (!std::isfinite(o.clearcoat_normal_scale))
            fail("%s: clearcoatNormalTexture.scale is not finite", what);
    }
}

/* KHR_materials_sheen of material i: sheenColorFactor (0, 0, 0: no sheen)
 * times sheenColorTexture's RGB (sRGB), sheenRoughnessFactor (0) times
 * sheenRoughnessTexture's alpha (linear). */
static void read_sheen(const Model &m, size_t i, texture_table &table, notes &warn,
                       st_gltf_material &o)
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

/* KHR_materials_anisotropy of material i: anisotropyStrength (0, in
 * [0, 1]), anisotropyRotation (0 radians, any finite angle) and
 * anisotropyTexture (linear: RG the direction, B the strength). */
static void read_anisotropy(const Model &m, size_t i, texture_table &table, notes &warn,
                            st_gltf_material &o)
{
    o.anisotropy = o.anisotropy_rotation = 0.0f;
    o.anisotropy_tex = -1;
    auto an = m.materials[i].extensions.find("KHR_materials_anisotropy");
    if (an == m.materials[i].extensions.end())
        return;
    const tinygltf::Value &v = an->second;
    char what[64];
    snprintf(what, sizeof what, "material %zu: KHR_materials_anisotropy", i);
    o.anisotropy = float(ext_number(v, "anisotropyStrength", 0.0, what));
    o.anisotropy_rotation = float(ext_number(v, "anisotropyRotation", 0.0, what));
    if (!(o.anisotropy >= 0.0f && o.anisotropy <= 1.0f))
        fail("%s: anisotropyStrength %g is not in [0, 1]", what, double(o.anisotropy));
    if (!std::isfinite(o.anisotropy_rotation))
        fail("%s: anisotropyRotation is not finite", what);
    o.anisotropy_tex = texture_ref(m, ext_texture_info(v, "anisotropyTexture", what), false, i,
                                   "anisotropyTexture", table, warn);
}

/* KHR_materials_diffuse_transmission of material i:
 * diffuseTransmissionFactor (0) x diffuseTransmissionTexture's A (linear)
 * and diffuseTransmissionColorFactor (1, 1, 1) x
 * diffuseTransmissionColorTexture's RGB (sRGB), each in [0, 1]. */
static void read_diffuse_transmission(const Model &m, size_t i, texture_table &table, notes &warn,
                                      st_gltf_material &o)
{
    o.diffuse_trans[0] = o.diffuse_trans[1] = o.diffuse_trans[2] = 1.0f;
    o.diffuse_trans[3] = 0.0f;
    o.diffuse_trans_tex = o.diffuse_trans_color_tex = -1;
    auto dt = m.materials[i].extensions.find("KHR_materials_diffuse_transmission");
    if (dt == m.materials[i].extensions.end())
        return;
    const tinygltf::Value &v = dt->second;
    char what[72];
    snprintf(what, sizeof what, "material %zu: KHR_materials_diffuse_transmission", i);
    o.diffuse_trans[3] = float(ext_number(v, "diffuseTransmissionFactor", 0.0, what));
    ext_numbers(v, "diffuseTransmissionColorFactor", 3, o.diffuse_trans, what);
    for (int k = 0; k < 4; k++)
        if (!(o.diffuse_trans[k] >= 0.0f && o.diffuse_trans[k] <= 1.0f))
            fail("%s: diffuseTransmissionFactor and diffuseTransmissionColorFactor must lie in "
                 "[0, 1]",
                 what);
    o.diffuse_trans_tex = texture_ref(m, ext_texture_info(v, "diffuseTransmissionTexture", what),
                                      false, i, "diffuseTransmissionTexture", table, warn);
    o.diffuse_trans_color_tex =
        texture_ref(m, ext_texture_info(v, "diffuseTransmissionColorTexture", what), true, i,
                    "diffuseTransmissionColorTexture", table, warn);
}

/* KHR_materials_iridescence of material i: iridescenceFactor (0, in
 * [0, 1]) x iridescenceTexture's R, iridescenceIor (1.3, >= 1) and the
 * thickness, mix(iridescenceThicknessMinimum (100 nm), ..Maximum (400 nm),
 * iridescenceThicknessTexture's G), the maximum without that texture
 * (both >= 0; linear textures). */
static void read_iridescence(const Model &m, size_t i, texture_table &table, notes &warn,
                             st_gltf_material &o)
{
    o.iridescence[0] = 0.0f;
    o.iridescence[1] = 1.3f;
    o.iridescence[2] = 100.0f;
    o.iridescence[3] = 400.0f;
    o.iridescence_tex = o.iridescence_thickness_tex = -1;
    auto ir = m.materials[i].extensions.find("KHR_materials_iridescence");
    if (ir == m.materials[i].extensions.end())
        return;
    const tinygltf::Value &v = ir->second;
    char what[64];
    snprintf(what, sizeof what, "material %zu: KHR_materials_iridescence", i);
    o.iridescence[0] = float(ext_number(v, "iridescenceFactor", 0.0, what));
    o.iridescence[1] = float(ext_number(v, "iridescenceIor", 1.3, what));
    o.iridescence[2] = float(ext_number(v, "iridescenceThicknessMinimum", 100.0, what));
    o.iridescence[3] = float(ext_number(v, "iridescenceThicknessMaximum", 400.0, what));
    if (!(o.iridescence[0] >= 0.0f && o.iridescence[0] <= 1.0f))
        fail("%s: iridescenceFactor %g is not in [0, 1]", what, double(o.iridescence[0]));
    if (!(o.iridescence[1] >= 1.0f) || !std::isfinite(o.iridescence[1]))
        fail("%s: iridescenceIor %g is not a finite number >= 1", what, double(o.iridescence[1]));
    for (int k = 2; k < 4; k++)
        if (!(o.iridescence[k] >= 0.0f) || !std::isfinite(o.iridescence[k]))
            fail("%s: iridescenceThicknessMinimum and ..Maximum must be finite and >= 0", what);
    o.iridescence_tex = texture_ref(m, ext_texture_info(v, "iridescenceTexture", what), false, i,
                                    "iridescenceTexture", table, warn);
    o.iridescence_thickness_tex =
        texture_ref(m, ext_texture_info(v, "iridescenceThicknessTexture", what), false, i,
                    "iridescenceThicknessTexture", table, warn);
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
static void read_spec_gloss(const Model &m, size_t i, texture_table &table, notes &warn,
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
    read_anisotropy(m, i, table, warn, o);
    read_diffuse_transmission(m, i, table, warn, o);
    read_iridescence(m, i, table, warn, o);
    o.dispersion = 0.0f; /* KHR_materials_dispersion: 20 / V_d, any value >= 0 */
    auto disp = mat.extensions.find("KHR_materials_dispersion");
    if (disp != mat.extensions.end()) {
        char what[64];
        snprintf(what, sizeof what, "material %zu: KHR_materials_dispersion", i);
        o.dispersion = float(ext_number(disp->second, "dispersion", 0.0, what));
        if (!(o.dispersion >= 0.0f) || !std::isfinite(o.dispersion))
            fail("%s: dispersion %g is not a finite number >= 0", what, double(o.dispersion));
    }
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

/* What each slot makes of an image that could not be read (decode_images):
 * a normal map (the base's or the clear coat's) is left out, the geometric
 * and vertex normals kept, since its white texel is not neutral (the
 * normal (1, 1, 1), some 55 degrees off), and so is an anisotropy texture
 * (white turns the direction by 45 degrees); every other slot keeps the white
 * image, which leaves its factor alone. One warning per normal map left
 * out, one per image made white. */
void note_unreadable(std::vector<st_gltf_material> &mats, const texture_table &table,
                     const std::vector<std::string> &why, notes &warn)
{
    auto unreadable = [&](int t) {
        return t >= 0 && size_t(table.refs[size_t(t)].image) < why.size() &&
               !why[size_t(table.refs[size_t(t)].image)].empty();
    };
    std::vector<char> white(why.size(), 0);
    for (size_t i = 0; i < mats.size(); i++) {
        st_gltf_material &o = mats[i];
        if (unreadable(o.normal_tex)) {
            note(warn, "material %zu: normalTexture: %s: left out (the vertex normals kept)", i,
                 why[size_t(table.refs[size_t(o.normal_tex)].image)].c_str());
            o.normal_tex = -1;
        }
        if (unreadable(o.clearcoat_normal_tex)) {
            note(warn,
                 "material %zu: clearcoatNormalTexture: %s: left out (the vertex normals kept)",
                 i, why[size_t(table.refs[size_t(o.clearcoat_normal_tex)].image)].c_str());
            o.clearcoat_normal_tex = -1;
        }
        if (unreadable(o.anisotropy_tex)) {
            note(warn, "material %zu: anisotropyTexture: %s: left out (the factors kept)", i,
                 why[size_t(table.refs[size_t(o.anisotropy_tex)].image)].c_str());
            o.anisotropy_tex = -1;
        }
        const int slots[] = {o.base_color_tex,   o.emission_tex,     o.metallic_roughness_tex,
                             o.specular_tex,     o.specular_color_tex, o.transmission_tex,
                             o.clearcoat_tex,    o.clearcoat_roughness_tex, o.sheen_color_tex,
                             o.sheen_roughness_tex, o.diffuse_trans_tex,
                             o.diffuse_trans_color_tex, o.iridescence_tex,
                             o.iridescence_thickness_tex};
        for (int t : slots)
            if (unreadable(t))
                white[size_t(table.refs[size_t(t)].image)] = 1;
    }
    for (size_t k = 0; k < why.size(); k++)
        if (white[k])
            note(warn, "%s: replaced by a white texture", why[k].c_str());
}

/* occlusionTexture (§3.9.3) is not read: it darkens the ambient light a
 * rasteriser adds, and a path tracer finds that occlusion itself. One
 * warning names the first material that has one and counts the rest. */
void note_occlusion(const Model &m, notes &warn)
{
    size_t count = 0, first = 0;
    for (size_t i = 0; i < m.materials.size(); i++)
        if (m.materials[i].occlusionTexture.index != -1 && count++ == 0)
            first = i;
    if (count)
        note(warn, "occlusionTexture of material %zu%s is not read (a path tracer finds "
                   "occlusion itself)",
             first, count > 1 ? (" and " + std::to_string(count - 1) + " more").c_str() : "");
}

} /* namespace st_gltf */
