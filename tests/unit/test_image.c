/* test_image.c — guards src/image/image.c, src/image/image_exr.c and src/image/image_png.c (include/st_image.h).
 *
 * Expected values are derived independently of the code under test: EXR round trips compare bit
 * patterns; PNG codes are recomputed here from the IEC 61966-2-1 formula and read back with
 * stb_image directly; sRGB reference values were computed in double precision from the formula
 * (Python 3: 1.055*0.5**(1/2.4)-0.055 = 0.7353569830524495). Error paths check the status, that
 * the message starts with the path, and the folder listing afterwards. Every test works in its
 * own fresh folder under /tmp, removed at the end.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "st_image.h"

#include <openexr.h>
#include <stb/stb_image.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define assert_near(got, want, tol)                                                          \
    do {                                                                                     \
        double g_ = (got), w_ = (want), t_ = (tol);                                          \
        if (!(fabs(g_ - w_) <= t_))                                                          \
            fail_msg("%s = %.17g, expected %.17g within %g", #got, g_, w_, t_);              \
    } while (0)

/* ---- scratch folders ----------------------------------------------------------------------- */

typedef struct scratch {
    char dir[64];
    char path[256];
} scratch;

static int setup_dir(void **state)
{
    scratch *s = calloc(1, sizeof *s);
    if (!s)
        return -1;
    snprintf(s->dir, sizeof s->dir, "/tmp/st_test_image.XXXXXX");
    if (!mkdtemp(s->dir)) {
        free(s);
        return -1;
    }
    *state = s;
    return 0;
}

static void remove_tree(const char *path)
{
    struct stat st;
    if (lstat(path, &st) != 0)
        return;
    if (S_ISDIR(st.st_mode)) {
        DIR *d = opendir(path);
        struct dirent *e;
        while (d && (e = readdir(d)) != NULL) {
            if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
                continue;
            char sub[512];
            snprintf(sub, sizeof sub, "%s/%s", path, e->d_name);
            remove_tree(sub);
        }
        if (d)
            closedir(d);
        rmdir(path);
    } else {
        unlink(path);
    }
}

static int teardown_dir(void **state)
{
    scratch *s = *state;
    remove_tree(s->dir);
    free(s);
    return 0;
}

static const char *in_dir(scratch *s, const char *name)
{
    snprintf(s->path, sizeof s->path, "%s/%s", s->dir, name);
    return s->path;
}

/* Number of entries in folder dir (without . and ..); the names, one per line, in listing. */
static int folder_entries(const char *dir, char *listing, size_t size)
{
    int n = 0;
    listing[0] = '\0';
    DIR *d = opendir(dir);
    assert_non_null(d);
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        size_t used = strlen(listing);
        snprintf(listing + used, size - used, "%s\n", e->d_name);
        n++;
    }
    closedir(d);
    return n;
}

static void assert_message_names(const st_error *err, const char *path)
{
    if (strncmp(err->msg, path, strlen(path)) != 0 || err->msg[strlen(path)] != ':')
        fail_msg("message does not start with '%s:': %s", path, err->msg);
    if (strchr(err->msg, '\n'))
        fail_msg("message is not one line: %s", err->msg);
}

static uint32_t float_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    return u;
}

/* xorshift32 (Marsaglia, "Xorshift RNGs", J. Stat. Software 2003): test data only. */
static uint32_t next_random(uint32_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return *s;
}

/* ---- the container ------------------------------------------------------------------------- */

static void create_defaults_names_and_zeroes(void **state)
{
    (void)state;
    st_error err = {ST_OK, ""};
    st_image img;
    assert_int_equal(st_image_create(&img, 3, 2, 4, NULL, &err), ST_OK);
    assert_string_equal(img.channel_names[0], "R");
    assert_string_equal(img.channel_names[3], "A");
    assert_ptr_equal((void *)img.data, (void *)img.udata);
    for (size_t i = 0; i < 3 * 2 * 4; i++)
        assert_int_equal(img.udata[i], 0);
    assert_int_equal(st_image_find_channel(&img, "B"), 2);
    assert_int_equal(st_image_find_channel(&img, "Z"), -1);
    st_image_free(&img);
    assert_null(img.data);
    st_image_free(&img); /* idempotent */
    st_image_free(NULL);

    assert_int_equal(st_image_create(&img, 1, 1, 6, NULL, &err), ST_OK);
    assert_string_equal(img.channel_names[5], "C5");
    st_image_free(&img);
}

static void create_rejects_bad_arguments(void **state)
{
    (void)state;
    st_image img;
    const char *dup[2] = {"R", "R"};
    const char *empty[2] = {"R", ""};
    const char *longname[1] = {"abcdefghijklmnopqrstuvwxyz0123456"}; /* 33 bytes */
    struct {
        uint32_t w, h, c;
        const char *const *names;
    } cases[] = {{0, 4, 3, NULL}, {4, 0, 3, NULL}, {4, 4, 0, NULL}, {4, 4, ST_IMAGE_MAX_CHANNELS + 1, NULL},
                 {4, 4, 2, dup},  {4, 4, 2, empty}, {4, 4, 1, longname}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        st_error err = {ST_OK, ""};
        assert_int_equal(st_image_create(&img, cases[i].w, cases[i].h, cases[i].c, cases[i].names,
                                         &err),
                         ST_ERR_USAGE);
        assert_null(img.data);
        assert_true(err.msg[0] != '\0');
    }
}

/* ---- EXR ----------------------------------------------------------------------------------- */

/* Values chosen to break any lossy or half-float path: tiny, half-max-plus-a-bit, negative,
 * subnormal, signed zero, float max, NaN with payload, then random bit patterns (finite). */
static float special_value(size_t i, uint32_t *rng)
{
    static const float fixed[] = {1e-30f, 65504.5f, -3.25f, 1.4e-45f, -0.0f, 3.4028235e38f, 0.1f,
                                  -1e20f};
    if (i < sizeof fixed / sizeof fixed[0])
        return fixed[i];
    if (i == sizeof fixed / sizeof fixed[0]) {
        uint32_t nan_bits = 0x7fc12345u;
        float f;
        memcpy(&f, &nan_bits, 4);
        return f;
    }
    uint32_t u;
    do
        u = next_random(rng);
    while ((u & 0x7f800000u) == 0x7f800000u); /* skip inf/NaN patterns */
    float f;
    memcpy(&f, &u, 4);
    return f;
}

static void exr_round_trip_float_bits_exact(void **state)
{
    scratch *s = *state;
    const char *names[4] = {"R", "G", "B", "W"};
    st_image img, back;
    st_error err = {ST_OK, ""};
    /* 19 rows: two ZIP chunks of 16 lines, the second partial */
    assert_int_equal(st_image_create(&img, 7, 19, 4, names, &err), ST_OK);
    uint32_t rng = 12345;
    for (size_t i = 0; i < 7 * 19 * 4; i++)
        img.data[i] = special_value(i, &rng);
    const char *path = in_dir(s, "float.exr");
    assert_int_equal(st_image_save_exr(path, &img, NULL, 0, &err), ST_OK);
    assert_int_equal(st_image_load_exr(path, &back, NULL, NULL, &err), ST_OK);
    assert_int_equal(back.width, 7);
    assert_int_equal(back.height, 19);
    assert_int_equal(back.channels, 4);
    for (uint32_t c = 0; c < 4; c++) {
        int k = st_image_find_channel(&back, names[c]);
        assert_true(k >= 0);
        assert_int_equal(back.types[k], ST_PIXEL_FLOAT);
        for (size_t p = 0; p < 7 * 19; p++)
            if (float_bits(back.data[p * 4 + (size_t)k]) != float_bits(img.data[p * 4 + c]))
                fail_msg("channel %s sample %zu: %08x != %08x", names[c], p,
                         float_bits(back.data[p * 4 + (size_t)k]),
                         float_bits(img.data[p * 4 + c]));
    }
    st_image_free(&img);
    st_image_free(&back);
}

/* Three FLOAT channels of a real render (tests/data/render-noise-48x48-rgb.f32:
 * 48 x 48 x R,G,B little-endian floats, from the 48 x 48 default scene at 16
 * spp): the image that came back as garbage in every pixel when the writer
 * used ZIP (16-line chunks) with OpenEXR 3.1.5; bit-exact now. Synthetic
 * noise of several distributions did not trigger it. */
static void exr_roundtrip_render_three_channels(void **state)
{
    scratch *s = *state;
    const char *names[3] = {"R", "G", "B"};
    st_image img, back;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(&img, 48, 48, 3, names, &err), ST_OK);
    FILE *f = fopen("tests/data/render-noise-48x48-rgb.f32", "rb");
    assert_non_null(f);
    assert_int_equal(fread(img.data, sizeof(float), 48 * 48 * 3, f), 48 * 48 * 3);
    fclose(f);
    const char *path = in_dir(s, "render.exr");
    assert_int_equal(st_image_save_exr(path, &img, NULL, 0, &err), ST_OK);
    assert_int_equal(st_image_load_exr(path, &back, NULL, NULL, &err), ST_OK);
    for (uint32_t c = 0; c < 3; c++) {
        int k = st_image_find_channel(&back, names[c]);
        assert_true(k >= 0);
        for (size_t p = 0; p < 48 * 48; p++)
            if (float_bits(back.data[p * 3 + (size_t)k]) != float_bits(img.data[p * 3 + c]))
                fail_msg("channel %s sample %zu: %g != %g", names[c], p,
                         (double)back.data[p * 3 + (size_t)k], (double)img.data[p * 3 + c]);
    }
    st_image_free(&img);
    st_image_free(&back);
}

static void exr_round_trip_uint_exact(void **state)
{
    scratch *s = *state;
    const char *names[3] = {"sum.R.hi", "sum.R.lo", "W"};
    st_image img, back;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(&img, 33, 5, 3, names, &err), ST_OK);
    img.types[0] = img.types[1] = ST_PIXEL_UINT;
    uint32_t rng = 777;
    static const uint32_t edge[] = {0u, 1u, 0xffffffffu, 0x80000000u, 0x7fffffffu};
    for (size_t p = 0; p < 33 * 5; p++) {
        img.udata[p * 3 + 0] = p < 5 ? edge[p] : next_random(&rng);
        img.udata[p * 3 + 1] = next_random(&rng);
        img.data[p * 3 + 2] = (float)p * -0.5f;
    }
    const char *path = in_dir(s, "uint.exr");
    assert_int_equal(st_image_save_exr(path, &img, NULL, 0, &err), ST_OK);
    assert_int_equal(st_image_load_exr(path, &back, NULL, NULL, &err), ST_OK);
    for (uint32_t c = 0; c < 3; c++) {
        int k = st_image_find_channel(&back, names[c]);
        assert_true(k >= 0);
        assert_int_equal(back.types[k], img.types[c]);
        for (size_t p = 0; p < 33 * 5; p++)
            assert_int_equal(back.udata[p * 3 + (size_t)k], img.udata[p * 3 + c]);
    }
    st_image_free(&img);
    st_image_free(&back);
}

static void exr_channels_come_back_sorted_by_name(void **state)
{
    scratch *s = *state;
    st_image img, back;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(&img, 2, 2, 3, NULL, &err), ST_OK); /* R, G, B */
    for (size_t p = 0; p < 4; p++)
        for (size_t c = 0; c < 3; c++)
            img.data[p * 3 + c] = (float)(10 * c + p);
    const char *path = in_dir(s, "rgb.exr");
    assert_int_equal(st_image_save_exr(path, &img, NULL, 0, &err), ST_OK);
    assert_int_equal(st_image_load_exr(path, &back, NULL, NULL, &err), ST_OK);
    assert_string_equal(back.channel_names[0], "B");
    assert_string_equal(back.channel_names[1], "G");
    assert_string_equal(back.channel_names[2], "R");
    assert_int_equal(st_image_find_channel(&back, "R"), 2);
    for (size_t p = 0; p < 4; p++)
        assert_true(back.data[p * 3 + 2] == (float)p); /* R was 10*0 + p */
    st_image_free(&img);
    st_image_free(&back);
}

static const st_attr *find_attr(const st_attr *a, int n, const char *name)
{
    for (int i = 0; i < n; i++)
        if (strcmp(a[i].name, name) == 0)
            return &a[i];
    return NULL;
}

static void exr_attributes_round_trip(void **state)
{
    scratch *s = *state;
    st_attr attrs[4];
    memset(attrs, 0, sizeof attrs);
    snprintf(attrs[0].name, sizeof attrs[0].name, "strata.sampler");
    snprintf(attrs[0].value, sizeof attrs[0].value, "halton");
    snprintf(attrs[1].name, sizeof attrs[1].name, "strata.empty");
    /* a name over 31 bytes needs OpenEXR's long-name flag */
    snprintf(attrs[2].name, sizeof attrs[2].name, "strata.a.rather.long.attribute.name.42");
    memset(attrs[2].value, 'x', sizeof attrs[2].value - 1); /* the longest value that fits */
    snprintf(attrs[3].name, sizeof attrs[3].name, "strata.cmd");
    snprintf(attrs[3].value, sizeof attrs[3].value, "render --spp 16 \"a b\" é");
    st_image img, back;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(&img, 3, 3, 3, NULL, &err), ST_OK);
    const char *path = in_dir(s, "attrs.exr");
    assert_int_equal(st_image_save_exr(path, &img, attrs, 4, &err), ST_OK);
    st_attr *got = NULL;
    int n = -1;
    assert_int_equal(st_image_load_exr(path, &back, &got, &n, &err), ST_OK);
    assert_int_equal(n, 5); /* the four and "software"; required ones are not read, nor "type" */
    for (int i = 0; i < 4; i++) {
        const st_attr *a = find_attr(got, n, attrs[i].name);
        if (!a)
            fail_msg("attribute %s missing", attrs[i].name);
        assert_string_equal(a->value, attrs[i].value);
    }
    free(got);
    st_image_free(&img);
    st_image_free(&back);
}

static void exr_reserved_attribute_fails_leaves_nothing(void **state)
{
    scratch *s = *state;
    st_attr bad = {"channels", "R,G,B", ST_ATTR_STRING};
    st_image img;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(&img, 2, 2, 3, NULL, &err), ST_OK);
    const char *path = in_dir(s, "reserved.exr");
    assert_int_equal(st_image_save_exr(path, &img, &bad, 1, &err), ST_ERR_FORMAT);
    assert_message_names(&err, path);
    assert_non_null(strstr(err.msg, "channels"));
    char listing[1024];
    assert_int_equal(folder_entries(s->dir, listing, sizeof listing), 0);
    st_image_free(&img);
}

/* Writes a tiled (4x4) file with a HALF and a FLOAT channel through the OpenEXR C API directly,
 * data window (3,5)-(12,11): 10x7 pixels, so edge tiles are partial. HALF holds k/8, exact. */
static void write_tiled_half(const char *path)
{
    exr_context_t ctx;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    assert_int_equal(exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init), 0);
    int part;
    assert_int_equal(exr_add_part(ctx, NULL, EXR_STORAGE_TILED, &part), 0);
    exr_attr_box2i_t win = {{{{3, 5}}}, {{{12, 11}}}};
    exr_attr_v2f_t center = {{{0.f, 0.f}}};
    assert_int_equal(exr_initialize_required_attr(ctx, part, &win, &win, 1.f, &center, 1.f,
                                                  EXR_LINEORDER_INCREASING_Y, EXR_COMPRESSION_ZIP),
                     0);
    assert_int_equal(exr_set_tile_descriptor(ctx, part, 4, 4, EXR_TILE_ONE_LEVEL,
                                             EXR_TILE_ROUND_DOWN),
                     0);
    assert_int_equal(exr_add_channel(ctx, part, "H", EXR_PIXEL_HALF, EXR_PERCEPTUALLY_LOGARITHMIC,
                                     1, 1),
                     0);
    assert_int_equal(exr_add_channel(ctx, part, "F", EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LOGARITHMIC,
                                     1, 1),
                     0);
    assert_int_equal(exr_write_header(ctx), 0);
    float px[7][10][2]; /* [y][x][F, H] */
    for (int y = 0; y < 7; y++)
        for (int x = 0; x < 10; x++) {
            px[y][x][0] = 1000.25f * (float)(y * 10 + x) - 7.f;
            px[y][x][1] = (float)(y * 10 + x - 30) / 8.f;
        }
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    int started = 0;
    for (int ty = 0; ty < 2; ty++)
        for (int tx = 0; tx < 3; tx++) {
            exr_chunk_info_t ci;
            assert_int_equal(exr_write_tile_chunk_info(ctx, part, tx, ty, 0, 0, &ci), 0);
            assert_int_equal(started ? exr_encoding_update(ctx, part, &ci, &enc)
                                     : exr_encoding_initialize(ctx, part, &ci, &enc),
                             0);
            for (int c = 0; c < enc.channel_count; c++) {
                int k = strcmp(enc.channels[c].channel_name, "F") == 0 ? 0 : 1;
                enc.channels[c].encode_from_ptr = (const uint8_t *)&px[ty * 4][tx * 4][k];
                enc.channels[c].user_pixel_stride = 8;
                enc.channels[c].user_line_stride = 80;
                enc.channels[c].user_bytes_per_element = 4;
                enc.channels[c].user_data_type = EXR_PIXEL_FLOAT;
            }
            if (!started)
                assert_int_equal(exr_encoding_choose_default_routines(ctx, part, &enc), 0);
            started = 1;
            assert_int_equal(exr_encoding_run(ctx, part, &enc), 0);
        }
    exr_encoding_destroy(ctx, &enc);
    assert_int_equal(exr_finish(&ctx), 0);
}

static void exr_loads_tiled_half_with_offset_window(void **state)
{
    scratch *s = *state;
    const char *path = in_dir(s, "tiled.exr");
    write_tiled_half(path);
    st_image img;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_load_exr(path, &img, NULL, NULL, &err), ST_OK);
    assert_int_equal(img.width, 10);
    assert_int_equal(img.height, 7);
    assert_int_equal(img.channels, 2);
    assert_int_equal(img.x0, 0); /* the data window is the display window, both at (3, 5) */
    assert_int_equal(img.y0, 0);
    assert_int_equal(img.display_width, 10);
    assert_int_equal(img.display_height, 7);
    int f = st_image_find_channel(&img, "F"), h = st_image_find_channel(&img, "H");
    assert_int_equal(f, 0); /* sorted: F before H */
    assert_int_equal(h, 1);
    assert_int_equal(img.types[h], ST_PIXEL_FLOAT); /* HALF is widened */
    for (int y = 0; y < 7; y++)
        for (int x = 0; x < 10; x++) {
            size_t p = (size_t)(y * 10 + x) * 2;
            assert_true(img.data[p + (size_t)f] == 1000.25f * (float)(y * 10 + x) - 7.f);
            assert_true(img.data[p + (size_t)h] == (float)(y * 10 + x - 30) / 8.f);
        }
    st_image_free(&img);
}

/* A window of a larger image (render --crop): OpenEXR's own reader finds the data window at
 * (x0, y0) inside the display window (0, 0) - (dw-1, dh-1); st_image_load_exr gives back the
 * origin, the display size and every pixel. 37 rows span three 16-line ZIP chunks, whose y is
 * then the window's. */
static void exr_data_window_round_trips(void **state)
{
    scratch *s = *state;
    const char *path = in_dir(s, "window.exr");
    st_image img, back;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(&img, 5, 37, 1, (const char *const[]){"Y"}, &err), ST_OK);
    for (size_t i = 0; i < 5 * 37; i++)
        img.data[i] = 0.5f * (float)i - 3.0f;
    img.x0 = 7;
    img.y0 = 2;
    img.display_width = 20;
    img.display_height = 50;
    assert_int_equal(st_image_save_exr(path, &img, NULL, 0, &err), ST_OK);
    exr_context_t ctx;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    assert_int_equal(exr_start_read(&ctx, path, &init), 0);
    exr_attr_box2i_t dw, disp;
    assert_int_equal(exr_get_data_window(ctx, 0, &dw), 0);
    assert_int_equal(exr_get_display_window(ctx, 0, &disp), 0);
    exr_finish(&ctx);
    assert_int_equal(dw.min.x, 7);
    assert_int_equal(dw.min.y, 2);
    assert_int_equal(dw.max.x, 11);
    assert_int_equal(dw.max.y, 38);
    assert_int_equal(disp.min.x, 0);
    assert_int_equal(disp.min.y, 0);
    assert_int_equal(disp.max.x, 19);
    assert_int_equal(disp.max.y, 49);
    assert_int_equal(st_image_load_exr(path, &back, NULL, NULL, &err), ST_OK);
    assert_int_equal(back.x0, 7);
    assert_int_equal(back.y0, 2);
    assert_int_equal(back.display_width, 20);
    assert_int_equal(back.display_height, 50);
    assert_int_equal(back.width, 5);
    assert_int_equal(back.height, 37);
    assert_memory_equal(back.data, img.data, sizeof(float) * 5 * 37);
    st_image_free(&img);
    st_image_free(&back);
}

static void write_bytes(const char *path, const void *bytes, size_t n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(bytes, 1, n, f), n);
    assert_int_equal(fclose(f), 0);
}

static void exr_load_malformed_names_file(void **state)
{
    scratch *s = *state;
    st_image img;
    /* not an EXR at all */
    const char *text = "this is not an OpenEXR file, just some text\n";
    char bad[256];
    snprintf(bad, sizeof bad, "%s", in_dir(s, "text.exr"));
    write_bytes(bad, text, strlen(text));
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_load_exr(bad, &img, NULL, NULL, &err), ST_ERR_FORMAT);
    assert_message_names(&err, bad);
    assert_null(img.data);

    /* a valid file cut short: inside the header, and inside the pixel data */
    st_image full;
    assert_int_equal(st_image_create(&full, 64, 64, 3, NULL, &err), ST_OK);
    uint32_t rng = 99;
    for (size_t i = 0; i < 64 * 64 * 3; i++)
        full.data[i] = (float)(next_random(&rng) % 1000) / 7.f; /* poorly compressible */
    char good[256];
    snprintf(good, sizeof good, "%s", in_dir(s, "good.exr"));
    assert_int_equal(st_image_save_exr(good, &full, NULL, 0, &err), ST_OK);
    FILE *f = fopen(good, "rb");
    assert_non_null(f);
    static unsigned char bytes[1 << 16];
    size_t n = fread(bytes, 1, sizeof bytes, f);
    fclose(f);
    assert_true(n > 1000 && n < sizeof bytes);
    size_t cuts[2] = {60, n / 2};
    for (int i = 0; i < 2; i++) {
        char cut[256];
        snprintf(cut, sizeof cut, "%s/cut%d.exr", s->dir, i);
        write_bytes(cut, bytes, cuts[i]);
        st_error e2 = {ST_OK, ""};
        st_attr *attrs = (st_attr *)1;
        int nattrs = 5;
        assert_int_equal(st_image_load_exr(cut, &img, &attrs, &nattrs, &e2), ST_ERR_FORMAT);
        assert_message_names(&e2, cut);
        /* the first cut ends inside the header, the second inside the pixel chunks */
        assert_non_null(strstr(e2.msg, i == 0 ? "not a readable OpenEXR" : "cannot read pixels"));
        assert_null(img.data);
        assert_null(attrs);
        assert_int_equal(nattrs, 0);
    }
    st_image_free(&full);
}

static void exr_load_missing_file_is_io_error(void **state)
{
    scratch *s = *state;
    st_image img;
    st_error err = {ST_OK, ""};
    const char *path = in_dir(s, "absent.exr");
    assert_int_equal(st_image_load_exr(path, &img, NULL, NULL, &err), ST_ERR_IO);
    assert_message_names(&err, path);
    assert_non_null(strstr(err.msg, "No such file or directory"));
}

/* Saving into a missing folder, and onto an existing folder's name (refused when the output is
 * opened: st_outfile never replaces what is not a regular file): ST_ERR_IO naming the file, and
 * the folder holds exactly what it held before. */
static void unwritable_path_fails_leaves_nothing(void **state, const char *ext)
{
    scratch *s = *state;
    st_image img;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(&img, 4, 4, 3, NULL, &err), ST_OK);
    char path[256], listing[1024];
    snprintf(path, sizeof path, "%s/missing/x.%s", s->dir, ext);
    assert_int_equal(st_image_save(path, &img, NULL, 0, &err), ST_ERR_IO);
    assert_message_names(&err, path);
    assert_non_null(strstr(err.msg, "No such file or directory"));
    assert_int_equal(folder_entries(s->dir, listing, sizeof listing), 0);

    snprintf(path, sizeof path, "%s/taken.%s", s->dir, ext);
    assert_int_equal(mkdir(path, 0755), 0);
    st_error err2 = {ST_OK, ""};
    assert_int_equal(st_image_save(path, &img, NULL, 0, &err2), ST_ERR_IO);
    assert_message_names(&err2, path);
    int n = folder_entries(s->dir, listing, sizeof listing);
    if (n != 1)
        fail_msg("folder holds %d entries after a failed save:\n%s", n, listing);
    assert_int_equal(folder_entries(path, listing, sizeof listing), 0);
    st_image_free(&img);
}

static void exr_unwritable_path_fails_leaves_nothing(void **state)
{
    unwritable_path_fails_leaves_nothing(state, "exr");
}

static void png_unwritable_path_fails_leaves_nothing(void **state)
{
    unwritable_path_fails_leaves_nothing(state, "png");
}

static void exr_failed_save_keeps_existing_file(void **state)
{
    scratch *s = *state;
    st_image img;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(&img, 2, 2, 3, NULL, &err), ST_OK);
    img.data[0] = 42.f;
    const char *path = in_dir(s, "keep.exr");
    assert_int_equal(st_image_save_exr(path, &img, NULL, 0, &err), ST_OK);
    st_attr bad = {"dataWindow", "x", ST_ATTR_STRING};
    img.data[0] = 7.f;
    assert_int_equal(st_image_save_exr(path, &img, &bad, 1, &err), ST_ERR_FORMAT);
    st_image back;
    st_error e2 = {ST_OK, ""};
    assert_int_equal(st_image_load_exr(path, &back, NULL, NULL, &e2), ST_OK);
    assert_true(back.data[st_image_find_channel(&back, "R")] == 42.f);
    char listing[1024];
    assert_int_equal(folder_entries(s->dir, listing, sizeof listing), 1);
    st_image_free(&img);
    st_image_free(&back);
}

/* ---- sRGB ---------------------------------------------------------------------------------- */

static void srgb_encode_known_points(void **state)
{
    (void)state;
    /* IEC 61966-2-1 OETF evaluated in double by hand/Python (see file comment) */
    assert_near(st_image_srgb_encode(0.0f), 0.0, 0.0);
    assert_near(st_image_srgb_encode(0.003f), 12.92 * (double)0.003f, 1e-8); /* linear branch */
    /* 0.0031308f is 0.00313080009 > 0.0031308, so the power branch applies:
     * 1.055*0.00313080009^(1/2.4) - 0.055 = 0.04044990863524276 (Python, double) */
    assert_near(st_image_srgb_encode(0.0031308f), 0.04044990863524276, 1e-8);
    /* ... and the branches meet there: 12.92*0.0031308 = 0.040449936, 2.9e-8 away */
    assert_near(st_image_srgb_encode(0.0031308f), 12.92 * 0.0031308, 1e-7);
    assert_near(st_image_srgb_encode(0.5f), 0.7353569830524495, 1e-7);
    assert_near(st_image_srgb_encode(1.0f), 1.0, 0.0);
    /* clamping */
    assert_near(st_image_srgb_encode(-1.0f), 0.0, 0.0);
    assert_near(st_image_srgb_encode(7.0f), 1.0, 0.0);
    assert_near(st_image_srgb_encode(NAN), 0.0, 0.0);
    assert_near(st_image_srgb_encode(INFINITY), 1.0, 0.0);
}

static void srgb_quantize_known_codes(void **state)
{
    (void)state;
    assert_int_equal(st_image_srgb_quantize(0.0f), 0);
    assert_int_equal(st_image_srgb_quantize(1.0f), 255);
    assert_int_equal(st_image_srgb_quantize(0.5f), 188); /* 255*0.73536 = 187.52 */
    /* 0.0031308 -> 255*0.040449936 = 10.31 */
    assert_int_equal(st_image_srgb_quantize(0.0031308f), 10);
    /* 18% grey -> 255*0.461356 = 117.65 */
    assert_int_equal(st_image_srgb_quantize(0.18f), 118);
}

static void srgb_decode_inverts_encode(void **state)
{
    (void)state;
    assert_near(st_image_srgb_decode(0.04045f), 0.04045 / 12.92, 1e-9);
    assert_near(st_image_srgb_decode(0.7353569830524495f), 0.5, 1e-6);
    for (int i = 0; i <= 1000; i++) {
        float x = (float)i / 1000.f;
        /* float evaluation: |error| <= a few ulps of 1 */
        assert_near(st_image_srgb_decode(st_image_srgb_encode(x)), x, 2e-6);
    }
}

/* ---- PNG ----------------------------------------------------------------------------------- */

/* The OETF written out again, independently of src/image/image_png.c. */
static int reference_code(double x)
{
    if (!(x > 0))
        x = 0;
    if (x > 1)
        x = 1;
    double v = x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1 / 2.4) - 0.055;
    return (int)floor(v * 255 + 0.5);
}

static void fill_gradient(st_image *img)
{
    for (uint32_t y = 0; y < img->height; y++)
        for (uint32_t x = 0; x < img->width; x++)
            for (uint32_t c = 0; c < 3; c++) {
                /* covers [-0.1, 1.1]: both clamps and both branches */
                double t = (double)(x + img->width * y) / (img->width * img->height - 1);
                img->data[(y * img->width + x) * img->channels + c] =
                    (float)(-0.1 + 1.2 * t * (c == 1 ? t : 1.0) + (c == 2 ? 0.001 : 0.0));
            }
}

static void png_codes_match_srgb_formula(void **state)
{
    scratch *s = *state;
    st_image img;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(&img, 37, 29, 3, NULL, &err), ST_OK);
    fill_gradient(&img);
    const char *path = in_dir(s, "grad.png");
    assert_int_equal(st_image_save_png(path, &img, &err), ST_OK);
    int w, h, n;
    unsigned char *px = stbi_load(path, &w, &h, &n, 0);
    assert_non_null(px);
    assert_int_equal(w, 37);
    assert_int_equal(h, 29);
    assert_int_equal(n, 3);
    for (size_t i = 0; i < 37 * 29 * 3; i++)
        if (px[i] != reference_code(img.data[i]))
            fail_msg("sample %zu: value %.9g, code %d, expected %d", i, img.data[i], px[i],
                     reference_code(img.data[i]));
    stbi_image_free(px);
    st_image_free(&img);
}

static void png_round_trip_within_quantisation_bound(void **state)
{
    scratch *s = *state;
    st_image img, back;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(&img, 64, 16, 3, NULL, &err), ST_OK);
    fill_gradient(&img);
    const char *path = in_dir(s, "round.png");
    assert_int_equal(st_image_save(path, &img, NULL, 0, &err), ST_OK);
    assert_int_equal(st_image_load(path, &back, &err), ST_OK);
    assert_int_equal(back.channels, 3);
    assert_string_equal(back.channel_names[0], "R");
    /* Bound: the code is within 0.5/255 of the encoded value, and the EOTF's slope is at most
     * (2.4/1.055)*1^1.4 = 2.275 (at V = 1), so |decoded - clamp(x)| <= 2.275*0.5/255 = 0.00446. */
    const double bound = 2.4 / 1.055 * 0.5 / 255 + 1e-6;
    double worst = 0;
    for (size_t i = 0; i < 64 * 16 * 3; i++) {
        double x = img.data[i] < 0 ? 0 : img.data[i] > 1 ? 1 : img.data[i];
        double e = fabs(back.data[i] - x);
        if (e > worst)
            worst = e;
    }
    if (!(worst <= bound))
        fail_msg("worst round-trip error %.6g exceeds %.6g", worst, bound);
    assert_true(worst > 0); /* it is quantised at all */
    st_image_free(&img);
    st_image_free(&back);
}

static void png_takes_rgb_by_name(void **state)
{
    scratch *s = *state;
    const char *names[4] = {"B", "W", "G", "R"}; /* e.g. as loaded from an EXR, plus weight */
    st_image img;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(&img, 2, 1, 4, names, &err), ST_OK);
    img.types[1] = ST_PIXEL_UINT; /* the uint channel is ignored */
    for (int p = 0; p < 2; p++) {
        img.data[p * 4 + 0] = 0.0f;   /* B */
        img.udata[p * 4 + 1] = 1234u; /* W */
        img.data[p * 4 + 2] = 0.5f;   /* G */
        img.data[p * 4 + 3] = 1.0f;   /* R */
    }
    const char *path = in_dir(s, "named.png");
    assert_int_equal(st_image_save_png(path, &img, &err), ST_OK);
    int w, h, n;
    unsigned char *px = stbi_load(path, &w, &h, &n, 3);
    assert_non_null(px);
    assert_int_equal(px[0], 255);
    assert_int_equal(px[1], 188);
    assert_int_equal(px[2], 0);
    stbi_image_free(px);

    const char *two[2] = {"X", "Y"};
    st_image small;
    assert_int_equal(st_image_create(&small, 2, 2, 2, two, &err), ST_OK);
    st_error e2 = {ST_OK, ""};
    assert_int_equal(st_image_save_png(in_dir(s, "two.png"), &small, &e2), ST_ERR_FORMAT);
    assert_message_names(&e2, s->path);
    st_image_free(&small);
    st_image_free(&img);
}

static void png_load_bad_input_names_file(void **state)
{
    scratch *s = *state;
    st_image img;
    st_error err = {ST_OK, ""};
    char path[256];
    snprintf(path, sizeof path, "%s", in_dir(s, "fake.png"));
    write_bytes(path, "\x89PNG\r\n\x1a\n garbage", 17);
    assert_int_equal(st_image_load(path, &img, &err), ST_ERR_FORMAT);
    assert_message_names(&err, path);
    assert_null(img.data);
    st_error e2 = {ST_OK, ""};
    assert_int_equal(st_image_load(in_dir(s, "absent.png"), &img, &e2), ST_ERR_IO);
    assert_message_names(&e2, s->path);
}

/* ---- choosing the format ------------------------------------------------------------------- */

static void save_picks_format_by_extension(void **state)
{
    scratch *s = *state;
    st_image img, back;
    st_error err = {ST_OK, ""};
    assert_int_equal(st_image_create(&img, 3, 2, 3, NULL, &err), ST_OK);
    img.data[0] = 0.25f;
    assert_int_equal(st_image_save(in_dir(s, "upper.EXR"), &img, NULL, 0, &err), ST_OK);
    assert_int_equal(st_image_load(s->path, &back, &err), ST_OK);
    assert_true(back.data[st_image_find_channel(&back, "R")] == 0.25f);
    st_image_free(&back);
    assert_int_equal(st_image_save(in_dir(s, "mixed.Png"), &img, NULL, 0, &err), ST_OK);
    unsigned char sig[8];
    FILE *f = fopen(s->path, "rb");
    assert_non_null(f);
    assert_int_equal(fread(sig, 1, 8, f), 8);
    fclose(f);
    assert_memory_equal(sig, "\x89PNG\r\n\x1a\n", 8);

    const char *bad[2] = {"x.tiff", "noext"};
    for (int i = 0; i < 2; i++) {
        st_error e2 = {ST_OK, ""};
        assert_int_equal(st_image_save(in_dir(s, bad[i]), &img, NULL, 0, &e2), ST_ERR_USAGE);
        assert_message_names(&e2, s->path);
        st_error e3 = {ST_OK, ""};
        assert_int_equal(st_image_load(s->path, &back, &e3), ST_ERR_USAGE);
    }
    st_error e4 = {ST_OK, ""};
    assert_int_equal(st_image_save(in_dir(s, "y.tiff"), &img, NULL, 0, &e4), ST_ERR_USAGE);
    assert_non_null(strstr(e4.msg, "'.tiff'"));
    char listing[1024];
    assert_int_equal(folder_entries(s->dir, listing, sizeof listing), 2); /* upper.EXR, mixed.Png */
    st_image_free(&img);
}

int main(void)
{
#define T(name) cmocka_unit_test_setup_teardown(name, setup_dir, teardown_dir)
    const struct CMUnitTest tests[] = {
        T(create_defaults_names_and_zeroes),
        T(create_rejects_bad_arguments),
        T(exr_round_trip_float_bits_exact),
        T(exr_roundtrip_render_three_channels),
        T(exr_round_trip_uint_exact),
        T(exr_channels_come_back_sorted_by_name),
        T(exr_attributes_round_trip),
        T(exr_reserved_attribute_fails_leaves_nothing),
        T(exr_loads_tiled_half_with_offset_window),
        T(exr_data_window_round_trips),
        T(exr_load_malformed_names_file),
        T(exr_load_missing_file_is_io_error),
        T(exr_unwritable_path_fails_leaves_nothing),
        T(exr_failed_save_keeps_existing_file),
        T(srgb_encode_known_points),
        T(srgb_quantize_known_codes),
        T(srgb_decode_inverts_encode),
        T(png_codes_match_srgb_formula),
        T(png_round_trip_within_quantisation_bound),
        T(png_takes_rgb_by_name),
        T(png_load_bad_input_names_file),
        T(png_unwritable_path_fails_leaves_nothing),
        T(save_picks_format_by_extension),
    };
#undef T
    return cmocka_run_group_tests_name("image", tests, NULL, NULL);
}
