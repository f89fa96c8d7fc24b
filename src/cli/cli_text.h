/* cli_text.h — the text writer of the CSV outputs (pattern, filter,
 * signal, converge) and of the bench JSON reports. */
#ifndef ST_CLI_TEXT_H
#define ST_CLI_TEXT_H

#include <stdio.h>

#include "st_error.h"

/* Writes a text file through emit(f, ctx) into an st_outfile (a temporary in
 * the same folder, then rename(2)), so no partial file is left; "-" is stdout.
 * Errors: ST_ERR_IO naming path. */
st_status st_cli_write_text(const char *path, void (*emit)(FILE *, const void *), const void *ctx,
                            st_error *err);

/* Prints a JSON report (root, from cJSON; NULL when building it failed) as
 * one line on stdout and deletes it. Errors: ST_ERR_NOMEM when root is NULL
 * or cannot be printed, ST_ERR_IO when stdout cannot be written. */
struct cJSON;
st_status st_cli_put_json(struct cJSON *root, st_error *err);

#endif
