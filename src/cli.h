/* cli.h — the command line, the only module that prints or exits (exit 2:
 * usage, 1: failure). Its files form one layered graph: main.c → cli.c
 * (dispatch) → cli_<subcommand>.c (cli_commands.h) → cli_session.c,
 * cli_progress.c, cli_args.c → cli_error.c → the library. */
#ifndef ST_CLI_H
#define ST_CLI_H

/* Runs `strata COMMAND ...`; returns the process's exit status. */
int st_cli_main(int argc, char **argv);

/* Writes a text file through emit(f, ctx) into an st_outfile (a temporary in
 * the same folder, then rename(2)), so no partial file is left; "-" is stdout.
 * Errors: ST_ERR_IO naming path. */
#include <stdio.h>
#include "st_error.h"
st_status st_cli_write_text(const char *path, void (*emit)(FILE *, const void *), const void *ctx,
                            st_error *err);

#endif
