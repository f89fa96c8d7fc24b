/* cli_names.c — unknown names and options, with suggestions (see cli_names.h). */
#include "cli_names.h"

#include <stdio.h>
#include <string.h>

#include "cli_error.h"
#include "st_names.h"

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
