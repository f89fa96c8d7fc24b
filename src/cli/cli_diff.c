/* cli_diff.c — `strata diff A B [--max-rmse X] [--convert]`: RMSE, PSNR and
 * the largest absolute difference of two images, through the same
 * st_diff_images that the image tests compare goldens with. An EXR holds
 * linear, unclipped radiance and a PNG clipped 8-bit sRGB, so a PNG is
 * compared with an EXR only when asked (--convert), in the PNG's terms. */
#include <stdio.h>
#include <string.h>

#include "cli_args.h"
#include "cli_commands.h"
#include "cli_error.h"
#include "cli_session.h"
#include "st_diff.h"
#include "st_image.h"

int st_cli_diff(int argc, char **argv)
{
    const char *a = NULL, *b = NULL;
    double max_rmse = -1.0;
    int convert = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            puts("usage: strata diff A B [--max-rmse X] [--convert]\n"
                 "  prints RMSE, PSNR (peak 1) and the largest absolute difference over R, G, B\n"
                 "  of the pixels both hold: EXR data windows (render --crop) of one display\n"
                 "  window are compared where they overlap (a crop with its full render: the\n"
                 "  crop's window); images of different sizes are refused;\n"
                 "  with --max-rmse (X >= 0), exits 1 when the RMSE is larger than X.\n"
                 "  An EXR (linear) and a PNG (8-bit sRGB, clipped) are refused together\n"
                 "  unless --convert: the EXR is then clamped to [0, 1] and quantised as\n"
                 "  its PNG would be (default exposure and tone curve) before comparing");
            return 0;
        }
        if (!strcmp(argv[i], "--max-rmse")) {
            float v;
            if (i + 1 >= argc)
                return st_cli_usage_error("diff: --max-rmse needs a value");
            if (st_cli_parse_float("--max-rmse", argv[++i], &v))
                return ST_CLI_EXIT_USAGE;
            if (v < 0.0f) /* a gate that could never fail */
                return st_cli_usage_error("diff: --max-rmse %s: must be >= 0", argv[i]);
            max_rmse = v;
        } else if (!strcmp(argv[i], "--convert")) {
            convert = 1;
        } else if (argv[i][0] == '-' && argv[i][1] != '\0') {
            return st_cli_usage_error("diff: unknown option %s", argv[i]);
        } else if (!a) {
            a = argv[i];
        } else if (!b) {
            b = argv[i];
        } else {
            return st_cli_usage_error("diff: unexpected argument %s", argv[i]);
        }
    }
    if (!a || !b)
        return st_cli_usage_error("diff: needs two images (strata diff A B)");
    int png_a = st_cli_has_extension(a, ".png"), png_b = st_cli_has_extension(b, ".png");
    if (png_a != png_b && !convert)
        return st_cli_usage_error("diff: %s is %s but %s is %s: compare images of one kind, "
                                  "or add --convert to compare the EXR as its PNG would be",
                                  a, png_a ? "8-bit sRGB (PNG)" : "linear (EXR)", b,
                                  png_b ? "8-bit sRGB (PNG)" : "linear (EXR)");
    if (png_a == png_b && convert)
        return st_cli_usage_error("diff: --convert compares an EXR with a PNG; %s and %s are "
                                  "of one kind", a, b);
    st_error err = {0};
    st_image ia = {0}, ib = {0};
    st_diff_result d;
    int rc = 0;
    if (st_image_load(a, &ia, &err) || st_image_load(b, &ib, &err)) {
        rc = st_cli_fail(&err);
    } else {
        if (convert)
            st_diff_quantize_srgb8(png_a ? &ib : &ia);
        if (st_diff_images(&ia, &ib, &d, &err)) {
            rc = st_cli_fail(&err);
        } else {
            printf("rmse %.9g\npsnr %.4f dB\nmax_abs %.9g\n", d.rmse, d.psnr, d.max_abs);
            if (max_rmse >= 0.0 && d.rmse > max_rmse) {
                fprintf(stderr, "strata: diff: rmse %.9g is above --max-rmse %g\n", d.rmse,
                        max_rmse);
                rc = 1;
            }
        }
    }
    st_image_free(&ia);
    st_image_free(&ib);
    return rc;
}
