/* cli_error.h — how the command line ends: the exit statuses and the one
 * "strata: error: ..." line. Every CLI file uses these; they use nothing of
 * the CLI, so the CLI's files depend on each other in one direction only
 * (dispatch → subcommands → session, arguments → these). */
#ifndef ST_CLI_ERROR_H
#define ST_CLI_ERROR_H

#include "st_error.h"
#include "st_outfile.h"

/* Exit statuses (DESIGN.md: 2 for a usage error, 1 for any other failure);
 * ST_CLI_HELP is no exit status: a parser's "help printed, exit 0". */
enum { ST_CLI_OK = 0, ST_CLI_EXIT_FAIL = 1, ST_CLI_EXIT_USAGE = 2, ST_CLI_HELP = 3 };

/* Prints prefix and msg as one line on stderr, every control character of
 * msg (which may quote a scene's names or a parser's words: ESC, BEL, a
 * newline that would forge a second "strata: error:" line) shown as \xNN. */
void st_cli_put_line(const char *prefix, const char *msg);

/* Prints "strata: error: MSG" (escaped as st_cli_put_line) and returns the
 * exit status for err. */
int st_cli_fail(const st_error *err);

/* Prints a usage error, escaped as st_cli_put_line (it quotes option values and arguments), and
 * returns ST_CLI_EXIT_USAGE. */
int st_cli_usage_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* A command's files checked apart (st_outfile_check_apart: files[0..nout) are outputs, the rest
 * inputs): ST_CLI_OK, or the error printed and ST_CLI_EXIT_USAGE when an output is also another
 * of its files. */
int st_cli_check_apart(const st_outfile_role *files, int n, int nout);

/* Every catchable signal that would end the process (SIGHUP, SIGINT, SIGQUIT,
 * SIGTERM, SIGALRM, SIGUSR1, SIGUSR2, SIGVTALRM, SIGXCPU) removes every
 * temporary output file of the process (st_outfile_remove_temporaries) and
 * exits 128 + its number (SIGINT 130, SIGTERM 143). SIGPIPE and SIGXFSZ are
 * ignored: the write fails instead and the command exits 1. */
void st_cli_catch_interrupts(void);

#endif
