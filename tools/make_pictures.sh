#!/bin/sh
# make_pictures.sh — remakes every picture of the README with ./strata, into
# scenes/pictures/. Run from the repository root after `make`.
set -e
S=./strata
P=scenes/pictures
mkdir -p $P/samplers $P/filters $P/renders
$S render --width 512 --height 512 --spp 64 --quiet -o $P/cornell-box.png
for s in random uniform stratified halton hammersley poisson best-candidate paddedsobol sobol zsobol \
    joint-stratified; do
    $S pattern --sampler $s --count 256 --png $P/samplers/$s.png
    $S pattern --sampler $s --count 1024 --spectrum $P/samplers/$s-spectrum.png
    $S render --width 128 --height 128 --spp 1 --sampler $s --filter box --quiet \
        -o $P/renders/1spp-$s.png
done
for f in box triangle gaussian mitchell lanczos catmull-rom blackman-harris; do
    $S filter $f --png $P/filters/$f.png
    $S render --width 128 --height 128 --spp 16 --sampler halton --filter $f --quiet \
        -o $P/renders/filter-$f.png
done
for r in splat fis; do
    $S render --width 128 --height 128 --spp 16 --filter mitchell --reconstruction $r --quiet \
        -o $P/renders/recon-$r.png
done
mkdir -p $P/signal
$S signal --freq 0.3 --png $P/signal/sine-above-nyquist.png 2> /dev/null
$S signal --freq 0.8 --png $P/signal/alias.png 2> /dev/null
$S signal --function step --filter lanczos --png $P/signal/gibbs-lanczos.png 2> /dev/null
$S signal --function step --filter gaussian --png $P/signal/blur-gaussian.png 2> /dev/null
mkdir -p $P/adaptive
$S render --adaptive --spp 256 --min-spp 16 --width 256 --height 256 --quiet \
    --spp-map $P/adaptive/spp-map.png -o /tmp/strata-adaptive.exr
ALL=random,uniform,stratified,halton,hammersley,poisson,best-candidate,sobol
$S converge --sampler $ALL --spp-list 4,16,64,256 --width 64 --height 64 --integrator direct \
    --reference-spp 8192 --seeds 4 --region 18,14,28,10 --quiet --png $P/adaptive/converge-smooth.png
$S converge --sampler $ALL --spp-list 4,16,64,256 --width 64 --height 64 --integrator direct \
    --reference-spp 8192 --seeds 4 --region 22,5,18,8 --quiet --png $P/adaptive/converge-edge.png
# textures and built-in scenes
mkdir -p $P/textures $P/models
for f in none bilinear trilinear; do
    $S render checkerboard --width 384 --height 288 --spp 1 --texture-filter $f --quiet \
        -o $P/textures/checkerboard-$f-1spp.png
done
$S render checkerboard --width 384 --height 288 --spp 1 --texture-filter none --sampler uniform \
    --quiet -o $P/textures/checkerboard-none-uniform-1spp.png
$S render checkerboard --width 384 --height 288 --spp 256 --texture-filter none --quiet \
    -o $P/textures/checkerboard-none-256spp.png
for f in none trilinear; do
    $S render zone-plate --width 240 --height 240 --spp 1 --texture-filter $f --quiet \
        -o $P/textures/zone-plate-$f-1spp.png
    $S render zone-plate --width 240 --height 240 --spp 1 --texture-filter $f --sampler uniform \
        --quiet -o $P/textures/zone-plate-$f-uniform-1spp.png
done
$S render soft-shadows --width 384 --height 288 --spp 256 --quiet -o $P/textures/soft-shadows.png
K=../shared/scenes/khronos
if [ -d $K ]; then
    for f in $(sed -n 's/^| [A-Za-z]* | `\([^`]*\.gl[tb]f*\)` |.*/\1/p' $K/INDEX.md); do
        $S render $K/$f --width 160 --height 120 --spp 64 --env 1 --quiet \
            -o $P/models/$(dirname $f).png
    done
fi
