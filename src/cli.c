/* cli.c — subcommand dispatch, error printing, progress bar, and the render,
 * devices and diff subcommands. */
#include "cli.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli_args.h"
#include "cli_run.h"
#include "st_device.h"
#include "st_diff.h"
#include "st_image.h"

int st_cli_fail(const st_error *err)
{
    fprintf(stderr, "strata: error: %s\n", err->msg[0] ? err->msg : st_status_text(err->status));
    return err->status == ST_ERR_USAGE ? ST_CLI_EXIT_USAGE : ST_CLI_EXIT_FAIL;
}

int st_cli_usage_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("strata: error: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return ST_CLI_EXIT_USAGE;
}

static const char main_help[] =
    "strata — an OpenCL renderer for sampling and reconstruction\n"
    "\n"
    "usage: strata COMMAND [options]   (strata COMMAND --help for each)\n"
    "  render [SCENE] -o OUT.exr|OUT.png   render a glTF scene (default: cornell-box)\n"
    "  bench [SCENE] [--json]              per-stage throughput of a render\n"
    "  pattern --sampler NAME --count N    sample points, scatter plot, spectrum, discrepancy\n"
    "  filter NAME [--csv F] [--png F]     a filter's profile and frequency response\n"
    "  signal [options]                    1-D sampling and reconstruction laboratory\n"
    "  merge PART.exr... -o OUT.exr        add split renders (--sample-range) into one image\n"
    "  converge [SCENE] --sampler LIST --spp-list LIST   error against spp, per sampler\n"
    "  diff A B [--max-rmse X]             compare two images (RMSE, PSNR, max difference)\n"
    "  devices                             list the OpenCL devices\n";

int st_cli_main(int argc, char **argv)
{
    if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        fputs(main_help, argc < 2 ? stderr : stdout);
        return argc < 2 ? ST_CLI_EXIT_USAGE : 0;
    }
    static const struct { const char *name; int (*run)(int, char **); } cmds[] = {
        {"render", st_cli_render}, {"bench", st_cli_bench},
        {"devices", st_cli_devices}, {"diff", st_cli_diff}, {"pattern", st_cli_pattern},
        {"filter", st_cli_filter}, {"merge", st_cli_merge},
        {"converge", st_cli_converge}, {"signal", st_cli_signal}};
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++)
        if (!strcmp(argv[1], cmds[i].name))
            return cmds[i].run(argc - 1, argv + 1);
    return st_cli_usage_error("unknown command '%s' (see strata --help)", argv[1]);
}

int st_cli_devices(int argc, char **argv)
{
    if (argc > 1 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        puts("usage: strata devices\n  lists every OpenCL device as P:D for --device");
        return 0;
    }
    if (argc > 1)
        return st_cli_usage_error("devices: unexpected argument %s", argv[1]);
    st_error err = {0};
    st_device_info *list;
    unsigned n;
    if (st_device_list(&list, &n, &err) != ST_OK)
        return st_cli_fail(&err);
    for (unsigned i = 0; i < n; i++) {
        const st_device_info *d = &list[i];
        printf("%u:%u  %-4s %s (%s) | %s | %u compute units, %.1f GiB | 64-bit atomics: %s\n",
               d->platform, d->device, d->is_gpu ? "gpu" : d->is_cpu ? "cpu" : "other", d->name,
               d->platform_name, d->c_version, d->compute_units,
               (double)d->global_mem / (1024.0 * 1024.0 * 1024.0),
               d->has_int64_atomics ? "yes" : "no");
    }
    if (n == 0)
        printf("no OpenCL devices (run `make deps`)\n");
    free(list);
    return 0;
}

int st_cli_diff(int argc, char **argv)
{
    const char *a = NULL, *b = NULL;
    double max_rmse = -1.0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            puts("usage: strata diff A B [--max-rmse X]\n"
                 "  prints RMSE, PSNR (peak 1) and the largest absolute difference over R, G, B;\n"
                 "  with --max-rmse, exits 1 when the RMSE is larger than X");
            return 0;
        }
        if (!strcmp(argv[i], "--max-rmse")) {
            float v;
            if (i + 1 >= argc)
                return st_cli_usage_error("diff: --max-rmse needs a value");
            if (st_cli_parse_float("--max-rmse", argv[++i], &v))
                return ST_CLI_EXIT_USAGE;
            max_rmse = v;
        } else if (argv[i][0] == '-' && argv[i][1] != '\0') {
            return st_cli_usage_error("diff: unknown option %s", argv[i]);
        } else if (!a) {
            a = argv[i];
        } else if (!b) {
            b = argv[i];
        } else {
            return st_cli_usage_error("diff: unexpected argument %s", argv[i]);
        }
    }
    if (!a || !b)
        return st_cli_usage_error("diff: needs two images (strata diff A B)");
    st_error err = {0};
    st_image ia = {0}, ib = {0};
    st_diff_result d;
    int rc = 0;
    if (st_image_load(a, &ia, &err) || st_image_load(b, &ib, &err) ||
        st_diff_images(&ia, &ib, &d, &err)) {
        rc = st_cli_fail(&err);
    } else {
        printf("rmse %.9g\npsnr %.4f dB\nmax_abs %.9g\n", d.rmse, d.psnr, d.max_abs);
        if (max_rmse >= 0.0 && d.rmse > max_rmse) {
            fprintf(stderr, "strata: diff: rmse %.9g is above --max-rmse %g\n", d.rmse, max_rmse);
            rc = 1;
        }
    }
    st_image_free(&ia);
    st_image_free(&ib);
    return rc;
}

/* Writes through a temporary name and rename(2), or to stdout for "-". */
st_status st_cli_write_text(const char *path, void (*emit)(FILE *, const void *), const void *ctx,
                            st_error *err)
{
    if (!strcmp(path, "-")) {
        emit(stdout, ctx);
        return fflush(stdout) == 0 ? ST_OK : st_fail(err, ST_ERR_IO, "stdout: write failed");
    }
    char tmp[4096];
    snprintf(tmp, sizeof tmp, "%s.tmp-strata", path);
    FILE *f = fopen(tmp, "w");
    if (!f)
        return st_fail(err, ST_ERR_IO, "%s: cannot create", path);
    emit(f, ctx);
    int bad = ferror(f);
    bad |= fclose(f) != 0;
    if (bad || rename(tmp, path) != 0) {
        remove(tmp);
        return st_fail(err, ST_ERR_IO, "%s: cannot write", path);
    }
    return ST_OK;
}

/* ---- progress ------------------------------------------------------------ */

void st_cli_progress(void *ctx, double fraction)
{
    st_cli_progress_state *p = ctx;
    if (!p->tty)
        return;
    int width = 40, fill = (int)(fraction * width + 0.5);
    fprintf(stderr, "\r%s [", p->label);
    for (int i = 0; i < width; i++)
        fputc(i < fill ? '#' : ' ', stderr);
    fprintf(stderr, "] %3.0f%%", fraction * 100.0);
    if (fraction >= 1.0)
        fputs("\r\033[K", stderr);
    fflush(stderr);
}

void st_cli_progress_init(st_cli_progress_state *p, const char *label, int quiet)
{
    p->label = label;
    p->tty = !quiet && isatty(fileno(stderr));
}
