#!/bin/sh
# test_pmj02bn.sh — pmj02bn's pixel samples come from its sorted blue-noise
# tile, unrotated (pbrt-v4's GetSortedPMJ02BNPixelSamples; the nets:
# test_sampling_pmj02.c pmj02bn_pixel_prefixes_are_nets), so its error on
# the zone plate is no worse than pmj02's: strata converge, 32x32, 16 and
# 256 spp, 4 seeds each, against a 4096-spp reference. Tolerance: pmj02bn's
# RMSE at most pmj02's plus 2 combined standard errors of the two means
# (sqrt(se1^2 + se2^2), the CSV's rmse_stderr). Measured: 1.79e-4 against
# 1.92e-4 at 16 spp, 3.0e-6 against 4.3e-6 at 256; with each pixel's
# samples rotated on the torus (before), 3.1e-4 and 2.4e-5 (5.7x). TAP output.
. tests/tap.sh
$S converge zone-plate --width 32 --height 32 --sampler pmj02,pmj02bn --spp-list 16,256 \
    --reference-spp 4096 --seeds 4 --quiet --csv "$T/c.csv" 2> "$T/err"
for spp in 16 256; do
    row() { awk -F, -v s="$1" -v n="$spp" '$1 == s && $2 == n { print $4, $5 }' "$T/c.csv"; }
    p=$(row pmj02) b=$(row pmj02bn)
    check "zone plate, $spp spp: pmj02bn's RMSE no worse than pmj02's" \
        'echo "$p $b" | awk "NF == 4 { exit !(\$3 <= \$1 + 2 * sqrt(\$2 * \$2 + \$4 * \$4)) } NF != 4 { exit 1 }"' \
        "(pmj02 RMSE, stderr: $p; pmj02bn: $b)"
done
echo "1..$n"
