#!/bin/sh
# test_pictures.sh — the README's pictures are what the current code makes:
# re-renders these few small ones with tools/make_pictures.sh (their commands
# live there only) and requires their pixels equal to the committed files,
# bit for bit (strata diff --max-rmse 0: every 8-bit code the same; the text
# chunks, which name the version, may differ). A failure here means
# `make pictures` was not run after a change of the images. TAP output.
. tests/tap.sh

CHECKED="renders/1spp-random.png renders/1spp-halton.png renders/1spp-sobol.png"
ONLY="$CHECKED" P="$T/pictures" S="$S" sh tools/make_pictures.sh
for name in $CHECKED; do
    if $S diff "$T/pictures/$name" "scenes/pictures/$name" --max-rmse 0 > "$T/d" 2>&1; then
        ok "scenes/pictures/$name is up to date"
    else
        not_ok "scenes/pictures/$name is stale: run make pictures ($(tail -1 "$T/d"))"
    fi
done
check "only the checked pictures were made" \
    '[ "$(cd "$T/pictures" && find . -type f | wc -l)" -eq 3 ]'
S="$S" sh tools/discrepancy_table.sh > "$T/table"
sed -n '/^| sampler | N = 256 | N = 1024 |$/,/^$/p' README.md | sed '/^$/d' > "$T/readme"
check "the README's discrepancy table is what the code measures" 'cmp -s "$T/table" "$T/readme"' \
    "($(diff "$T/table" "$T/readme" | head -3 | tr '\n' ' '))"
echo "1..$n"
