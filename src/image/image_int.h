/* image_int.h — what the image module's files share and the public header does not promise:
 * the check every save function makes of a caller's image. */
#ifndef ST_IMAGE_INT_H
#define ST_IMAGE_INT_H

#include "st_image.h"

/* An image handed to a save function: sizes, names and types as st_image_create makes them,
 * and a buffer for each channel's type. ST_ERR_USAGE naming path otherwise. */
st_status st_image_check(const char *path, const st_image *img, st_error *err);

#endif
