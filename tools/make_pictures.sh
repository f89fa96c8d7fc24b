#!/bin/sh
# make_pictures.sh — remakes the README's pictures with ./strata (`make pictures`).
# Every picture is one `pic NAME COMMAND...` line below, with @ standing for its
# path: the one place each picture's command is written. Environment:
#   P=DIR       where to write them (default scenes/pictures)
#   ONLY="A B"  make only these names (tests/image/test_pictures.sh re-renders a few
#               this way and requires them equal to the committed files)
#   S=BINARY    the strata to run (default ./strata)
#   E=DIR       the compass map and its tool (default build/envmaps and
#               build/release/make_envmap: `make pictures` makes them); the sky is
#               the one that ships, scenes/envmaps/sky.hdr
set -e
S=${S:-./strata}
P=${P:-scenes/pictures}
E=${E:-build/envmaps}
M=${M:-build/release/make_envmap}

# pic_with PROGRAM NAME ARGS...: runs PROGRAM ARGS with @ as the picture's path
pic_with() {
    prog=$1
    name=$2
    shift 2
    if [ -n "$ONLY" ]; then
        case " $ONLY " in *" $name "*) ;; *) return 0 ;; esac
    fi
    n=$#
    while [ "$n" -gt 0 ]; do
        a=$1
        shift
        [ "$a" = @ ] && a=$P/$name
        set -- "$@" "$a"
        n=$((n - 1))
    done
    mkdir -p "$(dirname "$P/$name")"
    "$prog" "$@"
}

pic() { pic_with "$S" "$@"; }

pic cornell-box.png render --width 512 --height 512 --spp 64 --quiet -o @
for s in random uniform stratified halton hammersley poisson best-candidate paddedsobol sobol zsobol \
    joint-stratified pmj02; do
    pic samplers/$s.png pattern --sampler $s --count 256 --png @
    pic samplers/$s-spectrum.png pattern --sampler $s --count 1024 --spectrum @
    pic renders/1spp-$s.png render --width 128 --height 128 --spp 1 --sampler $s --filter box \
        --quiet -o @
done
for f in box triangle gaussian mitchell lanczos catmull-rom blackman-harris; do
    pic filters/$f.png filter $f --png @
    pic renders/filter-$f.png render --width 128 --height 128 --spp 16 --sampler halton \
        --filter $f --quiet -o @
done
for r in splat fis; do
    pic renders/recon-$r.png render --width 128 --height 128 --spp 16 --filter mitchell \
        --reconstruction $r --quiet -o @
done
pic signal/sine-above-nyquist.png signal --freq 0.3 --png @ > /dev/null
pic signal/alias.png signal --freq 0.8 --png @ > /dev/null
pic signal/gibbs-lanczos.png signal --function step --filter lanczos --png @ > /dev/null
pic signal/blur-gaussian.png signal --function step --filter gaussian --png @ > /dev/null
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pic adaptive/spp-map.png render --sampler random --adaptive --spp 64 --width 256 --height 256 \
    --quiet --spp-map @ -o "$tmp/adaptive.exr"
pic sampling/error-spectrum.png converge --sampler random,best-candidate,sobol,zsobol \
    --spp-list 4 --width 128 --height 128 --region 36,28,56,28 --integrator direct \
    --filter box --seeds 8 --reference-spp 1024 --quiet --error-spectrum @ > /dev/null
ALL=random,uniform,stratified,halton,hammersley,poisson,best-candidate,sobol
pic adaptive/converge-smooth.png converge --sampler $ALL --spp-list 4,16,64,256 --width 64 \
    --height 64 --integrator direct --reference-spp 8192 --seeds 4 --region 18,14,28,10 \
    --quiet --png @
pic adaptive/converge-edge.png converge --sampler $ALL --spp-list 4,16,64,256 --width 64 \
    --height 64 --integrator direct --reference-spp 8192 --seeds 4 --region 22,5,18,8 \
    --quiet --png @
# the lecture's comparisons, one sheet each (strata compare)
pic compare/jitter.png compare --sampler uniform,stratified --spp 1,4 --filter box --width 96 \
    --height 96 --reference-spp 256 --crop 30,4,36,20 --quiet -o @
pic compare/halton.png compare --sampler stratified,halton --spp 1,16 --width 96 --height 96 \
    --quiet -o @
pic compare/best-candidate.png compare --sampler stratified,best-candidate --spp 1,16 \
    --width 96 --height 96 --quiet -o @
# textures and built-in scenes
for f in none bilinear trilinear; do
    pic textures/checkerboard-$f-1spp.png render checkerboard --width 384 --height 288 --spp 1 \
        --texture-filter $f --quiet -o @
done
pic textures/checkerboard-none-uniform-1spp.png render checkerboard --width 384 --height 288 \
    --spp 1 --texture-filter none --sampler uniform --quiet -o @
pic textures/checkerboard-none-256spp.png render checkerboard --width 384 --height 288 \
    --spp 256 --texture-filter none --quiet -o @
for f in none trilinear; do
    pic textures/zone-plate-$f-1spp.png render zone-plate --width 240 --height 240 --spp 1 \
        --texture-filter $f --quiet -o @
    pic textures/zone-plate-$f-uniform-1spp.png render zone-plate --width 240 --height 240 \
        --spp 1 --texture-filter $f --sampler uniform --quiet -o @
done
pic textures/soft-shadows.png render soft-shadows --width 384 --height 288 --spp 256 --quiet -o @
# the environment maps' orientation: the compass map itself, and seen through a
# camera looking along -Z at the grid of spheres' centre (metal spheres reflect
# it), then turned by 90 degrees
pic_with "$M" envmap/compass.png compass @ 256 128
pic_with "$M" envmap/sky.png sky @ 256 128
K=../shared/scenes/khronos
if [ -d $K ]; then
    SPHERES=$K/MetalRoughSpheresNoTextures/MetalRoughSpheresNoTextures.gltf
    for deg in 0 90; do
        pic envmap/compass-rotate-$deg.png render $SPHERES --width 160 --height 120 --spp 16 \
            --look-at 0.00277,0.00274,0.011,0.00277,0.00274,-0.0015 --fov 40 \
            --env $E/compass.hdr --env-rotate $deg --quiet -o @
    done
    for f in $(sed -n 's/^| [A-Za-z]* | `\([^`]*\.gl[tb]f*\)` |.*/\1/p' $K/INDEX.md); do
        pic models/$(dirname $f).png render $K/$f --width 160 --height 120 --spp 64 \
            --env scenes/envmaps/sky.hdr --quiet -o @
    done
fi
