#!/bin/sh
# tests/oclgrind/run.sh — tiny renders on Oclgrind (Debian's oclgrind 21.10),
# a simulated OpenCL device that checks every kernel: API errors
# (--check-api), data races (--data-races) and reads of uninitialised memory
# (--uninitialized). One render per integrator, sampler family, filter kind,
# reconstruction, adaptive sampling, and a split render merged on it. A run is
# ok when strata exits 0 and oclgrind reports nothing. device.c works around
# oclgrind's two known limits (no llvm.bitreverse with optimisation; fill
# buffers not counted as initialising). TAP output; `make test-oclgrind`.
S=${STRATA:-./strata}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
OG="oclgrind --check-api --data-races --uninitialized"
if ! command -v oclgrind > /dev/null; then
    echo "1..0 # SKIP oclgrind is not installed (make deps)"
    exit 0
fi
n=0
failed=0
run() {
    name=$1
    shift
    n=$((n + 1))
    $OG "$S" "$@" > "$T/out" 2> "$T/err"
    st=$?
    if [ $st -eq 0 ] && ! grep -q -i "oclgrind\|uninitiali\|data race\|invalid" "$T/err"; then
        echo "ok $n - $name"
    else
        failed=$((failed + 1))
        echo "not ok $n - $name (status $st)"
        head -20 "$T/err" | sed 's/^/#   /'
    fi
}
D="--device 0:0 --width 6 --height 4 --quiet"
run "direct lighting, halton, mitchell" render $D --spp 2 --integrator direct -o "$T/a.exr"
run "path tracing, random, box" render $D --spp 2 --integrator path --max-depth 3 --sampler random --filter box -o "$T/b.exr"
run "stratified, gaussian" render $D --spp 4 --sampler stratified --filter gaussian -o "$T/c.exr"
run "sobol, lanczos" render $D --spp 2 --sampler sobol --filter lanczos -o "$T/d.exr"
run "best-candidate (tiled), triangle" render $D --spp 2 --sampler best-candidate --filter triangle -o "$T/e.exr"
run "poisson (tiled), blackman-harris" render $D --spp 2 --sampler poisson --filter blackman-harris -o "$T/f.exr"
run "filter importance sampling" render $D --spp 2 --sampler halton --reconstruction fis -o "$T/g.exr"
run "adaptive sampling" render $D --adaptive --spp 3 --min-spp 2 --max-spp 4 --sampler random -o "$T/h.exr"
# sobol's adaptive path (counts in powers of two, one round): 12 x 8 is the
# least frame of the default scene where its pilot predicts a gain
run "adaptive sampling, sobol" render --device 0:0 --width 12 --height 8 --quiet --adaptive --spp 8 --filter box --sampler sobol -o "$T/h2.exr"
# oclgrind is a GPU-like device (one lane by default, where --packets auto is
# none): --lanes builds the CPU's widths, so the packet and shade kernels'
# lanes are checked too, at AVX2's 8 and AVX-512's 16
run "packets of 8 rays (camera, shadow), shade in 8 lanes, direct" render $D --spp 2 --integrator direct --packets coherent --lanes 8 -o "$T/k.exr"
run "packets of 8 rays (every closest hit), path" render $D --spp 2 --max-depth 2 --packets all --lanes 8 -o "$T/l.exr"
run "packets of 16 rays, shade in 16 lanes, path" render $D --spp 2 --max-depth 2 --packets all --lanes 16 -o "$T/l16.exr"
run "packets of 1 ray (one lane), direct" render $D --spp 2 --integrator direct --packets all -o "$T/n.exr"
# the layers' rows: a clear coat with its own normal map, thin-walled glass,
# a textured anisotropic metal beside an isotropic one (lanes of both), a
# diffusely transmitting sheet with a lamp behind it, iridescent quads, a
# dispersive slab
run "clear coat's normal map, 8 lanes" render tests/scenes/coat_normal.gltf $D --spp 2 --max-depth 3 --env 1 --lanes 8 -o "$T/cn.exr"
run "thin-walled glass, 8 lanes" render tests/scenes/thin_pane.gltf $D --spp 2 --max-depth 3 --lanes 8 -o "$T/tw.exr"
run "anisotropic metal with its texture, 8 lanes" render tests/scenes/aniso_quad.gltf $D --spp 2 --max-depth 3 --env 1 --lanes 8 -o "$T/an.exr"
run "diffuse transmission, 8 lanes" render tests/scenes/dtrans_lamp.gltf $D --spp 2 --max-depth 3 --env 0 --lanes 8 -o "$T/dt.exr"
run "iridescence with its textures, 8 lanes" render tests/scenes/irid_quad.gltf $D --spp 2 --max-depth 3 --env 1 --lanes 8 -o "$T/ir.exr"
run "dispersion through a slab, 8 lanes" render tests/scenes/dispersion_slab.gltf $D --spp 2 --max-depth 4 --env 0 --lanes 8 -o "$T/di.exr"
# the splat's filter weights in lanes (kernels/filter_lanes.h), its tiles
# shared by a work-group here: lanczos' turns in 8 lanes, catmull-rom's in
# 4 with an adaptive render's weighted rounds
run "splat weights in 8 lanes, lanczos" render $D --spp 2 --integrator direct --filter lanczos --lanes 8 -o "$T/q.exr"
run "splat weights in 4 lanes, catmull-rom, adaptive" render $D --spp 8 --adaptive --sampler random --filter catmull-rom --lanes 4 -o "$T/r.exr"
# the adaptive kernels' pixels in 16 lanes: 24 pixels, the last work-item's
# lanes half filled
run "adaptive kernels in 16 lanes, mitchell" render $D --spp 6 --adaptive --sampler random --filter mitchell --lanes 16 -o "$T/s.exr"
# the CPU's splat paths, which the plan never takes on this GPU-like device,
# forced (STRATA_SPLAT): tiles of one work-item in four passes, whose plain
# adds to the film are race-free only where no two windows of a pass
# overlap (three 16-pixel tiles across: the first and third in one pass),
# and the box filter's gather by pixel with its edge taps (unscrambled
# Hammersley's sample 0 on a pixel corner)
STRATA_SPLAT=tiles-alone
export STRATA_SPLAT
run "splat tiles alone in four passes, lanczos" render --device 0:0 --width 40 --height 6 --quiet --spp 1 --integrator direct --filter lanczos -o "$T/t.exr"
STRATA_SPLAT=pixels
run "splat by pixel and edges, box" render $D --spp 2 --integrator direct --filter box --sampler hammersley --scramble none -o "$T/u.exr"
unset STRATA_SPLAT
# the AOVs, each a render of its own after the image's: buffers released by
# one render and created by the next (device.c's third Oclgrind limit)
run "AOVs after the image, direct, 8 lanes" render $D --spp 2 --integrator direct --lanes 8 --aov albedo,normal,depth,position -o "$T/v.exr"
run "split part 0:1" render $D --spp 2 --sample-range 0:1 -o "$T/p1.exr"
run "split part 1:2" render $D --spp 2 --sample-range 1:2 -o "$T/p2.exr"
run "merge (resolve on the device)" merge "$T/p1.exr" "$T/p2.exr" --device 0:0 -o "$T/m.exr"
echo "1..$n"
# a failure fails the make target (and CI)
[ "$failed" -eq 0 ]
