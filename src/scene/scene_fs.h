/* scene_fs.h — how the scene module reads a user's files (the scene file in
 * scene.c; buffers and images by URI in gltf_parse.cpp's tinygltf callbacks):
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

/* Reads the whole regular file at path into *data (malloc'd, the caller
 * frees) and its size into *size. Anything but a regular file (a device, a
 * FIFO, a socket) is refused without waiting on it (opened O_NONBLOCK, checked
 * with fstat), as is a file larger than `limit`, before any read. ST_ERR_IO
 * ("PATH: cannot open: ...", "PATH: not a regular file ..."), ST_ERR_FORMAT
 * ("PATH: N bytes, larger than N MiB, the limit for ..."), ST_ERR_NOMEM. what
 * names the limit ("a scene file"). */
st_status st_scene_fs_read(const char *path, size_t limit, const char *what, unsigned char **data,
                           size_t *size, st_error *err);

/* Reads standard input to its end into *data, within limit (a scene given as
 * "-": it has no folder, so it may use data: URIs only). */
st_status st_scene_fs_read_stdin(size_t limit, unsigned char **data, size_t *size, st_error *err);

/* The scene's folder base_dir ("" for the working folder) opened as a
 * descriptor for st_scene_fs_read_at; -1 with errno set. */
int st_scene_fs_open_dir(const char *base_dir);

/* Reads the file that the relative URI path `uri` names inside the folder
 * dir_fd, as st_scene_fs_read does: a regular file only, within limit. The
 * path is walked one name at a time with openat(2) and O_NOFOLLOW from the
 * folder's descriptor, so it cannot leave the folder (an absolute path, ".."
 * above it and every symbolic link are refused), and nothing is checked by
 * name and then opened by name again (no race with a link swapped in). Errors
 * start with the URI ("x.bin: cannot open: ...", "../a.bin: the URI leads
 * outside the scene's folder; refused"). */
st_status st_scene_fs_read_at(int dir_fd, const char *uri, size_t limit, const char *what,
                              unsigned char **data, size_t *size, st_error *err);

/* When path is a symbolic link: the file it leads to, resolved (realpath(3),
 * malloc'd); otherwise NULL. */
char *st_scene_fs_link_target(const char *path);

#ifdef __cplusplus
}
#endif

#endif
