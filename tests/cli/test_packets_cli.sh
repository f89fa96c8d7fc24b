#!/bin/sh
# test_packets_cli.sh — which rays `--packets auto` traces in packets, as
# `strata bench` reports it: coherent rays where the kernels have lanes (a
# CPU device's, src/render/plan.c), on small scenes and large ones alike, none
# at one lane; an explicit choice is kept. --lanes builds the kernels at the
# width asked, which bench and the EXR header name with the kernels that
# ran, and leaves the image as it is, its compiler's warnings about vectors
# wider than the device's silenced; the trace benchmark says when it sorted
# its rays. TAP output.
. tests/tap.sh

B="--width 16 --height 16 --spp 1 --integrator direct"
ICO=${BUILD:-build/release}/make_icosphere
"$ICO" "$T/ico6" 6 > /dev/null # 20 x 4^6 = 81,920 triangles
"$ICO" "$T/ico5" 5 > /dev/null # 20,480 triangles
# the packets named on bench's settings line
packets() { sed -n 's/^settings .*, packets \([a-z]*\)$/\1/p' "$1"; }
$S bench cornell-box $B > "$T/cornell" 2> /dev/null
$S bench "$T/ico5.gltf" $B > "$T/ico5" 2> /dev/null
$S bench "$T/ico6.gltf" $B > "$T/ico6" 2> /dev/null
$S bench "$T/ico6.gltf" $B --packets none > "$T/ico6-none" 2> /dev/null
$S bench cornell-box $B --lanes 1 > "$T/cornell-w1" 2> /dev/null
$S bench cornell-box $B --packets all --json > "$T/cornell-all.json" 2> /dev/null
check "the level-6 icosphere has 81,920 triangles" 'grep -q "(81920 triangles" "$T/ico6"'
check "auto: coherent for the 32-triangle Cornell box" '[ "$(packets "$T/cornell")" = coherent ]'
check "auto: coherent for 20,480 triangles" '[ "$(packets "$T/ico5")" = coherent ]'
check "auto at --lanes 1: none" '[ "$(packets "$T/cornell-w1")" = none ]'
check "auto: coherent for 81,920 triangles" '[ "$(packets "$T/ico6")" = coherent ]'
check "--packets none is kept on a large scene" '[ "$(packets "$T/ico6-none")" = none ]'
check "--packets all is kept on a small scene, and --json names it" \
    'grep -q "\"packets\":[ ]*\"all\"" "$T/cornell-all.json"'

# --lanes: the width asked, the kernels named, the image unchanged
$S bench cornell-box $B --packets all --lanes 4 --json > "$T/lanes4.json" 2> /dev/null
check "bench --lanes 4 --json names the width" 'grep -q "\"lanes\":[ ]*4" "$T/lanes4.json"'
check "bench --json names the packet kernel it ran" \
    'grep -q "\"kernels\":[ ]*\"lanes 4: .*trace_rays_packet" "$T/lanes4.json"'
R="cornell-box --width 20 --height 12 --spp 2 -q"
$S render $R -o "$T/default.exr" 2> /dev/null
for w in 1 4 16; do
    $S render $R --lanes $w --packets all -o "$T/w$w.exr" 2> /dev/null
    check "--lanes $w --packets all: the same image" \
        '$S diff "$T/default.exr" "$T/w$w.exr" --max-rmse 0 > "$T/diff" && grep -q "max_abs 0$" "$T/diff"'
done
# built afresh at 16 lanes, wider than AVX2's registers: clang's warnings
# about the ABI of such vectors stay off the terminal
POCL_CACHE_DIR="$T/cache" $S render $R --lanes 16 -o "$T/fresh16.exr" 2> "$T/fresh16.err"
check "a fresh build at --lanes 16 prints no compiler warnings" \
    '[ -s "$T/fresh16.exr" ] && ! grep -q "warning" "$T/fresh16.err"' "($(grep -m1 warning "$T/fresh16.err"))"
check "the EXR header names the kernels and their width" \
    'grep -a -q "lanes 16: generate_rays" "$T/w16.exr"'
# the trace benchmark sorts its rays first in a scene of 65,536 triangles or
# more on a CPU device, and says so; the hits are the rays' own either way
if $S devices 2> /dev/null | grep -q "Portable Computing Language"; then
    $S bench "$T/ico6.gltf" --rays random --count 5000 --json > "$T/ico6-rays" 2> /dev/null
    $S bench "$T/ico6.gltf" --rays random --count 5000 > "$T/ico6-rays.txt" 2> /dev/null
    $S bench "$T/ico5.gltf" --rays random --count 5000 --json > "$T/ico5-rays" 2> /dev/null
    sorted() { python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["rays"]["sorted"])' "$1"; }
    check "bench --rays sorts the rays of 81,920 triangles, and says so" \
        '[ "$(sorted "$T/ico6-rays")" = True ] && grep -q "(sorted by ray first, sort counted)$" "$T/ico6-rays.txt"'
    check "... not those of 20,480" '[ "$(sorted "$T/ico5-rays")" = False ]'
fi
$S devices > "$T/devices"
check "devices names each device's lanes and how they were chosen" \
    'grep -q "| lanes \(1\|4\|8\|16\) (" "$T/devices"'
expect "--lanes 3 is a usage error" 2 "strata: error: --lanes 3: must be auto, 1, 4, 8 or 16" \
    $S render cornell-box --lanes 3 -o "$T/x.exr"
check "... and writes nothing" '[ ! -e "$T/x.exr" ]'
echo "1..$n"
