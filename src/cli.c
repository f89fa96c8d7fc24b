/* cli.c — the command line's entry: subcommand dispatch (each subcommand is
 * its own file, cli_<name>.c). */
#include "cli.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "cli_commands.h"
#include "cli_error.h"
#include "st_names.h"
#include "st_version.h"

static const char main_help[] =
    "strata — an OpenCL renderer for sampling and reconstruction\n"
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
    "  --version                           print the version\n";

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

int st_cli_main(int argc, char **argv)
{
    st_cli_catch_interrupts();
    if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        fputs(main_help, argc < 2 ? stderr : stdout);
        return argc < 2 ? ST_CLI_EXIT_USAGE : 0;
    }
    if (!strcmp(argv[1], "--version")) {
        printf("strata %s\n", st_version);
        return 0;
    }
    static const struct { const char *name; int (*run)(int, char **); } cmds[] = {
        {"render", st_cli_render}, {"bench", st_cli_bench},
        {"devices", st_cli_devices}, {"diff", st_cli_diff}, {"pattern", st_cli_pattern},
        {"filter", st_cli_filter}, {"merge", st_cli_merge},
        {"converge", st_cli_converge}, {"signal", st_cli_signal}, {"compare", st_cli_compare}};
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++)
        if (!strcmp(argv[1], cmds[i].name))
            return check_stdout(cmds[i].run(argc - 1, argv + 1));
    const char *names[sizeof cmds / sizeof cmds[0]];
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++)
        names[i] = cmds[i].name;
    int k = st_name_nearest(names, (int)(sizeof names / sizeof names[0]), argv[1]);
    if (k >= 0)
        return st_cli_usage_error("unknown command '%s'; did you mean %s? (see strata --help)",
                                  argv[1], names[k]);
    return st_cli_usage_error("unknown command '%s' (see strata --help)", argv[1]);
}
