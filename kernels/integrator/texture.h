/* texture.h — texture lookups, shared by the kernels (shade_hits) and the host
 * (the scene loader's mip chains, the light table, tests/device/test_texture.c), so
 * the tests run the device's own code. Included after st_shared.h (ST_FN,
 * ST_GLOBAL, ST_CONSTANT, st_texture).
 *
 * A texture is one image's mip chain in a packed RGBA8 array (st_shared.h,
 * st_texture). A lookup at (u, v) with level of detail `lod`:
 *   1. (u, v) goes through the reference's KHR_texture_transform matrix;
 *   2. the wrap mode maps it into the image (REPEAT: fract; MIRRORED_REPEAT:
 *      period 2, reflected; CLAMP_TO_EDGE: the edge texel), on the texel
 *      lattice of the level read, texel centres at (i + 1/2) / width;
 *   3. the filter: ST_TEXFILTER_NONE reads the nearest texel of level 0,
 *      BILINEAR interpolates the four nearest texels of level 0, TRILINEAR
 *      interpolates bilinear lookups of levels floor(lod) and floor(lod) + 1
 *      by the fraction of lod (OpenGL 4.6 §8.14.2, LINEAR_MIPMAP_LINEAR),
 *      lod clamped to [0, levels - 1]; at lod <= 0 (magnification) it reads
 *      level 0 bilinearly, or its nearest texel when the sampler's
 *      magFilter is NEAREST (ST_TEX_MAG_NEAREST);
 *   4. RGB bytes of an sRGB texture are decoded to linear by st_srgb_table,
 *      the others and alpha divided by 255.
 * Filtering happens on linear values (after the sRGB decode), as GPUs do for
 * SRGB8_ALPHA8 textures. The result is RGBA in out[4].
 *
 * Level of detail by ray cones (Akenine-Moller, Nilsson, Andersson, Barre-
 * Brisebois, Toth, Karras, "Texture Level of Detail Strategies for Real-Time
 * Ray Tracing", Ray Tracing Gems, ch. 20, 2019, eq. 34):
 *   lod = Delta + log2(w) - log2|n . d|,  Delta = 1/2 log2(t_a / p_a),
 * w the cone's width at the hit, n the surface normal, d the ray direction,
 * t_a = width x height x |uv area| the triangle's area in texels, p_a its
 * world area. Delta is split into the triangle's part (st_tri_uv.lod) and the
 * texture's (st_texture.lod_bias). Tests: tests/device/test_texture.c. */
#ifndef ST_TEXTURE_H
#define ST_TEXTURE_H

#ifndef __OPENCL_VERSION__
#include "st_shared.h"
#define ST_LOG2F(x) log2f(x)
#else
#define ST_LOG2F(x) log2(x)
#endif

/* floor(x), but for -0, which becomes +0 (no lookup tells them apart): a
 * float of magnitude 2^23 or more is an integer already, and is returned
 * as it is, as are NaN and the infinities; below, the truncation, less one
 * where it rounded up. The lookups take floors of every coordinate, and
 * PoCL's CPU devices make OpenCL's floor() a run of compares and branches
 * (objdump of the kernels), where this is a few branch-free instructions,
 * the same text on the host. */
ST_FN st_f32 st_tex_floor(st_f32 x)
{
    int small = x < 8388608.0f && x > -8388608.0f;
    st_f32 t = (st_f32)(st_i32)(small ? x : 0.0f); /* no conversion out of range */
    t = t > x ? t - 1.0f : t;
    return small ? t : x;
}

/* sRGB decode (IEC 61966-2-1:1999): c = b / 255,
 *   linear = c / 12.92                   c <= 0.04045
 *   linear = ((c + 0.055) / 1.055)^2.4    otherwise,
 * tabulated to 9 significant digits (test_texture.c checks it against the
 * formula), so host and device decode to the same bits. */
ST_CONSTANT st_f32 st_srgb_table[256] = {
    0.0f, 0.000303526984f, 0.000607053967f, 0.000910580951f, 0.00121410793f, 0.00151763492f,
    0.0018211619f, 0.00212468888f, 0.00242821587f, 0.00273174285f, 0.00303526984f, 0.00334653576f,
    0.00367650732f, 0.00402471702f, 0.00439144204f, 0.00477695348f, 0.0051815167f, 0.00560539162f,
    0.00604883302f, 0.00651209079f, 0.00699541019f, 0.00749903204f, 0.00802319299f, 0.00856812562f,
    0.0091340587f, 0.00972121732f, 0.010329823f, 0.010960094f, 0.0116122452f, 0.0122864884f,
    0.0129830323f, 0.013702083f, 0.0144438436f, 0.0152085144f, 0.0159962934f, 0.0168073758f,
    0.0176419545f, 0.0185002201f, 0.019382361f, 0.0202885631f, 0.0212190104f, 0.0221738848f,
    0.0231533662f, 0.0241576324f, 0.0251868596f, 0.0262412219f, 0.0273208916f, 0.0284260395f,
    0.0295568344f, 0.0307134437f, 0.0318960331f, 0.0331047666f, 0.0343398068f, 0.0356013149f,
    0.0368894504f, 0.0382043716f, 0.0395462353f, 0.0409151969f, 0.0423114106f, 0.0437350293f,
    0.0451862044f, 0.0466650863f, 0.0481718242f, 0.049706566f, 0.0512694584f, 0.052860647f,
    0.0544802764f, 0.05612849f, 0.0578054302f, 0.0595112382f, 0.0612460542f, 0.0630100177f,
    0.0648032667f, 0.0666259386f, 0.0684781698f, 0.0703600957f, 0.0722718507f, 0.0742135684f,
    0.0761853815f, 0.0781874218f, 0.0802198203f, 0.0822827071f, 0.0843762115f, 0.086500462f,
    0.0886555863f, 0.0908417112f, 0.0930589628f, 0.0953074666f, 0.0975873471f, 0.0998987282f,
    0.102241733f, 0.104616484f, 0.107023103f, 0.109461711f, 0.111932428f, 0.114435374f,
    0.116970668f, 0.119538428f, 0.122138772f, 0.124771818f, 0.12743768f, 0.130136477f,
    0.132868322f, 0.13563333f, 0.138431615f, 0.141263291f, 0.144128471f, 0.147027266f,
    0.14995979f, 0.152926152f, 0.155926464f, 0.158960835f, 0.162029376f, 0.165132195f,
    0.1682694f, 0.171441101f, 0.174647404f, 0.177888416f, 0.181164244f, 0.184474995f,
    0.187820772f, 0.191201683f, 0.19461783f, 0.19806932f, 0.201556254f, 0.205078736f,
    0.20863687f, 0.212230757f, 0.2158605f, 0.2195262f, 0.223227957f, 0.226965874f,
    0.230740049f, 0.234550582f, 0.238397574f, 0.242281122f, 0.246201327f, 0.250158285f,
    0.254152094f, 0.258182853f, 0.262250658f, 0.266355605f, 0.270497791f, 0.274677312f,
    0.278894263f, 0.28314874f, 0.287440838f, 0.29177065f, 0.296138271f, 0.300543794f,
    0.304987314f, 0.309468923f, 0.313988713f, 0.318546778f, 0.323143209f, 0.327778098f,
    0.332451536f, 0.337163615f, 0.341914425f, 0.346704056f, 0.3515326f, 0.356400144f,
    0.36130678f, 0.366252596f, 0.37123768f, 0.376262123f, 0.381326011f, 0.386429434f,
    0.391572478f, 0.396755231f, 0.40197778f, 0.407240212f, 0.412542613f, 0.417885071f,
    0.42326767f, 0.428690497f, 0.434153636f, 0.439657174f, 0.445201195f, 0.450785783f,
    0.456411023f, 0.462077f, 0.467783796f, 0.473531496f, 0.479320183f, 0.48514994f,
    0.49102085f, 0.496932995f, 0.502886458f, 0.508881321f, 0.514917665f, 0.520995573f,
    0.527115126f, 0.533276404f, 0.539479489f, 0.545724461f, 0.552011402f, 0.55834039f,
    0.564711506f, 0.571124829f, 0.57758044f, 0.584078418f, 0.590618841f, 0.597201788f,
    0.603827339f, 0.610495571f, 0.617206562f, 0.623960392f, 0.630757136f, 0.637596874f,
    0.644479682f, 0.651405637f, 0.658374817f, 0.665387298f, 0.672443157f, 0.67954247f,
    0.686685312f, 0.693871761f, 0.701101892f, 0.70837578f, 0.715693501f, 0.723055129f,
    0.73046074f, 0.737910409f, 0.74540421f, 0.752942217f, 0.760524505f, 0.768151147f,
    0.775822218f, 0.783537792f, 0.79129794f, 0.799102738f, 0.806952258f, 0.814846572f,
    0.822785754f, 0.830769877f, 0.838799012f, 0.846873232f, 0.854992608f, 0.863157213f,
    0.871367119f, 0.879622397f, 0.887923118f, 0.896269353f, 0.904661174f, 0.913098652f,
    0.921581856f, 0.930110858f, 0.938685728f, 0.947306537f, 0.955973353f, 0.964686248f,
    0.97344529f, 0.98225055f, 0.991102097f, 1.0f,
};

ST_FN st_f32 st_srgb_to_linear(st_u32 byte)
{
    return st_srgb_table[byte & 255u];
}

/* i mod p in [0, p). The lookups' i is at most one period outside [0, p)
 * (st_tex_reduce has brought the coordinate within two periods, and a
 * texel's neighbour is one off): a conditional add or subtract brings it
 * home without the integer division of `%`, which any other i takes. */
ST_FN st_i32 st_tex_mod(st_i32 i, st_i32 p)
{
    i = i < 0 ? i + p : i;
    i = i >= p ? i - p : i;
    if ((st_u32)i >= (st_u32)p) {
        i %= p;
        i = i < 0 ? i + p : i;
    }
    return i;
}

/* Texel index i of a lattice of n texels, wrapped into [0, n). */
ST_FN st_i32 st_tex_wrap(st_i32 i, st_i32 n, st_u32 mode)
{
    if (mode == ST_WRAP_CLAMP)
        return i < 0 ? 0 : i >= n ? n - 1 : i;
    if (mode == ST_WRAP_MIRROR) {
        st_i32 p = 2 * n;
        i = st_tex_mod(i, p);
        return i < n ? i : p - 1 - i;
    }
    return st_tex_mod(i, n);
}

/* A coordinate brought into one or two periods before it is scaled to
 * texels, so that the integer conversion cannot overflow: REPEAT to [0, 1),
 * MIRRORED_REPEAT to [0, 2), CLAMP_TO_EDGE to [-1, 2]. NaN and infinities
 * become 0. */
ST_FN st_f32 st_tex_reduce(st_f32 u, st_u32 mode)
{
    if (!(u > -1e30f && u < 1e30f))
        return 0.0f;
    if (mode == ST_WRAP_CLAMP)
        return u < -1.0f ? -1.0f : u > 2.0f ? 2.0f : u;
    if (mode == ST_WRAP_MIRROR)
        return u - 2.0f * st_tex_floor(0.5f * u);
    return u - st_tex_floor(u);
}

/* One texel of a level (first texel `base`, w texels a row) as linear RGBA. */
ST_FN void st_tex_texel(ST_GLOBAL const st_u32 *texels, st_u32 base, st_u32 w, st_i32 x,
                        st_i32 y, st_u32 srgb, st_f32 out[4])
{
    st_u32 t = texels[base + (st_u32)y * w + (st_u32)x];
    for (st_u32 c = 0; c < 3u; c++) {
        st_u32 b = (t >> (8u * c)) & 255u;
        out[c] = srgb ? st_srgb_to_linear(b) : (st_f32)b * (1.0f / 255.0f);
    }
    out[3] = (st_f32)(t >> 24) * (1.0f / 255.0f);
}

/* The level after the one of first texel *base and size *w x *h: each
 * level max(1, w/2) x max(1, h/2), stored right after the previous one. */
ST_FN void st_tex_next_level(st_u32 *base, st_u32 *w, st_u32 *h)
{
    *base += *w * *h;
    *w = *w > 1u ? *w / 2u : 1u;
    *h = *h > 1u ? *h / 2u : 1u;
}

/* First texel and size of level `level` (level 0 at tex->offset). */
ST_FN st_u32 st_tex_level(ST_GLOBAL const st_texture *tex, st_u32 level, st_u32 *w, st_u32 *h)
{
    st_u32 base = tex->offset;
    *w = tex->width;
    *h = tex->height;
    for (st_u32 l = 0; l < level; l++)
        st_tex_next_level(&base, w, h);
    return base;
}

/* Nearest texel of a level: the one whose cell holds (u, v). */
ST_FN void st_tex_nearest(ST_GLOBAL const st_texture *tex, ST_GLOBAL const st_u32 *texels,
                          st_u32 level, st_f32 u, st_f32 v, st_f32 out[4])
{
    st_u32 w, h;
    st_u32 base = st_tex_level(tex, level, &w, &h);
    st_i32 x = (st_i32)st_tex_floor(st_tex_reduce(u, tex->wrap_s) * (st_f32)w);
    st_i32 y = (st_i32)st_tex_floor(st_tex_reduce(v, tex->wrap_t) * (st_f32)h);
    x = st_tex_wrap(x, (st_i32)w, tex->wrap_s);
    y = st_tex_wrap(y, (st_i32)h, tex->wrap_t);
    st_tex_texel(texels, base, w, x, y, tex->flags & ST_TEX_SRGB, out);
}

/* Bilinear interpolation of the four texels around (u, v) in the level of
 * first texel `base` and size w x h, texel centres at (i + 1/2) / w. */
ST_FN void st_tex_bilinear_in(ST_GLOBAL const st_texture *tex, ST_GLOBAL const st_u32 *texels,
                              st_u32 base, st_u32 w, st_u32 h, st_f32 u, st_f32 v, st_f32 out[4])
{
    st_u32 srgb = tex->flags & ST_TEX_SRGB;
    st_f32 x = st_tex_reduce(u, tex->wrap_s) * (st_f32)w - 0.5f;
    st_f32 y = st_tex_reduce(v, tex->wrap_t) * (st_f32)h - 0.5f;
    st_f32 fx0 = st_tex_floor(x), fy0 = st_tex_floor(y);
    st_f32 fx = x - fx0, fy = y - fy0;
    st_i32 x0 = (st_i32)fx0, y0 = (st_i32)fy0;
    st_i32 xs[2], ys[2];
    xs[0] = st_tex_wrap(x0, (st_i32)w, tex->wrap_s);
    xs[1] = st_tex_wrap(x0 + 1, (st_i32)w, tex->wrap_s);
    ys[0] = st_tex_wrap(y0, (st_i32)h, tex->wrap_t);
    ys[1] = st_tex_wrap(y0 + 1, (st_i32)h, tex->wrap_t);
    for (st_u32 c = 0; c < 4u; c++)
        out[c] = 0.0f;
    for (st_u32 j = 0; j < 2u; j++)
        for (st_u32 i = 0; i < 2u; i++) {
            st_f32 t[4];
            st_f32 wgt = (i ? fx : 1.0f - fx) * (j ? fy : 1.0f - fy);
            st_tex_texel(texels, base, w, xs[i], ys[j], srgb, t);
            for (st_u32 c = 0; c < 4u; c++)
                out[c] += wgt * t[c];
        }
}

/* st_tex_bilinear_in on level `level`. */
ST_FN void st_tex_bilinear(ST_GLOBAL const st_texture *tex, ST_GLOBAL const st_u32 *texels,
                           st_u32 level, st_f32 u, st_f32 v, st_f32 out[4])
{
    st_u32 w, h, base = st_tex_level(tex, level, &w, &h);
    st_tex_bilinear_in(tex, texels, base, w, h, u, v, out);
}

/* The texture at (u, v) (before its transform) with level of detail lod,
 * filtered as `filter` (ST_TEXFILTER_*), into out[4] (linear RGBA). */
ST_FN void st_tex_sample(ST_GLOBAL const st_texture *tex, ST_GLOBAL const st_u32 *texels,
                         st_f32 u, st_f32 v, st_f32 lod, st_u32 filter, st_f32 out[4])
{
    st_f32 tu = tex->transform[0] * u + tex->transform[1] * v + tex->transform[2];
    st_f32 tv = tex->transform[3] * u + tex->transform[4] * v + tex->transform[5];
    if (filter == ST_TEXFILTER_NONE) {
        st_tex_nearest(tex, texels, 0u, tu, tv, out);
        return;
    }
    if (filter == ST_TEXFILTER_BILINEAR || !(lod > 0.0f)) { /* NaN: level 0 */
        if (filter == ST_TEXFILTER_TRILINEAR && (tex->flags & ST_TEX_MAG_NEAREST))
            st_tex_nearest(tex, texels, 0u, tu, tv, out);
        else
            st_tex_bilinear(tex, texels, 0u, tu, tv, out);
        return;
    }
    st_f32 top = (st_f32)(tex->levels - 1u);
    if (lod >= top) {
        st_tex_bilinear(tex, texels, tex->levels - 1u, tu, tv, out);
        return;
    }
    st_f32 l0 = st_tex_floor(lod), f = lod - l0;
    st_f32 hi[4];
    st_u32 w, h, base = st_tex_level(tex, (st_u32)l0, &w, &h);
    st_tex_bilinear_in(tex, texels, base, w, h, tu, tv, out);
    st_tex_next_level(&base, &w, &h); /* level l0 + 1, a step on from l0 */
    st_tex_bilinear_in(tex, texels, base, w, h, tu, tv, hi);
    for (st_u32 c = 0; c < 4u; c++)
        out[c] += f * (hi[c] - out[c]);
}

/* Ray-cone level of detail (eq. 34 above): tri_lod = st_tri_uv.lod, width =
 * the cone's width at the hit, cos_nd = n . d (either sign; clamped away from
 * 0, where a grazing hit would ask for an infinite level). */
ST_FN st_f32 st_tex_lod(st_f32 tri_lod, ST_GLOBAL const st_texture *tex, st_f32 width,
                        st_f32 cos_nd)
{
    st_f32 c = cos_nd < 0.0f ? -cos_nd : cos_nd;
    c = c > 1e-4f ? c : 1e-4f;
    st_f32 w = width > 1e-30f ? width : 1e-30f;
    return tri_lod + tex->lod_bias + ST_LOG2F(w / c);
}

#endif
