#!/bin/sh
# test_crop.sh — render --crop X,Y,W,H: the window's pixels equal the full
# render's there bit for bit (strata diff compares a crop with its full render
# over the crop's data window: rmse 0 and largest difference 0), for filters
# whose splats reach 1, 2 and 3 pixels (the apron), filter importance
# sampling, a tiled sampler and adaptive sampling, at the image's corners and inside; split
# parts of a crop merge into the same window; a PNG of a crop is the window
# alone; bad windows are usage errors. TAP output.
. tests/tap.sh
P="--width 40 --height 28 --spp 4 --quiet"
# bit_equal NAME OPTIONS CROP: the crop of a render with OPTIONS equals its full render
bit_equal() {
    $S render $P $2 -o "$T/full.exr" && $S render $P $2 --crop "$3" -o "$T/crop.exr" &&
        $S diff "$T/crop.exr" "$T/full.exr" > "$T/diff" 2>&1
    check "$1" 'grep -q "^rmse 0$" "$T/diff" && grep -q "^max_abs 0$" "$T/diff"' "($(cat "$T/diff"))"
}
bit_equal "crop equals the full render: mitchell (radius 2), inside" "" 9,5,17,11
bit_equal "crop equals the full render: lanczos (radius 3), top-left corner" "--filter lanczos" 0,0,13,9
bit_equal "crop equals the full render: box (radius 0.5), bottom-right corner" "--filter box" 30,20,10,8
bit_equal "crop equals the full render: gaussian, sobol, one pixel" "--filter gaussian --sampler sobol" 21,13,1,1
bit_equal "crop equals the full render: filter importance sampling" "--reconstruction fis --filter lanczos" 3,4,20,10
bit_equal "crop equals the full render: tiled sampler (poisson)" "--sampler poisson --filter mitchell" 11,2,15,20
bit_equal "crop equals the full render: adaptive sampling" "--adaptive --sampler random --min-spp 2" 3,4,20,10

# the check can fail: another seed's crop differs from the full render
$S render $P --seed 1 --crop 9,5,17,11 -o "$T/other.exr"
$S render $P -o "$T/full.exr"
$S diff "$T/other.exr" "$T/full.exr" > "$T/diff" 2>&1
check "a crop of another seed differs (the comparison can fail)" '! grep -q "^rmse 0$" "$T/diff"' "($(cat "$T/diff"))"

# the data window is the crop: a crop moved by one pixel no longer matches
$S render $P --crop 10,5,17,11 -o "$T/moved.exr"
$S diff "$T/moved.exr" "$T/crop.exr" > "$T/diff" 2>&1
check "diff compares overlapping windows pixel by pixel (shifted crops differ)" \
    'grep -q "^rmse " "$T/diff" && ! grep -q "^rmse 0$" "$T/diff"' "($(cat "$T/diff"))"
expect "diff refuses windows that do not overlap" 1 "do not overlap" \
    sh -c "$S render $P --crop 0,0,5,5 -o $T/a.exr && $S render $P --crop 30,20,5,5 -o $T/b.exr && $S diff $T/a.exr $T/b.exr"
expect "diff refuses images of different sizes" 1 "sizes differ" \
    sh -c "$S render --width 20 --height 14 --spp 4 --quiet -o $T/small.exr && $S diff $T/small.exr $T/full.exr"

# split parts of a crop merge into the window of one full render
M="--filter mitchell --sampler stratified"
$S render $P $M -o "$T/full.exr"
$S render $P $M --crop 4,3,25,17 --sample-range 0:1 -o "$T/p1.exr"
$S render $P $M --crop 4,3,25,17 --sample-range 1:4 -o "$T/p2.exr"
$S merge "$T/p1.exr" "$T/p2.exr" -o "$T/merged.exr" 2> "$T/err"
$S diff "$T/merged.exr" "$T/full.exr" > "$T/diff" 2>&1
check "merged parts of a crop equal the full render's window bit for bit" \
    'grep -q "^rmse 0$" "$T/diff" && grep -q "^max_abs 0$" "$T/diff"' "($(cat "$T/diff") $(cat "$T/err"))"
$S render $P $M --crop 4,4,25,17 --sample-range 1:4 -o "$T/p3.exr"
expect "merge refuses parts of different windows" 1 "data window at (4, 4)" \
    $S merge "$T/p1.exr" "$T/p3.exr" -o "$T/bad.exr"
$S render $P $M --sample-range 1:4 -o "$T/p4.exr"
expect "merge refuses a whole part with a crop's part" 1 "pixels, but" \
    $S merge "$T/p1.exr" "$T/p4.exr" -o "$T/bad.exr"

# the summary names the window
$S render --width 40 --height 28 --spp 4 --crop 4,3,25,17 -o "$T/c.exr" > "$T/summary" 2> /dev/null
check "the summary names the window" 'grep -q "rendered 40x28, window 25x17 at (4, 3), 4 spp" "$T/summary"' "($(cat "$T/summary"))"

# a PNG of a crop is the window alone: width and height from the IHDR chunk
$S render $P --crop 4,3,25,17 -o "$T/crop.png"
size=$(od -An -tu1 -j16 -N8 "$T/crop.png" | awk '{print $3 * 256 + $4 "x" $7 * 256 + $8}')
check "a PNG of a 25x17 crop is 25x17 pixels" '[ "$size" = "25x17" ]' "($size)"

# usage errors: exit 2, one line naming --crop
expect "a window past the right edge is a usage error" 2 "^strata: error: --crop 30,0,11,5: the window must be non-empty and inside the 40x28 image" \
    $S render $P --crop 30,0,11,5 -o "$T/x.exr"
expect "a window past the bottom edge is a usage error" 2 "inside the 40x28 image" \
    $S render $P --crop 0,27,1,2 -o "$T/x.exr"
expect "an empty window is a usage error" 2 "^strata: error: --crop 3,3,0,4: the window is empty" \
    $S render $P --crop 3,3,0,4 -o "$T/x.exr"
expect "a malformed window is a usage error" 2 "expected X,Y,W,H" \
    $S render $P --crop 3,3,4 -o "$T/x.exr"
expect "a negative origin is a usage error" 2 "expected X,Y,W,H" \
    $S render $P --crop -1,3,4,4 -o "$T/x.exr"
expect "bench takes no --crop" 2 "only \`strata render\` takes it" \
    $S bench $P --crop 0,0,4,4
echo "1..$n"
