#!/bin/sh
# test_converge.sh — strata converge: the CSV form, the lecture's slopes on a
# smooth region, and its usage errors. TAP output.
#
# Slopes: on a smooth part of the Cornell box's back wall (direct lighting,
# 32x32 pixels, region 9,7,14,5: no edges, no shadow boundaries) the error is
# the light-sampling noise. Independent (random) samples converge as N^-1/2:
# the fitted slope must lie in -0.5 +/- 0.1. Stratified samples converge
# faster: their slope must be steeper than random's by at least 0.07
# (measured over 4..256 spp, 4 seeds, reference 8192 spp: random -0.49,
# stratified -0.62; stratification is per pair of dimensions, so the
# interaction between pixel position and light point still converges at
# N^-1/2, which keeps stratified from N^-1; Halton, a true 4-D sequence,
# measured -0.79). joint-stratified stratifies the pixel and light pairs
# jointly (an orthogonal array; at 4 spp, q = 2, it is plain stratified):
# its slope must be steeper than stratified's by 0.04 (measured over
# 16..256 spp: -0.72 against -0.61).
S=${STRATA:-./strata}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
n=0
check() { n=$((n + 1)); if eval "$2"; then echo "ok $n - $1"; else echo "not ok $n - $1 $3"; fi; }
expect() {
    name=$1 want=$2 pat=$3
    shift 3
    "$@" > "$T/out" 2> "$T/err"
    got=$?
    check "$name" '[ "$got" -eq "$want" ] && grep -q -- "$pat" "$T/err"' "(status $got: $(head -c 200 "$T/err"))"
}

$S converge --sampler random,stratified,joint-stratified --spp-list 4,16,64,256 --width 32 --height 32 \
    --integrator direct --reference-spp 8192 --seeds 4 --region 9,7,14,5 --quiet \
    --csv "$T/c.csv" --png "$T/c.png" > "$T/out" 2>&1
check "converge writes the CSV header" '[ "$(head -1 "$T/c.csv")" = "sampler,spp,seeds,rmse,rmse_stderr,rel_mse,rmse_measured" ]'
check "one row per sampler and count" '[ "$(wc -l < "$T/c.csv")" -eq 13 ]'
check "converge writes the plot" '[ -s "$T/c.png" ]'
slope() { awk -F, -v s="$1" 'NR > 1 && $1 == s { x = log($2); y = log($4); n++; sx += x; sy += y; sxx += x * x; sxy += x * y }
    END { printf "%.4f", (n * sxy - sx * sy) / (n * sxx - sx * sx) }' "$T/c.csv"; }
r=$(slope random)
st=$(slope stratified)
check "random slope $r is -0.5 +/- 0.1" 'awk -v r="$r" "BEGIN { exit !(r > -0.6 && r < -0.4) }"'
check "stratified slope $st is steeper than random's $r by 0.07 or more" 'awk -v r="$r" -v s="$st" "BEGIN { exit !(s < r - 0.07) }"'
j=$(slope joint-stratified)
check "joint-stratified slope $j is steeper than stratified's $st by 0.04 or more" 'awk -v j="$j" -v s="$st" "BEGIN { exit !(j < s - 0.04) }"'

expect "a bad spp list exits 2" 2 "--spp-list x: expected an integer" $S converge --sampler random --spp-list 4,x --csv -
expect "a decreasing spp list exits 2" 2 "counts must increase" $S converge --sampler random --spp-list 16,4 --csv -
expect "an unknown sampler in the list exits 2" 2 "--sampler dart: unknown; expected one of random" $S converge --sampler random,dart --spp-list 4 --csv -
expect "a region outside the image exits 2" 2 "--region 30,0,8,8: outside the 32x32 image" $S converge --width 32 --height 32 --sampler random --spp-list 4 --region 30,0,8,8 --csv -
expect "an empty region exits 2" 2 "--region 0,0,0,4: expected X,Y,W,H" $S converge --sampler random --spp-list 4 --region 0,0,0,4 --csv -
expect "--spp is refused (the study sets it)" 2 "--spp is set by the study" $S converge --sampler random --spp-list 4 --spp 8 --csv -
expect "nothing to write exits 2" 2 "nothing to write" $S converge --sampler random --spp-list 4

# --error-spectrum alone is something to write: one panel per sampler, a PNG
$S converge --sampler random,zsobol --spp-list 2 --width 16 --height 12 --integrator direct \
    --reference-spp 64 --seeds 2 --quiet --error-spectrum "$T/e.png" > "$T/out" 2>&1
check "--error-spectrum writes a PNG" '[ "$(head -c 4 "$T/e.png" | od -An -c | tr -d " ")" = "211PNG" ]' "$(cat "$T/out")"
expect "--error-spectrum with more than 8 panels exits 2" 2 "at most 8 panels" $S converge --sampler random,uniform,stratified,halton,hammersley --adaptive --spp-list 4 --error-spectrum "$T/x.png"
# progress counts samples, not renders: 1 spp then 255 spp, the first render is
# 1/256 of the work (counted in renders it was half, and the ETA read 1:07 where
# 2:45 remained); waves of 16 spp, so the 255-spp render reports as it goes
$S converge --sampler random --seeds 1 --spp-list 1,255 --width 64 --height 64 \
    --reference-spp 16 --wave 65536 --csv "$T/p.csv" > /dev/null 2> "$T/err"
grep "^strata: converge  *[0-9]*%" "$T/err" > "$T/lines"
first=$(sed -n '1s/^strata: converge  *\([0-9]*\)%.*/\1/p' "$T/lines")
check "converge's progress is in samples, past 1 spp of 256 at under half" \
    '[ -n "$first" ] && [ "$first" -lt 50 ] && ! grep -qv "samples/s" "$T/lines" && tail -1 "$T/lines" | grep -q " 100%"' \
    "($(tr '\n' ' ' < "$T/lines"))"
echo "1..$n"
