/* device_fixture.h — the one device fixture of the tests that run kernels:
 * the default OpenCL device (PoCL's CPU) with the program built, as cmocka
 * group setup and teardown; a scene loader; and a device at a given lane
 * width. Include after <cmocka.h>. */
#ifndef ST_DEVICE_FIXTURE_H
#define ST_DEVICE_FIXTURE_H

#include <stdio.h>

#include "st_device.h"
#include "st_scene.h"

static st_device *dev;

static int device_setup(void **state)
{
    (void)state;
    st_error err = {0};
    if (st_device_create(NULL, &dev, &err) != ST_OK || st_device_build(dev, NULL, &err) != ST_OK) {
        fprintf(stderr, "device: %s\n%s\n", err.msg, dev ? st_device_build_log(dev) : "");
        return -1;
    }
    return 0;
}

static int device_teardown(void **state)
{
    (void)state;
    st_device_destroy(dev);
    dev = NULL;
    return 0;
}

/* Scene `name` (a file or a built-in scene), or the test fails. */
static inline st_scene *fixture_scene(const char *name)
{
    st_error err = {0};
    st_scene *s = NULL;
    if (st_scene_load(name, &s, &err) != ST_OK)
        fail_msg("load %s: %s", name, err.msg);
    return s;
}

/* The default device with its kernels built at `lanes` lanes (--lanes),
 * or the test fails; the caller destroys it. */
static inline st_device *fixture_device_at(unsigned lanes)
{
    st_error err = {0};
    st_device *d = NULL;
    if (st_device_create(NULL, &d, &err) != ST_OK || st_device_set_lanes(d, lanes, &err) != ST_OK)
        fail_msg("device at %u lanes: %s", lanes, err.msg);
    return d;
}

#endif
