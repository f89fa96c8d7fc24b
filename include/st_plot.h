/* st_plot.h — the laboratory's pictures: scatter plots of sample patterns,
 * heat maps (periodograms), and line plots (filter profiles, frequency
 * responses, convergence curves), drawn with cairo and saved as PDF or SVG
 * when the path ends in .pdf or .svg (any case), else as PNG.
 *
 * A picture is one or more panels side by side. Each panel kind is described
 * by a plain struct that borrows the caller's arrays for the duration of the
 * call; nothing here allocates anything the caller must free. Zero-initialise
 * a description and set what you need: every field's zero value means "none"
 * or "automatic".
 *
 * Files are written to a temporary name in the destination folder and renamed
 * into place, so a failed save leaves no partial file and no temporary (an
 * existing file of the same name survives a failed save).
 * Errors: ST_ERR_USAGE for a bad description (the message names the field),
 * ST_ERR_IO when the file cannot be created, written or renamed (the message
 * starts with the path), ST_ERR_NOMEM when cairo runs out of memory. Nothing
 * here prints.
 *
 * Coordinates: data y grows upwards in every panel (row 0 of a heat map is its
 * bottom row); pixel coordinates (st_plot_rect) grow right and down, as in the
 * PNG. Tests: tests/unit/test_plot.c. */
#ifndef ST_PLOT_H
#define ST_PLOT_H

#include "st_error.h"

#include <stdint.h>

#define ST_PLOT_MIN_SIZE 64u    /* smallest panel side, pixels */
#define ST_PLOT_MAX_SIZE 8192u  /* largest image side, pixels */
#define ST_PLOT_MAX_PANELS 8u

typedef enum st_plot_kind { ST_PLOT_SCATTER, ST_PLOT_HEATMAP, ST_PLOT_LINES } st_plot_kind;

/* Points in the unit square (first two floats of each point; x right, y up). */
typedef struct st_plot_scatter {
    const char *title;               /* NULL: none */
    const float *points;             /* count * stride floats */
    uint32_t count, stride;          /* stride 0 means 2 */
    uint32_t strata_nx, strata_ny;   /* > 0: draw the nx x ny stratum grid */
    int toroidal;                    /* nonzero: dashed border, "toroidal tile" note */
    double point_radius;             /* pixels; <= 0: automatic from count */
    const char *xlabel, *ylabel;     /* axis titles, required: a plot without them is refused */
} st_plot_scatter;

/* A width x height array of doubles as an image with a colour bar (viridis,
 * approximated by 9 control points of matplotlib's table). */
typedef struct st_plot_heatmap {
    const char *title, *colorbar_label; /* NULL: none */
    const double *values;               /* row-major, width * height; row 0 at the bottom */
    uint32_t width, height;
    int log10;                          /* nonzero: colour by log10(v); v <= 0 or NaN: grey */
    double vmin, vmax;                  /* colour range (in log10 units when log10);
                                           vmin >= vmax: the data's finite min..max */
    double x0, x1, y0, y1;              /* data coordinates of the first and last column
                                           (row) centres, for axis ticks; x0 == x1: none */
    const char *xlabel, *ylabel;        /* axis titles, required (as a scatter's) */
} st_plot_heatmap;

typedef enum st_plot_style {
    ST_PLOT_STYLE_LINE = 0,
    ST_PLOT_STYLE_POINTS,
    ST_PLOT_STYLE_LINE_POINTS
} st_plot_style;

/* One named curve. Non-finite values (and values <= 0 on a log axis) break
 * the line. */
typedef struct st_plot_series {
    const char *name;    /* legend entry; NULL: not in the legend */
    const double *x, *y; /* n values each */
    uint32_t n;
    st_plot_style style;
    uint32_t color;      /* 0xRRGGBB; 0: the next colour of the built-in palette */
    double width;        /* line width, pixels; <= 0: 2 */
    const double *yerr;  /* n half-lengths of vertical error bars (y +- yerr); NULL: none */
    int dashed;          /* nonzero: a dashed line (guides) */
} st_plot_series;

/* A labelled vertical line at data x (e.g. "Nyquist"). */
typedef struct st_plot_marker {
    double x;
    const char *label; /* NULL: none */
} st_plot_marker;

#define ST_PLOT_LOG_X 1u
#define ST_PLOT_LOG_Y 2u

typedef struct st_plot_lines {
    const char *title, *xlabel, *ylabel;   /* title NULL: none; axis titles required */
    const st_plot_series *series;
    uint32_t series_count;
    const st_plot_marker *markers;
    uint32_t marker_count;
    uint32_t flags;                        /* ST_PLOT_LOG_X | ST_PLOT_LOG_Y */
    double xmin, xmax, ymin, ymax;         /* axis ranges; min >= max: fit the data */
    int legend_left;                       /* nonzero: legend top-left instead of top-right */
    int legend_outside;                    /* nonzero: legend right of the axes, off the data
                                              (the axes narrow to make room) */
} st_plot_lines;

/* One panel: `kind` says which pointer is read. */
typedef struct st_plot_panel {
    st_plot_kind kind;
    const st_plot_scatter *scatter;
    const st_plot_heatmap *heatmap;
    const st_plot_lines *lines;
} st_plot_panel;

/* A rectangle in pixels: left, top, width, height. */
typedef struct st_plot_rect {
    double x, y, w, h;
} st_plot_rect;

/* Saves `count` panels side by side: the PNG is count * panel_width wide and
 * panel_height high (e.g. a filter's profile next to its frequency response).
 * panel_width, panel_height in [ST_PLOT_MIN_SIZE, ST_PLOT_MAX_SIZE], count in
 * [1, ST_PLOT_MAX_PANELS]. */
st_status st_plot_save_row(const char *path, const st_plot_panel *panels, uint32_t count,
                           uint32_t panel_width, uint32_t panel_height, st_error *err);

/* One-panel shorthands of st_plot_save_row. */
st_status st_plot_save_scatter(const char *path, const st_plot_scatter *plot, uint32_t width,
                               uint32_t height, st_error *err);
st_status st_plot_save_heatmap(const char *path, const st_plot_heatmap *plot, uint32_t width,
                               uint32_t height, st_error *err);
st_status st_plot_save_lines(const char *path, const st_plot_lines *plot, uint32_t width,
                             uint32_t height, st_error *err);

/* The pixel rectangle of a panel's data area (the unit square of a scatter
 * plot, the image of a heat map, the axes box of a line plot) for a panel of
 * width x height pixels whose left edge is at x = 0. Data maps linearly (or
 * logarithmically) onto it: x = lo at r.x, x = hi at r.x + r.w; y = lo at
 * r.y + r.h (the bottom), y = hi at r.y. A heat map's cell (i, j) covers
 * [r.x + i*r.w/width, ...) with row j counted from the bottom. */
st_plot_rect st_plot_data_rect(const st_plot_panel *panel, uint32_t width, uint32_t height);

#endif
