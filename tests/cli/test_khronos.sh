#!/bin/sh
# test_khronos.sh — scenes through the command line: every Khronos sample
# model under ../shared/scenes/khronos (INDEX.md lists them) renders at a
# small size to a finite image that is not black; the built-in scenes
# render; malformed files end in one "strata: error: FILE: ..." line, exit
# status 1 and no image; skipped parts of a file become "strata: warning:"
# lines; the scene options (--env, --texture-filter, --camera) are checked;
# nested transforms render as their baked vertices do. TAP output.
# Under `make test SANITIZE=1` the same runs use the sanitized binary.
. tests/tap.sh
K=${KHRONOS:-../shared/scenes/khronos}

# rmse_of A B: the RMSE `strata diff` prints (empty when the diff fails,
# e.g. on a non-finite value)
rmse_of() { "$S" diff "$1" "$2" 2> /dev/null | sed -n 's/^rmse //p'; }

R="--width 40 --height 30 --spp 2 --quiet"
# an all-black reference: a scene without emitters, the environment off
"$S" render tests/scenes/layout_u16.gltf $R --env 0 -o "$T/black.exr" 2> /dev/null

# ---- the Khronos sample models ---------------------------------------------
if [ -f "$K/INDEX.md" ]; then
    for f in $(sed -n 's/^| [A-Za-z]* | `\([^`]*\.gl[tb]f*\)` |.*/\1/p' "$K/INDEX.md"); do
        rm -f "$T/m.exr"
        "$S" render "$K/$f" $R -o "$T/m.exr" > "$T/out" 2> "$T/err"
        status=$?
        rmse=$(rmse_of "$T/m.exr" "$T/black.exr")
        # (VC encloses its city in a sky box, mesh "skbox", that no sky
        # reaches, and nothing in it emits: the light at its camera lights it)
        if [ $status -eq 0 ] && [ -s "$T/m.exr" ] && [ -n "$rmse" ] &&
            awk -v r="$rmse" 'BEGIN { exit !(r > 0) }'; then
            ok "$f renders finite and not black (rmse from black $rmse)"
        else
            not_ok "$f (status $status, rmse from black '$rmse', stderr: $(head -c 300 "$T/err"))"
        fi
    done
else
    skip "$K not found (the Khronos sample models)"
fi

# ---- KHR_lights_punctual: the lamp lit by its own lights alone ----------------
L="$K/LightsPunctualLamp/glTF/LightsPunctualLamp.gltf"
if [ -f "$L" ]; then
    "$S" render "$L" $R --env 0 -o "$T/lamp.exr" 2> "$T/err"
    rmse=$(rmse_of "$T/lamp.exr" "$T/black.exr")
    check "LightsPunctualLamp is lit by its punctual lights (--env 0: RMS above 0.01)" \
        '[ -n "$rmse" ] && ! grep -q "no light at all" "$T/err" && awk -v r="$rmse" "BEGIN { exit !(r > 0.01) }"' \
        "(RMS $rmse)"
elif [ -d "$K" ]; then
    skip "$L not found"
else
    skip "$K not found (the Khronos sample models)"
fi

# ---- built-in scenes -----------------------------------------------------------
for s in checkerboard soft-shadows zone-plate; do
    rm -f "$T/b.exr"
    "$S" render "$s" $R -o "$T/b.exr" 2> "$T/err"
    rmse=$(rmse_of "$T/b.exr" "$T/black.exr")
    check "built-in $s renders finite and not black" \
        '[ -s "$T/b.exr" ] && [ -n "$rmse" ] && ! grep -qv "^strata: note:" "$T/err" && awk -v r="$rmse" "BEGIN { exit !(r > 0) }"'
done
"$S" render --scene-list > "$T/list"
check "--scene-list names the built-in scenes" \
    'for s in cornell-box furnace checkerboard soft-shadows zone-plate; do grep -qx "$s" "$T/list" || exit 1; done'

# ---- malformed files: one error line naming the file, exit 1, no image ---------
for f in tests/scenes/bad_*; do
    rm -f "$T/bad.png"
    expect "$(basename "$f") exits 1 naming the file" 1 "^strata: error: $f: " \
        "$S" render "$f" $R -o "$T/bad.png"
    check "$(basename "$f") writes no image" '[ ! -e "$T/bad.png" ] && [ $(wc -l < "$T/err") -eq 1 ]'
done

# ---- warnings ----------------------------------------------------------------------
"$S" render tests/scenes/textures.gltf $R -o "$T/w.exr" 2> "$T/err"
check "skipped primitives warn naming file and mesh" \
    'grep -q "^strata: warning: tests/scenes/textures.gltf: mesh 0 (quads) primitive 3: mode 1 (LINES) skipped" "$T/err"'
check "a texture on TEXCOORD_1 that a primitive lacks warns" \
    'grep -q "^strata: warning: .*material 1 reads TEXCOORD_1, which the primitive lacks" "$T/err"'
check "warnings do not stop the render" '[ -s "$T/w.exr" ]'

# ---- scene options -------------------------------------------------------------------
expect "--env with two numbers exits 2" 2 "^strata: error: --env 1,2: expected R,G,B" "$S" render --env 1,2 $R -o "$T/o.exr"
expect "negative --env exits 2" 2 "^strata: error: --env -1" "$S" render --env -1 $R -o "$T/o.exr"
expect "unknown --texture-filter exits 2" 2 "--texture-filter cubic: unknown; expected one of none, bilinear, trilinear" "$S" render --texture-filter cubic $R -o "$T/o.exr"
expect "--camera past the last camera exits 2" 2 "^strata: error: --camera 4: tests/scenes/camera_pick.gltf has 4 camera nodes" "$S" render tests/scenes/camera_pick.gltf --camera 4 $R -o "$T/o.exr"
check "failed option writes nothing" '[ ! -e "$T/o.exr" ]'
"$S" render tests/scenes/camera_pick.gltf --camera 3 $R -o "$T/c3.exr" 2> /dev/null
"$S" render tests/scenes/camera_pick.gltf --camera 1 $R -o "$T/c1.exr" 2> /dev/null
rmse=$(rmse_of "$T/c1.exr" "$T/c3.exr")
check "--camera picks another view" '[ -n "$rmse" ] && awk -v r="$rmse" "BEGIN { exit !(r > 0) }"'
"$S" render tests/scenes/camera_pick.gltf --camera auto $R -o "$T/ca.exr" 2> /dev/null
rmse=$(rmse_of "$T/ca.exr" "$T/c1.exr")
check "--camera auto frames the bounds instead of a camera node" '[ -n "$rmse" ] && awk -v r="$rmse" "BEGIN { exit !(r > 0) }"'
"$S" render checkerboard $R --env 0.25,0.5,1 --texture-filter none -o "$T/e.exr" 2> /dev/null
check "EXR records env, texture filter and camera" \
    'grep -aq "0.25,0.5,1" "$T/e.exr" && grep -aq "strata.texture_filter" "$T/e.exr" && grep -aq "strata.camera" "$T/e.exr"'

# ---- transforms: nested TRS nodes render as their baked vertices ---------------------------
"$S" render tests/scenes/trs_nested.gltf --width 64 --height 48 --spp 4 --quiet -o "$T/nested.exr" 2> /dev/null
"$S" render tests/scenes/trs_baked.gltf --width 64 --height 48 --spp 4 --quiet -o "$T/baked.exr" 2> /dev/null
rmse=$(rmse_of "$T/nested.exr" "$T/baked.exr")
check "nested TRS renders as baked vertices (rmse $rmse < 1e-3)" \
    '[ -n "$rmse" ] && awk -v r="$rmse" "BEGIN { exit !(r < 1e-3) }"'

echo "1..$n"
