#!/bin/sh
# test_plots.sh — the laboratory's plots as files for a paper: PNG, PDF or SVG
# by extension, labelled axes, the spectrum's colour range, filter responses
# in dB. TAP output.
. tests/tap.sh

$S pattern --sampler halton --count 64 --png "$T/p.svg"
check "a scatter plot as SVG" 'grep -q "<svg" "$T/p.svg"'
$S pattern --sampler halton --count 64 --png "$T/p.pdf"
check "a scatter plot as PDF" '[ "$(head -c 4 "$T/p.pdf")" = "%PDF" ]'
$S pattern --sampler random --count 64 --spectrum "$T/s.png" --range -1,1
check "a spectrum with --range as PNG" '[ "$(head -c 4 "$T/s.png" | tail -c 3)" = PNG ]'
expect "--range needs LO < HI" 2 "^strata: error: --range 1,1: expected LO,HI with LO < HI" $S pattern --sampler random --count 64 --spectrum "$T/x.png" --range 1,1
$S pattern --sampler random --count 64 --png "$T/x.PDF"
check "the extension in any case" '[ "$(head -c 4 "$T/x.PDF")" = "%PDF" ]'
$S filter lanczos --db --png "$T/f.svg"
check "a filter response in dB, labelled" 'grep -q "<svg" "$T/f.svg"'
expect "--db without a plot exits 2" 2 "^strata: error: --db applies to the plot" $S filter box --db --csv -
# filter takes render's spellings of the filter's parameters: Mitchell's
# 6 k(0) = 6 - 2B, so k(0) = 5/6 at B = 1/2
$S filter mitchell --filter-b 0.5 --filter-c 0.25 --filter-radius 2 --csv "$T/m.csv"
k0=$(sed -n 's/^0\.000000,//p' "$T/m.csv" | head -1)
check "filter --filter-b B: the profile of that B (k(0) = 5/6 at B = 1/2)" \
    'awk -v k="$k0" "BEGIN { exit !(k - 5 / 6 < 1e-6 && 5 / 6 - k < 1e-6) }"' "(k(0) = $k0)"
expect "filter names a parameter as render does" 2 "^strata: error: --filter-b/--filter-c apply to mitchell only" \
    $S filter gaussian --filter-b 0.2 --csv -
expect "filter --b, render's --filter-b spelt otherwise, is refused" 2 "unknown option --b" \
    $S filter mitchell --b 0.5 --csv -
# converge: the slope is fitted over the falling part only. A curve made to stop
# falling: the reference is the unscrambled 16-spp Halton render itself, so RMSE is
# 0 at 16 spp and rises again at 64: a plateau from 16 spp on.
$S render --width 16 --height 16 --spp 16 --sampler halton --scramble none -q -o "$T/r16.exr"
$S converge --sampler halton --scramble none --spp-list 4,16,64 --width 16 --height 16 \
    --reference "$T/r16.exr" --png "$T/c.svg" > "$T/slopes" 2> /dev/null
check "converge plots as SVG" 'grep -q "<svg" "$T/c.svg"'
check "a curve that stops falling names its plateau" \
    'grep -q "halton .* (to 16 spp, then a plateau)" "$T/slopes"' "($(cat "$T/slopes"))"
echo "1..$n"
