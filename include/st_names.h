/* st_names.h — looking a name up in a table of names (samplers, filters,
 * integrators, ...): the one definition every module's lookup uses. */
#ifndef ST_NAMES_H
#define ST_NAMES_H

/* The index of name in names[0 .. count), or -1. Exact, case-sensitive. */
int st_name_lookup(const char *const *names, int count, const char *name);

#endif
