/* cli_devices.c — `strata devices`: every OpenCL device as the P:D that
 * --device takes, with what a render needs of it (OpenCL C version, 64-bit
 * atomics for the film) and the lane width --lanes auto takes there, with
 * how it was chosen. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_commands.h"
#include "cli_error.h"
#include "st_device.h"
#include "st_render.h"

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
        st_lanes_choice c;
        char lanes[1400];
        if (st_render_lanes_recall(d, &c, &err) != ST_OK)
            return st_cli_fail(&err);
        printf("%u:%u  %-4s %s (%s) | %s | %u compute units, %.1f GiB | 64-bit atomics: %s | "
               "lanes %s\n",
               d->platform, d->device, d->is_gpu ? "gpu" : d->is_cpu ? "cpu" : "other", d->name,
               d->platform_name, d->c_version, d->compute_units,
               (double)d->global_mem / (1024.0 * 1024.0 * 1024.0),
               d->has_int64_atomics ? "yes" : "no",
               st_render_lanes_describe(&c, lanes, sizeof lanes));
    }
    free(list);
    return 0;
}
