/* cli.h — the command line: subcommands, option parsing, progress and exit
 * codes. The only module that prints or exits (exit 2: usage, 1: failure). */
#ifndef ST_CLI_H
#define ST_CLI_H

int st_cli_main(int argc, char **argv);

/* Subcommands, each in its own file (cli_*.c). */
int st_cli_render(int argc, char **argv);
int st_cli_bench(int argc, char **argv);
int st_cli_devices(int argc, char **argv);
int st_cli_diff(int argc, char **argv);
int st_cli_pattern(int argc, char **argv);
int st_cli_signal(int argc, char **argv);
int st_cli_filter(int argc, char **argv);
int st_cli_merge(int argc, char **argv);
int st_cli_converge(int argc, char **argv);

/* Prints "strata: error: MSG" and returns the exit status for err. */
struct st_error;
int st_cli_fail(const struct st_error *err);
/* Writes a text file through emit(f, ctx): to a temporary name in the same
 * folder, then rename(2), so no partial file is left; "-" is stdout. */
#include <stdio.h>
#include "st_error.h"
st_status st_cli_write_text(const char *path, void (*emit)(FILE *, const void *), const void *ctx,
                            st_error *err);

/* Prints a usage error and returns 2. */
int st_cli_usage_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

#endif
