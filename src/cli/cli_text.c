/* cli_text.c — the text outputs of the laboratory commands (CSV tables)
 * and of the benchmarks (JSON). */
#include "cli_text.h"

#include <cjson/cJSON.h> /* Debian libcjson-dev */
#include <errno.h>
#include <string.h>

#include "st_outfile.h"

/* Writes through an st_outfile (a temporary and rename), or to stdout for "-". */
st_status st_cli_write_text(const char *path, void (*emit)(FILE *, const void *), const void *ctx,
                            st_error *err)
{
    if (!strcmp(path, "-")) {
        emit(stdout, ctx);
        errno = 0;
        if (fflush(stdout) == 0 && !ferror(stdout))
            return ST_OK;
        return st_fail(err, ST_ERR_IO, "stdout: write failed (%s)", strerror(errno ? errno : EIO));
    }
    st_outfile *out = NULL;
    if (st_outfile_open(path, &out, err) != ST_OK)
        return err ? err->status : ST_ERR_IO;
    emit(st_outfile_stream(out), ctx);
    return st_outfile_commit(out, err);
}

st_status st_cli_put_json(cJSON *root, st_error *err)
{
    char *text = root ? cJSON_PrintUnformatted(root) : NULL;
    cJSON_Delete(root);
    if (!text)
        return st_fail(err, ST_ERR_NOMEM, "bench: cannot build the JSON report");
    int bad = puts(text) == EOF || fflush(stdout) != 0;
    cJSON_free(text);
    return bad ? st_fail(err, ST_ERR_IO, "stdout: write failed") : ST_OK;
}
