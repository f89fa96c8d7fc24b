/* cli_commands.h — the subcommands, one file each (cli_<name>.c), called by
 * cli.c's dispatch with argv[0] the subcommand's name; each returns its exit
 * status. No subcommand calls another: what several share lives in
 * cli_session.c, cli_progress.c, cli_args.c and cli_error.c. */
#ifndef ST_CLI_COMMANDS_H
#define ST_CLI_COMMANDS_H

int st_cli_render(int argc, char **argv);
int st_cli_bench(int argc, char **argv);
/* bench --rays: the trace benchmark (cli_bench_trace.c), a part of bench */
struct st_cli_render_args;
int st_cli_bench_trace(struct st_cli_render_args *a);
int st_cli_devices(int argc, char **argv);
int st_cli_diff(int argc, char **argv);
int st_cli_pattern(int argc, char **argv);
int st_cli_signal(int argc, char **argv);
int st_cli_filter(int argc, char **argv);
int st_cli_merge(int argc, char **argv);
int st_cli_converge(int argc, char **argv);
int st_cli_compare(int argc, char **argv);

#endif
