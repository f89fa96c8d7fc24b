#!/bin/sh
# test_mitsuba_aniso.sh — strata's anisotropic GGX (KHR_materials_anisotropy)
# against Mitsuba 3's `roughconductor` with alpha_u and alpha_v:
# tests/scenes/aniso_mitsuba.gltf (three white metal spheres, Fresnel 1 in
# both renderers, of strength 0, 0.5 along the tangent dP/du and 0.5 turned
# by 90 degrees, on a Lambertian floor and wall) in a uniform environment,
# the same camera, sampler (random), filter (box) and depth in both
# (tools/bench_mitsuba.py converts the scene, alpha_t = mix(roughness², 1,
# strength²) along the tangent). The images agree when each channel's mean
# is within 1 % and the RMSE of 16 x 16 block means is within twice what
# the per-pixel noise leaves there (bench_mitsuba.py compare): Mitsuba
# given the two axes swapped, or the isotropic lobe, fails the block test.
# Needs Mitsuba 3 in build/bench-py (`make bench-deps`); without it the
# test is skipped, saying so. TAP output.
. tests/tap.sh

PY=${BENCH_PY:-build/bench-py/bin/python}
if [ ! -x "$PY" ] || ! "$PY" -c "import mitsuba" 2> /dev/null; then
    echo "1..0 # SKIP Mitsuba 3 is not installed (make bench-deps): the anisotropy comparison"
    exit 0
fi
W=96 H=72 SPP=1024 DEPTH=12 SCENE=tests/scenes/aniso_mitsuba.gltf
$S render $SCENE --env 1,1,1 --width $W --height $H --spp $SPP --sampler random \
    --filter box --max-depth $DEPTH -q -o "$T/strata.exr" 2> "$T/s.err"
status=$?
check "strata renders aniso_mitsuba" '[ $status -eq 0 ]' "(status $status: $(head -c 300 "$T/s.err"))"
WIDTH=$W HEIGHT=$H SPP=$SPP RUNS=1 ENV=1,1,1 MAX_DEPTH=$DEPTH \
    "$PY" tools/bench_mitsuba.py render $SCENE path "$T/mitsuba.exr" > "$T/m.out" 2> "$T/m.err"
status=$?
check "Mitsuba renders aniso_mitsuba" '[ $status -eq 0 ]' "(status $status: $(tail -c 300 "$T/m.err"))"
"$PY" tools/bench_mitsuba.py compare "$T/strata.exr" "$T/mitsuba.exr" > "$T/cmp" 2>&1
status=$?
sed 's/^/# /' "$T/cmp"
check "strata's anisotropic metal agrees with Mitsuba's roughconductor" '[ $status -eq 0 ]'
echo "1..$n"
