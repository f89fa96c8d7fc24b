/* plot.c — scatter plots, heat maps and line plots drawn with cairo into PNG
 * files (see include/st_plot.h for the contract).
 *
 * Invariant: a picture either lands complete under its final name or not at
 * all: cairo encodes it into an st_outfile (st_outfile.h), the temporary
 * beside the destination that is renamed over it only when complete; every
 * failure removes the temporary. Layout is a pure function of the panel
 * description and its pixel size (st_plot_data_rect), so tests can find
 * where a point or a line must have been drawn. */
#include "st_plot.h"
#include "st_outfile.h"

#include <cairo/cairo.h>
#include <cairo/cairo-pdf.h>
#include <cairo/cairo-svg.h>
#include <strings.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#define ST_PI 3.14159265358979323846

/* ---- layout ----------------------------------------------------------------- */

/* Font size in pixels for a panel: about 1/36 of its shorter side. */
static double font_size(uint32_t w, uint32_t h)
{
    double fs = (w < h ? w : h) / 36.0;
    return fs < 9.0 ? 9.0 : (fs > 16.0 ? 16.0 : fs);
}

/* Axes box inside the margins: title above, tick labels and axis label
 * below and to the left; `right` pixels reserved on the right. */
static st_plot_rect margins(uint32_t w, uint32_t h, double fs, double right)
{
    st_plot_rect r;
    r.x = 5.5 * fs;
    r.y = 2.4 * fs;
    r.w = w - r.x - right;
    r.h = h - r.y - 3.4 * fs;
    if (r.w < 1.0)
        r.w = 1.0;
    if (r.h < 1.0)
        r.h = 1.0;
    return r;
}

/* Largest rectangle of aspect a (width / height) centred in r. */
static st_plot_rect fit_aspect(st_plot_rect r, double a)
{
    st_plot_rect f = r;
    if (r.w / r.h > a) {
        f.w = r.h * a;
        f.x = r.x + 0.5 * (r.w - f.w);
    } else {
        f.h = r.w / a;
        f.y = r.y + 0.5 * (r.h - f.h);
    }
    return f;
}

/* The legend box's width: its longest name at 0.9 fs, its line sample and
 * padding; *rows: the named series. */
static double legend_width(cairo_t *cr, const st_plot_lines *p, double fs, uint32_t *rows)
{
    double wmax = 0.0;
    *rows = 0;
    cairo_save(cr);
    cairo_set_font_size(cr, 0.9 * fs);
    for (uint32_t s = 0; s < p->series_count; ++s)
        if (p->series[s].name) {
            cairo_text_extents_t te;
            cairo_text_extents(cr, p->series[s].name, &te);
            wmax = te.x_advance > wmax ? te.x_advance : wmax;
            ++*rows;
        }
    cairo_restore(cr);
    return wmax + 3.6 * fs;
}

/* The margin an outside legend takes on the right: its box and a gap either
 * side, measured on a scratch surface (the layout is asked before there is
 * one to draw on), and never more than half the panel. */
static double outside_legend_margin(const st_plot_lines *p, uint32_t width, double fs)
{
    cairo_surface_t *scratch = cairo_image_surface_create(CAIRO_FORMAT_A8, 1, 1);
    cairo_t *cr = cairo_create(scratch);
    uint32_t rows;
    double m = legend_width(cr, p, fs, &rows) + 1.2 * fs;
    cairo_destroy(cr);
    cairo_surface_destroy(scratch);
    return m > 0.5 * width ? 0.5 * width : m;
}

st_plot_rect st_plot_data_rect(const st_plot_panel *panel, uint32_t width, uint32_t height)
{
    double fs = font_size(width, height);
    switch (panel->kind) {
    case ST_PLOT_SCATTER:
        return fit_aspect(margins(width, height, fs, 1.5 * fs), 1.0);
    case ST_PLOT_HEATMAP: {
        const st_plot_heatmap *hm = panel->heatmap;
        double a = (hm && hm->height) ? (double)hm->width / hm->height : 1.0;
        return fit_aspect(margins(width, height, fs, 8.0 * fs), a);
    }
    case ST_PLOT_LINES:
    default:
        return margins(width, height, fs,
                       panel->lines && panel->lines->legend_outside
                           ? outside_legend_margin(panel->lines, width, fs)
                           : 1.5 * fs);
    }
}

/* ---- drawing helpers ---------------------------------------------------------- */

static void set_rgb(cairo_t *cr, uint32_t rgb)
{
    cairo_set_source_rgb(cr, ((rgb >> 16) & 255) / 255.0, ((rgb >> 8) & 255) / 255.0,
                         (rgb & 255) / 255.0);
}

/* Text with its anchor at fraction (ax, ay) of its ink box: (0.5, 0.5) centres. */
static void draw_text(cairo_t *cr, double x, double y, const char *text, double ax, double ay)
{
    cairo_text_extents_t te;
    cairo_text_extents(cr, text, &te);
    cairo_move_to(cr, x - te.x_bearing - ax * te.width, y - te.y_bearing - ay * te.height);
    cairo_show_text(cr, text);
}

static void draw_title(cairo_t *cr, const char *title, uint32_t w, double fs)
{
    if (!title)
        return;
    cairo_save(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_font_size(cr, 1.15 * fs);
    draw_text(cr, 0.5 * w, 1.1 * fs, title, 0.5, 0.5);
    cairo_restore(cr);
}

/* "Nice" ticks (1, 2, 5 x 10^k steps) covering [lo, hi], at most ~max + 1. */
static int nice_ticks(double lo, double hi, int max, double *ticks, double *step_out)
{
    double span = hi - lo;
    if (!(span > 0.0) || !isfinite(span))
        return 0;
    double raw = span / max, mag = pow(10.0, floor(log10(raw))), step = 10.0 * mag;
    if (raw <= mag)
        step = mag;
    else if (raw <= 2.0 * mag)
        step = 2.0 * mag;
    else if (raw <= 5.0 * mag)
        step = 5.0 * mag;
    int n = 0;
    for (double k = ceil(lo / step - 1e-9); k * step <= hi + 1e-9 * span && n < 2 * max + 2; ++k)
        ticks[n++] = fabs(k * step) < 1e-9 * step ? 0.0 : k * step;
    *step_out = step;
    return n;
}

/* Label of a tick at a multiple of step: just enough decimals. */
static void format_tick(double v, double step, char *buf, size_t size)
{
    double a = fabs(v);
    if (a != 0.0 && (a >= 1e5 || a < 1e-3)) {
        snprintf(buf, size, "%.3g", v);
        return;
    }
    int dec = step >= 1.0 ? 0 : (int)ceil(-log10(step) - 1e-9);
    snprintf(buf, size, "%.*f", dec > 6 ? 6 : dec, v);
}

/* An axis maps data values (log10 first, when logarithmic) onto pixels. */
typedef struct axis {
    double lo, hi; /* data range (log10 of it when log) */
    int log;
    double p0, p1; /* pixels of lo and hi */
} axis;

static double axis_map(const axis *a, double v)
{
    double t = a->log ? log10(v) : v;
    return a->p0 + (t - a->lo) / (a->hi - a->lo) * (a->p1 - a->p0);
}

/* Tick positions and labels of an axis; returns the count. Log axes tick the
 * decades, plus 2 and 5 times them when fewer than three decades show. */
typedef struct tick {
    double v;
    char label[32];
    int major;
} tick;

static int axis_ticks(const axis *a, tick *out, int max_out)
{
    int n = 0;
    if (!a->log) {
        double t[32], step;
        int k = nice_ticks(a->lo, a->hi, 6, t, &step);
        for (int i = 0; i < k && n < max_out; ++i, ++n) {
            out[n].v = t[i];
            out[n].major = 1;
            format_tick(t[i], step, out[n].label, sizeof out[n].label);
        }
        return n;
    }
    /* Decades; with more than 10 of them, every k-th only and no minor ticks. */
    double span = a->hi - a->lo, every = span > 10.0 ? ceil(span / 8.0) : 1.0;
    int few = span < 3.0;
    for (double d = floor(a->lo); d <= ceil(a->hi) && n < max_out; ++d) {
        if (fmod(fabs(d), every) != 0.0)
            continue;
        for (int m = 1; m <= (every > 1.0 ? 1 : 9) && n < max_out; ++m) {
            double e = d + log10((double)m);
            if (e < a->lo - 1e-9 || e > a->hi + 1e-9)
                continue;
            int labelled = m == 1 || (few && (m == 2 || m == 5));
            out[n].v = pow(10.0, e);
            out[n].major = labelled;
            if (labelled)
                snprintf(out[n].label, sizeof out[n].label, "%g", out[n].v);
            else
                out[n].label[0] = '\0';
            ++n;
        }
    }
    return n;
}

/* Frame, ticks, tick labels and grid lines of an axes box. */
static void draw_axes(cairo_t *cr, st_plot_rect r, const axis *ax, const axis *ay, double fs,
                      int grid)
{
    tick t[96];
    cairo_save(cr);
    cairo_set_font_size(cr, fs);
    cairo_set_line_width(cr, 1.0);
    for (int pass = 0; pass < 2; ++pass) {
        const axis *a = pass == 0 ? ax : ay;
        int n = axis_ticks(a, t, 96);
        for (int i = 0; i < n; ++i) {
            double p = axis_map(a, t[i].v);
            double len = t[i].major ? 0.45 * fs : 0.25 * fs;
            if (grid) {
                cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
                if (pass == 0) {
                    cairo_move_to(cr, p, r.y);
                    cairo_line_to(cr, p, r.y + r.h);
                } else {
                    cairo_move_to(cr, r.x, p);
                    cairo_line_to(cr, r.x + r.w, p);
                }
                cairo_stroke(cr);
            }
            cairo_set_source_rgb(cr, 0, 0, 0);
            if (pass == 0) {
                cairo_move_to(cr, p, r.y + r.h);
                cairo_line_to(cr, p, r.y + r.h + len);
                cairo_stroke(cr);
                if (t[i].label[0])
                    draw_text(cr, p, r.y + r.h + 0.7 * fs, t[i].label, 0.5, 0.0);
            } else {
                cairo_move_to(cr, r.x, p);
                cairo_line_to(cr, r.x - len, p);
                cairo_stroke(cr);
                if (t[i].label[0])
                    draw_text(cr, r.x - 0.7 * fs, p, t[i].label, 1.0, 0.5);
            }
        }
    }
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_rectangle(cr, r.x, r.y, r.w, r.h);
    cairo_stroke(cr);
    cairo_restore(cr);
}

static void draw_axis_labels(cairo_t *cr, st_plot_rect r, const char *xlabel, const char *ylabel,
                             double fs)
{
    cairo_save(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_font_size(cr, fs);
    if (xlabel)
        draw_text(cr, r.x + 0.5 * r.w, r.y + r.h + 2.5 * fs, xlabel, 0.5, 0.5);
    if (ylabel) {
        cairo_translate(cr, 1.0 * fs, r.y + 0.5 * r.h);
        cairo_rotate(cr, -ST_PI / 2);
        draw_text(cr, 0, 0, ylabel, 0.5, 0.5);
    }
    cairo_restore(cr);
}

/* ---- scatter ------------------------------------------------------------------ */

static st_status check_scatter(const st_plot_scatter *s, st_error *err)
{
    if (!s)
        return st_fail(err, ST_ERR_USAGE, "plot: scatter panel without a description");
    if (s->count > 0 && !s->points)
        return st_fail(err, ST_ERR_USAGE, "plot: scatter: %u points but points is NULL",
                       s->count);
    if (s->stride == 1)
        return st_fail(err, ST_ERR_USAGE, "plot: scatter: stride 1 < 2 floats per point");
    return ST_OK;
}

static void draw_scatter(cairo_t *cr, const st_plot_scatter *s, uint32_t w, uint32_t h)
{
    st_plot_panel panel = {.kind = ST_PLOT_SCATTER, .scatter = s};
    st_plot_rect r = st_plot_data_rect(&panel, w, h);
    double fs = font_size(w, h);
    axis ax = {0.0, 1.0, 0, r.x, r.x + r.w}, ay = {0.0, 1.0, 0, r.y + r.h, r.y};

    cairo_save(cr);
    cairo_set_line_width(cr, 1.0);
    cairo_set_source_rgb(cr, 0.75, 0.75, 0.75);
    for (uint32_t i = 1; i < s->strata_nx; ++i) {
        double x = axis_map(&ax, (double)i / s->strata_nx);
        cairo_move_to(cr, x, r.y);
        cairo_line_to(cr, x, r.y + r.h);
    }
    for (uint32_t j = 1; j < s->strata_ny; ++j) {
        double y = axis_map(&ay, (double)j / s->strata_ny);
        cairo_move_to(cr, r.x, y);
        cairo_line_to(cr, r.x + r.w, y);
    }
    cairo_stroke(cr);

    uint32_t stride = s->stride ? s->stride : 2;
    double pr = s->point_radius > 0.0 ? s->point_radius
                                      : 0.35 * r.w / sqrt(s->count > 0 ? (double)s->count : 1.0);
    if (s->point_radius <= 0.0)
        pr = pr < 0.8 ? 0.8 : (pr > 4.0 ? 4.0 : pr);
    cairo_rectangle(cr, r.x, r.y, r.w, r.h);
    cairo_clip(cr);
    cairo_set_source_rgb(cr, 0.12, 0.24, 0.60);
    for (uint32_t i = 0; i < s->count; ++i) {
        const float *p = s->points + (size_t)i * stride;
        cairo_new_sub_path(cr);
        cairo_arc(cr, axis_map(&ax, p[0]), axis_map(&ay, p[1]), pr, 0.0, 2.0 * ST_PI);
        if (i % 4096 == 4095) /* keep paths short */
            cairo_fill(cr);
    }
    cairo_fill(cr);
    cairo_restore(cr);

    draw_axes(cr, r, &ax, &ay, fs, 0);
    draw_axis_labels(cr, r, s->xlabel, s->ylabel, fs);
    if (s->toroidal) {
        double dash[2] = {0.6 * fs, 0.4 * fs};
        cairo_save(cr);
        cairo_set_source_rgb(cr, 0.85, 0.33, 0.1);
        cairo_set_line_width(cr, 1.5);
        cairo_set_dash(cr, dash, 2, 0.0);
        cairo_rectangle(cr, r.x, r.y, r.w, r.h);
        cairo_stroke(cr);
        cairo_set_font_size(cr, 0.85 * fs);
        draw_text(cr, r.x + r.w, r.y + r.h + 2.5 * fs, "toroidal tile: edges wrap", 1.0, 0.5);
        cairo_restore(cr);
    }
    draw_title(cr, s->title, w, fs);
}

/* ---- heat map ----------------------------------------------------------------- */

/* Viridis (van der Walt & Smith, matplotlib 2015) at t = 0, 1/8, ..., 1,
 * interpolated linearly between these control points. */
static const double VIRIDIS[9][3] = {
    {0.267004, 0.004874, 0.329415}, {0.282623, 0.140926, 0.457517}, {0.253935, 0.265254, 0.529983},
    {0.206756, 0.371758, 0.553117}, {0.163625, 0.471133, 0.558148}, {0.127568, 0.566949, 0.550556},
    {0.134692, 0.658636, 0.517649}, {0.266941, 0.748751, 0.440573}, {0.993248, 0.906157, 0.143936}};

static void viridis(double t, double rgb[3])
{
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    double s = t * 8.0;
    int i = s >= 8.0 ? 7 : (int)s;
    double f = s - i;
    for (int c = 0; c < 3; ++c)
        rgb[c] = VIRIDIS[i][c] + f * (VIRIDIS[i + 1][c] - VIRIDIS[i][c]);
}

static st_status check_heatmap(const st_plot_heatmap *hm, st_error *err)
{
    if (!hm)
        return st_fail(err, ST_ERR_USAGE, "plot: heat map panel without a description");
    if (!hm->values || hm->width == 0 || hm->height == 0)
        return st_fail(err, ST_ERR_USAGE, "plot: heat map: no values (%u x %u)", hm->width,
                       hm->height);
    if (hm->width > ST_PLOT_MAX_SIZE || hm->height > ST_PLOT_MAX_SIZE)
        return st_fail(err, ST_ERR_USAGE, "plot: heat map: %u x %u values exceed %u per side",
                       hm->width, hm->height, ST_PLOT_MAX_SIZE);
    return ST_OK;
}

/* The value coloured for v: log10(v) when asked, NaN when not drawable. */
static double heat_value(const st_plot_heatmap *hm, double v)
{
    if (!isfinite(v))
        return NAN;
    if (hm->log10)
        return v > 0.0 ? log10(v) : NAN;
    return v;
}

static void heat_range(const st_plot_heatmap *hm, double *lo, double *hi)
{
    if (hm->vmin < hm->vmax) {
        *lo = hm->vmin;
        *hi = hm->vmax;
        return;
    }
    *lo = INFINITY;
    *hi = -INFINITY;
    for (size_t i = 0; i < (size_t)hm->width * hm->height; ++i) {
        double v = heat_value(hm, hm->values[i]);
        if (v < *lo)
            *lo = v;
        if (v > *hi)
            *hi = v;
    }
    if (!(*lo <= *hi)) { /* nothing finite */
        *lo = 0.0;
        *hi = 1.0;
    }
    if (*lo == *hi) {
        *lo -= 0.5;
        *hi += 0.5;
    }
}

/* The values as a width x height image, row 0 at the bottom. */
static cairo_surface_t *heat_image(const st_plot_heatmap *hm, double lo, double hi)
{
    cairo_surface_t *img = cairo_image_surface_create(CAIRO_FORMAT_RGB24, (int)hm->width,
                                                      (int)hm->height);
    if (cairo_surface_status(img) != CAIRO_STATUS_SUCCESS)
        return img;
    cairo_surface_flush(img);
    unsigned char *data = cairo_image_surface_get_data(img);
    int stride = cairo_image_surface_get_stride(img);
    for (uint32_t j = 0; j < hm->height; ++j) {
        uint32_t *row = (uint32_t *)(data + (size_t)(hm->height - 1 - j) * stride);
        for (uint32_t i = 0; i < hm->width; ++i) {
            double v = heat_value(hm, hm->values[(size_t)j * hm->width + i]), rgb[3] = {.6, .6, .6};
            if (!isnan(v))
                viridis((v - lo) / (hi - lo), rgb);
            row[i] = (uint32_t)lround(rgb[0] * 255) << 16 | (uint32_t)lround(rgb[1] * 255) << 8 |
                     (uint32_t)lround(rgb[2] * 255);
        }
    }
    cairo_surface_mark_dirty(img);
    return img;
}

static void draw_colorbar(cairo_t *cr, const st_plot_heatmap *hm, st_plot_rect r, double lo,
                          double hi, double fs)
{
    st_plot_rect bar = {r.x + r.w + 1.2 * fs, r.y, 1.2 * fs, r.h};
    cairo_pattern_t *grad = cairo_pattern_create_linear(0, bar.y + bar.h, 0, bar.y);
    for (int i = 0; i <= 8; ++i)
        cairo_pattern_add_color_stop_rgb(grad, i / 8.0, VIRIDIS[i][0], VIRIDIS[i][1],
                                         VIRIDIS[i][2]);
    cairo_save(cr);
    cairo_rectangle(cr, bar.x, bar.y, bar.w, bar.h);
    cairo_set_source(cr, grad);
    cairo_fill(cr);
    cairo_pattern_destroy(grad);

    axis a = {lo, hi, 0, bar.y + bar.h, bar.y};
    double t[32], step;
    int n = nice_ticks(lo, hi, 6, t, &step);
    char label[32];
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1.0);
    cairo_set_font_size(cr, 0.9 * fs);
    for (int i = 0; i < n; ++i) {
        double p = axis_map(&a, t[i]);
        cairo_move_to(cr, bar.x + bar.w, p);
        cairo_line_to(cr, bar.x + bar.w + 0.4 * fs, p);
        cairo_stroke(cr);
        format_tick(t[i], step, label, sizeof label);
        draw_text(cr, bar.x + bar.w + 0.6 * fs, p, label, 0.0, 0.5);
    }
    cairo_rectangle(cr, bar.x, bar.y, bar.w, bar.h);
    cairo_stroke(cr);
    const char *text = hm->colorbar_label ? hm->colorbar_label : (hm->log10 ? "log10" : NULL);
    if (text) {
        cairo_translate(cr, bar.x + bar.w + 4.8 * fs, bar.y + 0.5 * bar.h);
        cairo_rotate(cr, -ST_PI / 2);
        draw_text(cr, 0, 0, text, 0.5, 0.5);
    }
    cairo_restore(cr);
}

static st_status draw_heatmap(cairo_t *cr, const st_plot_heatmap *hm, uint32_t w, uint32_t h,
                              st_error *err)
{
    st_plot_panel panel = {.kind = ST_PLOT_HEATMAP, .heatmap = hm};
    st_plot_rect r = st_plot_data_rect(&panel, w, h);
    double fs = font_size(w, h), lo, hi;
    heat_range(hm, &lo, &hi);
    cairo_surface_t *img = heat_image(hm, lo, hi);
    if (cairo_surface_status(img) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(img);
        return st_fail(err, ST_ERR_NOMEM, "plot: heat map: out of memory for %u x %u values",
                       hm->width, hm->height);
    }
    cairo_save(cr);
    cairo_rectangle(cr, r.x, r.y, r.w, r.h);
    cairo_clip(cr);
    cairo_translate(cr, r.x, r.y);
    cairo_scale(cr, r.w / hm->width, r.h / hm->height);
    cairo_set_source_surface(cr, img, 0, 0);
    cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
    cairo_paint(cr);
    cairo_restore(cr);
    cairo_surface_destroy(img);

    if (hm->x0 != hm->x1 && hm->y0 != hm->y1) { /* cell centres at the given coordinates */
        double dx = (hm->x1 - hm->x0) / (hm->width > 1 ? hm->width - 1 : 1);
        double dy = (hm->y1 - hm->y0) / (hm->height > 1 ? hm->height - 1 : 1);
        axis ax = {hm->x0 - 0.5 * dx, hm->x1 + 0.5 * dx, 0, r.x, r.x + r.w};
        axis ay = {hm->y0 - 0.5 * dy, hm->y1 + 0.5 * dy, 0, r.y + r.h, r.y};
        draw_axes(cr, r, &ax, &ay, fs, 0);
    } else {
        cairo_save(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_set_line_width(cr, 1.0);
        cairo_rectangle(cr, r.x, r.y, r.w, r.h);
        cairo_stroke(cr);
        cairo_restore(cr);
    }
    draw_axis_labels(cr, r, hm->xlabel, hm->ylabel, fs);
    draw_colorbar(cr, hm, r, lo, hi, fs);
    draw_title(cr, hm->title, w, fs);
    return ST_OK;
}

/* ---- line plot ------------------------------------------------------------------ */

/* Tableau 10, the default colour cycle of matplotlib. */
static const uint32_t PALETTE[10] = {0x1f77b4, 0xff7f0e, 0x2ca02c, 0xd62728, 0x9467bd,
                                     0x8c564b, 0xe377c2, 0x7f7f7f, 0xbcbd22, 0x17becf};

static st_status check_lines(const st_plot_lines *p, st_error *err)
{
    if (!p)
        return st_fail(err, ST_ERR_USAGE, "plot: line panel without a description");
    if (p->series_count > 0 && !p->series)
        return st_fail(err, ST_ERR_USAGE, "plot: lines: %u series but series is NULL",
                       p->series_count);
    if (p->marker_count > 0 && !p->markers)
        return st_fail(err, ST_ERR_USAGE, "plot: lines: %u markers but markers is NULL",
                       p->marker_count);
    for (uint32_t i = 0; i < p->series_count; ++i)
        if (p->series[i].n > 0 && (!p->series[i].x || !p->series[i].y))
            return st_fail(err, ST_ERR_USAGE, "plot: lines: series %u has NULL x or y", i);
    if ((p->flags & ST_PLOT_LOG_X) && p->xmin < p->xmax && !(p->xmin > 0.0))
        return st_fail(err, ST_ERR_USAGE, "plot: lines: log x axis needs xmin > 0, not %g",
                       p->xmin);
    if ((p->flags & ST_PLOT_LOG_Y) && p->ymin < p->ymax && !(p->ymin > 0.0))
        return st_fail(err, ST_ERR_USAGE, "plot: lines: log y axis needs ymin > 0, not %g",
                       p->ymin);
    return ST_OK;
}

/* A value is drawable when finite (and positive on a log axis). */
static int drawable(double v, int log)
{
    return isfinite(v) && (!log || v > 0.0);
}

/* The axis range: given, or the data's (log10'd) extent, padded by `pad`. */
static void fit_axis(axis *a, const st_plot_lines *p, int is_x, double pad)
{
    double given_lo = is_x ? p->xmin : p->ymin, given_hi = is_x ? p->xmax : p->ymax;
    a->log = (p->flags & (is_x ? ST_PLOT_LOG_X : ST_PLOT_LOG_Y)) != 0;
    if (given_lo < given_hi) {
        a->lo = a->log ? log10(given_lo) : given_lo;
        a->hi = a->log ? log10(given_hi) : given_hi;
        return;
    }
    double lo = INFINITY, hi = -INFINITY;
    for (uint32_t s = 0; s < p->series_count; ++s)
        for (uint32_t i = 0; i < p->series[s].n; ++i) {
            double v = is_x ? p->series[s].x[i] : p->series[s].y[i];
            double o = is_x ? p->series[s].y[i] : p->series[s].x[i];
            if (!drawable(v, a->log) || !isfinite(o))
                continue;
            v = a->log ? log10(v) : v;
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
    for (uint32_t m = 0; is_x && m < p->marker_count; ++m)
        if (drawable(p->markers[m].x, a->log)) {
            double v = a->log ? log10(p->markers[m].x) : p->markers[m].x;
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
    if (!(lo <= hi)) {
        lo = 0.0;
        hi = 1.0;
    } else if (lo == hi) {
        double d = a->log ? 0.5 : (lo != 0.0 ? 0.1 * fabs(lo) : 1.0);
        lo -= d;
        hi += d;
    }
    a->lo = lo - pad * (hi - lo);
    a->hi = hi + pad * (hi - lo);
}

static uint32_t series_color(const st_plot_series *s, uint32_t index)
{
    return s->color ? s->color : PALETTE[index % 10];
}

/* Vertical bars from y - yerr to y + yerr with short caps; on a log axis a bar whose lower
 * end is not positive runs to the axis' bottom. */
static void draw_error_bars(cairo_t *cr, const st_plot_series *s, const axis *ax, const axis *ay)
{
    for (uint32_t i = 0; i < s->n; ++i) {
        double e = s->yerr[i];
        if (!drawable(s->x[i], ax->log) || !drawable(s->y[i], ay->log) || !(e > 0))
            continue;
        double px = axis_map(ax, s->x[i]), top = axis_map(ay, s->y[i] + e);
        double bottom = drawable(s->y[i] - e, ay->log) ? axis_map(ay, s->y[i] - e) : ay->p0;
        cairo_move_to(cr, px, bottom);
        cairo_line_to(cr, px, top);
        cairo_move_to(cr, px - 4.0, top);
        cairo_line_to(cr, px + 4.0, top);
        cairo_move_to(cr, px - 4.0, bottom);
        cairo_line_to(cr, px + 4.0, bottom);
    }
    cairo_save(cr);
    cairo_set_line_width(cr, 1.2);
    cairo_stroke(cr);
    cairo_restore(cr);
}

static void draw_series(cairo_t *cr, const st_plot_series *s, uint32_t color, const axis *ax,
                        const axis *ay)
{
    cairo_save(cr);
    set_rgb(cr, color);
    cairo_set_line_width(cr, s->width > 0.0 ? s->width : 2.0);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    if (s->dashed) {
        double dash[2] = {6.0, 4.0};
        cairo_set_dash(cr, dash, 2, 0.0);
    }
    if (s->yerr)
        draw_error_bars(cr, s, ax, ay);
    if (s->style != ST_PLOT_STYLE_POINTS) {
        int pen = 0;
        for (uint32_t i = 0; i < s->n; ++i) {
            if (!drawable(s->x[i], ax->log) || !drawable(s->y[i], ay->log)) {
                pen = 0;
                continue;
            }
            double px = axis_map(ax, s->x[i]), py = axis_map(ay, s->y[i]);
            if (pen)
                cairo_line_to(cr, px, py);
            else
                cairo_move_to(cr, px, py);
            pen = 1;
        }
        cairo_stroke(cr);
    }
    if (s->style != ST_PLOT_STYLE_LINE) {
        double pr = 1.5 * (s->width > 0.0 ? s->width : 2.0);
        for (uint32_t i = 0; i < s->n; ++i)
            if (drawable(s->x[i], ax->log) && drawable(s->y[i], ay->log)) {
                cairo_new_sub_path(cr);
                cairo_arc(cr, axis_map(ax, s->x[i]), axis_map(ay, s->y[i]), pr, 0, 2 * ST_PI);
            }
        cairo_fill(cr);
    }
    cairo_restore(cr);
}

static void draw_markers(cairo_t *cr, const st_plot_lines *p, st_plot_rect r, const axis *ax,
                         double fs)
{
    double dash[2] = {0.5 * fs, 0.35 * fs};
    cairo_save(cr);
    cairo_set_font_size(cr, 0.9 * fs);
    for (uint32_t m = 0; m < p->marker_count; ++m) {
        if (!drawable(p->markers[m].x, ax->log))
            continue;
        double x = axis_map(ax, p->markers[m].x);
        if (x < r.x - 0.5 || x > r.x + r.w + 0.5)
            continue;
        cairo_set_source_rgb(cr, 0.35, 0.35, 0.35);
        cairo_set_line_width(cr, 1.5);
        cairo_set_dash(cr, dash, 2, 0.0);
        cairo_move_to(cr, x, r.y);
        cairo_line_to(cr, x, r.y + r.h);
        cairo_stroke(cr);
        if (p->markers[m].label) {
            cairo_set_dash(cr, NULL, 0, 0.0);
            /* near the bottom, clear of the legend at the top */
            draw_text(cr, x + 0.3 * fs, r.y + r.h - 0.4 * fs - 1.3 * fs * m, p->markers[m].label,
                      0.0, 1.0);
        }
    }
    cairo_restore(cr);
}

static void draw_legend(cairo_t *cr, const st_plot_lines *p, st_plot_rect r, double fs)
{
    uint32_t rows = 0;
    double bw = legend_width(cr, p, fs, &rows);
    if (rows == 0)
        return;
    cairo_save(cr);
    cairo_set_font_size(cr, 0.9 * fs);
    double line = 1.4 * fs, bh = rows * line + 0.6 * fs;
    double bx = p->legend_outside ? r.x + r.w + 0.6 * fs
                : p->legend_left  ? r.x + 0.6 * fs
                                  : r.x + r.w - bw - 0.6 * fs,
           by = r.y + (p->legend_outside ? 0.0 : 0.6 * fs);
    cairo_rectangle(cr, bx, by, bw, bh);
    cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
    cairo_set_line_width(cr, 1.0);
    cairo_stroke(cr);
    uint32_t row = 0;
    for (uint32_t s = 0; s < p->series_count; ++s) {
        if (!p->series[s].name)
            continue;
        double y = by + 0.3 * fs + (row + 0.5) * line;
        set_rgb(cr, series_color(&p->series[s], s));
        cairo_set_line_width(cr, 2.0);
        double dash[2] = {6.0, 4.0};
        cairo_set_dash(cr, dash, p->series[s].dashed ? 2 : 0, 0.0);
        cairo_move_to(cr, bx + 0.5 * fs, y);
        cairo_line_to(cr, bx + 2.5 * fs, y);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        draw_text(cr, bx + 3.0 * fs, y, p->series[s].name, 0.0, 0.5);
        ++row;
    }
    cairo_restore(cr);
}

static void draw_lines(cairo_t *cr, const st_plot_lines *p, uint32_t w, uint32_t h)
{
    st_plot_panel panel = {.kind = ST_PLOT_LINES, .lines = p};
    st_plot_rect r = st_plot_data_rect(&panel, w, h);
    double fs = font_size(w, h);
    axis ax = {0}, ay = {0};
    fit_axis(&ax, p, 1, 0.0);
    fit_axis(&ay, p, 0, 0.05);
    ax.p0 = r.x;
    ax.p1 = r.x + r.w;
    ay.p0 = r.y + r.h;
    ay.p1 = r.y;

    draw_axes(cr, r, &ax, &ay, fs, 1);
    cairo_save(cr);
    cairo_rectangle(cr, r.x, r.y, r.w, r.h);
    cairo_clip(cr);
    if (!ay.log && ay.lo < 0.0 && ay.hi > 0.0) { /* the zero line */
        cairo_set_source_rgb(cr, 0.5, 0.5, 0.5);
        cairo_set_line_width(cr, 1.0);
        cairo_move_to(cr, r.x, axis_map(&ay, 0.0));
        cairo_line_to(cr, r.x + r.w, axis_map(&ay, 0.0));
        cairo_stroke(cr);
    }
    for (uint32_t s = 0; s < p->series_count; ++s)
        draw_series(cr, &p->series[s], series_color(&p->series[s], s), &ax, &ay);
    draw_markers(cr, p, r, &ax, fs);
    cairo_restore(cr);
    draw_legend(cr, p, r, fs);
    draw_axis_labels(cr, r, p->xlabel, p->ylabel, fs);
    draw_title(cr, p->title, w, fs);
}

/* ---- files ---------------------------------------------------------------------- */

/* cairo's write function: the outfile keeps the errno of a failure for commit to report. */
static cairo_status_t sink_write(void *closure, const unsigned char *data, unsigned int length)
{
    return st_outfile_write(closure, data, length) == 0 ? CAIRO_STATUS_SUCCESS
                                                        : CAIRO_STATUS_WRITE_ERROR;
}

/* Encodes the surface to path through an st_outfile. */
static st_status save_png(cairo_surface_t *surface, const char *path, st_error *err)
{
    st_outfile *out = NULL;
    if (st_outfile_open(path, &out, err) != ST_OK)
        return err ? err->status : ST_ERR_IO;
    cairo_status_t cs = cairo_surface_write_to_png_stream(surface, sink_write, out);
    if (cs == CAIRO_STATUS_SUCCESS)
        return st_outfile_commit(out, err);
    int e = st_outfile_error(out);
    st_outfile_abort(out);
    if (cs == CAIRO_STATUS_NO_MEMORY)
        return st_fail(err, ST_ERR_NOMEM, "%s: out of memory encoding PNG", path);
    return st_fail(err, ST_ERR_IO, "%s: cannot write (%s)", path,
                   e ? strerror(e) : cairo_status_to_string(cs));
}

/* Every plot names both axes: without them a reader has to guess what is
 * plotted against what (an image's pixels, a frequency, a sample count). */
static st_status check_titles(const char *xlabel, const char *ylabel, uint32_t i, st_error *err)
{
    if (!xlabel || !xlabel[0] || !ylabel || !ylabel[0])
        return st_fail(err, ST_ERR_USAGE, "plot: panel %u: no %s-axis title", i,
                       !xlabel || !xlabel[0] ? "x" : "y");
    return ST_OK;
}

static st_status check_panel(const st_plot_panel *p, uint32_t i, st_error *err)
{
    switch (p->kind) {
    case ST_PLOT_SCATTER:
        return check_scatter(p->scatter, err) ||
               check_titles(p->scatter->xlabel, p->scatter->ylabel, i, err);
    case ST_PLOT_HEATMAP:
        return check_heatmap(p->heatmap, err) ||
               check_titles(p->heatmap->xlabel, p->heatmap->ylabel, i, err);
    case ST_PLOT_LINES:
        return check_lines(p->lines, err) ||
               check_titles(p->lines->xlabel, p->lines->ylabel, i, err);
    }
    return st_fail(err, ST_ERR_USAGE, "plot: panel %u: unknown kind %d", i, (int)p->kind);
}

static st_status check_row(const char *path, const st_plot_panel *panels, uint32_t count,
                           uint32_t pw, uint32_t ph, st_error *err)
{
    if (!path || !path[0])
        return st_fail(err, ST_ERR_USAGE, "plot: no output path");
    if (!panels || count == 0 || count > ST_PLOT_MAX_PANELS)
        return st_fail(err, ST_ERR_USAGE, "%s: need 1..%u panels, got %u", path,
                       ST_PLOT_MAX_PANELS, panels ? count : 0);
    if (pw < ST_PLOT_MIN_SIZE || ph < ST_PLOT_MIN_SIZE || ph > ST_PLOT_MAX_SIZE ||
        (uint64_t)pw * count > ST_PLOT_MAX_SIZE)
        return st_fail(err, ST_ERR_USAGE, "%s: image %u x %u is outside %u..%u pixels per side",
                       path, pw * count, ph, ST_PLOT_MIN_SIZE, ST_PLOT_MAX_SIZE);
    for (uint32_t i = 0; i < count; ++i)
        if (check_panel(&panels[i], i, err) != ST_OK)
            return err ? err->status : ST_ERR_USAGE;
    return ST_OK;
}

/* Draws the panels side by side on any cairo surface. */
static st_status draw_row(cairo_t *cr, const st_plot_panel *panels, uint32_t count,
                          uint32_t panel_width, uint32_t panel_height, st_error *err)
{
    st_status s = ST_OK;
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    for (uint32_t i = 0; i < count && s == ST_OK; ++i) {
        cairo_save(cr);
        cairo_translate(cr, (double)i * panel_width, 0.0);
        cairo_rectangle(cr, 0, 0, panel_width, panel_height);
        cairo_clip(cr);
        if (panels[i].kind == ST_PLOT_SCATTER)
            draw_scatter(cr, panels[i].scatter, panel_width, panel_height);
        else if (panels[i].kind == ST_PLOT_HEATMAP)
            s = draw_heatmap(cr, panels[i].heatmap, panel_width, panel_height, err);
        else
            draw_lines(cr, panels[i].lines, panel_width, panel_height);
        cairo_restore(cr);
    }
    return s;
}

/* The file type of path: 1 PDF, 2 SVG, else 0, PNG (as before there were three). */
static int file_type(const char *path)
{
    const char *dot = strrchr(path, '.');
    return dot && !strcasecmp(dot, ".pdf") ? 1 : dot && !strcasecmp(dot, ".svg") ? 2 : 0;
}

/* A PDF or SVG drawn into out and finished there. */
static st_status save_vector(const char *path, const st_plot_panel *panels, uint32_t count,
                             uint32_t pw, uint32_t ph, st_error *err)
{
    st_outfile *out = NULL;
    if (st_outfile_open(path, &out, err) != ST_OK)
        return err ? err->status : ST_ERR_IO;
    double w = (double)pw * count;
    cairo_surface_t *sf = file_type(path) == 1
                              ? cairo_pdf_surface_create_for_stream(sink_write, out, w, ph)
                              : cairo_svg_surface_create_for_stream(sink_write, out, w, ph);
    cairo_t *cr = cairo_create(sf);
    st_status s = draw_row(cr, panels, count, pw, ph, err);
    cairo_destroy(cr);
    cairo_surface_finish(sf);
    cairo_status_t cs = cairo_surface_status(sf);
    cairo_surface_destroy(sf);
    if (s == ST_OK && cs != CAIRO_STATUS_SUCCESS) {
        int e = st_outfile_error(out);
        s = st_fail(err, cs == CAIRO_STATUS_NO_MEMORY ? ST_ERR_NOMEM : ST_ERR_IO,
                    "%s: cannot write (%s)", path, e ? strerror(e) : cairo_status_to_string(cs));
    }
    if (s != ST_OK) {
        st_outfile_abort(out);
        return s;
    }
    return st_outfile_commit(out, err);
}

st_status st_plot_save_row(const char *path, const st_plot_panel *panels, uint32_t count,
                           uint32_t panel_width, uint32_t panel_height, st_error *err)
{
    st_status s = check_row(path, panels, count, panel_width, panel_height, err);
    if (s != ST_OK)
        return s;
    if (file_type(path) > 0)
        return save_vector(path, panels, count, panel_width, panel_height, err);
    cairo_surface_t *surface = cairo_image_surface_create(
        CAIRO_FORMAT_RGB24, (int)(panel_width * count), (int)panel_height);
    cairo_t *cr = cairo_create(surface);
    if (cairo_status(cr) != CAIRO_STATUS_SUCCESS) {
        s = st_fail(err, ST_ERR_NOMEM, "%s: out of memory for a %u x %u image", path,
                    panel_width * count, panel_height);
        goto done;
    }
    s = draw_row(cr, panels, count, panel_width, panel_height, err);
    if (s == ST_OK && cairo_status(cr) != CAIRO_STATUS_SUCCESS)
        s = st_fail(err, ST_ERR_NOMEM, "%s: drawing failed: %s", path,
                    cairo_status_to_string(cairo_status(cr)));
    if (s == ST_OK) {
        cairo_surface_flush(surface);
        s = save_png(surface, path, err);
    }
done:
    cairo_destroy(cr);
    cairo_surface_destroy(surface);
    return s;
}

st_status st_plot_save_scatter(const char *path, const st_plot_scatter *plot, uint32_t width,
                               uint32_t height, st_error *err)
{
    st_plot_panel p = {.kind = ST_PLOT_SCATTER, .scatter = plot};
    return st_plot_save_row(path, &p, 1, width, height, err);
}

st_status st_plot_save_heatmap(const char *path, const st_plot_heatmap *plot, uint32_t width,
                               uint32_t height, st_error *err)
{
    st_plot_panel p = {.kind = ST_PLOT_HEATMAP, .heatmap = plot};
    return st_plot_save_row(path, &p, 1, width, height, err);
}

st_status st_plot_save_lines(const char *path, const st_plot_lines *plot, uint32_t width,
                             uint32_t height, st_error *err)
{
    st_plot_panel p = {.kind = ST_PLOT_LINES, .lines = plot};
    return st_plot_save_row(path, &p, 1, width, height, err);
}
