/* cli_names.h — the usage errors for a name or an option the command line
 * does not know, with a "did you mean" when one is close (st_names.h). */
#ifndef ST_CLI_NAMES_H
#define ST_CLI_NAMES_H

#include <getopt.h>

/* "OPT VALUE: unknown; did you mean NAME? (one of: ...)", or without a close
 * name "OPT VALUE: unknown; expected one of ..."; returns ST_CLI_EXIT_USAGE. */
int st_cli_unknown_name(const char *opt, const char *value, const char *const *names, int count);

/* "CMD: unknown option ARG; did you mean --NAME? (see strata CMD --help)",
 * the suggestion only when one of opts is close (ARG's "=value" ignored);
 * returns ST_CLI_EXIT_USAGE. */
int st_cli_unknown_option(const char *cmd, const char *arg, const struct option *opts);

/* Prints one of the name tables the options read (samplers, filters,
 * ..., scenes, devices), one name a line, for the shell completion
 * (tools/strata.bash-completion), so the completion offers what the parsers
 * accept. Returns 0, or ST_CLI_EXIT_USAGE for an unknown table. */
int st_cli_print_names(const char *table);

/* --texture-filter's names, by ST_TEXFILTER_* (also for the shell completion). */
extern const char *const st_cli_texfilter_names[3];

#endif
