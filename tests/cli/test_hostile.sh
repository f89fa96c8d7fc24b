#!/bin/sh
# test_hostile.sh — hostile input and interruption (issue 12): signals while
# an image is written, outputs checked before rendering, range and limit
# checks on the options, stdout write failures. TAP output.
. tests/tap.sh

R="--width 16 --height 12 --spp 2 --quiet"

# ---- interruption -------------------------------------------------------------------------
# Signals render $1 (a path in $T) with signal $2 while its image is written:
# as soon as the image's temporary exists (st_outfile's serial 1: serial 0 is
# the writability check before the render) and, with $3 = data, holds data (an
# EXR is written chunk by chunk; stb encodes a whole PNG before its one write,
# so a PNG's temporary is caught empty, while it is encoded). Sets st to the
# exit status and caught to 1 when the temporary was seen.
interrupt_at_write() {
    out=$1 sig=$2
    name=$(basename "$out")
    size=""
    [ "$3" = data ] && size="-size +0"
    $S render --width 2048 --height 2048 --spp 1 --sampler random --integrator direct --quiet \
        -o "$out" > /dev/null 2> "$T/err" &
    pid=$!
    caught=0
    i=0
    while [ $i -lt 200000 ] && kill -0 $pid 2> /dev/null; do
        # shellcheck disable=SC2086 # $size is empty or two words
        if [ -n "$(find "$T" -maxdepth 1 -name ".$name.strata-tmp.*.1" $size 2> /dev/null)" ]; then
            kill -$sig $pid
            caught=1
            break
        fi
        i=$((i + 1))
    done
    wait $pid
    st=$?
}
interrupt_at_write "$T/int.exr" TERM data
check "SIGTERM while an EXR is written exits 143" '[ $caught = 1 ] && [ $st = 143 ]' "(caught $caught, status $st)"
check "SIGTERM while an EXR is written leaves no file" '[ -z "$(ls -A "$T" | grep int)" ]' "($(ls -A "$T" | tr '\n' ' '))"
interrupt_at_write "$T/int.png" INT
check "SIGINT while a PNG is written exits 130" '[ $caught = 1 ] && [ $st = 130 ]' "(caught $caught, status $st)"
check "SIGINT while a PNG is written leaves no file" '[ -z "$(ls -A "$T" | grep int)" ]' "($(ls -A "$T" | tr '\n' ' '))"
# (a signal and its number on Linux)
for pair in HUP:1 QUIT:3 USR1:10 ALRM:14; do
    sig=${pair%:*} num=${pair#*:}
    interrupt_at_write "$T/int.exr" $sig data
    check "SIG$sig while an EXR is written exits $((128 + num)) and leaves no file" \
        '[ $caught = 1 ] && [ $st = $((128 + num)) ] && [ -z "$(ls -A "$T" | grep int)" ]' \
        "(caught $caught, status $st, $(ls -A "$T" | tr '\n' ' '))"
    rm -f "$T/int.exr"
done
interrupt_at_write "$T/int.exr" KILL data
check "SIGKILL while an EXR is written leaves its temporary (it cannot be caught)" \
    '[ $caught = 1 ] && [ -n "$(ls -A "$T" | grep "^.int.exr.strata-tmp")" ]' "(caught $caught, $(ls -A "$T" | tr '\n' ' '))"
$S render $R -o "$T/next.exr" 2> "$T/err"
check "the next write into the folder removes the dead process's temporary" \
    '[ -s "$T/next.exr" ] && [ -z "$(ls -A "$T" | grep int)" ]' "($(ls -A "$T" | tr '\n' ' '))"
rm -f "$T/next.exr"
(
    $S pattern --sampler random --count 200000 --dims 2 --csv - 2> "$T/err"
    echo $? > "$T/pipe.st"
) | head -1 > /dev/null
check "a closed stdout pipe exits 1 with one error line, not 141" \
    '[ "$(cat "$T/pipe.st")" = 1 ] && [ "$(grep -c "strata: error: stdout: write failed (Broken pipe)" "$T/err")" = 1 ] && [ "$(wc -l < "$T/err")" = 1 ]' \
    "(status $(cat "$T/pipe.st"), $(cat "$T/err"))"
# help cut short by its reader (`strata --help | head`): a pipe whose read end
# is closed before strata starts, so that every write fails (EPIPE)
for h in "--help" "help render" "filter --help" "--version"; do
    python3 -c 'import os, subprocess, sys
r, w = os.pipe()
os.close(r)
p = subprocess.run(sys.argv[1:], stdout=w, stderr=subprocess.PIPE)
sys.stderr.buffer.write(p.stderr)
sys.exit(p.returncode)' $S $h 2> "$T/err"
    status=$?
    check "strata $h into a closed pipe exits 0 quietly" '[ $status = 0 ] && [ ! -s "$T/err" ]' \
        "(status $status, $(cat "$T/err"))"
done

# The output's folder is checked before the render: this one would take minutes.
expect "missing output folder refused before rendering" 1 "^strata: error: $T/no/such/o.exr: cannot create" \
    timeout 60 $S render --width 4096 --height 4096 --spp 4096 --sampler random --filter box --quiet -o "$T/no/such/o.exr"
mkdir "$T/dir.png"
expect "output that is a folder refused before rendering" 1 "^strata: error: $T/dir.png: is a folder" \
    timeout 60 $S render --width 4096 --height 4096 --spp 4096 --sampler random --filter box --quiet -o "$T/dir.png"
expect "unwritable --spp-map folder refused before rendering" 1 "^strata: error: $T/no/map.png" \
    timeout 60 $S render --width 4096 --height 4096 --spp 4096 --sampler random --adaptive --quiet \
    --spp-map "$T/no/map.png" -o "$T/ok.exr"
expect "merge to a missing folder refused before reading parts" 1 "^strata: error: $T/no/m.exr" \
    $S merge "$T/none.exr" -o "$T/no/m.exr"

# ---- small things -------------------------------------------------------------------------
expect "--sample-range 0:0 is refused" 2 "^strata: error: --sample-range 0:0: needs K < M <= spp" $S render $R --sample-range 0:0 -o "$T/r.exr"
expect "--sample-range 3:3 is refused" 2 "--sample-range 3:3: needs K < M" $S render $R --sample-range 3:3 -o "$T/r.exr"
expect "--sample-range past spp is refused" 2 "--sample-range 1:3: must satisfy" $S render $R --sample-range 1:3 -o "$T/r.exr"
$S render $R -o "$T/a.exr" > /dev/null 2>&1
expect "diff --max-rmse -1 is a usage error" 2 "^strata: error: diff: --max-rmse -1: must be >= 0" $S diff "$T/a.exr" "$T/a.exr" --max-rmse -1
expect "devices to a full disk exits 1" 1 "^strata: error: stdout: write failed" sh -c "$S devices > /dev/full"
expect "diff to a full disk exits 1" 1 "^strata: error: stdout: write failed" sh -c "$S diff $T/a.exr $T/a.exr > /dev/full"
expect "the render summary to a full disk exits 1" 1 "^strata: error: stdout: write failed" sh -c "$S render --width 8 --height 8 --spp 1 -o $T/f.exr > /dev/full"
expect "--discrepancy on a million points is refused with its cost" 2 "O(N^2) work, 1e+12 point pairs (about 4000 s" \
    timeout 60 $S pattern --sampler halton --count 1000000 --discrepancy
expect "--crop 4294967296,0,2,2 is refused, not wrapped to 0" 2 "^strata: error: --crop 4294967296,0,2,2: expected X,Y,W,H" \
    $S render $R --crop 4294967296,0,2,2 -o "$T/r.exr"
expect "--sample-range 4294967296:2 is refused, not wrapped to 0:2" 2 "^strata: error: --sample-range 4294967296:2: expected K:M" \
    $S render $R --sample-range 4294967296:2 -o "$T/r.exr"
expect "a --max-spp too large for the film names --max-spp" 2 "^strata: error: --max-spp 1000000 with filter radius" \
    $S render --width 16 --height 12 --spp 8 --quiet --adaptive --max-spp 1000000 -o "$T/r.exr"
expect "--csv to a full disk names the reason" 1 "^strata: error: /dev/full: cannot write (No space left on device)" \
    $S pattern --sampler random --count 20000 --dims 2 --csv /dev/full
check "no image from refused integer options" '[ ! -e "$T/r.exr" ]'

# ---- film arithmetic ---------------------------------------------------------------------
expect "--filter-b outside [0, 1] is a usage error" 2 "^strata: error: --filter-b -1.57286e+06: must be in \[0, 1\]" $S render $R --filter mitchell --filter-b -1572861 -o "$T/b.exr"
expect "--filter-c 1e30 is a usage error" 2 "^strata: error: --filter-c 1e+30: must be in \[0, 1\]" $S render $R --filter mitchell --filter-c 1e30 -o "$T/b.exr"
expect "--filter-sigma past 16 is a usage error" 2 "^strata: error: --filter-sigma 100: must be in" $S render $R --filter gaussian --filter-sigma 100 -o "$T/b.exr"
check "no image from refused filter parameters" '[ ! -e "$T/b.exr" ]'
# An EXR int attribute's value (name, "int", size 4, little-endian value), or "missing".
int_attr() {
    python3 -c 'import struct, sys
d = open(sys.argv[1], "rb").read()
k = d.find(sys.argv[2].encode() + b"\0int\0\4\0\0\0")
print(struct.unpack("<i", d[k + len(sys.argv[2]) + 9:][:4])[0] if k >= 0 else "missing")' "$1" "$2"
}
$S render zone-plate --env 1e6 --width 16 --height 16 --spp 2 -o "$T/hot.exr" > "$T/hot.sum" 2>&1
clamped=$(sed -n 's/.*(\([0-9]*\) splats clamped.*/\1/p' "$T/hot.sum")
check "a radiance of 1e6 is clamped and counted in the summary" '[ "${clamped:-0}" -gt 0 ]' "($(cat "$T/hot.sum"))"
check "the EXR header holds the same clamped count as an int" '[ "$(int_attr "$T/hot.exr" strata.clamped_splats)" = "$clamped" ]' "($(int_attr "$T/hot.exr" strata.clamped_splats) vs $clamped)"
check "the EXR header holds the non-finite and zero-weight counts as ints" '[ "$(int_attr "$T/hot.exr" strata.nonfinite)" = 0 ] && [ "$(int_attr "$T/hot.exr" strata.zero_weight_pixels)" = 0 ]'

# ---- merge refuses what is not one render ------------------------------------------------
P="--width 16 --height 12 --spp 4 --sampler random --seed 3 --quiet"
# Replaces the value of EXR string attribute $2 in file $1 by $3 (same length;
# "@": as many X).
forge() {
    python3 -c 'import sys
p, name, new = sys.argv[1], sys.argv[2].encode(), sys.argv[3].encode()
d = bytearray(open(p, "rb").read())
k = d.find(name + b"\0int\0")
if k >= 0:  # name, type, size 4, the value
    k += len(name) + 5
    d[k + 4:k + 8] = int(new).to_bytes(4, "little")
else:
    k = d.find(name + b"\0string\0") + len(name) + 8
    n = int.from_bytes(d[k:k + 4], "little")
    new = b"X" * n if new == b"@" else new
    assert len(new) == n, (n, new)
    d[k + 4:k + 4 + n] = new
open(p, "wb").write(d)' "$1" "$2" "$3"
}
$S render $P --sample-range 0:2 -o "$T/p1.exr" && $S render $P --sample-range 2:4 -o "$T/p2.exr"
expect "merge of one part of two is refused naming the gap" 1 "samples 2:4 are in no part (the last, $T/p1.exr, ends at 2" \
    $S merge "$T/p1.exr" -o "$T/m.exr"
check "a refused merge writes nothing" '[ ! -e "$T/m.exr" ]'
$S merge "$T/p1.exr" --partial -o "$T/half.exr" 2> "$T/err"
check "merge --partial labels the result with the ranges it holds" 'grep -a -q "holds samples 0:2 of every pixel" "$T/half.exr"' "($(cat "$T/err"))"
$S merge "$T/p1.exr" "$T/p2.exr" -o "$T/full.exr" 2> "$T/err"
check "a complete merge is labelled 0:spp and not partial" 'grep -a -q "0:4" "$T/full.exr" && ! grep -a -q "strata.partial" "$T/full.exr"' "($(cat "$T/err"))"
cp "$T/p2.exr" "$T/past.exr" && forge "$T/past.exr" strata.sample_range 2:9
expect "a part whose range passes spp is refused" 1 "$T/past.exr: samples 2:9 pass the spp 4" $S merge "$T/p1.exr" "$T/past.exr" -o "$T/m.exr"
cp "$T/p1.exr" "$T/f1.exr" && cp "$T/p2.exr" "$T/f2.exr" && forge "$T/f1.exr" strata.spp 8 && forge "$T/f2.exr" strata.spp 8
expect "parts with a forged spp are refused (they do not tile 0:8)" 1 "samples 4:8 are in no part" $S merge "$T/f1.exr" "$T/f2.exr" -o "$T/m.exr"
cp "$T/p2.exr" "$T/dev.exr" && forge "$T/dev.exr" strata.device @
expect "parts from different devices are refused by name" 1 "$T/dev.exr: strata.device is XXX" $S merge "$T/p1.exr" "$T/dev.exr" -o "$T/m.exr"
$S render cornell-box $P --sample-range 2:4 -o "$T/other.exr"
$S render checkerboard $P --sample-range 0:2 -o "$T/check.exr"
expect "parts of different scenes are refused by content hash" 1 "$T/other.exr: strata.scene_hash is crc32:" $S merge "$T/check.exr" "$T/other.exr" -o "$T/m.exr"
$S render --width 16 --height 12 --spp 300000 --sample-range 100000:100001 --sampler random \
    --quiet -o "$T/wrap.exr" 2> /dev/null
forge "$T/wrap.exr" strata.sample_range 00:4294967297
expect "a part's range 0:4294967297 is refused, not read as 0:1" 1 "wrap.exr: no valid strata.sample_range" \
    $S merge "$T/wrap.exr" -o "$T/m.exr"
mkdir "$T/sc" && cp tests/scenes/materials_flat.gltf "$T/sc/"
SA=$(cd "$(dirname "$S")" && pwd)/$(basename "$S")
(cd "$T/sc" && "$SA" render materials_flat.gltf $P --sample-range 0:2 -o "$T/rel.exr" 2> /dev/null)
$S render "$T/sc/materials_flat.gltf" $P --sample-range 2:4 -o "$T/abs.exr" 2> /dev/null
$S merge "$T/rel.exr" "$T/abs.exr" -o "$T/both.exr" 2> "$T/err"
check "one scene named by a relative and an absolute path merges" '[ -s "$T/both.exr" ]' "($(cat "$T/err"))"

# ---- confinement: URIs stay in the scene's folder ----------------------------------------
mkdir -p "$T/cf/sub" "$T/cf/other"
cp tests/scenes/layout_u8.gltf "$T/cf/sub/" && cp tests/scenes/layout_u8.bin "$T/cf/other/secret.bin"
uri_scene() { sed "s|\"uri\": \"layout_u8.bin\"|\"uri\": \"$2\"|" tests/scenes/layout_u8.gltf > "$T/cf/sub/$1"; }
uri_scene up.gltf ../other/secret.bin
expect "a ../ buffer URI is refused naming it" 1 "sub/up.gltf: .*sub/../other/secret.bin : the URI leads outside the scene's folder" \
    $S render "$T/cf/sub/up.gltf" $R -o "$T/cf/o.exr"
uri_scene pw.gltf ../../../../../../../../etc/passwd
expect "a ../../etc/passwd URI is refused without its size" 1 "etc/passwd : the URI leads outside" \
    $S render "$T/cf/sub/pw.gltf" $R -o "$T/cf/o.exr"
check "the refusal does not quote the file's size" '! grep -q "requestedBytes\|size mismatch" "$T/err"'
uri_scene abs.gltf "$(pwd)/tests/scenes/layout_u8.bin"
expect "an absolute buffer URI is refused naming it" 1 "abs.gltf: .*$(pwd)/tests/scenes/layout_u8.bin : an absolute path; the URI leads outside" \
    $S render "$T/cf/sub/abs.gltf" $R -o "$T/cf/o.exr"
uri_scene link.gltf link.bin
ln -s ../other/secret.bin "$T/cf/sub/link.bin"
expect "a symbolic link out of the folder is refused" 1 "sub/link.bin : cannot open: a symbolic link, which could lead anywhere; refused" \
    $S render "$T/cf/sub/link.gltf" $R -o "$T/cf/o.exr"
cp "$T/cf/other/secret.bin" "$T/cf/sub/inside.bin" && uri_scene in.gltf inside.bin
$S render "$T/cf/sub/in.gltf" $R -o "$T/cf/in.exr" 2> "$T/err"
check "a buffer inside the folder still loads" '[ -s "$T/cf/in.exr" ]' "($(cat "$T/err"))"
check "no image from a refused scene" '[ ! -e "$T/cf/o.exr" ]'
mkfifo "$T/cf/sub/fifo.bin" && uri_scene fifo.gltf fifo.bin
expect "a FIFO named by a buffer URI is refused at once, not waited on" 1 "fifo.bin : not a regular file" \
    timeout 20 $S render "$T/cf/sub/fifo.gltf" $R -o "$T/cf/o.exr"
mkdir "$T/cf/sub/deeper" && cp "$T/cf/sub/inside.bin" "$T/cf/sub/deeper/" && uri_scene deeper.gltf deeper/../deeper/./inside.bin
$S render "$T/cf/sub/deeper.gltf" $R -o "$T/cf/deeper.exr" 2> "$T/err"
check "a URI through a subfolder and back (.. below the scene's folder) still loads" '[ -s "$T/cf/deeper.exr" ]' "($(cat "$T/err"))"
ln -s ../other "$T/cf/sub/otherlink" && uri_scene linkdir.gltf otherlink/secret.bin
expect "a URI through a linked folder is refused" 1 "otherlink/secret.bin : cannot open otherlink: a symbolic link" \
    $S render "$T/cf/sub/linkdir.gltf" $R -o "$T/cf/o.exr"
mkfifo "$T/cf/fifo-scene.gltf"
expect "a scene that is a FIFO is refused at once (read a stream with -)" 1 "fifo-scene.gltf: not a regular file" \
    timeout 20 $S render "$T/cf/fifo-scene.gltf" $R -o "$T/cf/o.exr"
expect "a scene on standard input (-) may not name files: it has no folder" 1 "^strata: error: -: .*layout_u8.bin : .*no folder: data: URIs only" \
    sh -c "$S render - $R -o $T/cf/o.exr < tests/scenes/layout_u8.gltf"
expect "/dev/stdin from a pipe is refused (not a regular file)" 1 "/dev/stdin: not a regular file" \
    sh -c "cat $T/cf/sub/in.gltf | $S render /dev/stdin $R -o $T/cf/o.exr"
sh -c "$S render /dev/stdin $R -o $T/cf/stdin.exr < $T/cf/sub/in.gltf" 2> "$T/err"
check "/dev/stdin redirected from a scene file finds its buffers beside that file, not in /dev" '[ -s "$T/cf/stdin.exr" ]' "($(cat "$T/err"))"

# ---- caps -----------------------------------------------------------------------------------
expect "an endless scene (/dev/zero) is refused: not a regular file" 1 "^strata: error: /dev/zero: not a regular file" \
    timeout 20 $S render /dev/zero $R -o "$T/z.exr"
expect "an endless scene on standard input stops at the 512 MiB cap" 1 "^strata: error: standard input: larger than 512 MiB, the limit for a scene file" \
    sh -c "timeout 120 $S render - $R -o $T/z.exr < /dev/zero"
truncate -s 1G "$T/sparse.gltf"
expect "a 1 GB sparse scene is refused by its size, unread" 1 "sparse.gltf: 1073741824 bytes, larger than 512 MiB, the limit for a scene file" \
    timeout 20 $S render "$T/sparse.gltf" $R -o "$T/z.exr"
truncate -s 1G "$T/cf/sub/huge.bin" && uri_scene huge.gltf huge.bin
expect "a 1 GB buffer is refused naming its URI" 1 "huge.bin : 1073741824 bytes, larger than 512 MiB, the limit for a buffer or image" \
    timeout 20 $S render "$T/cf/sub/huge.gltf" $R -o "$T/z.exr"
python3 -c 'import sys
print("{\"asset\": {\"version\": \"2.0\"}, \"buffers\": [{\"byteLength\": 1, \"uri\": \"data:application/octet-stream;base64," + "A" * (65 << 20) + "\"}]}")' > "$T/datauri.gltf"
expect "a 65 MiB data: URI is refused" 1 "datauri.gltf: a data: URI of .* bytes at byte [0-9]*: more than 64 MiB, the limit" \
    timeout 20 $S render "$T/datauri.gltf" $R -o "$T/z.exr"
sed -i 's/"uri": "data:/"uri": "\\u0064ata:/' "$T/datauri.gltf"
expect "a 65 MiB data: URI spelled with an escape (\\u0064ata:) is refused too" 1 "datauri.gltf: a string (a data: URI written with escapes?) of .* bytes at byte [0-9]*: more than 64 MiB" \
    timeout 20 $S render "$T/datauri.gltf" $R -o "$T/z.exr"
# a 48 kB PNG of 20000 x 20000 1-bit pixels (1.6 GB as RGBA) is refused by its header's size
python3 -c 'import json, struct, sys, zlib
def chunk(t, d): return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
W = H = 20000
raw = (b"\0" * (1 + (W + 7) // 8)) * H
open(sys.argv[2] + "/big.png", "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 1, 0, 0, 0, 0))
    + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
g = json.load(open(sys.argv[1]))
for im in g["images"]: im["uri"] = "big.png"
json.dump(g, open(sys.argv[2] + "/big.gltf", "w"))' tests/scenes/textured_quad.gltf "$T"
# (an image that cannot be used is a warning and a white texture: the model still renders)
expect "a PNG of 20000 x 20000 texels is refused before decoding (in 1 GB of memory)" 0 "big.gltf: image 0: 20000 x 20000 texels: more than 2^26: replaced by a white texture" \
    sh -c "ulimit -v 1000000; exec $S render $T/big.gltf $R -o $T/z.exr"
rm -f "$T/big.png"
# found by tests/fuzz/fuzz_exr.c: 1.7 kB whose header claims 8 x 134217981 pixels (12 GB)
expect "an EXR claiming 12 GB is refused before allocating" 1 "fuzz-exr-12gb-window.exr: 8 x 134217981 pixels x 3 channels: more than 2^30 samples" \
    $S diff tests/data/fuzz-exr-12gb-window.exr tests/data/fuzz-exr-12gb-window.exr
# found by tests/fuzz/fuzz_exr.c: 1.8 kB whose rows of 285212680 pixels overflow the decoder's
# 32-bit line stride (undefined behaviour before the check)
expect "an EXR whose rows pass 2^31 bytes is refused" 1 "fuzz-exr-wide-row.exr: rows of 285212680 pixels x 3 channels: more than 2^31 bytes" \
    $S diff tests/data/fuzz-exr-wide-row.exr tests/data/fuzz-exr-wide-row.exr
rm -f "$T/datauri.gltf" "$T/sparse.gltf" "$T/cf/sub/huge.bin"

# ---- deep JSON: tinygltf converts JSON to its Values recursively -------------------------------
# (a scene's text, $2 levels of $3 nesting under key $4, as .gltf or, with $5 = glb, as GLB)
deep_scene() {
    python3 -c 'import json, struct, sys
out, d, kind, key, glb = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4], sys.argv[5] == "glb"
inner = "[" * d + "]" * d if kind == "array" else "{\"a\":" * d + "1" + "}" * d
text = ("{\"asset\": {\"version\": \"2.0\"}, \"" + key + "\": {\"x\": " + inner + "}}").encode()
if glb:
    text += b" " * (-len(text) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text
    text = b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body
open(out, "wb").write(text)' "$1" "$2" "$3" "$4" "$5"
}
deep_scene "$T/deep.gltf" 15000 array extras gltf
expect "extras nested 15000 deep are refused, not a stack overflow" 1 "^strata: error: $T/deep.gltf: JSON nested more than 256 deep at byte" \
    $S render "$T/deep.gltf" $R -o "$T/z.exr"
deep_scene "$T/deep.glb" 15000 object extensions glb
expect "a GLB whose extensions nest 15000 deep is refused" 1 "^strata: error: $T/deep.glb: JSON nested more than 256 deep" \
    $S render "$T/deep.glb" $R -o "$T/z.exr"
# (252 levels in all, and 8 more brackets in a string after an escaped quote)
deep_scene "$T/deepstr.gltf" 250 array extras gltf
sed -i 's/"x": /"s": "[[[[{{{{\\"[[[[[[[[", "x": /' "$T/deepstr.gltf"
$S render "$T/deepstr.gltf" $R -o "$T/z.exr" > /dev/null 2> "$T/err"
check "extras 250 deep, and brackets inside strings, are parsed (to the next error: no scenes)" 'grep -q "no scenes" "$T/err"' "($(cat "$T/err"))"

# ---- what an output is decides how it is written ----------------------------------------------
PAT="pattern --sampler random --count 5 --dims 2"
mkfifo "$T/fifo"
timeout 20 cat "$T/fifo" > "$T/fifo.out" &
reader=$!
$S $PAT --csv "$T/fifo" 2> "$T/err"
st=$?
wait $reader
check "--csv to a FIFO streams into it (exit 0, a header and 5 rows read)" '[ $st = 0 ] && [ "$(wc -l < "$T/fifo.out")" = 6 ]' "(status $st, $(cat "$T/err"))"
check "the FIFO is still a FIFO" '[ -p "$T/fifo" ]'
# (a link of our own to /proc/self/fd/1, as /dev/stdout is: a failure must not replace /dev's)
ln -s /proc/self/fd/1 "$T/stdout"
rows=$($S $PAT --csv "$T/stdout" | wc -l)
check "--csv to a link to /proc/self/fd/1 (as /dev/stdout) writes the rows into the pipe" \
    '[ "$rows" = 6 ] && [ -L "$T/stdout" ]' "($rows rows: a header and 5)"
if mknod "$T/null" c 1 3 2> /dev/null; then
    $S $PAT --csv "$T/null" 2> "$T/err"
    check "--csv to a character device (a null device node) leaves it a device" '[ -c "$T/null" ]' "($(cat "$T/err"))"
else
    skip "--csv to a character device (cannot make a device node here)"
fi
echo old > "$T/target.csv" && chmod 640 "$T/target.csv" && ln -s target.csv "$T/link.csv"
$S $PAT --csv "$T/link.csv" 2> "$T/err"
check "--csv on a symbolic link replaces its target and keeps the link" '[ -L "$T/link.csv" ] && [ "$(wc -l < "$T/target.csv")" = 6 ]' "($(cat "$T/err"))"
check "the replaced target keeps its mode 640" '[ "$(stat -c %a "$T/target.csv")" = 640 ]' "($(stat -c %a "$T/target.csv"))"
python3 -c 'import socket, sys; socket.socket(socket.AF_UNIX).bind(sys.argv[1])' "$T/sock"
expect "an output that is a socket is refused by name" 1 "^strata: error: $T/sock: is a socket, not a file to write" \
    $S $PAT --csv "$T/sock"
check "the socket is left as it was" '[ -S "$T/sock" ]'
long=$(printf "%0244d" 0).exr
$S render $R -o "$T/$long" 2> "$T/err"
check "a legal 244-byte output name works" '[ -s "$T/$long" ]' "($(cat "$T/err"))"

# ---- images cut short ---------------------------------------------------------------------------
# A Radiance .hdr of 16 x 32 texels ($2: flat RGBE or rle, the run-length scanlines of the
# format), less its last $3 bytes.
hdr_file() {
    python3 -c 'import sys
out, kind, cut = sys.argv[1], sys.argv[2], int(sys.argv[3])
W, H = 16, 32
d = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (H, W)
for y in range(H):
    px = [(128, 64 + y, 32, 129)] * W
    if kind == "flat":
        d += b"".join(bytes(p) for p in px)
    else:  # a scanline: 2, 2, width, then each channel as one literal run of W bytes
        d += bytes([2, 2, W >> 8, W & 255])
        for c in range(4):
            d += bytes([W]) + bytes(p[c] for p in px)
open(out, "wb").write(d[:len(d) - cut] if cut else d)' "$1" "$2" "$3"
}
for kind in flat rle; do
    hdr_file "$T/whole-$kind.hdr" $kind 0
    $S render cornell-box $R --env "$T/whole-$kind.hdr" -o "$T/env.exr" 2> "$T/err"
    check "a whole $kind .hdr map loads" '[ -s "$T/env.exr" ]' "($(cat "$T/err"))"
    hdr_file "$T/cut-$kind.hdr" $kind 400
    expect "a $kind .hdr map cut short (rows missing) is refused" 1 "^strata: error: $T/cut-$kind.hdr: cut short: the file ends before its 16 x 32 texels do" \
        $S render cornell-box $R --env "$T/cut-$kind.hdr" -o "$T/env2.exr"
done
hdr_file "$T/cut2.hdr" flat 2
expect "a flat .hdr map missing half of its last texel is refused" 1 "cut2.hdr: cut short" \
    $S render cornell-box $R --env "$T/cut2.hdr" -o "$T/env2.exr"
check "no image from a map cut short" '[ ! -e "$T/env2.exr" ]'

# ---- scene text reaches the terminal escaped ------------------------------------------------------
# (an extension name with ESC, BEL and a newline that would forge a second error line)
esc_scene() {
    python3 -c 'import json, sys
g = json.load(open("tests/scenes/layout_u8.gltf"))
g["buffers"][0]["uri"] = "inside.bin"
g[sys.argv[2]] = ["EVIL\x1b[2J\x07\nstrata: error: forged\x9b"]
json.dump(g, open(sys.argv[1], "w"))' "$1" "$2"
}
esc_scene "$T/cf/sub/esc_used.gltf" extensionsUsed
$S render "$T/cf/sub/esc_used.gltf" $R -o "$T/esc.exr" 2> "$T/err"
check "a scene's extension name is escaped in a warning (one line, \\x1B shown)" \
    '[ "$(grep -c forged "$T/err")" = 1 ] && grep -q "EVIL\\\\x1B\[2J\\\\x07\\\\x0Astrata: error: forged\\\\xC2\\\\x9B, which" "$T/err" && ! grep -q "$(printf "\033")" "$T/err"' "($(cat -v "$T/err"))"
esc_scene "$T/cf/sub/esc_req.gltf" extensionsRequired
expect "a scene's extension name is escaped in an error" 1 "^strata: error: .*requires extension EVIL\\\\x1B\[2J\\\\x07\\\\x0Astrata: error: forged" \
    $S render "$T/cf/sub/esc_req.gltf" $R -o "$T/esc.exr"
check "the error is one line with no raw control character" '[ "$(wc -l < "$T/err")" = 1 ] && ! grep -q "$(printf "\007")" "$T/err"' "($(cat -v "$T/err"))"

# ---- what tinygltf would take silently ----------------------------------------------------------
# (layout_u8.gltf with one change, $2 a Python statement on g, into the folder of its buffer)
edit_scene() {
    python3 -c 'import json, sys
g = json.load(open("tests/scenes/layout_u8.gltf"))
g["buffers"][0]["uri"] = "inside.bin"
exec(sys.argv[2])
json.dump(g, open(sys.argv[1], "w"))' "$1" "$2"
}
edit_scene "$T/cf/sub/neg.gltf" 'g["accessors"][0]["byteOffset"] = -12'
expect "an accessor's byteOffset -12 is refused" 1 "neg.gltf: accessor 0: byteOffset is not an integer >= 0" \
    $S render "$T/cf/sub/neg.gltf" $R -o "$T/sil.exr"
edit_scene "$T/cf/sub/frac.gltf" 'g["bufferViews"][0]["byteLength"] = 59.5'
expect "a bufferView's byteLength 59.5 is refused" 1 "frac.gltf: bufferView 0: byteLength is not an integer >= 0" \
    $S render "$T/cf/sub/frac.gltf" $R -o "$T/sil.exr"
edit_scene "$T/cf/sub/v3.gltf" 'g["asset"]["version"] = "3.0"'
expect "asset version 3.0 is refused" 1 'v3.gltf: asset version "3.0": strata reads glTF 2.x only' \
    $S render "$T/cf/sub/v3.gltf" $R -o "$T/sil.exr"
edit_scene "$T/cf/sub/proj.gltf" 'g["nodes"][0]["matrix"] = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0.5, 0, 0, 0, 1]'
expect "a projective (non-affine) node matrix is refused" 1 "proj.gltf: node 0: matrix is not affine (last row 0 0 0.5 1" \
    $S render "$T/cf/sub/proj.gltf" $R -o "$T/sil.exr"
edit_scene "$T/cf/sub/affine.gltf" 'g["nodes"][0]["matrix"] = [2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 1, 2, 3, 1]'
$S render "$T/cf/sub/affine.gltf" $R -o "$T/sil.exr" 2> "$T/err"
check "an affine node matrix still loads" '[ -s "$T/sil.exr" ]' "($(cat "$T/err"))"
rm -f "$T/sil.exr"
python3 -c 'import struct, sys
text = open(sys.argv[1], "rb").read()
text += b" " * (-len(text) % 4)
body = struct.pack("<II", len(text), 0x4E4F534A) + text
open(sys.argv[2], "wb").write(b"glTF" + struct.pack("<II", 99, 12 + len(body)) + body)' "$T/cf/sub/affine.gltf" "$T/cf/sub/v99.glb"
expect "GLB version 99 is refused" 1 "v99.glb: GLB version 99: strata reads version 2" \
    $S render "$T/cf/sub/v99.glb" $R -o "$T/sil.exr"
check "no image from a refused scene" '[ ! -e "$T/sil.exr" ]'
for sc in 1e14 1e-17; do
    edit_scene "$T/cf/sub/scale.gltf" "g['nodes'][0]['scale'] = [$sc] * 3"
    $S render "$T/cf/sub/scale.gltf" $R -o "$T/scale.exr" 2> "$T/err"
    check "a scene scaled by $sc is rendered with a warning about its extent" \
        'grep -q "^strata: warning: .*scale.gltf: the scene spans .* units: beyond 1e13 or below 1e-16" "$T/err"' "($(cat "$T/err"))"
done
edit_scene "$T/cf/sub/scale.gltf" "g['nodes'][0]['scale'] = [1e12] * 3"
$S render "$T/cf/sub/scale.gltf" $R -o "$T/scale.exr" 2> "$T/err"
check "a scene scaled by 1e12 gets no such warning" '! grep -q "the scene spans" "$T/err"' "($(cat "$T/err"))"
expect "--exposure 1000 (every tone curve overflows to black) is refused" 2 "^strata: error: --exposure 1000: must be in \[-64, 64\]" \
    $S render $R --exposure 1000 --tonemap filmic -o "$T/exp.png"
$S render $R --exposure 64 --tonemap filmic -o "$T/exp.png" 2> "$T/err"
check "--exposure 64 with the filmic curve is not black" 'python3 -c "import sys, zlib, struct
d = open(sys.argv[1], \"rb\").read()
k = d.find(b\"IDAT\")
raw = zlib.decompress(d[k + 4:k + 4 + struct.unpack(\">I\", d[k - 4:k])[0]])
sys.exit(0 if max(raw) > 200 else 1)" "$T/exp.png"' "($(cat "$T/err"))"

# ---- work-group size: a CPU device runs a group on one thread's stack --------------------------
expect "--local-size 4096 on an 8 MiB stack is refused with the limit, not a crash" 2 "^strata: error: --local-size 4096: a CPU device runs a group on one thread's stack of 8192 KiB (ulimit -s), which holds at most 2048 work-items of 4096 bytes at 1 lanes" \
    sh -c "ulimit -s 8192; exec timeout 300 $S render cornell-box --width 256 --height 256 --spp 1 --quiet --integrator direct --lanes 1 --local-size 4096 -o $T/ls.exr"
expect "--local-size 4096 at 16 lanes on a 32 MiB stack is refused: each lane takes stack" 2 "^strata: error: --local-size 4096: .* at 16 lanes" \
    sh -c "ulimit -s 32768; exec timeout 300 $S render cornell-box --width 256 --height 256 --spp 1 --quiet --integrator direct --lanes 16 --local-size 4096 -o $T/ls.exr"
# shellcheck disable=SC3045 # dash (sh here) has ulimit -s
(ulimit -s 16384; timeout 300 $S render cornell-box --width 256 --height 256 --spp 1 --quiet --integrator direct --lanes 1 --local-size 4096 -o "$T/ls.exr" 2> "$T/err")
check "--local-size 4096 at 1 lane with a 16 MiB stack renders" '[ -s "$T/ls.exr" ]' "($(cat "$T/err"))"
rm -f "$T/ls.exr"
# shellcheck disable=SC3045
(ulimit -s 81920; timeout 300 $S render cornell-box --width 256 --height 256 --spp 1 --quiet --integrator direct --lanes 16 --local-size 4096 -o "$T/ls.exr" 2> "$T/err")
check "--local-size 4096 at 16 lanes with an 80 MiB stack renders" '[ -s "$T/ls.exr" ]' "($(cat "$T/err"))"

# ---- memory planned before it is asked for ------------------------------------------------------
# (about 31 GB, host and device: more than this machine's memory, and than a limit of 24 GB
# on a larger one)
expect "a 16384 x 16384 film is refused before allocating, naming --width and --height" 2 "^strata: error: the render needs .*MiB.*: reduce --width and --height" \
    sh -c "ulimit -v 24000000; exec timeout 120 $S render --width 16384 --height 16384 --spp 1 --quiet -o $T/mem.exr"
expect "an 8192 x 8192 render under ulimit -v 5000000 is refused, not a PoCL abort" 2 "^strata: error: the render needs about .* MiB of memory, more than the .* MiB the process may still take (ulimit -v): reduce --width and --height" \
    sh -c "ulimit -v 5000000; exec timeout 120 $S render --width 8192 --height 8192 --spp 1 --quiet -o $T/mem.exr"
# (about 13 GB: under a limit of 8 GB, so that it is refused on any machine)
expect "a wave of 2^26 work-items is refused naming --wave" 2 "^strata: error: the render needs .*: reduce --wave" \
    sh -c "ulimit -v 8000000; exec timeout 120 $S render --width 1024 --height 1024 --spp 64 --quiet --wave 67108864 -o $T/mem.exr"
check "no image from a render that would not fit" '[ ! -e "$T/mem.exr" ]'
# 100 instances of a mesh of 170000 (degenerate) triangles: 17 million, past the 2^24 cap
python3 -c 'import json, sys
n = 170000
g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": list(range(100))}],
     "nodes": [{"mesh": 0, "translation": [i, 0, 0]} for i in range(100)],
     "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
     "buffers": [{"uri": "inst.bin", "byteLength": 36 + 3 * n}],
     "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 3 * n}],
     "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 0]},
                   {"bufferView": 1, "componentType": 5121, "count": 3 * n, "type": "SCALAR"}]}
json.dump(g, open(sys.argv[1], "w"))' "$T/cf/sub/inst.gltf"
truncate -s $((36 + 3 * 170000)) "$T/cf/sub/inst.bin"
expect "a small scene instancing 17 million triangles is refused by the triangle cap" 1 "inst.gltf: the scene makes up to 17000000 triangles, every instance counted: more than 2^24" \
    sh -c "ulimit -v 4000000; exec timeout 120 $S render $T/cf/sub/inst.gltf $R -o $T/mem.exr"
printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4096 +X 16384\n' > "$T/envbig.hdr"
head -c 800000 /dev/zero >> "$T/envbig.hdr"
expect "an 800 kB map claiming 2^26 texels under ulimit -v 3000000 is refused before decoding" 1 "envbig.hdr: 67108864 texels need about 4096 MiB, more than the .* MiB the process may still take (ulimit -v)" \
    sh -c "ulimit -v 3000000; exec timeout 120 $S render cornell-box $R --env $T/envbig.hdr -o $T/mem.exr"
$S render $R -o "$T/whole.png" 2> /dev/null
size=$(stat -c %s "$T/whole.png")
head -c $((size / 2)) "$T/whole.png" > "$T/half.png"
head -c $((size - 12)) "$T/whole.png" > "$T/noend.png"
expect "a PNG cut in half is an error" 1 "^strata: error: $T/half.png: cannot decode image" $S diff "$T/whole.png" "$T/half.png"
expect "a PNG missing its IEND chunk is an error with a reason" 1 "^strata: error: $T/noend.png: cannot decode image (cut short or corrupt)" $S diff "$T/whole.png" "$T/noend.png"

echo "1..$n"
