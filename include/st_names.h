/* st_names.h — looking a name up in a table of names (samplers, filters,
 * integrators, ...): the one definition every module's lookup uses. */
#ifndef ST_NAMES_H
#define ST_NAMES_H

#include <stddef.h>

/* The index of name in names[0 .. count), or -1. Case-insensitive ("Halton"
 * is halton). */
int st_name_lookup(const char *const *names, int count, const char *name);

/* For a name that is not in the table: the index of the entry it was most
 * likely meant as, or -1 when none is close. Close: the name (3 bytes or
 * more) begins the entry, or the entry is at most max(2, length/3) edits
 * (Levenshtein, ignoring case) away and fewer than the name's length. NULL
 * entries are skipped. */
int st_name_nearest(const char *const *names, int count, const char *name);

/* "a, b, c" into buf (truncated to size). */
void st_name_list(const char *const *names, int count, char *buf, size_t size);

#endif
