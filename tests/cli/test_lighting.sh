#!/bin/sh
# test_lighting.sh — the lighting default through the command line: decided
# by the power the scene emits (emissive factor x the emissive texture's
# mean), not by the emissive factor alone, and by who emits it (st_scene.h):
# a scene that emits nothing, or whose emitters are dim, gets the white
# environment; one lit by lamps or punctual lights gets none, or a dim one
# where they would leave most of the view black. Each render
# without --env says which in one `strata: note:` naming the option that
# changes it; a render with no light at all is a `strata: warning:` (and
# black, exit 0). TAP output.
. tests/tap.sh
R="--width 16 --height 12 --spp 2 --quiet"
mean_of() { "$S" diff "$1" "$2" 2> /dev/null | sed -n 's/^rmse //p'; }

"$S" render tests/scenes/layout_u16.gltf $R --env 0 -o "$T/black.exr" 2> "$T/err0"
check "no light at all is a warning" "grep -q '^strata: warning: .*no light at all' '$T/err0'"

"$S" render tests/scenes/black_emitter.gltf $R -o "$T/q.exr" 2> "$T/err1"
check "a black emissive texture leaves the white environment on, with a note" \
    "grep -q '^strata: note: .*nothing in the scene emits light' '$T/err1'"
rmse=$(mean_of "$T/q.exr" "$T/black.exr")
check "the black emitter is lit" "[ -n '$rmse' ] && awk 'BEGIN { exit !($rmse > 0.1) }'" "(rmse $rmse)"

"$S" render cornell-box $R -o "$T/c.exr" 2> "$T/err2"
check "a scene lit by its lamp: one note, no environment, --env 1 to add one" \
    "[ \$(wc -l < '$T/err2') -eq 1 ] && grep -q '^strata: note: cornell-box: lit by its own lights alone, no environment (--env 1 for a white one)' '$T/err2'"

"$S" render tests/scenes/textured_quad.gltf $R -o "$T/d.exr" 2> "$T/err5"
check "a scene whose emitters are dim: one note, the white environment, --env 0 to turn it off" \
    "[ \$(wc -l < '$T/err5') -eq 1 ] && grep -q '^strata: note: .*lit by the default sky as well (--env 0 to turn it off)' '$T/err5'"
"$S" render tests/scenes/textured_quad.gltf $R --env 0 -o "$T/d0.exr" 2> /dev/null
rmse=$(mean_of "$T/d.exr" "$T/d0.exr")
check "and the environment lights it (against --env 0)" "[ -n '$rmse' ] && awk 'BEGIN { exit !($rmse > 0.1) }'" "(rmse $rmse)"

"$S" render furnace $R -o "$T/f.exr" 2> "$T/err6"
check "a camera inside a closed model: one note, no environment, --env 1 to add one" \
    "[ \$(wc -l < '$T/err6') -eq 1 ] && grep -q '^strata: note: furnace: the camera is inside a closed model; no environment (--env 1 for a white one)' '$T/err6'"

"$S" render tests/scenes/dark_box.gltf $R -o "$T/dark.exr" 2> "$T/err7"
check "nothing emits and the camera is enclosed: one note naming the light at the camera" \
    "[ \$(wc -l < '$T/err7') -eq 1 ] && grep -q '^strata: note: tests/scenes/dark_box.gltf: nothing in it emits light and the camera is inside a closed model, where no sky reaches; a light at the default camera lights it' '$T/err7'"
"$S" render tests/scenes/dark_box.gltf $R --env 1 -o "$T/dark1.exr" 2> "$T/err8"
check "... the same note with --env, the light being the scene's" \
    "[ \$(wc -l < '$T/err8') -eq 1 ] && grep -q 'a light at the default camera lights it' '$T/err8'"
rmse=$(mean_of "$T/dark.exr" "$T/black.exr")
check "and that light lights the view" "[ -n '$rmse' ] && awk 'BEGIN { exit !($rmse > 0.1) }'" "(rmse $rmse)"

"$S" render tests/scenes/black_emitter.gltf $R --env 0.5 -o "$T/e.exr" 2> "$T/err3"
check "an --env given is no note" "! grep -q 'note:\|warning:' '$T/err3'"
"$S" render tests/scenes/punctual.gltf $R -o "$T/p.exr" 2> "$T/err4"
check "a scene lit by punctual lights alone: the own-lights note, no warning" \
    "grep -q '^strata: note: .*lit by its own lights alone' '$T/err4' && ! grep -q 'warning:' '$T/err4'"
"$S" render tests/scenes/punctual.gltf $R --env 0 -o "$T/p0.exr" 2> /dev/null
rmse=$(mean_of "$T/p.exr" "$T/p0.exr")
check "its default environment is off (the same image as --env 0)" "[ '$rmse' = 0 ]" "(rmse $rmse)"
rmse=$(mean_of "$T/p.exr" "$T/black.exr")
check "and it is lit" "[ -n '$rmse' ] && awk 'BEGIN { exit !($rmse > 0.05) }'" "(rmse $rmse)"
"$S" render tests/scenes/sun_behind.gltf $R -o "$T/s.exr" 2> "$T/err8"
check "own lights that leave the view dark: one note, a dim environment, --env 0 to turn it off" \
    "[ \$(wc -l < '$T/err8') -eq 1 ] && grep -q '^strata: note: .*its own lights would leave most of the view black; the default sky is kept, dimmed to 0.25 (--env 0 to turn it off)' '$T/err8'"
"$S" render tests/scenes/sun_behind.gltf $R --env 0 -o "$T/s0.exr" 2> /dev/null
check "that environment is the default sky at 0.25, as the EXR records" \
    "grep -aq 'default sky x 0.25' '$T/s.exr'"
rmse=$(mean_of "$T/s.exr" "$T/s0.exr")
check "and the quad its light leaves black is lit (against --env 0)" "[ -n '$rmse' ] && awk 'BEGIN { exit !($rmse > 0.05) }'" "(rmse $rmse)"
"$S" bench cornell-box --width 8 --height 8 --spp 1 > /dev/null 2> "$T/err7"
check "bench says the lighting default once, though it opens the scene for its build timings too" \
    "[ \$(grep -c '^strata: note: cornell-box: lit by its own lights alone' '$T/err7') -eq 1 ]" "($(cat "$T/err7"))"
echo "1..$n"
