/* lanes_probe.cl — lanes.h's mask helpers as the device's compiler makes
 * them (movmskps on x86, the or-reduction elsewhere) beside the portable
 * or-reduction, for tests/device/test_lanes.c. Not a stage of the renderer. */
#include "st_shared.h"

/* Work-item b (< 2^16): the mask of 16 lanes whose lane j is set where bit
 * j of b is, built lane by lane (not by ST_BITS_MASK). Writes out[10 b ..
 * 10 b + 9]: ST_MASK_BITS of its first 4, 8 and 16 lanes, the portable
 * st_mask_bits_or<n> of the same, ST_ANY of each, and whether the compiler's
 * form is movmskps (1) or the portable one (0). */
__kernel void probe_mask_bits(__global uint *out)
{
    uint b = ST_ITEM();
    int lane[16];
    for (int j = 0; j < 16; j++)
        lane[j] = (b >> j) & 1u ? -1 : 0;
    ST_VEC(int, 4) m4 = ST_VLOAD(4, lane);
    ST_VEC(int, 8) m8 = ST_VLOAD(8, lane);
    ST_VEC(int, 16) m16 = ST_VLOAD(16, lane);
    __global uint *o = out + 10 * b;
    o[0] = ST_MASK_BITS(4, m4);
    o[1] = ST_MASK_BITS(8, m8);
    o[2] = ST_MASK_BITS(16, m16);
    o[3] = st_mask_bits_or4(m4);
    o[4] = st_mask_bits_or8(m8);
    o[5] = st_mask_bits_or16(m16);
    o[6] = ST_ANY(4, m4) ? 1u : 0u;
    o[7] = ST_ANY(8, m8) ? 1u : 0u;
    o[8] = ST_ANY(16, m16) ? 1u : 0u;
#ifdef ST_MOVMSK
    o[9] = 1u;
#else
    o[9] = 0u;
#endif
}
