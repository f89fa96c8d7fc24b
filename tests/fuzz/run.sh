#!/bin/sh
# tests/fuzz/run.sh SECONDS NAME... — runs each libFuzzer harness
# build/fuzz/fuzz_NAME for SECONDS, seeded from the project's files (glTF:
# tests/scenes and scenes; EXR: tests/golden and two tiny renders, an image and
# a split part), its new inputs kept in build/fuzz/corpus-NAME. Inputs run up
# to 1 MiB (a deep nesting needs kilobytes), and the glTF harness mutates with
# tests/fuzz/gltf.dict. TAP output: a
# harness is ok when libFuzzer found no crash, leak, sanitizer report or
# timeout; what it found is left in build/fuzz/ (crash-*, leak-*, timeout-*).
secs=$1
shift
S=${STRATA:-./strata}
seeds=build/fuzz/seeds-exr
mkdir -p "$seeds"
$S render --width 8 --height 6 --spp 1 --quiet -o "$seeds/render.exr" &&
    $S render --width 8 --height 6 --spp 2 --sample-range 0:1 --quiet -o "$seeds/part.exr" ||
    echo "# could not render EXR seeds; the EXR harness starts from tests/golden"
n=0
failed=0
for name in "$@"; do
    n=$((n + 1))
    case $name in
        gltf) from="tests/scenes scenes" dict=-dict=tests/fuzz/gltf.dict ;;
        exr) from="tests/golden $seeds" dict="" ;;
        *) from="" dict="" ;;
    esac
    corpus=build/fuzz/corpus-$name
    mkdir -p "$corpus"
    log=build/fuzz/fuzz_$name.log
    # shellcheck disable=SC2086 # $from is a list of folders, $dict empty or one word
    if build/fuzz/fuzz_$name -max_total_time="$secs" -max_len=1048576 $dict -timeout=20 -rss_limit_mb=3072 -malloc_limit_mb=4200 \
        -artifact_prefix=build/fuzz/ -print_final_stats=1 "$corpus" $from > "$log" 2>&1; then
        echo "ok $n - fuzz_$name: $(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$') runs in ${secs} s, nothing found"
    else
        failed=$((failed + 1))
        echo "not ok $n - fuzz_$name found a defect (see $log):"
        grep -m 5 'ERROR\|SUMMARY\|Test unit written' "$log" | sed 's/^/#   /'
    fi
done
echo "1..$n"
# a failure fails the make target (and CI)
[ "$failed" -eq 0 ]
