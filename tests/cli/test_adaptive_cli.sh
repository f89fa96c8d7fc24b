#!/bin/sh
# test_adaptive_cli.sh — `strata render --adaptive` from the command line:
# --spp is the mean (the summary and the EXR header say the samples taken,
# at most spp per pixel on average), the spp map is written, the pilot and
# the cap are checked against the mean, the adaptive options need
# --adaptive; sobol and halton adapt (their header names the pilot, a power
# of two) or, where their pilot predicts no gain (the furnace), go on
# uniformly with a note and the header saying so; every other sampler but
# random renders uniformly instead, with a note naming it and the EXR header
# saying so; bench names the adaptive kernels and times their build. TAP
# output.
. tests/tap.sh
P="--width 16 --height 16 --quiet"
$S render $P --sampler random --adaptive --spp 8 --spp-map "$T/map.png" -o "$T/a.exr" > "$T/sum" 2>&1
check "an adaptive render writes its image and spp map" '[ -s "$T/a.exr" ] && [ -s "$T/map.png" ]'
check "the EXR header names the mean, the pilot and the cap" \
    'grep -a -q "mean_spp 8, min_spp 2, max_spp 64, noise_threshold 0" "$T/a.exr"'
$S render --width 16 --height 16 --sampler random --adaptive --spp 8 -o "$T/b.exr" > "$T/sum" 2>&1
check "the summary gives the samples per pixel on average, at most --spp" \
    'grep -q "adaptive: [0-9]* samples in all, [0-8]\.[0-9]* per pixel (pilot 2, at most 64)" "$T/sum"' \
    "($(tail -1 "$T/sum"))"
check "random stays adaptive: no fallback note" '! grep -q "renders uniformly" "$T/sum"'
for smp in halton sobol; do
    $S render $P --sampler $smp --adaptive --spp 8 -o "$T/q.exr" > "$T/sum" 2>&1
    check "--adaptive with $smp adapts: no note" '! grep -q "note: --adaptive" "$T/sum"' "($(cat "$T/sum"))"
    check "--adaptive with $smp: the EXR header names the mean, the pilot and the cap" \
        'grep -a -q "mean_spp 8, pilot 2, max_spp 64, noise_threshold 0" "$T/q.exr"'
    $S render --width 16 --height 12 furnace --sampler $smp --adaptive --spp 8 -o "$T/f.exr" \
        > "$T/sum" 2> "$T/note"
    $S render --width 16 --height 12 furnace --sampler $smp --spp 8 -o "$T/u.exr" 2> /dev/null
    check "--adaptive with $smp on the furnace: one note, no gain predicted" \
        '[ "$(grep -c "^strata: note: --adaptive with sampler $smp rendered uniformly at 8 spp: its pilot predicted" "$T/note")" = 1 ]' \
        "($(cat "$T/note"))"
    check "--adaptive with $smp on the furnace: the EXR header says it went on uniformly" \
        'grep -a -q "uniform at mean_spp 8 (sampler $smp: its pilot predicted" "$T/f.exr"'
    check "--adaptive with $smp on the furnace: the image is the uniform render's" \
        '$S diff "$T/f.exr" "$T/u.exr" 2>&1 | grep -q "max_abs 0$"'
done
for smp in pmj02 zsobol stratified; do
    $S render $P --sampler $smp --adaptive --spp 8 -o "$T/f.exr" 2> "$T/note"
    $S render $P --sampler $smp --spp 8 -o "$T/u.exr" 2> /dev/null
    check "--adaptive with $smp: one note naming it" \
        '[ "$(grep -c "^strata: note: --adaptive with sampler $smp renders uniformly at 8 spp: its stratification" "$T/note")" = 1 ]' \
        "($(cat "$T/note"))"
    check "--adaptive with $smp: the EXR header says it fell back" \
        'grep -a -q "fallback: uniform at mean_spp 8 (sampler $smp: " "$T/f.exr"'
    check "--adaptive with $smp: the image is the uniform render's" \
        '$S diff "$T/f.exr" "$T/u.exr" 2>&1 | grep -q "max_abs 0$"'
done
expect "a cap below the mean exits 2" 2 "^strata: error: --max-spp 15: must be at least the mean spp 16" \
    $S render $P --adaptive --spp 16 --max-spp 15 -o "$T/x.exr"
expect "a pilot of the whole budget exits 2" 2 "^strata: error: --min-spp 16: the pilot must be below" \
    $S render $P --adaptive --spp 16 --min-spp 16 -o "$T/x.exr"
expect "a negative threshold exits 2" 2 "^strata: error: --noise-threshold -1: must not be negative" \
    $S render $P --adaptive --noise-threshold -1 -o "$T/x.exr"
expect "--max-spp without --adaptive exits 2" 2 "^strata: error: --max-spp applies to adaptive renders only" \
    $S render $P --max-spp 32 -o "$T/x.exr"
$S bench $P --sampler random --adaptive --spp 8 --cold > "$T/bench" 2> /dev/null
# in the order each first ran: the later rounds' sort by tile comes between
check "bench names the adaptive kernels it ran" \
    'grep "^kernels *lanes [0-9]*: " "$T/bench" | grep "adaptive_moments, adaptive_estimate" |
     grep -q "adaptive_blend"'
check "bench measures an adaptive render's kernel build" \
    'grep -q "^kernels *cold build [0-9][0-9.]* s, cached [0-9][0-9.]* s" "$T/bench"'
echo "1..$n"
