/* cli.h — the command line, the only module that prints or exits (exit 2:
 * usage, 1: failure). Its files form one layered graph: main.c → cli.c
 * (dispatch) → cli_<subcommand>.c (cli_commands.h) → cli_session.c,
 * cli_progress.c, cli_args.c, cli_text.c → cli_error.c → the library. */
#ifndef ST_CLI_H
#define ST_CLI_H

/* Runs `strata COMMAND ...`; returns the process's exit status. */
int st_cli_main(int argc, char **argv);

#endif
