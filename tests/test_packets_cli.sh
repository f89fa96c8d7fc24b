#!/bin/sh
# test_packets_cli.sh — which rays `--packets auto` traces in packets, as
# `strata bench` reports it: coherent rays on a CPU device for a scene of at
# least 65,536 triangles (src/render.c, ST_PACKET_MIN_TRIANGLES), none for a
# small one; an explicit choice is kept. TAP output.
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
$S bench cornell-box $B --packets all --json > "$T/cornell-all.json" 2> /dev/null
check "the level-6 icosphere has 81,920 triangles" 'grep -q "(81920 triangles" "$T/ico6"'
check "auto: none for the 32-triangle Cornell box" '[ "$(packets "$T/cornell")" = none ]'
check "auto: none for 20,480 triangles" '[ "$(packets "$T/ico5")" = none ]'
check "auto: coherent for 81,920 triangles" '[ "$(packets "$T/ico6")" = coherent ]'
check "--packets none is kept on a large scene" '[ "$(packets "$T/ico6-none")" = none ]'
check "--packets all is kept on a small scene, and --json names it" \
    'grep -q "\"packets\":[ ]*\"all\"" "$T/cornell-all.json"'
echo "1..$n"
