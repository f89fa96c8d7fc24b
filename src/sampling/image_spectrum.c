/* image_spectrum.c — the power spectrum of an image on its pixel grid
 * (st_sampling.h: st_spectrum_image), by FFTW: for the per-pixel error of a
 * render, white (independent) error is flat, blue-noise error (ZSobol,
 * best-candidate) is dark at low frequencies.
 *
 * Invariant: results are ADDED to the caller's array (averaging over seeds),
 * centred so that k = 0 sits at column w/2, row h/2. */
#include "st_sampling.h"

#include <fftw3.h>

st_status st_spectrum_image(const double *values, st_u32 w, st_u32 h, double *power,
                            st_error *err)
{
    if (!values || !power || w == 0 || h == 0 || (st_u64)w * h > (1u << 28))
        return st_fail(err, ST_ERR_USAGE, "image spectrum: %ux%u pixels (1 to 2^28) and "
                                          "non-NULL arrays needed", w, h);
    size_t n = (size_t)w * h;
    fftw_complex *buf = fftw_malloc(sizeof(fftw_complex) * n);
    fftw_plan plan = buf ? fftw_plan_dft_2d((int)h, (int)w, buf, buf, FFTW_FORWARD, FFTW_ESTIMATE)
                         : NULL;
    if (!plan) {
        fftw_free(buf);
        return st_fail(err, ST_ERR_NOMEM, "image spectrum: out of memory for %ux%u", w, h);
    }
    for (size_t i = 0; i < n; i++) { /* filled after planning, which may overwrite buf */
        buf[i][0] = values[i];
        buf[i][1] = 0.0;
    }
    fftw_execute(plan);
    for (st_u32 ky = 0; ky < h; ky++)
        for (st_u32 kx = 0; kx < w; kx++) {
            const double *f = buf[(size_t)ky * w + kx];
            size_t c = (size_t)((ky + h / 2) % h) * w + (kx + w / 2) % w;
            power[c] += (f[0] * f[0] + f[1] * f[1]) / (double)n;
        }
    fftw_destroy_plan(plan);
    fftw_free(buf);
    return ST_OK;
}
