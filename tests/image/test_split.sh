#!/bin/sh
# test_split.sh — the README's GNU parallel recipe with 4 parts on this
# machine: the merged image equals one render of all the samples, bit for bit
# (strata diff: rmse 0 and largest difference 0). TAP output.
S=${STRATA:-./strata}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
n=0
check() { n=$((n + 1)); if eval "$2"; then echo "ok $n - $1"; else echo "not ok $n - $1"; fi; }
OPTS="--width 48 --height 32 --spp 16 --sampler stratified --filter mitchell --seed 5 --quiet"

# the recipe: parts of 4 samples each, as independent jobs
parallel --will-cite -j 2 --link "$S render $OPTS --sample-range {1}:{2} -o $T/part{#}.exr" \
    ::: 0 4 8 12 ::: 4 8 12 16
check "GNU parallel renders 4 parts" '[ "$(ls "$T"/part*.exr | wc -l)" -eq 4 ]'
$S merge "$T"/part*.exr -o "$T/merged.exr" 2> "$T/err"
check "merge of the parts succeeds" '[ -s "$T/merged.exr" ]'
$S render $OPTS -o "$T/whole.exr"
$S diff "$T/whole.exr" "$T/merged.exr" > "$T/diff"
check "merged equals one render bit for bit" 'grep -q "^rmse 0$" "$T/diff" && grep -q "^max_abs 0$" "$T/diff"'
$S render --width 48 --height 32 --spp 16 --sampler stratified --seed 6 --quiet --sample-range 0:4 -o "$T/seed6.exr"
$S merge "$T/part1.exr" "$T/seed6.exr" -o "$T/bad.exr" 2> "$T/err"
check "parts of another seed are refused, naming the setting" 'grep -q "strata.seed is" "$T/err" && [ ! -e "$T/bad.exr" ]'
$S render $OPTS --sample-range 2:6 -o "$T/overlap.exr"
$S merge "$T/part1.exr" "$T/overlap.exr" -o "$T/bad.exr" 2> "$T/err"
check "overlapping sample ranges are refused" 'grep -q "overlap" "$T/err" && [ ! -e "$T/bad.exr" ]'
$S render --width 40 --height 32 --spp 16 --sampler stratified --filter mitchell --seed 5 --quiet --sample-range 4:8 -o "$T/size.exr"
$S merge "$T/part1.exr" "$T/size.exr" -o "$T/bad.exr" 2> "$T/err"
check "parts of another size are refused" 'grep -q "40x32 pixels" "$T/err"'
$S merge "$T/whole.exr" -o "$T/bad.exr" 2> "$T/err"
check "a resolved image is not a part" 'grep -q "not the raw film of a split render" "$T/err"'
echo "1..$n"
