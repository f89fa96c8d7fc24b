#!/bin/sh
# tests/run.sh — runs the test programs (cmocka, TAP output) and command-line
# test scripts (*.sh, TAP output) given as arguments, and ends with one line
# "N passed, N failed, N skipped" over all of them, after each skip's reason
# (once). Exit status 1 if any failed.
# A skip is TAP's: a result with the directive "# SKIP reason" (cmocka's
# skip() prints "not ok N # SKIP name", its reason on a line "# SKIP reason"
# of its own before it: tests/skip.h's ST_SKIP), or a whole script's plan
# "1..0 # SKIP reason".
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
    tail -n +$((layer_from + 1)) "$log" > "$log.layer"
    secs=$(echo "$(now) $layer_start" | awk '{ printf "%.1f", $1 - $2 }')
    summary="$summary# layer $layer: $(counts "$log.layer"), $secs s
"
}

# The results of a file of TAP lines as "N passed, N failed, N skipped".
SKIP='# *[Ss][Kk][Ii][Pp]'
counts() {
    skipped=$(grep -c "^\(ok\|not ok\|1\.\.0\) .*$SKIP" "$1")
    passed=$(grep '^ok' "$1" | grep -vc "$SKIP")
    failed=$(grep '^not ok' "$1" | grep -vc "$SKIP")
    echo "$passed passed, $failed failed, $skipped skipped"
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
    grep '^ok\|^not ok\|^1\.\.0 ' "$log.out" >> "$log"
    # each skip's reason: the directive's text, but for cmocka's (its test's
    # name), whose reason is the comment line "# SKIP reason" before it
    awk -v t="$t" '
        function why(r) { print (r == "" ? "no reason given, in " t : r) }
        { rest = $0; sub(/^[^#]*# *[Ss][Kk][Ii][Pp] */, "", rest) }
        /^# *[Ss][Kk][Ii][Pp]/ { reason = rest; next }
        /^not ok .*# *[Ss][Kk][Ii][Pp]/ { why(reason); reason = ""; next }
        /^(ok |1\.\.0 ).*# *[Ss][Kk][Ii][Pp]/ { why(rest) }' "$log.out" >> "$log.skips"
    # a program that crashed before reporting counts as one failure
    if [ $status -ne 0 ] && ! grep -q '^not ok' "$log.out"; then
        echo "not ok - $t exited with status $status"
        echo "not ok - $t exited with status $status" >> "$log"
    fi
done
end_layer
printf '%s' "$summary"
if [ -s "$log.skips" ]; then
    echo "# skipped, each reason once:"
    sort "$log.skips" | uniq -c | sed 's/^ *\([0-9]*\) \(.*\)/#   \2 (\1)/'
fi
result=$(counts "$log")
rm -f "$log" "$log.out" "$log.err" "$log.layer" "$log.skips"
echo "$result"
case $result in *", 0 failed,"*) exit 0 ;; *) exit 1 ;; esac

