/* layout.cl — reports the device's own sizes and offsets of every shared
 * struct and field (ST_LAYOUT_STRUCTS, ST_LAYOUT_FIELDS in st_shared.h), so
 * tests/device/test_layout.c can compare them with the host's. */
#include "st_shared.h"

/* Writes out[]: the size of each struct of ST_LAYOUT_STRUCTS, then the
 * offset of each field of ST_LAYOUT_FIELDS, in list order. */
__kernel void probe_layout(__global uint *out)
{
    uint k = 0;
#define ST_PROBE_SIZE(type) out[k++] = (uint)sizeof(type);
    ST_LAYOUT_STRUCTS(ST_PROBE_SIZE)
#define ST_PROBE_OFFSET(type, field)                                                        \
    {                                                                                       \
        type probe;                                                                         \
        out[k++] = (uint)((__private char *)&probe.field - (__private char *)&probe);       \
    }
    ST_LAYOUT_FIELDS(ST_PROBE_OFFSET)
}
