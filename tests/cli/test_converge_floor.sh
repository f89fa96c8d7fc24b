#!/bin/sh
# test_converge_floor.sh — strata converge's reference floor: the reference
# made here is the mean of two independent renders of N/2 spp, whose
# difference estimates its own RMSE (the floor, printed), and a slope is
# fitted only over points whose RMSE is at least 3 times the floor.
#
# Checks: (1) the floor printed agrees with an independent estimate, the RMS
# difference of two other renders of N/2 spp (strata diff) halved, within
# 25% (the two estimates average 3 x 70 region pixels each); (2) with a coarse
# reference (256 spp) the high-spp points of paddedsobol sink under 3 x the
# floor: the summary says so and the printed slope equals the least-squares
# slope over the CSV's points above 3 x the floor, recomputed here; (3) a
# given reference file reports no floor. TAP output.
. tests/tap.sh

opts="--width 32 --height 32 --integrator direct --region 9,7,14,5"
$S converge --sampler random,paddedsobol --spp-list 4,16,64,256,1024 $opts --reference-spp 256 \
    --seeds 2 --csv "$T/c.csv" > "$T/out" 2> "$T/err"
fl=$(sed -n 's/^converge: reference floor \([0-9.e+-]*\) .*/\1/p' "$T/out")
check "converge prints the reference floor ($fl)" '[ -n "$fl" ]' "$(cat "$T/out" "$T/err")"

# an independent estimate of the same floor: two other seeds, N/2 spp each,
# of the region only (a crop, equal to the full render there)
$S render --width 32 --height 32 --integrator direct --crop 9,7,14,5 --sampler paddedsobol \
    --spp 128 --seed 101 -o "$T/ac.exr" --quiet
$S render --width 32 --height 32 --integrator direct --crop 9,7,14,5 --sampler paddedsobol \
    --spp 128 --seed 202 -o "$T/bc.exr" --quiet
d=$($S diff "$T/ac.exr" "$T/bc.exr" | awk '/^rmse/ { print $2 }')
check "the floor $fl is half the RMS difference of two other half references ($d / 2) within 25%" \
    'awk -v f="$fl" -v d="$d" "BEGIN { e = d / 2; exit !(f > 0.75 * e && f < 1.25 * e) }"'

# the slope over the points whose measured RMSE ($7) is at least 3 x the floor, fitted to the
# RMSE with the floor taken out ($4), from the CSV
slope() { awk -F, -v s="$1" -v f="$fl" 'NR > 1 && $1 == s && $7 >= 3 * f { x = log($2); y = log($4); n++; sx += x; sy += y; sxx += x * x; sxy += x * y }
    END { if (n < 2) print "nan"; else printf "%.3f", (n * sxy - sx * sy) / (n * sxx - sx * sx) }' "$T/c.csv"; }
below=$(awk -F, -v f="$fl" 'NR > 1 && $1 == "paddedsobol" && $7 < 3 * f' "$T/c.csv" | wc -l)
check "paddedsobol has points under 3 x the floor ($below)" '[ "$below" -ge 1 ]'
ps=$(slope paddedsobol)
check "the printed paddedsobol slope is the fit above 3 x the floor ($ps)" \
    'grep -q "paddedsobol $ps (to [0-9]* spp, then the reference floor)" "$T/out"' "$(cat "$T/out")"
rs=$(slope random)
check "the printed random slope is the fit above 3 x the floor ($rs)" \
    'grep -q "slopes random $rs" "$T/out"' "$(cat "$T/out")"

# (4) the floor comes out in quadrature: with one seed, rmse^2 = rmse_measured^2 - floor^2
# (to the floor's printed 3 digits: within 1 % of the difference).
$S converge --sampler paddedsobol --spp-list 64 $opts --reference-spp 128 --seeds 1 \
    --csv "$T/q.csv" > "$T/qout" 2> /dev/null
fq=$(sed -n 's/^converge: reference floor \([0-9.e+-]*\) .*/\1/p' "$T/qout")
row=$(awk -F, 'NR == 2 { print $4, $7 }' "$T/q.csv")
check "rmse^2 = rmse_measured^2 - floor^2 ($row, floor $fq)" \
    'echo "$row $fq" | awk "{ d = \$2 * \$2 - \$3 * \$3; exit !(NF == 3 && d > 0 && (\$1 * \$1 - d) ^ 2 < (0.01 * d) ^ 2) }"'
# (5) and that is the error against a far better reference: random at 256 spp over the
# lower half (2,14,28,16), 4 seeds, against a reference of 128 spp made here (its noise
# about half the study's) and against a given paddedsobol 4096-spp one (its noise some
# 1/20 of the study's: adds 0.1 %). Measured: 1.104e-3 with the floor out, 1.249e-3
# measured (+21 %), 1.029e-3 against the fine reference (standard errors 4.8e-5 and
# 1.8e-5: 7 % is 1.5 of them). Bounds: within 12 % of it; the measured one over 12 % above.
half="--width 32 --height 32 --integrator direct --region 2,14,28,16"
$S converge --sampler random --spp-list 256 $half --reference-spp 128 --seeds 4 \
    --csv "$T/h.csv" > /dev/null 2>&1
$S render --width 32 --height 32 --integrator direct --sampler paddedsobol --spp 4096 --seed 77 \
    -o "$T/fine.exr" --quiet 2> /dev/null
$S converge --sampler random --spp-list 256 $half --reference "$T/fine.exr" --seeds 4 \
    --csv "$T/t.csv" > /dev/null 2>&1
row=$(awk -F, 'NR == 2 { print $4, $7 }' "$T/h.csv") truth=$(awk -F, 'NR == 2 { print $7 }' "$T/t.csv")
check "with the floor out, the rmse is the error against a far better reference ($row; $truth)" \
    'echo "$row $truth" | awk "{ exit !(NF == 3 && \$1 > 0.88 * \$3 && \$1 < 1.12 * \$3 && \$2 > 1.12 * \$3) }"'

$S render --width 32 --height 32 --integrator direct --spp 16 -o "$T/ref.exr" --quiet
$S converge --sampler random --spp-list 4,16 $opts --reference "$T/ref.exr" --seeds 2 \
    --csv "$T/g.csv" > "$T/gout" 2>&1
check "a given reference reports no floor" 'grep -q "reference floor not estimated" "$T/gout"' "$(cat "$T/gout")"
echo "1..$n"
