#!/bin/sh
# test_cli_usage.sh — what a new user meets first: a repeated option is a
# usage error (or, for -o, writes every file), every command takes -q,
# `strata help [TOPIC]`, the points CSV's header, `strata diff` of an EXR
# with a PNG, the shell completion from the program's own name tables, the
# man page's text and sections. TAP output.
. tests/tap.sh

R="--width 16 --height 12 --spp 2 --quiet"

# a repeated single-valued option: exit 2 naming it, nothing written
expect "--seed twice exits 2 naming it" 2 "^strata: error: render: --seed given twice" \
    $S render $R --seed 1 --seed 2 -o "$T/s.exr"
check "--seed twice wrote nothing" '[ ! -e "$T/s.exr" ]'
expect "--seed=1 then --seed 2 is the same error" 2 "--seed given twice" $S render $R --seed=1 --seed 2
expect "a repeated pattern option exits 2" 2 "^strata: error: pattern: --count given twice" \
    $S pattern --sampler random --count 4 --count 8 --csv -
expect "a repeated converge option exits 2" 2 "converge: --spp-list given twice" \
    $S converge --sampler random --spp-list 1 --spp-list 2
expect "compare writes one sheet: a second -o exits 2" 2 "compare: -o given twice" \
    $S compare --sampler random -o "$T/a.png" -o "$T/b.png"
expect "diff --max-rmse twice exits 2" 2 "diff: --max-rmse given twice" \
    $S diff a.exr b.exr --max-rmse 1 --max-rmse 2

# merge writes every -o, as render does
$S render $R --sample-range 0:1 -o "$T/p0.exr"
$S render $R --sample-range 1:2 -o "$T/p1.exr"
$S render $R -o "$T/whole.exr" -o "$T/whole.png"
$S merge "$T/p0.exr" "$T/p1.exr" -o "$T/m.exr" -o "$T/m.png"
check "merge with two -o writes both files" '[ -s "$T/m.exr" ] && [ -s "$T/m.png" ]'
check "merge's EXR equals the whole render" '$S diff "$T/m.exr" "$T/whole.exr" --max-rmse 0 > /dev/null 2>&1'
check "merge's PNG equals the whole render's PNG" '$S diff "$T/m.png" "$T/whole.png" --max-rmse 0 > /dev/null 2>&1'

# -q everywhere
for cmd in "merge $T/p0.exr $T/p1.exr -o $T/q.exr" "diff $T/m.exr $T/whole.exr" \
           "pattern --sampler random --count 4 --csv -" "filter box --csv -" \
           "signal --freq 0.1" "devices"; do
    $S $cmd -q > "$T/out" 2> "$T/err"
    st=$?
    check "${cmd%% *} accepts -q" '[ $st -eq 0 ] && ! grep -q "unknown option" "$T/err"' "(status $st: $(head -c 200 "$T/err"))"
done
$S merge "$T/p0.exr" "$T/p1.exr" -o "$T/q2.exr" --quiet 2> "$T/err"
check "merge accepts --quiet" '[ -s "$T/q2.exr" ]'

# strata help [TOPIC]
$S help > "$T/h" 2>&1
check "strata help prints the overview" '[ $? -eq 0 ] && grep -q "^usage: strata COMMAND" "$T/h"'
check "strata help is strata --help" '$S --help | cmp -s - "$T/h"'
for c in render merge diff compare; do
    $S $c --help > "$T/h$c"
    check "strata help $c is strata $c --help" '$S help $c | cmp -s - "$T/h$c"'
done
expect "strata help of an unknown topic suggests one" 2 "^strata: error: help: unknown topic 'rendr'; did you mean render?" $S help rendr

# pattern --csv: a header row
$S pattern --sampler random --count 3 --dims 2 --csv "$T/p.csv"
check "pattern --csv starts with a header row" '[ "$(head -1 "$T/p.csv")" = "x0,x1" ] && [ "$(wc -l < "$T/p.csv")" -eq 4 ]'

# diff: a linear EXR against an 8-bit sRGB PNG only when asked
expect "diff of an EXR with a PNG is refused, saying why" 2 "diff: .*whole.exr is linear (EXR) but .*whole.png is 8-bit sRGB (PNG)" \
    $S diff "$T/whole.exr" "$T/whole.png"
$S diff "$T/whole.exr" "$T/whole.png" --convert > "$T/d"
check "diff --convert: an EXR and its own PNG are equal" 'grep -qx "rmse 0" "$T/d" && grep -qx "max_abs 0" "$T/d"'
$S diff "$T/whole.png" "$T/whole.exr" --convert > "$T/d"
check "diff --convert works in either order" 'grep -qx "rmse 0" "$T/d"'
$S render $R --seed 3 -o "$T/other.exr"
$S diff "$T/other.exr" "$T/whole.png" --convert > "$T/d"
check "diff --convert still sees another render" '! grep -qx "rmse 0" "$T/d"'
expect "--convert with two EXRs exits 2" 2 "--convert compares an EXR with a PNG" $S diff "$T/whole.exr" "$T/m.exr" --convert

# the completion offers what the parsers accept
if command -v bash > /dev/null; then
    comp() { bash -c '. tools/strata.bash-completion; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _strata; echo "${COMPREPLY[*]}"' _ "$@"; }
    samplers=$($S render --sampler zzzzzz 2>&1 | sed 's/.*expected one of //; s/,//g')
    got=$(comp "$S" render --sampler "")
    check "completion offers every sampler the parser knows" '[ "$(echo $got | tr " " "\n" | sort)" = "$(echo $samplers | tr " " "\n" | sort)" ]' "(got '$got', want '$samplers')"
    for s in zsobol paddedsobol pmj02 joint-stratified; do
        check "completion offers $s" 'echo " $got " | grep -q " $s "'
    done
    got=$(comp "$S" render --device "")
    check "--device completes devices, not scenes" 'echo " $got " | grep -q " cpu " && ! echo "$got" | grep -q cornell' "(got '$got')"
    mkdir -p "$T/models/sub"
    : > "$T/models/sub/a.gltf"
    got=$(comp "$S" render "$T/models/s")
    check "completion walks into folders towards a scene" '[ "$got" = "$T/models/sub" ]' "(got '$got')"
    got=$(comp "$S" converge --sampler random,zs)
    check "completion completes the last item of a sampler list" '[ "$got" = "random,zsobol" ]' "(got '$got')"
    got=$(comp "$S" converge --sampler random,pmj)
    check "... offering every sampler that fits it" '[ "$got" = "random,pmj02 random,pmj02bn" ]' "(got '$got')"
    got=$(comp "$S" help co)
    check "completion completes help topics" '[ "$got" = "converge compare" ] || [ "$got" = "compare converge" ]' "(got '$got')"
fi

# the man page: help2man's input is plain ASCII (it mangles other bytes), and
# it has the sections a man page has
bad=""
for c in "" render bench pattern filter signal merge converge compare diff devices; do
    $S $c --help | LC_ALL=C grep -q '[^ -~]' && bad="$bad ${c:-main}"
done
check "every --help text is plain ASCII (help2man mangles the rest)" '[ -z "$bad" ]' "(non-ASCII in:$bad)"
if command -v help2man > /dev/null && [ -f Makefile ]; then
    sh tools/man-commands.sh "$S" render merge > "$T/strata.h2m"
    help2man --no-info --include="$T/strata.h2m" --output="$T/strata.1" "$S" 2> "$T/err"
    check "the man page has no mangled characters" '! grep -q "???" "$T/strata.1"'
    for sec in EXAMPLES ENVIRONMENT FILES "EXIT STATUS" "SEE ALSO"; do
        check "the man page has $sec" 'grep -q "^\.SH \"*$sec" "$T/strata.1"'
    done
    check "the man page names STRATA_KERNEL_DIR and POCL_CACHE_DIR" 'grep -q STRATA_KERNEL_DIR "$T/strata.1" && grep -q POCL_CACHE_DIR "$T/strata.1"'
fi

# bench --json on a render of a few milliseconds: the stages, timed by the
# device's clock inside the very run whose total is reported, and the row of
# what lies outside them add up to that total (each figure is printed to the
# microsecond), so no stage is ever longer than the whole, however loaded
# the machine (a stage timed by a wait after each launch was, on a 16 x 16
# render)
if command -v python3 > /dev/null; then
    ok_all=1
    for i in 1 2 3; do
        $S bench --width 16 --height 16 --spp 1 --json > "$T/b.json" 2> /dev/null || ok_all=0
        python3 -c 'import json, sys
d = json.load(open(sys.argv[1]))
s = d["stages"]
parts = sum(v["seconds"] for v in s.values())
ok = "outside_stages" in s and abs(parts - d["total"]["seconds"]) <= 1.5e-6 * len(s)
ok = ok and max(v["seconds"] for v in s.values()) <= d["total"]["seconds"]
sys.exit(0 if ok else 1)' "$T/b.json" || ok_all=0
    done
    check "bench --json: the stages and outside_stages add up to the total (3 runs)" '[ $ok_all -eq 1 ]' "($(cat "$T/b.json"))"
    $S bench --width 16 --height 16 --spp 1 > "$T/b.txt" 2> /dev/null
    check "bench: the text table has the row outside_stages, and no cold build unasked" \
        'grep -q "^outside_stages  *[0-9.]* " "$T/b.txt" && grep -q "^kernels *cached [0-9.]* s" "$T/b.txt" && ! grep -q "cold build" "$T/b.txt"'
    check "bench --json: no cold build unasked" '! grep -q kernel_build_cold_seconds "$T/b.json"'
fi
# --cold builds the kernels into a throwaway cache, and only then; bench
# reads the cache a render reads, so a second bench compiles nothing (PoCL
# adds a folder per compiled kernel to its cache; its empty tempfile_* are
# each process's own)
if $S devices 2> /dev/null | grep -q "Portable Computing Language"; then
    mkdir "$T/pc"
    POCL_CACHE_DIR="$T/pc" $S bench --width 16 --height 16 --spp 1 --lanes 8 > /dev/null 2>&1
    find "$T/pc" ! -name "tempfile_*" | sort > "$T/pc1"
    POCL_CACHE_DIR="$T/pc" $S bench --width 16 --height 16 --spp 1 --lanes 8 --cold --json > "$T/cold.json" 2> /dev/null
    find "$T/pc" ! -name "tempfile_*" | sort > "$T/pc2"
    check "bench twice in a row: the second (with --cold) compiles nothing into the cache" \
        '[ -s "$T/pc1" ] && cmp -s "$T/pc1" "$T/pc2"'
    check "bench --cold --json: a cold build time" \
        'python3 -c "import json, sys; sys.exit(not json.load(open(sys.argv[1]))[\"kernel_build_cold_seconds\"] > 0)" "$T/cold.json"'
fi
expect "bench --cold --rays is a usage error" 2 "strata: error: --cold times a render's kernel build" \
    $S bench --rays camera --cold
expect "render --cold is a usage error" 2 "strata: error: --cold: only \`strata bench\` takes it" \
    $S render --cold -o "$T/x.exr"

# the first run: kernels compiled into an empty PoCL cache. The notice says
# so at once, and the render's time (and rate) leave the compilation out:
# the cold render takes about as long as the same render warm, where it took
# several seconds more when the compilation fell in its first wave.
if $S devices 2> /dev/null | grep -q "Portable Computing Language"; then
    mkdir "$T/pocl-cache"
    P="--width 32 --height 32 --spp 16 --sampler stratified"
    POCL_CACHE_DIR="$T/pocl-cache" $S render $P -o "$T/cold.exr" > "$T/cold.out" 2> "$T/cold.err"
    POCL_CACHE_DIR="$T/pocl-cache" $S render $P -o "$T/warm.exr" > "$T/warm.out" 2> "$T/warm.err"
    check "a cold run says it compiles the kernels" \
        'grep -qx "strata: compiling kernels (first run, cached afterwards)..." "$T/cold.err"'
    check "a warm run does not" '! grep -q "compiling kernels" "$T/warm.err"'
    check "the cold compile prints no compiler warnings" '! grep -qi "warning" "$T/cold.err"'
    check "the summary gives the compile time apart" \
        'grep -q "; kernels compiled in [0-9.]* s before it$" "$T/cold.out"'
    cold=$(sed -n 's/.* spp in \([0-9.]*\) s:.*/\1/p' "$T/cold.out")
    warm=$(sed -n 's/.* spp in \([0-9.]*\) s:.*/\1/p' "$T/warm.out")
    compile=$(sed -n 's/.*kernels compiled in \([0-9.]*\) s.*/\1/p' "$T/cold.out")
    check "the cold render's time leaves the compilation out" \
        'awk -v c="$cold" -v w="$warm" "BEGIN { exit !(c < 3 * w + 0.5) }"' "(cold $cold s, warm $warm s)"
    check "the compilation took longer than the render it preceded" \
        'awk -v c="$cold" -v k="$compile" "BEGIN { exit !(k > c) }"' "(compile $compile s, render $cold s)"
    check "cold and warm renders are the same image" '$S diff "$T/cold.exr" "$T/warm.exr" --max-rmse 0 > /dev/null 2>&1'
    # PoCL compiles a kernel once for grids under 2^16 work-items wide and again
    # for wider ones; launches go in narrower rows, so a render whose waves are
    # far wider reuses the warm-up's one compile of each kernel.
    POCL_CACHE_DIR="$T/pocl-cache" $S render --width 512 --height 512 --spp 4 \
        --sampler stratified -q -o "$T/wide.exr" 2> /dev/null
    find "$T/pocl-cache" -name "*.so" | sed "s|/[^/]*/[^/]*\$||" | sort > "$T/kernels"
    check "a wide render compiles no kernel a second time" \
        '[ -s "$T/kernels" ] && [ -z "$(uniq -d "$T/kernels")" ]' \
        "($(uniq -c "$T/kernels" | sort -rn | head -3 | sed "s|$T/pocl-cache/||" | tr -s " \n" " "))"
else
    echo "# not PoCL: the first-run checks are left out"
fi

echo "1..$n"
