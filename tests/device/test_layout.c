/* test_layout.c — every struct and field that the host and the kernels
 * share (ST_LAYOUT_STRUCTS, ST_LAYOUT_FIELDS in st_shared.h) has the same
 * size and offset on the device (kernels/shared/layout.cl) as on the host, and the
 * wavefront buffers are sized from their element types. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include "device_fixture.h"
#include "st_shared.h"
#include "wave.h"

#define HOST_SIZE(type) (st_u32) sizeof(type),
#define HOST_OFFSET(type, field) (st_u32) offsetof(type, field),
#define NAME_SIZE(type) "sizeof(" #type ")",
#define NAME_OFFSET(type, field) #type "." #field,
static const st_u32 host[] = {ST_LAYOUT_STRUCTS(HOST_SIZE) ST_LAYOUT_FIELDS(HOST_OFFSET)};
static const char *const names[] = {ST_LAYOUT_STRUCTS(NAME_SIZE) ST_LAYOUT_FIELDS(NAME_OFFSET)};
enum { ENTRIES = sizeof host / sizeof host[0] };

static void device_layout_matches_host(void **state)
{
    (void)state;
    st_error err = {0};
    cl_kernel k;
    cl_mem out;
    st_u32 got[ENTRIES];
    memset(got, 0xff, sizeof got);
    assert_int_equal(st_device_kernel(dev, "probe_layout", &k, &err), ST_OK);
    assert_int_equal(st_device_buffer_create(dev, sizeof got, got, &out, &err), ST_OK);
    assert_int_equal(st_device_set_args(k, &err, 1, sizeof(cl_mem), (const void *)&out), ST_OK);
    assert_int_equal(st_device_launch(dev, k, 1, 1, &err), ST_OK);
    assert_int_equal(st_device_buffer_read(dev, out, sizeof got, got, &err), ST_OK);
    st_device_buffer_destroy(dev, out);
    for (int i = 0; i < ENTRIES; i++)
        if (got[i] != host[i])
            fail_msg("%s: device %u, host %u", names[i], got[i], host[i]);
}

/* Buffer sizes follow the extents: per item, per pixel, per pixel only in
 * adaptive renders, per item or per block of the sort only in waves that
 * sort their rays, one. */
static void wave_sizes_follow_the_list(void **state)
{
    (void)state;
    st_wave w;
    memset(&w, 0, sizeof w);
    w.items = 100;
    w.pixels = 12;
    assert_int_equal(st_wave_bytes(&w, ST_WAVE_ray), 100 * sizeof(st_ray));
    assert_int_equal(st_wave_bytes(&w, ST_WAVE_path), 100 * sizeof(st_path));
    assert_int_equal(st_wave_bytes(&w, ST_WAVE_film), 12 * sizeof(st_film_pixel));
    assert_int_equal(st_wave_bytes(&w, ST_WAVE_pilot_film), sizeof(st_film_pixel));
    assert_int_equal(st_wave_bytes(&w, ST_WAVE_stats), sizeof(st_film_stats));
    assert_int_equal(st_wave_bytes(&w, ST_WAVE_bin_start), 13 * sizeof(st_u32));
    assert_int_equal(st_wave_bytes(&w, ST_WAVE_bin_item), 100 * sizeof(st_u32));
    w.adaptive = 1;
    assert_int_equal(st_wave_bytes(&w, ST_WAVE_pilot_film), 12 * sizeof(st_film_pixel));
    assert_int_equal(st_wave_bytes(&w, ST_WAVE_pixel_spp), 12 * sizeof(st_u32));
    assert_int_equal(sizeof(st_film_pixel), ST_FILM_SUMS * sizeof(st_i64));
    /* the ray order's buffers: one element unless the wave sorts its rays */
    assert_int_equal(st_wave_bytes(&w, ST_WAVE_order_ray), sizeof(st_ray));
    assert_int_equal(st_wave_bytes(&w, ST_WAVE_order_count), sizeof(st_u32));
    w.ordered = 1;
    w.items = 5000; /* two blocks of the sort */
    assert_int_equal(st_wave_bytes(&w, ST_WAVE_order_ray), 5000 * sizeof(st_ray));
    assert_int_equal(st_wave_bytes(&w, ST_WAVE_order_pair), 5000 * sizeof(st_order_pair));
    assert_int_equal(st_wave_count(&w, ST_WAVE_order_count),
                     ST_ORDER_COUNTS + 2 * ST_ORDER_DIGITS);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(device_layout_matches_host),
        cmocka_unit_test(wave_sizes_follow_the_list),
    };
    return cmocka_run_group_tests(tests, device_setup, device_teardown);
}
