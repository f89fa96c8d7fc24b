#!/bin/sh
# test_lanes_auto.sh — --lanes auto, the default: on a CPU device the first
# render measures the candidate widths and keeps the fastest (the narrowest
# within 3 % of it) in the wisdom
# file (STRATA_CACHE_DIR/lanes here, a scratch folder), `strata devices` and
# bench say which width and how it was chosen, later renders reuse it without
# measuring, a file that cannot be read or written costs a measurement but
# never a render, and whatever width is chosen the image is the same.
# TAP output.
. tests/tap.sh

if ! $S devices 2> /dev/null | grep -q "  cpu "; then
    echo "1..0 # SKIP no CPU device: --lanes auto takes 1 without measuring elsewhere"
    exit 0
fi
export STRATA_CACHE_DIR="$T/wisdom"
W="$STRATA_CACHE_DIR/lanes"
R="cornell-box --width 20 --height 12 --spp 2"
# the first CPU device's line of `strata devices`
cpu_line() { $S devices | grep -m1 "  cpu "; }

check "before any render, devices says the width is not measured yet" \
    'cpu_line | grep -q "| lanes \(1\|4\|8\|16\) (not measured yet"'

$S render $R -o "$T/first.exr" 2> "$T/first.err"
check "the first render measures, and says so" \
    'grep -q "^strata: note: measuring which lane width is fastest" "$T/first.err"'
check "... and names the width it chose with the rates" \
    'grep -q "^strata: note: lanes \(1\|4\|8\|16\) (measured: 1: [0-9.]*, 4: [0-9.]*, 8: [0-9.]*, 16: [0-9.]* M samples/s, the narrowest within 3 % of the fastest; kept in $W)" "$T/first.err"' \
    "($(cat "$T/first.err"))"
# the wisdom: one line, key TAB width TAB rates, the width one of the rates'
check "the wisdom file holds one line: this device's key, a width and four positive rates" \
    '[ "$(wc -l < "$W")" -eq 1 ] && python3 -c "
import sys
key, width, rates = open(sys.argv[1]).read().rstrip(\"\n\").split(\"\t\")
r = dict(x.split(\":\") for x in rates.split())
assert width in (\"1\", \"4\", \"8\", \"16\") and sorted(r, key=int) == [\"1\", \"4\", \"8\", \"16\"]
assert all(float(v) > 0 for v in r.values())
# the narrowest width within 3 % of the fastest
best = max(float(v) for v in r.values())
assert float(r[width]) >= 0.97 * best - 1e-3
assert all(float(r[w]) < 0.97 * best + 1e-3 for w in r if int(w) < int(width))
assert \"Portable Computing Language\" in key or \"strata\" in key
" "$W"' "($(cat "$W"))"
chosen=$(cut -f2 "$W")
check "devices shows the remembered width and where it is kept" \
    'cpu_line | grep -q "| lanes $chosen (remembered: .* M samples/s, the narrowest within 3 % of the fastest; kept in $W)$"' "($(cpu_line))"

cp "$W" "$T/wisdom.before"
$S render $R -o "$T/second.exr" 2> "$T/second.err"
check "a second render measures nothing" '! grep -q "measuring" "$T/second.err"'
check "... and leaves the wisdom as it was" 'cmp -s "$W" "$T/wisdom.before"'
check "... and says in its EXR header which width it ran" \
    'grep -a -q "lanes $chosen: generate_rays" "$T/second.exr"'
$S bench $R --json > "$T/bench.json" 2> /dev/null
check "bench --json: the remembered width, said so" \
    'python3 -c "import json, sys; d = json.load(open(sys.argv[1])); sys.exit(not (d[\"lanes\"] == $chosen and d[\"lanes_chosen\"] == \"remembered\"))" "$T/bench.json"'
$S bench $R --lanes 4 > "$T/bench4" 2> /dev/null
check "bench --lanes 4: forced, said so" 'grep -q "^lanes      4 (--lanes)$" "$T/bench4"'

# the chosen width and every forced one give the same image
for w in 1 4 8 16; do
    $S render $R --lanes $w -o "$T/w$w.exr" 2> /dev/null
    check "--lanes $w renders the image auto renders, bit for bit" \
        '$S diff "$T/second.exr" "$T/w$w.exr" --max-rmse 0 > "$T/diff" && grep -q "max_abs 0$" "$T/diff"'
done

# another device's line is kept when this one's is rewritten; a line that
# names no width strata builds counts as none
printf 'strata 0.0.0 | Another Platform | another device | 1.0 | OpenCL 1.2\t8\t1:1 4:2 8:3 16:2\n' > "$W"
cut -f1 "$T/wisdom.before" | tr -d '\n' > "$T/key"
printf '\t3\t1:1\n' >> "$T/key"
cat "$T/key" >> "$W"
$S render $R -q -o "$T/third.exr" 2> "$T/third.err"
check "a remembered width of 3 is no width: the render measures again" \
    '[ -s "$T/third.exr" ] && [ "$(grep -c "^$(cut -f1 "$T/wisdom.before")	\(1\|4\|8\|16\)	" "$W")" -eq 1 ]' "($(cat "$W"))"
check "... keeping the other device's line" 'grep -q "^strata 0.0.0 | Another Platform" "$W"'

# this device's line from another strata version (other kernels) is
# dropped when this version's is written; other devices' lines stay
cut -f1 "$T/wisdom.before" | sed 's/^strata [^ ]* /strata 0.0.0-old /' | tr -d '\n' > "$T/old"
printf '\t8\t1:1 4:2 8:3 16:2\n' >> "$T/old"
grep "^strata 0.0.0 | Another Platform" "$W" > "$T/kept"
cat "$T/kept" "$T/old" > "$W"
$S render $R -q -o "$T/fourth.exr" 2> /dev/null
check "this device's line of another version is dropped, another device's kept" \
    '! grep -q "^strata 0.0.0-old " "$W" && grep -q "^strata 0.0.0 | Another Platform" "$W" && [ "$(wc -l < "$W")" -eq 2 ]' "($(cat "$W"))"

# a wisdom folder that cannot be made: the render measures, renders, and
# says the choice was not kept
printf 'x' > "$T/file"
STRATA_CACHE_DIR="$T/file/sub" $S render $R -o "$T/unkept.exr" 2> "$T/unkept.err"
check "an unwritable wisdom folder: the render still renders" '[ -s "$T/unkept.exr" ]'
check "... and says the choice was not kept" \
    'grep -q "^strata: note: lanes [0-9]* (measured: .*; not kept: " "$T/unkept.err"' "($(cat "$T/unkept.err"))"

expect "--lanes 5 is a usage error naming auto" 2 "strata: error: --lanes 5: must be auto, 1, 4, 8 or 16" \
    $S render $R --lanes 5 -o "$T/x.exr"
check "... and writes nothing" '[ ! -e "$T/x.exr" ]'
$S render $R --lanes auto -q -o "$T/auto.exr" 2> /dev/null
check "--lanes auto is accepted and renders the same image" \
    '$S diff "$T/second.exr" "$T/auto.exr" --max-rmse 0 > /dev/null'
echo "1..$n"
