#!/bin/sh
# test_glass_depth.sh — the default max depth follows the scene
# (st_render_default_depth): 12 where a material transmits, so a lamp seen
# through four glass panes (tests/scenes/glass_panes.gltf: eight interfaces
# before the lamp) is lit at the defaults and within 2 % of a render at
# depth 16 (the image's RMS against black), where depth 5, the default
# without glass, leaves it black; a scene without glass keeps 5; a
# --max-depth given wins. TAP output.
. tests/tap.sh
R="--width 24 --height 24 --spp 64 --env 0 --quiet"
rms_of() { "$S" diff "$1" "$T/black.exr" 2> /dev/null | sed -n 's/^rmse //p'; }
G=tests/scenes/glass_panes.gltf

"$S" render tests/scenes/layout_u16.gltf $R -o "$T/black.exr" 2> /dev/null
"$S" render $G $R -o "$T/d.exr" 2> /dev/null
for d in 5 12 16; do "$S" render $G $R --max-depth $d -o "$T/d$d.exr" 2> /dev/null; done
rmse=$("$S" diff "$T/d.exr" "$T/d12.exr" 2> /dev/null | sed -n 's/^rmse //p')
check "glass: the default depth is 12 (the same image as --max-depth 12)" "[ '$rmse' = 0 ]" "(rmse $rmse)"
a=$(rms_of "$T/d.exr") b=$(rms_of "$T/d16.exr") c=$(rms_of "$T/d5.exr")
check "the lamp behind four panes is lit at the defaults, within 2 % of depth 16" \
    "[ -n '$a' ] && [ -n '$b' ] && awk 'BEGIN { exit !($b > 1 && ($b - $a) / $b < 0.02 && ($a - $b) / $b < 0.02) }'" \
    "(RMS $a, at depth 16 $b)"
check "at depth 5, the old default, it is black" "[ '$c' = 0 ]" "(RMS $c)"

"$S" render cornell-box --width 16 --height 16 --spp 2 --quiet -o "$T/c.exr" 2> /dev/null
"$S" render cornell-box --width 16 --height 16 --spp 2 --quiet --max-depth 5 -o "$T/c5.exr" 2> /dev/null
rmse=$("$S" diff "$T/c.exr" "$T/c5.exr" 2> /dev/null | sed -n 's/^rmse //p')
check "without glass the default stays 5" "[ '$rmse' = 0 ]" "(rmse $rmse)"
echo "1..$n"
