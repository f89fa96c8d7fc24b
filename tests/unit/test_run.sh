#!/bin/sh
# test_run.sh — tests/run.sh's counts: fake test scripts print TAP (passes, a
# failure, skips with their directive, a script skipped whole by its plan,
# cmocka's "not ok N # SKIP name" after a "# SKIP reason" line) and run.sh must
# end with "N passed, N failed, N skipped", count each layer alike, list each
# skip's reason once with its count, and exit 1 on the failure, 0 without it.
# TAP output.
. tests/tap.sh
cat > "$T/a.sh" << 'EOF2'
echo "ok 1 - one"
echo "ok 2 - # SKIP no frobnicator here"
echo "not ok 3 - three"
echo "ok 4 - four # SKIP no frobnicator here"
echo "1..4"
EOF2
cat > "$T/b.sh" << 'EOF2'
echo "1..0 # SKIP nothing to see"
EOF2
cat > "$T/c.sh" << 'EOF2'
echo "1..2"
echo "# SKIP the models are elsewhere"
echo "not ok 1 # SKIP models_load"
echo "ok 2 - sizes"
EOF2
sh tests/run.sh --layer x "$T/a.sh" --layer y "$T/b.sh" "$T/c.sh" > "$T/out" 2>&1
status=$?
check "the last line counts passes, failures and skips" '[ "$(tail -1 "$T/out")" = "2 passed, 1 failed, 4 skipped" ]' "($(tail -1 "$T/out"))"
check "a failure exits 1" '[ $status -eq 1 ]'
check "each layer counts its own" 'grep -q "^# layer x: 1 passed, 1 failed, 2 skipped" "$T/out" &&
    grep -q "^# layer y: 1 passed, 0 failed, 2 skipped" "$T/out"'
check "each reason is listed once, with its count" \
    '[ "$(grep -c "no frobnicator here" "$T/out")" -eq 3 ] && grep -q "^#   no frobnicator here (2)$" "$T/out" &&
     grep -q "^#   nothing to see (1)$" "$T/out" && grep -q "^#   the models are elsewhere (1)$" "$T/out"' \
    "($(grep "^#  " "$T/out" | tr '\n' ' '))"
sh tests/run.sh "$T/b.sh" "$T/c.sh" > "$T/out" 2>&1
status=$?
check "skips alone exit 0" '[ $status -eq 0 ] && [ "$(tail -1 "$T/out")" = "1 passed, 0 failed, 2 skipped" ]' "($(tail -1 "$T/out"))"
echo "1..$n"
