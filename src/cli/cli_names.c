/* cli_names.c — unknown names and options, with suggestions (see cli_names.h). */
#include "cli_names.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_error.h"
#include "st_device.h"
#include "st_filter.h"
#include "st_names.h"
#include "st_render.h"
#include "st_sampling.h"
#include "st_scene.h"
#include "st_signal.h"
#include "st_tonemap.h"
#include "st_trace_bench.h"

const char *const st_cli_texfilter_names[3] = {"none", "bilinear", "trilinear"};

int st_cli_unknown_name(const char *opt, const char *value, const char *const *names, int count)
{
    char list[512];
    st_name_list(names, count, list, sizeof list);
    int k = st_name_nearest(names, count, value);
    if (k >= 0)
        return st_cli_usage_error("%s %s: unknown; did you mean %s? (one of: %s)", opt, value,
                                  names[k], list);
    return st_cli_usage_error("%s %s: unknown; expected one of %s", opt, value, list);
}

int st_cli_unknown_option(const char *cmd, const char *arg, const struct option *opts)
{
    const char *names[128];
    int n = 0;
    for (; opts[n].name && n < 128; n++)
        names[n] = opts[n].name;
    char word[64];
    snprintf(word, sizeof word, "%s", arg + strspn(arg, "-"));
    word[strcspn(word, "=")] = '\0';
    int k = arg[0] == '-' && arg[1] == '-' ? st_name_nearest(names, n, word) : -1;
    if (k >= 0)
        return st_cli_usage_error("%s: unknown option %s; did you mean --%s? (see strata %s "
                                  "--help)", cmd, arg, names[k], cmd);
    return st_cli_usage_error("%s: unknown option %s (see strata %s --help)", cmd, arg, cmd);
}

/* ---- the name tables, for the shell completion ------------------------------------------ */

static void print_names(const char *const *names, int count)
{
    for (int i = 0; i < count; i++)
        puts(names[i]);
}

/* Device specs: cpu, gpu and every P:D that `strata devices` lists (none
 * when no OpenCL platform answers: completion then offers cpu and gpu). */
static void print_devices(void)
{
    puts("cpu");
    puts("gpu");
    st_error err = {0};
    st_device_info *list;
    unsigned n;
    if (st_device_list(&list, &n, &err) != ST_OK)
        return;
    for (unsigned i = 0; i < n; i++)
        printf("%u:%u\n", list[i].platform, list[i].device);
    free(list);
}

int st_cli_print_names(const char *table)
{
    static const char *const on_none[2] = {"on", "none"};
    if (!table)
        table = "";
    if (!strcmp(table, "samplers")) {
        print_names(st_sampler_names, ST_SAMPLER_COUNT);
    } else if (!strcmp(table, "filters")) {
        print_names(st_filter_names, ST_FILTER_COUNT);
    } else if (!strcmp(table, "integrators")) {
        print_names(st_integrator_names, 2);
    } else if (!strcmp(table, "reconstructions")) {
        print_names(st_reconstruction_names, 2);
    } else if (!strcmp(table, "packets")) {
        print_names(st_packet_names, 4);
    } else if (!strcmp(table, "tonemaps")) {
        print_names(st_tonemap_names, ST_TONEMAP_COUNT);
    } else if (!strcmp(table, "texture-filters")) {
        print_names(st_cli_texfilter_names, 3);
    } else if (!strcmp(table, "rays")) {
        print_names(st_ray_set_names, ST_RAYS_COUNT);
    } else if (!strcmp(table, "functions")) {
        print_names(st_signal_function_names, ST_SIGNAL_FUNCTION_COUNT);
    } else if (!strcmp(table, "aovs")) {
        for (st_u32 k = 1; k < ST_AOV_COUNT; k++)
            puts(st_aov_layouts[k].name);
    } else if (!strcmp(table, "scramble")) {
        print_names(on_none, 2);
    } else if (!strcmp(table, "scenes")) {
        const char *names[64];
        st_u32 n = st_scene_builtin_names(names, 64);
        print_names(names, (int)n);
    } else if (!strcmp(table, "devices")) {
        print_devices();
    } else {
        return st_cli_usage_error("--names %s: unknown table; expected samplers, "
                                  "filters, integrators, reconstructions, packets, tonemaps, "
                                  "texture-filters, rays, functions, aovs, scramble, scenes or devices",
                                  table);
    }
    return 0;
}
