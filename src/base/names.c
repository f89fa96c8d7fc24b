/* names.c — name tables (see st_names.h). */
#include "st_names.h"

#include <ctype.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

int st_name_lookup(const char *const *names, int count, const char *name)
{
    for (int i = 0; i < count; i++)
        if (!strcasecmp(names[i], name))
            return i;
    return -1;
}

/* Levenshtein distance, ignoring case, of strings up to 63 bytes (longer ones: 64). */
static int edit_distance(const char *a, const char *b)
{
    size_t n = strlen(a), m = strlen(b);
    if (n > 63 || m > 63)
        return 64;
    int row[64];
    for (size_t j = 0; j <= m; j++)
        row[j] = (int)j;
    for (size_t i = 1; i <= n; i++) {
        int diag = row[0];
        row[0] = (int)i;
        for (size_t j = 1; j <= m; j++) {
            int up = row[j];
            int same = tolower((unsigned char)a[i - 1]) == tolower((unsigned char)b[j - 1]);
            int best = diag + !same;
            if (row[j] + 1 < best)
                best = row[j] + 1;
            if (row[j - 1] + 1 < best)
                best = row[j - 1] + 1;
            row[j] = best;
            diag = up;
        }
    }
    return row[m];
}

int st_name_nearest(const char *const *names, int count, const char *name)
{
    int best = -1, best_d = 0, len = (int)strlen(name);
    for (int i = 0; i < count; i++) {
        if (!names[i])
            continue;
        if (len >= 3 && !strncasecmp(names[i], name, (size_t)len))
            return i; /* a prefix: "best" for best-candidate */
        int d = edit_distance(names[i], name);
        if (best < 0 || d < best_d)
            best = i, best_d = d;
    }
    int limit = len / 3 > 2 ? len / 3 : 2;
    return best >= 0 && best_d <= limit && best_d < len ? best : -1;
}

void st_name_list(const char *const *names, int count, char *buf, size_t size)
{
    if (size)
        buf[0] = '\0';
    for (int i = 0; i < count && size; i++) {
        size_t used = strlen(buf);
        snprintf(buf + used, size - used, "%s%s", i ? ", " : "", names[i]);
    }
}
