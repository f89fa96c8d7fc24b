/* st_sheet.h — a comparison sheet: rendered images side by side in a labelled grid, a
 * reference at the left, each image captioned (settings, error), with an optional magnified
 * inset of one pixel rectangle under every image. Drawn with cairo; the file type follows the
 * extension: .png (pixels), .pdf or .svg (vector captions, images embedded). Images are shown
 * as 8-bit sRGB (st_image_srgb_quantize of R, G, B), enlarged without smoothing by the whole
 * factor max(1, floor(256 / width)) (the inset by max(1, floor(that width / inset width))), so
 * every image pixel stays a visible square. Written through st_outfile (no partial file).
 * Nothing here prints. Tests: tests/unit/test_sheet.c. */
#ifndef ST_SHEET_H
#define ST_SHEET_H

#include "st_error.h"
#include "st_image.h"

#include <stdint.h>

typedef struct st_sheet_cell {
    const st_image *image; /* FLOAT channels R, G, B; NULL: an empty cell */
    const char *caption;   /* first line: the settings */
    const char *note;      /* second line (e.g. "RMSE 0.0123"); NULL: none */
} st_sheet_cell;

typedef struct st_sheet {
    const char *title;               /* NULL: none */
    st_sheet_cell reference;         /* the left column, top row */
    const st_sheet_cell *cells;      /* rows * cols, row-major */
    uint32_t rows, cols;
    uint32_t inset[4];               /* X, Y, W, H of the magnified rectangle; W == 0: none */
} st_sheet;

/* The layout's size in pixels (PNG) or points (PDF, SVG): for tests and callers. Every image
 * (reference and cells) must be the same size. */
void st_sheet_size(const st_sheet *s, uint32_t image_w, uint32_t image_h, uint32_t *w,
                   uint32_t *h);

/* Saves the sheet. Errors: ST_ERR_USAGE for an extension other than .png/.pdf/.svg, images of
 * different sizes, an inset outside the image or a sheet over 16384 pixels a side; ST_ERR_IO
 * when the file cannot be written; ST_ERR_NOMEM. */
st_status st_sheet_save(const char *path, const st_sheet *s, st_error *err);

#endif
