#!/bin/sh
# test_hostile_files.sh — hostile input, round three (issue 55), the files a command writes and
# the lines it prints: the stale-temporary sweep never touches a live writer's temporary or a
# file strata did not make; an output is never one of the command's inputs or another output;
# usage errors quote option values escaped; --help and --version report a failed write;
# failures name their real cause (PoCL's kernel cache, a temporary, a .hdr's header). TAP.
. tests/tap.sh

R="--width 16 --height 12 --spp 2 --quiet"
PAT="pattern --sampler random --count 16 --dims 2"

# ---- the stale-temporary sweep -------------------------------------------------------------
# This host's name as a temporary carries it (st_outfile.h): letters, digits and '-', else '_'.
host=$(hostname | sed 's/[^A-Za-z0-9-]/_/g' | cut -c1-64)
mkdir "$T/w"
# A writer that this process cannot see by its pid (one in another pid namespace, or on
# another host) holding its temporary's lock, as a live strata writer does, until killed.
hold() {
    rm -f "$T/ready"
    (exec 9< "$1" && flock 9 && : > "$T/ready" && exec sleep 60) &
    holder=$!
    while [ ! -e "$T/ready" ]; do sleep 0.05; done
}
echo "a user's own" > "$T/w/.thesis.tex.tmp.4000000.1"
echo partial > "$T/w/.pts.csv.tmp.4000000.1"
live="$T/w/.pts.csv.strata-tmp.$host.4000001.1"
echo partial > "$live"
dead="$T/w/.pts.csv.strata-tmp.$host.4000002.1"
echo partial > "$dead"
elsewhere="$T/w/.pts.csv.strata-tmp.another-host.4000003.1"
echo partial > "$elsewhere"
hold "$live"
$S $PAT --csv "$T/w/pts.csv" 2> "$T/err"
check "a write into the folder succeeds" '[ -s "$T/w/pts.csv" ]' "($(cat "$T/err"))"
check "a file only named like an old temporary is not removed" \
    '[ "$(cat "$T/w/.thesis.tex.tmp.4000000.1")" = "a user'"'"'s own" ] && [ -e "$T/w/.pts.csv.tmp.4000000.1" ]' \
    "($(ls -A "$T/w" | tr '\n' ' '))"
check "a live temporary whose pid this process cannot see is not removed" '[ -e "$live" ]' \
    "($(ls -A "$T/w" | tr '\n' ' '))"
check "another host's temporary in a shared folder is not removed" '[ -e "$elsewhere" ]'
check "a dead writer's temporary (unlocked, this host's) is removed" '[ ! -e "$dead" ]'
kill $holder
wait $holder 2> /dev/null
$S $PAT --csv "$T/w/pts.csv" 2> "$T/err"
check "once its writer has ended, that temporary is removed by the next write" '[ ! -e "$live" ]'

# The issue's reproduction: a writer stopped while its output is written (its temporary exists
# and holds data: a CSV of a million points, written for a second or more), a second writer
# of the same name, then the first continued. The second runs in a pid namespace of its own
# where this machine allows one (root, or user namespaces), as in a container: the first's pid
# is then one it cannot see.
ns=""
unshare -p -f --mount-proc true 2> /dev/null && ns="unshare -p -f --mount-proc"
$S pattern --sampler random --count 1048576 --dims 4 --csv "$T/w/b.csv" 2> "$T/err1" &
first=$!
stopped=0
while kill -0 $first 2> /dev/null; do
    if [ -n "$(find "$T/w" -maxdepth 1 -name ".b.csv.*tmp.*" -size +0 2> /dev/null)" ]; then
        kill -STOP $first
        stopped=1
        break
    fi
done
$ns $S $PAT --csv "$T/w/b.csv" 2> "$T/err2"
second=$?
kill -CONT $first 2> /dev/null
wait $first
st=$?
check "a second writer of one name, while the first is stopped mid-write, succeeds${ns:+ (from another pid namespace)}" \
    '[ $stopped = 1 ] && [ $second = 0 ]' "(stopped $stopped, status $second, $(cat "$T/err2"))"
check "the first writer, continued, still renames its file into place" \
    '[ $st = 0 ] && [ "$(wc -l < "$T/w/b.csv")" = 1048577 ]' "(status $st, $(cat "$T/err1"))"
rm -f "$T/w/b.csv"

# ---- an output is never an input, nor another output --------------------------------------
P="--width 16 --height 12 --spp 4 --sampler random --seed 3 --quiet"
$S render $P --sample-range 0:2 -o "$T/p0.exr" 2> /dev/null && $S render $P --sample-range 2:4 -o "$T/p1.exr" 2> /dev/null
cp "$T/p0.exr" "$T/p0.keep"
expect "merge -o a part is refused" 2 "^strata: error: $T/p0.exr: -o and part 1 are the same file; refused" \
    $S merge "$T/p0.exr" "$T/p1.exr" -o "$T/p0.exr"
check "the part is left as it was" 'cmp -s "$T/p0.exr" "$T/p0.keep"'
ln "$T/p1.exr" "$T/hard.exr"
expect "merge -o a hard link of a part is refused (device and inode)" 2 "hard.exr: -o and part 2 are the same file" \
    $S merge "$T/p0.exr" "$T/p1.exr" -o "$T/hard.exr"
ln -s p1.exr "$T/soft.exr"
expect "merge -o a symbolic link to a part is refused" 2 "soft.exr: -o and part 2 are the same file" \
    $S merge "$T/p0.exr" "$T/p1.exr" -o "$T/soft.exr"
$S render $R -o "$T/e.exr" 2> /dev/null
cp "$T/e.exr" "$T/e.keep"
expect "render --env E -o E is refused" 2 "^strata: error: $T/e.exr: -o and --env are the same file" \
    $S render $R --env "$T/e.exr" -o "$T/e.exr"
check "the environment map is left as it was" 'cmp -s "$T/e.exr" "$T/e.keep"'
expect "render -o x.png --spp-map x.png (one new name twice) is refused" 2 "x.png: -o and --spp-map are the same file" \
    $S render --width 16 --height 12 --spp 8 --quiet --adaptive --sampler random -o "$T/x.png" --spp-map "$T/x.png"
check "nothing was written under that name" '[ ! -e "$T/x.png" ]'
expect "render -o ./x.exr -o x.exr (one name spelt twice) is refused" 2 "-o and -o are the same file" \
    $S render $R -o "$T/./x.exr" -o "$T/x.exr"
cp tests/scenes/materials_flat.gltf "$T/scene.gltf"
cp "$T/scene.gltf" "$T/scene.keep"
ln -s scene.gltf "$T/link.exr"
expect "render -o a link to the scene is refused" 2 "link.exr: -o and the scene are the same file" \
    $S render "$T/scene.gltf" $R -o "$T/link.exr"
check "the scene is left as it was" 'cmp -s "$T/scene.gltf" "$T/scene.keep"'
expect "pattern --csv F --png F is refused" 2 "x.csv: --csv and --png are the same file" \
    $S $PAT --csv "$T/x.csv" --png "$T/x.csv"
expect "filter --csv F --png F is refused" 2 "f.png: --csv and --png are the same file" \
    $S filter box --csv "$T/f.png" --png "$T/f.png"
expect "signal --csv F --spectrum-csv F is refused" 2 "s.csv: --csv and --spectrum-csv are the same file" \
    $S signal --csv "$T/s.csv" --spectrum-csv "$T/s.csv"
expect "converge --csv over its --reference is refused" 2 "e.exr: --csv and --reference are the same file" \
    $S converge --width 16 --height 12 --quiet --sampler random --spp-list 1 --reference "$T/e.exr" --csv "$T/e.exr"
expect "compare --csv over its --reference is refused" 2 "e.exr: --csv and --reference are the same file" \
    $S compare $R --sampler random --reference "$T/e.exr" -o "$T/sheet.png" --csv "$T/e.exr"
check "the reference is left as it was" 'cmp -s "$T/e.exr" "$T/e.keep"'
$S $PAT --csv /dev/null --png /dev/null 2> "$T/err"
check "a device named twice as an output is no clash" '[ $? = 0 ]' "($(cat "$T/err"))"

# ---- control characters in usage errors ---------------------------------------------------
nl='
'
# $1: name; the rest: a command whose usage error quotes a value holding ESC and a newline.
escaped() {
    name=$1
    shift
    "$@" > /dev/null 2> "$T/err"
    got=$?
    check "$name: exit 2, one line, ESC and newline shown as \\xNN" \
        '[ $got = 2 ] && [ "$(wc -l < "$T/err")" = 1 ] && grep -q "\\\\x1B" "$T/err" && grep -q "\\\\x0A" "$T/err" && ! grep -q "$(printf "\033")" "$T/err"' \
        "(status $got: $(cat -v "$T/err"))"
}
bad="a$(printf '\033')[31m${nl}strata: error: forged"
escaped "--filter" $S render $R --filter "$bad"
escaped "--integrator" $S render $R --integrator "$bad"
escaped "--tonemap" $S render $R --tonemap "$bad" -o "$T/t.png"
escaped "--crop" $S render $R --crop "$bad"
escaped "--env" $S render $R --env "$bad"
escaped "--sample-range" $S render $R --sample-range "$bad"
escaped "--lanes" $S render $R --lanes "$bad"
escaped "--exposure" $S render $R --exposure "$bad" -o "$T/t.png"
escaped "an unknown option" $S render $R "--$bad"
escaped "an unknown command" $S "$bad"
escaped "pattern --sampler" $S pattern --sampler "$bad" --count 4
escaped "merge's unknown option" $S merge "-$bad" -o "$T/m.exr"
mkdir "$T/odd${nl}dir"
cp tests/scenes/materials_flat.gltf "$T/odd${nl}dir/s.gltf"
$S render "$T/odd${nl}dir/s.gltf" $R -o "$T/odd.exr" 2> "$T/err"
check "the scene path in the lighting note is escaped" \
    '[ "$(grep -c "" "$T/err")" = "$(grep -c "^strata: " "$T/err")" ] && grep -q "odd\\\\x0Adir" "$T/err"' \
    "($(cat -v "$T/err"))"

# ---- messages that name the real cause --------------------------------------------------------
expect "a kernel cache that is /dev/null: the build failure names it" 1 \
    "^strata: error: kernel build failed on .*: PoCL's kernel cache /dev/null (POCL_CACHE_DIR) cannot be made: /dev/null is not a folder" \
    env POCL_CACHE_DIR=/dev/null timeout 300 $S render $R -o "$T/c.exr"
echo x > "$T/afile"
expect "a kernel cache under a file: devices exits 1 naming it" 1 \
    "^strata: error: no OpenCL devices: PoCL's kernel cache $T/afile/k (POCL_CACHE_DIR) cannot be made: $T/afile is not a folder" \
    env POCL_CACHE_DIR="$T/afile/k" $S devices
expect "a file-size limit too small for the kernel cache is named" 1 \
    "^strata: error: kernel build failed on .*: the file-size limit (ulimit -f) of [0-9]* bytes is too small" \
    sh -c "ulimit -f 8; POCL_CACHE_DIR='$T/fresh-cache' exec timeout 300 $S render $R -o '$T/c.exr'"
check "no image from a failed build" '[ ! -e "$T/c.exr" ]'
# /proc takes no new file, even from root: a file there is replaced through a temporary that
# cannot be made
expect "a file whose folder takes no new file: the error names the temporary" 1 \
    "^strata: error: /proc/version: cannot create its temporary .version.strata-tmp.$host.[0-9]*.[0-9]* (" \
    $S $PAT --csv /proc/version
printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y -5 +X 10\n' > "$T/neg.hdr"
expect "a .hdr of negative size names its header, not another format" 1 \
    "^strata: error: $T/neg.hdr: a Radiance HDR header without a valid size" \
    $S render $R --env "$T/neg.hdr" -o "$T/c.exr"
check "... and does not quote stb's last format tried" '! grep -q "not BMP" "$T/err"'

# ---- --help and --version into a full disk -------------------------------------------------
for arg in --version --help -h; do
    expect "strata $arg into /dev/full exits 1" 1 "^strata: error: stdout: write failed" \
        sh -c "$S $arg > /dev/full"
done
$S --version > "$T/v"
check "strata --version still exits 0 and prints the version" '[ $? = 0 ] && grep -q "^strata " "$T/v"'

echo "1..$n"
