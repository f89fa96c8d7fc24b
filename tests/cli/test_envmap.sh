#!/bin/sh
# test_envmap.sh — --env FILE and --env-rotate through the command line: a
# map read from an EXR (a render of strata's own, float RGB) lights a scene
# and names itself in the output's header; the rotation changes the image;
# bad maps are one `strata: error:` line naming the file, exit 1 (missing,
# not a float image, black everywhere, an impossible size, refused from an
# EXR's or .hdr's header before decoding), and bad options
# exit 2. TAP output.
. tests/tap.sh
R="--width 16 --height 12 --spp 2 --quiet"
BUILD=${BUILD:-build/release}

# the sky that ships (the README's first model example) is make_envmap's, and lights
# a model that emits nothing
if [ -x "$BUILD/make_envmap" ]; then
    "$BUILD/make_envmap" sky "$T/sky.hdr" > /dev/null
    check "scenes/envmaps/sky.hdr is tools/make_envmap.c's sky, byte for byte" 'cmp -s "$T/sky.hdr" scenes/envmaps/sky.hdr'
else
    skip "$BUILD/make_envmap is not built (make test builds it)"
fi
"$S" render tests/scenes/layout_u16.gltf $R --env 0 -o "$T/dark.exr" 2> /dev/null
"$S" render tests/scenes/layout_u16.gltf $R --env scenes/envmaps/sky.hdr -o "$T/sky.exr" 2> "$T/err"
rmse=$("$S" diff "$T/sky.exr" "$T/dark.exr" 2> /dev/null | sed -n 's/^rmse //p')
check "the shipped sky lights a model, without a note" \
    "[ -n '$rmse' ] && awk 'BEGIN { exit !($rmse > 0.01) }' && ! grep -q 'note:\|warning:' '$T/err'" "(rmse $rmse)"

"$S" render cornell-box --width 32 --height 16 --spp 4 --quiet -o "$T/map.exr" 2> /dev/null
"$S" render tests/scenes/layout_u16.gltf $R --env 0 -o "$T/black.exr" 2> /dev/null
"$S" render tests/scenes/layout_u16.gltf $R --env "$T/map.exr" -o "$T/lit.exr" 2> "$T/err"
check "a map lights a scene that emits nothing, without a note" \
    "[ -f '$T/lit.exr' ] && ! grep -q 'note:\\|warning:' '$T/err'"
rmse=$("$S" diff "$T/lit.exr" "$T/black.exr" 2> /dev/null | sed -n 's/^rmse //p')
check "and the image is lit" "[ -n '$rmse' ] && awk 'BEGIN { exit !($rmse > 0.01) }'" "(rmse $rmse)"
"$S" render tests/scenes/layout_u16.gltf $R --env "$T/map.exr" --env-rotate 90 -o "$T/turned.exr" \
    2> /dev/null
rmse=$("$S" diff "$T/lit.exr" "$T/turned.exr" 2> /dev/null | sed -n 's/^rmse //p')
check "--env-rotate 90 changes the image" "[ -n '$rmse' ] && awk 'BEGIN { exit !($rmse > 0) }'" \
    "(rmse $rmse)"
"$S" render tests/scenes/layout_u16.gltf $R --env "$T/map.exr" --env-rotate 90 -o "$T/again.exr" \
    2> /dev/null
check "the same command, the same image" "cmp -s '$T/turned.exr' '$T/again.exr' || \
    [ \"\$('$S' diff '$T/turned.exr' '$T/again.exr' 2> /dev/null | sed -n 's/^rmse //p')\" = 0 ]"
check "the header names the map and the turn" \
    "strings '$T/turned.exr' | grep -q 'map.exr' && strings '$T/turned.exr' | grep -q 'strata.env_rotate'"

printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 100000\n' > "$T/huge.hdr"
"$S" render cornell-box $R -o "$T/ldr.png" 2> /dev/null
cp "$T/ldr.png" "$T/ldr.hdr"
expect "a missing map exits 1 naming it" 1 "^strata: error: $T/none.hdr: cannot open" \
    "$S" render cornell-box $R --env "$T/none.hdr" -o "$T/o.exr"
expect "an 8-bit image is not a map" 1 "^strata: error: $T/ldr.hdr: not a Radiance HDR" \
    "$S" render cornell-box $R --env "$T/ldr.hdr" -o "$T/o.exr"
expect "a black map exits 1" 1 "^strata: error: $T/black.exr: the environment map is black" \
    "$S" render cornell-box $R --env "$T/black.exr" -o "$T/o.exr"
expect "an impossible size exits 1 before decoding" 1 \
    "^strata: error: $T/huge.hdr: 100000 x 100000 texels: an environment map has 1 to 2^26" \
    "$S" render cornell-box $R --env "$T/huge.hdr" -o "$T/o.exr"
# the small map's header, its data window claiming 16384 x 16384 (3 GiB of floats)
python3 - "$T/map.exr" "$T/huge.exr" << 'EOF'
import struct, sys
b = bytearray(open(sys.argv[1], "rb").read())
k = b.index(b"dataWindow\0box2i\0") + len(b"dataWindow\0box2i\0")
struct.pack_into("<4i", b, k + 4, 0, 0, 16383, 16383)
open(sys.argv[2], "wb").write(b)
EOF
expect "an EXR map of impossible size exits 1 before decoding (in 1 GB of memory)" 1 \
    "^strata: error: $T/huge.exr: 16384 x 16384 texels: an environment map has 1 to 2^26" \
    sh -c "ulimit -v 1000000; exec '$S' render cornell-box $R --env '$T/huge.exr' -o '$T/o.exr'"
expect "another extension is a usage error" 2 "^strata: error: --env sky.png: expected R,G,B" \
    "$S" render cornell-box $R --env sky.png -o "$T/o.exr"
expect "--env-rotate without a map exits 2" 2 "^strata: error: --env-rotate turns an environment map" \
    "$S" render cornell-box $R --env-rotate 30 -o "$T/o.exr"
expect "--env-rotate takes a number" 2 "^strata: error: --env-rotate x: expected a finite number" \
    "$S" render cornell-box $R --env "$T/map.exr" --env-rotate x -o "$T/o.exr"
echo "1..$n"
