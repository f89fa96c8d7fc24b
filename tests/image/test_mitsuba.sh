#!/bin/sh
# test_mitsuba.sh — strata's materials against Mitsuba 3's, like for like:
# each scene below in a uniform environment, the same camera, sampler
# (random), filter (box) and depth in both (tools/bench_mitsuba.py converts
# the scene). The images agree when each channel's mean is within 1 % and
# the RMSE of 16 x 16 block means is within twice what the per-pixel noise
# leaves there (bench_mitsuba.py compare).
# - glass_mitsuba: transmission (KHR_materials_transmission,
#   KHR_materials_ior, KHR_materials_volume's absorption) against Mitsuba's
#   `dielectric`, `roughdielectric` and an absorbing `homogeneous` medium
#   under `volpath`: a smooth glass sphere, a rough one that absorbs, a
#   tinted one of ior 1.33 on a Lambertian floor and wall; a sphere's ior
#   off by 0.12 fails the block test. glass_mitsuba_coarse repeats it with
#   coarse spheres (6 rings, 8 segments) whose smooth normals stray far from
#   the facets at the outline, where the two agree on the shading-normal
#   convention at a refracting surface (kernels/integrator/integrator.h
#   vertex_bounce). glass_mitsuba_thin makes the three spheres smooth and
#   thin-walled (no KHR_materials_volume) against Mitsuba's `thindielectric`.
# - aniso_mitsuba: anisotropic GGX (KHR_materials_anisotropy) against
#   `roughconductor` with alpha_u and alpha_v: three white metal spheres,
#   Fresnel 1 in both renderers, of strength 0, 0.5 along the tangent dP/du
#   and 0.5 turned by 90 degrees (alpha_t = mix(roughness², 1, strength²)
#   along the tangent); Mitsuba given the two axes swapped, or the
#   isotropic lobe, fails the block test.
# Needs Mitsuba 3 in build/bench-py (`make bench-deps`); without it the
# test is skipped, saying so. TAP output.
. tests/tap.sh

PY=${BENCH_PY:-build/bench-py/bin/python}
if [ ! -x "$PY" ] || ! "$PY" -c "import mitsuba" 2> /dev/null; then
    echo "1..0 # SKIP Mitsuba 3 is not installed (make bench-deps): the comparisons of glass and anisotropic metal"
    exit 0
fi
W=96 H=72 SPP=1024 DEPTH=12
for SCENE in tests/scenes/glass_mitsuba.gltf tests/scenes/glass_mitsuba_coarse.gltf \
    tests/scenes/glass_mitsuba_thin.gltf tests/scenes/aniso_mitsuba.gltf; do
    name=$(basename $SCENE .gltf)
    $S render $SCENE --env 1,1,1 --width $W --height $H --spp $SPP --sampler random \
        --filter box --max-depth $DEPTH -q -o "$T/strata.exr" 2> "$T/s.err"
    status=$?
    check "strata renders $name" '[ $status -eq 0 ]' "(status $status: $(head -c 300 "$T/s.err"))"
    WIDTH=$W HEIGHT=$H SPP=$SPP RUNS=1 ENV=1,1,1 MAX_DEPTH=$DEPTH \
        "$PY" tools/bench_mitsuba.py render $SCENE path "$T/mitsuba.exr" > "$T/m.out" 2> "$T/m.err"
    status=$?
    check "Mitsuba renders $name" '[ $status -eq 0 ]' "(status $status: $(tail -c 300 "$T/m.err"))"
    "$PY" tools/bench_mitsuba.py compare "$T/strata.exr" "$T/mitsuba.exr" > "$T/cmp" 2>&1
    status=$?
    sed 's/^/# /' "$T/cmp"
    check "strata agrees with Mitsuba 3 ($name)" '[ $status -eq 0 ]'
done
echo "1..$n"
