/* scene_fs.h — how the scene module reads a user's files (the scene file in
 * scene.c; buffers and images by URI in gltf_shim.cpp's tinygltf callbacks):
 * with a size cap, and, for URIs, only inside the scene's own folder.
 *
 * A scene is input from anywhere (a download, a mail): a URI must not reach
 * another file ("../../../etc/passwd", an absolute path, a symbolic link out
 * of the folder), and no file may take memory without bound (/dev/zero, a
 * sparse terabyte). The caps are stated in the README. Plain C, callable from
 * the shim. Tests: test_hostile.sh (confinement, caps). */
#ifndef ST_SCENE_FS_H
#define ST_SCENE_FS_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#include "st_error.h"

/* The most bytes of one file: the scene file, or a buffer or image it names. */
#define ST_SCENE_MAX_FILE_BYTES ((size_t)512 << 20)
/* The most characters of one data: URI inside a scene's JSON (tinygltf keeps
 * the text, a decoded copy and its parse tree: about 5x this in memory). */
#define ST_SCENE_MAX_DATA_URI_BYTES ((size_t)64 << 20)

/* Reads the whole file at path into *data (malloc'd, the caller frees) and its
 * size into *size. A regular file larger than `limit` is refused before any
 * read; anything else (a pipe, a device) is read up to limit + 1 bytes and
 * refused there. ST_ERR_IO ("PATH: cannot open: ..."), ST_ERR_FORMAT ("PATH:
 * larger than N MiB, the limit for ..."), ST_ERR_NOMEM. what names the limit
 * ("a scene file"). */
st_status st_scene_fs_read(const char *path, size_t limit, const char *what, unsigned char **data,
                           size_t *size, st_error *err);

/* 1 when path resolves (realpath(3): "..", "." and every symbolic link
 * followed) to a file inside the folder base_dir ("" for the working folder);
 * 0 when it lies outside or cannot be resolved. */
int st_scene_fs_is_inside(const char *base_dir, const char *path);

#ifdef __cplusplus
}
#endif

#endif
