/* cli.c — the command line's entry: subcommand dispatch (each subcommand is
 * its own file, cli_<name>.c). */
#include "cli.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "cli_commands.h"
#include "cli_error.h"
#include "cli_names.h"
#include "st_names.h"
#include "st_version.h"

static const char main_help[] =
    "strata: an OpenCL renderer for sampling and reconstruction\n"
    "\n"
    "usage: strata COMMAND [options]   (strata COMMAND --help for each)\n"
    "  render [SCENE] -o OUT.exr|OUT.png   render a glTF scene (default: cornell-box)\n"
    "  bench [SCENE] [--json]              per-stage throughput of a render\n"
    "  bench [SCENE] --rays camera|random   trace rays alone: rays/s, hit fraction, BVH build\n"
    "  pattern --sampler NAME --count N    sample points, scatter plot, spectrum, discrepancy\n"
    "  filter NAME [--csv F] [--png F]     a filter's profile and frequency response\n"
    "  signal [options]                    1-D sampling and reconstruction laboratory\n"
    "  merge PART.exr... -o OUT.exr        add split renders (--sample-range) into one image\n"
    "  converge [SCENE] --sampler LIST --spp-list LIST   error against spp, per sampler\n"
    "  diff A B [--max-rmse X]             compare two images (RMSE, PSNR, max difference)\n"
    "  compare [SCENE] --sampler LIST -o SHEET   renders side by side with their RMSE\n"
    "  devices                             list the OpenCL devices\n"
    "  help [COMMAND]                      this overview, or COMMAND's options\n"
    "  --version                           print the version\n"
    "every command takes -q (--quiet): no progress and no summary\n";

/* Everything a command printed must have reached stdout: a summary, a device
 * list or a diff written to a full disk or a closed pipe is a failure (exit 1),
 * not a success with lost output. */
static int check_stdout(int rc)
{
    errno = 0;
    if ((fflush(stdout) == 0 && !ferror(stdout)) || rc != 0)
        return rc; /* a failed command has said why already: one error line */
    int e = errno ? errno : EIO;
    fprintf(stderr, "strata: error: stdout: write failed (%s)\n", strerror(e));
    return rc ? rc : ST_CLI_EXIT_FAIL;
}

/* The commands, in the order of the help text (`strata --names commands`
 * prints them for the shell completion); quiet: the command's own parser
 * reads -q, else drop_quiet takes it away. */
static const struct { const char *name; int (*run)(int, char **); int quiet; } cmds[] = {
    {"render", st_cli_render, 1}, {"bench", st_cli_bench, 1},
    {"pattern", st_cli_pattern, 0}, {"filter", st_cli_filter, 0},
    {"signal", st_cli_signal, 0}, {"merge", st_cli_merge, 0},
    {"converge", st_cli_converge, 1}, {"diff", st_cli_diff, 0},
    {"compare", st_cli_compare, 1}, {"devices", st_cli_devices, 0}};
enum { NCMDS = sizeof cmds / sizeof cmds[0] };

/* `strata --names TABLE`: the names the parsers accept, for the shell
 * completion; the commands from this file's table, the rest from
 * cli_names.c. */
static int names(const char *table)
{
    if (!table || strcmp(table, "commands"))
        return st_cli_print_names(table);
    for (int i = 0; i < NCMDS; i++)
        puts(cmds[i].name);
    puts("help");
    return 0;
}

/* An option's name as written, without an attached value ("--seed=1" is
 * "--seed"), with --output spelt as -o; NULL for what is no option (a
 * value, a file, a negative number). */
static const char *option_name(const char *arg, char *buf, size_t size)
{
    if (!strcmp(arg, "-o") || !strcmp(arg, "--output") || !strncmp(arg, "--output=", 9))
        return "-o";
    if (!strcmp(arg, "-q"))
        return "--quiet";
    if (strncmp(arg, "--", 2) || !arg[2])
        return NULL;
    size_t n = strcspn(arg, "=");
    if (n >= size)
        n = size - 1;
    memcpy(buf, arg, n);
    buf[n] = '\0';
    return buf;
}

/* Whether an option may be given more than once: -o where a command writes
 * one result to several files (render, merge), and the switches -q and
 * --help, whose repeats mean the same. Any other option takes one value,
 * and a second one would silently override the first. */
static int may_repeat(const char *cmd, const char *opt)
{
    if (!strcmp(opt, "-o"))
        return !strcmp(cmd, "render") || !strcmp(cmd, "merge");
    return !strcmp(opt, "--quiet") || !strcmp(opt, "--help");
}

/* A usage error when an option other than those of may_repeat is given
 * twice. Options are read as the tokens that start with "--" (and -o, -q),
 * so a value that happens to start with "--" would count as an option:
 * no option of strata takes such a value. */
static int check_repeats(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        char a[64], b[64];
        const char *oi = option_name(argv[i], a, sizeof a);
        if (!oi || may_repeat(argv[0], oi))
            continue;
        for (int j = 1; j < i; j++) {
            const char *oj = option_name(argv[j], b, sizeof b);
            if (oj && !strcmp(oi, oj))
                return st_cli_usage_error("%s: %s given twice (give it once: a second "
                                          "value would silently replace the first)", argv[0], oi);
        }
    }
    return ST_CLI_OK;
}

/* -q and --quiet for a command that prints no progress or summary (its
 * output is what was asked for): accepted, so every command takes -q, and
 * removed before the command's own parser sees them. Returns the new argc. */
static int drop_quiet(int argc, char **argv)
{
    int n = 0;
    for (int i = 0; i < argc; i++)
        if (i == 0 || (strcmp(argv[i], "-q") && strcmp(argv[i], "--quiet")))
            argv[n++] = argv[i];
    argv[n] = NULL;
    return n;
}

static int unknown_command(const char *what, const char *name)
{
    const char *names[NCMDS];
    for (int i = 0; i < NCMDS; i++)
        names[i] = cmds[i].name;
    int k = st_name_nearest(names, NCMDS, name);
    if (k >= 0)
        return st_cli_usage_error("%s '%s'; did you mean %s? (see strata help)", what, name,
                                  names[k]);
    return st_cli_usage_error("%s '%s' (see strata help)", what, name);
}

/* `strata help [COMMAND]`: the overview, or COMMAND's --help. */
static int help(int argc, char **argv)
{
    if (argc < 2) {
        fputs(main_help, stdout);
        return 0;
    }
    if (argc > 2)
        return st_cli_usage_error("help: one topic at a time (strata help COMMAND)");
    for (int i = 0; i < NCMDS; i++)
        if (!strcmp(argv[1], cmds[i].name)) {
            char *args[] = {argv[1], "--help", NULL};
            return cmds[i].run(2, args);
        }
    return unknown_command("help: unknown topic", argv[1]);
}

int st_cli_main(int argc, char **argv)
{
    st_cli_catch_interrupts();
    if (argc < 2) {
        fputs(main_help, stderr);
        return ST_CLI_EXIT_USAGE;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        fputs(main_help, stdout);
        return check_stdout(0);
    }
    if (!strcmp(argv[1], "--version")) {
        printf("strata %s\n", st_version);
        return check_stdout(0);
    }
    if (!strcmp(argv[1], "--names")) /* for the shell completion, undocumented in --help */
        return check_stdout(names(argc > 2 ? argv[2] : NULL));
    if (!strcmp(argv[1], "help"))
        return check_stdout(help(argc - 1, argv + 1));
    for (int i = 0; i < NCMDS; i++) {
        if (strcmp(argv[1], cmds[i].name))
            continue;
        int n = argc - 1;
        if (check_repeats(n, argv + 1))
            return ST_CLI_EXIT_USAGE;
        if (!cmds[i].quiet)
            n = drop_quiet(n, argv + 1);
        return check_stdout(cmds[i].run(n, argv + 1));
    }
    return unknown_command("unknown command", argv[1]);
}
