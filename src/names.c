/* names.c — name tables (see st_names.h). */
#include "st_names.h"

#include <string.h>

int st_name_lookup(const char *const *names, int count, const char *name)
{
    for (int i = 0; i < count; i++)
        if (!strcmp(names[i], name))
            return i;
    return -1;
}
