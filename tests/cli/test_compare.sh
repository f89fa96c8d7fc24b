#!/bin/sh
# test_compare.sh — strata compare: the sheet in each format, the CSV, and its
# RMSE against an independent computation (the same renders made by strata
# render and measured by strata diff). TAP output.
. tests/tap.sh

G="--width 24 --height 16 -q"
$S compare --sampler random,halton --spp 1,2 --filter box $G --reference-spp 16 \
    --crop 4,4,8,6 -o "$T/sheet.png" --csv "$T/c.csv"
check "compare writes a PNG sheet" '[ "$(head -c 4 "$T/sheet.png" | tail -c 3)" = PNG ]'
check "the CSV has a header and one row per combination" \
    '[ "$(head -1 "$T/c.csv")" = "sampler,spp,filter,rmse,psnr" ] && [ "$(wc -l < "$T/c.csv")" -eq 5 ]'
check "the rows are sampler-major" \
    '[ "$(cut -d, -f1-3 "$T/c.csv" | tr "\n" " ")" = "sampler,spp,filter random,1,box random,2,box halton,1,box halton,2,box " ]'
# the reference: sobol, 16 spp, seed 0 + 0x5eed5eed, the first filter
$S render $G --sampler sobol --spp 16 --seed 1592614637 --filter box -o "$T/ref.exr"
$S render $G --sampler halton --spp 2 --filter box -o "$T/h2.exr"
want=$($S diff "$T/h2.exr" "$T/ref.exr" | sed -n 's/^rmse //p')
got=$(grep "^halton,2,box," "$T/c.csv" | cut -d, -f4)
check "the RMSE is strata diff's of the same renders" \
    'awk -v a="$got" -v b="$want" "BEGIN { exit !(a - b < 1e-8 && b - a < 1e-8) }"' "(got $got, want $want)"
$S compare --sampler random,halton --spp 1,2 --filter box $G --reference "$T/ref.exr" \
    -o "$T/sheet2.png" --csv "$T/c2.csv"
check "--reference FILE gives the same numbers" 'cmp -s "$T/c.csv" "$T/c2.csv"'
$S compare --sampler random --spp 1 $G --reference-spp 4 -o "$T/s.pdf"
$S compare --sampler random --spp 1 $G --reference-spp 4 -o "$T/s.svg"
check "a PDF sheet" '[ "$(head -c 4 "$T/s.pdf")" = "%PDF" ]'
check "an SVG sheet" 'grep -q "<svg" "$T/s.svg"'
expect "--sampler is required" 2 "^strata: error: compare: --sampler LIST is required" $S compare $G -o "$T/x.png"
expect "-o is required" 2 "^strata: error: compare: -o SHEET" $S compare --sampler random $G
expect "a sheet's extension" 2 "^strata: error: -o $T/x.jpg: the sheet must end in .png, .pdf or .svg" $S compare --sampler random $G -o "$T/x.jpg"
expect "a crop outside the image" 2 "^strata: error: --crop 20,4,8,6: outside the 24x16 image" $S compare --sampler random $G --crop 20,4,8,6 -o "$T/x.png"
expect "filter parameters are refused" 2 "^strata: error: compare: --filter-radius: each filter" $S compare --sampler random $G --filter-radius 1 -o "$T/x.png"
expect "a misspelt sampler" 2 "did you mean halton?" $S compare --sampler haltom $G -o "$T/x.png"
expect "a reference of another size" 2 "ref.exr: 24x16 pixels, the sheet renders 8x8" $S compare --sampler random --width 8 --height 8 --reference "$T/ref.exr" -o "$T/x.png"
check "failed compares wrote no sheet" '[ ! -e "$T/x.png" ] && [ ! -e "$T/x.jpg" ]'
echo "1..$n"
