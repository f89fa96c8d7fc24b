/* test_lanes.c — lanes.h's masks on the device (kernels/shared/lanes_probe.cl):
 * for every mask of 16 lanes, ST_MASK_BITS and ST_ANY at 4, 8 and 16 lanes in
 * the form the device's compiler gets (one movmskps on x86 CPUs) and the
 * portable or-reduction each give the bits the mask was made from. The
 * traversal and the shading read masks through them at every step, so a
 * lane out of place here would move hits and images. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <cmocka.h>

#include "device_fixture.h"

#define MASKS 65536u /* every mask of 16 lanes */
#define OUTS 10u     /* lanes_probe.cl's words per mask */

static void mask_bits_are_the_lanes_bits(void **state)
{
    (void)state;
    st_error err = {0};
    cl_kernel k;
    cl_mem b;
    size_t bytes = (size_t)MASKS * OUTS * sizeof(uint32_t);
    uint32_t *got = malloc(bytes);
    assert_non_null(got);
    assert_int_equal(st_device_kernel(dev, "probe_mask_bits", &k, &err), ST_OK);
    assert_int_equal(st_device_buffer_create(dev, bytes, NULL, &b, &err), ST_OK);
    assert_int_equal(st_device_set_args(k, &err, 1, sizeof(cl_mem), (const void *)&b), ST_OK);
    assert_int_equal(st_device_launch(dev, k, MASKS, 0, &err), ST_OK);
    assert_int_equal(st_device_buffer_read(dev, b, bytes, got, &err), ST_OK);
    st_device_buffer_destroy(dev, b);
    printf("# the device's mask bits: %s\n", got[9] ? "movmskps" : "the portable or-reduction");
    for (uint32_t m = 0; m < MASKS; m++) {
        const uint32_t *o = got + (size_t)m * OUTS;
        uint32_t want[OUTS - 1] = {m & 0xfu, m & 0xffu, m, m & 0xfu, m & 0xffu, m,
                                   (m & 0xfu) != 0, (m & 0xffu) != 0, m != 0};
        for (uint32_t j = 0; j < OUTS - 1; j++)
            if (o[j] != want[j])
                fail_msg("mask %#x, word %u: got %#x, want %#x", m, j, o[j], want[j]);
        if (o[9] != got[9])
            fail_msg("mask %#x: the form changed between work-items", m);
    }
    free(got);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(mask_bits_are_the_lanes_bits),
    };
    return cmocka_run_group_tests(tests, device_setup, device_teardown);
}
