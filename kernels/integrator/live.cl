/* live.cl — the list of the paths still alive, made between two vertices so
 * that the next vertex's trace and shade run over those paths alone: their
 * lanes all busy, no work-item spent on a path that has ended.
 *
 * shade_hits leaves one word per work-item, live_bits[g], bit k set where the
 * path at position ST_W g + k goes on. live_count adds up the bits of each
 * chunk of words, live_scan turns the chunks' counts into their first
 * positions (and the total, live_total), and live_scatter writes each chunk's
 * paths into the next vertex's list from there. The list keeps the
 * item order, so it is the same at every lane width and wave size, and each
 * path's numbers do not depend on it (a lane's arithmetic is its own). */
#include "st_shared.h"

/* The words of live_bits that shade_hits wrote at p's vertex. */
static st_u32 live_words(const st_params *p)
{
    return (st_live_count(p) + ST_W - 1u) / ST_W;
}

/* Work-item c: the live paths of chunk c, into live_sum[c]. */
__kernel void live_count(ST_STAGE_PARAMS)
{
    st_u32 c = ST_ITEM(), words = live_words(&p), sum = 0u;
    if (c * ST_LIVE_CHUNK >= words)
        return;
    st_u32 end = min(words, (c + 1u) * ST_LIVE_CHUNK);
    for (st_u32 w = c * ST_LIVE_CHUNK; w < end; w++)
        sum += popcount(live_bits[w]);
    live_sum[c] = sum;
}

/* One work-item: each chunk's count becomes its first position in the next
 * list; live_total[0] the list's length. */
__kernel void live_scan(ST_STAGE_PARAMS)
{
    if (ST_ITEM() != 0)
        return;
    st_u32 chunks = (live_words(&p) + ST_LIVE_CHUNK - 1u) / ST_LIVE_CHUNK, sum = 0u;
    for (st_u32 c = 0; c < chunks; c++) {
        st_u32 n = live_sum[c];
        live_sum[c] = sum;
        sum += n;
    }
    live_total[0] = sum;
}

/* Work-item c: the paths of chunk c that go on, into the next vertex's list
 * from the chunk's first position on, in order. */
__kernel void live_scatter(ST_STAGE_PARAMS)
{
    st_u32 c = ST_ITEM(), words = live_words(&p);
    if (c * ST_LIVE_CHUNK >= words)
        return;
    st_u32 end = min(words, (c + 1u) * ST_LIVE_CHUNK), at = live_sum[c];
    __global const st_u32 *list = st_live_list(&p, live_a, live_b);
    __global st_u32 *next = (p.vertex & 1u) ? live_b : live_a; /* vertex + 1's */
    for (st_u32 w = c * ST_LIVE_CHUNK; w < end; w++)
        for (st_u32 k = 0, bits = live_bits[w]; bits != 0u; k++, bits >>= 1)
            if (bits & 1u)
                next[at++] = st_live_item(list, ST_W * w + k);
}
