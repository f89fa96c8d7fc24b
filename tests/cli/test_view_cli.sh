#!/bin/sh
# test_view_cli.sh — the camera from the command line: --look-at and --fov
# parsed strictly, their geometry checked in the flags' words, and the view
# recorded in the EXR header (strata.camera, strata.fov). Where they land
# the image: tests/device/test_view.c. TAP output.
. tests/tap.sh
M=tests/scenes/markers.gltf
R="--width 16 --height 16 --spp 1 --quiet --env 0"

expect "--look-at with 5 numbers exits 2" 2 "^strata: error: --look-at 1,2,3,4,5: expected EX,EY,EZ,TX,TY,TZ" \
    "$S" render $M $R --look-at 1,2,3,4,5 -o "$T/o.exr"
expect "--look-at with a word exits 2" 2 "^strata: error: --look-at 1,2,3,4,5,x: expected" \
    "$S" render $M $R --look-at 1,2,3,4,5,x -o "$T/o.exr"
expect "--look-at with the eye on the target exits 2" 2 \
    "^strata: error: --look-at: the eye and the target are the same point" \
    "$S" render $M $R --look-at 1,2,3,1,2,3 -o "$T/o.exr"
expect "--look-at with up along the view exits 2" 2 "^strata: error: --look-at: the up vector 0,0,1 lies along the view" \
    "$S" render $M $R --look-at 0,0,5,0,0,0,0,0,1 -o "$T/o.exr"
expect "--look-at straight down without an up exits 2" 2 "^strata: error: --look-at: the up vector 0,1,0 lies along the view" \
    "$S" render $M $R --look-at 0,5,0,0,0,0 -o "$T/o.exr"
expect "--fov 0 exits 2" 2 "^strata: error: --fov 0: must lie strictly between 0 and 180" \
    "$S" render $M $R --fov 0 -o "$T/o.exr"
expect "--fov 180 exits 2" 2 "^strata: error: --fov 180: must lie strictly between 0 and 180" \
    "$S" render $M $R --fov 180 -o "$T/o.exr"
expect "--fov on an orthographic camera exits 2" 2 "^strata: error: --fov 30: the view's camera is orthographic" \
    "$S" render tests/scenes/aov_plane.gltf $R --fov 30 -o "$T/o.exr"
check "no image is left by the refused renders" '[ ! -e "$T/o.exr" ]'

"$S" render $M $R --look-at 1.25,1.5,1,1,2,-3,0.25,1,0 --fov 25 -o "$T/v.exr" 2> "$T/err"
check "a --look-at render succeeds" '[ -s "$T/v.exr" ]' "$(head -c 300 "$T/err")"
check "the EXR header records the look-at" 'grep -aq "look-at 1.25,1.5,1,1,2,-3,0.25,1,0" "$T/v.exr"'
check "the EXR header records the field of view" 'grep -aq "strata.fov" "$T/v.exr"'
"$S" render $M $R --look-at 1.25,1.5,1,1,2,-3 -o "$T/up.exr" 2> /dev/null
check "the up vector defaults to +Y" 'grep -aq "look-at 1.25,1.5,1,1,2,-3,0,1,0" "$T/up.exr"'
echo "1..$n"
