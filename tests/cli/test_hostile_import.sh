#!/bin/sh
# test_hostile_import.sh — hostile input, round three (issue 55), the scene import: values that
# overflow a float after conversion, numbers past 2^32 that would wrap, and the import's memory
# and work budget, reckoned from the file's declarations before anything is expanded. TAP.
. tests/tap.sh

R="--width 16 --height 12 --spp 1 --quiet"

# Writes tests/scenes/$1 with the Python statements $3 applied to its JSON (as g) to $T/$2.
edit() {
    python3 -c 'import json, sys
g = json.load(open(sys.argv[1]))
exec(sys.argv[3])
json.dump(g, open(sys.argv[2], "w"))' "tests/scenes/$1" "$T/$2" "$3"
}
# refused NAME PATTERN FILE: the render of $T/FILE exits 1 with PATTERN after its name.
refused() {
    expect "$1" 1 "^strata: error: $T/$3: $2" timeout 120 $S render "$T/$3" $R -o "$T/o.exr"
}

# ---- float overflow after conversion --------------------------------------------------------
edit punctual.gltf hot.gltf 'g["extensions"]["KHR_lights_punctual"]["lights"][0].update(intensity=1e20, color=[1e20] * 3)'
refused "a light of colour 1e20 x intensity 1e20 is refused naming the product" \
    "light 0 (in node order): colour 1e+20 x intensity 1e+20 = 1e+40, past the most a light may have" hot.gltf
edit punctual.gltf farcam.gltf 'g["nodes"][1]["translation"] = [0, 0, 1e39]'
refused "a camera at z = 1e39 (infinite as a float) is refused" \
    "camera 0 at (0, 0, inf): a coordinate past the float range" farcam.gltf
edit punctual.gltf farlight.gltf 'g["nodes"][2]["translation"] = [0, 0, 1e39]'
refused "a light at z = 1e39 is refused" "light 0 (in node order) at (0, 0, inf): a coordinate past the float range" farlight.gltf
check "no image from a refused scene" '[ ! -e "$T/o.exr" ]'

echo "1..$n"
