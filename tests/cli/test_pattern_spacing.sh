#!/bin/sh
# test_pattern_spacing.sh — `strata pattern --discrepancy` reports the
# minimum distance x sqrt(N), and the blue-noise samplers keep it where the
# literature puts them: Mitchell's best-candidate about 0.75 without pixels
# (one point per pixel, as the renderer's tile: measured 0.56..0.60 at 1 spp,
# bound 0.5), Poisson disk near its radius (>= 0.5), while random points let
# it fall towards 0 (P(d > r) ~ exp(-pi N^2 r^2 / 2), median d sqrt(N) ~
# 0.66 / sqrt(N) = 0.010 at 4096 points; measured 0.011; bound 0.1). TAP
# output. The binary is $STRATA.
. tests/tap.sh

# md SAMPLER: the plain minimum distance x sqrt(N) of 4096 points
md() { $S pattern --sampler "$1" --count 4096 --discrepancy | sed -n 's/^minimum distance x sqrt(N) (2-D): \([0-9.]*\) (toroidal \([0-9.]*\))$/\1/p'; }

bc=$(md best-candidate)
check "best-candidate: minimum distance x sqrt(N) >= 0.5 (got $bc)" \
    'awk -v d="$bc" "BEGIN { exit !(d != \"\" && d >= 0.5 && d < 1.075) }"'
po=$(md poisson)
check "poisson: minimum distance x sqrt(N) >= 0.5 (got $po)" \
    'awk -v d="$po" "BEGIN { exit !(d != \"\" && d >= 0.5 && d < 1.075) }"'
ra=$(md random)
check "random: minimum distance x sqrt(N) < 0.1 (got $ra)" \
    'awk -v d="$ra" "BEGIN { exit !(d != \"\" && d < 0.1) }"'
$S pattern --help > "$T/help" 2>&1
check "help names the minimum distance" 'grep -q "minimum distance" "$T/help"'
echo "1..$n"
