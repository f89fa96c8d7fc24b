/* image_file.c — the choice of file format by extension: the one file of the
 * image module that names both formats, above image_exr.c and image_png.c
 * (which build their images with image.c's container). */
#include "st_image.h"

#include <string.h>
#include <strings.h>

/* The extension of the last path component, including the dot ("" when there is none). */
static const char *extension_of(const char *path)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    const char *dot = strrchr(base, '.');
    return dot ? dot : "";
}

st_status st_image_save(const char *path, const st_image *img, const st_attr *attrs, int nattrs,
                        st_error *err)
{
    const char *ext = extension_of(path);
    if (strcasecmp(ext, ".exr") == 0)
        return st_image_save_exr(path, img, attrs, nattrs, err);
    if (strcasecmp(ext, ".png") == 0 || strcmp(path, "-") == 0)
        return st_image_save_png_text(path, img, attrs, nattrs, err);
    return st_fail(err, ST_ERR_USAGE, "%s: unsupported image extension '%s' (use .exr or .png)",
                   path, ext);
}

st_status st_image_load(const char *path, st_image *img, st_error *err)
{
    const char *ext = extension_of(path);
    if (strcasecmp(ext, ".exr") == 0)
        return st_image_load_exr(path, img, NULL, NULL, err);
    if (strcasecmp(ext, ".png") == 0)
        return st_image_load_png(path, img, err);
    memset(img, 0, sizeof *img);
    return st_fail(err, ST_ERR_USAGE, "%s: unsupported image extension '%s' (use .exr or .png)",
                   path, ext);
}
