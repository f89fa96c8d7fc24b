#!/bin/sh
# test_ux.sh — the command line's conveniences: --version, the version in the
# files strata writes, make install. TAP output.
. tests/tap.sh

R="--width 16 --height 12 --spp 2 --quiet"
$S --version > "$T/v" 2>&1
check "--version prints strata and a version" 'grep -qx "strata [0-9A-Za-z][0-9A-Za-z.+-]*" "$T/v"'
# the release of VERSION, then git describe's distance (tools/version.sh, whose
# cases tests/unit/test_version.sh checks); -dirty left out: the tree may
# change between the build and this check
check "--version is VERSION's release and the distance from it" \
    '[ "$(sed "s/-dirty\$//" "$T/v")" = "strata $(sh tools/version.sh | sed "s/-dirty\$//")" ] &&
     grep -q "^strata $(cat VERSION)" "$T/v"' "(got $(cat "$T/v"))"
v=$(sed 's/^strata //' "$T/v")
check "--help lists --version" '$S --help | grep -q -- "--version"'

$S render $R -o "$T/a.png"
$S render $R -o "$T/b.png"
# -o -: a PNG on standard output, nothing else there (the summary left out),
# into a pipe or a file
$S render --width 16 --height 12 --spp 2 -o - 2> "$T/err" | cat > "$T/piped.png"
$S render --width 16 --height 12 --spp 2 -o - > "$T/stdout.png" 2> "$T/err"
check "-o - writes the PNG to standard output, into a pipe or a file" \
    '[ "$(head -c 4 "$T/piped.png" | tail -c 3)" = PNG ] && $S diff "$T/piped.png" "$T/a.png" | grep -qx "rmse 0" &&
     $S diff "$T/stdout.png" "$T/a.png" | grep -qx "rmse 0"' "($(head -c 200 "$T/err"))"
expect "-o - with a split render is refused (it writes EXRs)" 2 "^strata: error: -o -: a split render" \
    $S render $R --part 0/2 -o -
check "a PNG names the version" 'grep -aq "Software.strata $v" "$T/a.png"'
check "a PNG carries the settings as text" 'grep -aq "strata.sampler.halton" "$T/a.png"'
check "a PNG made twice is the same file" 'cmp -s "$T/a.png" "$T/b.png"'
$S render $R -o "$T/a.exr"
check "an EXR names the version" 'grep -aq "software.string.*strata $v" "$T/a.exr"'
check "an EXR's spp is an int" 'grep -aq "strata.spp.int" "$T/a.exr"'

# names: any case; a close misspelling gets a suggestion; every name in each --help
expect "a misspelt sampler gets a suggestion" 2 "^strata: error: --sampler hallton: unknown; did you mean halton?" $S render --sampler hallton
expect "a misspelt filter gets a suggestion" 2 "--filter Mitchel: unknown; did you mean mitchell?" $S render --filter Mitchel
expect "a prefix suggests the whole name" 2 "did you mean best-candidate?" $S pattern --sampler best --count 4
expect "converge suggests sampler names" 2 "did you mean sobol?" $S converge --sampler sobl --spp-list 4
check "--crop's help says which commands take it, and no help line dangles" \
    '$S help render | grep -A3 -- "--crop" | grep -q "strata render.s alone, not" &&
     ! $S help render | grep -q "; render only\$"'
expect "bench refuses --crop as its help says" 2 "^strata: error: --crop: only .strata render. takes it" \
    $S bench --crop 0,0,4,4
expect "filter suggests filter names" 2 "^strata: error: filter gausian: unknown; did you mean gaussian?" $S filter gausian
expect "a misspelt option gets a suggestion" 2 "^strata: error: render: unknown option --sampel; did you mean --sampler?" $S render --sampel halton
expect "pattern options get suggestions" 2 "unknown option --cout; did you mean --count?" $S pattern --cout 3
expect "a misspelt command gets a suggestion" 2 "unknown command 'rendr'; did you mean render?" $S rendr
expect "a misspelt scene gets a suggestion" 2 "unknown built-in scene 'cornel-box'; did you mean cornell-box?" $S render cornel-box $R -o "$T/s.exr"
expect "a far-off name gets none" 2 "--sampler zzzzzz: unknown; expected one of" $S render --sampler zzzzzz
$S render CORNELL-BOX $R --sampler HALTON --filter Box --integrator Direct -o "$T/upper.exr"
$S render cornell-box $R --sampler halton --filter box --integrator direct -o "$T/lower.exr"
check "names are case-insensitive (same image)" \
    '$S diff "$T/upper.exr" "$T/lower.exr" --max-rmse 0 > /dev/null 2>&1'
samplers=$($S render --sampler zzzzzz 2>&1 | sed 's/.*expected one of //; s/,//g')
filters=$($S render --filter zzzzzz 2>&1 | sed 's/.*expected one of //; s/,//g')
check "the sampler list is read" '[ "$(echo $samplers | wc -w)" -ge 8 ]'
for cmd in render bench converge pattern compare; do
    missing=""
    for s in $samplers; do $S $cmd --help | grep -qw -- "$s" || missing="$missing $s"; done
    check "$cmd --help names every sampler" '[ -z "$missing" ]' "(missing:$missing)"
done
for cmd in render bench filter signal compare; do
    missing=""
    for f in $filters; do $S $cmd --help | grep -q -- "$f" || missing="$missing $f"; done
    check "$cmd --help names every filter" '[ -z "$missing" ]' "(missing:$missing)"
done

# progress when stderr is no terminal: plain lines at 10 % steps (or 10 s), with
# elapsed time, rate and ETA; -q: none. 32x32 pixels in waves of 1024 work-items:
# 16 steps of 6.25 %, so lines at 12.5, 25, ..., 100 %.
P="--width 32 --height 32 --spp 16 --wave 1024"
$S render $P -o "$T/p.exr" > "$T/pout" 2> "$T/perr"
check "progress: plain lines on a non-terminal" \
    '[ "$(grep -c "^strata: render *[0-9]*% ([0-9.]* s elapsed, [0-9.]* [kM] samples/s" "$T/perr")" -eq 8 ]' \
    "($(head -c 300 "$T/perr"))"
check "progress: lines before the end show an ETA" 'grep "^strata: render" "$T/perr" | head -1 | grep -q " 12% (.*, ETA [0-9.]* s)"'
check "progress: the last line is 100 % without ETA" 'tail -1 "$T/perr" | grep -q "^strata: render 100% ([^E]*)$"'
check "progress: no bar control characters in a log" '! grep -q "$(printf "\r")" "$T/perr"'
if command -v script > /dev/null; then # a terminal: the bar, redrawn in place
    script -qec "$S render $P -o $T/tty.exr" /dev/null > "$T/tty" 2>&1
    check "progress on a terminal: a bar with elapsed, rate and ETA, redrawn with CR" \
        'tr "\r" "\n" < "$T/tty" | grep -q "^render \[#* *\]  *[0-9]*%  [0-9.]* s elapsed, [0-9.]* [kM] samples/s, ETA "'
fi
$S render $P -q -o "$T/q.exr" > "$T/qout" 2> "$T/qerr"
check "-q: no progress and no summary (the lighting note stays)" \
    '! grep -qv "^strata: note:" "$T/qerr" && [ ! -s "$T/qout" ] && [ -s "$T/q.exr" ]'
$S render $P --sample-range 4:8 -o "$T/part.exr" 2> /dev/null > "$T/partsum"
check "a part's summary states its sample range" 'grep -q "32x32, samples 4:8 of 16 spp in" "$T/partsum"'

# --threads: a sub-device of the CPU device, the same image; --exposure and
# --tonemap for PNG only, recorded in its text
$S render $R --threads 1 -o "$T/t1.exr"
$S render $R -o "$T/tall.exr"
check "--threads 1 renders the same image" '$S diff "$T/t1.exr" "$T/tall.exr" --max-rmse 0 > /dev/null 2>&1'
expect "--threads above the compute units exits 2" 2 "^strata: error: --threads 4096: .* has [0-9]* compute units" $S render $R --threads 4096 -o "$T/t.exr"
expect "--threads 0 exits 2" 2 "^strata: error: --threads 0: expected an integer in 1..4096" $S render $R --threads 0
expect "--exposure with an EXR exits 2" 2 "^strata: error: --exposure applies to PNG output only" $S render $R --exposure 1 -o "$T/e.exr"
expect "--tonemap with bench exits 2" 2 "^strata: error: --tonemap: only .strata render. writes a PNG" $S bench $R --tonemap filmic
expect "an unknown tone curve exits 2" 2 "^strata: error: --tonemap flimic: unknown; did you mean filmic?" $S render $R --tonemap flimic -o "$T/e.png"
check "--exposure wrote nothing for the EXR" '[ ! -e "$T/e.exr" ]'
$S render $R --exposure 0 --tonemap clamp -o "$T/e0.png"
$S render $R -o "$T/edef.png"
$S render $R --exposure 1.5 --tonemap filmic -o "$T/e1.png"
check "exposure 0 with clamp is the default PNG" 'cmp -s "$T/e0.png" "$T/edef.png"'
check "exposure and curve change the PNG" '! $S diff "$T/e1.png" "$T/edef.png" --max-rmse 0 > /dev/null 2>&1'
check "the PNG records exposure and curve" 'grep -aq "strata.exposure.1.5" "$T/e1.png" && grep -aq "strata.tonemap.filmic" "$T/e1.png"'

# one render, several files (make demo)
$S render $R -o "$T/both.exr" -o "$T/both.png"
check "two -o write the EXR and the PNG of one render" \
    '$S diff "$T/both.exr" "$T/a.exr" --max-rmse 0 > /dev/null 2>&1 && cmp -s "$T/both.png" "$T/a.png"'
expect "a split render refuses a PNG among its outputs" 2 "^strata: error: -o $T/p.png: a split render" $S render $R --sample-range 0:1 -o "$T/p.exr" -o "$T/p.png"

if command -v help2man > /dev/null && command -v make > /dev/null && [ -f Makefile ]; then
    make --no-print-directory -s install PREFIX="$T/prefix" > "$T/inst" 2>&1
    check "make install installs the binary" '[ -x "$T/prefix/bin/strata" ]' "$(tail -3 "$T/inst")"
    check "the installed binary runs" '"$T/prefix/bin/strata" --version | grep -q "^strata "'
    check "make install installs a man page with every command" \
        '! for c in render bench pattern filter signal merge converge compare diff devices; do
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
