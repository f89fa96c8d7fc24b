/* splat_rows.h — the taps of a sample that needs no clamping, into a
 * work-item's own window of ST_ACC sums (film.cl): per tap one product,
 * one rounding of four floats to integers (ST_ROUND) and one add. film.cl
 * includes it twice: int4 partial sums rounded to int32 (splat_near), and
 * long4 sums through doubles, for the samples too bright for int32. The
 * integers are fixed_splat4's: (w L) 2^24 = w (L 2^24) exactly (a power of
 * two; the caller's bound rules out overflow, and an underflow rounds to 0
 * either way). No include guard: one copy per ST_ACC. */
#if !defined(ST_ACC) || !defined(ST_ROUND)
#error "define ST_ACC (the window's element) and ST_ROUND before including splat_rows.h"
#endif

/* Row a and, where `both`, row b = a + side: a[k] += round(wx[k st] wya
 * Ls), b[k] += round(wx[k st] wyb Ls). Four columns a step: their weights
 * read once for both rows and multiplied by wya and by wyb in one product
 * each (each lane the scalar product); then the last few columns one at a
 * time. */
ST_HOT void ST_CAT(splat_rows_, ST_ACC)(__local ST_ACC *a, int side, const float *wx, int st,
                                        int nx, float wya, float wyb, int both, float4 Ls)
{
    __local ST_ACC *b = a + side;
    int k = 0;
    for (; k + 4 <= nx; k += 4, wx += 4 * st, a += 4, b += 4) {
        float4 w = (float4)(wx[0], wx[st], wx[2 * st], wx[3 * st]), u = w * wya, v = w * wyb;
        a[0] += ST_ROUND(u.x * Ls);
        a[1] += ST_ROUND(u.y * Ls);
        a[2] += ST_ROUND(u.z * Ls);
        a[3] += ST_ROUND(u.w * Ls);
        if (both) {
            b[0] += ST_ROUND(v.x * Ls);
            b[1] += ST_ROUND(v.y * Ls);
            b[2] += ST_ROUND(v.z * Ls);
            b[3] += ST_ROUND(v.w * Ls);
        }
    }
    for (; k < nx; k++, wx += st, a++, b++) {
        a[0] += ST_ROUND(wx[0] * wya * Ls);
        if (both)
            b[0] += ST_ROUND(wx[0] * wyb * Ls);
    }
}

/* The nx x ny taps of a sample with weights w and factor scale from window
 * pixel row[0] on, rows side apart. */
ST_HOT void ST_CAT(splat_fitting_, ST_ACC)(__local ST_ACC *row, int side, tap_weights w, int nx,
                                           int ny, float scale, float4 L1)
{
    float4 Ls = L1 * ST_FIXED_SCALE;
    if (scale == 1.0f) { /* w 1 = w: the same integers without the product */
        for (int j = 0; j < ny; j += 2, row += 2 * side) {
            int both = j + 1 < ny;
            ST_CAT(splat_rows_, ST_ACC)(row, side, w.x, w.st, nx, w.y[j * w.st],
                                        w.y[(j + both) * w.st], both, Ls);
        }
        return;
    }
    for (int j = 0; j < ny; j++, row += side)
        for (int k = 0; k < nx; k++)
            row[k] += ST_ROUND(w.x[k * w.st] * w.y[j * w.st] * scale * Ls);
}
