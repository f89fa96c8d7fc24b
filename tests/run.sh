#!/bin/sh
# tests/run.sh — runs the test programs (cmocka, TAP output) and command-line
# test scripts (*.sh, TAP output) given as arguments, and ends with one line
# "N passed, N failed" over all of them. Exit status 1 if any failed.
BUILD=${BUILD:-build/release}
export CMOCKA_MESSAGE_OUTPUT=TAP
export STRATA=${STRATA:-./strata}
log=$(mktemp)
for t in "$@"; do
    [ -e "$t" ] || continue
    echo "# $t"
    case "$t" in
        *.sh) sh "$t" ;;
        *) "$t" ;;
    esac > "$log.out" 2> "$log.err"
    status=$?
    cat "$log.out"
    grep -v '^ok\|^not ok\|^1\.\.\|^#' "$log.err" | head -20
    cat "$log.out" >> "$log"
    # a program that crashed before reporting counts as one failure
    if [ $status -ne 0 ] && ! grep -q '^not ok' "$log.out"; then
        echo "not ok - $t exited with status $status"
        echo "not ok - $t exited with status $status" >> "$log"
    fi
done
passed=$(grep -c '^ok' "$log")
failed=$(grep -c '^not ok' "$log")
rm -f "$log" "$log.out" "$log.err"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
