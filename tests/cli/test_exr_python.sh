#!/bin/sh
# test_exr_python.sh — strata's ZIP-compressed EXRs (image_exr.c writes each
# chunk itself) read back exactly by another reader, OpenEXR's own Python
# binding (installed by `make deps` into build/pyexr). Python decodes each file
# and writes it uncompressed; strata then finds the copy identical: a render's
# FLOAT pixels (diff: rmse 0, max_abs 0) and a split part's UINT film (merged
# image identical). TAP output.
. tests/tap.sh
PY=${PYEXR:-build/pyexr/bin/python}
if ! "$PY" -c "import OpenEXR, numpy" 2> /dev/null; then
    echo "# OpenEXR's Python binding is not installed (make deps; it needs pip's network): skipped"
    echo "1..0 # SKIP no OpenEXR Python binding"
    exit 0
fi
# Decodes $1 with OpenEXR's Python binding, writes it uncompressed to $2 with the
# same header; prints the compression $1 had.
copy_raw() {
    "$PY" -c 'import sys, OpenEXR
f = OpenEXR.File(sys.argv[1], separate_channels=True)
h = dict(f.header())
print(h["compression"])
h["compression"] = OpenEXR.NO_COMPRESSION
OpenEXR.File(h, f.channels()).write(sys.argv[2])' "$1" "$2"
}
$S render --width 64 --height 40 --spp 4 --quiet -o "$T/a.exr"
comp=$(copy_raw "$T/a.exr" "$T/a-raw.exr")
check "strata writes ZIP-compressed EXRs" '[ "$comp" = "Compression.ZIP_COMPRESSION" ]' "($comp)"
check "compressed is smaller than raw" '[ $(wc -c < "$T/a.exr") -lt $(wc -c < "$T/a-raw.exr") ]'
$S diff "$T/a.exr" "$T/a-raw.exr" > "$T/diff" 2>&1
check "OpenEXR's Python binding reads the render exactly as strata does" 'grep -q "^rmse 0$" "$T/diff" && grep -q "^max_abs 0$" "$T/diff"' "($(cat "$T/diff"))"
P="--width 48 --height 32 --spp 4 --quiet"
$S render $P --sample-range 0:2 -o "$T/p1.exr" && $S render $P --sample-range 2:4 -o "$T/p2.exr"
copy_raw "$T/p1.exr" "$T/q1.exr" > /dev/null && copy_raw "$T/p2.exr" "$T/q2.exr" > /dev/null
$S merge "$T/p1.exr" "$T/p2.exr" -o "$T/m.exr" && $S merge "$T/q1.exr" "$T/q2.exr" -o "$T/n.exr"
$S diff "$T/m.exr" "$T/n.exr" > "$T/diff" 2>&1
check "OpenEXR's Python binding reads the raw film (UINT) exactly" 'grep -q "^rmse 0$" "$T/diff" && grep -q "^max_abs 0$" "$T/diff"' "($(cat "$T/diff"))"
"$PY" -c 'import sys, OpenEXR
h = OpenEXR.File(sys.argv[1]).header()
print(h["strata.clamped_splats"] + 0, h["strata.nonfinite"] + 0, h["strata.zero_weight_pixels"] + 0)' "$T/a.exr" > "$T/counts" 2>&1
check "the film counts are int attributes" '[ "$(cat "$T/counts")" = "0 0 0" ]' "($(cat "$T/counts"))"
echo "1..$n"
