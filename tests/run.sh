#!/bin/sh
# tests/run.sh — runs the test programs (cmocka, TAP output) and command-line
# test scripts (*.sh, TAP output) given as arguments, and ends with one line
# "N passed, N failed" over all of them. Exit status 1 if any failed.
# `--layer NAME` among the arguments starts a layer (make test-unit and its
# siblings): each layer ends with a comment line giving its counts and its
# wall time, so a slow layer shows.
BUILD=${BUILD:-build/release}
export CMOCKA_MESSAGE_OUTPUT=TAP
export STRATA=${STRATA:-./strata}
log=$(mktemp)
layer=""
layer_start=0
layer_from=0

now() { date +%s.%N; }

# end_layer: the current layer's counts (the lines of $log after $layer_from)
# and the seconds since it began.
end_layer() {
    [ -n "$layer" ] || return 0
    lp=$(tail -n +$((layer_from + 1)) "$log" | grep -c '^ok')
    lf=$(tail -n +$((layer_from + 1)) "$log" | grep -c '^not ok')
    secs=$(echo "$(now) $layer_start" | awk '{ printf "%.1f", $1 - $2 }')
    summary="$summary# layer $layer: $lp passed, $lf failed, $secs s
"
}

summary=""
expect_layer=0
for t in "$@"; do
    if [ "$expect_layer" -eq 1 ]; then
        layer=$t
        layer_start=$(now)
        layer_from=$(wc -l < "$log")
        expect_layer=0
        continue
    fi
    if [ "$t" = "--layer" ]; then
        end_layer
        expect_layer=1
        continue
    fi
    [ -e "$t" ] || continue
    echo "# $t"
    case "$t" in
        *.sh) sh "$t" ;;
        *) "$t" ;;
    esac > "$log.out" 2> "$log.err"
    status=$?
    cat "$log.out"
    grep -v '^ok\|^not ok\|^1\.\.\|^#' "$log.err" | head -20
    grep '^ok\|^not ok' "$log.out" >> "$log"
    # a program that crashed before reporting counts as one failure
    if [ $status -ne 0 ] && ! grep -q '^not ok' "$log.out"; then
        echo "not ok - $t exited with status $status"
        echo "not ok - $t exited with status $status" >> "$log"
    fi
done
end_layer
printf '%s' "$summary"
passed=$(grep -c '^ok' "$log")
failed=$(grep -c '^not ok' "$log")
rm -f "$log" "$log.out" "$log.err"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
