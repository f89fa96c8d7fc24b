/* test_plot.c — guards src/lab/plot.c: every picture is a valid PNG of the stated
 * size (read back with cairo), ink lands where st_plot_data_rect says the data
 * maps (a point, a line, a marker, a heat-map cell of the expected viridis
 * colour), and failed saves leave nothing behind. Pixel colours are compared
 * with a tolerance of a few levels of 255 for anti-aliasing and rounding. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <cairo/cairo.h>
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "scratch.h"
#include "st_plot.h"

/* ---- helpers -------------------------------------------------------------------- */

typedef struct rgb {
    int r, g, b;
} rgb;

/* Reads a PNG back with cairo and checks its size. */
static cairo_surface_t *load_png(const char *path, int w, int h)
{
    cairo_surface_t *s = cairo_image_surface_create_from_png(path);
    assert_int_equal(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
    assert_int_equal(cairo_image_surface_get_width(s), w);
    assert_int_equal(cairo_image_surface_get_height(s), h);
    return s;
}

static rgb pixel(cairo_surface_t *s, double x, double y)
{
    int ix = (int)x, iy = (int)y;
    assert_true(ix >= 0 && ix < cairo_image_surface_get_width(s));
    assert_true(iy >= 0 && iy < cairo_image_surface_get_height(s));
    const unsigned char *row =
        cairo_image_surface_get_data(s) + (size_t)iy * cairo_image_surface_get_stride(s);
    uint32_t v = ((const uint32_t *)row)[ix];
    rgb c = {(int)(v >> 16) & 255, (int)(v >> 8) & 255, (int)v & 255};
    return c;
}

static int is_white(rgb c)
{
    return c.r == 255 && c.g == 255 && c.b == 255;
}

static void assert_rgb_near(rgb c, int r, int g, int b, int tol)
{
    if (abs(c.r - r) > tol || abs(c.g - g) > tol || abs(c.b - b) > tol)
        fail_msg("pixel (%d,%d,%d), expected (%d,%d,%d) +- %d", c.r, c.g, c.b, r, g, b, tol);
}

/* 1 when a pixel of column x (or the one left of it) between rows y0 < y1 is
 * not white: finds dashed lines whatever the dash phase. */
static int column_has_ink(cairo_surface_t *s, double x, double y0, double y1)
{
    for (double y = y0; y <= y1; y += 1.0)
        if (!is_white(pixel(s, x, y)) || !is_white(pixel(s, x - 1.0, y)))
            return 1;
    return 0;
}

/* Pixel of data (x, y) in a panel whose data rectangle is r (y up). */
static double px(st_plot_rect r, double lo, double hi, double x)
{
    return r.x + (x - lo) / (hi - lo) * r.w;
}

static double py(st_plot_rect r, double lo, double hi, double y)
{
    return r.y + r.h - (y - lo) / (hi - lo) * r.h;
}

/* ---- scatter ---------------------------------------------------------------------- */

/* One point at (0.7, 0.3): its pixel is inked in the point colour, an empty
 * spot of the unit square stays white, the file has the stated size. */
static void plot_scatter_point_where_data_maps(void **state)
{
    (void)state;
    st_error err = {0};
    const float pts[2] = {0.7f, 0.3f};
    st_plot_scatter sc = {.xlabel = "x", .ylabel = "y", .title = "one point", .points = pts, .count = 1, .point_radius = 5.0};
    const char *path = scratch_path("scatter.png");
    assert_int_equal(st_plot_save_scatter(path, &sc, 320, 300, &err), ST_OK);
    cairo_surface_t *s = load_png(path, 320, 300);
    st_plot_panel panel = {.kind = ST_PLOT_SCATTER, .scatter = &sc};
    st_plot_rect r = st_plot_data_rect(&panel, 320, 300);
    assert_true(fabs(r.w - r.h) < 1e-9); /* the unit square stays square */
    rgb c = pixel(s, px(r, 0, 1, 0.7), py(r, 0, 1, 0.3));
    assert_rgb_near(c, 31, 61, 153, 3); /* (0.12, 0.24, 0.60) */
    assert_true(is_white(pixel(s, px(r, 0, 1, 0.3), py(r, 0, 1, 0.6))));
    cairo_surface_destroy(s);
}

/* Strata grid lines at i/nx and the toroidal border are drawn. */
static void plot_scatter_strata_and_tile_border(void **state)
{
    (void)state;
    st_error err = {0};
    const float pts[4] = {0.1f, 0.1f, 0.9f, 0.9f};
    st_plot_scatter sc = {.xlabel = "x", .ylabel = "y", .points = pts, .count = 2, .strata_nx = 4, .strata_ny = 2,
                          .toroidal = 1};
    const char *path = scratch_path("strata.png");
    assert_int_equal(st_plot_save_scatter(path, &sc, 400, 400, &err), ST_OK);
    cairo_surface_t *s = load_png(path, 400, 400);
    st_plot_panel panel = {.kind = ST_PLOT_SCATTER, .scatter = &sc};
    st_plot_rect r = st_plot_data_rect(&panel, 400, 400);
    /* grid lines x = 1/4 and y = 1/2, 1 px wide: the pixel holding the line
     * centre is at least half covered */
    assert_false(is_white(pixel(s, px(r, 0, 1, 0.25), py(r, 0, 1, 0.6))));
    assert_false(is_white(pixel(s, px(r, 0, 1, 0.6), py(r, 0, 1, 0.5))));
    /* the dashed orange tile border along the top edge */
    int orange = 0;
    for (double x = r.x + 2; x < r.x + r.w - 2; x += 1.0) {
        rgb c = pixel(s, x, r.y);
        orange |= c.r > 180 && c.g < 150 && c.b < 100;
    }
    assert_true(orange);
    /* no line at x = 0.6, y = 0.6 */
    assert_true(is_white(pixel(s, px(r, 0, 1, 0.6), py(r, 0, 1, 0.6))));
    cairo_surface_destroy(s);
}

/* ---- heat map ----------------------------------------------------------------------- */

/* 2 x 2 values 0, 1 (bottom row), 2, 3 (top row): the smallest value takes
 * viridis(0) = (68, 1, 84), the largest viridis(1) = (253, 231, 37), and row 0
 * is the bottom row; green rises with the value. */
static void plot_heatmap_cells_in_viridis(void **state)
{
    (void)state;
    st_error err = {0};
    const double v[4] = {0.0, 1.0, 2.0, 3.0};
    st_plot_heatmap hm = {.xlabel = "x", .ylabel = "y", .title = "2x2", .values = v, .width = 2, .height = 2};
    const char *path = scratch_path("heat.png");
    assert_int_equal(st_plot_save_heatmap(path, &hm, 400, 300, &err), ST_OK);
    cairo_surface_t *s = load_png(path, 400, 300);
    st_plot_panel panel = {.kind = ST_PLOT_HEATMAP, .heatmap = &hm};
    st_plot_rect r = st_plot_data_rect(&panel, 400, 300);
    rgb c00 = pixel(s, px(r, 0, 2, 0.5), py(r, 0, 2, 0.5));
    rgb c10 = pixel(s, px(r, 0, 2, 1.5), py(r, 0, 2, 0.5));
    rgb c01 = pixel(s, px(r, 0, 2, 0.5), py(r, 0, 2, 1.5));
    rgb c11 = pixel(s, px(r, 0, 2, 1.5), py(r, 0, 2, 1.5));
    assert_rgb_near(c00, 68, 1, 84, 2);
    assert_rgb_near(c11, 253, 231, 37, 2);
    assert_true(c00.g < c10.g && c10.g < c01.g && c01.g < c11.g);
    cairo_surface_destroy(s);
}

/* log10 scale: 1, 10, 100, 1000 are evenly spaced colours, 0 is grey. */
static void plot_heatmap_log_scale(void **state)
{
    (void)state;
    st_error err = {0};
    const double v[5] = {1.0, 10.0, 1000.0, 0.0, 100.0};
    st_plot_heatmap hm = {.xlabel = "x", .ylabel = "y", .values = v, .width = 5, .height = 1, .log10 = 1,
                          .colorbar_label = "log10 P"};
    const char *path = scratch_path("log.png");
    assert_int_equal(st_plot_save_heatmap(path, &hm, 500, 200, &err), ST_OK);
    cairo_surface_t *s = load_png(path, 500, 200);
    st_plot_panel panel = {.kind = ST_PLOT_HEATMAP, .heatmap = &hm};
    st_plot_rect r = st_plot_data_rect(&panel, 500, 200);
    double y = py(r, 0, 1, 0.5);
    assert_rgb_near(pixel(s, px(r, 0, 5, 0.5), y), 68, 1, 84, 2);     /* log 0: t = 0 */
    assert_rgb_near(pixel(s, px(r, 0, 5, 2.5), y), 253, 231, 37, 2);  /* log 3: t = 1 */
    assert_rgb_near(pixel(s, px(r, 0, 5, 3.5), y), 153, 153, 153, 1); /* 0: grey */
    /* t = 1/3 lies between control points 2 (0.25) and 3 (0.375): 2/3 of the way */
    rgb c = pixel(s, px(r, 0, 5, 1.5), y);
    double t = 2.0 / 3.0;
    assert_rgb_near(c, (int)lround(255 * (0.253935 + t * (0.206756 - 0.253935))),
                    (int)lround(255 * (0.265254 + t * (0.371758 - 0.265254))),
                    (int)lround(255 * (0.529983 + t * (0.553117 - 0.529983))), 2);
    cairo_surface_destroy(s);
}

/* ---- line plots ------------------------------------------------------------------ */

/* A red horizontal line y = 0.5 over x in [0, 1] and a marker at x = 0.25,
 * on explicit axes [0,1] x [0,1]. */
static void plot_lines_series_and_marker(void **state)
{
    (void)state;
    st_error err = {0};
    const double x[2] = {0.0, 1.0}, y[2] = {0.5, 0.5};
    st_plot_series se = {.name = "flat", .x = x, .y = y, .n = 2, .color = 0xff0000, .width = 4};
    st_plot_marker mk = {.x = 0.25, .label = "Nyquist"};
    st_plot_lines pl = {.title = "t", .xlabel = "x", .ylabel = "y", .series = &se,
                        .series_count = 1, .markers = &mk, .marker_count = 1,
                        .xmin = 0, .xmax = 1, .ymin = 0, .ymax = 1, .legend_left = 1};
    const char *path = scratch_path("lines.png");
    assert_int_equal(st_plot_save_lines(path, &pl, 480, 360, &err), ST_OK);
    cairo_surface_t *s = load_png(path, 480, 360);
    st_plot_panel panel = {.kind = ST_PLOT_LINES, .lines = &pl};
    st_plot_rect r = st_plot_data_rect(&panel, 480, 360);
    assert_rgb_near(pixel(s, px(r, 0, 1, 0.7), py(r, 0, 1, 0.5)), 255, 0, 0, 3);
    /* the dashed marker: ink somewhere along x = 0.25 in y 0.6..0.9 */
    assert_true(column_has_ink(s, px(r, 0, 1, 0.25), py(r, 0, 1, 0.9), py(r, 0, 1, 0.6)));
    /* nothing at (0.7, 0.7): no series, no marker, no grid line (ticks are
     * at multiples of 0.2) */
    assert_true(is_white(pixel(s, px(r, 0, 1, 0.7), py(r, 0, 1, 0.7))));
    cairo_surface_destroy(s);
}

/* A legend outside the axes, on the right, whose names are long: the
 * axes make room for it, so that its box and text end inside the picture
 * (the last columns stay white) and the names' ink lies right of the axes. */
static void plot_lines_outside_legend_fits(void **state)
{
    (void)state;
    st_error err = {0};
    const double x[2] = {1.0, 100.0}, y[2] = {1.0, 0.01};
    st_plot_series se[2] = {
        {.name = "uniform (slope -1.62, flat from 16 spp on)", .x = x, .y = y, .n = 2, .width = 2},
        {.name = "a second, shorter name", .x = x, .y = y, .n = 2, .width = 2, .dashed = 1}};
    st_plot_lines pl = {.xlabel = "x", .ylabel = "y", .series = se, .series_count = 2,
                        .flags = ST_PLOT_LOG_X | ST_PLOT_LOG_Y, .legend_outside = 1};
    const char *path = scratch_path("legend.png");
    assert_int_equal(st_plot_save_lines(path, &pl, 600, 400, &err), ST_OK);
    cairo_surface_t *s = load_png(path, 600, 400);
    st_plot_panel panel = {.kind = ST_PLOT_LINES, .lines = &pl};
    st_plot_rect r = st_plot_data_rect(&panel, 600, 400);
    assert_true(r.w > 0.3 * 600); /* the axes keep most of the room */
    for (double xx = 595.0; xx < 600.0; xx += 1.0)
        assert_false(column_has_ink(s, xx, 0.0, 399.0));
    assert_true(column_has_ink(s, r.x + r.w + 0.5 * (600.0 - r.x - r.w), r.y, r.y + 60.0));
    cairo_surface_destroy(s);
}

/* Log-log axes: the line y = x through (1,1) .. (100,100) passes the centre
 * of the data rectangle at (10, 10); points <= 0 are skipped, not fatal. */
static void plot_lines_log_axes(void **state)
{
    (void)state;
    st_error err = {0};
    const double x[4] = {0.0, 1.0, 10.0, 100.0}, y[4] = {-1.0, 1.0, 10.0, 100.0};
    st_plot_series se = {.x = x, .y = y, .n = 4, .color = 0x0000ff, .width = 4};
    st_plot_lines pl = {.xlabel = "x", .ylabel = "y", .series = &se, .series_count = 1, .flags = ST_PLOT_LOG_X | ST_PLOT_LOG_Y,
                        .xmin = 1, .xmax = 100, .ymin = 1, .ymax = 100};
    const char *path = scratch_path("loglog.png");
    assert_int_equal(st_plot_save_lines(path, &pl, 300, 300, &err), ST_OK);
    cairo_surface_t *s = load_png(path, 300, 300);
    st_plot_panel panel = {.kind = ST_PLOT_LINES, .lines = &pl};
    st_plot_rect r = st_plot_data_rect(&panel, 300, 300);
    assert_rgb_near(pixel(s, r.x + 0.5 * r.w, r.y + 0.5 * r.h), 0, 0, 255, 3);
    /* (14.5, 25.1): off the line and off every grid line (10, 20, 30) */
    assert_true(is_white(pixel(s, r.x + 0.58 * r.w, r.y + 0.3 * r.h)));
    cairo_surface_destroy(s);
}

/* Two panels side by side: twice as wide, each panel drawn at its offset. */
static void plot_row_panels_side_by_side(void **state)
{
    (void)state;
    st_error err = {0};
    const double x[2] = {0.0, 1.0}, y0[2] = {0.5, 0.5}, y1[2] = {0.2, 0.2};
    st_plot_series a = {.x = x, .y = y0, .n = 2, .color = 0x00aa00, .width = 4};
    st_plot_series b = {.x = x, .y = y1, .n = 2, .color = 0xaa00aa, .width = 4};
    st_plot_lines la = {.xlabel = "x", .ylabel = "y", .series = &a, .series_count = 1, .xmin = 0, .xmax = 1, .ymax = 1};
    st_plot_lines lb = {.xlabel = "x", .ylabel = "y", .series = &b, .series_count = 1, .xmin = 0, .xmax = 1, .ymax = 1};
    st_plot_panel panels[2] = {{.kind = ST_PLOT_LINES, .lines = &la},
                               {.kind = ST_PLOT_LINES, .lines = &lb}};
    const char *path = scratch_path("row.png");
    assert_int_equal(st_plot_save_row(path, panels, 2, 250, 200, &err), ST_OK);
    cairo_surface_t *s = load_png(path, 500, 200);
    st_plot_rect r = st_plot_data_rect(&panels[0], 250, 200);
    assert_rgb_near(pixel(s, px(r, 0, 1, 0.5), py(r, 0, 1, 0.5)), 0, 170, 0, 3);
    assert_rgb_near(pixel(s, 250 + px(r, 0, 1, 0.5), py(r, 0, 1, 0.2)), 170, 0, 170, 3);
    assert_true(is_white(pixel(s, 250 + px(r, 0, 1, 0.5), py(r, 0, 1, 0.5))));
    assert_true(is_white(pixel(s, px(r, 0, 1, 0.5), py(r, 0, 1, 0.3))));
    cairo_surface_destroy(s);
}

/* ---- failures ------------------------------------------------------------------------ */

/* A folder that does not exist: ST_ERR_IO naming the path, no file. */
static void plot_unwritable_path_fails_and_leaves_nothing(void **state)
{
    (void)state;
    st_error err = {0};
    const float pts[2] = {0.5f, 0.5f};
    st_plot_scatter sc = {.xlabel = "x", .ylabel = "y", .points = pts, .count = 1};
    char path[512];
    snprintf(path, sizeof path, "%s/missing/out.png", scratch_dir);
    assert_int_equal(st_plot_save_scatter(path, &sc, 128, 128, &err), ST_ERR_IO);
    assert_non_null(strstr(err.msg, path));
    assert_int_equal(access(path, F_OK), -1);
    assert_int_equal(scratch_entries(NULL, 0), 0);
}

/* A folder as the destination is refused by name before the PNG is written
 * (st_outfile never replaces what is not a regular file): nothing is left
 * beside it and the folder survives. (A rename that fails at commit is
 * test_outfile.c's outfile_failed_rename_removes_temporary.) */
static void plot_failed_rename_removes_temporary(void **state)
{
    (void)state;
    st_error err = {0};
    const double v[1] = {1.0};
    st_plot_heatmap hm = {.xlabel = "x", .ylabel = "y", .values = v, .width = 1, .height = 1};
    const char *path = scratch_path("taken");
    assert_int_equal(mkdir(path, 0755), 0);
    assert_int_equal(st_plot_save_heatmap(path, &hm, 128, 128, &err), ST_ERR_IO);
    assert_non_null(strstr(err.msg, "is a folder"));
    assert_int_equal(scratch_entries(NULL, 0), 1); /* just the folder */
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_true(S_ISDIR(st.st_mode));
}

/* A bad description is refused before anything is written; an existing file
 * of that name is untouched. */
static void plot_bad_description_keeps_existing_file(void **state)
{
    (void)state;
    st_error err = {0};
    const char *path = scratch_path("keep.png");
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs("old", f);
    fclose(f);
    st_plot_heatmap hm = {.xlabel = "x", .ylabel = "y", .values = NULL, .width = 4, .height = 4};
    assert_int_equal(st_plot_save_heatmap(path, &hm, 128, 128, &err), ST_ERR_USAGE);
    char buf[8] = {0};
    f = fopen(path, "rb");
    assert_non_null(f);
    assert_int_equal(fread(buf, 1, sizeof buf, f), 3);
    fclose(f);
    assert_string_equal(buf, "old");
    assert_int_equal(scratch_entries(NULL, 0), 1);
}

static void plot_rejects_bad_arguments(void **state)
{
    (void)state;
    st_error err = {0};
    const float pts[2] = {0.5f, 0.5f};
    const double x[2] = {1, 2};
    st_plot_scatter sc = {.xlabel = "x", .ylabel = "y", .points = pts, .count = 1};
    st_plot_series se = {.x = x, .y = NULL, .n = 2};
    st_plot_lines bad_series = {.xlabel = "x", .ylabel = "y", .series = &se, .series_count = 1};
    st_plot_series ok = {.x = x, .y = x, .n = 2};
    st_plot_lines bad_log = {.xlabel = "x", .ylabel = "y", .series = &ok, .series_count = 1, .flags = ST_PLOT_LOG_X,
                             .xmin = 0, .xmax = 10};
    st_plot_panel none[1] = {{.kind = ST_PLOT_SCATTER, .scatter = NULL}};
    const char *path = scratch_path("never.png");

    assert_int_equal(st_plot_save_scatter(path, &sc, 10, 128, &err), ST_ERR_USAGE);
    st_error_clear(&err);
    assert_int_equal(st_plot_save_scatter(path, &sc, 128, ST_PLOT_MAX_SIZE + 1, &err),
                     ST_ERR_USAGE);
    st_error_clear(&err);
    assert_int_equal(st_plot_save_scatter(NULL, &sc, 128, 128, &err), ST_ERR_USAGE);
    st_error_clear(&err);
    assert_int_equal(st_plot_save_row(path, none, 1, 128, 128, &err), ST_ERR_USAGE);
    st_error_clear(&err);
    assert_int_equal(st_plot_save_row(path, none, 0, 128, 128, &err), ST_ERR_USAGE);
    st_error_clear(&err);
    assert_int_equal(st_plot_save_lines(path, &bad_series, 128, 128, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "series 0"));
    st_error_clear(&err);
    assert_int_equal(st_plot_save_lines(path, &bad_log, 128, 128, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "log x"));
    st_error_clear(&err);
    sc.stride = 1;
    assert_int_equal(st_plot_save_scatter(path, &sc, 128, 128, &err), ST_ERR_USAGE);
    st_error_clear(&err);
    /* every kind of plot names both axes */
    st_plot_scatter untitled = {.points = pts, .count = 1, .ylabel = "y"};
    assert_int_equal(st_plot_save_scatter(path, &untitled, 128, 128, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "no x-axis title"));
    st_error_clear(&err);
    const double v[4] = {1, 2, 3, 4};
    st_plot_heatmap hm = {.values = v, .width = 2, .height = 2, .xlabel = "k_x"};
    assert_int_equal(st_plot_save_heatmap(path, &hm, 128, 128, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "no y-axis title"));
    st_error_clear(&err);
    st_plot_lines lines = {.series = &ok, .series_count = 1, .xlabel = "", .ylabel = "y"};
    assert_int_equal(st_plot_save_lines(path, &lines, 128, 128, &err), ST_ERR_USAGE);
    assert_non_null(strstr(err.msg, "no x-axis title"));
    assert_int_equal(scratch_entries(NULL, 0), 0);
}

/* Degenerate but valid input draws without failing: no points, a constant
 * heat map, a line plot without series (automatic ranges). */
static void plot_degenerate_inputs_still_draw(void **state)
{
    (void)state;
    st_error err = {0};
    st_plot_scatter sc = {.xlabel = "x", .ylabel = "y", .title = "empty"};
    const double v[4] = {2, 2, 2, 2};
    st_plot_heatmap hm = {.xlabel = "x", .ylabel = "y", .values = v, .width = 2, .height = 2,
                          .x0 = -1, .x1 = 1, .y0 = -1, .y1 = 1};
    st_plot_lines pl = {.xlabel = "x", .ylabel = "y", .title = "nothing", .flags = ST_PLOT_LOG_Y};
    st_plot_panel panels[3] = {{.kind = ST_PLOT_SCATTER, .scatter = &sc},
                               {.kind = ST_PLOT_HEATMAP, .heatmap = &hm},
                               {.kind = ST_PLOT_LINES, .lines = &pl}};
    const char *path = scratch_path("degenerate.png");
    assert_int_equal(st_plot_save_row(path, panels, 3, 200, 160, &err), ST_OK);
    cairo_surface_t *s = load_png(path, 600, 160);
    cairo_surface_destroy(s);
}

/* cairo and fontconfig keep font caches for the life of the process, which
 * LeakSanitizer (make test SANITIZE=1) reports as leaks. Release them at exit:
 * cairo's own reset, then fontconfig's FcFini, looked up at run time because
 * strata links cairo only. */
static void release_font_caches(void)
{
    cairo_debug_reset_static_data();
    void *fc = dlopen("libfontconfig.so.1", RTLD_LAZY);
    if (fc) {
        void (*fini)(void) = (void (*)(void))dlsym(fc, "FcFini");
        if (fini)
            fini();
        dlclose(fc);
    }
}

int main(void)
{
#define T(name) cmocka_unit_test_setup_teardown(name, scratch_make, scratch_remove)
    const struct CMUnitTest tests[] = {
        T(plot_scatter_point_where_data_maps),
        T(plot_scatter_strata_and_tile_border),
        T(plot_heatmap_cells_in_viridis),
        T(plot_heatmap_log_scale),
        T(plot_lines_series_and_marker),
        T(plot_lines_log_axes),
        T(plot_lines_outside_legend_fits),
        T(plot_row_panels_side_by_side),
        T(plot_unwritable_path_fails_and_leaves_nothing),
        T(plot_failed_rename_removes_temporary),
        T(plot_bad_description_keeps_existing_file),
        T(plot_rejects_bad_arguments),
        T(plot_degenerate_inputs_still_draw),
    };
#undef T
    int failed = cmocka_run_group_tests_name("plot", tests, NULL, NULL);
    release_font_caches();
    return failed;
}
