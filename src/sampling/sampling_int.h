/* sampling_int.h — helpers shared inside the sampling module by the two tile
 * generators (poisson_disk.c, best_candidate.c); not part of st_sampling.h.
 * Both draw from one splitmix64 stream per call, so a (count, seed) pair
 * always gives the same tile. */
#ifndef ST_SAMPLING_INT_H
#define ST_SAMPLING_INT_H

#include "st_sampling.h"

/* splitmix64 (Steele, Lea, Flood, "Fast Splittable Pseudorandom Number
 * Generators", OOPSLA 2014; constants as in Vigna's splitmix64.c). */
static inline st_u64 splitmix64(st_u64 *state)
{
    st_u64 z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* i mod g for i a few cells outside [0, g) (no division: this is hot). */
static inline st_u32 wrap_index(st_i64 i, st_u32 g)
{
    while (i < 0)
        i += g;
    while (i >= (st_i64)g)
        i -= g;
    return (st_u32)i;
}

/* The point-count limits both generators state in st_sampling.h. */
static inline st_status check_count(st_u32 count, st_u32 max, const char *what, st_error *err)
{
    if (count == 0)
        return st_fail(err, ST_ERR_USAGE, "%s: point count must be at least 1", what);
    if (count > max)
        return st_fail(err, ST_ERR_USAGE, "%s: point count %u exceeds the limit %u", what,
                       count, max);
    return ST_OK;
}

#endif
