/* sheet.c — comparison sheets (see st_sheet.h). */
#include "st_sheet.h"
#include "st_outfile.h"

#include <cairo/cairo.h>
#include <cairo/cairo-pdf.h>
#include <cairo/cairo-svg.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define MARGIN 12.0
#define FONT 13.0
#define CAPTION 43.0 /* two caption lines under each image (whole pixels: images stay sharp) */
#define TITLE 29.0
#define MAX_SIDE 16384u

typedef struct layout {
    double scale, inset_scale; /* image and inset magnification, whole pixels */
    double cell_w, image_h, inset_h, cell_h, title_h;
} layout;

static layout layout_of(const st_sheet *s, uint32_t iw, uint32_t ih)
{
    layout l;
    l.scale = iw >= 256 ? 1.0 : (double)(256 / iw); /* cells at least 256 wide */
    l.cell_w = iw * l.scale;
    l.image_h = ih * l.scale;
    l.inset_scale = s->inset[2] ? (double)(uint32_t)(l.cell_w / s->inset[2]) : 0;
    if (l.inset_scale < 1 && s->inset[2])
        l.inset_scale = 1;
    l.inset_h = s->inset[2] ? s->inset[3] * l.inset_scale : 0;
    l.cell_h = l.image_h + (l.inset_h > 0 ? l.inset_h + 4.0 : 0) + CAPTION;
    l.title_h = s->title ? TITLE : 0;
    return l;
}

void st_sheet_size(const st_sheet *s, uint32_t iw, uint32_t ih, uint32_t *w, uint32_t *h)
{
    layout l = layout_of(s, iw, ih);
    *w = (uint32_t)(MARGIN + (s->cols + 1) * (l.cell_w + MARGIN));
    *h = (uint32_t)(MARGIN + l.title_h + (s->rows ? s->rows : 1) * (l.cell_h + MARGIN));
}

/* The image as a cairo surface of 8-bit sRGB pixels. */
static cairo_surface_t *surface_of(const st_image *img)
{
    cairo_surface_t *sf =
        cairo_image_surface_create(CAIRO_FORMAT_RGB24, (int)img->width, (int)img->height);
    if (cairo_surface_status(sf) != CAIRO_STATUS_SUCCESS)
        return sf;
    int ch[3] = {st_image_find_channel(img, "R"), st_image_find_channel(img, "G"),
                 st_image_find_channel(img, "B")};
    cairo_surface_flush(sf);
    unsigned char *px = cairo_image_surface_get_data(sf);
    int stride = cairo_image_surface_get_stride(sf);
    for (uint32_t y = 0; y < img->height; y++)
        for (uint32_t x = 0; x < img->width; x++) {
            const float *p = img->data + ((size_t)y * img->width + x) * img->channels;
            uint32_t v = 0;
            for (int c = 0; c < 3; c++)
                v = v << 8 | st_image_srgb_quantize(p[ch[c]]);
            memcpy(px + (size_t)y * stride + 4 * x, &v, 4);
        }
    cairo_surface_mark_dirty(sf);
    return sf;
}

/* src's rectangle (sx, sy, sw, sh) enlarged scale times, each pixel a block of
 * scale x scale, as an image surface of its own. */
static cairo_surface_t *enlarged(cairo_surface_t *src, double scale, double sx, double sy,
                                 double sw, double sh)
{
    cairo_surface_t *big = cairo_image_surface_create(CAIRO_FORMAT_RGB24, (int)(sw * scale),
                                                      (int)(sh * scale));
    cairo_t *cr = cairo_create(big);
    cairo_scale(cr, scale, scale);
    cairo_set_source_surface(cr, src, -sx, -sy);
    cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
    cairo_paint(cr);
    cairo_destroy(cr);
    return big;
}

/* Draws src's rectangle (sx, sy, sw, sh) at (x, y), enlarged scale times, without smoothing.
 * The enlargement is done here, pixel by pixel, and the result placed at its own size: an SVG
 * viewer smooths an image it has to scale (cairo's SVG output cannot ask it not to), which
 * would blur the very per-pixel noise a sheet compares. */
static void draw_pixels(cairo_t *cr, cairo_surface_t *src, double x, double y, double scale,
                        double sx, double sy, double sw, double sh)
{
    cairo_surface_t *big = enlarged(src, scale, sx, sy, sw, sh);
    cairo_save(cr);
    cairo_rectangle(cr, x, y, sw * scale, sh * scale);
    cairo_clip(cr);
    cairo_set_source_surface(cr, big, x, y);
    cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
    cairo_paint(cr);
    cairo_restore(cr);
    cairo_surface_destroy(big);
}

static void draw_text(cairo_t *cr, double x, double y, const char *text)
{
    cairo_move_to(cr, x, y);
    cairo_show_text(cr, text);
}

/* Draws text at (x, y) within width w: in the sheet's font size when it fits, else in the
 * size that makes it fit, so a caption never runs into the next column. */
static void draw_text_within(cairo_t *cr, double x, double y, const char *text, double w)
{
    cairo_text_extents_t e;
    cairo_text_extents(cr, text, &e);
    double right = e.x_bearing + e.x_advance > e.width ? e.x_advance : e.x_bearing + e.width;
    cairo_save(cr);
    if (right > w && right > 0)
        cairo_set_font_size(cr, FONT * w / right);
    cairo_move_to(cr, x, y);
    cairo_show_text(cr, text);
    cairo_restore(cr);
}

static void draw_cell(cairo_t *cr, const st_sheet *s, const layout *l, const st_sheet_cell *c,
                      double x, double y)
{
    if (!c->image)
        return;
    cairo_surface_t *sf = surface_of(c->image);
    draw_pixels(cr, sf, x, y, l->scale, 0, 0, c->image->width, c->image->height);
    double ty = y + l->image_h;
    if (s->inset[2]) {
        cairo_set_source_rgb(cr, 1.0, 0.85, 0.0); /* the rectangle the inset enlarges */
        cairo_set_line_width(cr, 1.5);
        cairo_rectangle(cr, x + s->inset[0] * l->scale, y + s->inset[1] * l->scale,
                        s->inset[2] * l->scale, s->inset[3] * l->scale);
        cairo_stroke(cr);
        draw_pixels(cr, sf, x, ty + 4.0, l->inset_scale, s->inset[0], s->inset[1], s->inset[2],
                    s->inset[3]);
        ty += 4.0 + l->inset_h;
    }
    cairo_surface_destroy(sf);
    cairo_set_source_rgb(cr, 0, 0, 0);
    draw_text_within(cr, x, ty + FONT * 1.4, c->caption ? c->caption : "", l->cell_w);
    if (c->note)
        draw_text_within(cr, x, ty + 2 * FONT * 1.4, c->note, l->cell_w);
}

static void draw_sheet(cairo_t *cr, const st_sheet *s, const layout *l)
{
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, FONT);
    if (s->title) {
        cairo_set_source_rgb(cr, 0, 0, 0);
        draw_text(cr, MARGIN, MARGIN + FONT, s->title);
    }
    double top = MARGIN + l->title_h;
    draw_cell(cr, s, l, &s->reference, MARGIN, top);
    for (uint32_t r = 0; r < s->rows; r++)
        for (uint32_t k = 0; k < s->cols; k++)
            draw_cell(cr, s, l, &s->cells[r * s->cols + k], MARGIN + (k + 1) * (l->cell_w + MARGIN),
                      top + r * (l->cell_h + MARGIN));
}

static cairo_status_t sink(void *closure, const unsigned char *data, unsigned int length)
{
    return st_outfile_write(closure, data, length) == 0 ? CAIRO_STATUS_SUCCESS
                                                        : CAIRO_STATUS_WRITE_ERROR;
}

static st_status check(const char *path, const st_sheet *s, uint32_t *iw, uint32_t *ih,
                       st_error *err)
{
    const st_image *first = s->reference.image;
    for (uint32_t i = 0; !first && i < s->rows * s->cols; i++)
        first = s->cells[i].image;
    if (!first)
        return st_fail(err, ST_ERR_USAGE, "%s: a sheet without images", path);
    *iw = first->width, *ih = first->height;
    for (uint32_t i = 0; i <= s->rows * s->cols; i++) {
        const st_image *im = i ? s->cells[i - 1].image : s->reference.image;
        if (im && (im->width != *iw || im->height != *ih))
            return st_fail(err, ST_ERR_USAGE, "%s: images of different sizes", path);
        if (im && (st_image_find_channel(im, "R") < 0 || st_image_find_channel(im, "G") < 0 ||
                   st_image_find_channel(im, "B") < 0))
            return st_fail(err, ST_ERR_USAGE, "%s: an image without R, G, B", path);
    }
    const uint32_t *c = s->inset;
    if (c[2] && (c[3] == 0 || c[0] >= *iw || c[1] >= *ih || c[2] > *iw - c[0] ||
                 c[3] > *ih - c[1]))
        return st_fail(err, ST_ERR_USAGE, "%s: inset %u,%u,%u,%u is outside the %ux%u image",
                       path, c[0], c[1], c[2], c[3], *iw, *ih);
    uint32_t w, h;
    st_sheet_size(s, *iw, *ih, &w, &h);
    if (w > MAX_SIDE || h > MAX_SIDE)
        return st_fail(err, ST_ERR_USAGE, "%s: a %ux%u sheet is over %u a side", path, w, h,
                       MAX_SIDE);
    return ST_OK;
}

/* The surface for the extension: an image (written as PNG at the end), or PDF / SVG streaming
 * into out. NULL: an unknown extension. */
static cairo_surface_t *surface_for(const char *path, st_outfile *out, uint32_t w, uint32_t h)
{
    const char *dot = strrchr(path, '.');
    if (dot && !strcasecmp(dot, ".png"))
        return cairo_image_surface_create(CAIRO_FORMAT_RGB24, (int)w, (int)h);
    if (dot && !strcasecmp(dot, ".pdf"))
        return cairo_pdf_surface_create_for_stream(sink, out, w, h);
    if (dot && !strcasecmp(dot, ".svg"))
        return cairo_svg_surface_create_for_stream(sink, out, w, h);
    return NULL;
}

st_status st_sheet_save(const char *path, const st_sheet *s, st_error *err)
{
    uint32_t iw = 0, ih = 0, w, h;
    const char *dot = strrchr(path, '.');
    if (!dot || (strcasecmp(dot, ".png") && strcasecmp(dot, ".pdf") && strcasecmp(dot, ".svg")))
        return st_fail(err, ST_ERR_USAGE, "%s: a sheet is .png, .pdf or .svg", path);
    if (check(path, s, &iw, &ih, err) != ST_OK)
        return err->status;
    st_sheet_size(s, iw, ih, &w, &h);
    layout l = layout_of(s, iw, ih);
    st_outfile *out = NULL;
    if (st_outfile_open(path, &out, err) != ST_OK)
        return err->status;
    cairo_surface_t *sf = surface_for(path, out, w, h);
    cairo_t *cr = cairo_create(sf);
    draw_sheet(cr, s, &l);
    cairo_status_t cs = cairo_status(cr);
    cairo_destroy(cr);
    if (cs == CAIRO_STATUS_SUCCESS && !strcasecmp(dot, ".png"))
        cs = cairo_surface_write_to_png_stream(sf, sink, out);
    cairo_surface_finish(sf); /* PDF and SVG write their end here */
    if (cs == CAIRO_STATUS_SUCCESS)
        cs = cairo_surface_status(sf);
    cairo_surface_destroy(sf);
    if (cs != CAIRO_STATUS_SUCCESS) {
        int e = st_outfile_error(out);
        st_outfile_abort(out);
        return st_fail(err, cs == CAIRO_STATUS_NO_MEMORY ? ST_ERR_NOMEM : ST_ERR_IO,
                       "%s: cannot write (%s)", path, e ? strerror(e) : cairo_status_to_string(cs));
    }
    return st_outfile_commit(out, err);
}
