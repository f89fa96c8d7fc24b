#!/bin/sh
# test_signal.sh — `strata signal` from the command line: the summary line
# (RMS error, dominant and alias frequencies), the CSV tables, the PNG, usage
# errors (exit 2, "strata: error: ...") and failed writes (exit 1, nothing
# left behind). TAP output. The binary is $STRATA (default ./strata).
. tests/tap.sh

# field NAME FILE: the number after "NAME " in the summary line
field() { sed -n "s/.*$1 \([-0-9.e+]*\).*/\1/p" "$2" | head -1; }

# ---- help and summary ---------------------------------------------------------------
$S signal --help > "$T/help" 2>&1
check "help documents functions, sampling, filters and outputs" \
    'for o in --function --freqs --f0 --spacing --rate --filter --reconstruct --sinc-margin --csv --spectrum-csv --png; do grep -q -- "$o" "$T/help" || exit 1; done'

$S signal --function sine --freq 0.3 > "$T/s03" 2> "$T/e03"
check "sinc recovers a sine above the Nyquist rate (rms error < 1e-4)" \
    'awk -v e="$(field "rms error" "$T/s03")" "BEGIN { exit !(e != \"\" && e < 1e-4) }"'
check "summary names the Nyquist frequency and both dominant frequencies" \
    'grep -q "^signal: sine f = 0.3, T = 1 (Nyquist 0.5), 64 samples in \[0, 64), sinc: rms error" "$T/s03" && grep -q "dominant frequency: original 0.3[0-9]*, reconstruction 0.3" "$T/s03"'

$S signal --freq 0.8 > "$T/s08"
check "below the Nyquist rate the reconstruction shows the alias |f - k/T| = 0.2" \
    'grep -q "alias |f - k/T| = 0.2 (k = 1)" "$T/s08" && awk -v d="$(field "reconstruction" "$T/s08")" "BEGIN { exit !(d > 0.2 - 1/64 && d < 0.2 + 1/64) }"'
$S signal --freq 1.7 --filter mitchell > "$T/s17"
check "mitchell at f = 1.7 also shows the alias 0.3" \
    'awk -v d="$(field "reconstruction" "$T/s17")" "BEGIN { exit !(d > 0.3 - 1/64 && d < 0.3 + 1/64) }"'
$S signal --freq 0.4 --rate 2 > "$T/rate"
check "--rate 2 samples at T = 0.5" 'grep -q "T = 0.5 (Nyquist 1)" "$T/rate"'

# ---- CSV --------------------------------------------------------------------------------
$S signal --freq 0.3 --csv "$T/a.csv" > /dev/null
check "CSV header is x,original,sample,reconstruction,error" \
    '[ "$(head -1 "$T/a.csv")" = "x,original,sample,reconstruction,error" ]'
check "CSV holds the 4160 dense points (samples fall on them) and 64 samples" \
    '[ "$(wc -l < "$T/a.csv")" -eq 4161 ] && [ "$(awk -F, "NR > 1 && \$3 != \"\"" "$T/a.csv" | wc -l)" -eq 64 ]'
check "CSV error column is reconstruction - original" \
    'awk -F, "NR > 1 { d = \$4 - \$2 - \$5; if (d > 1e-8 || d < -1e-8) exit 1 }" "$T/a.csv"'
$S signal --freq 0.3 --offset 0.5 --csv "$T/off.csv" > /dev/null
check "samples off the dense grid get rows of their own, sorted by x" \
    '[ "$(wc -l < "$T/off.csv")" -eq 4225 ] && awk -F, "NR > 2 && \$1 < p { exit 1 } { p = \$1 }" "$T/off.csv"'
$S signal --freq 0.3 --csv - > "$T/stdout.csv" 2> "$T/stderr"
check "--csv - writes the table to stdout and the summary to stderr" \
    '[ "$(head -1 "$T/stdout.csv")" = "x,original,sample,reconstruction,error" ] && grep -q "^signal: " "$T/stderr" && ! grep -q "^signal: " "$T/stdout.csv"'

$S signal --freq 0.8 --spectrum-csv "$T/sp.csv" > /dev/null
check "spectrum CSV has the three series" \
    '[ "$(head -1 "$T/sp.csv")" = "series,frequency,magnitude" ] && for s in original sampled reconstruction; do grep -q "^$s," "$T/sp.csv" || exit 1; done'
check "original's spectrum peaks at 0.8 with magnitude 1/2" \
    'awk -F, "\$1 == \"original\" && \$3 > m { m = \$3; f = \$2 } END { exit !(f > 0.78 && f < 0.82 && m > 0.45 && m < 0.55) }" "$T/sp.csv"'
check "sampled spectrum below Nyquist peaks at the alias 0.2 (a copy of 0.8)" \
    'awk -F, "\$1 == \"sampled\" && \$2 <= 0.5 && \$3 > m { m = \$3; f = \$2 } END { exit !(f > 0.18 && f < 0.22 && m > 0.45) }" "$T/sp.csv"'

$S signal --filter box --points 4096 --csv "$T/zw.csv" > "$T/zw"
# the box is closed at its radius (as pbrt-v4's): a point halfway between two
# samples weighs both, so no point is without weight and x = 1.5 is the mean
# of the samples at 1 and 2
check "a box of radius T/2 exactly between two samples weighs both: no point without weight" \
    '! grep -q "zero filter weight" "$T/zw" && [ "$(awk -F, "NR > 1 && \$4 == \"\"" "$T/zw.csv" | wc -l)" -eq 0 ] && awk -F, "\$1 == 1.5 { m = (\$4 - (sin(2 * 3.14159265358979 * 0.1) + sin(2 * 3.14159265358979 * 0.2)) / 2); exit !(m < 1e-6 && m > -1e-6) }" "$T/zw.csv"'

# ---- Gibbs and blur at a step ---------------------------------------------------------------
maxrec() { awk -F, 'NR > 1 && $4 != "" && $4 > m { m = $4 } END { print m }' "$1"; }
$S signal --function step --edge 32.5 --filter lanczos --csv "$T/lz.csv" > /dev/null
$S signal --function step --edge 32.5 --csv "$T/sc.csv" > /dev/null
$S signal --function step --edge 32.5 --filter gaussian --csv "$T/ga.csv" > /dev/null
check "sinc and lanczos overshoot a step (Gibbs: max > 1.05)" \
    'awk -v a="$(maxrec "$T/lz.csv")" -v b="$(maxrec "$T/sc.csv")" "BEGIN { exit !(a > 1.05 && b > 1.05) }"'
check "gaussian does not overshoot a step" \
    'awk -v a="$(maxrec "$T/ga.csv")" "BEGIN { exit !(a <= 1.000001) }"'

# ---- PNG --------------------------------------------------------------------------------
$S signal --function chirp --filter catmull-rom --png "$T/c.png" > /dev/null
check "PNG is written" '[ "$(head -c 4 "$T/c.png" | od -An -c | tr -d " ")" = "211PNG" ]'
check "PNG has three 720x480 panels" \
    '[ "$(od -An -tu1 -j16 -N8 "$T/c.png" | tr -s " " | sed "s/^ //")" = "0 0 8 112 0 0 1 224" ]'
$S signal --function square --freq 0.07 --filter box --filter-radius 1 --reconstruct convolution > "$T/conv"
check "convolution mode is named in the summary" 'grep -q "box (r = 1 T, convolution)" "$T/conv"'
$S signal --function sines --freqs 0.05,0.2 --filter gaussian --filter-sigma 0.4 > "$T/sines"
check "sum of sines runs with a gaussian of chosen sigma" 'grep -q "^signal: sines f = 0.05,0.2" "$T/sines"'

# ---- usage errors -------------------------------------------------------------------------------
expect "unknown option exits 2" 2 "^strata: error: signal: unknown option --bogus" $S signal --bogus
expect "unknown function exits 2" 2 "^strata: error: --function wave: unknown" $S signal --function wave
expect "unknown filter exits 2" 2 "^strata: error: --filter sharp: unknown" $S signal --filter sharp
expect "sigma for box exits 2" 2 "^strata: error: --filter-sigma applies to gaussian only, not box" $S signal --filter box --filter-sigma 1
expect "radius for sinc exits 2" 2 "^strata: error: --filter-radius does not apply to sinc" $S signal --filter-radius 2
expect "--reconstruct with sinc exits 2" 2 "^strata: error: --reconstruct does not apply to sinc" $S signal --reconstruct average
expect "--sinc-margin with a filter exits 2" 2 "^strata: error: --sinc-margin applies to sinc only" $S signal --filter box --sinc-margin 10
expect "bad --reconstruct exits 2" 2 "^strata: error: --reconstruct sum: expected average or convolution" $S signal --filter box --reconstruct sum
expect "--freqs with sine exits 2" 2 "^strata: error: --freqs does not apply to --function sine" $S signal --freqs 0.1,0.2
expect "--edge with sine exits 2" 2 "^strata: error: --edge does not apply to --function sine" $S signal --edge 3
expect "sines without --freqs exits 2" 2 "^strata: error: --function sines needs --freqs" $S signal --function sines
expect "bad number in --freqs exits 2" 2 "^strata: error: --freqs x: expected a finite number" $S signal --function sines --freqs 0.1,x
expect "bad --freq exits 2" 2 "^strata: error: --freq abc: expected a finite number" $S signal --freq abc
expect "zero spacing exits 2" 2 "^strata: error: --spacing 0: must be positive" $S signal --spacing 0
expect "--spacing with --rate exits 2" 2 "^strata: error: --spacing and --rate" $S signal --spacing 1 --rate 2
expect "offset of a whole sample exits 2" 2 "^strata: error: --offset 1: must be in \[0, 1)" $S signal --offset 1
expect "too few dense points for the frequency exits 2" 2 "^strata: error: --points 100: the dense grid cannot resolve" $S signal --freq 2 --points 100
expect "too few points exits 2" 2 "^strata: error: --points 10: expected an integer in 16" $S signal --points 10
expect "missing value exits 2" 2 "^strata: error: signal: option --freq needs a value" $S signal --freq
expect "stray argument exits 2" 2 "^strata: error: signal: unexpected argument extra" $S signal extra
expect "radius past the limit exits 2" 2 "^strata: error: --filter-radius 100: must be in" $S signal --filter box --filter-radius 100

# ---- failed writes ----------------------------------------------------------------------------
expect "unwritable CSV exits 1 naming it" 1 "^strata: error: $T/no/dir/a.csv" $S signal --csv "$T/no/dir/a.csv"
mkdir "$T/dir.csv"
expect "CSV that is a folder exits 1 naming it" 1 "^strata: error: $T/dir.csv" $S signal --csv "$T/dir.csv"
expect "unwritable PNG exits 1 naming it" 1 "^strata: error: $T/no/dir/a.png" $S signal --png "$T/no/dir/a.png"
check "failed writes leave no temporary" '[ -z "$(ls -A "$T/dir.csv")" ] && [ -z "$(ls -A "$T" | grep tmp)" ]'

# --jitter: the alias at 0.1 no longer dominates (test_signal.c checks the spectrum)
$S signal --function sine --freq 0.9 --length 256 --jitter --seed 2 --filter gaussian > "$T/j" 2>&1
check "--jitter: the reconstruction's dominant frequency is not the alias 0.1" \
    'grep -q "alias |f - k/T| = 0.1" "$T/j" && ! grep -q "reconstruction 0.09[0-9]*;\|reconstruction 0.10[0-9]*;" "$T/j"' "($(cat "$T/j"))"
expect "--seed without --jitter exits 2" 2 "^strata: error: --seed applies to --jitter only" \
    $S signal --seed 3
expect "--offset with --jitter exits 2" 2 "^strata: error: --offset with --jitter" \
    $S signal --jitter --offset 0.5
echo "1..$n"
