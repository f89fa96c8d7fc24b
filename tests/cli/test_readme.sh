#!/bin/sh
# test_readme.sh — the README's quick start, line for line: every `./strata`
# command of its "Quick start" section runs in a scratch folder (with a glTF and
# a .glb of tests/scenes as the user's model.gltf and model.glb, two renders as
# a.exr and b.exr) and exits 0, writing the files it names. Each command's
# seconds are printed as a comment: the quick start is meant to take seconds on
# two cores, but a test never fails on time. TAP output.
. tests/tap.sh
case $S in /*) ;; *) S=$PWD/$S ;; esac
sed -n '/^## Quick start/,/^## /p' README.md |
    awk '/^\.\/strata / { cmd = $0; while (cmd ~ /\\$/) { sub(/\\$/, "", cmd); getline more; cmd = cmd more }
                         print cmd }' > "$T/commands"
check "the quick start holds strata commands" '[ "$(wc -l < "$T/commands")" -ge 8 ]' "($(wc -l < "$T/commands"))"
cp tests/scenes/textures.gltf "$T/model.gltf"
cp tests/scenes/textured.glb "$T/model.glb"
ln -s "$PWD/scenes" "$T/scenes"
ln -s "$S" "$T/strata"
R="--width 16 --height 16 --spp 2 --quiet"
(cd "$T" && ./strata render $R -o a.exr && ./strata render $R --seed 1 -o b.exr) 2> /dev/null
while read -r cmd; do
    rm -f "$T/err"
    start=$(date +%s.%N)
    (cd "$T" && eval "$cmd") > /dev/null 2> "$T/err"
    status=$?
    secs=$(echo "$(date +%s.%N) $start" | awk '{ printf "%.1f", $1 - $2 }')
    name=$(echo "${cmd%%#*}" | tr -s ' ' | sed 's/ *$//')
    echo "# $secs s: $name"
    made=1
    for out in $(echo "$cmd" | grep -o -- '\(-o\|--png\|--spectrum\) [^ ]*' | sed 's/^[^ ]* //'); do
        [ -s "$T/$out" ] || made=0
    done
    check "README: $name" '[ $status -eq 0 ] && [ $made -eq 1 ]' "(status $status, $(head -c 300 "$T/err"))"
done < "$T/commands"
echo "1..$n"
