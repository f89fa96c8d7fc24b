#!/bin/sh
# test_ux.sh — the command line's conveniences: --version, the version in the
# files strata writes, make install. TAP output.
. tests/tap.sh

R="--width 16 --height 12 --spp 2 --quiet"
$S --version > "$T/v" 2>&1
check "--version prints strata and a version" 'grep -qx "strata [0-9A-Za-z][0-9A-Za-z.+-]*" "$T/v"'
if git rev-parse --git-dir > /dev/null 2>&1; then
    check "--version is git describe of the checkout" \
        '[ "$(cat "$T/v")" = "strata $(git describe --tags --always --dirty)" ]'
fi
v=$(sed 's/^strata //' "$T/v")
check "--help lists --version" '$S --help | grep -q -- "--version"'

$S render $R -o "$T/a.png"
$S render $R -o "$T/b.png"
check "a PNG names the version" 'grep -aq "Software.strata $v" "$T/a.png"'
check "a PNG carries the settings as text" 'grep -aq "strata.sampler.halton" "$T/a.png"'
check "a PNG made twice is the same file" 'cmp -s "$T/a.png" "$T/b.png"'
$S render $R -o "$T/a.exr"
check "an EXR names the version" 'grep -aq "software.string.*strata $v" "$T/a.exr"'
check "an EXR's spp is an int" 'grep -aq "strata.spp.int" "$T/a.exr"'

if command -v help2man > /dev/null && command -v make > /dev/null && [ -f Makefile ]; then
    make --no-print-directory -s install PREFIX="$T/prefix" > "$T/inst" 2>&1
    check "make install installs the binary" '[ -x "$T/prefix/bin/strata" ]' "$(tail -3 "$T/inst")"
    check "the installed binary runs" '"$T/prefix/bin/strata" --version | grep -q "^strata "'
    check "make install installs a man page with every command" \
        '! for c in render bench pattern filter signal merge converge diff devices; do
             grep -q "^\.SS strata $c" "$T/prefix/share/man/man1/strata.1" || echo missing; done |
             grep -q missing'
    check "the man page lists the render options" 'grep -q "sample\\\\-range" "$T/prefix/share/man/man1/strata.1"'
    f="$T/prefix/share/bash-completion/completions/strata"
    check "make install installs a bash completion" '[ -f "$f" ]'
    if command -v bash > /dev/null; then
        words=$(PATH="$T/prefix/bin:$PATH" bash -c '. "$1"; COMP_WORDS=(strata render --sampler h); COMP_CWORD=3; _strata; echo "${COMPREPLY[*]}"' _ "$f")
        check "the completion completes sampler names" '[ "$words" = "halton hammersley" ]' "(got '$words')"
        words=$(PATH="$T/prefix/bin:$PATH" bash -c '. "$1"; COMP_WORDS=(strata render --sample); COMP_CWORD=2; _strata; echo "${COMPREPLY[*]}"' _ "$f")
        check "the completion completes options from --help" '[ "$words" = "--sample-range --sampler" ]' "(got '$words')"
    fi
else
    echo "# help2man or make not found: make install not tested"
fi
echo "1..$n"
