#!/bin/sh
# test_cli.sh — command-line behaviour: exit codes, one-line errors naming
# what and where, no partial output, and the happy paths. TAP output.
. tests/tap.sh

R="--width 16 --height 12 --spp 2 --quiet"
expect "unknown option exits 2" 2 "^strata: error: render: unknown option --bogus" $S render --bogus
expect "unknown command exits 2" 2 "^strata: error: unknown command 'paint'" $S paint
expect "bad --spp exits 2" 2 "^strata: error: --spp abc: expected an integer" $S render --spp abc
expect "zero width exits 2" 2 "^strata: error: --width 0" $S render --width 0
expect "negative seed exits 2" 2 "^strata: error: --seed -1" $S render --seed -1
expect "unknown sampler names the choices" 2 "--sampler fancy: unknown; expected one of random" $S render --sampler fancy
expect "unknown filter exits 2" 2 "--filter sharp: unknown" $S render --filter sharp
expect "filter parameter of another filter exits 2" 2 "--filter-b/--filter-c apply to mitchell only, not box" $S render --filter box --filter-b 0.5
expect "sigma for mitchell exits 2" 2 "--filter-sigma applies to gaussian only" $S render --filter-sigma 1
expect "radius past the limit exits 2" 2 "--filter-radius 9: must be in" $S render --filter-radius 9
expect "overflowing spp exits 2" 2 "could overflow the 64-bit film" $S render --sampler random --filter lanczos --spp 16000000
expect "--scramble with a sampler that has none exits 2" 2 "--scramble applies to stratified, halton, hammersley, paddedsobol, sobol and zsobol, not random" $S render --sampler random --scramble none
expect "pattern --scramble with poisson exits 2" 2 "--scramble applies to .* not poisson" $S pattern --sampler poisson --count 4 --scramble none --csv -
expect "bad output extension exits 2" 2 "the output must end in .exr or .png" $S render -o "$T/x.tif"
check "bad output extension writes nothing" '[ ! -e "$T/x.tif" ]'
expect "missing value exits 2" 2 "needs a value" $S render --spp
expect "bad sample range exits 2" 2 "--sample-range 4:2" $S render --spp 8 --sample-range 4:2
expect "bad device spec exits 2" 2 "--device xyz: expected cpu, gpu or P:D" $S render --device xyz $R -o "$T/d.exr"

expect "missing scene exits 1 naming the file" 1 "^strata: error: $T/none.gltf" $S render "$T/none.gltf" $R -o "$T/m.exr"
check "missing scene writes nothing" '[ ! -e "$T/m.exr" ]'
touch "$T/m.obj"
for f in m.obj "$T/m.obj"; do
    expect "a .obj ($f) is refused naming the formats read" 2 \
        "^strata: error: $f: strata reads glTF 2.0 scenes (.gltf, .glb) and its built-in scenes" \
        $S render "$f" $R -o "$T/m.exr"
done
printf '{"asset": {"version": "2.0"}, "meshes": [' > "$T/trunc.gltf"
expect "truncated scene exits 1 naming the file" 1 "^strata: error: $T/trunc.gltf" $S render "$T/trunc.gltf" $R -o "$T/t.exr"
check "truncated scene writes nothing" '[ ! -e "$T/t.exr" ]'
expect "unknown built-in scene exits with its name" 2 "nosuchscene" $S render nosuchscene $R -o "$T/n.exr"
expect "unwritable output exits 1 naming it" 1 "^strata: error: $T/no/such/dir/o.exr" $S render $R -o "$T/no/such/dir/o.exr"
mkdir "$T/ro.exr"
expect "output that is a folder exits 1" 1 "^strata: error: $T/ro.exr" $S render $R -o "$T/ro.exr"
check "failed writes leave no temporary" '[ -z "$(ls -A "$T/ro.exr")" ] && [ -z "$(ls -A "$T" | grep -i tmp)" ]'

$S render --width 16 --height 12 --spp 2 -o "$T/a.exr" > "$T/sum" 2>&1
check "render writes an EXR" '[ -s "$T/a.exr" ]'
check "render prints a summary with samples/s and rays/s" 'grep -q "samples/s.*rays/s" "$T/sum"'
$S render $R -o "$T/a.png" > /dev/null 2>&1
check "render writes a PNG" '[ "$(head -c 4 "$T/a.png" | od -An -c | tr -d " ")" = "211PNG" ]'
$S render $R -o "$T/b.exr" > /dev/null 2>&1
$S diff "$T/a.exr" "$T/b.exr" > "$T/diff" 2>&1
check "two renders are identical (diff rmse 0)" 'grep -q "^rmse 0$" "$T/diff"'
check "the EXR header records the settings" 'grep -a -q "strata.sampler" "$T/a.exr" && grep -a -q "halton" "$T/a.exr" && grep -a -q "strata.integrator" "$T/a.exr"'
$S render --width 16 --height 12 --spp 2 --seed 9 --quiet -o "$T/c.exr" > /dev/null 2>&1
expect "diff --max-rmse fails on different images" 1 "above --max-rmse" $S diff "$T/a.exr" "$T/c.exr" --max-rmse 0
expect "diff of a missing file exits 1" 1 "^strata: error: $T/zz.exr" $S diff "$T/a.exr" "$T/zz.exr"
$S devices > "$T/dev" 2>&1
check "devices lists a device with its OpenCL C version and atomics" 'grep -q "OpenCL C 1\.[2-9].*64-bit atomics: yes" "$T/dev"'
$S render --scene-list > "$T/list"
check "scene list names the built-in scenes" 'grep -q "^cornell-box$" "$T/list"'
$S render --help > "$T/help"
check "render --help documents --max-depth" 'grep -q -- "--max-depth" "$T/help"'

# the OpenCL layer's own failures
mkdir "$T/novendors"
OCL_ICD_VENDORS="$T/novendors" $S devices > "$T/out" 2> "$T/err"
st=$?
check "no OpenCL platform: exit 1 naming make deps" '[ $st -eq 1 ] && grep -q "^strata: error: no OpenCL platform found: run .make deps." "$T/err"'
OCL_ICD_VENDORS="$T/novendors" $S render $R -o "$T/nv.exr" > /dev/null 2>&1
check "no OpenCL platform: render writes nothing" '[ ! -e "$T/nv.exr" ]'
# STRATA_KERNEL_DIR: the kernels read from a copy of kernels/, their includes found
# through its folders (the search path tools/embed.c inlines them with); the copy's path has a
# blank, which the compiler's options cannot quote
K="$T/ker nels"
cp -R kernels "$K"
$S render $R -o "$T/emb.exr" > /dev/null 2>&1
STRATA_KERNEL_DIR="$K" $S render $R -o "$T/kd.exr" > /dev/null 2> "$T/err"
check "STRATA_KERNEL_DIR: the same image as the embedded kernels" '[ -e "$T/kd.exr" ] && $S diff "$T/emb.exr" "$T/kd.exr" --max-rmse 0 > /dev/null'
printf '\nthis is not C;\n' >> "$K/film/filters.h"
STRATA_KERNEL_DIR="$K" $S render $R -o "$T/kh.exr" > /dev/null 2> "$T/err"
check "a header of a kernel folder that fails to build: the log names it" 'grep -q "ker nels/film/filters.h:[0-9]*:[0-9]*:" "$T/err" && [ ! -e "$T/kh.exr" ]'
cp kernels/film/filters.h "$K/film/filters.h"
printf '\n__kernel void broken(void) { this is not C; }\n' >> "$K/film/film.cl"
STRATA_KERNEL_DIR="$K" $S render $R -o "$T/kb.exr" > "$T/out" 2> "$T/err"
st=$?
check "a kernel that fails to build: exit 1 and the cause" '[ $st -eq 1 ] && grep -q "^strata: error: kernel build failed on .*CL_BUILD_PROGRAM_FAILURE" "$T/err"'
check "a kernel that fails to build: the compiler log names the file" 'grep -q "ker nels/film/film.cl:[0-9]*:[0-9]*:" "$T/err" && [ ! -e "$T/kb.exr" ]'
rm "$K/film/film.cl" && mkfifo "$K/film/film.cl"
expect "a FIFO among the kernel files is refused at once, not waited on" 1 "film/film.cl: cannot read kernel (not a regular file" \
    env STRATA_KERNEL_DIR="$K" timeout 20 $S render $R -o "$T/kf.exr"
# STRATA_SPLAT: a splat path forced (tests/oclgrind/run.sh), the image the
# plan's own; a name it does not know fails before anything is written
for sp in samples tiles tiles-alone pixels; do
    STRATA_SPLAT=$sp $S render $R -o "$T/sp-$sp.exr" > /dev/null 2>&1
    check "STRATA_SPLAT=$sp: the same image as the plan's splat" '[ -e "$T/sp-$sp.exr" ] && $S diff "$T/emb.exr" "$T/sp-$sp.exr" --max-rmse 0 > /dev/null'
done
STRATA_SPLAT=gather $S render $R -o "$T/sp-bad.exr" > /dev/null 2> "$T/err"
st=$?
check "STRATA_SPLAT with an unknown name: exit 2 naming it and the names known" '[ $st -eq 2 ] && grep -q "^strata: error: STRATA_SPLAT=gather: unknown splat (samples, tiles, tiles-alone or pixels)" "$T/err" && [ ! -e "$T/sp-bad.exr" ]'

# strata pattern
$S pattern --sampler halton --scramble none --count 1000 --dims 3 --csv "$T/h.csv" > /dev/null 2>&1
check "pattern writes a header row naming the dimensions" '[ "$(sed -n 1p "$T/h.csv")" = "x0,x1,x2" ]'
check "pattern writes one line per point after it" '[ "$(wc -l < "$T/h.csv")" -eq 1001 ]'
check "halton point 1 is (1/2, 1/3, 1/5) as floats" '[ "$(sed -n 3p "$T/h.csv")" = "0.5,0.333333313,0.199999988" ]'
$S pattern --sampler hammersley --scramble none --count 256 --discrepancy > "$T/d256"
check "unscrambled Hammersley D*_256 = 0.016052 (closed form)" 'grep -q "^star discrepancy (exact, 2-D): 0.01605" "$T/d256"'
$S pattern --sampler hammersley --scramble none --count 1024 --discrepancy > "$T/d1024"
check "unscrambled Hammersley D*_1024 = 0.004665 (closed form)" 'grep -q "^star discrepancy (exact, 2-D): 0.00466[45]" "$T/d1024"'
check "discrepancy output labels the L2-star value" 'grep -q "^L2-star discrepancy (Warnock, 2-D): " "$T/d1024"'
$S pattern --sampler poisson --count 256 --png "$T/p.png" --spectrum "$T/s.png" --radial "$T/r.csv" --seeds 2
check "pattern writes scatter and spectrum PNGs" '[ -s "$T/p.png" ] && [ -s "$T/s.png" ]'
check "radial power CSV has a header and kmax+1 = 33 rows" '[ "$(head -1 "$T/r.csv")" = "frequency,power,count" ] && [ "$(wc -l < "$T/r.csv")" -eq 34 ]'
expect "pattern without --count exits 2" 2 "--sampler and --count are required" $S pattern --sampler halton --csv -
expect "pattern with an unknown sampler exits 2" 2 "--sampler dart: unknown" $S pattern --sampler dart --count 4 --csv -
expect "pattern into a missing folder exits 1" 1 "^strata: error: $T/nope/p.csv: cannot create" $S pattern --sampler random --count 4 --csv "$T/nope/p.csv"
# ---- bench --json -----------------------------------------------------------------------------
# The scene path holds a quote and a backslash: printf-built JSON would not parse, and an
# unescaped or doubly escaped path would not come back equal.
Q="$T/q\"b\\x"
mkdir "$Q" && cp scenes/furnace.gltf "$Q/s.gltf"
$S bench "$Q/s.gltf" --width 8 --height 8 --spp 1 --json > "$T/bench.json" 2> "$T/bench.err"
json_keys_ok() {
    python3 - "$1" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
assert d["check"]["passed"] is True and d["width"] == 8 and d["spp"] == 1
assert d["stages"]["trace_rays"]["unit"] == "rays/s" and d["total"]["rays"] > 0
# the live list's compaction has no count of its own: its seconds, no made-up rate
assert set(d["stages"]["live_scatter"]) == {"seconds"}
EOF
}
json_scene_is() {
    python3 - "$1" "$2" <<'EOF'
import json, sys
sys.exit(json.load(open(sys.argv[1]))["scene"] != sys.argv[2])
EOF
}
check "bench --json parses, with its keys" 'json_keys_ok "$T/bench.json" 2> /dev/null'
check "bench --json escapes a quote and a backslash" 'json_scene_is "$T/bench.json" "$Q/s.gltf" 2> /dev/null'
$S bench "$Q/s.gltf" --width 8 --height 8 --spp 1 > "$T/bench.txt" 2> /dev/null
check "bench prints a rate for a stage that ran, a dash for one without a count" \
    'grep -q "^trace_rays .* M rays/s" "$T/bench.txt" && grep -q "^live_scatter .* - " "$T/bench.txt" &&
     ! grep -q "0\.00 M" "$T/bench.txt"'
# ---- bench --rays (the trace benchmark) --------------------------------------------------------
$S bench --rays random --count 5000 --json > "$T/trace.json" 2> /dev/null
trace_keys_ok() {
    python3 - "$1" "$2" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
r, b = d["rays"], d["bvh"]
assert r["kind"] == "random" and r["count"] == 5000 and r["seconds"] > 0
assert abs(r["rays_per_second"] - 5000 / r["seconds"]) < 1e-6 * r["rays_per_second"]
assert 0 < r["hit_fraction"] < 1 and b["triangles"] == 32 and b["seconds"] >= 0
assert d["version"] == sys.argv[2]
EOF
}
check "bench --rays --json parses, with its keys and the version" \
    'trace_keys_ok "$T/trace.json" "$($S --version | cut -d" " -f2)" 2> /dev/null'
check "bench --rays camera prints rays/s and the hit fraction" '$S bench --rays camera --count 1000 2> /dev/null | grep -q "camera rays: 1000 in .* M rays/s, hit fraction 0\.[0-9]"'
expect "bench --rays with an unknown set exits 2" 2 "--rays sky: unknown; expected one of camera, random" $S bench --rays sky
expect "bench --count without --rays exits 2" 2 "--count applies to the trace benchmark only" $S bench --count 10
expect "render --rays exits 2" 2 "--rays: only .strata bench. takes it" $S render --rays camera
expect "pmj02 past its table's 4096 spp exits 2" 2 "^strata: error: --spp 4097: pmj02's tables hold at most 4096" $S render --sampler pmj02 --spp 4097
expect "pattern pmj02 past 4096 points exits 2" 2 "^strata: error: .*count 4097: pmj02's tables hold at most 4096" $S pattern --sampler pmj02 --count 4097 --csv -

echo "1..$n"
