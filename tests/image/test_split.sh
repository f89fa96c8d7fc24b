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

# the recipe: 4 parts of 4 samples each, as independent jobs
parallel --will-cite -j 2 "$S render $OPTS --part {}/4 -o $T/part{}.exr" ::: 0 1 2 3
check "GNU parallel renders 4 parts" '[ "$(ls "$T"/part*.exr | wc -l)" -eq 4 ]'
$S merge "$T"/part*.exr -o "$T/merged.exr" 2> "$T/err"
check "merge of the parts succeeds" '[ -s "$T/merged.exr" ]'
$S render $OPTS -o "$T/whole.exr"
$S merge "$T"/part*.exr -o "$T/merged.png" -o - 2> /dev/null | cat > "$T/piped.png"
check "merge -o - writes the PNG to standard output" '$S diff "$T/piped.png" "$T/merged.png" | grep -qx "rmse 0"'
$S diff "$T/whole.exr" "$T/merged.exr" > "$T/diff"
check "merged equals one render bit for bit" 'grep -q "^rmse 0$" "$T/diff" && grep -q "^max_abs 0$" "$T/diff"'
$S render --width 48 --height 32 --spp 16 --sampler stratified --seed 6 --quiet --sample-range 0:4 -o "$T/seed6.exr"
$S merge "$T/part0.exr" "$T/seed6.exr" -o "$T/bad.exr" 2> "$T/err"
check "parts of another seed are refused, naming the setting" 'grep -q "strata.seed is" "$T/err" && [ ! -e "$T/bad.exr" ]'
$S render $OPTS --sample-range 2:6 -o "$T/overlap.exr"
$S merge "$T/part0.exr" "$T/overlap.exr" -o "$T/bad.exr" 2> "$T/err"
check "overlapping sample ranges are refused" 'grep -q "overlap" "$T/err" && [ ! -e "$T/bad.exr" ]'
$S render --width 40 --height 32 --spp 16 --sampler stratified --filter mitchell --seed 5 --quiet --sample-range 4:8 -o "$T/size.exr"
$S merge "$T/part0.exr" "$T/size.exr" -o "$T/bad.exr" 2> "$T/err"
check "parts of another size are refused" 'grep -q "40x32 pixels" "$T/err"'
$S merge "$T/whole.exr" -o "$T/bad.exr" 2> "$T/err"
check "a resolved image is not a part" 'grep -q "not the raw film of a split render" "$T/err"'

# --part K/N: 10 spp in 4 parts tile 0..10 (merge refuses gaps and overlaps)
# in parts of 2 or 3 samples, and merge to the whole render
P="--width 24 --height 16 --spp 10 --sampler stratified --seed 2 --quiet"
for k in 0 1 2 3; do $S render $P --part $k/4 -o "$T/q$k.exr"; done
$S merge "$T"/q?.exr -o "$T/qmerged.exr" 2> "$T/err"
$S render $P -o "$T/qwhole.exr"
$S diff "$T/qwhole.exr" "$T/qmerged.exr" > "$T/diff" 2>&1
check "--part K/4 of 10 spp: the parts tile 0..10 and merge to one render bit for bit" \
    'grep -q "^rmse 0$" "$T/diff" && grep -q "^max_abs 0$" "$T/diff"'
sizes=""
for k in 0 1 2 3; do # the range a part holds, as merge --partial reads it from its header
    $S merge --partial "$T/q$k.exr" -o "$T/one.exr" 2> "$T/err"
    range=$(sed -n 's/.*the image holds \([0-9]*:[0-9]*\) of 10 spp.*/\1/p' "$T/err")
    sizes="$sizes $((${range#*:} - ${range%:*}))"
done
check "--part K/4 of 10 spp: parts of 2 or 3 samples" '[ "$(echo $sizes | tr " " "\n" | sort -u | tr "\n" " ")" = "2 3 " ]' "(sizes:$sizes)"
check "the EXR header records --part" 'grep -a -q "strata.part" "$T/q2.exr" && grep -a -q "2/4" "$T/q2.exr"'
check "the merged image does not claim one part" '! grep -a -q "strata.part" "$T/qmerged.exr"'
for bad in 4/4 1/0 x/2 1:2; do
    $S render $P --part $bad -o "$T/bad.exr" 2> "$T/err"
    status=$?
    check "--part $bad is refused" '[ $status -eq 2 ] && grep -q "^strata: error: --part $bad: expected K/N" "$T/err"'
done
$S render $P --part 0/11 -o "$T/bad.exr" 2> "$T/err"
check "--part 0/11 of 10 spp is refused (a part without samples)" 'grep -q "^strata: error: --part 0/11: 11 parts of --spp 10" "$T/err"'
$S render $P --part 0/2 --sample-range 0:1 -o "$T/bad.exr" 2> "$T/err"
check "--part with --sample-range is refused" 'grep -q "both choose the samples" "$T/err"'
echo "1..$n"
