/* st_version.h — strata's version: `git describe` of the build's checkout,
 * or the Makefile's fallback outside git (build/.../version.c is generated). */
#ifndef ST_VERSION_H
#define ST_VERSION_H

extern const char st_version[];

#endif
